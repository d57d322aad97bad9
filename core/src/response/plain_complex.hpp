#pragma once
// Complex numbers with plain arithmetic for the response's sampling loops (internal to the core).
// std::complex's product checks for infinities and NaN on every call, which costs more than the
// product itself there; these values are finite by construction.

#include <cmath>

#include "sincos.hpp"

namespace slosh::detail {

struct Complex {
  double re{}, im{};
  [[nodiscard]] double real() const { return re; }
  [[nodiscard]] double imag() const { return im; }
};

inline Complex operator*(Complex a, Complex b) {
  return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
}

inline Complex operator*(double a, Complex b) {
  return {a * b.re, a * b.im};
}

/// exp(lambda tau).
inline Complex exp_of(Complex lambda, double tau) {
  const double e = std::exp(lambda.re * tau);
  const SinCos sc = fast_sincos(lambda.im * tau);
  return {e * sc.cos, e * sc.sin};
}

/// exp((-sigma + i wd) tau): a damped mode's decay and rotation over tau.
inline Complex decay_rotation(double sigma, double wd, double tau) {
  return exp_of({-sigma, wd}, tau);
}

}  // namespace slosh::detail
