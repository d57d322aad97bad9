#pragma once
// Planar paths of straight lines and circular arcs joined with a common tangent (SPEC §14): a
// rotary table's arc, a curved track, a robot's planar path. A law s(t) moves the container
// along the path; the world pose and its derivatives follow in closed form:
//   velocity     = s' T
//   acceleration = s'' T + kappa s'^2 N
//   jerk         = (s''' - kappa^2 s'^3) T + 3 kappa s' s'' N
// with T = (cos psi, sin psi) the tangent, N = (-sin psi, cos psi) the left normal, psi the
// tangent direction and kappa the signed curvature (1 / radius, positive turning left).

#include <cstddef>
#include <optional>
#include <vector>

#include "slosh/core/motion/planar_kinematics.hpp"

namespace slosh {

/// One element of a path.
struct PathElement {
  enum class Kind : unsigned char { kLine, kArc };
  Kind kind{Kind::kLine};
  double length{};  ///< line: its length [m], > 0
  double radius{};  ///< arc: its radius [m], > 0
  double angle{};   ///< arc: the angle turned [rad], signed (left positive), non-zero
  /// The tangent direction the element starts with [rad, world frame], when the caller states
  /// it: it must equal the direction the path arrives with (common tangent), else the path is
  /// refused. Unset: the element continues the path's tangent.
  std::optional<double> start_heading;

  [[nodiscard]] static PathElement line(double length,
                                        std::optional<double> start_heading = std::nullopt) {
    return {Kind::kLine, length, 0.0, 0.0, start_heading};
  }
  [[nodiscard]] static PathElement arc(double radius, double angle,
                                       std::optional<double> start_heading = std::nullopt) {
    return {Kind::kArc, 0.0, radius, angle, start_heading};
  }
  /// Arc length [m].
  [[nodiscard]] double arc_length() const;
};

/// A validated planar path from the origin.
class PlanarPath {
 public:
  /// Throws InvalidMotion naming the element ("segments[i]") for a line of length <= 0, an arc
  /// of radius <= 0 or angle 0, a non-finite value, or a stated start heading that differs from
  /// the arriving tangent by more than 1e-6 rad; "segments" when there is none.
  /// `start_heading`: the tangent direction at the start [rad]. `container_turns`: the container
  /// turns with the path's tangent (a rotary table, a carousel: its heading theta = psi - psi_0)
  /// or keeps its orientation (a carriage on a curved track: theta = 0).
  PlanarPath(std::vector<PathElement> elements, double start_heading, bool container_turns);

  /// The straight move of `length` [m] in `direction` [rad].
  [[nodiscard]] static PlanarPath line(double length, double direction = 0.0);
  /// The arc of a table (or track) of `radius` [m] turning `angle` [rad] (signed, left
  /// positive), starting at the origin heading `start_heading`.
  [[nodiscard]] static PlanarPath arc(double radius, double angle, bool container_turns,
                                      double start_heading = 0.0);

  [[nodiscard]] double length() const { return starts_.back(); }
  [[nodiscard]] bool container_turns() const { return container_turns_; }
  /// The tangent direction at the start, as constructed [rad].
  [[nodiscard]] double start_heading() const { return start_heading_; }
  [[nodiscard]] const std::vector<PathElement>& elements() const { return elements_; }
  /// Arc length where each element starts, then the total length (size elements + 1) [m].
  [[nodiscard]] const std::vector<double>& element_starts() const { return starts_; }
  /// Signed curvature of element i [1/m] (0 on lines).
  [[nodiscard]] double curvature(std::size_t i) const { return curvature_[i]; }
  /// The element holding arc length s (the first below 0, the last beyond the length; at a
  /// join, the element that starts there).
  [[nodiscard]] std::size_t element_at(double s) const;
  /// World pose and derivatives at arc length s moving with s' = s_dot, s'' = s_ddot,
  /// s''' = s_dddot (closed forms above; z = 0). Beyond the ends the end elements extend.
  [[nodiscard]] PlanarKinematics at(double s, double s_dot, double s_ddot, double s_dddot) const;
  /// at() on element i (the caller knows it).
  [[nodiscard]] PlanarKinematics at(std::size_t i, double s, double s_dot, double s_ddot,
                                    double s_dddot) const;
  /// Horizontal acceleration and heading rate only (the models' hot path).
  void acceleration(std::size_t i, double s, double s_dot, double s_ddot, double& ax, double& ay,
                    double& theta_dot) const;

 private:
  std::vector<PathElement> elements_;
  std::vector<double> starts_;     // arc length at each element start, then the total
  std::vector<double> heading_;    // tangent direction at each element start [rad]
  std::vector<double> curvature_;  // signed [1/m]
  std::vector<double> x0_, y0_;    // element start points [m]
  double start_heading_{};
  bool container_turns_{};
};

}  // namespace slosh
