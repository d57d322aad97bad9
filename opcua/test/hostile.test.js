"use strict";
// What a hostile integrator tried: recipe ids that look like node id paths, a service (or a proxy in
// front of it) answering 2xx/3xx with something that is not a plan, and JSON arguments nested too
// deep. Real gateway and real `slosh serve` on loopback; the broken answers come from a small HTTP
// server in this process.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");
const fs = require("fs");
const http = require("http");
const { StatusCodes } = require("../lib/stack");
const S = require("./support");

const thesis = { radius: 48.5, height: 150, fill: 82, fluid: "water", stroke: 800, time: 1.0, strategy: "multi_notch" };
const ALLOWED = "allowed: printable characters, not U+0000 to U+001F, U+007F to U+009F, U+2028, U+2029, U+FFFD or a lone surrogate";
const OPTIONS_JSON = require("../lib/arguments").planArgs.findIndex((a) => a.name === "OptionsJson");

const dirs = [];
function scratch(prefix) {
  const d = S.scratch(prefix);
  dirs.push(d);
  return d;
}

// The gateways of every suite below start together before the first test (support.js
// startPool); each suite's before hook opens its session.
const starts = S.startPool();
after(() => starts.stopAll());

describe("slosh-opcua against hostile input", () => {
  let stack; let slosh; let conn;
  const started = starts(() => S.stack({ prefix: "slosh-opcua-hostile-", session: false }));

  before(async () => {
    await starts.all();
    stack = await started;
    stack.conn = await S.connect(stack.gateway.endpoint);
    ({ slosh, conn } = stack);
  });

  after(async () => {
    if (stack) await stack.stop();
    for (const d of dirs) fs.rmSync(d, { recursive: true, force: true });
  });

  it("recipe ids with a dot never collide with another product's node ids, in either order", async () => {
    for (const [first, second] of [["x", "x.Status"], ["y.LastPlan", "y"], ["z.Parameters.StrokeMm", "z"]]) {
      for (const id of [first, second]) {
        const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, recipeId: id }));
        assert.equal(r.statusCode.name, "Good", `${id} after ${first}: ${await S.readValue(conn.session, "ns=1;s=Slosh.LastError")}`);
      }
      // Planned again: the product is whole, not a leftover that fails every later plan.
      const again = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, recipeId: second }));
      assert.equal(again.statusCode.name, "Good");
    }
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.x.Status"), "optimal");
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.x%2EStatus.Status"), "optimal");
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.y%2ELastPlan.Parameters.StrokeMm"), 800);
    const products = await conn.session.browse("ns=1;s=Products");
    for (const n of ["x", "x.Status", "y", "y.LastPlan"]) assert.ok(products.references.some((p) => p.browseName.name === n), n);
  });

  it("an import goes on past a row it refuses and counts it failed with its message", async () => {
    const row = (rid, stroke) => ({ recipe_id: rid, format: { container: { radius_mm: 48.5, height_mm: 150 }, fill_height_mm: 82, fluid: "water", stroke_mm: stroke, motion_time_s: 0.7 } });
    const table = JSON.stringify([row("imp.a", 500), row("ctl\u0001x", 500), row("imp", 400), row("sep\u2029x", 500)]);
    const submitted = await S.httpJson("POST", `${slosh.url}/v1/batches`, { table, table_format: "json" });
    assert.equal(submitted.status, 202, submitted.text);
    const id = submitted.body.id;
    await S.until("the batch job", 30000, async () => (await S.httpJson("GET", `${slosh.url}/v1/batches/${id}`)).body.state === "done");
    const imp = await S.callMethod(conn.session, "ImportBatchJob", [["String", id]]);
    assert.equal(imp.statusCode.name, "Good");
    assert.deepEqual(imp.outputArguments.map((v) => v.value), [2, 2]);
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.imp.Parameters.StrokeMm"), 400);
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.imp%2Ea.Parameters.StrokeMm"), 500);
    const lastError = await S.readValue(conn.session, "ns=1;s=Slosh.LastError");
    assert.ok(lastError.endsWith(`ImportBatchJob: batch job ${id} row 4: RecipeId "sep\\u2029x" contains a line or paragraph separator (U+2029): ${ALLOWED}; the row is not imported`), lastError);
    // The product "sep" was not made from "sep\u2029x" (node-opcua's node id parser stops at U+2029).
    const products = (await conn.session.browse("ns=1;s=Products")).references.map((p) => p.browseName.name);
    assert.ok(!products.includes("sep"), products.join());
  });

  it("refuses RecipeIds with separators, C1 controls and lone surrogates on RecipeId, naming the allowed characters", async () => {
    // A lone surrogate has no UTF-8: the client's encoder sends U+FFFD in its place.
    const cases = [["p\u2029q", "\"p\\u2029q\" contains a line or paragraph separator (U+2029)"], ["l\u2028s", "\"l\\u2028s\" contains a line or paragraph separator (U+2028)"],
      ["nel\u0085", "\"nel\\u0085\" contains a control character (U+0085)"], ["c1\u009b", "\"c1\\u009b\" contains a control character (U+009B)"],
      ["lone\ud800", "\"lone\\ufffd\" contains the replacement character (U+FFFD)"]];
    for (const [id, what] of cases) {
      const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, recipeId: id }));
      assert.equal(r.statusCode.value, StatusCodes.BadInvalidArgument.value, JSON.stringify(id));
      assert.equal(r.inputArgumentResults[0].value, StatusCodes.BadInvalidArgument.value);
      assert.equal(r.inputArgumentResults.filter((x) => x.value !== StatusCodes.Good.value).length, 1);
      assert.equal(r.inputArgumentDiagnosticInfos[0].additionalInfo, `RecipeId ${what}: ${ALLOWED}`);
    }
    const products = (await conn.session.browse("ns=1;s=Products")).references.map((p) => p.browseName.name);
    for (const n of ["p", "l", "nel", "c1", "lone"]) assert.ok(!products.some((p) => p.startsWith(n)), products.join());
  });

  it("a Table over the service's 1 MiB body limit is refused on Table, naming its size and the limit", async () => {
    const table = "recipe_id\n" + "x".repeat(1024 * 1024);
    const r = await S.callMethod(conn.session, "PlanTable", [["String", table], ["String", "csv"]]);
    assert.equal(r.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.deepEqual(r.inputArgumentResults.map((x) => x.value), [StatusCodes.BadInvalidArgument.value, StatusCodes.Good.value]);
    const body = Buffer.byteLength(JSON.stringify({ table, table_format: "csv" }));
    assert.equal(r.inputArgumentDiagnosticInfos[0].additionalInfo,
      `Table is ${table.length} bytes long (${body} bytes as the request's JSON): allowed at most 1048576 bytes (1 MiB, the service's body limit, counting the request around it); split the table`);
    assert.equal(r.inputArgumentDiagnosticInfos[1].additionalInfo, null);
  });

  it("node-opcua's own argument checks carry the gateway's message and set LastError", async () => {
    const { Variant, DataType } = require("../lib/stack");
    const call = (method, args) => conn.session.call({ objectId: "ns=1;s=Slosh", methodId: `ns=1;s=Slosh.${method}`, inputArguments: args });
    const str = (value) => new Variant({ dataType: DataType.String, value });
    const cases = [
      ["GetPlan", [], "BadArgumentsMissing", ["GetPlan takes 1 argument (Key): 0 given"]],
      ["ImportBatchJob", [str("a"), str("b")], "BadTooManyArguments", ["ImportBatchJob takes 1 argument (JobId): 2 given"]],
      ["PlanTable", [str("x"), new Variant({ dataType: DataType.Double, value: 1 })], "BadTypeMismatch", [null, "TableFormat must be a String, got Double"]],
    ];
    for (const [method, args, status, infos] of cases) {
      const r = await call(method, args);
      assert.equal(r.statusCode.name, status);
      assert.deepEqual(r.inputArgumentDiagnosticInfos.map((d) => d.additionalInfo), infos);
      const message = infos.filter(Boolean)[0];
      assert.ok((await S.readValue(conn.session, "ns=1;s=Slosh.LastError")).endsWith(` ${method}: ${message}`));
    }
  });

  it("MotionJson and the rectangle arguments reach the service, which plans them or refuses naming the argument", async () => {
    // An arc is planned (SPEC §14); an arc that does not turn is refused on MotionJson.
    const arc = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, stroke: 0, motion: "{\"type\":\"arc\",\"radius_mm\":300,\"angle_deg\":90}" }));
    assert.equal(arc.statusCode.value, StatusCodes.Good.value);
    const motion = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, stroke: 0, motion: "{\"type\":\"arc\",\"radius_mm\":300,\"angle_deg\":0}" }));
    assert.equal(motion.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.equal(motion.inputArgumentResults[10].value, StatusCodes.BadInvalidArgument.value);
    assert.equal(motion.inputArgumentDiagnosticInfos[10].additionalInfo, "format.motion.angle_deg = 0 is not allowed: an arc turns, allowed -3600 to 3600 deg except 0 (signed, left positive)");
    // A rectangular container is planned (SPEC §15); a side out of range is refused on its argument.
    const rect = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, radius: 0, length: 100, width: 80 }));
    assert.equal(rect.statusCode.value, StatusCodes.Good.value);
    const thin = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, radius: 0, length: 100, width: 0.5 }));
    assert.equal(thin.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.equal(thin.inputArgumentResults[3].value, StatusCodes.BadInvalidArgument.value);
    assert.equal(thin.inputArgumentDiagnosticInfos[3].additionalInfo, "format.container.width_mm = 0.5 is out of range: allowed 1 to 4000 mm");
  });

  it("JSON nested deeper than the service's 64 levels (counting the request around it) is refused on its own argument, before parsing", async () => {
    for (const levels of [64, 5000]) {
      const deep = "{\"a\":".repeat(levels) + "1" + "}".repeat(levels);
      const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, options: deep }));
      assert.equal(r.statusCode.value, StatusCodes.BadInvalidArgument.value);
      assert.equal(r.inputArgumentResults[OPTIONS_JSON].value, StatusCodes.BadInvalidArgument.value);
      assert.equal(r.inputArgumentResults.filter((x) => x.value !== StatusCodes.Good.value).length, 1);
      assert.equal(r.inputArgumentDiagnosticInfos[OPTIONS_JSON].additionalInfo,
        `OptionsJson nests ${levels} levels deep: allowed at most 63 levels (the service's limit of 64 counts the request object around it)`);
    }
    // The gateway's bound is the service's: 64 levels of options are 65 in the request, which the
    // service refuses as malformed.
    const deep64 = "{\"a\":".repeat(64) + "1" + "}".repeat(64);
    const refused = await S.httpJson("POST", `${slosh.url}/v1/plans`, {
      format: { container: { radius_mm: thesis.radius }, fill_height_mm: thesis.fill, fluid: thesis.fluid, stroke_mm: thesis.stroke, motion_time_s: thesis.time },
      options: JSON.parse(deep64) });
    assert.equal(refused.status, 400, refused.text);
    // 63 levels reach the service: its answer, word for word, not the gateway's check.
    const ok = "{\"a\":".repeat(63) + "1" + "}".repeat(63);
    const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, options: ok }));
    const direct = await S.httpJson("POST", `${slosh.url}/v1/plans`, {
      format: { container: { radius_mm: thesis.radius, height_mm: thesis.height }, fill_height_mm: thesis.fill, fluid: thesis.fluid,
        stroke_mm: thesis.stroke, motion_time_s: thesis.time },
      strategy: thesis.strategy, options: JSON.parse(ok) });
    assert.equal(direct.status, 422, direct.text);
    assert.equal(direct.body.error.field, "options.a");
    assert.equal(r.statusCode.value, StatusCodes.BadInvalidArgument.value);
    assert.equal(r.inputArgumentResults[OPTIONS_JSON].value, StatusCodes.BadInvalidArgument.value);
    assert.equal(r.inputArgumentDiagnosticInfos[OPTIONS_JSON].additionalInfo, direct.body.error.message);
  });
});

