#pragma once
// The cam table of a law at a motion controller's fixed cycle (SPEC §6).
//
// Sample k is the law's state at t_k = k * period, k = 0..N, where N is the first k with
// t_k >= T (within kCamTimeTolerance). Samples at or after T hold the rest state with the position
// set to the stroke exactly, so the last sample lands on the stroke even when T is not a multiple
// of the cycle. At a switch time the jerk is the one of the segment that starts there.

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "slosh/core/invalid_input.hpp"
#include "slosh/core/law/motion_law.hpp"

namespace slosh {

/// A sample time within this distance of a switch time (or of T) counts as on it [s].
constexpr double kCamTimeTolerance{1e-12};

/// Shortest controller cycle a cam table is sampled at [s].
constexpr double kCamMinPeriod{1e-5};

/// Shortest motion span master_end - master_start of a master-axis table, and so the shortest
/// master period [master units]: the derivatives per master unit stay finite.
constexpr double kMinMasterSpan{1e-6};

/// Slowest and fastest master speed (master_end - master_start) / motion time of a master-axis
/// table [master units/s]. The derivatives per master unit divide the law's by the speed, its
/// square and its cube, which stay between 1e-90 and 1e90 here: every cell is a finite number
/// (a master period of 1e308 over 0.5 s overflowed the speed to inf and gave a
/// table of zeros).
constexpr double kMinMasterSpeed{1e-30};
constexpr double kMaxMasterSpeed{1e30};

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
  /// The master speed (end - start) / motion time is refused (check_master_speed): the speed
  /// [master units/s]; `input` is then kPeriod, `value` the period and `bounds` the allowed
  /// speeds [master units/s].
  std::optional<double> speed;
  /// Significant digits of allowed(): bounds_digits(value, bounds).
  int digits{10};
  /// One sentence in core names ("master end = 400 must be finite and in (30, 360]").
  std::string message;

  /// The allowed set as text with `digits` significant digits, no unit: "> 0", "[0, 360)",
  /// "(30, 360]", ">= 3.6e-05".
  [[nodiscard]] std::string allowed() const;
  /// The refused value, shortest round trip (master_value_text).
  [[nodiscard]] std::string value_text() const;
};

/// A master axis refused by sample_master_cam_table or master_positions, with the refusal.
class MasterAxisError : public std::invalid_argument {
 public:
  explicit MasterAxisError(MasterAxisRefusal refusal);
  [[nodiscard]] const MasterAxisRefusal& refusal() const noexcept { return refusal_; }

 private:
  MasterAxisRefusal refusal_;
};

/// `v` with `digits` significant digits ("%g" style: "360", "3.600001081e-05").
[[nodiscard]] std::string master_number_text(double v, int digits = 10);

/// `v` as the shortest text that reads back as `v` ("360", "360.0000000001", "1e-05", "5e-324",
/// "inf", "nan").
[[nodiscard]] std::string master_value_text(double v);

/// The fewest significant digits from 10 to 17 with which `bounds`, as their texts read, still
/// leave out `value` (a value outside `bounds`): "360.0000000001 is out of range (30, 360]",
/// never "... [0, 359.999999]" for a value that reads 359.999999 (17 digits are exact).
[[nodiscard]] int bounds_digits(double value, const InputBounds& bounds);

/// Checks, in order: period finite and >= kMinMasterSpan; start in [0, period), and at most
/// period - kMinMasterSpan (refused with that bound when it lies in between); end in
/// (start, period], and at least start + kMinMasterSpan (refused with that bound when it lies
/// in between); step finite and > 0 with at most `max_rows` rows (period / step <= max_rows -
/// kMasterExtraRows). nullopt when the axis is valid. `max_rows` must exceed kMasterExtraRows.
/// An allowed set is never empty.
[[nodiscard]] std::optional<MasterAxisRefusal> check_master_axis(
    const MasterAxis& axis, std::size_t max_rows = kCamMaxSamples);

/// Checks the master speed (end - start) / motion_time of a valid axis driving a law of
/// duration `motion_time` (> 0, finite): in [kMinMasterSpeed, kMaxMasterSpeed], a finite
/// number. The refusal names the period (input kPeriod, `speed` set). nullopt when it is.
[[nodiscard]] std::optional<MasterAxisRefusal> check_master_speed(const MasterAxis& axis,
                                                                  double motion_time);

/// The master positions of the rows of a valid axis (see above), increasing, first 0, last the
/// period. Throws MasterAxisError when check_master_axis refuses the axis.
[[nodiscard]] std::vector<double> master_positions(const MasterAxis& axis);

/// True when the master position `x` lies on the grid k * step (within kMasterGridTolerance
/// steps).
[[nodiscard]] bool on_master_grid(double x, double step);

/// True when `start`, `end` and `period` all lie on the step grid: every row is `step` apart
/// (an equidistant cam table).
[[nodiscard]] bool master_grid_is_equidistant(const MasterAxis& axis);

/// Samples `law` (rest to rest over [0, duration]) on the master axis; the rows at and after the
/// end hold the position `stroke` exactly. Throws MasterAxisError when check_master_axis (at
/// most kCamMaxSamples rows) or check_master_speed refuses the axis, std::invalid_argument when
/// the law has no positive finite duration.
[[nodiscard]] std::vector<MasterCamSample> sample_master_cam_table(const MotionLaw& law,
                                                                   double stroke,
                                                                   const MasterAxis& axis);

}  // namespace slosh
