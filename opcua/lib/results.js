"use strict";
// Failures -> OPC UA call results. The status code says what kind of failure it is; the text (the
// service's 422 message word for word, or the gateway's own) travels as the DiagnosticInfo of the
// argument it concerns (inputArgumentDiagnosticInfos, additionalInfo) with that argument's result
// set to BadInvalidArgument, and is kept in the LastError variable.
const { StatusCodes, DiagnosticInfo } = require("./stack");
const { ServiceError } = require("./service_client");
const { ArgumentError } = require("./requests");
const { argumentOfField } = require("./arguments");
const { ProductError } = require("./products");

function statusOf(err) {
  if (err instanceof ArgumentError) return err.invalidState ? StatusCodes.BadInvalidState : StatusCodes.BadInvalidArgument;
  if (err instanceof ServiceError) {
    if (err.kind === "timeout") return StatusCodes.BadTimeout;
    if (err.kind === "shutdown") return StatusCodes.BadShutdown;
    if (err.kind === "unreachable" || err.kind === "protocol") return StatusCodes.BadCommunicationError;
    if (err.status === 400 || err.status === 413 || err.status === 422) return StatusCodes.BadInvalidArgument;
    if (err.status === 404) return StatusCodes.BadNotFound;
    if (err.status === 409) return StatusCodes.BadInvalidState;
    if (err.status === 503) return StatusCodes.BadResourceUnavailable;
    if (err.status === 504) return StatusCodes.BadTimeout;
    return StatusCodes.BadInternalError;
  }
  return StatusCodes.BadInternalError;
}

// The index of the argument a failure concerns, or -1.
function argumentIndex(err, args) {
  if (err instanceof ArgumentError) return args.findIndex((a) => a.name === err.argument);
  if (err instanceof ServiceError) return argumentOfField(args, err.field);
  return -1;
}

// A call result for err on a method with input arguments args. Every argument gets a
// DiagnosticInfo carrying the message when the failure is tied to no argument (a timeout, an
// unreachable service), else only the argument concerned.
function failureResult(err, args) {
  const statusCode = statusOf(err);
  const index = argumentIndex(err, args);
  // Only the gateway's and the service's own messages travel whole; anything else (a fault of
  // node-opcua or of the gateway) is cut to its first line, never a stack or an address-space dump.
  const known = err instanceof ArgumentError || err instanceof ServiceError || err instanceof ProductError;
  const message = known ? err.message : `internal error of the gateway: ${String(err && err.message).split("\n")[0].slice(0, 200)}`;
  const inputArgumentResults = args.map((_, i) => (i === index ? StatusCodes.BadInvalidArgument : StatusCodes.Good));
  const inputArgumentDiagnosticInfos = args.map((_, i) =>
    (index === -1 || i === index ? new DiagnosticInfo({ additionalInfo: message }) : new DiagnosticInfo({})));
  return { statusCode, inputArgumentResults, inputArgumentDiagnosticInfos, message };
}

module.exports = { failureResult };
