#pragma once
// One oscillator x'' = rhs(x, x', a) from rest, stepped by DOP853 over the pieces of a motion law
// (and its rest window) on NonlinearResponse's grid: equal steps within a piece of at most h_max,
// harmonic pieces resolved with steps_per_period steps per period. Shared by the responses that
// integrate in dual numbers (calibration), so their grids stay the nonlinear response's.

#include <cstddef>
#include <vector>

#include "response/nonlinear_scheme.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/response/response.hpp"

namespace slosh::detail {

/// Calls on_step(t0, h, step) after each step (step holds the interpolants of that step);
/// `dense_rate` as dop853_step's.
template <typename S, typename Rhs, typename OnStep>
void integrate_law_pieces(const std::vector<LawPiece>& pieces, double h_max,
                          double steps_per_period, const Rhs& rhs, bool dense_rate,
                          OnStep&& on_step) {
  S x(0.0), v(0.0);
  DopStep<S> step;
  for (const LawPiece& piece : pieces) {
    const double L = piece.duration();
    if (!(L > 0.0)) continue;
    const auto n = step_count(L, piece_max_step(h_max, piece.harmonic_omega, steps_per_period), 1);
    const double h = L / static_cast<double>(n);
    S f0 = rhs(x, v, piece.acceleration(0.0));
    for (std::size_t i = 0; i < n; ++i) {
      const double tau = h * static_cast<double>(i);
      dop853_step(
          rhs, [&](std::size_t k) { return piece.acceleration(tau + kDopC[k] * h); }, x, v, f0,
          S(h), true, step, dense_rate);
      on_step(piece.t_begin + tau, h, step);
      x = step.x1;
      v = step.v1;
      f0 = step.f1;
    }
  }
}

}  // namespace slosh::detail
