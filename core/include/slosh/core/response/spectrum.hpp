#pragma once
// Fourier transform of the acceleration, X_a(omega) = int_0^T a(t) exp(-j omega t) dt (SPEC §4).

#include <array>
#include <complex>
#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"

namespace slosh {

/// Closed-form X_a(omega) of the 7-segment law with durations d and stroke s.
///
/// For omega T >= 8 it uses the jerk-jump form obtained by integrating by parts twice
/// (a(0) = a(T) = 0):  X = -(1/omega^2) sum_k (J_{k+1} - J_k) exp(-j omega t_k),
/// for omega T < 8 the per-segment form of SPEC §4 written with the well-conditioned
/// phi1(z) = (1 - e^{-z})/z and phi2(z) = (1 - (1 + z) e^{-z})/z^2 (series for small |z|).
/// Instantiated for double and long double (the latter for high-precision checks).
template <typename T>
[[nodiscard]] std::complex<T> seven_segment_spectrum(const std::array<T, kSegments>& d, T stroke,
                                                     T omega);

/// |X_a| of the 7-segment law at omega0 + k step, k = 0..count-1, written to `out` (resized): the
/// band checks' grids. Above omega T = 0.5 (every point of the grid) each exp(-j omega t_i)
/// advances by one complex product per point in the jerk-jump form, recomputed every 32 points
/// against drift (the error stays below 1e-13 of the jerk-jump terms' scale sum |w_i| / omega^2,
/// i.e. below 1e-10 of |X| down to omega T = 0.5: far under any tolerance the checks apply, whose
/// maxima are refined on seven_segment_spectrum anyway); otherwise every point is
/// seven_segment_spectrum.
void seven_segment_magnitudes(const Durations& d, double stroke, double omega0, double step,
                              std::size_t count, std::vector<double>* out);

/// X_a(omega) of a built law.
[[nodiscard]] std::complex<double> acceleration_spectrum(const SevenSegmentLaw& law, double omega);

/// |X_a(omega)|^2 and its exact gradient with respect to the 7 durations (A and B move with the
/// durations so that the stroke and rest-to-rest stay satisfied). Forward-mode differentiation of
/// A, B and the jerks, analytic differentiation of the exponentials. Relative accuracy of the
/// gradient is about 50 eps / (omega T)^4, i.e. full precision for omega T >= 1, where every
/// spectral objective of the product is evaluated.
struct SpectrumPowerGradient {
  double power{};                          ///< |X_a(omega)|^2 [(m/s)^2]
  std::array<double, kSegments> gradient;  ///< d|X|^2 / d dT_i [(m/s)^2 / s]
  std::complex<double> X;                  ///< X_a(omega) [m/s]
};
[[nodiscard]] SpectrumPowerGradient spectrum_power_gradient(const Durations& d, double stroke,
                                                            double omega);

/// spectrum_power_gradient at several frequencies, sharing A, B and their derivatives (the band
/// constraints of min_jerk_band). Writes one entry per frequency to `out`.
void spectrum_power_gradients(const Durations& d, double stroke, const std::vector<double>& omegas,
                              std::vector<SpectrumPowerGradient>* out);

/// X_a(omega) and its exact derivatives dX/d dT_i (same method and accuracy as
/// spectrum_power_gradient; the notch strategy constrains Re X and Im X separately).
struct SpectrumGradient {
  std::complex<double> X;                            ///< X_a(omega) [m/s]
  std::array<std::complex<double>, kSegments> dX{};  ///< dX / d dT_i [m/s^2]
};
[[nodiscard]] SpectrumGradient spectrum_gradient(const Durations& d, double stroke, double omega);

/// X_a(omega) of any piecewise law in closed form, piece by piece: int_0^L tau^n e^{-j w tau} for
/// the polynomial terms (series below one radian per piece, recursion above) and the same for the
/// harmonic terms shifted by +-W.
[[nodiscard]] std::complex<double> acceleration_spectrum(const MotionLaw& law, double omega);

/// FFT-normalised single-sided amplitude A_fft = (2/T)|X_a| (thesis eq. 4.50) [m/s^2].
[[nodiscard]] inline double fft_amplitude(std::complex<double> X, double motion_time) {
  return 2.0 / motion_time * std::abs(X);
}

}  // namespace slosh
