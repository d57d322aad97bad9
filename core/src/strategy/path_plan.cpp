// Planning along a planar path (path_plan.hpp): the strategies' laws of s(t), verified on the
// planar models, with the path's machine limits; time_domain optimises the planar model itself.

#include "slosh/core/strategy/path_plan.hpp"

#include <algorithm>
#include <cmath>

#include "slosh/core/motion/planar_drive.hpp"

namespace slosh {

namespace {

/// Samples per smooth stretch before the golden-section refinement [-].
constexpr int kAccelerationSamples{64};

/// The largest f over [a, b]: samples, then golden section around the best sample.
template <typename F>
std::pair<double, double> maximise(const F& f, double a, double b) {
  double best_t = a, best = f(a);
  const double step = (b - a) / kAccelerationSamples;
  for (int i = 1; i <= kAccelerationSamples; ++i) {
    const double t = i == kAccelerationSamples ? b : a + step * i;
    const double v = f(t);
    if (v > best) {
      best = v;
      best_t = t;
    }
  }
  double lo = std::max(a, best_t - step), hi = std::min(b, best_t + step);
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  while (hi - lo > 1e-12) {
    if (f1 < f2) {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + r * (hi - lo);
      f2 = f(x2);
    } else {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - r * (hi - lo);
      f1 = f(x1);
    }
  }
  const double t = 0.5 * (lo + hi);
  const double v = f(t);
  return v > best ? std::pair{v, t} : std::pair{best, best_t};
}

/// The time in [a, b] where the law's position crosses s (it is increasing there).
double crossing(const MotionLaw& law, double s, double a, double b) {
  for (int it = 0; it < 200 && b - a > 1e-15; ++it) {
    const double m = 0.5 * (a + b);
    (law.at(m).position < s ? a : b) = m;
  }
  return 0.5 * (a + b);
}

}  // namespace

PathAcceleration path_acceleration(const PlanarPath& path, const MotionLaw& law) {
  // Smooth stretches: the law's pieces cut where s crosses a join of the path.
  std::vector<double> cuts = law.breakpoints();
  const std::vector<double>& starts = path.element_starts();
  const std::size_t pieces = cuts.size();
  for (std::size_t i = 0; i + 1 < pieces; ++i) {
    const double s0 = law.at(cuts[i]).position, s1 = law.at(cuts[i + 1]).position;
    for (std::size_t e = 1; e + 1 < starts.size(); ++e) {
      if (s0 < starts[e] && starts[e] < s1)
        cuts.push_back(crossing(law, starts[e], cuts[i], cuts[i + 1]));
    }
  }
  std::sort(cuts.begin(), cuts.end());
  PathAcceleration out;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    const std::size_t e = path.element_at(law.at(0.5 * (a + b)).position);
    const double kappa = std::abs(path.curvature(e));
    // Each stretch's own closed form: its ends evaluated inside it, not on the neighbour.
    auto state = [&](double t) {
      return law.at(std::clamp(t, a + 1e-13 * (b - a), b - 1e-13 * (b - a)));
    };
    const auto total = maximise(
        [&](double t) {
          const KinematicState k = state(t);
          return std::hypot(k.acceleration, kappa * k.velocity * k.velocity);
        },
        a, b);
    if (total.first > out.total) {
      out.total = total.first;
      out.time = total.second;
    }
    if (kappa > 0.0) {
      const auto normal = maximise(
          [&](double t) {
            const double v = state(t).velocity;
            return kappa * v * v;
          },
          a, b);
      out.normal = std::max(out.normal, normal.first);
    }
  }
  return out;
}

PathPrediction predict_on_path(const SloshingModel& model, const PlanarPath& path,
                               const MotionLaw& law, double rest_time) {
  PathPrediction p;
  const PlanarDrive drive(path, law);
  p.linear = planar_linear_peaks(model, drive, rest_time);
  p.nonlinear = planar_nonlinear_peaks(model, drive, rest_time);
  const PathAcceleration a = path_acceleration(path, law);
  p.a_total_peak = a.total;
  p.a_total_time = a.time;
  p.a_normal_peak = a.normal;
  const KinematicSummary k = law.summary();
  p.v_peak = k.v_peak;
  p.j_peak = k.j_peak;
  return p;
}

}  // namespace slosh