describe("slosh-opcua against a service whose 2xx/3xx answer is not a plan", () => {
  let server; let stack; let conn; let answer;

  const started = starts(async () => {
    server = http.createServer((req, res) => {
      if (req.url === "/readyz") {
        res.writeHead(200, { "Content-Type": "application/json" });
        res.end("{\"ready\":true}");
        return;
      }
      req.resume();
      req.on("end", () => {
        res.writeHead(answer.status, answer.headers);
        res.end(answer.body);
      });
    });
    await new Promise((r) => server.listen(0, "127.0.0.1", r));
    return S.stack({ prefix: "slosh-opcua-notplan-", service: `http://127.0.0.1:${server.address().port}`, session: false });
  });

  before(async () => {
    await starts.all();
    stack = await started;
    stack.conn = await S.connect(stack.gateway.endpoint);
    ({ conn } = stack);
  });

  after(async () => {
    if (stack) await stack.stop();
    if (server) server.close();
  });

  const json = { "Content-Type": "application/json" };
  const cases = [
    ["an HTML page", { status: 200, headers: { "Content-Type": "text/html" }, body: "<html>proxy login</html>" }, /not a plan: not a JSON object \(got text "<html>proxy login<\/html>"\)$/],
    ["{}", { status: 200, headers: json, body: "{}" }, /not a plan: status is not a non-empty string \(got \{\}\)$/],
    ["a 302 with no body", { status: 302, headers: { Location: "/elsewhere" }, body: "" }, /not a plan: not a JSON object \(got an empty body\)$/],
    ["durations of the wrong type", { status: 200, headers: json, body: "{\"status\":\"optimal\",\"key\":\"k\",\"durations_s\":\"0.1\"}" }, /not a plan: durations_s is neither null nor an array of 7 numbers/],
    ["6 durations", { status: 200, headers: json, body: "{\"status\":\"optimal\",\"key\":\"k\",\"durations_s\":[1,2,3,4,5,6]}" }, /durations_s is neither null nor an array of 7 numbers/],
  ];
  for (const [name, a, message] of cases) {
    it(`PlanFormat: ${name} is BadCommunicationError naming the answer`, async () => {
      answer = a;
      const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, recipeId: "never" }));
      assert.equal(r.statusCode.value, StatusCodes.BadCommunicationError.value);
      assert.match(r.inputArgumentDiagnosticInfos[0].additionalInfo, /^the slosh service answered POST \/v1\/plans with a body that is not a plan: /);
      assert.match(r.inputArgumentDiagnosticInfos[0].additionalInfo, message);
    });
  }

  it("a general law (durations_s null) is a plan", async () => {
    answer = { status: 200, headers: json, body: "{\"status\":\"optimal\",\"key\":\"k\",\"message\":\"m\",\"durations_s\":null}" };
    const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs(thesis));
    assert.equal(r.statusCode.name, "Good");
    assert.deepEqual([...r.outputArguments[2].value], []);
  });

  it("PlanTable and ImportBatchJob: an answer that is not a batch job is BadCommunicationError", async () => {
    answer = { status: 202, headers: json, body: "{}" };
    const t = await S.callMethod(conn.session, "PlanTable", [["String", "recipe_id\n"], ["String", "csv"]]);
    assert.equal(t.statusCode.value, StatusCodes.BadCommunicationError.value);
    assert.match(t.inputArgumentDiagnosticInfos[0].additionalInfo, /POST \/v1\/batches with a body that is not a created batch job: id is not a batch job id/);
    answer = { status: 200, headers: { "Content-Type": "text/html" }, body: "<p>hi</p>" };
    const i = await S.callMethod(conn.session, "ImportBatchJob", [["String", "ab12"]]);
    assert.equal(i.statusCode.value, StatusCodes.BadCommunicationError.value);
    assert.match(i.inputArgumentDiagnosticInfos[0].additionalInfo, /GET \/v1\/batches\/\{id\} with a body that is not a batch job: not a JSON object/);
  });
});

