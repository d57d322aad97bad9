#pragma once
// The spectrum of any core law by quadrature, for checking the closed forms (shared by the
// planner, property and spectrum tests).

#include <algorithm>
#include <cmath>
#include <complex>

#include "slosh/core/law/motion_law.hpp"
#include "support/reference_integrators.hpp"

namespace slosh::test {

/// Gauss-Legendre X_a(omega) of a law from its sampled acceleration, on the law's breakpoints
/// with the rate of its fastest harmonic piece.
inline std::complex<double> quadrature_of(const MotionLaw& law, double omega) {
  double rate = 0.0;
  for (const LawPiece& p : law.pieces()) rate = std::max(rate, std::abs(p.harmonic_omega));
  return gauss_legendre_spectrum([&](double t) { return law.at(t).acceleration; },
                                 law.breakpoints(), omega, rate);
}

}  // namespace slosh::test
