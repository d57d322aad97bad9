// The smoothing of a trajectory's samples (sample_smoothing.hpp): a log's rounding does not
// become acceleration, and a clean commanded motion is left as it is.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "slosh/core/motion/sample_smoothing.hpp"
#include "slosh/core/motion/sampled_trajectory.hpp"
#include "slosh/core/motion/trajectory_ends.hpp"

namespace slosh {
namespace test_sample_smoothing {

constexpr double kPi = std::numbers::pi;
/// The first mode of the thesis cup (R 48.5 mm, h 82 mm of water) [rad/s]:
/// sqrt(g 1.8412 / R tanh(1.8412 h / R)), the mode the moving-end fit is sized on.
const double kThesisOmega1 = std::sqrt(9.81 * 1.8412 / 0.0485 * std::tanh(1.8412 * 82.0 / 48.5));

/// x = 250 (1 - cos(pi t / 1.2)) mm for 1.2 s, then 0.3 s at rest, sampled at 1 kHz, its
/// positions rounded to `quantum` metres (0: exact).
TrajectorySamples half_cosine(double quantum) {
  TrajectorySamples s;
  for (int i = 0; i <= 1500; ++i) {
    const double t = 1e-3 * i;
    const double x = 0.25 * (1.0 - std::cos(kPi * std::min(t, 1.2) / 1.2));
    s.t.push_back(t);
    s.x.push_back(quantum > 0.0 ? quantum * std::round(x / quantum) : x);
    s.y.push_back(0.0);
  }
  return s;
}

double exact_acceleration(double t) {
  const double w = kPi / 1.2;
  return t < 1.2 ? 0.25 * w * w * std::cos(w * t) : 0.0;
}

/// Largest |ax| over the spline on a grid of 0.1 ms.
double peak_acceleration(const SampledTrajectory& tr) {
  double peak = 0.0;
  for (int i = 0; i <= 15000; ++i) peak = std::max(peak, std::abs(tr.at(1e-4 * i).ax));
  return peak;
}

// Rounding to q is a uniform error of standard deviation q / sqrt(12) where the log moves.
TEST(SampleSmoothing, NoiseOfARoundedLogIsItsQuantisation) {
  const TrajectorySamples s = half_cosine(1e-5);
  EXPECT_NEAR(sample_noise(s.t, s.x), 1e-5 / std::sqrt(12.0), 0.1e-5 / std::sqrt(12.0));
  // The exact samples: round-off of 0.5 m (1e-16) is all there is; a log at rest has none.
  const TrajectorySamples exact = half_cosine(0.0);
  EXPECT_LT(sample_noise(exact.t, exact.x), 1e-15);
  EXPECT_EQ(sample_noise(exact.t, exact.y), 0.0);
}

// A log rounded to 0.01 mm (and 0.1 mm) at 1 kHz: the interpolating spline made its peak
// acceleration 29.8 m/s^2 (300) instead of the motion's 1.71 (1.94 on the exact samples: the
// spline's overshoot at the stop's acceleration step). Smoothed, the acceleration follows the
// motion within 2.5 % (7 %) of its peak away from the stop, the peak lies between the motion's
// and the exact samples' spline's, and the log starts and ends at rest (below the 1 mm/s a
// moving end is warned of).
TEST(SampleSmoothing, ARoundedLogKeepsItsAcceleration) {
  const SampledTrajectory exact(half_cosine(0.0));
  const double exact_peak = peak_acceleration(exact);
  EXPECT_NEAR(exact_peak, 1.943, 1e-3);
  for (double quantum : {1e-5, 1e-4}) {
    const SampledTrajectory rounded(half_cosine(quantum));
    double worst = 0.0;
    for (int i = 0; i <= 1100; ++i) {
      const double t = 0.05 + 1e-3 * i;
      worst = std::max(worst, std::abs(rounded.at(t).ax - exact_acceleration(t)));
    }
    const double tolerance = quantum == 1e-5 ? 0.025 : 0.07;
    EXPECT_LT(worst, tolerance * 1.71) << quantum;
    const double peak = peak_acceleration(rounded);
    EXPECT_GT(peak, 1.71) << quantum;
    EXPECT_LT(peak, exact_peak) << quantum;
    EXPECT_LT(std::abs(rounded.at(0.0).vx), 1e-3) << quantum;
    EXPECT_LT(std::abs(rounded.at(1.5).vx), 1e-3) << quantum;
  }
}

// A clean quintic at uneven times is reproduced to round-off (its sixth differences are
// round-off, so nothing is smoothed); a cubic trend is never bent: the smoothing of noise plus
// a cubic is the cubic plus the smoothing of the noise alone (the penalty's fourth differences
// and the noise's sixth differences of a cubic are 0).
TEST(SampleSmoothing, CleanPolynomialsAreKept) {
  TrajectorySamples s;
  auto x = [](double t) { return 0.1 + t * (0.2 + t * (-0.3 + t * (0.4 + t * (-0.5 + 0.6 * t)))); };
  auto a = [](double t) { return -0.6 + t * (2.4 + t * (-6.0 + 12.0 * t)); };
  for (int i = 0; i <= 1000; ++i) {
    const double t = 1e-3 * i + 2e-4 * std::sin(1.0 * i);  // jittered times
    s.t.push_back(t);
    s.x.push_back(x(t));
    s.y.push_back(0.0);
  }
  const SampledTrajectory tr(s);
  for (double t : {0.0, 0.3337, 0.5, 0.999}) {
    EXPECT_NEAR(tr.at(t).x, x(t), 1e-12) << t;
    EXPECT_NEAR(tr.at(t).ax, a(t), 2e-5) << t;
  }
  std::vector<double> noise, noisy;
  for (double t : s.t) {
    noise.push_back(1e-4 * std::sin(1e4 * t * t));  // aliased far above the samples' Nyquist
    noisy.push_back(noise.back() + 1.0 + t * (-2.0 + t * (3.0 - 4.0 * t)));
  }
  const SmoothedSamples alone = smoothed_samples(s.t, noise);
  const SmoothedSamples trend = smoothed_samples(s.t, noisy);
  EXPECT_GT(alone.lambda, 1.0);
  EXPECT_NEAR(trend.lambda / alone.lambda, 1.0, 1e-6);
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    ASSERT_NEAR(trend.value[i] - (noisy[i] - noise[i]), alone.value[i], 1e-12) << i;
  }
  // Reinsch's criterion: the residual sum of squares is n sigma^2.
  double rss = 0.0;
  for (std::size_t i = 0; i < noise.size(); ++i) {
    rss += (noise[i] - alone.value[i]) * (noise[i] - alone.value[i]);
  }
  const double n = static_cast<double>(noise.size());
  EXPECT_NEAR(rss / (n * alone.noise * alone.noise), 1.0, 2e-3);
}

/// A Bologna run's pose CSV (tests/data/bologna-4d, University of Bologna, MIT licence) with its
/// positions printed to `position_digits` decimals of a metre and its quaternions to
/// `quaternion_digits` (0: as logged), as a robot's log prints them.
TrajectorySamples rounded_bologna(int position_digits, int quaternion_digits) {
  std::ifstream in(std::string(SLOSH_SOURCE_DIR) +
                   "/tests/data/bologna-4d/TRD_2D_0.3m_2.2s_270deg.trajectory.csv");
  std::string line;
  std::getline(in, line);
  std::ostringstream out;
  out << line << "\n";
  while (std::getline(in, line)) {
    std::vector<double> f;
    std::istringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) f.push_back(std::stod(field));
    char buf[512];
    const int p = position_digits, q = quaternion_digits;
    if (q > 0) {
      std::snprintf(buf, sizeof buf, "%.17g,%.*f,%.*f,%.*f,%.*f,%.*f,%.*f,%.*f", f[0], p, f[1], p,
                    f[2], p, f[3], q, f[4], q, f[5], q, f[6], q, f[7]);
    } else {
      std::snprintf(buf, sizeof buf, "%.17g,%.*f,%.*f,%.*f,%.17g,%.17g,%.17g,%.17g", f[0], p, f[1],
                    p, f[2], p, f[3], f[4], f[5], f[6], f[7]);
    }
    out << buf << "\n";
  }
  std::istringstream csv(out.str());
  return read_pose_csv(csv, "rounded");
}