describe("slosh-opcua --max-products", () => {
  let stack; let conn;

  const started = starts(() => S.stack({ prefix: "slosh-opcua-max-", extra: ["--max-products", "2"], session: false }));

  before(async () => {
    await starts.all();
    stack = await started;
    stack.conn = await S.connect(stack.gateway.endpoint);
    ({ conn } = stack);
  });

  after(async () => {
    if (stack) await stack.stop();
  });

  it("keeps at most N products: the one planned longest ago makes room, and LastError says so", async () => {
    for (const id of ["m1", "m2", "m1", "m3"]) {
      const r = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, recipeId: id }));
      assert.equal(r.statusCode.name, "Good");
    }
    const products = await conn.session.browse("ns=1;s=Products");
    assert.deepEqual(products.references.map((p) => p.browseName.name).sort(), ["m1", "m3"]);
    const gone = await conn.session.read({ nodeId: "ns=1;s=Products.m2.Status", attributeId: 13 });
    assert.equal(gone.statusCode.value, StatusCodes.BadNodeIdUnknown.value);
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.m1.Status"), "optimal");
    assert.match(await S.readValue(conn.session, "ns=1;s=Slosh.LastError"), /Products: product "m2" \(planned longest ago\) removed: --max-products 2 reached$/);
    // Planned again, it comes back whole.
    const again = await S.callMethod(conn.session, "PlanFormat", S.planArgs({ ...thesis, recipeId: "m2" }));
    assert.equal(again.statusCode.name, "Good");
    assert.equal(await S.readValue(conn.session, "ns=1;s=Products.m2.Parameters.StrokeMm"), 800);
  });
});

