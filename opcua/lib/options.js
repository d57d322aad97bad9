"use strict";
// Command line, configuration file and environment of slosh-opcua. Lowest to highest precedence:
// defaults, the --config file (JSON), the environment (SLOSH_OPCUA_*), the flags. A bad value stops
// the start with a message naming the setting, the value and what is allowed (exit 2).
const fs = require("fs");
const path = require("path");

const USAGE = `usage: slosh-opcua --service URL [--port N] [options]

OPC UA server (IEC 62541) in front of the slosh HTTP service: methods PlanFormat, MinTime,
GetPlan, PlanTable, ImportBatchJob; the Products folder; ServiceReady and LastError.

  --service URL      the slosh service, e.g. http://127.0.0.1:8080 (required; SLOSH_OPCUA_SERVICE)
  --port N           OPC UA TCP port, 0 = any free one (default 4840; SLOSH_OPCUA_PORT)
  --host ADDR        listen address and endpoint host name (default: every interface, the
                     machine's host name in the endpoint URL; SLOSH_OPCUA_HOST)
  --timeout-s S      bound of each call to the service and of a whole ImportBatchJob,
                     0.1 to 600 s (default 30; a call then fails with BadTimeout;
                     SLOSH_OPCUA_TIMEOUT_S)
  --poll-s S         readiness poll period of GET /readyz, 0.1 to 60 s (default 2; SLOSH_OPCUA_POLL_S)
  --security LIST    comma list of none, basic256sha256 (default none,basic256sha256:
                     Basic256Sha256 is offered as SignAndEncrypt only; SLOSH_OPCUA_SECURITY)
  --state-dir DIR    where the PKI lives (default \${XDG_STATE_HOME:-~/.local/state}/slosh/opcua;
                     the server certificate is created in DIR/pki/own on first start;
                     SLOSH_OPCUA_STATE_DIR)
  --max-products N   most products kept in the Products folder, 1 to 100000 (default 2000,
                     ~285 kB of RSS each); beyond it the product planned longest ago is removed and
                     LastError says so (SLOSH_OPCUA_MAX_PRODUCTS)
  --session-timeout-s S
                     longest session timeout granted, 1 to 3000 s (default 60): a client asking
                     for more gets this, so the session of a client that died without closing it
                     is freed at most S after its last request (SLOSH_OPCUA_SESSION_TIMEOUT_S)
  --max-sessions N   most sessions open at once, 1 to 1000 (default 50); one more is refused
                     with BadTooManySessions (SLOSH_OPCUA_MAX_SESSIONS)
  --config FILE      JSON file with any of the keys service, port, host, timeout_s, poll_s,
                     security, state_dir, max_products, session_timeout_s, max_sessions and
                     users: [{"user": "...", "password": "..."}]
                     (SLOSH_OPCUA_CONFIG)
  --port-file FILE   write the port once listening (for --port 0)
  --help             this text

User name and password: the config's "users", or SLOSH_OPCUA_USER and SLOSH_OPCUA_PASSWORD. When
any user is configured, anonymous sessions are refused.`;

class UsageError extends Error {}

// The settings a flag, the environment and the config file can give: [flag (--name), environment
// variable, config key, default]. --config and --port-file are flags only; the config's "users"
// is read on its own.
const SETTINGS = [
  ["service", "SLOSH_OPCUA_SERVICE", "service", undefined],
  ["port", "SLOSH_OPCUA_PORT", "port", 4840],
  ["host", "SLOSH_OPCUA_HOST", "host", ""],
  ["timeout-s", "SLOSH_OPCUA_TIMEOUT_S", "timeout_s", 30],
  ["poll-s", "SLOSH_OPCUA_POLL_S", "poll_s", 2],
  ["security", "SLOSH_OPCUA_SECURITY", "security", "none,basic256sha256"],
  ["state-dir", "SLOSH_OPCUA_STATE_DIR", "state_dir", undefined],
  ["max-products", "SLOSH_OPCUA_MAX_PRODUCTS", "max_products", 2000],
  // node-opcua grants up to 50 min per session: ten clients killed without closing their sessions
  // would hold every session slot that long. 60 s is ample for a client's keep-alive (it pings at
  // a third of the timeout).
  ["session-timeout-s", "SLOSH_OPCUA_SESSION_TIMEOUT_S", "session_timeout_s", 60],
  ["max-sessions", "SLOSH_OPCUA_MAX_SESSIONS", "max_sessions", 50],
];

