"use strict";
// The address space of the gateway: Objects/Slosh with the methods (PlanFormat, MinTime, GetPlan,
// ImportBatchJob, PlanTable), the health variables (ServiceReady, LastError) and the Products
// folder. Each method calls the slosh HTTP service (docs/api.md) through one bounded client.
const { DataType, Variant, VariantArrayType, StatusCodes, DiagnosticInfo } = require("./stack");
const { units, none: NO_UNIT } = require("./units");
const A = require("./arguments");
const { buildPlanRequest, buildMinTimeRequest, buildTableRequest, planSummary, ArgumentError } = require("./requests");
const { checkPlan, checkMinTime, checkJob, checkJobPage, checkJobCreated } = require("./answers");
const { ServiceError } = require("./service_client");
const { failureResult } = require("./results");
const { Products, checkRecipeId } = require("./products");

// Rows per results page of a batch job. A row of the full view is about 30 KiB
// (docs/machines.md), so a page is some 7.5 MB: far below what the service client accepts in one
// answer (MAX_ANSWER_BYTES, 64 MiB) even for rows with long general laws.
const PAGE_ROWS = 250;

// How long the PlanTable follower retries a failing service: the service's default
// batch_job_stale_s (docs/machines.md), after which an unfinished job of a stopped replica reads
// as failed anyway.
const FOLLOW_RETRY_MS = 30000;


function argumentDefinition(a) {
  return {
    name: a.name,
    description: { text: a.unit ? `${a.description} [${units[a.unit].displayName.text}]` : a.description },
    dataType: DataType[a.type],
    valueRank: a.array ? 1 : -1,
  };
}

function outputVariants(outputs, values) {
  return outputs.map((o) => {
    const v = values[o.name];
    if (o.array) return new Variant({ dataType: DataType[o.type], arrayType: VariantArrayType.Array, value: v || [] });
    return new Variant({ dataType: DataType[o.type], value: v });
  });
}

// Argument values by name from the call's variants.
function valuesOf(args, inputArguments) {
  const values = {};
  args.forEach((a, i) => { values[a.name] = inputArguments[i] ? inputArguments[i].value : undefined; });
  return values;
}

class Gateway {
  // server: an initialised OPCUAServer; service: a ServiceClient; options.pollMs: readiness poll
  // period; options.log(message).
  constructor(server, service, options) {
    this.server = server;
    this.service = service;
    this.log = options.log || (() => {});
    this.pollMs = options.pollMs;
    this.ready = false;
    this.lastError = "";
    const addressSpace = server.engine.addressSpace;
    const namespace = addressSpace.getOwnNamespace();
    this.namespace = namespace;
    this.root = namespace.addObject({ organizedBy: addressSpace.rootFolder.objects, browseName: "Slosh", nodeId: "s=Slosh",
      description: "Anti-sloshing motion planning (the slosh service behind this gateway)" });
    namespace.addVariable({ componentOf: this.root, browseName: "ServiceReady", nodeId: "s=Slosh.ServiceReady", dataType: "Boolean",
      description: "True while the slosh service answers GET /readyz with 200 (polled)", minimumSamplingInterval: 100,
      value: { get: () => new Variant({ dataType: DataType.Boolean, value: this.ready }) } });
    namespace.addVariable({ componentOf: this.root, browseName: "LastError", nodeId: "s=Slosh.LastError", dataType: "String",
      description: "The last failure of a method call or of the readiness poll (UTC time, method, message); empty when none",
      minimumSamplingInterval: 100,
      value: { get: () => new Variant({ dataType: DataType.String, value: this.lastError }) } });
    namespace.addVariable({ componentOf: this.root, browseName: "ServiceUrl", nodeId: "s=Slosh.ServiceUrl", dataType: "String",
      description: "The slosh HTTP service this gateway calls",
      value: { dataType: DataType.String, value: service.base.href } });
    this.products = new Products(namespace, this.root, {
      maxProducts: options.maxProducts,
      onEvict: (id) => this.setError("Products", `product ${JSON.stringify(id.slice(0, 60))} (planned longest ago) removed: --max-products ${options.maxProducts} reached`),
    });

    this.argumentsOf = {};
    this.explainStackRefusals(server);
    this.method("PlanFormat", A.planArgs, A.planOutputs, "Plan one format (POST /v1/plans); with a RecipeId the plan is kept in Products", (v) => this.planFormat(v));
    this.method("MinTime", A.minTimeArgs, A.minTimeOutputs, "Shortest motion time of the format within the limits (POST /v1/min-time)", (v) => this.minTime(v));
    this.method("GetPlan", A.getPlanArgs, A.planOutputs, "A plan by its key (GET /v1/plans/{key})", (v) => this.getPlan(v));
    this.method("PlanTable", A.tableArgs, A.tableOutputs, "Plan a recipe table as a batch job (POST /v1/batches); its recipes land in Products when it finishes", (v) => this.planTable(v));
    this.method("ImportBatchJob", A.importArgs, A.importOutputs, "Write the recipes of a finished batch job to Products", (v) => this.importBatchJob(v));
  }