// The Bologna 270 deg run ends by creeping the last 0.05 mm into its pose over 50 ms. Printed to
// 0.1 mm, its positions repeat one value over the last 25 samples (and its quaternions, printed
// to 4 decimals, over 27), but the smoothed spline ends at 11.6 mm/s (1.24 deg/s), and the end
// was warned of as moving. The verdict is now the samples': they hold still there, and the end is
// at rest; the rounded log stays within a quantum of the logged one.
TEST(SampleSmoothing, ALogThatSitsStillAtItsEndEndsAtRest) {
  const SampledTrajectory logged(rounded_bologna(9, 0));
  for (const auto& [p, q] : {std::pair{4, 0}, std::pair{9, 4}}) {
    const TrajectorySamples s = rounded_bologna(p, q);
    const std::size_t n = s.t.size();
    // The samples' own verdict, counted here: the last samples equal to the last one.
    const std::vector<double>& still = p == 4 ? s.y : s.theta;
    std::size_t run = 0;
    while (still[n - 1 - run] == still.back()) ++run;
    ASSERT_GE(run, 25U) << p;
    EXPECT_GE(rest_runs(still, sample_noise(s.t, still)).tail, run) << p;
    const SampledTrajectory tr(s);
    EXPECT_TRUE(moving_end_warnings(tr, 18.96).empty())
        << p << ": " << moving_end_warnings(tr, 18.96).front();
    if (p == 4) {
      for (std::size_t i = 0; i < n; i += 7) {
        EXPECT_NEAR(tr.at(s.t[i]).y, logged.at(s.t[i]).y, 2e-4) << i;
      }
    }
  }
}

