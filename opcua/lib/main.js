"use strict";
// slosh-opcua: starts the OPC UA server in front of the slosh service and runs until SIGINT or
// SIGTERM. Exit 0 on a clean stop, 1 when the server cannot start, 2 on a bad setting.
const crypto = require("crypto");
const fs = require("fs");
const path = require("path");
const { resolve, UsageError, USAGE } = require("./options");
const { version } = require("../package.json");

function log(message) {
  process.stderr.write(`slosh-opcua: ${message}\n`);
}

function sameSecret(a, b) {
  // Digests of equal length, so the comparison time does not depend on where they differ.
  const da = crypto.createHash("sha256").update(a).digest();
  const db = crypto.createHash("sha256").update(b).digest();
  return crypto.timingSafeEqual(da, db);
}

// node-opcua grants a client up to 50 min (a constant of its own): the session of a client killed
// without closing it would hold a session slot that long. Requests for more than maxMs (or for
// none, node-opcua's 30 s default) are lowered to maxMs before node-opcua sees them, so the
// CreateSession answer's revisedSessionTimeout says what the client really got.
function boundSessionTimeout(server, maxMs) {
  const original = server._on_CreateSessionRequest;
  if (typeof original !== "function") throw new Error("node-opcua has no _on_CreateSessionRequest: --session-timeout-s cannot be applied with this version");
  server._on_CreateSessionRequest = function (message, channel) {
    const request = message.request;
    request.requestedSessionTimeout = Math.min(request.requestedSessionTimeout || 30000, maxMs);
    return original.call(this, message, channel);
  };
}

// mkdir -p, one level at a time: Node's recursive mkdirSync never returns for a path under /proc
// (/proc/self/x: mkdir answers ENOENT for a parent that exists, and Node retries the parent
// forever), so a wrong --state-dir would hang the start instead of failing it.
function makeDirectory(dir) {
  const parts = path.resolve(dir).split(path.sep).filter(Boolean);
  let at = path.sep;
  for (const part of parts) {
    at = path.join(at, part);
    let stat = null;
    try { stat = fs.statSync(at); } catch (e) { if (e.code !== "ENOENT") throw e; }
    if (stat && !stat.isDirectory()) throw Object.assign(new Error(`ENOTDIR: not a directory, mkdir '${dir}' (${at} is a file)`), { code: "ENOTDIR" });
    if (!stat) fs.mkdirSync(at, { mode: 0o700 });
  }
}

