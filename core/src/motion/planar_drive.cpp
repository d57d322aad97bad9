#include "slosh/core/motion/planar_drive.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace slosh {

namespace {

/// The first time in [a, b] where the law's position reaches s (bisection to the round-off of
/// t: a stage a round-off beyond the join still evaluates the piece's element, extended).
double crossing_time(const MotionLaw& law, double s, double a, double b) {
  for (int it = 0; it < 200 && b - a > 1e-15 * std::max(1.0, b); ++it) {
    const double m = 0.5 * (a + b);
    if (law.at(m).position < s) {
      a = m;
    } else {
      b = m;
    }
  }
  return b;
}

/// The roots of c0 + c1 t + c2 t^2 in (lo, hi), ascending.
std::vector<double> quadratic_roots(double c0, double c1, double c2, double lo, double hi) {
  std::vector<double> r;
  if (c2 == 0.0) {
    if (c1 != 0.0) r.push_back(-c0 / c1);
  } else if (const double disc = c1 * c1 - 4.0 * c2 * c0; disc >= 0.0) {
    const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
    r.push_back(q / c2);
    if (q != 0.0) r.push_back(c0 / q);
  }
  std::erase_if(r, [&](double t) { return !(t > lo && t < hi); });
  std::sort(r.begin(), r.end());
  return r;
}

/// The largest |v(t)| over [lo, hi] of the quartic v = c0 + c1 t + ... + c4 t^4, exactly: at an
/// end or at a root of v'. Between the roots of v'' (a quadratic, in closed form) v' is
/// monotone, so each of its roots there is bracketed by a change of sign and located by
/// bisection to round-off.
double quartic_max_abs(const std::array<double, 5>& c, double lo, double hi) {
  auto v = [&c](double t) { return c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * c[4]))); };
  auto dv = [&c](double t) { return c[1] + t * (2.0 * c[2] + t * (3.0 * c[3] + t * 4.0 * c[4])); };
  std::vector<double> cuts{lo};
  for (double t : quadratic_roots(2.0 * c[2], 6.0 * c[3], 12.0 * c[4], lo, hi)) cuts.push_back(t);
  cuts.push_back(hi);
  double best = 0.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    double a = cuts[i], b = cuts[i + 1];
    best = std::max({best, std::abs(v(a)), std::abs(v(b))});
    const double fa = dv(a);
    if ((fa > 0.0) == (dv(b) > 0.0)) continue;
    for (int it = 0; it < 200; ++it) {
      const double m = 0.5 * (a + b);
      if (!(m > a && m < b)) break;
      ((dv(m) > 0.0) == (fa > 0.0) ? a : b) = m;
    }
    best = std::max({best, std::abs(v(a)), std::abs(v(b))});
  }
  return best;
}

/// The largest speed |s'| over local times [lo, hi] of a law piece: exact for a polynomial
/// piece; with a harmonic term, s' = (the polynomial part + hs / W) + (hc sin W t - hs cos W t) / W
/// and the bound is the first part's exact maximum plus the second's amplitude.
double max_speed(const LawPiece& p, double lo, double hi) {
  const std::array<double, 4>& a = p.poly;
  std::array<double, 5> c{p.velocity_begin, a[0], a[1] / 2.0, a[2] / 3.0, a[3] / 4.0};
  if (p.harmonic_omega == 0.0) return quartic_max_abs(c, lo, hi);
  const double w = std::abs(p.harmonic_omega);
  c[0] += p.harmonic_sin / p.harmonic_omega;
  return quartic_max_abs(c, lo, hi) + std::hypot(p.harmonic_cos, p.harmonic_sin) / w;
}

}  // namespace

PlanarDrive::PlanarDrive(const PlanarPath& path, const MotionLaw& law)
    : path_(std::make_shared<const PlanarPath>(path)),
      law_(std::make_shared<const MotionLaw>(law)),
      duration_(law.duration()),
      turns_(path.container_turns() &&
             std::any_of(path.elements().begin(), path.elements().end(),
                         [](const PathElement& e) { return e.kind == PathElement::Kind::kArc; })) {
  const std::vector<double>& starts = path.element_starts();
  const std::vector<LawPiece>& lp = law.pieces();
  for (std::size_t k = 0; k < lp.size(); ++k) {
    const LawPiece& p = lp[k];
    if (!(p.t_end > p.t_begin)) continue;
    // Joins crossed on this piece (where the curvature, so the normal acceleration, jumps).
    std::vector<double> cuts{p.t_begin};
    const double s0 = law.at(p.t_begin).position;
    const double s1 = p.at(p.duration()).position;
    for (std::size_t j = 1; j + 1 < starts.size(); ++j) {
      const double sj = starts[j];
      if ((s0 < sj && s1 > sj)) {
        const double tj = crossing_time(law, sj, p.t_begin, p.t_end);
        if (tj > cuts.back() && tj < p.t_end) cuts.push_back(tj);
      }
    }
    cuts.push_back(p.t_end);
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double middle = law.at(0.5 * (cuts[c] + cuts[c + 1])).position;
      const std::size_t element = path.element_at(middle);
      const double kappa = std::abs(path.curvature(element));
      const double rate =
          kappa == 0.0 ? 0.0 : kappa * max_speed(p, cuts[c] - p.t_begin, cuts[c + 1] - p.t_begin);
      pieces_.push_back({cuts[c], cuts[c + 1], k, element, p.harmonic_omega, rate});
    }
  }
}

PlanarDrive::PlanarDrive(const SampledTrajectory& trajectory)
    : trajectory_(std::make_shared<const SampledTrajectory>(trajectory)),
      duration_(trajectory.end_time() - trajectory.start_time()),
      turns_(trajectory.turns()) {
  const std::vector<double>& t = trajectory.samples().t;
  const double t0 = t.front();
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
    pieces_.push_back({t[i] - t0, t[i + 1] - t0, i, 0});
}

PlanarExcitation PlanarDrive::excitation(std::size_t k, double t) const {
  const DrivePiece& piece = pieces_[k];
  PlanarExcitation e;
  if (trajectory_) {
    const PlanarKinematics q = trajectory_->at(piece.source, t + trajectory_->start_time());
    e.ax = q.ax;
    e.ay = q.ay;
    e.az = q.az;
    e.theta_dot = q.theta_dot;
    return e;
  }
  const LawPiece& lp = law_->pieces()[piece.source];
  const KinematicState s = lp.at(t - lp.t_begin);
  path_->acceleration(piece.element, s.position, s.velocity, s.acceleration, e.ax, e.ay,
                      e.theta_dot);
  return e;
}

double PlanarDrive::turning_rate(std::size_t k, double t) const {
  if (trajectory_) return excitation(k, t).theta_dot;
  const DrivePiece& piece = pieces_[k];
  if (!path_->container_turns()) return 0.0;
  const LawPiece& lp = law_->pieces()[piece.source];
  return path_->curvature(piece.element) * lp.at(t - lp.t_begin).velocity;
}

PlanarKinematics PlanarDrive::kinematics(double t) const {
  if (trajectory_) return trajectory_->at(t + trajectory_->start_time());
  const KinematicState s = law_->at(t);
  if (t < 0.0 || t >= duration_) return path_->at(s.position, 0.0, 0.0, 0.0);
  return path_->at(s.position, s.velocity, s.acceleration, s.jerk);
}

}  // namespace slosh
