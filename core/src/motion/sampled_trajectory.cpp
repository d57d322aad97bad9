#include "slosh/core/motion/sampled_trajectory.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string_view>

#include "slosh/core/motion/invalid_motion.hpp"
#include "slosh/core/motion/sample_smoothing.hpp"
#include "text.hpp"

namespace slosh {

namespace {

/// Largest | |q| - 1 | of a logged orientation [-]: a unit quaternion printed to 3 decimals is
/// off by up to ~1e-3 (5e-4 in each of two components); within it the quaternion is normalised,
/// beyond it the row is not a rotation.
constexpr double kQuaternionNormTolerance{1e-3};
/// Largest |qx|, |qy| taken as a rotation about the vertical axis [-]: a tilt of at most
/// 2 asin(sqrt 2 1e-3) = 2.8e-3 rad (0.16 deg), the level a robot's log carries as noise; its
/// static effect on the wall height (R tan 0.16 deg, 0.14 mm at R = 50 mm) is ignored.
constexpr double kTiltTolerance{1e-3};
/// UTF-8's byte order mark, which spreadsheets put before a CSV's header.
constexpr std::string_view kByteOrderMark{"\xEF\xBB\xBF"};

std::string indexed(const char* name, std::size_t i) {
  return std::string(name) + "[" + std::to_string(i) + "]";
}

/// Not-a-knot cubic spline through (t, v) (n >= 4): the second derivatives M of the interior
/// rows h0 M_{i-1} + 2 (h0 + h1) M_i + h1 M_{i+1} = 6 (slope difference), with the third
/// derivative continuous at the second and the next-to-last knots, so the end pieces are the
/// cubics through their four nearest samples. A natural spline (M = 0 at the ends) would force
/// a zero acceleration at both ends, wrong for a motion that starts or stops with an
/// acceleration step (x = 250 (1 - cos(pi t / 1.2)) mm starts at 1.71 m/s^2; at 1 kHz the
/// natural spline's bias lowers its linear eta_rest by 0.9 %). The end rows are the interior
/// ones with M_0 = M_1 - (h0 / h1) (M_2 - M_1) (and its mirror) substituted; the tridiagonal
/// system is then solved by the Thomas algorithm.
CubicSpline not_a_knot_spline(const std::vector<double>& t, const std::vector<double>& v) {
  const std::size_t n = t.size();
  CubicSpline s{v, std::vector<double>(n, 0.0)};
  if (n < 4) return s;
  std::vector<double> lower(n, 0.0), diag(n, 0.0), upper(n, 0.0), rhs(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
    lower[i] = h0;
    diag[i] = 2.0 * (h0 + h1);
    upper[i] = h1;
    rhs[i] = 6.0 * ((v[i + 1] - v[i]) / h1 - (v[i] - v[i - 1]) / h0);
  }
  {
    const double h0 = t[1] - t[0], h1 = t[2] - t[1];
    diag[1] = (h0 + h1) * (h0 + 2.0 * h1) / h1;
    upper[1] = (h1 * h1 - h0 * h0) / h1;
    lower[1] = 0.0;
  }
  {
    const std::size_t k = n - 2;
    const double h0 = t[k] - t[k - 1], h1 = t[k + 1] - t[k];
    lower[k] = (h0 * h0 - h1 * h1) / h0;
    diag[k] = (h0 + h1) * (h1 + 2.0 * h0) / h0;
    upper[k] = 0.0;
  }
  // Forward elimination over rows 1..n-2, then back substitution.
  for (std::size_t i = 2; i + 1 < n; ++i) {
    const double m = lower[i] / diag[i - 1];
    diag[i] -= m * upper[i - 1];
    rhs[i] -= m * rhs[i - 1];
  }
  s.second[n - 2] = rhs[n - 2] / diag[n - 2];
  for (std::size_t i = n - 3; i >= 1; --i) {
    s.second[i] = (rhs[i] - upper[i] * s.second[i + 1]) / diag[i];
  }
  // The end knots from the not-a-knot conditions.
  const double a0 = t[1] - t[0], a1 = t[2] - t[1];
  s.second[0] = s.second[1] - a0 / a1 * (s.second[2] - s.second[1]);
  const double b1 = t[n - 1] - t[n - 2], b0 = t[n - 2] - t[n - 3];
  s.second[n - 1] = s.second[n - 2] + b1 / b0 * (s.second[n - 2] - s.second[n - 3]);
  return s;
}

/// Value and three derivatives of spline piece i at t.
struct Jet {
  double v, d1, d2, d3;
};
Jet spline_at(const CubicSpline& s, const std::vector<double>& t, std::size_t i, double tt) {
  const double h = t[i + 1] - t[i];
  const double a = (t[i + 1] - tt) / h, b = (tt - t[i]) / h;
  const double m0 = s.second[i], m1 = s.second[i + 1];
  const double y0 = s.value[i], y1 = s.value[i + 1];
  Jet j;
  j.v = a * y0 + b * y1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
  j.d1 = (y1 - y0) / h - (3.0 * a * a - 1.0) / 6.0 * h * m0 + (3.0 * b * b - 1.0) / 6.0 * h * m1;
  j.d2 = a * m0 + b * m1;
  j.d3 = (m1 - m0) / h;
  return j;
}

}  // namespace

SampledTrajectory::SampledTrajectory(TrajectorySamples samples) : samples_(std::move(samples)) {
  const std::size_t n = samples_.t.size();
  if (n < 4) {
    throw InvalidMotion("t", "t: a trajectory needs at least 4 samples, got " + std::to_string(n));
  }
  if (samples_.z.empty()) samples_.z.assign(n, 0.0);
  if (samples_.theta.empty()) samples_.theta.assign(n, 0.0);
  const std::pair<const char*, const std::vector<double>*> columns[] = {{"t", &samples_.t},
                                                                        {"x", &samples_.x},
                                                                        {"y", &samples_.y},
                                                                        {"z", &samples_.z},
                                                                        {"theta", &samples_.theta}};
  for (const auto& [name, column] : columns) {
    if (column->size() != n) {
      throw InvalidMotion(name, std::string(name) + ": " + std::to_string(column->size()) +
                                    " samples, but t has " + std::to_string(n));
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite((*column)[i])) {
        throw InvalidMotion(
            indexed(name, i),
            indexed(name, i) + " = " + detail::precise((*column)[i]) + " must be finite");
      }
    }
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (!(samples_.t[i] > samples_.t[i - 1])) {
      throw InvalidMotion(indexed("t", i), indexed("t", i) + " = " +
                                               detail::precise(samples_.t[i]) +
                                               " s must be greater than " + indexed("t", i - 1) +
                                               " = " + detail::precise(samples_.t[i - 1]) +
                                               " s (times strictly increasing)");
    }
  }
  auto spline = [&](const std::vector<double>& v) {
    return not_a_knot_spline(samples_.t, smoothed_samples(samples_.t, v).value);
  };
  x_ = spline(samples_.x);
  y_ = spline(samples_.y);
  z_ = spline(samples_.z);
  theta_ = spline(samples_.theta);
  auto varies = [](const std::vector<double>& v) {
    return std::any_of(v.begin(), v.end(), [&](double e) { return e != v.front(); });
  };
  vertical_ = varies(samples_.z);
  turns_ = varies(samples_.theta);
}