// Only a run that holds still counts: the clean half-cosine's smoothed samples are its samples
// (its 301 rest samples hold still exactly); rounded to 0.1 mm and cut at 0.9 s, while it moves at
// 0.25 (pi / 1.2) sin(0.75 pi) = 0.463 m/s, the log is still warned of as ending moving, at that
// speed.
TEST(SampleSmoothing, OnlyRunsThatHoldStillAreAtRest) {
  const TrajectorySamples exact = half_cosine(0.0);
  const SmoothedSamples g = smoothed_samples(exact.t, exact.x);
  EXPECT_EQ(g.value, exact.x);
  EXPECT_EQ(g.rest.head, 0U);
  EXPECT_EQ(g.rest.tail, 301U);  // t = 1.2 .. 1.5 s
  TrajectorySamples cut = half_cosine(1e-4);
  for (auto* v : {&cut.t, &cut.x, &cut.y}) v->resize(901);
  const SampledTrajectory tr(cut);
  const std::vector<std::string> w = moving_end_warnings(tr, kThesisOmega1);
  ASSERT_EQ(w.size(), 1U);
  const std::string head =
      "the trajectory ends moving: at its last sample (t_s[900] = 0.9 s) the container moves at ";
  ASSERT_EQ(w.front().substr(0, head.size()), head);
  const double speed = 0.25 * kPi / 1.2 * std::sin(kPi * 0.9 / 1.2);
  EXPECT_NEAR(std::stod(w.front().substr(head.size())), speed * 1e3, 0.01 * speed * 1e3);
}

/// Gaussian noise of deviation sigma, the same on every standard library (Box-Muller on
/// mt19937_64, whose sequence the standard fixes).
class Noise {
 public:
  Noise(unsigned seed, double sigma) : rng_(seed), sigma_(sigma) {}
  double operator()() {
    if (sigma_ == 0.0) return 0.0;
    auto uniform = [this] { return (static_cast<double>(rng_() >> 11) + 0.5) * 0x1p-53; };
    const double r = std::sqrt(-2.0 * std::log(uniform()));
    return sigma_ * r * std::cos(2.0 * kPi * uniform());
  }

