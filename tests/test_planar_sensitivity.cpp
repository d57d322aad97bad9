// The planar sensitivity integrator (what time_domain optimises along a path): its gradients on
// seeded random arcs and paths against central differences of the same discrete response.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

#include "response/planar_sensitivity.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/motion/planar_path.hpp"

namespace slosh {
namespace test_planar_sensitivity {

using detail::D8;
using detail::DualPair;

/// The planar model at a_z = 0 (docs/models.md): M q'' = b, b = -(C^2 |v|^2 q + w^2 (1 + alpha
/// |q|^2) q + 2 zeta w (v + C^2 (q . v) q) + a / R), M = I + C^2 q q^T, so q'' = b - lam q with
/// lam = C^2 (q . b) / (1 + C^2 |q|^2); written once more here in dual arithmetic, which
/// differentiates it by the chain rule, operation by operation.
DualPair dual_formula(const detail::PlanarTangentRhs& p, const DualPair& x, const DualPair& v,
                      const std::array<D8, 2>& a) {
  const D8& qx = x.c[0];
  const D8& qy = x.c[1];
  const D8& vx = v.c[0];
  const D8& vy = v.c[1];
  const D8 r2 = qx * qx + qy * qy;
  const D8 v2 = vx * vx + vy * vy;
  const D8 qv = qx * vx + qy * vy;
  const D8 stiff = p.w2 * (1.0 + p.alpha * r2);
  const D8 damp = p.c2 * qv;
  const D8 bx =
      -(p.c2 * (v2 * qx) + stiff * qx + p.two_zw * (vx + qx * damp) + p.inv_radius * a[0]);
  const D8 by =
      -(p.c2 * (v2 * qy) + stiff * qy + p.two_zw * (vy + qy * damp) + p.inv_radius * a[1]);
  const D8 lam = p.c2 * (qx * bx + qy * by) / (1.0 + p.c2 * r2);
  DualPair out;
  out.c[0] = bx - lam * qx;
  out.c[1] = by - lam * qy;
  return out;
}

// Seeded random states (up to large angles, where the nonlinear terms dominate), accelerations
// and derivative lanes: the values agree bit for bit, the derivative lanes to rounding.
TEST(PlanarSensitivity, TangentRightHandSideMatchesDualNumbers) {
  std::mt19937 rng(5150);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    const detail::PlanarTangentRhs p{std::pow(10.0, 2.0 * u(rng) + 1.0), 0.1 * (1.0 + u(rng)),
                                     std::pow(10.0, 2.0 * u(rng) + 2.0),
                                     std::pow(10.0, 2.0 * u(rng) + 1.0), 2.0 + u(rng)};
    const double scale = 0.5 / std::sqrt(p.c2);  // |q| up to about a tilt of 30 degrees
    DualPair x, v;
    std::array<D8, 2> a;
    for (D8* d : {&x.c[0], &x.c[1], &v.c[0], &v.c[1], &a[0], &a[1]}) {
      for (std::size_t i = 0; i < 8; ++i) d->x[i] = u(rng);
    }
    for (D8* d : {&x.c[0], &x.c[1]}) d->x[0] *= scale;
    for (D8* d : {&v.c[0], &v.c[1]}) d->x[0] *= 10.0 * scale;
    for (D8* d : {&a[0], &a[1]}) d->x[0] *= 5.0;
    const DualPair got = p(x, v, a);
    const DualPair want = dual_formula(p, x, v, a);
    for (std::size_t c = 0; c < 2; ++c) {
      EXPECT_EQ(got.c[c].x[0], want.c[c].x[0]) << trial;
      double size = 0.0;
      for (std::size_t i = 1; i < 8; ++i) size = std::max(size, std::abs(want.c[c].x[i]));
      for (std::size_t i = 1; i < 8; ++i) {
        EXPECT_NEAR(got.c[c].x[i], want.c[c].x[i], 1e-13 * size) << trial << " lane " << i;
      }
    }
  }
}

// Seeded random arcs (either container orientation) and line-arc-line paths, perturbed laws: the
// wave heights' gradients are the derivatives of the discrete response (central differences with
// the step counts frozen), during the motion and the rest window.
TEST(PlanarSensitivity, GradientsOnSeededRandomPathsMatchCentralDifferences) {
  std::mt19937 rng(271828);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    const bool track = trial % 2 == 1;
    const PlanarPath path =
        track ? PlanarPath({PathElement::line(0.05 + 0.25 * u(rng)),
                            PathElement::arc(0.1 + 0.5 * u(rng), 0.5 + 2.0 * u(rng)),
                            PathElement::line(0.05 + 0.25 * u(rng))},
                           u(rng), u(rng) < 0.5)
              : PlanarPath::arc(0.1 + 0.8 * u(rng), 0.5 + 3.5 * u(rng), u(rng) < 0.5);
    Format f = thesis_format();
    f.stroke = path.length();
    f.motion_time = 0.9 + 0.8 * u(rng);
    const SloshingModel m = make_sloshing_model(f, {});
    Durations d = uniform_durations(f.motion_time);
    for (double& x : d) x *= 0.75 + 0.5 * u(rng);
    detail::PlanarSensitivity sens(m, path, 1.0, 12.0);
    sens.freeze_steps(d.data());
    sens.compute(d.data());
    std::vector<double> times;
    for (int i = 0; i < 8; ++i) times.push_back((0.05 + 0.9 * u(rng)) * (sens.motion_time() + 1.0));
    std::vector<double> values;
    std::vector<std::array<double, kSegments>> gradients;
    sens.eta_at(times, values, gradients);
    const double h = 1e-6;
    for (std::size_t i = 0; i < kSegments; ++i) {
      Durations up = d, down = d;
      up[i] += h;
      down[i] -= h;
      std::vector<double> v_up, v_down;
      std::vector<std::array<double, kSegments>> unused;
      sens.compute(up.data());
      sens.eta_at(times, v_up, unused);
      sens.compute(down.data());
      sens.eta_at(times, v_down, unused);
      for (std::size_t k = 0; k < times.size(); ++k) {
        const double fd = (v_up[k] - v_down[k]) / (2.0 * h);
        EXPECT_NEAR(gradients[k][i], fd, 1e-5 * std::abs(fd) + 1e-9)
            << "trial " << trial << " d" << i << " t " << times[k];
      }
    }
  }
}

