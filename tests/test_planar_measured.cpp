// The planar models against the nine measured runs of tests/data/bologna-4d (University of
// Bologna, MIT licence, see its README): a water-filled cylinder carried by a robot along a
// lemniscate, a circle about a distant axis and an arc while it turns about its own axis, the
// wall height filmed. Each commanded trajectory is simulated with both models at the measured
// first-mode frequency and the JDSMC damping; the measurement's clock offset is estimated by
// the cross-correlation of the measured height with the predicted one, and the predicted peak
// is compared with the measured peak in the model's window.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "slosh/core/response/peak_finder.hpp"
#include "slosh/core/response/planar_response.hpp"

namespace slosh {
namespace test_planar_measured {

constexpr double kMeasuredOmega1{18.961};  // [rad/s], the group's validation script
constexpr double kRestTime{4.0};           // [s] after the trajectory's last sample

std::string data_path(const std::string& name) {
  return std::string(SLOSH_SOURCE_DIR) + "/tests/data/bologna-4d/" + name;
}

struct Measured {
  std::vector<double> t, eta;  // [s], [m]
};

Measured read_measured(const std::string& run) {
  std::ifstream in(data_path(run + ".measured.csv"));
  Measured m;
  std::string line;
  std::getline(in, line);  // t_s,eta_mm
  while (std::getline(in, line)) {
    const std::size_t comma = line.find(',');
    if (comma == std::string::npos) continue;
    m.t.push_back(std::stod(line.substr(0, comma)));
    m.eta.push_back(std::stod(line.substr(comma + 1)) * 1e-3);
  }
  return m;
}

SloshingModel bologna_model() {
  Format f;
  f.container.radius = 0.049;
  f.fill_height = 0.080;
  ModelOptions options;
  options.damping = DampingCorrelation::kPaper;
  options.omega_scale = kMeasuredOmega1 / natural_frequency(0.049, 0.080, 1);
  return make_sloshing_model(f, options);
}

/// sum_i m_i p(t_i - offset): the measured height against the prediction shifted by offset.
double correlation(const Measured& m, const PlanarResponse& p, double window, double offset) {
  double c = 0.0;
  for (std::size_t i = 0; i < m.t.size(); ++i) {
    const double t = m.t[i] - offset;
    if (t > 0.0 && t < window) c += m.eta[i] * p.eta(t);
  }
  return c;
}

/// The offset of the measurement's clock: the best frame-spaced shift, refined by golden
/// section within one frame either side.
double clock_offset(const Measured& m, const PlanarResponse& p, double window) {
  const double frame = (m.t.back() - m.t.front()) / static_cast<double>(m.t.size() - 1);
  const double last = m.t.back() - window;
  Peak best{-1.0, 0.0};
  for (double o = m.t.front(); o <= last; o += frame) {
    const double c = correlation(m, p, window, o);
    if (c > best.value) best = {c, o};
  }
  return refine_max([&](double o) { return correlation(m, p, window, o); }, best.time - frame,
                    best.time + frame, 1e-6)
      .time;
}

/// The measured peak |eta| within the model's window and its time on the model's clock.
Peak measured_peak(const Measured& m, double offset, double window) {
  Peak peak;
  for (std::size_t i = 0; i < m.t.size(); ++i) {
    const double t = m.t[i] - offset;
    if (t >= 0.0 && t <= window && std::abs(m.eta[i]) > peak.value) peak = {std::abs(m.eta[i]), t};
  }
  return peak;
}

struct RunResult {
  std::string run;
  double measured{}, linear{}, nonlinear{};  // peaks [m]
  double measured_time{}, nonlinear_time{};  // on the model's clock [s]
};

/// Time of the largest of a response's two window peaks [s].
double peak_time(const PlanarPeaks& p) {
  return p.motion.value >= p.rest.value ? p.motion.time : p.rest.time;
}

RunResult simulate_run(const std::string& run) {
  std::ifstream in(data_path(run + ".trajectory.csv"));
  const SampledTrajectory trajectory(read_pose_csv(in, run));
  const SloshingModel model = bologna_model();
  trajectory.check_sampling(model.omega1());
  const PlanarDrive drive(trajectory);
  const PlanarLinearResponse linear(model, drive, kRestTime);
  const PlanarNonlinearResponse nonlinear(model, drive, kRestTime);
  const double window = drive.duration() + kRestTime;
  const Measured m = read_measured(run);
  const double offset = clock_offset(m, nonlinear, window);
  const Peak measured = measured_peak(m, offset, window);
  RunResult r{run, measured.value};
  r.measured_time = measured.time;
  r.nonlinear_time = peak_time(nonlinear.peaks());
  r.linear = std::max(linear.peaks().motion.value, linear.peaks().rest.value);
  // The exact piecewise linear peaks on the spline's pieces agree with the integration.
  const PlanarPeaks exact = planar_linear_peaks(model, drive, kRestTime);
  EXPECT_NEAR(std::max(exact.motion.value, exact.rest.value), r.linear, 1e-7 * r.linear) << run;
  r.nonlinear = std::max(nonlinear.peaks().motion.value, nonlinear.peaks().rest.value);
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

TEST(PlanarMeasured, BothModelsPredictTheNineBolognaRuns) {
  const char* runs[] = {
      "LE_2D_0m_4.8s_900deg",    "LE_2D_0m_5s_900deg",      "LE_2D_0m_5.3s_900deg",
      "RD_2D_0.3m_6.3s_720deg",  "RD_2D_0.3m_6.5s_720deg",  "RD_2D_0.3m_6.8s_720deg",
      "TRD_2D_0.3m_2.2s_270deg", "TRD_2D_0.3m_2.4s_270deg", "TRD_2D_0.3m_2.6s_270deg"};
  std::vector<double> lin_err, nl_err;
  for (const char* run : runs) {
    const RunResult r = simulate_run(run);
    lin_err.push_back(std::abs(r.linear - r.measured) / r.measured);
    nl_err.push_back(std::abs(r.nonlinear - r.measured) / r.measured);
    // The estimated clock puts the measured peak where the model has it (within 0.6 s: the
    // lemniscate's lobes raise nearly equal waves about half a second apart).
    EXPECT_NEAR(r.measured_time, r.nonlinear_time, 0.6) << run;
    std::printf("| %s | %.1f | %.1f | %+.0f %% | %.1f | %+.0f %% |\n", run, r.measured * 1e3,
                r.linear * 1e3, 100 * (r.linear / r.measured - 1), r.nonlinear * 1e3,
                100 * (r.nonlinear / r.measured - 1));
  }
  // What the models achieve (docs/models.md), with a small margin: the nonlinear model is the
  // one to trust for the peak; the linear one over-predicts the lemniscate and arc runs by up to
  // a third and is right on the circle.
  EXPECT_LT(median(nl_err), 0.06);
  EXPECT_LT(*std::max_element(nl_err.begin(), nl_err.end()), 0.26);
  EXPECT_LT(median(lin_err), 0.27);
  EXPECT_LT(*std::max_element(lin_err.begin(), lin_err.end()), 0.36);
  std::printf("linear: median %.1f %%, max %.1f %%; nonlinear: median %.1f %%, max %.1f %%\n",
              100 * median(lin_err), 100 * *std::max_element(lin_err.begin(), lin_err.end()),
              100 * median(nl_err), 100 * *std::max_element(nl_err.begin(), nl_err.end()));
}

}  // namespace test_planar_measured
}  // namespace slosh
