"use strict";
// The Products folder (PackML's spirit, OPC 30050): one object per recipe id, holding the recipe's
// parameters and its last plan as variables with engineering units, its Status and LastPlanned, so
// a PLC or HMI reads a recipe's durations without calling a method. Products live in the gateway's
// memory: a restart starts with an empty folder (the plans stay in the service's store; PlanFormat
// or ImportBatchJob brings them back).
const { DataType, Variant } = require("./stack");
const { units } = require("./units");
const { planArgs, planOutputs } = require("./arguments");

const MAX_RECIPE_ID = 128;
// Each product is 59 nodes of the address space, ~285 kB of resident memory with node-opcua 2.160
// (docs/opcua.md): the default 2 000 products hold ~700 MB, up to 1.2 GB while importing into a
// full folder.
const DEFAULT_MAX_PRODUCTS = 2000;

// A variable of a product: [browse name, type ("Double[]" for an array), unit, description, value].
function variableOf(arg, description, value) {
  return [arg.name, arg.array ? `${arg.type}[]` : arg.type, arg.unit, description, value];
}

// Parameters: PlanFormat's arguments but RecipeId, valued from (plan, request options). Where the
// value is not what the caller typed (the fluid the service resolved, a batch row's options) the
// description says so in place of the argument's.
const parameterValues = {
  RadiusMm: (p) => p.format.container.radius_mm,
  LengthMm: (p) => p.format.container.length_mm,
  WidthMm: (p) => p.format.container.width_mm,
  ContainerHeightMm: (p) => p.format.container.height_mm,
  FillHeightMm: (p) => p.format.fill_height_mm,
  Fluid: (p) => (typeof p.format.fluid === "string" ? p.format.fluid : p.format.fluid && p.format.fluid.name),
  DensityKgM3: (p) => p.format.fluid && p.format.fluid.density_kg_m3,
  ViscosityPaS: (p) => p.format.fluid && p.format.fluid.viscosity_pa_s,
  StrokeMm: (p) => p.format.stroke_mm,
  MotionJson: (p) => (p.format.motion ? JSON.stringify(p.format.motion) : ""),
  MotionTimeS: (p) => p.format.motion_time_s,
  Strategy: (p) => p.strategy,
  OptionsJson: (p, options) => options || "",
};
const parameterDescriptions = {
  Fluid: "Fluid name (as the service resolved it)",
  DensityKgM3: "Fluid density (kg/m³)",
  ViscosityPaS: "Fluid dynamic viscosity (Pa·s)",
  Strategy: "Strategy planned",
  OptionsJson: "Plan options as given to PlanFormat (JSON); empty from a batch",
};
const parameterVars = planArgs.filter((a) => a.name !== "RecipeId").map((a) =>
  variableOf(a, parameterDescriptions[a.name] || a.description, parameterValues[a.name]));

// Last plan: PlanFormat's outputs but Status (the product's own Status), valued from the plan
// summary (requests.js planSummary).
const planVars = planOutputs.filter((o) => o.name !== "Status").map((o) =>
  variableOf(o, o.description, (summary) => summary[o.name]));

// What a RecipeId may not hold, with why: control characters (C0, DEL and C1, NEL among them),
// the line and paragraph separators U+2028 and U+2029 (node-opcua's node id parser stops at them,
// so "p\u2029q" would be product "p"), lone surrogates (no UTF-8 for them) and U+FFFD (what a
// lone surrogate became on its way through a client's UTF-8 encoder).
const REFUSED_RECIPE_CHARS = /[\u0000-\u001f\u007f-\u009f\u2028\u2029\ufffd]|[\ud800-\udbff](?![\udc00-\udfff])|(?<![\ud800-\udbff])[\udc00-\udfff]/;
const ALLOWED_RECIPE_CHARS = "allowed: printable characters, not U+0000 to U+001F, U+007F to U+009F, U+2028, U+2029, U+FFFD or a lone surrogate";

function checkRecipeId(id) {
  if (typeof id !== "string" || id.length === 0) return "RecipeId is empty";
  if (id.length > MAX_RECIPE_ID) return `RecipeId is ${id.length} characters long: allowed 1 to ${MAX_RECIPE_ID}`;
  const m = REFUSED_RECIPE_CHARS.exec(id);
  if (m) {
    const code = m[0].charCodeAt(0);
    const what = code <= 0x9f ? "a control character" : code === 0xfffd ? "the replacement character" : code >= 0xd800 && code <= 0xdfff ? "a lone surrogate" : "a line or paragraph separator";
    const hex = code.toString(16).toUpperCase().padStart(4, "0");
    // JSON.stringify escapes C0 controls and lone surrogates but not U+2028/9 or C1: escaped here.
    const shown = JSON.stringify(id.slice(0, 60)).replace(/[\u007f-\u009f\u2028\u2029\ufffd]/g, (c) => `\\u${c.charCodeAt(0).toString(16).padStart(4, "0")}`);
    return `RecipeId ${shown} contains ${what} (U+${hex}): ${ALLOWED_RECIPE_CHARS}`;
  }
  return null;
}

function nodeIdPart(id) {
  return id.replace(/%/g, "%25").replace(/\./g, "%2E");
}

class ProductError extends Error {}

// Deletes node and everything it aggregates (components and properties, e.g. an analog item's
// EngineeringUnits): node-opcua's deleteNode removes only the node itself, and the children left
// in the namespace's index would keep their memory.
function deleteTree(addressSpace, node) {
  const pending = [node];
  const all = [];
  while (pending.length > 0) {
    const n = pending.pop();
    all.push(n);
    for (const c of n.getAggregates()) pending.push(c);
  }
  for (let i = all.length - 1; i >= 0; i -= 1) {
    try { addressSpace.deleteNode(all[i]); } catch (e) { /* already gone */ }
  }
}

