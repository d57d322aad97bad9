#pragma once
// The cam table of a law at a motion controller's fixed cycle (SPEC §6).
//
// Sample k is the law's state at t_k = k * period, k = 0..N, where N is the first k with
// t_k >= T (within kCamTimeTolerance). Samples at or after T hold the rest state with the position
// set to the stroke exactly, so the last sample lands on the stroke even when T is not a multiple
// of the cycle. At a switch time the jerk is the one of the segment that starts there.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "slosh/core/invalid_input.hpp"
#include "slosh/core/law/motion_law.hpp"

namespace slosh {

/// A sample time within this distance of a switch time (or of T) counts as on it [s].
constexpr double kCamTimeTolerance{1e-12};

/// Shortest controller cycle a cam table is sampled at [s].
constexpr double kCamMinPeriod{1e-5};

/// Shortest motion span master_end - master_start of a master-axis table [master units]: the
/// derivatives per master unit stay finite.
constexpr double kMinMasterSpan{1e-6};

/// Most samples in one cam table (10 million: 2.8 h at 1 ms).
constexpr std::size_t kCamMaxSamples{10'000'000};

/// One row of a cam table (SI units).
struct CamSample {
  double t{};             ///< [s]
  double position{};      ///< [m]
  double velocity{};      ///< [m/s]
  double acceleration{};  ///< [m/s^2]
  double jerk{};          ///< [m/s^3]
};

/// Number of cycles N of a law of duration `motion_time` sampled every `period` (samples: N + 1).
[[nodiscard]] std::size_t cam_cycles(double motion_time, double period);

/// Samples `law` every `period` seconds; the samples at and after the end hold the position
/// `stroke` exactly. Throws std::invalid_argument for a period below kCamMinPeriod or a table of
/// more than kCamMaxSamples samples.
[[nodiscard]] std::vector<CamSample> sample_cam_table(const MotionLaw& law, double stroke,
                                                      double period);

// ---------------------------------------------------------------------------------------------
// Master-axis cam tables (SPEC §11): the same law driven by a master axis (e.g. the machine
// cycle in degrees) instead of the clock.
//
// The table covers one whole master period [0, period], what a PLC cam table holds for one
// machine cycle (PLCopen MC_CamTableSelect, Beckhoff or Siemens cam tables): the slave dwells at
// 0 up to `start`, follows the law while the master goes from `start` to `end` at the constant
// master speed w = (end - start) / T [master units/s] (law time t = (theta - start) / w), and
// dwells at the stroke from `end` to `period`. Run with a relative (additive) slave, the cam
// advances the slave by one stroke per master cycle.
//
// Rows are at theta_k = k * step (k = 0, 1, ... up to the period), plus `start`, `end` and
// `period` themselves when they are off that grid (a grid point within kMasterGridTolerance steps
// of one of them is replaced by it), so rows land exactly on the start (position 0), on the end
// (position = the stroke exactly) and on the period. The derivatives are per master unit:
// ds/dtheta = v / w, d2s/dtheta2 = a / w^2, d3s/dtheta3 = j / w^3. Before `start` every value
// is 0; at and after `end` the slave rests at the stroke exactly. A row whose law time is on a
// switch time (within kCamTimeTolerance) carries the jerk of the segment starting there.

/// A master position within this many steps of the start, the end or the period counts as on it
/// [-] (fraction of the master step).
constexpr double kMasterGridTolerance{1e-9};

/// Rows a master axis needs besides its grid points: the start, the end and the period when they
/// are off the grid [-].
constexpr std::size_t kMasterExtraRows{3};

/// The master axis of a cam table, in master units (e.g. degrees of a 360-degree cycle).
struct MasterAxis {
  double period{360.0};  ///< length of the master cycle; finite, > 0 [master units]
  double start{0.0};     ///< master position where the motion starts; 0 <= start < end
  double end{360.0};     ///< master position where the motion ends (at the stroke); <= period
  double step{1.0};      ///< master distance between rows; finite, > 0 [master units]
};

/// One row of a master-axis cam table (slave in SI units per master unit).
struct MasterCamSample {
  double master{};        ///< master position [master units]
  double position{};      ///< slave position [m]
  double velocity{};      ///< ds/dtheta [m / master unit]
  double acceleration{};  ///< d2s/dtheta2 [m / master unit^2]
  double jerk{};          ///< d3s/dtheta3 [m / master unit^3]
};

/// A member of MasterAxis, by its core name.
enum class MasterAxisInput { kPeriod, kStart, kEnd, kStep };

/// Why a master axis is refused: the member, its value and what it may be (master units).
struct MasterAxisRefusal {
  MasterAxisInput input{};
  double value{};      ///< the refused value [master units]
  InputBounds bounds;  ///< what the member may be, given the members checked before it
  /// The step is refused because the table would have more than the allowed rows (bounds.lo is
  /// then the smallest step allowed).
  bool too_many_rows{false};
  /// One sentence in core names ("master end = 400 must be finite and in (30, 360]").
  std::string message;

  /// The allowed set as text, 10 significant digits, no unit: "> 0", "[0, 360)", "(30, 360]",
  /// ">= 3.6e-05".
  [[nodiscard]] std::string allowed() const;
};

/// Checks, in order: period finite and > 0; start in [0, period); end in (start, period]; step
/// finite and > 0 with at most `max_rows` rows (period / step <= max_rows - kMasterExtraRows).
/// nullopt when the axis is valid. `max_rows` must exceed kMasterExtraRows.
[[nodiscard]] std::optional<MasterAxisRefusal> check_master_axis(
    const MasterAxis& axis, std::size_t max_rows = kCamMaxSamples);

/// The master positions of the rows of a valid axis (see above), increasing, first 0, last the
/// period. Throws std::invalid_argument when check_master_axis refuses the axis.
[[nodiscard]] std::vector<double> master_positions(const MasterAxis& axis);

/// True when the master position `x` lies on the grid k * step (within kMasterGridTolerance
/// steps).
[[nodiscard]] bool on_master_grid(double x, double step);

/// True when `start`, `end` and `period` all lie on the step grid: every row is `step` apart
/// (an equidistant cam table).
[[nodiscard]] bool master_grid_is_equidistant(const MasterAxis& axis);

/// Samples `law` (rest to rest over [0, duration]) on the master axis; the rows at and after the
/// end hold the position `stroke` exactly. Throws std::invalid_argument when check_master_axis
/// refuses the axis (at most kCamMaxSamples rows) or the law has no positive finite duration.
[[nodiscard]] std::vector<MasterCamSample> sample_master_cam_table(const MotionLaw& law,
                                                                   double stroke,
                                                                   const MasterAxis& axis);

}  // namespace slosh
