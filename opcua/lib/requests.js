"use strict";
// Method arguments -> the service's JSON requests (docs/api.md, docs/min-time.md). What the gateway
// checks itself is only what the HTTP API cannot express (which of two alternative arguments was
// meant, JSON text that does not parse); every value is validated by the service, whose 422 message
// the caller then sees word for word.

const { minTimeArgs } = require("./arguments");

class ArgumentError extends Error {
  constructor(argument, message) {
    super(message);
    this.argument = argument;
  }
}

function number(v, name) {
  if (typeof v !== "number" || !Number.isFinite(v)) {
    throw new ArgumentError(name, `${name} = ${v} is not a finite number`);
  }
  return v;
}

// The service's own bounds on a request (docs/api.md): nesting deeper than 64 is 400
// malformed_json, a body over 1 MiB is 413. Checked here first so the refusal names the argument
// that held the JSON, and so a deep text never reaches the recursive JSON.parse (5 000 levels
// would overflow its stack).
const MAX_JSON_DEPTH = 64;
const MAX_JSON_BYTES = 1024 * 1024;

// The deepest nesting of [ and { in text, outside strings: one pass, no recursion.
function jsonDepth(text) {
  let depth = 0;
  let deepest = 0;
  let inString = false;
  for (let i = 0; i < text.length; i += 1) {
    const c = text.charCodeAt(i);
    if (inString) {
      if (c === 92) i += 1; // backslash: skip the escaped character
      else if (c === 34) inString = false;
    } else if (c === 34) {
      inString = true;
    } else if (c === 123 || c === 91) {
      depth += 1;
      if (depth > deepest) deepest = depth;
    } else if (c === 125 || c === 93) {
      depth -= 1;
    }
  }
  return deepest;
}

// at: how deep the argument's object sits in the request the service reads (0: it is the
// request; 1: a member of it, as options; 2: format.motion). The service's 64 levels count the
// objects around it, so OptionsJson may nest 63.
function jsonObject(text, name, at) {
  const bytes = Buffer.byteLength(text, "utf8");
  if (bytes > MAX_JSON_BYTES) {
    throw new ArgumentError(name, `${name} is ${bytes} bytes long: allowed at most ${MAX_JSON_BYTES} bytes (the service's body limit)`);
  }
  const depth = jsonDepth(text);
  if (depth > MAX_JSON_DEPTH - at) {
    const around = at === 0 ? "" : ` (the service's limit of ${MAX_JSON_DEPTH} counts the ${at === 1 ? "request object" : `${at} objects`} around it)`;
    throw new ArgumentError(name, `${name} nests ${depth} levels deep: allowed at most ${MAX_JSON_DEPTH - at} levels${around}`);
  }
  let value;
  try {
    value = JSON.parse(text);
  } catch (e) {
    throw new ArgumentError(name, `${name} is not valid JSON: ${e.message}`);
  }
  if (value === null || typeof value !== "object" || Array.isArray(value)) {
    throw new ArgumentError(name, `${name} must be a JSON object ({...}), got ${text.slice(0, 60)}`);
  }
  return value;
}

// a: {RadiusMm, LengthMm, ...} -> format (without motion_time_s).
function buildFormat(a) {
  const radius = number(a.RadiusMm, "RadiusMm");
  const length = number(a.LengthMm, "LengthMm");
  const width = number(a.WidthMm, "WidthMm");
  const height = number(a.ContainerHeightMm, "ContainerHeightMm");
  let container;
  if (radius !== 0 && (length !== 0 || width !== 0)) {
    throw new ArgumentError("RadiusMm", `RadiusMm = ${radius} and LengthMm = ${length}, WidthMm = ${width}: give the radius of a round container or the length and width of a rectangular one, not both`);
  } else if (radius !== 0) {
    container = { radius_mm: radius };
  } else if (length !== 0 || width !== 0) {
    container = { shape: "rectangular", length_mm: length, width_mm: width };
  } else {
    throw new ArgumentError("RadiusMm", "RadiusMm = 0 and LengthMm = 0: give the radius of a round container or the length and width of a rectangular one");
  }
  if (height !== 0) container.height_mm = height;

  const density = number(a.DensityKgM3, "DensityKgM3");
  const viscosity = number(a.ViscosityPaS, "ViscosityPaS");
  const name = a.Fluid || "";
  let fluid;
  if (name !== "" && (density !== 0 || viscosity !== 0)) {
    throw new ArgumentError("Fluid", `Fluid = "${name}" and DensityKgM3 = ${density}, ViscosityPaS = ${viscosity}: give a catalogue name or a density and viscosity, not both`);
  } else if (name !== "") {
    fluid = name;
  } else if (density !== 0 || viscosity !== 0) {
    fluid = { density_kg_m3: density, viscosity_pa_s: viscosity };
  } else {
    throw new ArgumentError("Fluid", "Fluid is empty and DensityKgM3 = 0, ViscosityPaS = 0: give a catalogue name (e.g. water) or a density and viscosity");
  }

  const format = { container, fill_height_mm: number(a.FillHeightMm, "FillHeightMm"), fluid };
  const stroke = number(a.StrokeMm, "StrokeMm");
  const motion = a.MotionJson || "";
  if (stroke !== 0 && motion !== "") {
    throw new ArgumentError("StrokeMm", `StrokeMm = ${stroke} and MotionJson given: give the stroke of a straight move or a motion object, not both`);
  } else if (stroke !== 0) {
    format.stroke_mm = stroke;
  } else if (motion !== "") {
    format.motion = jsonObject(motion, "MotionJson", 2);
  } else {
    throw new ArgumentError("StrokeMm", "StrokeMm = 0 and MotionJson is empty: give the stroke (mm) or the motion as JSON");
  }
  return format;
}

