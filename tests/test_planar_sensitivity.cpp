// The planar sensitivity integrator (what time_domain optimises along a path): its gradients on
// seeded random arcs and paths against central differences of the same discrete response.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "response/planar_sensitivity.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/motion/planar_path.hpp"

namespace slosh {
namespace {

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

}  // namespace
}  // namespace slosh
