"use strict";
// Real parts for the gateway tests: a `build/slosh serve` on a free loopback port, the gateway
// (opcua/slosh-opcua) on a free loopback port, and node-opcua's client. Every wait is bounded and
// polls for the condition (a port file, /readyz, a variable), never a fixed sleep.
const { spawn } = require("child_process");
const fs = require("fs");
const http = require("http");
const os = require("os");
const path = require("path");
let opcua;
try {
  opcua = require("../lib/stack");
} catch (e) {
  throw new Error(`node-opcua is not installed in opcua/node_modules (${e.message}): run scripts/install-deps.sh (npm ci in opcua/)`);
}
const { OPCUAClient, MessageSecurityMode, SecurityPolicy, DataType, Variant, AttributeIds } = opcua;

const root = path.resolve(__dirname, "..", "..");
const sloshBinary = process.env.SLOSH_BINARY || path.join(root, "build", "slosh");
const gatewayScript = path.join(root, "opcua", "slosh-opcua");

function scratch(prefix) {
  return fs.mkdtempSync(path.join(os.tmpdir(), prefix));
}

async function until(what, deadlineMs, condition, stepMs = 50) {
  const end = Date.now() + deadlineMs;
  for (;;) {
    const value = await condition();
    if (value) return value;
    if (Date.now() > end) throw new Error(`timed out after ${deadlineMs} ms waiting for ${what}`);
    await new Promise((r) => setTimeout(r, stepMs));
  }
}

function portFromFile(file) {
  try {
    const text = fs.readFileSync(file, "utf8");
    return text.endsWith("\n") ? Number(text.trim()) : 0;
  } catch (e) {
    return 0;
  }
}

class Child {
  constructor(command, args, env, logFile) {
    this.log = logFile;
    const out = fs.openSync(logFile, "w");
    this.proc = spawn(command, args, { env, stdio: ["ignore", out, out] });
    fs.closeSync(out);
    this.exited = new Promise((resolve) => this.proc.on("exit", (code, signal) => resolve({ code, signal })));
    this.proc.on("exit", () => { this.dead = true; });
  }

  output() {
    return fs.readFileSync(this.log, "utf8");
  }

  async stop() {
    if (this.dead) return;
    this.proc.kill("SIGTERM");
    const timer = setTimeout(() => this.proc.kill("SIGKILL"), 10000);
    await this.exited;
    clearTimeout(timer);
  }
}

function httpJson(method, url, body) {
  return new Promise((resolve, reject) => {
    const data = body === undefined ? null : Buffer.from(JSON.stringify(body));
    const req = http.request(url, { method, headers: data ? { "Content-Type": "application/json", "Content-Length": data.length } : {} }, (res) => {
      const chunks = [];
      res.on("data", (c) => chunks.push(c));
      res.on("end", () => {
        const text = Buffer.concat(chunks).toString();
        let json = null;
        try { json = JSON.parse(text); } catch (e) { json = null; }
        resolve({ status: res.statusCode, body: json, text });
      });
    });
    req.setTimeout(30000, () => req.destroy(new Error(`${method} ${url}: no answer in 30 s`)));
    req.on("error", reject);
    if (data) req.write(data);
    req.end();
  });
}

async function startSlosh(dir) {
  const portFile = path.join(dir, "slosh.port");
  const env = { ...process.env, HOME: dir, XDG_STATE_HOME: path.join(dir, "state") };
  const child = new Child(sloshBinary, ["serve", "--host", "127.0.0.1", "--port", "0", "--port-file", portFile,
    "--workers", "2", "--cache", ""], env, path.join(dir, "slosh.log"));
  const port = await until("slosh serve's port file", 30000, () => (child.dead ? Promise.reject(new Error("slosh serve exited:\n" + child.output())) : portFromFile(portFile)));
  child.url = `http://127.0.0.1:${port}`;
  await until("slosh /readyz", 30000, async () => {
    try { return (await httpJson("GET", child.url + "/readyz")).status === 200; } catch (e) { return false; }
  });
  return child;
}

// extra: more flags; env: more environment. Resolves the child with .endpoint and .stateDir.
async function startGateway(dir, serviceUrl, extra = [], env = {}) {
  const portFile = path.join(dir, `gateway-${Date.now()}.port`);
  const stateDir = path.join(dir, "opcua-state");
  const child = new Child(process.execPath, [gatewayScript, "--service", serviceUrl, "--port", "0", "--port-file", portFile,
    "--host", "127.0.0.1", "--state-dir", stateDir, "--poll-s", "0.2", ...extra],
  { ...process.env, HOME: dir, ...env }, path.join(dir, `gateway-${Date.now()}.log`));
  const port = await until("the gateway's port file", 45000, () => (child.dead ? Promise.reject(new Error("slosh-opcua exited:\n" + child.output())) : portFromFile(portFile)));
  child.endpoint = `opc.tcp://127.0.0.1:${port}`;
  child.stateDir = stateDir;
  return child;
}