// A following row of time_domain along a path: peak_time's maximum over a span around each window
// peak is that peak (found there by the roots of the step polynomial's slope, here by bisection
// on its sign), and the row's value K |q(peak_time)| as a function of the durations has the
// gradient eta_at gives at that time (the envelope theorem): against central differences of the
// maximum itself, re-located at every perturbed point.
TEST(PlanarSensitivity, FollowedPeaksAreTheWindowPeaksWithTheEnvelopeGradient) {
  std::mt19937 rng(314159);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    const PlanarPath path = PlanarPath::arc(0.15 + 0.6 * u(rng), 0.8 + 2.0 * u(rng), u(rng) < 0.5);
    Format f = thesis_format();
    f.stroke = path.length();
    f.motion_time = 0.9 + 0.7 * u(rng);
    const SloshingModel m = make_sloshing_model(f, {});
    const double span = 2.0 * std::numbers::pi / m.omega1() / 16.0;
    Durations d = uniform_durations(f.motion_time);
    for (double& x : d) x *= 0.8 + 0.4 * u(rng);
    const double T = std::accumulate(d.begin(), d.end(), 0.0);
    detail::PlanarSensitivity sens(m, path, 1.0, 12.0);
    sens.freeze_steps(d.data());
    sens.compute(d.data());
    const std::vector<detail::PlanarWindowPeak> peaks = sens.window_peaks(0.0, T, 4.0 * span);
    ASSERT_GE(peaks.size(), 3U);
    // Interior peaks of the motion (a window's largest value can sit on its edge, not a maximum).
    std::vector<double> at;
    for (const detail::PlanarWindowPeak& p : peaks) {
      if (p.time < span || p.time > T - span) continue;
      const double t = sens.peak_time(p.time - 0.7 * span, p.time + 0.6 * span);
      std::vector<double> v;
      std::vector<std::array<double, kSegments>> g;
      sens.eta_at({t}, v, g);
      if (std::abs(t - p.time) < 1e-6) {
        EXPECT_NEAR(v[0], p.value, 1e-12 * p.value) << "trial " << trial << " t " << p.time;
        at.push_back(p.time);
      } else {
        // The window's largest value lay on its edge: the span's maximum is at least as high.
        EXPECT_GE(v[0], p.value * (1.0 - 1e-12)) << "trial " << trial << " t " << p.time;
      }
    }
    ASSERT_FALSE(at.empty());
    auto followed = [&](const Durations& x, std::vector<std::array<double, kSegments>>* grad) {
      sens.compute(x.data());
      std::vector<double> times;
      for (double t : at) times.push_back(sens.peak_time(t - 0.7 * span, t + 0.6 * span));
      std::vector<double> v;
      std::vector<std::array<double, kSegments>> g;
      sens.eta_at(times, v, g);
      if (grad != nullptr) *grad = g;
      return v;
    };
    std::vector<std::array<double, kSegments>> gradients;
    (void)followed(d, &gradients);
    const double h = 1e-6;
    for (std::size_t i = 0; i < kSegments; ++i) {
      Durations up = d, down = d;
      up[i] += h;
      down[i] -= h;
      const std::vector<double> v_up = followed(up, nullptr);
      const std::vector<double> v_down = followed(down, nullptr);
      for (std::size_t k = 0; k < at.size(); ++k) {
        const double fd = (v_up[k] - v_down[k]) / (2.0 * h);
        EXPECT_NEAR(gradients[k][i], fd, 1e-5 * std::abs(fd) + 1e-9)
            << "trial " << trial << " d" << i << " peak " << at[k];
      }
    }
  }
}

}  // namespace test_planar_sensitivity
}  // namespace slosh
