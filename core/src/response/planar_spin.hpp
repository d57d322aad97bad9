#pragma once
// The liquid's spin under a turning container, and the polynomial fits the planar models share
// (internal to the core; planar_response.hpp states the spin model).
//
// The spin depends on the container's turning rate alone, not on the wave, so it is integrated
// once per drive, ahead of the wave: on sub-steps of every drive piece (at most a quarter of the
// first mode's period and of a law piece's harmonic, an eighth of a turn of the heading, and
// max_step) the turning rate is
// interpolated by a degree-7 polynomial at Chebyshev nodes and the spin's equation
// w_l' = sqrt(nu Omega) / h (theta' - w_l) is stepped by DOP853, whose dense output gives w_l on
// the sub-step. In the rest window (theta' = 0) the equation has a closed form, interpolated on
// the sub-steps the same way instead of stepped. A wave integrator reads it over its own steps
// (which never cross a drive piece, where the spin is smooth) by the same interpolation.

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/response/planar_response.hpp"

namespace slosh::detail {

inline constexpr std::size_t kFitTerms{8};
using FitPoly = std::array<double, kFitTerms>;

/// Sub-steps per period of the first mode and of a law piece's harmonic [-]: a degree-7
/// interpolant of content at W rad/s over H errs by ~ (W H / 2)^8 / (2^7 8!), below 1e-8 of
/// the forcing at the first mode's frequency (and far below for the slower content of paths).
inline constexpr double kFitStepsPerPeriod{4.0};
/// Sub-steps per turn of the heading on an arc (DrivePiece::heading_rate) of the planar linear
/// model's exact solution [-]: the world-frame acceleration turns with the heading, and at
/// W H = pi / 4 its interpolant errs by ~1e-10 of the forcing (a whirl's peaks within ~5e-9 of a
/// fine integration; 4 per turn left 3e-7).
inline constexpr double kFitStepsPerTurn{8.0};

/// Chebyshev nodes on [0, 1] and the inverse of their monomial Vandermonde matrix: the
/// interpolating polynomial's coefficients in u are inverse * values.
struct ChebyshevFit {
  std::array<double, kFitTerms> node{};
  std::array<std::array<double, kFitTerms>, kFitTerms> inverse{};
  ChebyshevFit();
  [[nodiscard]] FitPoly fit(const FitPoly& values) const {
    FitPoly c{};
    for (std::size_t r = 0; r < kFitTerms; ++r) {
      double s = 0.0;
      for (std::size_t k = 0; k < kFitTerms; ++k) s += inverse[r][k] * values[k];
      c[r] = s;
    }
    return c;
  }
};
const ChebyshevFit& chebyshev();

inline double horner(const FitPoly& c, double u) {
  double r = c[kFitTerms - 1];
  for (std::size_t k = kFitTerms - 1; k > 0; --k) r = r * u + c[k - 1];
  return r;
}

/// The longest fit sub-step of a model [s].
double fit_step(const SloshingModel& model, const PlanarOptions& options);
/// Sub-steps of drive piece p of length L (the rest window: no harmonic, no heading rate): at
/// most h_fit, kFitStepsPerPeriod per period of its harmonic and kFitStepsPerTurn per turn of
/// its heading. The spin and the linear model's exact solution share them.
std::size_t fit_steps(double L, double h_fit, const DrivePiece& p);

/// The liquid's spin rate over the drive and the rest window, piecewise polynomial.
class SpinTrack {
 public:
  struct Piece {
    double t0{}, H{};
    FitPoly w{};  ///< w_l(t0 + u H) [rad/s], u in [0, 1]
  };
  /// Empty: the spin is not modelled or the container does not turn.
  SpinTrack() = default;
  SpinTrack(const PlanarDrive& drive, double rest_time, const SloshingModel& model,
            const PlanarOptions& options);
  [[nodiscard]] bool empty() const { return pieces_.empty(); }
  [[nodiscard]] const std::vector<Piece>& pieces() const { return pieces_; }
  /// w_l(t) [rad/s] (0 before the start).
  [[nodiscard]] double at(double t) const;
  /// w_l over [t0, t0 + h] as a polynomial in theta = (t - t0) / h (the interval inside one
  /// drive piece or the rest window).
  [[nodiscard]] FitPoly over(double t0, double h) const;

 private:
  std::vector<Piece> pieces_;
};

}  // namespace slosh::detail
