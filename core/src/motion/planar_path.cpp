#include "slosh/core/motion/planar_path.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "response/sincos.hpp"
#include "slosh/core/motion/invalid_motion.hpp"
#include "text.hpp"

namespace slosh {

namespace {

/// Largest difference between a stated start heading and the arriving tangent [rad]: 1e-6 rad
/// (5.7e-5 deg) admits headings and angles written to 6 decimals of a degree (a CAD or PLC
/// export), far below any physical kink (the jump of the tangent is what shakes the liquid).
constexpr double kTangentTolerance{1e-6};

std::string element_name(std::size_t i) {
  return "segments[" + std::to_string(i) + "]";
}

std::string degrees(double rad) {
  std::ostringstream out;
  out.precision(10);
  out << rad * 180.0 / std::numbers::pi << " deg";
  return out.str();
}

/// a - b wrapped to (-pi, pi].
double angle_difference(double a, double b) {
  double d = std::remainder(a - b, 2.0 * std::numbers::pi);
  if (d <= -std::numbers::pi) d += 2.0 * std::numbers::pi;
  return d;
}

void check_element(const PathElement& e, std::size_t i) {
  const std::string name = element_name(i);
  if (e.kind == PathElement::Kind::kLine) {
    if (!(std::isfinite(e.length) && e.length > 0.0)) {
      throw InvalidMotion(name, name + ": a line's length " + detail::precise(e.length) +
                                    " m must be finite and > 0 m");
    }
  } else {
    if (!(std::isfinite(e.radius) && e.radius > 0.0)) {
      throw InvalidMotion(name, name + ": an arc's radius " + detail::precise(e.radius) +
                                    " m must be finite and > 0 m");
    }
    if (!std::isfinite(e.angle) || e.angle == 0.0) {
      throw InvalidMotion(
          name, name + ": an arc's angle " + degrees(e.angle) + " must be finite and non-zero");
    }
  }
  if (e.start_heading && !std::isfinite(*e.start_heading)) {
    throw InvalidMotion(
        name, name + ": the start heading " + degrees(*e.start_heading) + " must be finite");
  }
}

}  // namespace

double PathElement::arc_length() const {
  return kind == Kind::kLine ? length : radius * std::abs(angle);
}

PlanarPath::PlanarPath(std::vector<PathElement> elements, double start_heading,
                       bool container_turns)
    : elements_(std::move(elements)),
      start_heading_(start_heading),
      container_turns_(container_turns) {
  if (elements_.empty()) {
    throw InvalidMotion("segments", "segments: a path needs at least one line or arc");
  }
  if (!std::isfinite(start_heading)) {
    throw InvalidMotion("start_heading",
                        "start_heading: " + degrees(start_heading) + " must be finite");
  }
  double s = 0.0, psi = start_heading, x = 0.0, y = 0.0;
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    const PathElement& e = elements_[i];
    check_element(e, i);
    if (e.start_heading) {
      const double d = angle_difference(*e.start_heading, psi);
      if (std::abs(d) > kTangentTolerance) {
        const std::string name = element_name(i);
        // The first segment joins nothing: its heading must be the path's start heading.
        throw InvalidMotion(
            name, name + " starts at heading " + degrees(*e.start_heading) +
                      (i == 0 ? " but the path starts at heading " + degrees(psi) +
                                    " (start_heading_deg): give the first segment that heading"
                              : " but the path arrives at heading " + degrees(psi) +
                                    ": lines and arcs must join with a common tangent (within "
                                    "1e-6 rad)"));
      }
    }
    const double kappa =
        e.kind == PathElement::Kind::kLine ? 0.0 : std::copysign(1.0 / e.radius, e.angle);
    starts_.push_back(s);
    heading_.push_back(psi);
    curvature_.push_back(kappa);
    x0_.push_back(x);
    y0_.push_back(y);
    const double L = e.arc_length();
    if (e.kind == PathElement::Kind::kLine) {
      x += L * std::cos(psi);
      y += L * std::sin(psi);
    } else {
      const double psi1 = psi + e.angle;
      x += (std::sin(psi1) - std::sin(psi)) / kappa;
      y -= (std::cos(psi1) - std::cos(psi)) / kappa;
      psi = psi1;
    }
    s += L;
  }
  starts_.push_back(s);
}

PlanarPath PlanarPath::line(double length, double direction) {
  return PlanarPath({PathElement::line(length)}, direction, false);
}

PlanarPath PlanarPath::arc(double radius, double angle, bool container_turns,
                           double start_heading) {
  return PlanarPath({PathElement::arc(radius, angle)}, start_heading, container_turns);
}

std::size_t PlanarPath::element_at(double s) const {
  // starts_[0] = 0; the last entry is the total length and starts nothing.
  const auto it = std::upper_bound(starts_.begin() + 1, starts_.end() - 1, s);
  return static_cast<std::size_t>(it - starts_.begin()) - 1;
}

PlanarKinematics PlanarPath::at(double s, double s_dot, double s_ddot, double s_dddot) const {
  return at(element_at(s), s, s_dot, s_ddot, s_dddot);
}

PlanarKinematics PlanarPath::at(std::size_t i, double s, double s_dot, double s_ddot,
                                double s_dddot) const {
  const double u = s - starts_[i];
  const double kappa = curvature_[i];
  const double psi0 = heading_[i];
  const double psi = psi0 + kappa * u;
  const double c = std::cos(psi), sn = std::sin(psi);
  PlanarKinematics k;
  if (kappa == 0.0) {
    k.x = x0_[i] + u * c;
    k.y = y0_[i] + u * sn;
  } else {
    k.x = x0_[i] + (sn - std::sin(psi0)) / kappa;
    k.y = y0_[i] - (c - std::cos(psi0)) / kappa;
  }
  // Tangent and normal components, then the rotation by psi.
  const double at = s_ddot, an = kappa * s_dot * s_dot;
  const double jt = s_dddot - kappa * kappa * s_dot * s_dot * s_dot;
  const double jn = 3.0 * kappa * s_dot * s_ddot;
  k.vx = s_dot * c;
  k.vy = s_dot * sn;
  k.ax = at * c - an * sn;
  k.ay = at * sn + an * c;
  k.jx = jt * c - jn * sn;
  k.jy = jt * sn + jn * c;
  if (container_turns_) {
    k.theta = psi - start_heading_;
    k.theta_dot = kappa * s_dot;
    k.theta_ddot = kappa * s_ddot;
    k.theta_dddot = kappa * s_dddot;
  }
  return k;
}

void PlanarPath::acceleration(std::size_t i, double s, double s_dot, double s_ddot, double& ax,
                              double& ay, double& theta_dot) const {
  const double kappa = curvature_[i];
  const double psi = heading_[i] + kappa * (s - starts_[i]);
  const detail::SinCos sc = detail::fast_sincos(psi);  // the integrators call this per stage
  const double c = sc.cos, sn = sc.sin;
  const double an = kappa * s_dot * s_dot;
  ax = s_ddot * c - an * sn;
  ay = s_ddot * sn + an * c;
  theta_dot = container_turns_ ? kappa * s_dot : 0.0;
}

}  // namespace slosh
