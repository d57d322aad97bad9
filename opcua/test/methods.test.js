"use strict";
// The gateway's methods, products and health against a real `slosh serve`, called by node-opcua's
// client over loopback. Expected figures come from the service's own HTTP answer to the same
// request (the gateway must pass them on unchanged), and units from the UNECE codes packed by hand.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");
const fs = require("fs");
const net = require("net");
const { StatusCodes, BrowseDirection, NodeClass } = require("../lib/stack");
const S = require("./support");

// OPC UA Part 8: unitId = the UNECE common code's characters packed big-endian into an Int32.
const unitId = (code) => [...code].reduce((acc, c) => (acc << 8) | c.charCodeAt(0), 0);

const thesis = { radius: 48.5, height: 150, fill: 82, fluid: "water", stroke: 800, time: 1.0, strategy: "multi_notch" };
const thesisRequest = { format: { container: { radius_mm: 48.5, height_mm: 150 }, fill_height_mm: 82, fluid: "water", stroke_mm: 800, motion_time_s: 1.0 }, strategy: "multi_notch" };

function minTimeArgs(o) {
  return [["Double", o.radius ?? 0], ["Double", 0], ["Double", 0], ["Double", o.height ?? 0], ["Double", o.fill ?? 0],
    ["String", o.fluid ?? ""], ["Double", 0], ["Double", 0], ["Double", o.stroke ?? 0], ["String", ""],
    ["Double", o.etaMotion ?? 0], ["Double", o.etaRest ?? 0], ["Double", o.aMax ?? 0], ["Double", 0], ["Double", 0],
    ["String", o.request ?? ""]];
}

function diagnostics(result) {
  return result.inputArgumentDiagnosticInfos.map((d) => (d && d.additionalInfo) || null);
}

const scratchDirs = [];
function scratch(prefix) {
  const d = S.scratch(prefix);
  scratchDirs.push(d);
  return d;
}

// A service that accepts connections and never answers (the BadTimeout test).
const silentSockets = [];
const silent = net.createServer((sock) => silentSockets.push(sock));

// The two gateways of this file start together: the shared one in front of a real slosh serve and
// the one in front of the silent service, with --timeout-s 1.
const starts = S.startPool();
const shared = starts(() => S.stack({ session: false }));
const silentGateway = starts(async () => {
  await new Promise((r) => silent.listen(0, "127.0.0.1", r));
  return S.startGateway(scratch("slosh-opcua-slow-"), `http://127.0.0.1:${silent.address().port}`, ["--timeout-s", "1"]);
});