  // node-opcua checks the number and types of a call's arguments itself and answers
  // BadArgumentsMissing, BadTooManyArguments or BadTypeMismatch without calling the method, so
  // with no message and no LastError. The calls are wrapped where node-opcua makes them
  // (AddressSpaceAccessor.callMethod, per instance) to give those answers the gateway's message.
  explainStackRefusals(server) {
    const accessor = server.engine && server.engine.addressSpaceAccessor;
    if (!accessor || typeof accessor.callMethod !== "function") return;
    const original = accessor.callMethod;
    const refusals = [StatusCodes.BadArgumentsMissing, StatusCodes.BadTooManyArguments, StatusCodes.BadTypeMismatch, StatusCodes.BadOutOfRange].map((c) => c.value);
    accessor.callMethod = async (context, methodToCall) => {
      const result = await original.call(accessor, context, methodToCall);
      const id = methodToCall.methodId;
      const name = id && id.namespace === this.namespace.index && typeof id.value === "string" && id.value.startsWith("Slosh.") ? id.value.slice(6) : null;
      const args = name && this.argumentsOf[name];
      if (!args || !result || !result.statusCode || !refusals.includes(result.statusCode.value)) return result;
      const given = methodToCall.inputArguments || [];
      const typeOf = (v) => (v ? `${DataType[v.dataType]}${v.arrayType === VariantArrayType.Array ? "[]" : ""}` : "nothing");
      const wanted = (a) => `${a.type}${a.array ? "[]" : ""}`;
      let message;
      let marked = [];
      if (given.length !== args.length) {
        message = `${name} takes ${args.length} argument${args.length === 1 ? "" : "s"} (${args.map((a) => a.name).join(", ")}): ${given.length} given`;
      } else {
        const results = result.inputArgumentResults || [];
        marked = args.map((_, i) => i).filter((i) => results[i] && results[i].value !== StatusCodes.Good.value);
        message = marked.map((i) => `${args[i].name} must be a ${wanted(args[i])}, got ${typeOf(given[i])}`).join("; ") || `${name}: ${result.statusCode.name}`;
      }
      this.setError(name, message);
      const inputArgumentDiagnosticInfos = args.map((_, i) => (marked.length === 0 || marked.includes(i) ? new DiagnosticInfo({ additionalInfo: message }) : new DiagnosticInfo({})));
      return { ...result, inputArgumentResults: result.inputArgumentResults || args.map(() => StatusCodes.Good), inputArgumentDiagnosticInfos };
    };
  }

  method(name, args, outputs, description, handler) {
    this.argumentsOf[name] = args;
    const method = this.namespace.addMethod(this.root, {
      browseName: name, nodeId: `s=Slosh.${name}`, description,
      inputArguments: args.map(argumentDefinition),
      outputArguments: outputs.map(argumentDefinition),
    });
    // OPC UA Arguments carry no unit: the units of the arguments are properties of the method, one
    // EUInformation per argument in argument order (unitId -1 for unitless ones).
    for (const [prop, list] of [["InputArgumentUnits", args], ["OutputArgumentUnits", outputs]]) {
      this.namespace.addVariable({ propertyOf: method, browseName: prop, nodeId: `s=Slosh.${name}.${prop}`,
        dataType: "EUInformation", valueRank: 1, arrayDimensions: [list.length],
        description: `The engineering unit of each ${prop.startsWith("Input") ? "input" : "output"} argument, in argument order`,
        value: { dataType: DataType.ExtensionObject, arrayType: VariantArrayType.Array,
          value: list.map((a) => (a.unit ? units[a.unit] : NO_UNIT)) } });
    }
    // Two parameters: node-opcua takes a two-argument function as promise-returning.
    method.bindMethod(async (inputArguments, _context) => {
      try {
        const values = await handler(valuesOf(args, inputArguments));
        return { statusCode: StatusCodes.Good, outputArguments: outputVariants(outputs, values) };
      } catch (err) {
        const result = failureResult(err, args);
        this.setError(name, result.message);
        delete result.message;
        return result;
      }
    });
    return method;
  }

  setError(where, message) {
    this.lastError = `${new Date().toISOString()} ${where}: ${message}`;
    this.log(this.lastError);
  }

  async planFormat(v) {
    const id = v.RecipeId || "";
    if (id !== "") {
      const problem = checkRecipeId(id);
      if (problem) throw new ArgumentError("RecipeId", problem);
    }
    const { body } = await this.service.request("POST", "/v1/plans", buildPlanRequest(v));
    checkPlan(body, "POST", "/v1/plans");
    const summary = planSummary(body);
    if (id !== "") this.products.setPlan(id, body, summary, v.OptionsJson || "");
    return summary;
  }

