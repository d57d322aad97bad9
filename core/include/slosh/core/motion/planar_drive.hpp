#pragma once
// What the planar sloshing models are driven by: the container's world-frame acceleration
// (horizontal and vertical) and its heading rate, on pieces where they are smooth. A drive is
// a law s(t) along a planar path (the pieces are the law's, cut where s crosses a join of the
// path, where the curvature jumps) or a sampled trajectory (the pieces are its sample intervals,
// where the splines' acceleration is linear). Time runs from 0 at the motion's start.

#include <cstddef>
#include <memory>
#include <vector>

#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/motion/planar_kinematics.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/motion/sampled_trajectory.hpp"

namespace slosh {

/// The excitation of the liquid at one instant.
struct PlanarExcitation {
  double ax{}, ay{};   ///< horizontal acceleration, world frame [m/s^2]
  double az{};         ///< vertical acceleration [m/s^2] (effective gravity g + az)
  double theta_dot{};  ///< the container's turning rate about its vertical axis [rad/s]
};

/// A smooth stretch of a drive, [t_begin, t_end] [s].
struct DrivePiece {
  double t_begin{}, t_end{};
  std::size_t source{};  ///< the law piece, or the trajectory's sample interval
  /// The path element the piece runs on (the one at its middle): its closed form is used over
  /// the whole piece, so a stage at the piece's start is not evaluated on the element before
  /// because s(t_begin) rounds below the join.
  std::size_t element{};
  /// Period of the law piece's harmonic term [s] (0: none): steps must resolve it too.
  double harmonic_omega{};
  /// The largest heading rate |kappa s'| over the piece [rad/s] (0 on a line and for a sampled
  /// trajectory): the world-frame acceleration turns at this rate on an arc, so steps must
  /// resolve it too (a fast whirl on a tiny radius turns it far faster than any mode).
  double heading_rate{};
};

class PlanarDrive {
 public:
  /// The law moves the container along the path: s(t) = law position, its stroke should equal
  /// the path length (a law beyond the ends extends the end elements).
  PlanarDrive(const PlanarPath& path, const MotionLaw& law);
  /// The sampled trajectory, its time shifted so that it starts at 0.
  explicit PlanarDrive(const SampledTrajectory& trajectory);

  /// The end of the motion [s] (then at rest).
  [[nodiscard]] double duration() const { return duration_; }
  [[nodiscard]] const std::vector<DrivePiece>& pieces() const { return pieces_; }
  /// True when the heading may change (the spin term needs integrating).
  [[nodiscard]] bool turns() const { return turns_; }
  /// True when the container may move vertically (the effective gravity changes).
  [[nodiscard]] bool vertical() const { return trajectory_ && trajectory_->has_vertical_motion(); }
  /// Excitation at time t on piece k (t within it; the models' hot path).
  [[nodiscard]] PlanarExcitation excitation(std::size_t k, double t) const;
  /// The container's turning rate theta' at time t on piece k [rad/s]: excitation(k, t)'s
  /// theta_dot without the accelerations (the liquid's spin needs it alone).
  [[nodiscard]] double turning_rate(std::size_t k, double t) const;
  /// Pose and derivatives at any t (at rest before 0 and after the duration).
  [[nodiscard]] PlanarKinematics kinematics(double t) const;

 private:
  std::shared_ptr<const PlanarPath> path_;
  std::shared_ptr<const MotionLaw> law_;
  std::shared_ptr<const SampledTrajectory> trajectory_;
  std::vector<DrivePiece> pieces_;
  double duration_{};
  bool turns_{};
};

}  // namespace slosh