async function connect(endpoint, options = {}, identity = undefined) {
  const client = OPCUAClient.create({
    endpointMustExist: false,
    connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
    requestedSessionTimeout: 60000,
    ...options,
  });
  await client.connect(endpoint);
  try {
    const session = await client.createSession(identity);
    return { client, session, async close() { await session.close(); await client.disconnect(); } };
  } catch (e) {
    await client.disconnect();
    throw e;
  }
}

// A fresh scratch directory (name prefix), a slosh serve in it (or the service at `service`), a
// gateway in front of it and, unless session is false, a connected session. extra: the gateway's
// further flags, or a function of the directory that returns them (a config file written there);
// env: its further environment. Resolves { dir, slosh, gateway, conn, stop() }; stop() closes and
// stops what was started and removes the directory. A failed start stops what it had started.
async function stack({ prefix = "slosh-opcua-", service, extra = [], env = {}, session = true } = {}) {
  const s = { dir: scratch(prefix), slosh: null, gateway: null, conn: null };
  s.stop = async () => {
    if (s.stopped) return;
    s.stopped = true;
    if (s.conn) await s.conn.close();
    if (s.gateway) await s.gateway.stop();
    if (s.slosh) await s.slosh.stop();
    fs.rmSync(s.dir, { recursive: true, force: true });
  };
  try {
    if (service === undefined) s.slosh = await startSlosh(s.dir);
    const flags = typeof extra === "function" ? extra(s.dir) : extra;
    s.gateway = await startGateway(s.dir, service === undefined ? s.slosh.url : service, flags, env);
    if (session) s.conn = await connect(s.gateway.endpoint);
  } catch (e) {
    await s.stop().catch(() => {});
    throw e;
  }
  return s;
}

// Starts what a test file needs before its first test, `limit` at a time. A gateway start is
// some 2.5 s of CPU (node-opcua's modules and its standard address space); one after the other,
// the starts were most of a file's time. Started together up front, the tests then run one after
// the other against idle processes, so no test's time bound is measured against another start.
// Sessions are opened by the tests that use them, not up front: an idle session would expire
// (the gateway's session timeout) while the tests before it run.
// starts(name, fn): fn's promise, queued now (a rejection is kept for whoever awaits it);
// starts.all(): resolves once every queued start has settled; starts.stopAll(): stops them.
function startPool(limit = 3) {
  let active = 0;
  const queue = [];
  const every = [];
  const next = () => {
    while (active < limit && queue.length) {
      const { fn, resolve, reject } = queue.shift();
      active += 1;
      Promise.resolve().then(fn).then(resolve, reject).finally(() => { active -= 1; next(); });
    }
  };
  const starts = (fn) => {
    const p = new Promise((resolve, reject) => { queue.push({ fn, resolve, reject }); next(); });
    p.catch(() => {});
    every.push(p);
    return p;
  };
  starts.all = () => Promise.allSettled(every);
  // Stops whatever started and is still running (a suite's own after hook stops its part first;
  // this catches the parts of suites that never ran).
  starts.stopAll = async () => {
    for (const r of await starts.all()) {
      if (r.status === "fulfilled" && r.value && typeof r.value.stop === "function") await r.value.stop().catch(() => {});
    }
  };
  return starts;
}

// Calls Slosh.<method> with [type, value] pairs.
async function callMethod(session, method, args) {
  return session.call({
    objectId: "ns=1;s=Slosh",
    methodId: `ns=1;s=Slosh.${method}`,
    inputArguments: args.map(([type, value]) => new Variant({ dataType: DataType[type], value })),
  });
}

async function readValue(session, nodeId) {
  const dv = await session.read({ nodeId, attributeId: AttributeIds.Value });
  if (!dv.statusCode.isGood()) throw new Error(`read ${nodeId}: ${dv.statusCode.toString()}`);
  return dv.value.value;
}

// The value of the child (component or property) `name` of nodeId, found by browsing.
async function readChild(session, nodeId, name) {
  const result = await session.browse({ nodeId, resultMask: 63, browseDirection: 0, includeSubtypes: true, referenceTypeId: "HierarchicalReferences" });
  const ref = result.references.find((r) => r.browseName.name === name);
  if (!ref) throw new Error(`${nodeId} has no child ${name}: ${result.references.map((r) => r.browseName.name)}`);
  return readValue(session, ref.nodeId);
}

// PlanFormat arguments in their order (arguments.js planArgs).
function planArgs(o) {
  return [["String", o.recipeId || ""], ["Double", o.radius ?? 0], ["Double", o.length ?? 0], ["Double", o.width ?? 0],
    ["Double", o.height ?? 0], ["Double", o.fill ?? 0], ["String", o.fluid ?? ""], ["Double", o.density ?? 0],
    ["Double", o.viscosity ?? 0], ["Double", o.stroke ?? 0], ["String", o.motion ?? ""], ["Double", o.time ?? 0],
    ["String", o.strategy ?? ""], ["String", o.options ?? ""]];
}

module.exports = { root, scratch, until, httpJson, startSlosh, startGateway, connect, stack, startPool, callMethod, readValue, readChild, planArgs,
  MessageSecurityMode, SecurityPolicy };