async function start(settings) {
  // The PKI holds the server's private key: everything the gateway creates is for its user only
  // (node-opcua writes the key 0644 under the default umask).
  process.umask(0o077);
  // The state directory and the key are checked before the OPC UA stack is loaded (some 2 s of
  // CPU): a start that cannot succeed fails at once.
  makeDirectory(settings.stateDir);
  const pki = path.join(settings.stateDir, "pki");
  // A key file that is not a key would fail deep in node-opcua with a message naming no file.
  const keyFile = path.join(pki, "own", "private", "private_key.pem");
  if (fs.existsSync(keyFile)) {
    try { crypto.createPrivateKey(fs.readFileSync(keyFile)); } catch (e) {
      throw new Error(`the private key ${keyFile} is not a readable PEM key (${e.message}): move it away to have a new one made, or restore it`);
    }
  }
  // Loaded here, not at the top: --help and a bad setting answer without loading the OPC UA stack.
  const { OPCUAServer, OPCUACertificateManager, SecurityPolicy, MessageSecurityMode, UserTokenType } = require("./stack");
  const { ServiceClient } = require("./service_client");
  const { Gateway } = require("./gateway");
  // Client certificates are not trusted until an operator moves them from pki/rejected/certs to
  // pki/trusted/certs (docs/opcua.md): a secure channel is only as good as that decision.
  const serverCertificateManager = new OPCUACertificateManager({ rootFolder: pki, automaticallyAcceptUnknownCertificate: false });
  await serverCertificateManager.initialize();
  // X.509 user tokens are not offered, but node-opcua keeps a user PKI anyway: inside the state
  // directory, not in its default per-user config folder (a read-only root in the container).
  const userCertificateManager = new OPCUACertificateManager({ rootFolder: path.join(settings.stateDir, "user-pki"), automaticallyAcceptUnknownCertificate: false });
  await userCertificateManager.initialize();
  const policies = [];
  const modes = [];
  if (settings.security.none) { policies.push(SecurityPolicy.None); modes.push(MessageSecurityMode.None); }
  if (settings.security.basic256sha256) { policies.push(SecurityPolicy.Basic256Sha256); modes.push(MessageSecurityMode.SignAndEncrypt); }
  const wildcard = settings.host === "" || settings.host === "0.0.0.0" || settings.host === "::";
  const users = settings.users;
  const server = new OPCUAServer({
    port: settings.port,
    ...(wildcard ? {} : { host: settings.host, hostname: settings.host }),
    serverCertificateManager,
    userCertificateManager,
    certificateFile: path.join(pki, "own", "certs", "certificate.pem"),
    privateKeyFile: path.join(pki, "own", "private", "private_key.pem"),
    securityPolicies: policies,
    securityModes: modes,
    allowAnonymous: users.length === 0,
    userManager: {
      isValidUser: (user, password) => users.some((u) => sameSecret(u.user, user || "") && sameSecret(u.password, password || "")),
    },
    // One connection per session is the usual client: as many connections as sessions.
    serverCapabilities: { maxSessions: settings.maxSessions },
    maxConnectionsPerEndpoint: settings.maxSessions,
    buildInfo: { productName: "slosh-opcua", productUri: "urn:slosh:opcua", manufacturerName: "slosh", softwareVersion: version },
    serverInfo: { applicationName: { text: "slosh OPC UA gateway", locale: "en" } },
  });
  await server.initialize();
  boundSessionTimeout(server, settings.sessionTimeoutMs);
  // A key made by an earlier start under another umask is tightened too.
  for (const [p, mode] of [[pki, 0o700], [path.join(pki, "own", "private"), 0o700], [path.join(pki, "own", "private", "private_key.pem"), 0o600]]) {
    if (fs.existsSync(p)) fs.chmodSync(p, mode);
  }
  const service = new ServiceClient(settings.service, settings.timeoutMs);
  const gateway = new Gateway(server, service, { pollMs: settings.pollMs, maxProducts: settings.maxProducts, log });
  await server.start();
  // node-opcua lists an X.509 user token policy on every endpoint whatever the options say (its
  // server does not pass userTokenTypes on): the gateway accepts user names only, so only those
  // (and Anonymous when no user is set) are offered.
  for (const endpoint of server.endpoints) {
    for (const d of endpoint.endpointDescriptions()) {
      d.userIdentityTokens = (d.userIdentityTokens || []).filter((t) => t.tokenType !== UserTokenType.Certificate);
    }
  }
  const port = server.endpoints[0].port;
  await gateway.startPolling();
  if (settings.portFile) fs.writeFileSync(settings.portFile, `${port}\n`);
  log(`listening on ${server.getEndpointUrl()} (${[settings.security.none && "None", settings.security.basic256sha256 && "Basic256Sha256 SignAndEncrypt"].filter(Boolean).join(", ")}; ${users.length ? `${users.length} user(s), anonymous refused` : "anonymous"}), service ${settings.service}, PKI ${pki}`);
  return { server, gateway, service };
}

async function main(argv) {
  let settings;
  try {
    settings = resolve(argv);
  } catch (e) {
    if (e instanceof UsageError) {
      process.stderr.write(`slosh-opcua: ${e.message}\n`);
      process.exit(2);
    }
    throw e;
  }
  if (settings.help) {
    process.stdout.write(USAGE + "\n");
    return;
  }
  for (const w of settings.warnings || []) log(`warning: ${w}`);
  let running;
  try {
    running = await start(settings);
  } catch (e) {
    log(`cannot start: ${e.message}`);
    process.exit(1);
  }
  let stopping = false;
  const stop = async () => {
    if (stopping) return;
    stopping = true;
    running.gateway.stop();
    running.service.close();
    await running.server.shutdown(0);
    process.exit(0);
  };
  process.on("SIGINT", stop);
  process.on("SIGTERM", stop);
}

module.exports = { main, start };
