// Spatial motions (SPEC §14): paths of lines and arcs against closed forms written here, their
// refusals word for word, sampled trajectories and the measured runs' pose CSV.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "slosh/core/motion/invalid_motion.hpp"
#include "slosh/core/motion/planar_drive.hpp"
#include "slosh/core/motion/planar_path.hpp"
#include "slosh/core/motion/sampled_trajectory.hpp"

namespace slosh {
namespace test_planar_motion {

constexpr double kPi = std::numbers::pi;

std::string refusal_of(const auto& build) {
  try {
    build();
  } catch (const InvalidMotion& e) {
    return e.member() + " | " + e.what();
  }
  return "accepted";
}

// A rotary table of radius rho turning left from heading 0: the container is at
// p(phi) = rho (sin phi, 1 - cos phi) with phi = s / rho; derivatives by the chain rule in phi.
TEST(PlanarPath, ArcPoseAndDerivativesMatchTheTableKinematics) {
  const double rho = 0.3, angle = kPi / 2;
  const PlanarPath path = PlanarPath::arc(rho, angle, true);
  EXPECT_NEAR(path.length(), rho * angle, 1e-15);
  for (double s : {0.0, 0.1, 0.37, 0.47}) {
    const double sd = 0.8, sdd = -2.5, sddd = 40.0;
    const double phi = s / rho, w = sd / rho, wd = sdd / rho, wdd = sddd / rho;
    const PlanarKinematics k = path.at(s, sd, sdd, sddd);
    const double c = std::cos(phi), sn = std::sin(phi);
    EXPECT_NEAR(k.x, rho * sn, 1e-15);
    EXPECT_NEAR(k.y, rho * (1.0 - c), 1e-15);
    EXPECT_NEAR(k.vx, rho * c * w, 1e-14);
    EXPECT_NEAR(k.vy, rho * sn * w, 1e-14);
    EXPECT_NEAR(k.ax, rho * (c * wd - sn * w * w), 1e-13);
    EXPECT_NEAR(k.ay, rho * (sn * wd + c * w * w), 1e-13);
    EXPECT_NEAR(k.jx, rho * (c * wdd - 3.0 * sn * w * wd - c * w * w * w), 1e-12);
    EXPECT_NEAR(k.jy, rho * (sn * wdd + 3.0 * c * w * wd - sn * w * w * w), 1e-12);
    EXPECT_NEAR(k.theta, phi, 1e-15);  // the container turns with the table
    EXPECT_NEAR(k.theta_dot, w, 1e-15);
    EXPECT_NEAR(k.theta_ddot, wd, 1e-14);
    EXPECT_NEAR(k.theta_dddot, wdd, 1e-13);
  }
  // A carriage on the same curve keeps its orientation.
  EXPECT_EQ(PlanarPath::arc(rho, angle, false).at(0.2, 1.0, 0.0, 0.0).theta_dot, 0.0);
}

// A line, a right-hand arc, a line: the pose is continuous across the joins and its
// derivatives are those of the pose (central differences of the closed-form position).
TEST(PlanarPath, JoinedPathIsSmoothAndItsDerivativesDifferentiateThePose) {
  const PlanarPath path(
      {PathElement::line(0.2), PathElement::arc(0.1, -kPi / 2), PathElement::line(0.15, -kPi / 2)},
      0.0, false);
  EXPECT_NEAR(path.length(), 0.35 + 0.1 * kPi / 2, 1e-15);
  // Ends: (0.2 + 0.1, -0.1) after the quarter turn to the right, then 0.15 down.
  const PlanarKinematics end = path.at(path.length(), 0.0, 0.0, 0.0);
  EXPECT_NEAR(end.x, 0.3, 1e-15);
  EXPECT_NEAR(end.y, -0.25, 1e-15);
  // s(t) = s0 + v t + a t^2 / 2 + j t^3 / 6 around t = 0, differentiated numerically.
  const double v = 0.7, a = 1.3, j = -9.0, h = 1e-4;
  for (double s0 : {0.1, 0.2 + 1e-3, 0.3, 0.45}) {
    auto pose = [&](double t) {
      return path.at(s0 + v * t + a * t * t / 2 + j * t * t * t / 6, 0.0, 0.0, 0.0);
    };
    const PlanarKinematics k = path.at(s0, v, a, j);
    const PlanarKinematics p2 = pose(2 * h), p1 = pose(h), p0 = pose(0), m1 = pose(-h),
                           m2 = pose(-2 * h);
    EXPECT_NEAR(k.vx, (p1.x - m1.x) / (2 * h), 1e-7) << s0;
    EXPECT_NEAR(k.ay, (p1.y - 2 * p0.y + m1.y) / (h * h), 1e-5) << s0;
    EXPECT_NEAR(k.ax, (p1.x - 2 * p0.x + m1.x) / (h * h), 1e-5) << s0;
    EXPECT_NEAR(k.jx, (p2.x - 2 * p1.x + 2 * m1.x - m2.x) / (2 * h * h * h), 1e-3) << s0;
    EXPECT_NEAR(k.jy, (p2.y - 2 * p1.y + 2 * m1.y - m2.y) / (2 * h * h * h), 1e-3) << s0;
  }
}

TEST(PlanarPath, RefusalsNameTheElement) {
  EXPECT_EQ(refusal_of([] {
              return PlanarPath({PathElement::line(0.2), PathElement::arc(0.1, kPi / 2, kPi / 3)},
                                0.0, false);
            }),
            "segments[1] | segments[1] starts at heading 60 deg but the path arrives at heading "
            "0 deg: lines and arcs must join with a common tangent (within 1e-6 rad)");
  EXPECT_EQ(refusal_of([] {
              return PlanarPath({PathElement::arc(0.1, kPi / 2), PathElement::line(0.2, 0.0)}, 0.0,
                                false);
            }),
            "segments[1] | segments[1] starts at heading 0 deg but the path arrives at heading "
            "90 deg: lines and arcs must join with a common tangent (within 1e-6 rad)");
  // The first segment joins nothing: it is told the path's start heading.
  EXPECT_EQ(refusal_of([] { return PlanarPath({PathElement::line(0.2, kPi / 6)}, 0.0, false); }),
            "segments[0] | segments[0] starts at heading 30 deg but the path starts at heading "
            "0 deg (start_heading_deg): give the first segment that heading");
  EXPECT_EQ(refusal_of([] { return PlanarPath::arc(0.0, 1.0, true); }),
            "segments[0] | segments[0]: an arc's radius 0 m must be finite and > 0 m");
  EXPECT_EQ(refusal_of([] { return PlanarPath::arc(0.3, 0.0, true); }),
            "segments[0] | segments[0]: an arc's angle 0 deg must be finite and non-zero");
  EXPECT_EQ(refusal_of([] { return PlanarPath::line(-1.0); }),
            "segments[0] | segments[0]: a line's length -1 m must be finite and > 0 m");
  EXPECT_EQ(refusal_of([] { return PlanarPath({}, 0.0, false); }),
            "segments | segments: a path needs at least one line or arc");
  // A stated heading equal to the arriving tangent (modulo a turn) is accepted.
  EXPECT_EQ(
      refusal_of([] {
        return PlanarPath({PathElement::arc(0.1, kPi), PathElement::line(0.2, -kPi)}, 0.0, false);
      }),
      "accepted");
}

TrajectorySamples sine_samples(std::size_t n, double dt) {
  TrajectorySamples s;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    s.t.push_back(t);
    s.x.push_back(std::sin(3.0 * t));
    s.y.push_back(0.5 * t * t);
  }
  return s;
}

TEST(SampledTrajectory, SplineAccelerationFollowsTheSampledMotion) {
  const SampledTrajectory tr(sine_samples(1001, 1e-3));
  for (double t : {0.2, 0.5003, 0.77}) {
    const PlanarKinematics k = tr.at(t);
    EXPECT_NEAR(k.x, std::sin(3.0 * t), 1e-9);
    EXPECT_NEAR(k.vx, 3.0 * std::cos(3.0 * t), 1e-5);
    EXPECT_NEAR(k.ax, -9.0 * std::sin(3.0 * t), 1e-4);
    EXPECT_NEAR(k.ay, 1.0, 1e-4);
  }
  EXPECT_FALSE(tr.turns());
  EXPECT_FALSE(tr.has_vertical_motion());
}

// The not-a-knot ends: a cubic sampled at uneven times is its own spline, to the ends (a
// natural spline's second derivative would be 0 at both), in every coordinate.
TEST(SampledTrajectory, ACubicIsItsOwnSplineUpToTheEnds) {
  TrajectorySamples s;
  const std::vector<double> t{0.0, 0.01, 0.025, 0.03, 0.047, 0.06, 0.08};
  auto x = [](double v) { return 2.0 + v * (0.5 + v * (3.0 - 40.0 * v)); };
  for (double v : t) {
    s.t.push_back(v);
    s.x.push_back(x(v));
    s.y.push_back(-x(v));
    s.z.push_back(0.5 * x(v));
    s.theta.push_back(0.1 * x(v));
  }
  const SampledTrajectory tr(s);
  for (double v : {0.0, 0.004, 0.028, 0.07, 0.08}) {
    const PlanarKinematics k = tr.at(v);
    const double a = 6.0 - 240.0 * v, j = -240.0;
    EXPECT_NEAR(k.x, x(v), 1e-12) << v;
    EXPECT_NEAR(k.ax, a, 1e-9) << v;
    EXPECT_NEAR(k.ay, -a, 1e-9) << v;
    EXPECT_NEAR(k.az, 0.5 * a, 1e-9) << v;
    EXPECT_NEAR(k.theta_ddot, 0.1 * a, 1e-9) << v;
    EXPECT_NEAR(k.jx, j, 1e-6) << v;
  }
}

TEST(SampledTrajectory, RefusalsSayWhatIsWrong) {
  EXPECT_EQ(refusal_of([] { return SampledTrajectory(sine_samples(3, 1e-3)); }),
            "t | t: a trajectory needs at least 4 samples, got 3");
  EXPECT_EQ(refusal_of([] {
              TrajectorySamples s = sine_samples(6, 1e-3);
              s.t[4] = s.t[3];
              return SampledTrajectory(s);
            }),
            "t[4] | t[4] = 0.003 s must be greater than t[3] = 0.003 s (times strictly "
            "increasing)");
  EXPECT_EQ(refusal_of([] {
              TrajectorySamples s = sine_samples(6, 1e-3);
              s.y[2] = std::nan("");
              return SampledTrajectory(s);
            }),
            "y[2] | y[2] = nan must be finite");
  EXPECT_EQ(refusal_of([] {
              TrajectorySamples s = sine_samples(6, 1e-3);
              s.theta = {0.0, 1.0};
              return SampledTrajectory(s);
            }),
            "theta | theta: 2 samples, but t has 6");
  // 20 samples per period of a 19.26 rad/s mode: 61.3 per second.
  const SampledTrajectory coarse(sine_samples(10, 0.02));
  EXPECT_EQ(refusal_of([&] { coarse.check_sampling(19.26); }),
            "t[1] | t[1]: samples 0 and 1 are 0.02 s apart; the first sloshing mode "
            "(3.065324204 Hz) needs at least 61.30648408 samples per second (a spacing of at "
            "most 0.01631148834 s)");
  EXPECT_EQ(refusal_of([&] { coarse.check_sampling(15.0); }), "accepted");
}

std::string run_file(const std::string& run) {
  return std::string(SLOSH_SOURCE_DIR) + "/tests/data/bologna-4d/" + run + ".trajectory.csv";
}

TEST(PoseCsv, ReadsAMeasuredRunWithItsTurnsUnwrapped) {
  std::ifstream in(run_file("LE_2D_0m_5s_900deg"));
  ASSERT_TRUE(in) << run_file("LE_2D_0m_5s_900deg");
  const SampledTrajectory tr(read_pose_csv(in, "LE_2D_0m_5s_900deg"));
  EXPECT_EQ(tr.size(), 3001u);
  EXPECT_NEAR(tr.end_time() - tr.start_time(), 6.0, 1e-9);
  // 900 degrees of rotation about the vertical axis, continuous through every half turn.
  EXPECT_NEAR(std::abs(tr.samples().theta.back() - tr.samples().theta.front()), 5.0 * kPi, 1e-6);
  tr.check_sampling(18.961);  // 500 Hz
  EXPECT_TRUE(tr.turns());
}

TEST(PoseCsv, RefusesTiltsAndBadRows) {
  auto read = [](const std::string& text) {
    std::istringstream in(text);
    return read_pose_csv(in, "run.csv");
  };
  const std::string header = "t_s,x_m,y_m,z_m,qx,qy,qz,qw\n";
  EXPECT_EQ(refusal_of([&] {
              return read(header + "0,0,0,0,0,0,0,1\n0.1,0,0,0,0.1,0,0,0.99498743710662\n");
            }),
            "line 3 | run.csv line 3: the orientation tilts the container (qx = 0.1, qy = 0); only "
            "rotations about the vertical axis are modelled (allowed |qx|, |qy| <= 0.001, a tilt "
            "of at most 0.16 deg)");
  EXPECT_EQ(refusal_of([&] { return read(header + "0,0,0,0,0,0,0,2\n"); }),
            "line 2 | run.csv line 2: the quaternion's norm 2 must be 1 (allowed 0.999 to 1.001; "
            "it is then normalised)");
  EXPECT_EQ(
      refusal_of([&] { return read(header + "0,0,0,0,0,0,0.6,0.8\n0,0,0,0,0,0,0.6,0.8015\n"); }),
      "line 3 | run.csv line 3: the quaternion's norm 1.001200405 must be 1 (allowed 0.999 "
      "to 1.001; it is then normalised)");
  EXPECT_EQ(refusal_of([&] { return read(header + "0,0,0,0,0,0,1\n"); }),
            "line 2 | run.csv line 2: expected 8 comma-separated numbers, got \"0,0,0,0,0,0,1\"");
  EXPECT_EQ(refusal_of([&] { return read(header + "0,0,x,0,0,0,0,1\n"); }),
            "line 2 | run.csv line 2: field 3 \"x\" is not a finite number");
  EXPECT_EQ(refusal_of([&] { return read("t,x,y\n"); }),
            "line 1 | run.csv line 1: header \"t,x,y\" must be t_s,x_m,y_m,z_m,qx,qy,qz,qw");
}

// Robot logs print quaternions to a few decimals and carry a little tilt: a yaw of 30 deg
// rounded to 3 decimals (|q| = 1.000118) and a tilt of 2e-6 read as the same heading to 1e-3
// rad; a spreadsheet's byte order mark before the header is skipped.
TEST(PoseCsv, AcceptsRoundedQuaternionsSmallTiltsAndAByteOrderMark) {
  const std::string rows = "0,0,0,0,0,0,0.259,0.966\n0.1,0,0,0,2e-6,-2e-6,0.258819,0.965926\n";
  std::istringstream in("\xEF\xBB\xBFt_s,x_m,y_m,z_m,qx,qy,qz,qw\n" + rows);
  const TrajectorySamples s = read_pose_csv(in, "run.csv");
  ASSERT_EQ(s.theta.size(), 2u);
  EXPECT_NEAR(s.theta[0], kPi / 6, 1e-3);
  EXPECT_NEAR(s.theta[1], kPi / 6, 1e-6);
  EXPECT_NEAR(s.theta[0], 2.0 * std::atan2(0.259, 0.966), 1e-15);
}

// Along an arc the drive's excitation is the path's acceleration at the law's s(t), and the
// pieces are cut where s crosses a join.
TEST(PlanarDrive, CutsPiecesAtJoinsAndForwardsTheAcceleration) {
  std::vector<LawPiece> pieces{{0.0, 1.0, {0.6, 0.0, 0.0, 0.0}}, {1.0, 2.0, {-0.6, 0.0, 0.0, 0.0}}};
  const MotionLaw law("bang-bang", pieces);  // s = 0.6 m over 2 s
  const PlanarPath path(
      {PathElement::line(0.15), PathElement::arc(0.2, 1.0), PathElement::line(0.6 - 0.15 - 0.2)},
      0.0, true);
  const PlanarDrive drive(path, law);
  ASSERT_EQ(drive.pieces().size(), 4u);  // joins at s = 0.15 (t = sqrt(0.5)) and 0.35
  EXPECT_NEAR(drive.pieces()[0].t_end, std::sqrt(0.5), 1e-14);
  EXPECT_NEAR(drive.pieces()[2].t_end, 2.0 - std::sqrt(2.0 * 0.25 / 0.6), 1e-14);
  const double t = 0.9;  // s = 0.243 m: on the arc
  const PlanarExcitation e = drive.excitation(1, t);
  const KinematicState s = law.at(t);
  const PlanarKinematics k = path.at(s.position, s.velocity, s.acceleration, s.jerk);
  EXPECT_DOUBLE_EQ(e.ax, k.ax);
  EXPECT_DOUBLE_EQ(e.ay, k.ay);
  EXPECT_DOUBLE_EQ(e.theta_dot, s.velocity / 0.2);
  EXPECT_TRUE(drive.turns());
}

}  // namespace test_planar_motion
}  // namespace slosh