function buildPlanRequest(a) {
  const format = buildFormat(a);
  format.motion_time_s = number(a.MotionTimeS, "MotionTimeS");
  const request = { format };
  if (a.Strategy) request.strategy = a.Strategy;
  if (a.OptionsJson) request.options = jsonObject(a.OptionsJson, "OptionsJson", 1);
  return request;
}

function buildMinTimeRequest(a) {
  const extra = a.RequestJson ? jsonObject(a.RequestJson, "RequestJson", 0) : {};
  for (const member of ["format", "eta_motion_max_mm", "eta_rest_max_mm"]) {
    if (member in extra) {
      throw new ArgumentError("RequestJson", `RequestJson.${member}: give it through its own argument, not in RequestJson`);
    }
  }
  const request = { format: buildFormat(a), ...extra };
  // The numbers after the format (EtaMotionMaxMm, ..., JMax): each sets the member its field
  // names; 0 = not given. All are read before any is set, so a bad number is reported first.
  const given = [];
  for (const arg of minTimeArgs) {
    if (arg.type !== "Double" || arg.field.startsWith("format.")) continue;
    const v = number(a[arg.name], arg.name);
    if (v !== 0) given.push([arg.field, v]);
  }
  if (given.some(([field]) => field.startsWith("options.limits.")) && request.options && request.options.limits) {
    throw new ArgumentError("RequestJson", "RequestJson.options.limits: give the machine limits through AMax, VMax, JMax, not both");
  }
  for (const [field, v] of given) setMember(request, field, v);
  return request;
}

// Sets the member at a dotted path (options.limits.a_max), creating the objects on the way as
// copies, so what RequestJson gave is never altered in place.
function setMember(object, path, value) {
  const names = path.split(".");
  let at = object;
  for (const name of names.slice(0, -1)) {
    at[name] = { ...(at[name] || {}) };
    at = at[name];
  }
  at[names[names.length - 1]] = value;
}

// A plan response (full view) -> the PlanFormat outputs, in planOutputs order.
function planSummary(plan) {
  const k = plan.kinematics || {};
  const p = plan.prediction || {};
  const nl = p.nonlinear || {};
  const li = p.linear || {};
  const num = (v) => (typeof v === "number" ? v : NaN);
  return {
    Status: plan.status || "",
    Message: plan.message || "",
    DurationsS: Array.isArray(plan.durations_s) ? plan.durations_s : [],
    A: num(k.a_max),
    B: num(k.a_min),
    EtaMotionNonlinearMm: num(nl.eta_motion_mm),
    EtaRestNonlinearMm: num(nl.eta_rest_mm),
    EtaMotionLinearMm: num(li.eta_motion_mm),
    EtaRestLinearMm: num(li.eta_rest_mm),
    Key: plan.key || "",
  };
}

// The body of POST /v1/batches for a table: its size is checked here, where the refusal can name
// Table, rather than by the service, whose 413 names no member.
function buildTableRequest(a) {
  const request = { table: a.Table || "", table_format: a.TableFormat || "" };
  const bodyBytes = Buffer.byteLength(JSON.stringify(request), "utf8");
  if (bodyBytes > MAX_JSON_BYTES) {
    const tableBytes = Buffer.byteLength(request.table, "utf8");
    throw new ArgumentError("Table", `Table is ${tableBytes} bytes long (${bodyBytes} bytes as the request's JSON): allowed at most ${MAX_JSON_BYTES} bytes (1 MiB, the service's body limit, counting the request around it); split the table`);
  }
  return request;
}

module.exports = { ArgumentError, buildTableRequest, buildPlanRequest, buildMinTimeRequest, planSummary };
