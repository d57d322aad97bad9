"use strict";
// node-opcua, loaded without its start-up check of RSA PKCS#1 v1.5. On node 20 and 21 the check
// (node-opcua-secure-channel's verify_pcks1.js, run when the package loads) makes a 4096-bit RSA
// key pair only to print a warning: 0.5 to 1 s of CPU on every start of the gateway, of
// slosh-opcua-client and of a test's client. PKCS#1 v1.5 encryption is used by the
// Basic128Rsa15 policy only, which the gateway does not offer (None and Basic256Sha256, whose
// asymmetric encryption is RSA-OAEP), so the warning never applies to it. Every module of the
// gateway loads node-opcua through this one, and the first load in a process must be this one.
const fs = require("fs");
const path = require("path");

function skipPkcs1Check() {
  let dir;
  try {
    const opcua = path.dirname(require.resolve("node-opcua/package.json"));
    dir = path.dirname(require.resolve("node-opcua-secure-channel/package.json", { paths: [opcua] }));
  } catch (e) {
    return;
  }
  const file = path.join(dir, "dist", "source", "verify_pcks1.js");
  // Another layout of node-opcua (another version): its check runs, which costs time only.
  if (!fs.existsSync(file) || require.cache[file]) return;
  const check = new module.constructor(file, module);
  check.filename = file;
  check.loaded = true;
  check.exports = { testRSAPKCS1V15_EncryptDecrypt: async () => {} };
  require.cache[file] = check;
}

skipPkcs1Check();
module.exports = require("node-opcua");
