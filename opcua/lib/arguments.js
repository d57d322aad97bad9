"use strict";
// The methods' arguments: name, OPC UA type, unit, description, and how a request member maps to
// the argument (so a 422 naming `format.container.radius_mm` marks the RadiusMm argument).
// Numbers use 0 (and strings "") for "not given": OPC UA method arguments are all mandatory.

// A Double argument: unit a key of units.js; field the request member it sets (a 422 naming it,
// or a member under it, marks this argument).
function num(name, unit, field, description) {
  return { name, type: "Double", unit, field, description };
}

// A String argument; field as for num (null: no request member).
function str(name, field, description) {
  return { name, type: "String", unit: null, field, description };
}

const formatArgs = [
  num("RadiusMm", "mm", "format.container.radius_mm",
    "Radius of a round container (mm); 0 for a rectangular one (LengthMm, WidthMm)"),
  num("LengthMm", "mm", "format.container.length_mm",
    "Rectangular container: length along the motion (mm); 0 for a round one"),
  num("WidthMm", "mm", "format.container.width_mm",
    "Rectangular container: width across the motion (mm); 0 for a round one"),
  num("ContainerHeightMm", "mm", "format.container.height_mm",
    "Container height (mm): the free board is height - fill height; 0 = not given"),
  num("FillHeightMm", "mm", "format.fill_height_mm", "Fill height of the liquid (mm)"),
  str("Fluid", "format.fluid",
    "Fluid catalogue name (e.g. water, GET /v1/fluids); empty for DensityKgM3 + ViscosityPaS"),
  num("DensityKgM3", "kg_m3", "format.fluid.density_kg_m3",
    "Custom fluid density (kg/m³) when Fluid is empty; else 0"),
  num("ViscosityPaS", "pa_s", "format.fluid.viscosity_pa_s",
    "Custom fluid dynamic viscosity (Pa·s) when Fluid is empty; else 0"),
  num("StrokeMm", "mm", "format.stroke_mm",
    "Stroke of a straight move (mm); 0 when MotionJson gives the motion"),
  str("MotionJson", "format.motion",
    "The motion as a JSON object (format.motion: line, arc, path); empty when StrokeMm is given"),
];

const planArgs = [
  str("RecipeId", null, "Product (recipe) id: the plan is kept in Products/<RecipeId>; empty = not kept"),
  ...formatArgs,
  num("MotionTimeS", "s", "format.motion_time_s", "Motion time T (s)"),
  str("Strategy", "strategy",
    "Strategy (auto, notch, multi_notch, min_jerk_band, time_domain, shaper, ...); empty = auto"),
  str("OptionsJson", "options",
    "Plan options as a JSON object (as in POST /v1/plans, e.g. {\"limits\": {\"a_max\": 10}}); empty = defaults"),
];

const planOutputs = [
  { name: "Status", type: "String", unit: null, description: "Plan status: optimal, acceptable, infeasible, time_limit, failed" },
  { name: "Message", type: "String", unit: null, description: "What happened, for a line engineer" },
  { name: "DurationsS", type: "Double", array: true, unit: "s", description: "The 7 segment durations T1..T7 (s); empty for a general (filtered) law" },
  { name: "A", type: "Double", unit: "m_s2", description: "Acceleration plateau level A (m/s²)" },
  { name: "B", type: "Double", unit: "m_s2", description: "Deceleration plateau level B, positive (m/s²)" },
  { name: "EtaMotionNonlinearMm", type: "Double", unit: "mm", description: "Peak wave height during the motion, nonlinear model (mm)" },
  { name: "EtaRestNonlinearMm", type: "Double", unit: "mm", description: "Peak wave height in the rest window, nonlinear model (mm)" },
  { name: "EtaMotionLinearMm", type: "Double", unit: "mm", description: "Peak wave height during the motion, linear model (mm)" },
  { name: "EtaRestLinearMm", type: "Double", unit: "mm", description: "Peak wave height in the rest window, linear model (mm)" },
  { name: "Key", type: "String", unit: null, description: "Recipe key (GetPlan, GET /v1/plans/{key})" },
];

const minTimeArgs = [
  ...formatArgs,
  num("EtaMotionMaxMm", "mm", "eta_motion_max_mm",
    "Limit of the wave height during the motion (mm); 0 = the free board (needs ContainerHeightMm)"),
  num("EtaRestMaxMm", "mm", "eta_rest_max_mm", "Limit of the residual wave height at rest (mm); 0 = 3 mm"),
  num("AMax", "m_s2", "options.limits.a_max", "Machine acceleration limit (m/s²); 0 = none"),
  num("VMax", "m_s", "options.limits.v_max", "Machine velocity limit (m/s); 0 = none"),
  num("JMax", "m_s3", "options.limits.j_max", "Machine jerk limit (m/s³); 0 = none"),
  str("RequestJson", "",
    "Further min-time request members as a JSON object (strategies, limit_model, options, ...); empty = defaults"),
];

const minTimeOutputs = [
  { name: "TMinS", type: "Double", unit: "s", description: "Shortest motion time of the winning strategy (s)" },
  { name: "Winner", type: "String", unit: null, description: "The strategy that reaches TMinS" },
  { name: "GainPct", type: "Double", unit: "pct", description: "Gain over the uniform law's T_min (%); NaN when the uniform law was not searched" },
  { name: "Key", type: "String", unit: null, description: "Min-time answer key" },
];

const getPlanArgs = [
  { name: "Key", type: "String", unit: null, field: "key", description: "Recipe key of a plan (PlanFormat's Key)" },
];

const tableArgs = [
  str("Table", "table", "A recipe table (docs/batch.md): CSV with a header row, JSON lines or a JSON array"),
  str("TableFormat", "table_format", "csv, jsonl or json"),
];

const tableOutputs = [
  { name: "JobId", type: "String", unit: null, description: "The batch job id (GET /v1/batches/{id}); its recipes land in Products when it finishes" },
];

const importArgs = [
  str("JobId", "id", "A finished batch job's id (POST /v1/batches)"),
];

const importOutputs = [
  { name: "Planned", type: "UInt32", unit: null, description: "Recipes whose plan was written to Products" },
  { name: "Failed", type: "UInt32", unit: null, description: "Recipes whose row is an error (Status = error)" },
];

// The argument whose field is the longest prefix of the error's field (e.g.
// format.fluid.density_kg_m3 -> DensityKgM3, options.limits.a_max -> OptionsJson for PlanFormat).
function argumentOfField(args, field) {
  if (!field) return -1;
  let best = -1;
  let bestLength = -1;
  args.forEach((a, i) => {
    if (a.field === null || a.field === undefined) return;
    const f = a.field;
    const matches = f === "" || field === f || field.startsWith(f + ".") || field.startsWith(f + "[");
    if (matches && f.length > bestLength) {
      best = i;
      bestLength = f.length;
    }
  });
  return best;
}

module.exports = {
  formatArgs, planArgs, planOutputs, minTimeArgs, minTimeOutputs, getPlanArgs,
  tableArgs, tableOutputs, importArgs, importOutputs, argumentOfField,
};
