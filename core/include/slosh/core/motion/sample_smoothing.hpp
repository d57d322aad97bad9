#pragma once
// Smoothing of one sampled coordinate before its cubic spline (SPEC §14: a trajectory's
// acceleration is the second derivative of its samples through smoothing splines). A log's
// rounding is noise to a second derivative: 0.01 mm at 1 kHz differentiates twice to ~30 m/s^2.
//
// The smoothed values g minimise
//     sum_i (y_i - g_i)^2 + lambda sum_j (d4_j . g)^2
// where d4_j are the fourth divided differences over samples j..j+4, each row scaled to unit
// norm (so each term is measured in units of its own noise, at any spacing). The penalty is the
// discrete form of the integral of the fourth derivative squared: every cubic has none, so a
// cubic is never bent, and neither the end acceleration nor the end jerk is pulled to 0 (the
// natural ends of Reinsch's cubic smoothing spline, whose penalty is the second derivative,
// would force zero acceleration at both ends). The not-a-knot cubic spline through g then gives
// the kinematics; with lambda -> 0 it is the interpolating spline of the samples.
//
// lambda follows Reinsch's (1967) criterion: the residual sum of squares equals n sigma^2, with
// sigma the samples' noise estimated from their sixth divided differences (unit-norm rows, so
// each is a N(0, sigma^2) variable for independent noise): sigma = median |d6| / 0.6745 over
// the rows that are not exactly 0 (a log holding still repeats its value and carries no
// rounding). A smooth motion's sixth differences are ~ (w h)^6 of its amplitude (1e-17 m at
// 1 kHz for a 3 Hz motion of 0.25 m), so a clean commanded trajectory gets a sigma at its
// round-off and is interpolated as it is; jerk and acceleration steps touch only a few rows and do
// not move the median.
//
// The normal equations are solved in Reinsch's residual form (I / lambda + D D^T) w = D y,
// g = y - D^T w: banded (half bandwidth 4) and well conditioned for the residual whatever
// lambda, since the residual, not g, is what is computed.
//
// An end holds still when its last (first) kMinRestSamples samples or more all lie within the
// samples' resolution of the end sample (rest_runs): half their quantum (the smallest nonzero
// step between two neighbours; for a rounded log, the samples that repeat the end's value), at
// most 4 sigma. The moving-end verdict (trajectory_ends.hpp) takes such an end as at rest. The
// fit is not pinned there: held still over the run at the free fit's lambda it left the samples
// of a half-cosine rounded to 0.1 mm by 0.85 mm (its approach repeats the end value for 8 ms
// before the stop's acceleration step), and with lambda chosen on the pinned fit the criterion
// smoothed 1000 times less. So a rounded log that sits still at its end can still end its
// spline with a small slope (a measured run rounded to 0.1 mm: 11.6 mm/s), which the verdict
// does not take for motion.

#include <cstddef>
#include <vector>

namespace slosh {

/// Least samples for a noise estimate (a sixth divided difference needs 7); fewer are not
/// smoothed.
inline constexpr std::size_t kMinSmoothedSamples{7};
/// Largest lambda [-]: beyond it the fit is the least-squares cubic to ~1e-12 (the penalised
/// rows weigh 1e12 times their residual), and I / lambda stays well above D D^T's round-off.
inline constexpr double kMaxSmoothing{1e12};

/// Least samples of a run at an end that holds still (rest_runs) [-]: twice the penalty's order,
/// so that penalised rows lie wholly inside the run and the spline's end pieces on it.
inline constexpr std::size_t kMinRestSamples{8};

/// How many samples at each end hold still (0: that end moves; the size of v when all do).
struct RestRuns {
  std::size_t head{};
  std::size_t tail{};
};

struct SmoothedSamples {
  std::vector<double> value;  ///< g
  double noise{};             ///< sigma [unit of the samples]
  double lambda{};            ///< 0 when not smoothed
  RestRuns rest{};            ///< the runs that hold still at each end
};

/// sigma of the samples v at times t (0 for fewer than kMinSmoothedSamples samples or when
/// every sixth difference is 0).
[[nodiscard]] double sample_noise(const std::vector<double>& t, const std::vector<double>& v);

/// The runs of at least kMinRestSamples samples at each end of v within min(quantum / 2,
/// 4 noise) of the end sample, where the quantum is the smallest nonzero |v[i+1] - v[i]| (exactly
/// equal samples only when the noise is 0).
[[nodiscard]] RestRuns rest_runs(const std::vector<double>& v, double noise);

/// The smoothed samples: v itself when sigma is at most 16 eps of the largest |v| (the samples'
/// own round-off: exact samples); else the penalised fit whose residual sum of
/// squares is n sigma^2 (to 0.1 %), or the one at kMaxSmoothing when even that one stays closer.
[[nodiscard]] SmoothedSamples smoothed_samples(const std::vector<double>& t,
                                               const std::vector<double>& v);

}  // namespace slosh