class Products {
  // maxProducts: the most products kept (--max-products); onEvict(id): told when the product that
  // was planned longest ago leaves to make room for a new one.
  constructor(namespace, parent, { maxProducts = DEFAULT_MAX_PRODUCTS, onEvict = () => {} } = {}) {
    this.namespace = namespace;
    this.maxProducts = maxProducts;
    this.onEvict = onEvict;
    this.folder = namespace.addObject({ organizedBy: parent, typeDefinition: "FolderType", browseName: "Products", nodeId: "s=Products",
      description: "One object per recipe id: its parameters and last plan (PackML products)" });
    this.items = new Map();
  }

  variable(parent, prefix, state, [name, type, unit, description]) {
    const isArray = type.endsWith("[]");
    const dataType = isArray ? type.slice(0, -2) : type;
    const options = {
      componentOf: parent,
      browseName: name,
      nodeId: `s=${prefix}.${name}`,
      description,
      dataType,
      valueRank: isArray ? 1 : -1,
      minimumSamplingInterval: 100,
      value: {
        get: () => {
          const v = state[name];
          if (v === undefined || v === null) return new Variant({ dataType: DataType[dataType], value: isArray ? [] : (dataType === "String" ? "" : 0), arrayType: isArray ? 1 : undefined });
          return new Variant({ dataType: DataType[dataType], value: v, arrayType: isArray ? 1 : undefined });
        },
      },
    };
    if (unit) {
      return this.namespace.addAnalogDataItem({ ...options, engineeringUnits: units[unit], engineeringUnitsRange: { low: 0, high: 1e6 } });
    }
    return this.namespace.addVariable(options);
  }

  ensure(id) {
    let item = this.items.get(id);
    if (item) return item;
    // Room for one more: the product planned longest ago goes (the Map is kept in planning order).
    while (this.items.size >= this.maxProducts) {
      const [oldest, old] = this.items.entries().next().value;
      this.items.delete(oldest);
      deleteTree(this.namespace.addressSpace, old.node);
      this.onEvict(oldest);
    }
    const prefix = `Products.${nodeIdPart(id)}`;
    // Built fully or not at all: a failure half way deletes what was added, so a later plan of
    // the same id starts from nothing instead of failing on the leftovers.
    let node = null;
    try {
      // A qualified name object, not the string: node-opcua would read "2:cup" as namespace 2.
      node = this.namespace.addObject({ organizedBy: this.folder, browseName: { name: id, namespaceIndex: this.namespace.index }, nodeId: `s=${prefix}`,
        description: `Recipe ${id}` });
      const state = { Status: "", LastPlanned: null };
      const params = {};
      const plan = {};
      this.namespace.addVariable({ componentOf: node, browseName: "Status", nodeId: `s=${prefix}.Status`, dataType: "String",
        description: "Plan status of the last plan (optimal, acceptable, infeasible, time_limit, failed) or error",
        minimumSamplingInterval: 100,
        value: { get: () => new Variant({ dataType: DataType.String, value: state.Status }) } });
      this.namespace.addVariable({ componentOf: node, browseName: "LastPlanned", nodeId: `s=${prefix}.LastPlanned`, dataType: "DateTime",
        description: "When the gateway last received a plan (or an error) for this recipe (UTC)",
        minimumSamplingInterval: 100,
        value: { get: () => new Variant({ dataType: DataType.DateTime, value: state.LastPlanned }) } });
      const paramsNode = this.namespace.addObject({ componentOf: node, browseName: "Parameters", nodeId: `s=${prefix}.Parameters`,
        description: "The recipe's format, strategy and options" });
      const planNode = this.namespace.addObject({ componentOf: node, browseName: "LastPlan", nodeId: `s=${prefix}.LastPlan`,
        description: "The recipe's last plan" });
      for (const v of parameterVars) this.variable(paramsNode, `${prefix}.Parameters`, params, v);
      for (const v of planVars) this.variable(planNode, `${prefix}.LastPlan`, plan, v);
      item = { node, state, params, plan };
    } catch (err) {
      if (node) {
        deleteTree(this.namespace.addressSpace, node);
      }
      // node-opcua's message carries a dump of the address space: only its first line.
      throw new ProductError(`product ${JSON.stringify(id.slice(0, 60))} could not be created: ${String(err.message).split("\n")[0].slice(0, 200)}`);
    }
    this.items.set(id, item);
    return item;
  }

  // The product of id, made the most recently planned one.
  touch(id) {
    const item = this.ensure(id);
    this.items.delete(id);
    this.items.set(id, item);
    return item;
  }

  // A full plan response for recipe id; options: the OptionsJson text it was planned with.
  setPlan(id, plan, summary, options) {
    const item = this.touch(id);
    for (const [name, , , , get] of parameterVars) {
      let v;
      try { v = get(plan, options); } catch (e) { v = undefined; }
      item.params[name] = v;
    }
    for (const [name, , , , get] of planVars) item.plan[name] = get(summary);
    item.state.Status = summary.Status;
    item.state.LastPlanned = new Date();
  }

  // A recipe whose plan failed (a batch row with an error): its last plan is kept, Status says error.
  setError(id, message) {
    const item = this.touch(id);
    item.plan.Message = message;
    item.state.Status = "error";
    item.state.LastPlanned = new Date();
  }
}

module.exports = { Products, ProductError, checkRecipeId };