function parseArgs(argv) {
  const flags = {};
  const known = new Set([...SETTINGS.map(([flag]) => flag), "config", "port-file"]);
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === "--help" || a === "-h") return { help: true };
    const m = /^--([a-z-]+)(?:=(.*))?$/.exec(a);
    if (!m || !known.has(m[1])) throw new UsageError(`unknown argument ${JSON.stringify(a)} (see --help)`);
    let value = m[2];
    if (value === undefined) {
      if (i + 1 >= argv.length || argv[i + 1].startsWith("--")) {
        if (m[1] === "service") throw new UsageError("--service needs a value: the service URL is missing (e.g. http://127.0.0.1:8080)");
        throw new UsageError(`--${m[1]} needs a value`);
      }
      value = argv[++i];
    }
    if (m[1] in flags) throw new UsageError(`--${m[1]} is given twice`);
    flags[m[1]] = value;
  }
  return { flags };
}

function numberSetting(name, value, low, high, integer) {
  // A config file says what it means in JSON: "80" (a string) is not the number 80.
  if (name.startsWith("config ") && typeof value !== "number") {
    throw new UsageError(`${name} = ${JSON.stringify(value)} is not a JSON number: allowed ${integer ? "an integer " : ""}${low} to ${high}`);
  }
  // Decimal digits only: Number() would also take " 0", "0x10" (16), "1e1" and "" (0).
  const text = String(value);
  const n = Number(text);
  const pattern = integer ? /^[0-9]+$/ : /^[0-9]+(\.[0-9]+)?$/;
  if (typeof value === "string" && !pattern.test(text)) {
    throw new UsageError(`${name} = ${JSON.stringify(value)} is not a decimal number: allowed ${integer ? "an integer " : ""}${low} to ${high}`);
  }
  if (!Number.isFinite(n) || (integer && !Number.isInteger(n)) || n < low || n > high) {
    throw new UsageError(`${name} = ${JSON.stringify(value)} is out of range: allowed ${integer ? "an integer " : ""}${low} to ${high}`);
  }
  return n;
}

function defaultStateDir(env) {
  if (env.XDG_STATE_HOME && path.isAbsolute(env.XDG_STATE_HOME)) return path.join(env.XDG_STATE_HOME, "slosh", "opcua");
  if (env.HOME) return path.join(env.HOME, ".local", "state", "slosh", "opcua");
  throw new UsageError("state directory: neither XDG_STATE_HOME (an absolute path) nor HOME is set; give --state-dir DIR");
}

