"use strict";
// Shape checks of the service's successful answers (docs/api.md, docs/min-time.md, docs/batch.md).
// A 2xx/3xx answer that is not what the API promises (an HTML page of a proxy, `{}`, a redirect
// with no body, members of the wrong type) must not read as a Good call with empty outputs: it is a
// ServiceError of kind "protocol" (BadCommunicationError) that says what was wrong.
const { ServiceError } = require("./service_client");

const isObject = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
const isNumber = (v) => typeof v === "number";

function describe(body) {
  if (body === "" || body === undefined) return "an empty body";
  if (typeof body === "string") return `text ${JSON.stringify(body.slice(0, 80))}`;
  return JSON.stringify(body).slice(0, 120);
}

function fail(method, path, body, problem) {
  throw new ServiceError("protocol", `the slosh service answered ${method} ${path} with a body that is not ${problem.what}: ${problem.why} (got ${describe(body)})`);
}

// Each check returns the first problem or null.
function planProblem(b) {
  if (!isObject(b)) return "not a JSON object";
  if (typeof b.status !== "string" || b.status === "") return "status is not a non-empty string";
  if (typeof b.key !== "string") return "key is not a string";
  if (b.message !== undefined && b.message !== null && typeof b.message !== "string") return "message is not a string";
  const d = b.durations_s;
  if (d !== undefined && d !== null && !(Array.isArray(d) && d.length === 7 && d.every(isNumber))) return "durations_s is neither null nor an array of 7 numbers";
  for (const m of ["kinematics", "prediction"]) {
    if (b[m] !== undefined && b[m] !== null && !isObject(b[m])) return `${m} is not an object`;
  }
  return null;
}

function minTimeProblem(b) {
  if (!isObject(b)) return "not a JSON object";
  if (!isObject(b.headline)) return "headline is not an object";
  const h = b.headline;
  if (h.t_min_s !== undefined && h.t_min_s !== null && !isNumber(h.t_min_s)) return "headline.t_min_s is not a number";
  if (h.winner !== undefined && h.winner !== null && typeof h.winner !== "string") return "headline.winner is not a string";
  if (b.key !== undefined && typeof b.key !== "string") return "key is not a string";
  return null;
}

function jobProblem(b) {
  if (!isObject(b)) return "not a JSON object";
  if (typeof b.state !== "string" || b.state === "") return "state is not a non-empty string";
  return null;
}

function jobPageProblem(b) {
  const p = jobProblem(b);
  if (p) return p;
  if (!isObject(b.results)) return "results is not an object";
  if (!Array.isArray(b.results.rows) || !b.results.rows.every(isObject)) return "results.rows is not an array of objects";
  const n = b.results.next_offset;
  if (n !== undefined && n !== null && !(Number.isInteger(n) && n >= 0)) return "results.next_offset is neither null nor an offset";
  return null;
}

function jobCreatedProblem(b) {
  if (!isObject(b)) return "not a JSON object";
  if (typeof b.id !== "string" || !/^[0-9a-f]{1,64}$/.test(b.id)) return "id is not a batch job id (hex digits)";
  return null;
}

function checker(what, problemOf) {
  return (body, method, path) => {
    const why = problemOf(body);
    if (why) fail(method, path, body, { what, why });
    return body;
  };
}

module.exports = {
  checkPlan: checker("a plan", planProblem),
  checkMinTime: checker("a min-time answer", minTimeProblem),
  checkJob: checker("a batch job", jobProblem),
  checkJobPage: checker("a batch job page", jobPageProblem),
  checkJobCreated: checker("a created batch job", jobCreatedProblem),
};