  async minTime(v) {
    const { body } = await this.service.request("POST", "/v1/min-time", buildMinTimeRequest(v));
    checkMinTime(body, "POST", "/v1/min-time");
    const h = body.headline || {};
    return {
      TMinS: typeof h.t_min_s === "number" ? h.t_min_s : NaN,
      Winner: h.winner || "",
      GainPct: typeof h.gain_pct === "number" ? h.gain_pct : NaN,
      Key: body.key || "",
    };
  }

  async getPlan(v) {
    const key = v.Key || "";
    if (!/^[0-9a-f]{32}$/.test(key)) {
      throw new ArgumentError("Key", `Key = ${JSON.stringify(key.slice(0, 60))} is not a recipe key: 32 lowercase hex digits expected`);
    }
    const { body } = await this.service.request("GET", `/v1/plans/${key}`);
    checkPlan(body, "GET", "/v1/plans/{key}");
    return planSummary(body);
  }

  async planTable(v) {
    // Without a view: a full row costs some 30 KiB of the service's batch_jobs_bytes, which would
    // bound a table to a few thousand recipes; the import fetches each plan by its key instead.
    const { body } = await this.service.request("POST", "/v1/batches", buildTableRequest(v));
    checkJobCreated(body, "POST", "/v1/batches");
    this.follow(body.id);
    return { JobId: body.id };
  }

  // The job record of id with its results page at offset (the page only once the job finished).
  // deadline: see importJob.
  async jobPage(id, offset, deadline = null) {
    const { body } = await this.service.request("GET", `/v1/batches/${encodeURIComponent(id)}?offset=${offset}&limit=${PAGE_ROWS}`, undefined, this.bounded(deadline));
    checkJob(body, "GET", "/v1/batches/{id}");
    return body;
  }

  // Polls a job this gateway submitted until it finishes, then imports it from the poll's own
  // answer (which holds the first page). Bounded by the job's own life: a job that stays
  // unfinished for its stale time reads as failed. A failure that may pass (the service
  // restarting or overloaded: no connection, no answer in time, 502/503/504) is retried for
  // FOLLOW_RETRY_MS after the first one of a row of failures; no caller waits on this, so only
  // LastError tells, and it says how to import the job by hand once the service is back.
  follow(id) {
    let failingSince = null;
    let delay = 500;
    const tick = async () => {
      try {
        const record = await this.jobPage(id, 0);
        failingSince = null;
        delay = 500;
        if (record.state === "queued" || record.state === "running") {
          setTimeout(tick, 250).unref();
          return;
        }
        if (record.state === "done") await this.importJob(id, record);
        else this.setError("PlanTable", `batch job ${id} ended ${record.state}: ${record.message || ""}`);
      } catch (err) {
        const transient = err.kind === "unreachable" || err.kind === "timeout" || (err.kind === "http" && [502, 503, 504].includes(err.status));
        if (transient && !this.stopped) {
          if (failingSince === null) failingSince = Date.now();
          if (Date.now() - failingSince < FOLLOW_RETRY_MS) {
            this.setError("PlanTable", `batch job ${id}: ${err.message}; retrying for up to ${FOLLOW_RETRY_MS / 1000} s`);
            setTimeout(tick, delay).unref();
            delay = Math.min(delay * 2, 4000);
            return;
          }
          this.setError("PlanTable", `batch job ${id}: ${err.message}; gave up following it after ${FOLLOW_RETRY_MS / 1000} s of failures: call ImportBatchJob with JobId ${id} once the service is back (the job is kept for batch_job_ttl_s once done)`);
          return;
        }
        this.setError("PlanTable", `batch job ${id}: ${err.message}`);
      }
    };
    setTimeout(tick, 100).unref();
  }

  async importBatchJob(v) {
    const id = v.JobId || "";
    if (!/^[0-9a-f]{1,64}$/.test(id)) {
      throw new ArgumentError("JobId", `JobId = ${JSON.stringify(id.slice(0, 60))} is not a batch job id: hex digits expected`);
    }
    // The whole call, not each request, is bounded by --timeout-s: an import of thousands of rows
    // (one request each) would otherwise go on long after the client gave up on it.
    const deadline = { at: Date.now() + this.service.timeoutMs, done: 0, failed: 0 };
    return this.importJob(id, await this.jobPage(id, 0, deadline), deadline);
  }

  // The options of a request made under deadline (null: each request has the whole --timeout-s).
  bounded(deadline) {
    if (!deadline) return {};
    const left = deadline.at - Date.now();
    if (left <= 0) this.expired(deadline);
    return { timeoutMs: left, boundName: "--timeout-s, the bound of the whole ImportBatchJob call", onTimeout: () => this.expiredError(deadline) };
  }

