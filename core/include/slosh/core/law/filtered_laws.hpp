#pragma once
// Anti-sloshing laws of a prescribed duration by filtering (Guagliumi et al., JDSMC 2022,
// [JDSMC] in docs/models.md, sec. 3.1, 3.4, 4): input shapers convolved with a base law, and the
// chain of three rectangular FIR filters on a step. Both results are exact piecewise laws
// (MotionLaw), so the spectrum, the exact linear response and the nonlinear model apply to them
// unchanged.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>
#include "slosh/core/enum_names.hpp"

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"

namespace slosh {

/// Base laws the filters act on (paper sec. 4: poly5 and the modified trapezoid; the uniform
/// 7-segment law is the product's baseline).
enum class BaseLaw { kSevenSegmentUniform, kPoly5, kModifiedTrapezoid };

template <>
struct EnumNames<BaseLaw> {
  static constexpr std::array<EnumName<BaseLaw>, 3> table{{
      {BaseLaw::kPoly5, "poly5"},
      {BaseLaw::kModifiedTrapezoid, "modified_trapezoid"},
      {BaseLaw::kSevenSegmentUniform, "seven_segment_uniform"},
  }};
};
[[nodiscard]] inline std::string to_string(BaseLaw value) {
  return std::string(name_of(value));
}

/// The base law of `stroke` [m] over `duration` [s].
[[nodiscard]] MotionLaw make_base_law(BaseLaw base, double stroke, double duration);

/// Input shaper families: the paper's ZV, ZVD, ZVDD and EI (sec. 3.1), and the insensitive
/// shapers of Singhose et al. for an uncertain frequency: MZV and the two- and three-hump EI.
/// Values are appended (kMZV, kEI2, kEI3 after kEI); the API lists them in the table's order.
enum class ShaperType { kZV, kZVD, kZVDD, kEI, kMZV, kEI2, kEI3 };

template <>
struct EnumNames<ShaperType> {
  static constexpr std::array<EnumName<ShaperType>, 7> table{{
      {ShaperType::kZV, "zv"},
      {ShaperType::kMZV, "mzv"},
      {ShaperType::kZVD, "zvd"},
      {ShaperType::kZVDD, "zvdd"},
      {ShaperType::kEI, "ei"},
      {ShaperType::kEI2, "ei2"},
      {ShaperType::kEI3, "ei3"},
  }};
};
[[nodiscard]] inline std::string to_string(ShaperType value) {
  return std::string(name_of(value));
}

/// Default residual vibration V of the EI shapers (ei, ei2, ei3: the height of their humps) [-]
/// (5 %).
constexpr double kDefaultEiResidual{0.05};

/// One impulse of a shaper.
struct Impulse {
  double time{};       ///< t_j [s]
  double amplitude{};  ///< A_j [-]
};

/// A train of impulses with unit sum.
struct InputShaper {
  ShaperType type{ShaperType::kZV};
  std::vector<Impulse> impulses;
  /// True when the impulses satisfy the design equations of `type` exactly at (omega, zeta)
  /// (see make_shaper). False only for ei2 and ei3 when the damped hump design has no solution
  /// (large zeta or V): the impulses are then the damping-compensated closed form.
  bool exact_design{true};
  /// The delay it adds: the time of the last impulse [s].
  [[nodiscard]] double delay() const { return impulses.empty() ? 0.0 : impulses.back().time; }
};

/// The damped period T_d = 2 pi / (omega sqrt(1 - zeta^2)) (paper eq. 5) [s].
[[nodiscard]] double damped_period(double omega, double zeta);

/// The shaper of `type` for a mode (omega [rad/s], zeta [-]); `residual` is V [-] (ei, ei2, ei3).
/// K = exp(-zeta pi / sqrt(1 - zeta^2)) (eq. 5), T_d the damped period; amplitudes sum to 1.
/// Impulses at t_j = T_d j / 2 (eq. 6) with amplitudes
///   ZV   [1, K] / (1 + K)
///   ZVD  [1, 2K, K^2] / (1 + K)^2
///   ZVDD [1, 3K, 3K^2, K^3] / (1 + K)^3
///   EI   [p, q K, p K^2] with p (1 + K^2) + q K = 1 and (2p - q) K^2 = V: the one-hump EI shaper
///        (undamped amplitudes (1+V)/4, (1-V)/2, (1+V)/4) with the same damping compensation as the
///        ZV family, leaving exactly the residual V at omega (with damping the hump's top moves off
///        omega and tops V slightly: by 1.4e-4 V at zeta = 0.05, 6.7e-4 V at 0.1).
/// MZV: three impulses at t_j = 3 T_d j / 8 (135 degrees of the damped oscillation apart),
///   [a, b K_m, a K_m^2] / sum, a = 1 - 1/sqrt(2), b = sqrt(2) - 1, K_m = K^(3/4): no residual at
///   omega for every zeta (undamped, also none at 5 omega / 3); delay 3/4 T_d, between ZV and ZVD.
/// ei2, ei3: the two- and three-hump EI shapers (Singhose, Derezinski & Singer 1996; Singhose,
///   Porter, Tuttle & Singer 1997): the residual stays <= V over a wide band around omega, touching
///   V at its humps (zero slope there) and vanishing between them.
///   ei2, 4 impulses: zero at omega and at one frequency below and one above it, humps of height V
///     between them; undamped t_j = T j / 2 (T = 2 pi / omega), [a, 1/2 - a, 1/2 - a, a] with
///     a = (3X^2 + 2X + 3V^2) / (16X), X = (V^2 (sqrt(1 - V^2) + 1))^(1/3).
///   ei3, 5 impulses: humps of height V at omega and at one frequency below and one above it,
///     zeros between and outside them; undamped t_j = T j / 2, [a1, a2, 1 - 2a1 - 2a2, a2, a1]
///     with a1 = (1 + 3V + 2 sqrt(2V(V + 1))) / 16, a2 = (1 - V) / 4.
///   With damping the same conditions (unit sum, every zero exact, every hump exactly V with zero
///   slope, the middle one of ei3 at omega) are solved for the amplitudes and the impulse times by
///   Newton's method (to 1e-12), continued in zeta from the undamped closed form (a few ms, up to
///   ~35 ms near the limit below). The solution agrees with Singhose's damped fits for V = 5 %
///   within their own accuracy (1.5e-3 in amplitude, 5e-3 T in time for zeta <= 0.05). It exists
///   for zeta up to a limit that falls with V: V = 0.01: 0.61 (ei2), 0.46 (ei3); V = 0.05: 0.45,
///   0.32; V = 0.2: 0.24, 0.13; V = 0.5: 0.06, 0.03; none for V <= 1e-4 (the continuation fails).
///   Beyond it exact_design is false and the undamped closed form with the ZV family's damping
///   compensation (a_j K^j / sum, t_j = T_d j / 2) is returned: it keeps ei2's zero at omega and
///   its humps below V. V = 0 gives the limits, exactly: zvdd (ei2) and [1, 4, 6, 4, 1] / 16
///   compensated like the ZV family (ei3).
/// Throws std::invalid_argument for omega <= 0, zeta outside [0, 1) or V outside [0, 1).
[[nodiscard]] InputShaper make_shaper(ShaperType type, double omega, double zeta,
                                      double residual = kDefaultEiResidual);

/// Residual vibration of a mode after the impulse train, relative to a single unit impulse
/// (paper sec. 3.1: Z_n divided by omega / sqrt(1 - zeta^2)) [-]:
/// |sum_j A_j exp((-zeta omega + i omega sqrt(1 - zeta^2)) (t_N - t_j))|.
[[nodiscard]] double shaper_residual(const InputShaper& shaper, double omega, double zeta);

/// The largest shaper_residual(shaper, w, zeta) over w in [omega_lo, omega_hi] [rad/s] [-]: what a
/// mode whose frequency is only known to lie in that range may keep. The derivative of the squared
/// residual is sampled at 256 points per period 2 pi / t_N of its fastest term (t_N the delay) and
/// each sign change from + to - is bisected to the last bit, the ends included: exact to round-off
/// (~1e-15) unless a maximum and a minimum lie within one sample step (1/256 of that period).
/// Cost: (omega_hi - omega_lo) t_N 256 / (2 pi) evaluations of the residual and its slope.
/// Throws std::invalid_argument for an empty shaper, zeta outside [0, 1), unless
/// 0 <= omega_lo <= omega_hi (finite), and beyond 1e7 samples.
[[nodiscard]] double max_residual_over(const InputShaper& shaper, double omega_lo, double omega_hi,
                                       double zeta);

/// The convolution sum_j A_j base(t - t_j) as an exact piecewise law (duration: the base's plus
/// the shaper's delay). Throws std::invalid_argument when overlapping pieces carry harmonic terms
/// of different frequencies (a piece holds one harmonic).
[[nodiscard]] MotionLaw convolve(const MotionLaw& base, const InputShaper& shaper);

/// The chain of three rectangular FIR filters of durations T1, T2, T3 (eq. 13) applied to a step
/// of `stroke`: jerk = stroke / (T1 T2 T3) * sum over subsets S of {T1, T2, T3} of
/// (-1)^|S| H(t - sum S). Duration T1 + T2 + T3.
struct FirChain {
  double t1{}, t2{}, t3{};  ///< [s]
  MotionLaw law;
  /// The seven durations when conditions (14) hold (T1 >= T2 + T3, T2 >= T3):
  /// [T3, T2 - T3, T3, T1 - T2 - T3, T3, T2 - T3, T3].
  std::optional<Durations> durations;
};

/// Throws std::invalid_argument unless every T_i > 0.
[[nodiscard]] FirChain make_fir_chain(double stroke, double t1, double t2, double t3);

}  // namespace slosh

