"use strict";
// The methods' arguments: name, OPC UA type, unit, description, and how a request member maps to
// the argument (so a 422 naming `format.container.radius_mm` marks the RadiusMm argument).
// Numbers use 0 (and strings "") for "not given": OPC UA method arguments are all mandatory.

const formatArgs = [
  { name: "RadiusMm", type: "Double", unit: "mm", field: "format.container.radius_mm",
    description: "Radius of a round container (mm); 0 for a rectangular one (LengthMm, WidthMm)" },
  { name: "LengthMm", type: "Double", unit: "mm", field: "format.container.length_mm",
    description: "Rectangular container: length along the motion (mm); 0 for a round one" },
  { name: "WidthMm", type: "Double", unit: "mm", field: "format.container.width_mm",
    description: "Rectangular container: width across the motion (mm); 0 for a round one" },
  { name: "ContainerHeightMm", type: "Double", unit: "mm", field: "format.container.height_mm",
    description: "Container height (mm): the free board is height - fill height; 0 = not given" },
  { name: "FillHeightMm", type: "Double", unit: "mm", field: "format.fill_height_mm",
    description: "Fill height of the liquid (mm)" },
  { name: "Fluid", type: "String", unit: null, field: "format.fluid",
    description: "Fluid catalogue name (e.g. water, GET /v1/fluids); empty for DensityKgM3 + ViscosityPaS" },
  { name: "DensityKgM3", type: "Double", unit: "kg_m3", field: "format.fluid.density_kg_m3",
    description: "Custom fluid density (kg/m³) when Fluid is empty; else 0" },
  { name: "ViscosityPaS", type: "Double", unit: "pa_s", field: "format.fluid.viscosity_pa_s",
    description: "Custom fluid dynamic viscosity (Pa·s) when Fluid is empty; else 0" },
  { name: "StrokeMm", type: "Double", unit: "mm", field: "format.stroke_mm",
    description: "Stroke of a straight move (mm); 0 when MotionJson gives the motion" },
  { name: "MotionJson", type: "String", unit: null, field: "format.motion",
    description: "The motion as a JSON object (format.motion: line, arc, path); empty when StrokeMm is given" },
];

const planArgs = [
  { name: "RecipeId", type: "String", unit: null, field: null,
    description: "Product (recipe) id: the plan is kept in Products/<RecipeId>; empty = not kept" },
  ...formatArgs,
  { name: "MotionTimeS", type: "Double", unit: "s", field: "format.motion_time_s",
    description: "Motion time T (s)" },
  { name: "Strategy", type: "String", unit: null, field: "strategy",
    description: "Strategy (auto, notch, multi_notch, min_jerk_band, time_domain, shaper, ...); empty = auto" },
  { name: "OptionsJson", type: "String", unit: null, field: "options",
    description: "Plan options as a JSON object (as in POST /v1/plans, e.g. {\"limits\": {\"a_max\": 10}}); empty = defaults" },
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
  { name: "EtaMotionMaxMm", type: "Double", unit: "mm", field: "eta_motion_max_mm",
    description: "Limit of the wave height during the motion (mm); 0 = the free board (needs ContainerHeightMm)" },
  { name: "EtaRestMaxMm", type: "Double", unit: "mm", field: "eta_rest_max_mm",
    description: "Limit of the residual wave height at rest (mm); 0 = 3 mm" },
  { name: "AMax", type: "Double", unit: "m_s2", field: "options.limits.a_max",
    description: "Machine acceleration limit (m/s²); 0 = none" },
  { name: "VMax", type: "Double", unit: "m_s", field: "options.limits.v_max",
    description: "Machine velocity limit (m/s); 0 = none" },
  { name: "JMax", type: "Double", unit: "m_s3", field: "options.limits.j_max",
    description: "Machine jerk limit (m/s³); 0 = none" },
  { name: "RequestJson", type: "String", unit: null, field: "",
    description: "Further min-time request members as a JSON object (strategies, limit_model, options, ...); empty = defaults" },
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

module.exports = { formatArgs, planArgs, planOutputs, minTimeArgs, minTimeOutputs, getPlanArgs, argumentOfField };