  expiredError(deadline) {
    return new ServiceError("timeout", `ImportBatchJob did not finish within ${this.service.timeoutMs / 1000} s (--timeout-s): ${deadline.done} rows imported and ${deadline.failed} failed before it stopped, the rest not imported; `
      + "call it again to import the whole job (rows already imported are written again), or use PlanTable, which imports in the background");
  }

  expired(deadline) {
    throw this.expiredError(deadline);
  }

  // Writes the rows of job id to Products; first: its record with the first results page.
  // deadline: {at (ms since the epoch), done, failed} bounding the whole import, which stops
  // between two rows once it passed (the rows written stay written); null for the background
  // import of PlanTable, which no caller waits on.
  async importJob(id, first, deadline = null) {
    if (first.state !== "done") {
      const p = first.progress || {};
      throw Object.assign(new ArgumentError("JobId", `batch job ${id} is ${first.state} (${p.done || 0} of ${p.total || 0} done): import it once it is done`), { invalidState: true });
    }
    let planned = 0;
    let failed = 0;
    let pageBody = first;
    for (;;) {
      checkJobPage(pageBody, "GET", "/v1/batches/{id}");
      const page = pageBody.results;
      for (const row of page.rows) {
        if (deadline) {
          deadline.done = planned;
          deadline.failed = failed;
          if (Date.now() >= deadline.at) this.expired(deadline);
        }
        // One bad row (an id the gateway refuses, a plan that is gone or malformed) is counted as
        // failed with its message and never stops the rows after it.
        const rid = row.recipe_id === undefined || row.recipe_id === null || row.recipe_id === "" ? `row-${row.row}` : String(row.recipe_id);
        const refused = checkRecipeId(rid);
        if (refused) {
          failed += 1;
          this.setError("ImportBatchJob", `batch job ${id} row ${row.row}: ${refused}; the row is not imported`);
          continue;
        }
        try {
          if (row.status === "error" || !row.key) {
            this.products.setError(rid, row.error ? row.error.message : (row.message || "error"));
            failed += 1;
            continue;
          }
          const plan = await this.planOfRow(row, deadline);
          this.products.setPlan(rid, plan, planSummary(plan), "");
          planned += 1;
        } catch (err) {
          if (err.kind === "timeout" || err.kind === "unreachable") throw err;
          failed += 1;
          this.setError("ImportBatchJob", `batch job ${id} row ${row.row} (${JSON.stringify(rid.slice(0, 60))}): ${String(err.message).split("\n")[0].slice(0, 200)}`);
        }
      }
      if (page.next_offset === null || page.next_offset === undefined) break;
      if (deadline) {
        deadline.done = planned;
        deadline.failed = failed;
      }
      pageBody = await this.jobPage(id, page.next_offset, deadline);
    }
    return { Planned: planned, Failed: failed };
  }

  // The full plan of a batch row, which carries the format the recipe was planned with: the row's
  // own (a job posted with view full by another client), else the one the service keeps under its
  // key.
  async planOfRow(row, deadline) {
    if (row.plan !== undefined) {
      checkPlan(row.plan, "GET", "/v1/batches/{id}");
      return row.plan;
    }
    try {
      const plan = (await this.service.request("GET", `/v1/plans/${encodeURIComponent(row.key)}`, undefined, this.bounded(deadline))).body;
      checkPlan(plan, "GET", "/v1/plans/{key}");
      return plan;
    } catch (err) {
      // A plan the cache no longer holds (evicted, or a time_limit plan, which is never
      // cached): the row's own figures, without the parameters.
      if (!(err.kind === "http" && err.status === 404)) throw err;
      return { ...row, format: {} };
    }
  }

  // Polls GET /readyz every pollMs while the server runs.
  startPolling() {
    const poll = async () => {
      let ready = false;
      try {
        const { status, body } = await this.service.request("GET", "/readyz", undefined, { raw: true, timeoutMs: Math.min(this.service.timeoutMs, Math.max(this.pollMs, 1000)),
          boundName: "the readiness poll's bound: --poll-s, at least 1 s, at most --timeout-s" });
        ready = status === 200;
        if (!ready) this.setError("ServiceReady", `GET /readyz answered ${status}: ${typeof body === "object" ? JSON.stringify(body).slice(0, 200) : String(body).slice(0, 200)}`);
      } catch (err) {
        if (this.ready) this.setError("ServiceReady", err.message);
        else if (!this.lastError) this.setError("ServiceReady", err.message);
      }
      this.ready = ready;
      if (!this.stopped) this.pollTimer = setTimeout(poll, this.pollMs);
    };
    return poll();
  }

  stop() {
    this.stopped = true;
    clearTimeout(this.pollTimer);
  }
}

module.exports = { Gateway };
