"use strict";
// Security of the gateway: its endpoints (None and Basic256Sha256 SignAndEncrypt only), its own
// certificate created on first start, a client certificate refused until it is moved to the
// trusted folder (the documented command), user names and passwords from the config file, and
// the command line's checks.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");
const { spawnSync } = require("child_process");
const fs = require("fs");
const path = require("path");
const { OPCUACertificateManager, UserTokenType, StatusCodes } = require("../lib/stack");
const S = require("./support");

const gatewayScript = path.join(S.root, "opcua", "slosh-opcua");

function cli(args, env = {}) {
  const r = spawnSync(process.execPath, [gatewayScript, ...args], { env: { ...process.env, ...env }, encoding: "utf8", timeout: 30000 });
  return { code: r.status, stdout: r.stdout, stderr: r.stderr };
}

describe("slosh-opcua command line", () => {
  it("--help prints the usage and exits 0", () => {
    const r = cli(["--help"]);
    assert.equal(r.code, 0);
    assert.match(r.stdout, /^usage: slosh-opcua --service URL \[--port N\]/);
  });
  it("refuses bad settings with a message naming the setting and the allowed values (exit 2)", () => {
    const cases = [
      [[], "slosh-opcua: --service URL is required (the slosh HTTP service, e.g. http://127.0.0.1:8080)"],
      [["--service", "localhost:8080"], "slosh-opcua: --service = \"localhost:8080\" is not a service URL: http://host[:port][/path] or https://… expected"],
      [["--service", "http://127.0.0.1:8080", "--port", "65536"], "slosh-opcua: --port = \"65536\" is out of range: allowed an integer 0 to 65535"],
      [["--service", "http://127.0.0.1:8080", "--timeout-s", "0"], "slosh-opcua: --timeout-s = \"0\" is out of range: allowed 0.1 to 600"],
      [["--service", "http://127.0.0.1:8080", "--security", "basic128"], "slosh-opcua: --security = \"basic128\": unknown policy \"basic128\": allowed none, basic256sha256"],
      [["--service", "http://127.0.0.1:8080", "--prot", "1"], "slosh-opcua: unknown argument \"--prot\" (see --help)"],
      [["--service", "http://127.0.0.1:8080", "--port"], "slosh-opcua: --port needs a value"],
    ];
    for (const [args, message] of cases) {
      const r = cli(args);
      assert.equal(r.code, 2, `${args.join(" ")}: ${r.stderr}`);
      assert.equal(r.stderr.trim(), message);
    }
    const env = cli(["--service", "http://127.0.0.1:8080"], { SLOSH_OPCUA_USER: "op" });
    assert.equal(env.code, 2);
    assert.equal(env.stderr.trim(), "slosh-opcua: SLOSH_OPCUA_USER and SLOSH_OPCUA_PASSWORD go together: set both or neither");
  });
});

