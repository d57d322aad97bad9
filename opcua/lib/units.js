"use strict";
// Engineering units (OPC UA EUInformation, UNECE Recommendation 20 common codes) of the gateway's
// arguments and variables. A unitId is the common code packed into an Int32 as OPC UA Part 8
// specifies (node-opcua's makeEUInformation does the packing).
const { makeEUInformation } = require("./stack");

const units = {
  mm: makeEUInformation("MMT", "mm", "millimetre"),
  s: makeEUInformation("SEC", "s", "second"),
  kg_m3: makeEUInformation("KMQ", "kg/m³", "kilogram per cubic metre"),
  pa_s: makeEUInformation("C65", "Pa·s", "pascal second"),
  m_s2: makeEUInformation("MSK", "m/s²", "metre per second squared"),
  m_s: makeEUInformation("MTS", "m/s", "metre per second"),
  m_s3: makeEUInformation("A68", "m/s³", "metre per second cubed"),
  pct: makeEUInformation("P1", "%", "percent"),
};
// "No unit" for unitless arguments: unitId -1 (OPC UA Part 8: no unit information).
const none = makeEUInformation("", "", "no unit");
none.unitId = -1;


module.exports = { units, none };