describe("slosh-opcua settings a hostile integrator tried", () => {
  const { spawnSync } = require("child_process");
  const path = require("path");
  const script = path.join(S.root, "opcua", "slosh-opcua");
  const run = (args, env = {}) => spawnSync(process.execPath, [script, ...args], { env: { ...process.env, HOME: scratch("slosh-opcua-set-"), ...env }, encoding: "utf8", timeout: 15000, killSignal: "SIGKILL" });

  it("refuses credentials, queries and a missing URL in --service with a message that says so", () => {
    const cases = [
      [["--service"], "slosh-opcua: --service needs a value: the service URL is missing (e.g. http://127.0.0.1:8080)\n"],
      [["--service", "--port", "1"], "slosh-opcua: --service needs a value: the service URL is missing (e.g. http://127.0.0.1:8080)\n"],
      [["--service", "http://op:secret@127.0.0.1:8080"], "slosh-opcua: --service holds a user name or password (user:pass@): the slosh service takes no credentials in its URL; remove them\n"],
      [["--service", "http://127.0.0.1:8080/?a=1"], "slosh-opcua: --service = \"http://127.0.0.1:8080/?…\" has a query or fragment: http://host[:port][/path] expected\n"],
    ];
    for (const [args, message] of cases) {
      const r = run(args);
      assert.equal(r.status, 2, r.stderr);
      assert.equal(r.stderr, message);
      assert.doesNotMatch(r.stderr, /secret/);
    }
  });

  it("refuses a config whose port is a string or that lists a user twice; warns of passwords others can read", () => {
    const dir = scratch("slosh-opcua-cfg-");
    const file = path.join(dir, "c.json");
    fs.writeFileSync(file, JSON.stringify({ service: "http://127.0.0.1:1", port: "80" }));
    let r = run(["--config", file]);
    assert.equal(r.status, 2);
    assert.equal(r.stderr, "slosh-opcua: config port = \"80\" is not a JSON number: allowed an integer 0 to 65535\n");
    fs.writeFileSync(file, JSON.stringify({ service: "http://127.0.0.1:1", users: [{ user: "a", password: "b" }, { user: "a", password: "c" }] }));
    r = run(["--config", file]);
    assert.equal(r.status, 2);
    assert.equal(r.stderr, `slosh-opcua: --config ${file}: users[1]: user "a" is listed twice\n`);
    const { resolve } = require("../lib/options");
    fs.writeFileSync(file, JSON.stringify({ service: "http://127.0.0.1:1", users: [{ user: "a", password: "b" }] }));
    fs.chmodSync(file, 0o640);
    assert.deepEqual(resolve(["--config", file], { HOME: dir }).warnings,
      [`--config ${file} holds passwords and is readable by group or others (mode 640): chmod 600 it`]);
    fs.chmodSync(file, 0o600);
    assert.deepEqual(resolve(["--config", file], { HOME: dir }).warnings, []);
  });
  it("a --state-dir under /proc fails the start with exit 1 instead of hanging", () => {
    // One path is enough: /proc/1/nope and the like hung the same way (each start costs seconds).
    for (const dir of ["/proc/self/x"]) {
      const r = run(["--service", "http://127.0.0.1:1", "--port", "0", "--state-dir", dir]);
      assert.equal(r.error, undefined, `${dir}: ${r.error}`);
      assert.equal(r.status, 1, r.stderr);
      assert.equal(r.stderr, `slosh-opcua: cannot start: ENOENT: no such file or directory, mkdir '${dir}'\n`);
    }
  });

  it("checks every source of a setting, not only the one that wins, and takes decimal numbers only", () => {
    const { resolve } = require("../lib/options");
    const dir = scratch("slosh-opcua-src-");
    const file = path.join(dir, "c.json");
    fs.writeFileSync(file, JSON.stringify({ port: "14899" }));
    const refused = (argv, env) => {
      try { resolve(argv, { HOME: dir, ...env }); } catch (e) { return e.message; }
      return "accepted";
    };
    const svc = ["--service", "http://127.0.0.1:1"];
    const cases = [
      [[...svc, "--config", file, "--port", "1"], {}, "config port = \"14899\" is not a JSON number: allowed an integer 0 to 65535"],
      [[...svc, "--config", file], { SLOSH_OPCUA_PORT: "1" }, "config port = \"14899\" is not a JSON number: allowed an integer 0 to 65535"],
      [[...svc, "--port", "1"], { SLOSH_OPCUA_TIMEOUT_S: "abc" }, "SLOSH_OPCUA_TIMEOUT_S = \"abc\" is not a decimal number: allowed 0.1 to 600"],
      [[...svc, "--port", "0x10"], {}, "--port = \"0x10\" is not a decimal number: allowed an integer 0 to 65535"],
      [[...svc, "--port", " 0"], {}, "--port = \" 0\" is not a decimal number: allowed an integer 0 to 65535"],
      [[...svc, "--timeout-s", "1e1"], {}, "--timeout-s = \"1e1\" is not a decimal number: allowed 0.1 to 600"],
      [[...svc, "--state-dir", ""], {}, "--state-dir = \"\" is not a directory: give a path"],
      [svc, { SLOSH_OPCUA_SECURITY: "" }, "SLOSH_OPCUA_SECURITY is empty: allowed none, basic256sha256 or both"],
      [[...svc, "--security", ""], {}, "--security is empty: allowed none, basic256sha256 or both"],
      [["--service", "http://x#f"], {}, "--service = \"http://x#…\" has a query or fragment: http://host[:port][/path] expected"],
      [["--service", "http://x?token=s3"], {}, "--service = \"http://x?…\" has a query or fragment: http://host[:port][/path] expected"],
      [["--service", "http://x"], { SLOSH_OPCUA_SERVICE: "ftp://y" }, "SLOSH_OPCUA_SERVICE = \"ftp://y\" is not a service URL: http://host[:port][/path] or https://… expected"],
      [[...svc, "--session-timeout-s", "0.5"], {}, "--session-timeout-s = \"0.5\" is out of range: allowed 1 to 3000"],
      [[...svc, "--max-sessions", "0"], {}, "--max-sessions = \"0\" is out of range: allowed an integer 1 to 1000"],
    ];
    for (const [argv, env, message] of cases) assert.equal(refused(argv, env), message, JSON.stringify([argv, env]));
    const ok = resolve([...svc, "--port", "16", "--timeout-s", "2.5"], { HOME: dir });
    assert.deepEqual([ok.port, ok.timeoutMs, ok.sessionTimeoutMs, ok.maxSessions], [16, 2500, 60000, 50]);
  });
});