function serviceUrl(name, service) {
  let url;
  try { url = new URL(String(service)); } catch (e) { url = null; }
  if (!url || !["http:", "https:"].includes(url.protocol) || !url.hostname) {
    throw new UsageError(`${name} = ${JSON.stringify(service)} is not a service URL: http://host[:port][/path] or https://… expected`);
  }
  // A user name and password in the URL would be shown by Slosh.ServiceUrl and the log, and the
  // service takes none: refused rather than hidden.
  if (url.username || url.password) {
    throw new UsageError(`${name} holds a user name or password (user:pass@): the slosh service takes no credentials in its URL; remove them`);
  }
  // The value as given (URL would print http://x/?a for http://x?a), cut before the query: it
  // may hold a token.
  if (url.search || url.hash || /[?#]/.test(String(service))) {
    throw new UsageError(`${name} = ${JSON.stringify(String(service).replace(/([?#]).*$/s, "$1…"))} has a query or fragment: http://host[:port][/path] expected`);
  }
  return url;
}

function securityPolicies(name, security) {
  const list = (Array.isArray(security) ? security : String(security).split(",")).map((s) => String(s).trim().toLowerCase());
  const policies = { none: false, basic256sha256: false };
  if (list.every((s) => s === "")) throw new UsageError(`${name} is empty: allowed none, basic256sha256 or both`);
  for (const s of list) {
    if (!(s in policies)) throw new UsageError(`${name} = ${JSON.stringify(security)}: unknown policy ${JSON.stringify(s)}: allowed none, basic256sha256`);
    policies[s] = true;
  }
  return policies;
}

function hostSetting(name, host) {
  if (typeof host !== "string" || /[\s/]/.test(host)) throw new UsageError(`${name} = ${JSON.stringify(host)} is not a host name or address`);
}

function stateDirSetting(name, dir) {
  // "" would resolve to the working directory: a PKI with the server's key where nobody meant it.
  if (typeof dir !== "string" || dir === "") throw new UsageError(`${name} = ${JSON.stringify(dir)} is not a directory: give a path`);
  return path.resolve(dir);
}

// -> {service, port, host, timeoutMs, pollMs, security: {none, basic256sha256}, stateDir, users, portFile}
function resolve(argv, env = process.env) {
  const parsed = parseArgs(argv);
  if (parsed.help) return { help: true };
  const f = parsed.flags;
  const configPath = f.config !== undefined ? f.config : env.SLOSH_OPCUA_CONFIG;
  let config = {};
  if (configPath) {
    let text;
    try { text = fs.readFileSync(configPath, "utf8"); } catch (e) { throw new UsageError(`--config ${configPath}: cannot read it: ${e.code || e.message}`); }
    try { config = JSON.parse(text); } catch (e) { throw new UsageError(`--config ${configPath}: not valid JSON: ${e.message}`); }
    if (config === null || typeof config !== "object" || Array.isArray(config)) throw new UsageError(`--config ${configPath}: a JSON object expected`);
    const allowed = new Set([...SETTINGS.map(([, , key]) => key), "users"]);
    for (const k of Object.keys(config)) if (!allowed.has(k)) throw new UsageError(`--config ${configPath}: unknown key ${JSON.stringify(k)}: allowed ${[...allowed].join(", ")}`);
  }
  // Every source given, highest precedence first: [the name of the source, for messages; its
  // value]. An environment variable set to "" is given (and refused where "" is not a value).
  const sources = (flag) => {
    const [, envName, key] = SETTINGS.find(([name]) => name === flag);
    const given = [];
    if (f[flag] !== undefined) given.push([`--${flag}`, f[flag]]);
    if (env[envName] !== undefined) given.push([envName, env[envName]]);
    if (config[key] !== undefined) given.push([`config ${key}`, config[key]]);
    return given;
  };
  // -> [the name of the setting's source, for messages; its value].
  const pick = (flag) => {
    const given = sources(flag);
    if (given.length > 0) return given[0];
    return [`--${flag}`, SETTINGS.find(([name]) => name === flag)[3]];
  };
  // A numeric setting: every source given is checked, not only the one that wins, so a bad value
  // in the config file is found before the day the flag overriding it is dropped.
  const numeric = (flag, low, high, integer) => {
    const given = sources(flag);
    for (const [name, value] of given) numberSetting(name, value, low, high, integer);
    const [name, value] = pick(flag);
    return numberSetting(name, value, low, high, integer);
  };

  const serviceSources = sources("service");
  if (serviceSources.length === 0) throw new UsageError("--service URL is required (the slosh HTTP service, e.g. http://127.0.0.1:8080)");
  let url;
  for (const [serviceName, service] of [...serviceSources].reverse()) url = serviceUrl(serviceName, service);
  const [securityName, security] = pick("security");
  for (const [name, value] of sources("security")) securityPolicies(name, value);
  const policies = securityPolicies(securityName, security);
  for (const [name, value] of sources("host")) hostSetting(name, value);
  const [hostName, host] = pick("host");
  hostSetting(hostName, host);
  for (const [name, value] of sources("state-dir")) stateDirSetting(name, value);
  const [stateDirName, stateDirValue] = pick("state-dir");
  const stateDir = stateDirValue !== undefined ? stateDirSetting(stateDirName, stateDirValue) : defaultStateDir(env);

  const users = [];
  const warnings = [];
  if (config.users !== undefined) {
    if (!Array.isArray(config.users)) throw new UsageError(`--config ${configPath}: users must be a list of {"user", "password"}`);
    config.users.forEach((u, i) => {
      if (!u || typeof u.user !== "string" || u.user === "" || typeof u.password !== "string" || u.password === "") {
        throw new UsageError(`--config ${configPath}: users[${i}] needs a non-empty "user" and "password"`);
      }
      if (users.some((x) => x.user === u.user)) throw new UsageError(`--config ${configPath}: users[${i}]: user ${JSON.stringify(u.user)} is listed twice`);
      users.push({ user: u.user, password: u.password });
    });
    // Passwords in a file others can read: the gateway starts, but says so.
    try {
      const mode = fs.statSync(configPath).mode;
      if (config.users.length > 0 && (mode & 0o077) !== 0) {
        warnings.push(`--config ${configPath} holds passwords and is readable by group or others (mode ${(mode & 0o777).toString(8)}): chmod 600 it`);
      }
    } catch (e) { /* read above; a race is harmless */ }
  }
  if (env.SLOSH_OPCUA_USER || env.SLOSH_OPCUA_PASSWORD) {
    if (!env.SLOSH_OPCUA_USER || !env.SLOSH_OPCUA_PASSWORD) throw new UsageError("SLOSH_OPCUA_USER and SLOSH_OPCUA_PASSWORD go together: set both or neither");
    users.push({ user: env.SLOSH_OPCUA_USER, password: env.SLOSH_OPCUA_PASSWORD });
  }

  return {
    service: url.href,
    port: numeric("port", 0, 65535, true),
    host,
    timeoutMs: Math.round(numeric("timeout-s", 0.1, 600, false) * 1000),
    pollMs: Math.round(numeric("poll-s", 0.1, 60, false) * 1000),
    sessionTimeoutMs: Math.round(numeric("session-timeout-s", 1, 3000, false) * 1000),
    maxSessions: numeric("max-sessions", 1, 1000, true),
    security: policies,
    stateDir,
    users,
    portFile: f["port-file"],
    warnings,
    maxProducts: numeric("max-products", 1, 100000, true),
  };
}

module.exports = { resolve, UsageError, USAGE };
