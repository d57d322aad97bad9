#pragma once
// Units of the exported tables: the planner works in SI units, the tables in a drive's.

namespace slosh::service {

/// Millimetres per metre.
inline constexpr double kMmPerM = 1e3;

}  // namespace slosh::service
