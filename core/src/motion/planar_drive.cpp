#include "slosh/core/motion/planar_drive.hpp"

#include <algorithm>
#include <cmath>

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
      pieces_.push_back({cuts[c], cuts[c + 1], k, path.element_at(middle), p.harmonic_omega});
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