namespace slosh {

/// Order of the IIR anti-sloshing filter (paper eq. 8: critically damped 2nd order target,
/// eq. 9: 3rd order).
enum class IirOrder { kSecond = 2, kThird = 3 };

/// Default pole tau of the IIR filter [1/s] (paper sec. 4: 40 to 100 works for ~1 s laws).
constexpr double kDefaultIirTau{50.0};

/// The FOH difference equation of F_IIR (paper eq. 10-12):
///   y(k) = -sum_i a_i y(k - i) + b_0 u(k + 1) + sum_{i >= 1} b_i u(k + 1 - i).
struct IirFilter {
  IirOrder order{IirOrder::kSecond};
  double tau{kDefaultIirTau};  ///< [1/s]
  double sample_period{1e-3};  ///< T_s [s]
  std::vector<long double> a;  ///< a_1 .. a_n (long double: see make_iir_filter)
  std::vector<long double> b;  ///< b_0 .. b_{n+1}
};

/// Coefficients of eq. 11 (second order) or eq. 12 (third order) for a mode (omega, zeta).
[[nodiscard]] IirFilter make_iir_filter(IirOrder order, double omega, double zeta, double tau,
                                        double sample_period);

/// Runs the difference equation on samples u(0..N-1) (u(k) = u(0) before 0 and u(N-1) after the
/// end: the input rests at both ends) and returns `output_length` samples.
[[nodiscard]] std::vector<double> apply_iir(const IirFilter& filter, const std::vector<double>& u,
                                            std::size_t output_length);

}  // namespace slosh