describe("slosh-opcua messages that name the right cause", () => {
  const net = require("net");
  const path = require("path");
  const sockets = [];
  const silent = net.createServer((s) => sockets.push(s));
  // One gateway for the first two tests (one start less): its service never answers GET /readyz
  // until the first test is done, and never answers a plan. The second test stops the gateway.
  let pollsHang = true;
  const hungPolls = [];
  const hung = [];
  const svc = http.createServer((req, res) => {
    if (req.url === "/readyz") {
      if (pollsHang) { hungPolls.push(res); return; }
      res.writeHead(200, { "Content-Type": "application/json" });
      res.end("{}");
      return;
    }
    hung.push(res);
  });
  const started = starts(async () => {
    await Promise.all([new Promise((r) => silent.listen(0, "127.0.0.1", r)), new Promise((r) => svc.listen(0, "127.0.0.1", r))]);
    return S.startGateway(scratch("slosh-opcua-hang-"), `http://127.0.0.1:${svc.address().port}`, ["--timeout-s", "20"]);
  });

  before(() => starts.all());

  after(async () => {
    const gw = await started.catch(() => null);
    if (gw) await gw.stop();
    sockets.forEach((s) => s.destroy());
    silent.close();
    hungPolls.concat(hung).forEach((r) => r.destroy());
    svc.close();
  });

  it("a readiness poll that times out names the poll's bound, not --timeout-s alone", async () => {
    const gw = await started;
    const c = await S.connect(gw.endpoint);
    try {
      const last = await S.until("the poll's timeout in LastError", 15000, async () => {
        const v = await S.readValue(c.session, "ns=1;s=Slosh.LastError");
        return v.includes("did not answer") ? v : null;
      });
      assert.match(last, /ServiceReady: the slosh service at http:\/\/127\.0\.0\.1:\d+ did not answer GET \/readyz within 1 s \(the readiness poll's bound: --poll-s, at least 1 s, at most --timeout-s\)$/);
    } finally {
      await c.close();
    }
  });

  it("a call pending when the gateway stops is answered BadShutdown, not blamed on the service", async () => {
    // Ready, but a plan never comes: the call is pending for sure once the request arrived.
    pollsHang = false;
    const gw = await started;
    const c = await S.connect(gw.endpoint);
    try {
      await S.until("ServiceReady true", 10000, async () => (await S.readValue(c.session, "ns=1;s=Slosh.ServiceReady")) === true);
      const call = S.callMethod(c.session, "PlanFormat", S.planArgs(thesis));
      await S.until("the call to reach the service", 5000, () => hung.length > 0);
      gw.proc.kill("SIGTERM");
      const r = await call;
      assert.equal(r.statusCode.value, StatusCodes.BadShutdown.value);
      assert.match(r.inputArgumentDiagnosticInfos[0].additionalInfo, /^the gateway is shutting down: POST \/v1\/plans was not answered; call again once it is back$/);
    } finally {
      await c.close().catch(() => {});
      await gw.stop();
    }
  });

  it("a private key file that is not a key stops the start naming the file", async () => {
    const dir = scratch("slosh-opcua-badkey-");
    const keyDir = path.join(dir, "opcua-state", "pki", "own", "private");
    fs.mkdirSync(keyDir, { recursive: true });
    fs.writeFileSync(path.join(keyDir, "private_key.pem"), "not a key\n");
    await assert.rejects(S.startGateway(dir, `http://127.0.0.1:${silent.address().port}`),
      (e) => e.message.includes(`slosh-opcua: cannot start: the private key ${path.join(keyDir, "private_key.pem")} is not a readable PEM key`));
  });
});

describe("slosh-opcua sessions of clients that died without closing them", () => {
  const { spawn } = require("child_process");
  const path = require("path");
  const sessionGateway = starts(() => S.startGateway(scratch("slosh-opcua-sessions-"), "http://127.0.0.1:1", ["--session-timeout-s", "3", "--max-sessions", "2"]));

  before(() => starts.all());

  it("a requested timeout beyond --session-timeout-s gets the bound, and dead clients' sessions are freed within it", async () => {
    const gw = await sessionGateway;
    // A client process that opens two sessions asking for an hour each, says what it got, and is
    // then killed: its sessions are never closed.
    const hog = spawn(process.execPath, ["-e", `
      const { OPCUAClient } = require(${JSON.stringify(path.join(S.root, "opcua", "lib", "stack"))});
      (async () => {
        const got = [];
        for (let i = 0; i < 2; i++) {
          const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 }, requestedSessionTimeout: 3600000, keepSessionAlive: false });
          await client.connect(${JSON.stringify(gw.endpoint)});
          got.push((await client.createSession()).timeout);
        }
        process.stdout.write(JSON.stringify(got) + "\\n");
        setInterval(() => {}, 1000);
      })().catch((e) => { process.stdout.write("ERROR " + e.message + "\\n"); });`], { stdio: ["ignore", "pipe", "inherit"] });
    let out = "";
    hog.stdout.on("data", (c) => { out += c; });
    try {
      await S.until("the hog's sessions", 20000, () => out.includes("\n"));
      const lastActivity = Date.now();
      assert.deepEqual(JSON.parse(out), [3000, 3000]);
      hog.kill("SIGKILL");
      // Freed 3 s after the last request, plus node-opcua's 1 s watchdog period (node-opcua's own
      // bound would hold both slots for 50 min).
      const c = await S.until("a session once the dead ones timed out", 8000, async () => {
        try { return await S.connect(gw.endpoint); } catch (e) { return null; }
      }, 250);
      assert.ok(Date.now() - lastActivity < 8000);
      await c.close();
    } finally {
      hog.kill("SIGKILL");
      await gw.stop();
    }
  });
});

describe("slosh-opcua ImportBatchJob bounded as a whole by --timeout-s", () => {
  let server; let gw; let c; let planRequests = 0; let cafePolls = 0;
  const ROWS = 12;
  const plan = (key) => ({ status: "optimal", key, message: "", durations_s: [0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1], kinematics: { a_max: 1, a_min: 1 }, prediction: {},
    format: { container: { radius_mm: 48.5 }, fill_height_mm: 82, fluid: "water", stroke_mm: 800, motion_time_s: 1 }, strategy: "auto" });

  const started = starts(async () => {
    // A done job of 12 rows whose plans each take 250 ms to come: 3 s in all, 1 s allowed.
    server = http.createServer((req, res) => {
      const send = (body) => { res.writeHead(200, { "Content-Type": "application/json" }); res.end(JSON.stringify(body)); };
      if (req.url === "/readyz") return send({ ready: true });
      if (req.method === "POST" && req.url === "/v1/batches") {
        req.resume();
        res.writeHead(202, { "Content-Type": "application/json" });
        res.end(JSON.stringify({ id: "cafe" }));
        return undefined;
      }
      if (req.url.startsWith("/v1/batches/cafe")) {
        // The service restarting under the follower: 503, then no connection, then the job.
        cafePolls += 1;
        if (cafePolls === 1) {
          res.writeHead(503, { "Content-Type": "application/json" });
          res.end(JSON.stringify({ error: { code: "overloaded", message: "the service is starting" } }));
          return undefined;
        }
        if (cafePolls === 2) { req.socket.destroy(); return undefined; }
        return send({ state: "done", progress: { done: 1, total: 1 }, results: { rows: [{ row: 1, recipe_id: "followed", status: "optimal", key: "kf" }], next_offset: null } });
      }
      if (req.url.startsWith("/v1/batches/")) {
        const rows = Array.from({ length: ROWS }, (_, i) => ({ row: i + 1, recipe_id: `slow${i + 1}`, status: "optimal", key: `k${i + 1}` }));
        return send({ state: "done", progress: { done: ROWS, total: ROWS }, results: { rows, next_offset: null } });
      }
      planRequests += 1;
      const key = req.url.split("/").pop();
      setTimeout(() => send(plan(key)), 250);
      return undefined;
    });
    await new Promise((r) => server.listen(0, "127.0.0.1", r));
    return S.startGateway(scratch("slosh-opcua-slowimp-"), `http://127.0.0.1:${server.address().port}`, ["--timeout-s", "1"]);
  });

  before(async () => {
    await starts.all();
    gw = await started;
    c = await S.connect(gw.endpoint);
  });

  after(async () => {
    if (c) await c.close();
    if (gw) await gw.stop();
    if (server) server.close();
  });

  it("answers BadTimeout naming --timeout-s, stops importing, and keeps the rows it wrote", async () => {
    const t0 = Date.now();
    const r = await S.callMethod(c.session, "ImportBatchJob", [["String", "ab12"]]);
    const elapsed = Date.now() - t0;
    assert.equal(r.statusCode.value, StatusCodes.BadTimeout.value);
    assert.ok(elapsed < 2500, `answered after ${elapsed} ms`);
    const message = r.inputArgumentDiagnosticInfos[0].additionalInfo;
    const m = /^ImportBatchJob did not finish within 1 s \(--timeout-s\): (\d+) rows imported and 0 failed before it stopped, the rest not imported; call it again to import the whole job \(rows already imported are written again\), or use PlanTable, which imports in the background$/.exec(message);
    assert.ok(m, message);
    const done = Number(m[1]);
    assert.ok(done >= 1 && done < ROWS, message);
    assert.match(await S.readValue(c.session, "ns=1;s=Slosh.LastError"), /ImportBatchJob: ImportBatchJob did not finish within 1 s/);
    // No work goes on for a caller that is gone: no more plan requests once the answer is out.
    const seen = planRequests;
    await new Promise((res) => setTimeout(res, 700));
    assert.equal(planRequests, seen);
    assert.ok(seen <= done + 1, `${seen} plan requests for ${done} rows imported`);
    const products = (await c.session.browse("ns=1;s=Products")).references.map((p) => p.browseName.name).sort();
    assert.deepEqual(products, Array.from({ length: done }, (_, i) => `slow${i + 1}`).sort());
    assert.equal(await S.readValue(c.session, "ns=1;s=Products.slow1.Status"), "optimal");
  });

  it("PlanTable's follower retries a service that fails for a while (503, no connection) and imports the job", async () => {
    const r = await S.callMethod(c.session, "PlanTable", [["String", "recipe_id\nfollowed\n"], ["String", "csv"]]);
    assert.equal(r.statusCode.name, "Good");
    const errors = new Set();
    await S.until("the followed job in Products", 10000, async () => {
      errors.add(await S.readValue(c.session, "ns=1;s=Slosh.LastError"));
      const dv = await c.session.read({ nodeId: "ns=1;s=Products.followed.Status", attributeId: 13 });
      return dv.statusCode.isGood() && dv.value.value === "optimal";
    });
    assert.ok(cafePolls >= 3, `${cafePolls} polls`);
    assert.ok([...errors].some((e) => / PlanTable: batch job cafe: the service is starting; retrying for up to 30 s$/.test(e)), [...errors].join("\n"));
  });
});