 private:
  std::mt19937_64 rng_;
  double sigma_;
};

/// A 500 Hz log of 1.2 s: x(t) [m] plus noise of sigma [m] on x and y.
TrajectorySamples noisy_log(const std::function<double(double)>& x, double sigma, unsigned seed) {
  Noise noise(seed, sigma);
  TrajectorySamples s;
  for (int i = 0; i <= 600; ++i) {
    const double t = i / 500.0;
    s.t.push_back(t);
    s.x.push_back(x(t) + noise());
    s.y.push_back(noise());
  }
  return s;
}

/// 200 mm half-cosine from 0.2 s to 1.0 s, at rest before and after.
double resting_move(double t) {
  const double u = std::clamp(t - 0.2, 0.0, 0.8);
  return 0.1 * (1.0 - std::cos(kPi * u / 0.8));
}

/// At rest until 0.2 s, then a smooth ramp (a raised cosine of speed over 0.4 s) to `speed`
/// [m/s], held to the log's end.
double speeding_up(double t, double speed) {
  const double u = std::clamp(t - 0.2, 0.0, 0.4);
  const double ramp = 0.5 * speed * (u - 0.4 / kPi * std::sin(kPi * u / 0.4));
  return ramp + speed * std::max(0.0, t - 0.6);
}

/// At rest until 1.0 s, then creeping at `speed` [m/s] to the log's end.
double creeping(double t, double speed) {
  return resting_move(t) + speed * std::max(0.0, t - 1.0);
}

const std::string kEndsMovingAt =
    "the trajectory ends moving: at its last sample (t_s[600] = 1.2 s) the container moves at ";
const std::string kEndsMovingTail =
    " mm/s and turns at 0 deg/s; the models see no acceleration after it, as if the container "
    "went on at that speed through the rest window: the wave of stopping it is not in the "
    "prediction (eta_rest in particular); end the trajectory at rest";

// A clean move at rest at both ends plus noise of 0.05 mm at 500 Hz: its smoothed spline ends
// with slopes of several mm/s (the noise of the last samples), which were warned of as moving
// ends; the end fits see rest within their scatter.
TEST(TrajectoryEnds, ANoisyLogAtRestIsNotWarnedOf) {
  double largest_spline_slope = 0.0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const SampledTrajectory tr(noisy_log(resting_move, 0.05e-3, seed));
    for (const double t : {0.0, 1.2}) {
      const PlanarKinematics k = tr.at(t);
      largest_spline_slope = std::max(largest_spline_slope, std::hypot(k.vx, k.vy));
    }
    const std::vector<std::string> w = moving_end_warnings(tr, kThesisOmega1);
    EXPECT_TRUE(w.empty()) << seed << ": " << w.front();
  }
  EXPECT_GT(largest_spline_slope, 5e-3);  // what the spline's slope would have said
}

// A log that really ends moving, at 50 mm/s, is warned of at that speed, clean (to the digit:
// the end is a straight line, which the fit follows exactly) and with the same noise (the fit's
// slope within its scatter). Before, the spline's slope there was quoted, off by up to 18 mm/s.
TEST(TrajectoryEnds, ALogThatEndsMovingIsWarnedOfWithOrWithoutNoise) {
  const auto move = [](double t) { return speeding_up(t, 0.05); };
  const std::vector<std::string> clean =
      moving_end_warnings(SampledTrajectory(noisy_log(move, 0.0, 1)), kThesisOmega1);
  EXPECT_EQ(clean, std::vector<std::string>{kEndsMovingAt + "50" + kEndsMovingTail});
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const std::vector<std::string> w =
        moving_end_warnings(SampledTrajectory(noisy_log(move, 0.05e-3, seed)), kThesisOmega1);
    ASSERT_EQ(w.size(), 1U) << seed;
    ASSERT_EQ(w.front().substr(0, kEndsMovingAt.size()), kEndsMovingAt) << w.front();
    std::size_t end = 0;
    const double speed = std::stod(w.front().substr(kEndsMovingAt.size()), &end);
    EXPECT_NEAR(speed, 50.0, 16.0) << seed;  // 4 of the fit's standard errors (~4 mm/s)
    EXPECT_EQ(w.front().substr(kEndsMovingAt.size() + end), kEndsMovingTail) << seed;
  }
}

