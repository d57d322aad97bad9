#pragma once
// An independent multi-start reference for the spectral strategies: the 7-segment
// law, its spectrum and jerk integral rebuilt from the SPEC text with forward-mode dual numbers
// (exact gradients), solved from many seeded starts by NLopt's SLSQP called directly. Nothing
// here calls into slosh::core, so the planner can be checked against it.

#include <array>
#include <complex>
#include <cstdint>
#include <vector>

namespace slosh::test {

using SevenDurations = std::array<double, 7>;

/// The problem data the reference needs (SI units).
struct SpectralProblem {
  double stroke{};  ///< s [m]
  double T{};       ///< motion time [s]
  double omega1{};  ///< [rad/s]
  double min_ramp{0.05};
  double band{0.15};  ///< min_jerk_band half width, relative [-]
  double tol_rel{0.2};
  double p_notch{0.15};
};

/// A and B of the durations (rest-to-rest over the stroke, SPEC §3).
struct Plateaus {
  double A{}, B{};
};
[[nodiscard]] Plateaus reference_plateaus(const SevenDurations& d, double stroke);

/// X_a(omega) of the 7-segment law, closed form rebuilt from SPEC §3-§4.
[[nodiscard]] std::complex<double> reference_spectrum(const SevenDurations& d, double stroke,
                                                      double omega);

/// Jerk integral sum J_i^2 dT_i [m^2/s^5].
[[nodiscard]] double reference_jerk_integral(const SevenDurations& d, double stroke);

/// Largest |X| over [lo, hi]: 4000 intervals, then golden section around every local maximum.
[[nodiscard]] double reference_band_max(const SevenDurations& d, double stroke, double lo,
                                        double hi);

/// X_ref: the uniform law's largest |X| over the band [(1 - band) w1, (1 + band) w1].
[[nodiscard]] double reference_x_ref(const SpectralProblem& p);

/// The best of a multi-start.
struct ReferenceOptimum {
  bool feasible{false};  ///< some start met the constraints (on the reference's grid)
  double objective{};    ///< best objective (min_jerk_band: jerk / uniform jerk; multi_notch:
                         ///< weighted power / X_ref^2; min-max: the band max / X_ref)
  SevenDurations durations{};
  int feasible_starts{};
  int starts{};
};

/// min jerk s.t. |X(w)| <= tol X_ref on `grid_points` band frequencies, from `starts` starts
/// (the uniform law and seeded Dirichlet points), SLSQP with exact gradients.
[[nodiscard]] ReferenceOptimum reference_min_jerk_band(const SpectralProblem& p, int starts,
                                                       int grid_points = 101,
                                                       std::uint64_t seed = 7);

/// min-max of |X| / X_ref over the band (epigraph), from `starts` starts.
[[nodiscard]] ReferenceOptimum reference_min_band_excess(const SpectralProblem& p, int starts,
                                                         int grid_points = 101,
                                                         std::uint64_t seed = 7);

/// min |X(w-)|^2 + |X(w1)|^2 + |X(w+)|^2 (weights 1) / X_ref^2, from `starts` starts.
[[nodiscard]] ReferenceOptimum reference_multi_notch(const SpectralProblem& p, int starts,
                                                     std::uint64_t seed = 7);

}  // namespace slosh::test
