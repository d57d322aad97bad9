#include "slosh/core/motion/trajectory_ends.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "slosh/core/motion/sample_smoothing.hpp"
#include "text.hpp"

namespace slosh {

namespace {

using Matrix4 = std::array<std::array<double, 4>, 4>;

/// The inverse of a symmetric positive definite 4 x 4 matrix (Gauss-Jordan; the fit's Gram
/// matrix of 1, u, u^2, u^3 over u in [0, 1] has a condition number ~1e4, far from trouble).
Matrix4 inverse(Matrix4 a) {
  Matrix4 inv{};
  for (std::size_t i = 0; i < 4; ++i) inv[i][i] = 1.0;
  for (std::size_t c = 0; c < 4; ++c) {
    const double d = a[c][c];
    for (std::size_t k = 0; k < 4; ++k) {
      a[c][k] /= d;
      inv[c][k] /= d;
    }
    for (std::size_t r = 0; r < 4; ++r) {
      if (r == c) continue;
      const double f = a[r][c];
      for (std::size_t k = 0; k < 4; ++k) {
        a[r][k] -= f * a[c][k];
        inv[r][k] -= f * inv[c][k];
      }
    }
  }
  return inv;
}

/// The samples the end fit takes: those within `window` of the end sample, at least
/// kMinEndFitSamples (all when there are fewer).
std::size_t end_fit_count(const std::vector<double>& t, bool last, double window) {
  const std::size_t n = t.size();
  const double end = last ? t.back() : t.front();
  std::size_t m = 1;
  while (m < n && std::abs(t[last ? n - 1 - m : m] - end) <= window) ++m;
  return std::min(n, std::max(m, kMinEndFitSamples));
}

}  // namespace

EndRate end_rate(const std::vector<double>& t, const std::vector<double>& v, bool last,
                 double window) {
  const std::size_t n = t.size(), m = end_fit_count(t, last, window);
  auto at = [&](std::size_t j) { return last ? n - 1 - j : j; };
  // u = |t - t_end| / span in [0, 1], values from the end's: the Gram matrix stays well
  // conditioned however far the clock and the pose are from 0.
  const double span = std::abs(t[at(m - 1)] - t[at(0)]);
  std::vector<std::array<double, 4>> basis(m);
  Matrix4 gram{};
  std::array<double, 4> rhs{};
  for (std::size_t j = 0; j < m; ++j) {
    const double u = std::abs(t[at(j)] - t[at(0)]) / span, y = v[at(j)] - v[at(0)];
    basis[j] = {1.0, u, u * u, u * u * u};
    for (std::size_t r = 0; r < 4; ++r) {
      rhs[r] += basis[j][r] * y;
      for (std::size_t c = 0; c < 4; ++c) gram[r][c] += basis[j][r] * basis[j][c];
    }
  }
  const Matrix4 inv = inverse(gram);
  std::array<double, 4> coef{};
  for (std::size_t r = 0; r < 4; ++r) {
    for (std::size_t c = 0; c < 4; ++c) coef[r] += inv[r][c] * rhs[c];
  }
  double rss = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    double fit = 0.0;
    for (std::size_t r = 0; r < 4; ++r) fit += coef[r] * basis[j][r];
    rss += (v[at(j)] - v[at(0)] - fit) * (v[at(j)] - v[at(0)] - fit);
  }
  const double variance = m > 4 ? rss / static_cast<double>(m - 4) : 0.0;
  // u grows away from the end: at the last sample it runs against time.
  const double sign = last ? -1.0 : 1.0;
  return {sign * coef[1] / span, std::sqrt(variance * inv[1][1]) / span};
}

