#pragma once
// Rest-to-rest motion laws as sampled-anywhere value types.
//
// Every law the product simulates is piecewise: on piece k, with tau = t - t_begin,
//   a(tau) = p0 + p1 tau + p2 tau^2 + p3 tau^3 + hc cos(W tau) + hs sin(W tau).
// Position, velocity and jerk follow in closed form, and so does the exact linear response.

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace slosh {

/// Kinematic state of a law at one instant.
struct KinematicState {
  double position{};      ///< [m]
  double velocity{};      ///< [m/s]
  double acceleration{};  ///< [m/s^2]
  double jerk{};          ///< [m/s^3]
};

/// One piece of a piecewise law.
struct LawPiece {
  double t_begin{};              ///< [s]
  double t_end{};                ///< [s]
  std::array<double, 4> poly{};  ///< acceleration polynomial in tau [m/s^2, m/s^3, ...]
  double harmonic_cos{};         ///< hc [m/s^2]
  double harmonic_sin{};         ///< hs [m/s^2]
  double harmonic_omega{};       ///< W [rad/s]; 0 when the piece has no harmonic term
  double velocity_begin{};       ///< v(t_begin) [m/s]
  double position_begin{};       ///< s(t_begin) [m]

  [[nodiscard]] double duration() const { return t_end - t_begin; }
  /// State at local time tau in [0, duration()].
  [[nodiscard]] KinematicState at(double tau) const;
  /// Acceleration at local time tau [m/s^2]: at(tau).acceleration alone, for the integrators'
  /// right-hand sides, which need nothing else.
  [[nodiscard]] double acceleration(double tau) const {
    double a = poly[0] + tau * (poly[1] + tau * (poly[2] + tau * poly[3]));
    if (harmonic_omega != 0.0) {
      a += harmonic_cos * std::cos(harmonic_omega * tau) +
           harmonic_sin * std::sin(harmonic_omega * tau);
    }
    return a;
  }
};

/// Peak kinematic figures of a law.
struct KinematicSummary {
  double a_peak_positive{};  ///< max a(t) [m/s^2]
  double a_peak_negative{};  ///< max -a(t) [m/s^2]
  double v_peak{};           ///< max |v(t)| [m/s]
  double j_peak{};           ///< max |j(t)| [m/s^3]
};

/// A rest-to-rest law over [0, duration()]; at rest before 0 and at the stroke after.
class MotionLaw {
 public:
  MotionLaw() = default;
  /// Builds a law from pieces given only their acceleration terms; the velocity and position at
  /// each piece start are integrated exactly from zero.
  MotionLaw(std::string name, std::vector<LawPiece> pieces);

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::vector<LawPiece>& pieces() const { return pieces_; }
  [[nodiscard]] double duration() const { return pieces_.empty() ? 0.0 : pieces_.back().t_end; }
  /// Position reached at the end [m].
  [[nodiscard]] double stroke() const;
  /// Times where the law changes expression: 0, every piece end.
  [[nodiscard]] std::vector<double> breakpoints() const;
  /// State at any t, right-continuous (t < 0: rest at 0; t >= duration: rest at the stroke; at a
  /// piece boundary, including 0, the piece that starts there).
  [[nodiscard]] KinematicState at(double t) const;
  /// Peaks of acceleration, velocity and jerk (exact per piece for polynomial pieces, sampled
  /// densely with local refinement for harmonic pieces).
  [[nodiscard]] KinematicSummary summary() const;
  /// Returns the same law with every acceleration multiplied by `factor`.
  [[nodiscard]] MotionLaw scaled(double factor) const;

 private:
  std::string name_;
  std::vector<LawPiece> pieces_;
};

/// Quintic polynomial s [10u^3 - 15u^4 + 6u^5], u = t/T.
[[nodiscard]] MotionLaw make_poly5_law(double stroke, double motion_time);
/// Cycloidal law: a = 2 pi s / T^2 sin(2 pi t / T).
[[nodiscard]] MotionLaw make_cycloidal_law(double stroke, double motion_time);
/// Modified trapezoid: sinusoidal blends, 1/8 splits (C_a = 4.888).
[[nodiscard]] MotionLaw make_modified_trapezoid_law(double stroke, double motion_time);

/// The law whose acceleration is linear between the knots (t[k], a[k]) (first-order hold):
/// piece k spans [t[k], t[k+1]] with a(t[k]) = a[k] and slope (a[k+1] - a[k]) / (t[k+1] - t[k]).
/// `t` increasing [s], `a` [m/s^2], the same size (at least 2).
[[nodiscard]] MotionLaw piecewise_linear_law(std::string name, const std::vector<double>& t,
                                             const std::vector<double>& a);

}  // namespace slosh