describe("slosh-opcua security", () => {
  let stack; let dir; let slosh; let gateway;
  const user = { userName: "line-7", password: "s3cret-format" };

  before(async () => {
    const withUsers = (d) => {
      const config = path.join(d, "opcua.json");
      fs.writeFileSync(config, JSON.stringify({ users: [{ user: user.userName, password: user.password }] }), { mode: 0o600 });
      return ["--config", config];
    };
    // No anonymous session: each test connects with its own security and identity.
    stack = await S.stack({ prefix: "slosh-opcua-sec-", extra: withUsers, session: false });
    ({ dir, slosh, gateway } = stack);
  });

  after(async () => {
    if (stack) await stack.stop();
  });

  it("creates its own certificate in the state directory and offers None and Basic256Sha256 SignAndEncrypt only", async () => {
    const own = path.join(gateway.stateDir, "pki", "own", "certs", "certificate.pem");
    assert.ok(fs.existsSync(own), `${own} missing`);
    assert.match(fs.readFileSync(own, "utf8"), /^-----BEGIN CERTIFICATE-----/);
    const key = path.join(gateway.stateDir, "pki", "own", "private", "private_key.pem");
    assert.equal(fs.statSync(key).mode & 0o777, 0o600, "the private key is for the gateway's user only");
    assert.equal(fs.statSync(path.join(gateway.stateDir, "pki")).mode & 0o777, 0o700);
    const { OPCUAClient } = require("../lib/stack");
    const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 } });
    await client.connect(gateway.endpoint);
    const endpoints = await client.getEndpoints();
    await client.disconnect();
    const offered = endpoints.map((e) => `${e.securityPolicyUri.split("#")[1]}/${e.securityMode}`).sort();
    assert.deepEqual([...new Set(offered)], ["Basic256Sha256/3", "None/1"]);
    for (const e of endpoints) {
      const kinds = e.userIdentityTokens.map((t) => t.tokenType);
      assert.ok(!kinds.includes(UserTokenType.Anonymous), "a configured user turns anonymous sessions off");
      assert.ok(kinds.includes(UserTokenType.UserName));
      // User names only, as documented: no X.509 user token policy on any endpoint.
      assert.deepEqual([...new Set(kinds)], [UserTokenType.UserName], `${e.securityPolicyUri} offers ${kinds}`);
    }
  });

  it("refuses anonymous sessions and wrong passwords; accepts the configured user", async () => {
    await assert.rejects(S.connect(gateway.endpoint), /Cannot find ANONYMOUS user token policy|BadIdentityTokenInvalid|BadIdentityTokenRejected|BadUserAccessDenied/);
    await assert.rejects(S.connect(gateway.endpoint, {}, { type: UserTokenType.UserName, userName: user.userName, password: "wrong" }),
      /BadUserAccessDenied|BadIdentityTokenRejected/);
    const c = await S.connect(gateway.endpoint, {}, { type: UserTokenType.UserName, ...user });
    assert.equal(await S.readValue(c.session, "ns=1;s=Slosh.ServiceReady"), true);
    await c.close();
  });

  it("Basic256Sha256 SignAndEncrypt: a client certificate is refused until moved to trusted, then the call works", async () => {
    const clientPki = path.join(dir, "client-pki");
    // The client trusts the gateway's own certificate (copied, as an operator would).
    fs.mkdirSync(path.join(clientPki, "trusted", "certs"), { recursive: true });
    fs.copyFileSync(path.join(gateway.stateDir, "pki", "own", "certs", "certificate.pem"), path.join(clientPki, "trusted", "certs", "slosh-opcua.pem"));
    const manager = new OPCUACertificateManager({ rootFolder: clientPki, automaticallyAcceptUnknownCertificate: false });
    await manager.initialize();
    const secure = { securityMode: S.MessageSecurityMode.SignAndEncrypt, securityPolicy: S.SecurityPolicy.Basic256Sha256, clientCertificateManager: manager };
    const identity = { type: UserTokenType.UserName, ...user };
    await assert.rejects(S.connect(gateway.endpoint, secure, identity));
    const rejected = path.join(gateway.stateDir, "pki", "rejected");
    const files = await S.until("the client certificate in pki/rejected", 10000, () => {
      const list = fs.readdirSync(rejected).filter((f) => f.endsWith(".pem"));
      return list.length ? list : null;
    });
    // The operator's command (docs/opcua.md): move it to trusted/certs and restart the gateway. The
    // certificate manager polls its folders, but a certificate moved before its poll has seen it
    // in rejected/ would stay rejected in memory until a restart.
    await gateway.stop();
    const ownBefore = fs.readFileSync(path.join(gateway.stateDir, "pki", "own", "certs", "certificate.pem"), "utf8");
    for (const f of files) fs.renameSync(path.join(rejected, f), path.join(gateway.stateDir, "pki", "trusted", "certs", f));
    gateway = await S.startGateway(dir, slosh.url, ["--config", path.join(dir, "opcua.json")]);
    stack.gateway = gateway;  // the one the suite's stop() stops
    assert.equal(fs.readFileSync(path.join(gateway.stateDir, "pki", "own", "certs", "certificate.pem"), "utf8"), ownBefore,
      "a restart keeps the server's certificate (clients trust it)");
    const c = await S.connect(gateway.endpoint, secure, identity);
    assert.equal(c.client.securityMode, S.MessageSecurityMode.SignAndEncrypt);
    assert.equal(c.client.securityPolicy, S.SecurityPolicy.Basic256Sha256);
    try {
      const direct = await S.httpJson("POST", slosh.url + "/v1/plans", { format: { container: { radius_mm: 48.5 }, fill_height_mm: 82, fluid: "water", stroke_mm: 500, motion_time_s: 0.7 }, strategy: "notch" });
      const r = await S.callMethod(c.session, "GetPlan", [["String", direct.body.key]]);
      assert.equal(r.statusCode.value, StatusCodes.Good.value);
      assert.deepEqual([...r.outputArguments[2].value], direct.body.durations_s);
    } finally {
      await c.close();
    }
  });
});
