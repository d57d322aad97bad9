"use strict";
// HTTP client of the slosh service. Every call is bounded by one deadline (connect, send, wait and
// read together), so an OPC UA method never waits on a hung or unreachable service longer than the
// gateway's --timeout-s. Failures are ServiceError values that say which OPC UA status they map to.
const http = require("http");
const https = require("https");

const MAX_ANSWER_BYTES = 64 * 1024 * 1024;

class ServiceError extends Error {
  // kind: "unreachable" (no connection), "timeout" (no answer in time), "http" (an error answer),
  // "protocol" (an answer that is not the service's JSON). status: the HTTP status for "http".
  constructor(kind, message, { status = 0, field = null, code = null } = {}) {
    super(message);
    this.kind = kind;
    this.status = status;
    this.field = field;
    this.code = code;
  }
}

class ServiceClient {
  // base: the service URL (http://host:port, optionally with a path prefix); timeoutMs: the bound
  // of each call.
  constructor(base, timeoutMs) {
    this.base = new URL(base);
    this.timeoutMs = timeoutMs;
    this.pending = new Set();
    // A new connection per call: a kept-alive socket that the service closed (a restart) would
    // fail the next call with ECONNRESET, which reads as a broken answer rather than "down". The
    // calls come at a line's format-change rate; the connection costs ~0.1 ms on loopback.
    this.agent = new (this.base.protocol === "https:" ? https : http).Agent({ keepAlive: false, maxSockets: 16 });
  }

  url(path) {
    const prefix = this.base.pathname.replace(/\/+$/, "");
    return new URL(prefix + path, this.base);
  }

  // Resolves {status, body (parsed JSON or text), headers}; rejects with a ServiceError for a
  // connection failure, a timeout, or (unless raw) any status >= 400.
  // boundName: what sets timeoutMs, for the timeout's message; onTimeout: makes the error of a
  // timeout instead (a bound of more than this one request says what it bounds).
  request(method, path, body = undefined, { raw = false, timeoutMs = this.timeoutMs, boundName = "--timeout-s", onTimeout = null } = {}) {
    if (this.closing) return Promise.reject(new ServiceError("shutdown", "the gateway is shutting down: call again once it is back"));
    const target = this.url(path);
    const lib = target.protocol === "https:" ? https : http;
    const payload = body === undefined ? null : Buffer.from(JSON.stringify(body));
    return new Promise((resolve, reject) => {
      let done = false;
      const finish = (fn, value) => {
        if (done) return;
        done = true;
        clearTimeout(timer);
        this.pending.delete(abort);
        fn(value);
      };
      // Called by close(): a call still waiting when the gateway stops is answered as such, not
      // as a failure of the service.
      const abort = () => {
        finish(reject, new ServiceError("shutdown", `the gateway is shutting down: ${method} ${path} was not answered; call again once it is back`));
        req.destroy();
      };
      this.pending.add(abort);
      const req = lib.request(target, {
        method,
        agent: this.agent,
        headers: {
          Accept: "application/json",
          ...(payload ? { "Content-Type": "application/json", "Content-Length": payload.length } : {}),
        },
      }, (res) => {
        const chunks = [];
        let size = 0;
        res.on("data", (c) => {
          size += c.length;
          chunks.push(c);
          // The largest answer the gateway asks for is a page of batch rows (gateway.js PAGE_ROWS).
          if (size > MAX_ANSWER_BYTES) {
            finish(reject, new ServiceError("protocol", `the slosh service answered ${method} ${path} with more than ${MAX_ANSWER_BYTES} bytes`));
            req.destroy();
          }
        });
        res.on("error", (e) => finish(reject, new ServiceError("unreachable", `the slosh service at ${this.base.origin} broke the answer: ${e.message}`)));
        res.on("end", () => {
          const text = Buffer.concat(chunks).toString("utf8");
          let parsed = text;
          if ((res.headers["content-type"] || "").includes("json")) {
            try { parsed = JSON.parse(text); } catch (e) {
              return finish(reject, new ServiceError("protocol", `the slosh service answered ${method} ${path} with JSON it could not parse: ${e.message}`));
            }
          }
          if (res.statusCode >= 400 && !raw) {
            const err = parsed && typeof parsed === "object" && parsed.error ? parsed.error : null;
            const message = err && err.message ? err.message : `${method} ${path}: HTTP ${res.statusCode}`;
            return finish(reject, new ServiceError("http", message, { status: res.statusCode, field: err ? err.field || null : null, code: err ? err.code || null : null }));
          }
          finish(resolve, { status: res.statusCode, body: parsed, headers: res.headers });
        });
      });
      const timer = setTimeout(() => {
        finish(reject, onTimeout ? onTimeout() : new ServiceError("timeout", `the slosh service at ${this.base.origin} did not answer ${method} ${path} within ${timeoutMs / 1000} s (${boundName})`));
        req.destroy();
      }, timeoutMs);
      req.on("error", (e) => finish(reject, new ServiceError("unreachable", `the slosh service at ${this.base.origin} is unreachable: ${e.code || e.message}`)));
      if (payload) req.write(payload);
      req.end();
    });
  }

  close() {
    this.closing = true;
    for (const abort of [...this.pending]) abort();
    this.agent.destroy();
  }
}

module.exports = { ServiceClient, ServiceError };
