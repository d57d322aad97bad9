// A rectangular tank along a planar or spatial motion (rectangular_planar.hpp): both directions'
// modes in the tank's frame in one DOP853 state, driven by the rotated acceleration of the
// tank's centre; peaks on the dense output.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "slosh/core/constants.hpp"
#include "slosh/core/response/peak_finder.hpp"
#include "slosh/core/response/rectangular_nonlinear_direction.hpp"
#include "slosh/core/response/rectangular_nonlinear_validity.hpp"
#include "slosh/core/response/rectangular_planar.hpp"

#include "response/nonlinear_scheme.hpp"
#include "response/planar_scheme.hpp"
#include "response/planar_spin.hpp"
#include "response/rectangular_planar_model.hpp"

namespace slosh {

namespace detail {

TankDirection tank_direction(const SloshingModel& m, bool nonlinear) {
  TankDirection d;
  d.side = m.radius;
  d.zeta = m.zeta;
  for (int n = 0; n < m.modes(); ++n) {
    const auto i = static_cast<std::size_t>(n);
    d.w2[i] = m.omega[i] * m.omega[i];
    d.two_zw[i] = 2.0 * m.zeta * m.omega[i];
    d.gain[i] = m.eta_gain[i];
    d.fastest = std::max(d.fastest, m.omega[i]);
  }
  if (nonlinear) {
    const RectangularSecondMode s = rectangular_second_mode(m);
    d.alpha = m.alpha;
    d.K = m.K;
    d.k_raw = rectangular_wall_gain(m.radius, m.fill_height, 1) * m.radius;
    d.even_gain = m.K / d.k_raw;
    d.s2 = s.sigma2 * s.sigma2;
    d.two_zs = 2.0 * m.zeta * s.sigma2;
    d.d4 = s.d4;
    d.d5 = s.d5;
    d.fastest = std::max(d.fastest, s.sigma2);
  }
  return d;
}

}  // namespace detail

namespace {

/// The share of the larger direction's wave below which the other is round-off, at rest.
constexpr double kRestShare{1e-9};

using detail::TankExcitation;
using detail::TankModel;

/// Integrates the model over the drive and the rest window, keeping every step.
template <std::size_t M, bool Nonlinear>
void integrate_tank(const RectangularModel& model, const PlanarDrive& drive, double frame_angle,
                    double rest_time, const PlanarOptions& options, const detail::SpinTrack& spin,
                    std::vector<RectangularPlanarResponse::Step>& steps, double& fastest) {
  using Model = TankModel<M, Nonlinear>;
  using V = detail::Vec<Model::N>;
  Model m;
  m.dir[0] = detail::tank_direction(model.along_length, Nonlinear);
  m.dir[1] = detail::tank_direction(model.along_width, Nonlinear);
  fastest = m.fastest_omega();
  const double h_max =
      std::min(options.max_step, 2.0 * std::numbers::pi / fastest / options.steps_per_period);
  const double T = drive.duration();
  const std::vector<DrivePiece>& pieces = drive.pieces();
  auto rhs = [&m](const V& x, const V& v, const TankExcitation& e) { return m.rhs(x, v, e); };
  // A drive that does not turn keeps its heading: read it once.
  const bool turning = drive.turns();
  const double theta0 = drive.kinematics(0.0).theta;
  V x(0.0), v(0.0);
  detail::DopStep<V> step;
  for (std::size_t k = 0; k <= pieces.size(); ++k) {
    const bool in_rest = k == pieces.size();
    const DrivePiece p = in_rest ? DrivePiece{T, T + rest_time} : pieces[k];
    const double L = p.t_end - p.t_begin;
    if (!(L > 0.0)) continue;
    const double hp = detail::drive_piece_step(h_max, p, options.steps_per_period);
    const std::size_t n = step_count(L, hp, 1);
    const double h = L / static_cast<double>(n);
    auto excitation = [&](double t) {
      TankExcitation out;
      if (in_rest) return out;
      const PlanarExcitation e = drive.excitation(k, t);
      const double psi = frame_angle + (turning ? drive.kinematics(t).theta : theta0);
      const double c = std::cos(psi), s = std::sin(psi);
      out.a[0] = e.ax * c + e.ay * s;
      out.a[1] = -e.ax * s + e.ay * c;
      out.g_scale = 1.0 + e.az / kGravity;
      return out;
    };
    V f0 = rhs(x, v, excitation(p.t_begin));
    for (std::size_t j = 0; j < n; ++j) {
      const double t0 = p.t_begin + h * static_cast<double>(j);
      TankExcitation end{};
      auto acc = [&](std::size_t i) {
        if (i == 12) return end;  // c_12 = c_11 = 1
        const TankExcitation e = excitation(t0 + detail::kDopC[i] * h);
        if (i == 11) end = e;
        return e;
      };
      detail::dop853_step(rhs, acc, x, v, f0, V(h), true, step, false);
      RectangularPlanarResponse::Step s;
      s.t0 = t0;
      s.h = h;
      m.signals(step.x_poly, s.eta);
      if (!spin.empty()) s.spin = spin.over(t0, h);
      steps.push_back(s);
      x = step.x1;
      v = step.v1;
      f0 = step.f1;
    }
  }
}

template <bool Nonlinear>
void dispatch_tank(const RectangularModel& model, const PlanarDrive& drive, double frame_angle,
                   double rest_time, const PlanarOptions& options, const detail::SpinTrack& spin,
                   std::vector<RectangularPlanarResponse::Step>& steps, double& fastest) {
  if (model.along_length.modes() != model.along_width.modes()) {
    throw std::invalid_argument("rectangular planar model: both directions need as many modes");
  }
  switch (model.along_length.modes()) {
    case 1:
      return integrate_tank<1, Nonlinear>(model, drive, frame_angle, rest_time, options, spin,
                                          steps, fastest);
    case 2:
      return integrate_tank<2, Nonlinear>(model, drive, frame_angle, rest_time, options, spin,
                                          steps, fastest);
    case 3:
      return integrate_tank<3, Nonlinear>(model, drive, frame_angle, rest_time, options, spin,
                                          steps, fastest);
    case 4:
      return integrate_tank<4, Nonlinear>(model, drive, frame_angle, rest_time, options, spin,
                                          steps, fastest);
    case 5:
      return integrate_tank<5, Nonlinear>(model, drive, frame_angle, rest_time, options, spin,
                                          steps, fastest);
    default:
      throw std::invalid_argument("rectangular planar model: modes must be in [1, 5]");
  }
}

}  // namespace

RectangularPlanarResponse::RectangularPlanarResponse(const RectangularModel& model,
                                                     const PlanarDrive& drive, double frame_angle,
                                                     double rest_time, RectangularPlanarModel which,
                                                     const PlanarOptions& options)
    : half_length_(0.5 * model.along_length.radius),
      half_width_(0.5 * model.along_width.radius),
      motion_time_(drive.duration()) {
  const double L = model.along_length.radius, W = model.along_width.radius;
  const bool spinning = drive.turns() && options.spin != SpinLag::kNone;
  spin_gain_ = spinning ? (L * L + W * W) / (12.0 * kGravity) : 0.0;
  const detail::SpinTrack spin =
      spinning ? detail::SpinTrack(drive, rest_time, model.along_length, options)
               : detail::SpinTrack();
  double fastest = 0.0;
  if (which == RectangularPlanarModel::kNonlinear) {
    dispatch_tank<true>(model, drive, frame_angle, rest_time, options, spin, steps_, fastest);
  } else {
    dispatch_tank<false>(model, drive, frame_angle, rest_time, options, spin, steps_, fastest);
  }
  // The peaks as the rectangular line responses locate theirs.
  const double step = std::min(kMaxPeakStep, 2.0 * std::numbers::pi / fastest / kSamplesPerPeriod);
  // In motion the waves also follow the forcing's turn with the heading (a whirl).
  double heading_rate = 0.0;
  for (const DrivePiece& p : drive.pieces()) heading_rate = std::max(heading_rate, p.heading_rate);
  const double motion_step = detail::piece_max_step(step, heading_rate, kSamplesPerPeriod);
  const double T = motion_time_, end = T + rest_time;
  auto search = [&](const auto& f) -> SloshPeaks {
    return {find_max(f, 0.0, T, motion_step), find_max(f, T, end, step)};
  };
  auto highest = [this](double t) { return eta_highest(t); };
  auto length = [this](double t) { return std::abs(value(t, 0)) + std::abs(value(t, 1)); };
  auto width = [this](double t) { return std::abs(value(t, 2)) + std::abs(value(t, 3)); };
  const SloshPeaks h = search(highest);
  peaks_.along_length = search(length);
  peaks_.along_width = search(width);
  // The corner's world direction: the signs of the two odd waves at the peak, in the frame the
  // tank had then.
  auto corner = [&](const Peak& p) {
    const double t = std::clamp(p.time, 0.0, T);
    return PlanarPeak{p.value, p.time,
                      world_corner_angle(frame_angle + drive.kinematics(t).theta, p.time)};
  };
  peaks_.highest = {corner(h.motion), corner(h.rest)};
}

const RectangularPlanarResponse::Step* RectangularPlanarResponse::step_at(double t,
                                                                          double& s) const {
  if (steps_.empty() || t <= steps_.front().t0) {
    s = 0.0;
    return nullptr;
  }
  auto it = std::upper_bound(steps_.begin(), steps_.end(), t,
                             [](double v, const Step& st) { return v < st.t0; });
  const Step& st = *(it - 1);
  s = std::min((t - st.t0) / st.h, 1.0);
  return &st;
}

double RectangularPlanarResponse::value(double t, std::size_t signal) const {
  double s = 0.0;
  const Step* st = step_at(t, s);
  if (st == nullptr) return 0.0;
  return detail::dense_value(st->eta[signal], s);
}

double RectangularPlanarResponse::corner_angle(double t) const {
  const double eL = eta_length(t), eW = eta_width(t);
  // A direction whose wave is round-off of the other's (a tank moved along W: cos 90 deg =
  // 6e-17 drives L) is at rest: the highest wall is the other direction's middle.
  const double floor = kRestShare * std::max(std::abs(eL), std::abs(eW));
  const double sx = eL > floor ? 1.0 : eL < -floor ? -1.0 : 0.0;
  const double sy = eW > floor ? 1.0 : eW < -floor ? -1.0 : 0.0;
  if (sx == 0.0 && sy == 0.0) return 0.0;
  return std::atan2(sy * half_width_, sx * half_length_);
}

double RectangularPlanarResponse::spin_rise(double t) const {
  if (spin_gain_ == 0.0) return 0.0;
  double s = 0.0;
  const Step* st = step_at(t, s);
  if (st == nullptr) return 0.0;
  const double w = detail::dense_value(st->spin, s);
  return spin_gain_ * w * w;
}

double RectangularPlanarResponse::eta_highest(double t) const {
  double s = 0.0;
  const Step* st = step_at(t, s);
  if (st == nullptr) return 0.0;
  double r = highest_corner(detail::dense_value(st->eta[0], s), detail::dense_value(st->eta[1], s),
                            detail::dense_value(st->eta[2], s), detail::dense_value(st->eta[3], s));
  if (spin_gain_ != 0.0) {
    const double w = detail::dense_value(st->spin, s);
    r += spin_gain_ * w * w;
  }
  return r;
}

RectangularPlanarPeaks rectangular_planar_linear_peaks(const RectangularModel& model,
                                                       const PlanarDrive& drive, double frame_angle,
                                                       double rest_time,
                                                       const PlanarOptions& options) {
  return RectangularPlanarResponse(model, drive, frame_angle, rest_time,
                                   RectangularPlanarModel::kLinear, options)
      .peaks();
}

RectangularPlanarNonlinearPeaks rectangular_planar_nonlinear_peaks(const RectangularModel& model,
                                                                   const PlanarDrive& drive,
                                                                   double frame_angle,
                                                                   double rest_time,
                                                                   const PlanarOptions& options) {
  const RectangularPlanarResponse r(model, drive, frame_angle, rest_time,
                                    RectangularPlanarModel::kNonlinear, options);
  const RectangularPlanarPeaks& p = r.peaks();
  RectangularPeaks line;
  line.along_length = p.along_length;
  line.along_width = p.along_width;
  const RectangularWaveHeights heights = wave_heights(line);
  // The validity is checked on the directions the motion excites (a non-finite height counts as
  // excited): the orientation of a line that excites the same ones.
  auto excited = [](double h) { return !(h == 0.0); };
  const bool l = excited(heights.along_length), w = excited(heights.along_width);
  RectangularModel checked = model;
  checked.orientation_deg = l && w ? 45.0 : w ? 90.0 : 0.0;
  if (RectangularNonlinearValidity v = rectangular_nonlinear_validity(checked, heights); !v.valid) {
    return {rectangular_planar_linear_peaks(model, drive, frame_angle, rest_time, options), false,
            std::move(v.reason)};
  }
  return {p, true, {}};
}

}  // namespace slosh