double SampledTrajectory::required_rate(double omega1) {
  return kSamplesPerFirstPeriod * omega1 / (2.0 * std::numbers::pi);
}

void SampledTrajectory::check_sampling(double omega1) const {
  const double rate = required_rate(omega1);
  const double spacing = 1.0 / rate;
  const std::vector<double>& t = samples_.t;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double gap = t[i] - t[i - 1];
    const double period = 2.0 * std::numbers::pi / omega1,
                 shortest = kMinStepPerFirstPeriod * period;
    if (gap < shortest) {
      throw InvalidMotion(
          indexed("t", i),
          indexed("t", i) + ": samples " + std::to_string(i - 1) + " and " + std::to_string(i) +
              " are " + detail::precise(gap) + " s apart; the time step must be at least " +
              detail::precise(shortest) + " s (1e-9 of the first sloshing mode's period " +
              detail::precise(period) + " s)");
    }
    if (gap > spacing) {
      throw InvalidMotion(
          indexed("t", i),
          indexed("t", i) + ": samples " + std::to_string(i - 1) + " and " + std::to_string(i) +
              " are " + detail::precise(gap) + " s apart; the first sloshing mode (" +
              detail::precise(omega1 / (2.0 * std::numbers::pi)) + " Hz) needs at least " +
              detail::precise(rate) + " samples per second (a spacing of at most " +
              detail::precise(spacing) + " s)");
    }
  }
}

std::size_t SampledTrajectory::interval_at(double t) const {
  const std::vector<double>& ts = samples_.t;
  const auto it = std::upper_bound(ts.begin(), ts.end(), t);
  const auto i = static_cast<std::ptrdiff_t>(it - ts.begin()) - 1;
  return static_cast<std::size_t>(
      std::clamp<std::ptrdiff_t>(i, 0, static_cast<std::ptrdiff_t>(ts.size()) - 2));
}