describe("slosh-opcua against a real slosh serve", () => {
  let stack; let slosh; let gateway; let conn;

  before(async () => {
    await starts.all();
    stack = await shared;
    stack.conn = await S.connect(stack.gateway.endpoint);
    ({ slosh, gateway, conn } = stack);
  });

  after(async () => {
    await starts.stopAll();
    silentSockets.forEach((sock) => sock.destroy());
    silent.close();
    for (const d of scratchDirs) fs.rmSync(d, { recursive: true, force: true });
  });

  it("browses Objects/Slosh: the methods, the health variables and the Products folder", async () => {
    const browse = await conn.session.browse({ nodeId: "ns=1;s=Slosh", browseDirection: BrowseDirection.Forward, resultMask: 63 });
    const names = browse.references.map((r) => r.browseName.name).sort();
    for (const n of ["GetPlan", "ImportBatchJob", "LastError", "MinTime", "PlanFormat", "PlanTable", "Products", "ServiceReady", "ServiceUrl"]) {
      assert.ok(names.includes(n), `${n} missing from ${names}`);
    }
    const objects = await conn.session.browse("ns=0;i=85");
    assert.ok(objects.references.some((r) => r.browseName.name === "Slosh"));
    const plan = browse.references.find((r) => r.browseName.name === "PlanFormat");
    assert.equal(plan.nodeClass, NodeClass.Method);
    const args = await S.readChild(conn.session, "ns=1;s=Slosh.PlanFormat", "InputArguments");
    assert.deepEqual(args.map((a) => a.name), ["RecipeId", "RadiusMm", "LengthMm", "WidthMm", "ContainerHeightMm", "FillHeightMm",
      "Fluid", "DensityKgM3", "ViscosityPaS", "StrokeMm", "MotionJson", "MotionTimeS", "Strategy", "OptionsJson"]);
    for (const a of args) assert.ok(a.description.text.length > 10, `${a.name} has no description`);
    const eu = await S.readChild(conn.session, "ns=1;s=Slosh.PlanFormat", "InputArgumentUnits");
    assert.equal(eu.length, args.length);
    const expected = { RadiusMm: "MMT", FillHeightMm: "MMT", DensityKgM3: "KMQ", ViscosityPaS: "C65", MotionTimeS: "SEC", StrokeMm: "MMT" };
    args.forEach((a, i) => {
      if (expected[a.name]) assert.equal(eu[i].unitId, unitId(expected[a.name]), `${a.name} unit`);
      if (["RecipeId", "Fluid", "Strategy", "OptionsJson", "MotionJson"].includes(a.name)) assert.equal(eu[i].unitId, -1, `${a.name} is unitless`);
    });
    const outEu = await S.readChild(conn.session, "ns=1;s=Slosh.PlanFormat", "OutputArgumentUnits");
    const outs = await S.readChild(conn.session, "ns=1;s=Slosh.PlanFormat", "OutputArguments");
    assert.equal(outEu[outs.findIndex((o) => o.name === "A")].unitId, unitId("MSK"));
    assert.equal(outEu[outs.findIndex((o) => o.name === "DurationsS")].unitId, unitId("SEC"));
    assert.equal(outEu[outs.findIndex((o) => o.name === "EtaRestNonlinearMm")].unitId, unitId("MMT"));
    const minEu = await S.readChild(conn.session, "ns=1;s=Slosh.MinTime", "InputArgumentUnits");
    const minArgs = await S.readChild(conn.session, "ns=1;s=Slosh.MinTime", "InputArguments");
    assert.equal(minEu[minArgs.findIndex((a) => a.name === "AMax")].unitId, unitId("MSK"));
  });

  it("PlanFormat returns the service's plan and keeps it in Products/<RecipeId>", async () => {
    const direct = await S.httpJson("POST", slosh.url + "/v1/plans", thesisRequest);
    assert.equal(direct.status, 200);
    const t0 = new Date();
    const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, recipeId: "thesis-800" }));
    assert.equal(r.statusCode.name, "Good");
    const [status, message, durations, A, B, etaMotionNl, etaRestNl, etaMotionLin, etaRestLin, key] = r.outputArguments.map((v) => v.value);
    const p = direct.body;
    assert.equal(status, p.status);
    assert.equal(message, p.message);
    assert.deepEqual([...durations], p.durations_s);
    assert.equal(durations.length, 7);
    assert.ok(Math.abs(durations.reduce((a, b) => a + b, 0) - 1.0) < 1e-9, "the durations sum to T");
    assert.equal(A, p.kinematics.a_max);
    assert.equal(B, p.kinematics.a_min);
    assert.equal(etaMotionNl, p.prediction.nonlinear.eta_motion_mm);
    assert.equal(etaRestNl, p.prediction.nonlinear.eta_rest_mm);
    assert.equal(etaMotionLin, p.prediction.linear.eta_motion_mm);
    assert.equal(etaRestLin, p.prediction.linear.eta_rest_mm);
    assert.equal(key, p.key);

    const base = "ns=1;s=Products.thesis-800";
    assert.deepEqual([...await S.readValue(conn.session, `${base}.LastPlan.DurationsS`)], p.durations_s);
    assert.equal(await S.readValue(conn.session, `${base}.LastPlan.A`), p.kinematics.a_max);
    assert.equal(await S.readValue(conn.session, `${base}.LastPlan.Key`), p.key);
    assert.equal(await S.readValue(conn.session, `${base}.Status`), p.status);
    assert.equal(await S.readValue(conn.session, `${base}.Parameters.RadiusMm`), 48.5);
    assert.equal(await S.readValue(conn.session, `${base}.Parameters.StrokeMm`), 800);
    assert.equal(await S.readValue(conn.session, `${base}.Parameters.Strategy`), "multi_notch");
    const planned = await S.readValue(conn.session, `${base}.LastPlanned`);
    assert.ok(planned >= new Date(t0.getTime() - 1000) && planned <= new Date(), `LastPlanned ${planned.toISOString()}`);
    const eu = await S.readChild(conn.session, `${base}.LastPlan.DurationsS`, "EngineeringUnits");
    assert.equal(eu.unitId, unitId("SEC"));
    const euR = await S.readChild(conn.session, `${base}.Parameters.RadiusMm`, "EngineeringUnits");
    assert.equal(euR.unitId, unitId("MMT"));
  });

  it("PlanFormat: a bad field is BadInvalidArgument with the service's message on that argument", async () => {
    const direct = await S.httpJson("POST", slosh.url + "/v1/plans", { ...thesisRequest, format: { ...thesisRequest.format, container: { radius_mm: -3, height_mm: 150 } } });
    assert.equal(direct.status, 422);
    const expected = "format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm";
    assert.equal(direct.body.error.message, expected);
    const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, radius: -3 }));
    assert.equal(r.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.equal(r.inputArgumentResults[1].value, StatusCodes.BadInvalidArgument.value, "RadiusMm is the bad argument");
    assert.ok(r.inputArgumentResults.every((s, i) => i === 1 || s.value === StatusCodes.Good.value));
    assert.equal(diagnostics(r)[1], expected);
    assert.match(await S.readValue(conn.session, "ns=1;s=Slosh.LastError"), / PlanFormat: format\.container\.radius_mm = -3 is out of range: allowed 1 to 2000 mm$/);

    const fill = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, fill: 0.5 }));
    assert.equal(fill.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.equal(fill.inputArgumentResults[5].value, StatusCodes.BadInvalidArgument.value, "FillHeightMm is the bad argument");
    assert.match(diagnostics(fill)[5], /^format\.fill_height_mm = 0\.5 is out of range/);

    const both = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, length: 100, width: 60 }));
    assert.equal(both.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.equal(diagnostics(both)[1], "RadiusMm = 48.5 and LengthMm = 100, WidthMm = 60: give the radius of a round container or the length and width of a rectangular one, not both");

    const options = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, options: "{\"p_notch\": " }));
    assert.equal(options.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.match(diagnostics(options)[13], /^OptionsJson is not valid JSON: /);
  });

  it("MinTime returns the service's headline; a bad limit names its field", async () => {
    const request = "{\"strategies\": [\"multi_notch\", \"shaper\"]}";
    const direct = await S.httpJson("POST", slosh.url + "/v1/min-time", {
      format: { container: { radius_mm: 48.5, height_mm: 150 }, fill_height_mm: 82, fluid: "water", stroke_mm: 800 },
      strategies: ["multi_notch", "shaper"] });
    assert.equal(direct.status, 200);
    const r = await S.callMethod(conn.session, "MinTime", minTimeArgs({ radius: 48.5, height: 150, fill: 82, fluid: "water", stroke: 800, request }));
    assert.equal(r.statusCode.name, "Good");
    const [tMin, winner, gain, key] = r.outputArguments.map((v) => v.value);
    assert.equal(tMin, direct.body.headline.t_min_s);
    assert.equal(winner, direct.body.headline.winner);
    assert.ok(Number.isNaN(gain), "no baseline searched: the gain is NaN");
    assert.equal(key, direct.body.key);

    const withBaseline = await S.callMethod(conn.session, "MinTime", minTimeArgs({ radius: 48.5, height: 150, fill: 82, fluid: "water", stroke: 800, request: "{\"strategies\": [\"baseline\", \"shaper\"]}" }));
    assert.equal(withBaseline.statusCode.name, "Good");
    const directB = await S.httpJson("POST", slosh.url + "/v1/min-time", {
      format: { container: { radius_mm: 48.5, height_mm: 150 }, fill_height_mm: 82, fluid: "water", stroke_mm: 800 },
      strategies: ["baseline", "shaper"] });
    const h = directB.body.headline;
    assert.equal(withBaseline.outputArguments[2].value, h.gain_pct);
    assert.ok(Math.abs(h.gain_pct - 100 * (h.baseline_t_min_s - h.t_min_s) / h.baseline_t_min_s) < 1e-9);

    const bad = await S.callMethod(conn.session, "MinTime", minTimeArgs({ radius: 48.5, height: 150, fill: 82, fluid: "water", stroke: 800, etaRest: -1, request }));
    assert.equal(bad.statusCode.value, StatusCodes.BadInvalidArgument.value);
    const directBad = await S.httpJson("POST", slosh.url + "/v1/min-time", {
      format: { container: { radius_mm: 48.5, height_mm: 150 }, fill_height_mm: 82, fluid: "water", stroke_mm: 800 },
      eta_rest_max_mm: -1, strategies: ["multi_notch", "shaper"] });
    assert.equal(directBad.status, 422);
    assert.match(directBad.body.error.message, /^eta_rest_max_mm = -1 is out of range/);
    assert.equal(bad.inputArgumentResults[11].value, StatusCodes.BadInvalidArgument.value, "EtaRestMaxMm is the bad argument");
    assert.equal(diagnostics(bad)[11], directBad.body.error.message);
  });

  it("GetPlan returns a cached plan by key; an unknown key is BadNotFound, a malformed one BadInvalidArgument", async () => {
    const direct = await S.httpJson("POST", slosh.url + "/v1/plans", thesisRequest);
    const r = await S.callMethod(conn.session, "GetPlan", [["String", direct.body.key]]);
    assert.equal(r.statusCode.name, "Good");
    assert.deepEqual([...r.outputArguments[2].value], direct.body.durations_s);
    assert.equal(r.outputArguments[9].value, direct.body.key);
    const unknown = await S.callMethod(conn.session, "GetPlan", [["String", "0".repeat(32)]]);
    assert.equal(unknown.statusCode.value, StatusCodes.BadNotFound.value);
    const malformed = await S.callMethod(conn.session, "GetPlan", [["String", "../healthz"]]);
    assert.equal(malformed.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.equal(diagnostics(malformed)[0], "Key = \"../healthz\" is not a recipe key: 32 lowercase hex digits expected");
  });

  it("a batch fills Products: PlanTable follows its job, ImportBatchJob imports a finished one", async () => {
    const table = "recipe_id,radius_mm,container_height_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
      + "tray-a,48.5,150,82,water,500,0.7,notch\n"
      + "tray-bad,-3,150,82,water,500,0.7,notch\n"
      + "\"2:odd.id\",48.5,150,82,water,400,0.6,notch\n";
    const r = await S.callMethod(conn.session, "PlanTable", [["String", table], ["String", "csv"]]);
    assert.equal(r.statusCode.name, "Good");
    const job = r.outputArguments[0].value;
    const rows = await S.until("the batch job", 30000, async () => {
      const rec = await S.httpJson("GET", `${slosh.url}/v1/batches/${job}`);
      return rec.body.state === "done" ? rec.body.results.rows : null;
    });
    const good = rows.find((x) => x.recipe_id === "tray-a");
    const bad = rows.find((x) => x.recipe_id === "tray-bad");
    // PlanTable's job has no view: its rows are figures only, small in the service's job memory.
    assert.equal(good.plan, undefined);
    // The import writes the rows in table order: the last row's product comes last.
    await S.until("Products/2:odd.id", 10000, async () => {
      try { return (await S.readValue(conn.session, "ns=1;s=Products.2:odd%2Eid.Status")) !== ""; } catch (e) { return false; }
    });
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.tray-bad.Status"), "error");
    const base = "ns=1;s=Products.tray-a";
    assert.deepEqual([...await S.readValue(conn.session, `${base}.LastPlan.DurationsS`)], good.durations_s);
    assert.equal(await S.readValue(conn.session, `${base}.LastPlan.EtaRestNonlinearMm`), good.prediction.nonlinear.eta_rest_mm);
    assert.equal(await S.readValue(conn.session, `${base}.LastPlan.Key`), good.key);
    assert.equal(await S.readValue(conn.session, `${base}.Status`), good.status);
    assert.equal(await S.readValue(conn.session, `${base}.Parameters.StrokeMm`), 500);
    assert.equal(await S.readValue(conn.session, `${base}.Parameters.MotionTimeS`), 0.7);
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.tray-bad.LastPlan.Message"), bad.error.message);
    // A recipe id that looks like a qualified name ("2:…") keeps its text as the browse name.
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.2:odd%2Eid.Parameters.StrokeMm"), 400);
    const products = await conn.session.browse("ns=1;s=Products");
    assert.ok(products.references.some((x) => x.browseName.name === "2:odd.id" && x.browseName.namespaceIndex === 1));
    assert.ok(["tray-a", "tray-bad", "thesis-800"].every((n) => products.references.some((x) => x.browseName.name === n)));

    // A job submitted over HTTP (e.g. by slosh batch --server), imported once done.
    const submitted = await S.httpJson("POST", `${slosh.url}/v1/batches`, { table: table.replace(/tray-/g, "cup-"), table_format: "csv" });
    assert.equal(submitted.status, 202);
    const id = submitted.body.id;
    await S.until("the second batch job", 30000, async () => (await S.httpJson("GET", `${slosh.url}/v1/batches/${id}`)).body.state === "done");
    const imp = await S.callMethod(conn.session, "ImportBatchJob", [["String", id]]);
    assert.equal(imp.statusCode.name, "Good");
    assert.deepEqual(imp.outputArguments.map((v) => v.value), [2, 1]);
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.cup-a.LastPlan.Key"), good.key);
    // A job posted with the full view is imported from its rows' own plans, parameters included.
    const full = await S.httpJson("POST", `${slosh.url}/v1/batches`, { table: table.replace(/tray-/g, "jar-"), table_format: "csv", view: "full" });
    assert.equal(full.status, 202);
    await S.until("the full-view batch job", 30000, async () => (await S.httpJson("GET", `${slosh.url}/v1/batches/${full.body.id}`)).body.state === "done");
    const impFull = await S.callMethod(conn.session, "ImportBatchJob", [["String", full.body.id]]);
    assert.equal(impFull.statusCode.name, "Good");
    assert.deepEqual(impFull.outputArguments.map((v) => v.value), [2, 1]);
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.jar-a.LastPlan.Key"), good.key);
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.jar-a.Parameters.StrokeMm"), 500);
    const unknown = await S.callMethod(conn.session, "ImportBatchJob", [["String", "0".repeat(32)]]);
    assert.equal(unknown.statusCode.value, StatusCodes.BadNotFound.value);
  });

  it("slosh-opcua-client (the README's commands) calls, reads and browses", async () => {
    const { execFile } = require("child_process");
    const run = (args) => new Promise((resolve) => {
      execFile(process.execPath, [require("path").join(S.root, "opcua", "slosh-opcua-client"), "--endpoint", gateway.endpoint, ...args],
        { timeout: 30000 }, (err, stdout, stderr) => resolve({ code: err ? err.code : 0, stdout, stderr }));
    });
    const direct = await S.httpJson("POST", slosh.url + "/v1/plans", thesisRequest);
    // Each run is a process loading node-opcua (about a second of CPU): the runs that do not need
    // the product cli-1 run together with the one that makes it, the read and the browse after it.
    const [ok, bad, unknown] = await Promise.all([
      run(["call", "PlanFormat", JSON.stringify({ RecipeId: "cli-1", RadiusMm: 48.5, ContainerHeightMm: 150, FillHeightMm: 82,
        Fluid: "water", StrokeMm: 800, MotionTimeS: 1.0, Strategy: "multi_notch" })]),
      run(["call", "PlanFormat", JSON.stringify({ RadiusMm: -3, FillHeightMm: 82, Fluid: "water", StrokeMm: 800, MotionTimeS: 1.0 })]),
      run(["call", "PlanFormats", "{}"]),
    ]);
    assert.equal(ok.code, 0, ok.stderr);
    const out = JSON.parse(ok.stdout);
    assert.deepEqual(out.DurationsS, direct.body.durations_s);
    assert.equal(out.Key, direct.body.key);
    const [read, browse] = await Promise.all([run(["read", "ns=1;s=Products.cli-1.LastPlan.DurationsS"]), run(["browse"])]);
    assert.deepEqual(JSON.parse(read.stdout), direct.body.durations_s);
    assert.equal(bad.code, 1);
    assert.equal(bad.stderr.trim(), "BadInvalidArgument (0x80ab0000) (RadiusMm): format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm");
    assert.match(browse.stdout, /^ {2}cli-1 {2}Object {2}ns=1;s=Products\.cli-1$/m);
    assert.equal(unknown.code, 2);
    assert.equal(unknown.stderr, "slosh-opcua-client: unknown method \"PlanFormats\": the gateway has PlanFormat, MinTime, GetPlan, PlanTable, ImportBatchJob\n");
  });

  it("a service that accepts but never answers gives BadTimeout after --timeout-s", async () => {
    const c = await S.connect((await silentGateway).endpoint);
    try {
      const t0 = Date.now();
      const r = await S.callMethod(c.session, "PlanFormat", S.planArgs(thesis));
      const elapsed = Date.now() - t0;
      assert.equal(r.statusCode.value, StatusCodes.BadTimeout.value);
      assert.ok(elapsed >= 900 && elapsed < 4000, `answered after ${elapsed} ms`);
      assert.match(diagnostics(r)[0], /did not answer POST \/v1\/plans within 1 s \(--timeout-s\)$/);
    } finally {
      await c.close();
    }
  });

  it("the gateway skips node-opcua's PKCS#1 v1.5 check (a 4096-bit RSA key made at each start on node 20)", async () => {
    // On node 20 the check fails and warns NODE-OPCUA-W27 a few seconds after the start, by now.
    assert.doesNotMatch(gateway.output(), /NODE-OPCUA-W27|verify_pcks1/);
    assert.match(gateway.output(), /listening on opc\.tcp:/);
  });

  // The last test: it stops the shared service.
  it("ServiceReady follows /readyz; a service that is down gives BadCommunicationError at once", async () => {
    assert.equal(await S.readValue(conn.session, "ns=1;s=Slosh.ServiceReady"), true);
    await slosh.stop();
    const t0 = Date.now();
    const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs(thesis));
    assert.equal(r.statusCode.value, StatusCodes.BadCommunicationError.value);
    assert.ok(Date.now() - t0 < 5000, `answered after ${Date.now() - t0} ms`);
    assert.match(diagnostics(r)[0], /^the slosh service at http:\/\/127\.0\.0\.1:\d+ is unreachable: ECONNREFUSED$/);
    await S.until("ServiceReady false", 10000, async () => (await S.readValue(conn.session, "ns=1;s=Slosh.ServiceReady")) === false);
    assert.match(await S.readValue(conn.session, "ns=1;s=Slosh.LastError"), /unreachable: ECONNREFUSED$/);
  });
});