namespace slosh {

/// Default sample period of the IIR law [s] (a 1 ms controller cycle, as in the paper).
constexpr double kDefaultIirSamplePeriod{1e-3};
/// The filtered law ends one sample after the last sample whose |acceleration| exceeds this
/// fraction of its peak [-] (the e^(-tau t) tail below it is cut; with tau = 50 this gives the
/// ~0.19 s delay the paper reports on a 1 s poly5 law).
constexpr double kIirTailTolerance{1e-3};
/// Largest |acceleration| a filtered law may have [m/s^2] (1e5 g: far beyond any machine, the
/// bound simulate accepts for general laws, so every planned law can be re-simulated).
constexpr double kMaxLawAcceleration{1e6};
/// Shortest base law a shaper or the IIR filter may leave room for [s] (the 1 ms ramp floor).
constexpr double kMinBaseDuration{1e-3};

/// The IIR law needs at least this many samples over the motion (T_s <= T / 20).
constexpr int kIirMinSamples{20};
/// The iir strategy samples at most this many over the motion (bounds its time and the size of
/// the returned law: T_s >= T / 20000).
constexpr int kIirMaxSamples{20000};
/// Most base-duration updates of the delay compensation.
constexpr int kIirMaxIterations{30};

/// An IIR-filtered law of a prescribed duration (paper sec. 4).
struct IirLaw {
  /// False when the filter's delay leaves no time for the base law (less than kMinBaseDuration):
  /// `law` is empty and `delay` is the delay measured on the base law of duration T.
  bool fits{false};
  /// Acceleration linear between the samples k T_s (first-order hold, as the difference equation
  /// assumes), then at rest up to exactly the prescribed duration; rest-to-rest exactly.
  MotionLaw law;
  double base_duration{};      ///< duration of the base law that was filtered [s]
  double delay{};              ///< filtered duration minus base duration, last pass [s]
  double filtered_duration{};  ///< filtered duration before padding to T [s]
  int iterations{};            ///< filter passes
  /// Largest rest-to-rest correction relative to the peak acceleration [-]: the samples are
  /// scaled by (c0 + c1 t / T) so the piecewise-linear law ends at rest exactly at the stroke
  /// (it absorbs the cut tail and the hold's O(T_s^2) integration error).
  double correction{};
};

/// Filters `base(duration)` (acceleration samples at k T_s) with `filter`, re-planning the base
/// duration T - Delta T until the filtered law ends within one sample before `motion_time`, and
/// pads it with rest to exactly `motion_time`. `stroke` is the base laws' stroke [m].
[[nodiscard]] IirLaw make_iir_law(const std::function<MotionLaw(double)>& base,
                                  const IirFilter& filter, double stroke, double motion_time);

}  // namespace slosh