PlanarKinematics SampledTrajectory::at(double t) const {
  return at(interval_at(t), t);
}

PlanarKinematics SampledTrajectory::at(std::size_t i, double t) const {
  PlanarKinematics k;
  const bool before = t<start_time(), after = t> end_time();
  const double tt = before ? start_time() : after ? end_time() : t;
  const Jet x = spline_at(x_, samples_.t, i, tt), y = spline_at(y_, samples_.t, i, tt);
  const Jet z = spline_at(z_, samples_.t, i, tt), th = spline_at(theta_, samples_.t, i, tt);
  k.x = x.v;
  k.y = y.v;
  k.z = z.v;
  k.theta = th.v;
  if (before || after) return k;  // at rest outside the samples
  k.vx = x.d1;
  k.vy = y.d1;
  k.vz = z.d1;
  k.ax = x.d2;
  k.ay = y.d2;
  k.az = z.d2;
  k.jx = x.d3;
  k.jy = y.d3;
  k.jz = z.d3;
  k.theta_dot = th.d1;
  k.theta_ddot = th.d2;
  k.theta_dddot = th.d3;
  return k;
}

double SampledTrajectory::sample_vertical_acceleration(std::size_t i) const {
  const std::vector<double>& t = samples_.t;
  const std::vector<double>& z = z_.value;
  const double h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
  return 2.0 * ((z[i + 1] - z[i]) / h1 - (z[i] - z[i - 1]) / h0) / (h0 + h1);
}

TrajectorySamples read_pose_csv(std::istream& in, const std::string& source) {
  TrajectorySamples s;
  std::string line;
  std::size_t line_no = 0;
  auto where = [&](std::size_t no) { return source + " line " + std::to_string(no); };
  auto fail = [&](const std::string& why) {
    throw InvalidMotion("line " + std::to_string(line_no), where(line_no) + ": " + why);
  };
  if (!std::getline(in, line)) {
    line_no = 1;
    fail("empty; expected the header t_s,x_m,y_m,z_m,qx,qy,qz,qw");
  }
  line_no = 1;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line.starts_with(kByteOrderMark)) line.erase(0, kByteOrderMark.size());
  if (line != "t_s,x_m,y_m,z_m,qx,qy,qz,qw") {
    fail("header \"" + line + "\" must be t_s,x_m,y_m,z_m,qx,qy,qz,qw");
  }
  double previous_theta = 0.0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    double f[8];
    std::string_view rest(line);
    for (int k = 0; k < 8; ++k) {
      const std::size_t comma = rest.find(',');
      const std::string_view field = rest.substr(0, comma);
      if ((comma == std::string_view::npos) != (k == 7)) {
        fail("expected 8 comma-separated numbers, got \"" + line + "\"");
      }
      const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), f[k]);
      if (ec != std::errc() || end != field.data() + field.size() || !std::isfinite(f[k])) {
        fail("field " + std::to_string(k + 1) + " \"" + std::string(field) +
             "\" is not a finite number");
      }
      if (comma != std::string_view::npos) rest.remove_prefix(comma + 1);
    }
    const double norm = std::sqrt(f[4] * f[4] + f[5] * f[5] + f[6] * f[6] + f[7] * f[7]);
    if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
      fail("the quaternion's norm " + detail::precise(norm) +
           " must be 1 (allowed 0.999 to 1.001; it is then normalised)");
    }
    const double qx = f[4] / norm, qy = f[5] / norm, qz = f[6] / norm, qw = f[7] / norm;
    if (std::abs(qx) > kTiltTolerance || std::abs(qy) > kTiltTolerance) {
      fail("the orientation tilts the container (qx = " + detail::precise(qx) +
           ", qy = " + detail::precise(qy) +
           "); only rotations about the vertical axis are modelled (allowed |qx|, |qy| <= "
           "0.001, a tilt of at most 0.16 deg)");
    }
    double theta = 2.0 * std::atan2(qz, qw);
    if (!s.theta.empty()) {  // unwrap: the nearest turn to the previous sample
      theta = previous_theta + std::remainder(theta - previous_theta, 2.0 * std::numbers::pi);
    }
    previous_theta = theta;
    s.t.push_back(f[0]);
    s.x.push_back(f[1]);
    s.y.push_back(f[2]);
    s.z.push_back(f[3]);
    s.theta.push_back(theta);
  }
  return s;
}

}  // namespace slosh