namespace {

/// Whether the samples v hold still at the end `last` (or the first): a run of at least
/// kMinRestSamples samples within their resolution (rest_runs).
bool holds_still(const std::vector<double>& t, const std::vector<double>& v, bool last) {
  const RestRuns runs = rest_runs(v, sample_noise(t, v));
  return (last ? runs.tail : runs.head) > 0;
}

/// A coordinate's rate at the end as the end fit shows it: its slope when it stands out of its
/// standard error and the samples do not hold still there, else 0.
double fitted_rate(const std::vector<double>& t, const std::vector<double>& v, bool last,
                   double window) {
  if (holds_still(t, v, last)) return 0.0;
  const EndRate r = end_rate(t, v, last, window);
  return std::abs(r.rate) > kEndFitSignificance * r.standard_error ? r.rate : 0.0;
}

/// The container's speed (x, y, z) [m/s] and turning rate [rad/s] at an end.
struct EndMotion {
  double speed{};
  double rate{};
};

/// The end motion the end fits show (fitted_rate of each coordinate).
EndMotion fitted_end(const TrajectorySamples& s, bool last, double window) {
  const double vx = fitted_rate(s.t, s.x, last, window), vy = fitted_rate(s.t, s.y, last, window),
               vz = fitted_rate(s.t, s.z, last, window);
  return {std::sqrt(vx * vx + vy * vy + vz * vz),
          std::abs(fitted_rate(s.t, s.theta, last, window))};
}

/// The end motion of the splines the models are driven by: their slopes at the end sample, 0
/// for a coordinate whose samples hold still there.
EndMotion spline_end(const SampledTrajectory& trajectory, bool last) {
  const TrajectorySamples& s = trajectory.samples();
  PlanarKinematics k = trajectory.at(last ? trajectory.end_time() : trajectory.start_time());
  if (holds_still(s.t, s.x, last)) k.vx = 0.0;
  if (holds_still(s.t, s.y, last)) k.vy = 0.0;
  if (holds_still(s.t, s.z, last)) k.vz = 0.0;
  if (holds_still(s.t, s.theta, last)) k.theta_dot = 0.0;
  return {std::sqrt(k.vx * k.vx + k.vy * k.vy + k.vz * k.vz), std::abs(k.theta_dot)};
}

/// What the models computed at the end `last` (or the first), for a container that moves
/// (`moving`) and / or turns (`turning`) there.
std::string end_treatment(bool last, bool moving, bool turning) {
  std::string out;
  if (moving) {
    out += last ? "the models see no acceleration after it, as if the container went on at "
                  "that speed through the rest window: the wave of stopping it is not in the "
                  "prediction (eta_rest in particular)"
                : "the models take the liquid at rest there, as if the container had always "
                  "moved at that speed: the wave of the acceleration that brought it to that "
                  "speed is not in the prediction";
  }
  if (turning) {
    if (moving) out += "; ";
    out += last ? "the models stop its turning at once at that sample: the rest window holds "
                  "the liquid's spin running down after that sudden stop, not the turning going "
                  "on nor a real stop of it"
                : "the models start its turning at once at that sample with the liquid at rest: "
                  "the liquid's spin-up from that sudden start is in the prediction, not the "
                  "turning before it";
  }
  return out;
}

}  // namespace

std::vector<std::string> moving_end_warnings(const SampledTrajectory& trajectory, double omega1) {
  std::vector<std::string> out;
  const TrajectorySamples& s = trajectory.samples();
  const double window = kEndFitPeriods * 2.0 * std::numbers::pi / omega1;
  for (const bool last : {false, true}) {
    const EndMotion fit = fitted_end(s, last, window), spline = spline_end(trajectory, last);
    const bool moving = fit.speed > kMovingEndSpeed && spline.speed > kMovingEndSpeed;
    const bool turning = fit.rate > kTurningEndRate && spline.rate > kTurningEndRate;
    if (!moving && !turning) continue;
    const std::size_t i = last ? trajectory.size() - 1 : 0;
    std::string w = std::string("the trajectory ") + (last ? "ends" : "starts") +
                    " moving: at its " + (last ? "last" : "first") + " sample (t_s[" +
                    std::to_string(i) + "] = " + detail::precise(s.t[i]) +
                    " s) the container moves at " + detail::sig3(fit.speed * 1e3) +
                    " mm/s and turns at " + detail::sig3(fit.rate * 180.0 / std::numbers::pi) +
                    " deg/s; " + end_treatment(last, moving, turning) + "; " +
                    (last ? "end" : "start") + " the trajectory at rest";
    out.push_back(std::move(w));
  }
  return out;
}

}  // namespace slosh