// A creeping end: a drift of 0.5 mm/s is below the 1 mm/s that counts (stopping it at once
// leaves a wave of thousandths of a millimetre) and is not warned of, clean or noisy; one of
// 5 mm/s is, when the samples show it clean; under noise of 0.05 mm it is within the fit's
// scatter over a quarter period and is not.
TEST(TrajectoryEnds, ACreepingEndIsWarnedOfOnlyAboveOneMillimetrePerSecondAndTheNoise) {
  for (const double sigma : {0.0, 0.05e-3}) {
    const auto slow = [](double t) { return creeping(t, 0.5e-3); };
    const std::vector<std::string> w =
        moving_end_warnings(SampledTrajectory(noisy_log(slow, sigma, 3)), kThesisOmega1);
    EXPECT_TRUE(w.empty()) << sigma << ": " << w.front();
  }
  const auto faster = [](double t) { return creeping(t, 5e-3); };
  EXPECT_EQ(moving_end_warnings(SampledTrajectory(noisy_log(faster, 0.0, 3)), kThesisOmega1),
            std::vector<std::string>{kEndsMovingAt + "5" + kEndsMovingTail});
  EXPECT_TRUE(
      moving_end_warnings(SampledTrajectory(noisy_log(faster, 0.05e-3, 3)), kThesisOmega1).empty());
}

// The end fit's slope is a cubic's own, and its standard error is the scatter of the slopes
// over many noisy logs: pure noise of 0.05 mm fitted over 40 ms at 500 Hz, 2000 times.
TEST(TrajectoryEnds, TheEndFitsStandardErrorIsTheSlopesScatter) {
  std::vector<double> t, cubic;
  for (int i = 0; i <= 100; ++i) {
    t.push_back(1e6 + i / 500.0);  // a machine's clock: the fit is taken from the end
    const double u = i / 500.0;
    cubic.push_back(0.3 + 0.02 * u - 0.5 * u * u + 3.0 * u * u * u);
  }
  const EndRate first = end_rate(t, cubic, false, 0.04);
  // The clock's rounding at 1e6 s (1e-10 s) moves the samples by 2e-11 m.
  EXPECT_NEAR(first.rate, 0.02, 1e-7);
  EXPECT_LT(first.standard_error, 1e-7);
  const double u = 0.2;
  EXPECT_NEAR(end_rate(t, cubic, true, 0.04).rate, 0.02 - u + 9.0 * u * u, 1e-7);
  double sum = 0.0, sum2 = 0.0, se = 0.0;
  constexpr int kLogs = 2000;
  for (int k = 0; k < kLogs; ++k) {
    Noise noise(static_cast<unsigned>(100 + k), 0.05e-3);
    std::vector<double> v;
    for (std::size_t i = 0; i < t.size(); ++i) v.push_back(noise());
    const EndRate r = end_rate(t, v, true, 0.04);
    sum += r.rate;
    sum2 += r.rate * r.rate;
    se += r.standard_error / kLogs;
  }
  const double mean = sum / kLogs, scatter = std::sqrt(sum2 / kLogs - mean * mean);
  EXPECT_NEAR(se, scatter, 0.06 * scatter);
  EXPECT_NEAR(mean, 0.0, 4.0 * scatter / std::sqrt(kLogs));
}

}  // namespace test_sample_smoothing
}  // namespace slosh
