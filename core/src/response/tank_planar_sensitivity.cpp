#include "response/tank_planar_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "response/rectangular_planar_model.hpp"
#include "slosh/core/constants.hpp"
#include "slosh/core/response/peak_finder.hpp"

namespace slosh::detail {

namespace {

/// The drive in the tank's frame at one instant, in duals: what TankModel::rhs reads, and the
/// container's turning rate theta' the spin follows.
struct TankDualExcitation {
  std::array<D8, 2> a{};
  double g_scale{1.0};
  D8 theta_dot;
};

/// Whether the container turns on `path` (PlanarDrive::turns).
bool turns_on(const PlanarPath& path) {
  return path.container_turns() &&
         std::any_of(path.elements().begin(), path.elements().end(),
                     [](const PathElement& e) { return e.kind == PathElement::Kind::kArc; });
}

double fastest_of(const RectangularModel& tank, RectangularPlanarModel which) {
  const bool nonlinear = which == RectangularPlanarModel::kNonlinear;
  return std::max(tank_direction(tank.along_length, nonlinear).fastest,
                  tank_direction(tank.along_width, nonlinear).fastest);
}

int sign_of(double v) {
  return v > 0.0 ? 1 : v < 0.0 ? -1 : 0;
}

/// The tank's frame along the path: a turning tank keeps its L axis at delta from the tangent,
/// one that keeps its orientation keeps it at the world angle frame_angle.
struct TankFrame {
  bool turns;
  double cd, sd, cf, sf;
  TankFrame(const PlanarPath& path, double frame_angle)
      : turns(path.container_turns()),
        cd(std::cos(frame_angle - path.start_heading())),
        sd(std::sin(frame_angle - path.start_heading())),
        cf(std::cos(frame_angle)),
        sf(std::sin(frame_angle)) {}

  /// a_L, a_W and theta' at t on a piece of the drive.
  [[gnu::always_inline]] TankDualExcitation excitation(const PieceDrive& drive, const D8& t) const {
    TankDualExcitation e;
    if (drive.rest) return e;
    if (turns) {
      const PieceMotion pm = drive.motion(t);
      e.a[0] = pm.acc * cd + pm.normal * sd;
      e.a[1] = pm.normal * cd - pm.acc * sd;
      e.theta_dot = drive.kappa * pm.speed;
    } else {
      const std::array<D8, 2> a = drive.world(t);
      e.a[0] = a[0] * cf + a[1] * sf;
      e.a[1] = a[1] * cf - a[0] * sf;
    }
    return e;
  }
};

}  // namespace

TankPlanarSensitivity::TankPlanarSensitivity(const RectangularModel& tank, const PlanarPath& path,
                                             double frame_angle, double rest_time,
                                             RectangularPlanarModel which, double steps_per_period,
                                             const PlanarOptions& options)
    : tank_(tank),
      path_(path),
      frame_angle_(frame_angle),
      rest_time_(rest_time),
      which_(which),
      fastest_(fastest_of(tank, which)),
      nu_(options.kinematic_viscosity) {
  if (tank.along_length.modes() != tank.along_width.modes()) {
    throw std::invalid_argument("rectangular planar model: both directions need as many modes");
  }
  h_max_ = std::min(0.05, 2.0 * std::numbers::pi / fastest_ / steps_per_period);
  steps_per_period_ = steps_per_period;
  peak_step_ = std::min(kMaxPeakStep, 2.0 * std::numbers::pi / fastest_ / kSamplesPerPeriod);
  const double L = tank.along_length.radius, W = tank.along_width.radius;
  if (turns_on(path) && options.spin != SpinLag::kNone) {
    spin_gain_ = (L * L + W * W) / (12.0 * kGravity);
  }
}

namespace {

/// The largest mode count per direction the tank's models take (as RectangularPlanarResponse),
/// and the default's.
constexpr std::size_t kTankModes{5};
constexpr std::size_t kDefaultTankModes{3};

/// The state of the models of at most `Modes` modes per direction: both directions' coordinates
/// (the nonlinear model's Modes + 1 each at most), then the liquid's spin, always last. DOP853 is
/// instantiated for the default's bound and for the largest (a model with fewer modes leaves the
/// rest at 0): with a single 13-wide state for every count, the default 3-mode model spent a
/// third of the pass on lanes it never used.
template <std::size_t Modes>
struct TankStateOf {
  static constexpr std::size_t kSpin{2 * (Modes + 1)};
  using Type = DualVec<kSpin + 1>;
};

/// A tank's models in dual numbers (TankModel of M <= Modes modes, linear or nonlinear).
template <std::size_t Modes>
struct TankDualModel {
  using State = typename TankStateOf<Modes>::Type;
  virtual ~TankDualModel() = default;
  [[nodiscard]] virtual State rhs(const State& x, const State& v,
                                  const TankDualExcitation& e) const = 0;
  virtual void signals(const DensePoly<State>& p,
                       std::array<std::array<D8, kDenseTerms>, 4>& eta) const = 0;
};

template <std::size_t Modes, std::size_t M, bool Nonlinear>
struct TankDualModelOf final : TankDualModel<Modes> {
  using State = typename TankDualModel<Modes>::State;
  TankModel<M, Nonlinear> m;
  TankDualModelOf(const RectangularModel& tank) {
    m.dir[0] = tank_direction(tank.along_length, Nonlinear);
    m.dir[1] = tank_direction(tank.along_width, Nonlinear);
  }
  [[nodiscard]] State rhs(const State& x, const State& v,
                          const TankDualExcitation& e) const override {
    return m.rhs(x, v, e);
  }
  void signals(const DensePoly<State>& p,
               std::array<std::array<D8, kDenseTerms>, 4>& eta) const override {
    m.template signals<D8>(p, eta);
  }
};

template <std::size_t Modes, bool Nonlinear>
std::unique_ptr<TankDualModel<Modes>> dual_model_of(const RectangularModel& tank) {
  const std::size_t modes = static_cast<std::size_t>(tank.along_length.modes());
  if (modes < 1 || modes > Modes) {
    throw std::invalid_argument("rectangular planar model: modes must be in [1, 5]");
  }
  switch (modes) {
    case 1:
      return std::make_unique<TankDualModelOf<Modes, 1, Nonlinear>>(tank);
    case 2:
      return std::make_unique<TankDualModelOf<Modes, 2, Nonlinear>>(tank);
    case 3:
      return std::make_unique<TankDualModelOf<Modes, 3, Nonlinear>>(tank);
    default:
      if constexpr (Modes >= 5) {
        if (modes == 4) return std::make_unique<TankDualModelOf<Modes, 4, Nonlinear>>(tank);
        return std::make_unique<TankDualModelOf<Modes, 5, Nonlinear>>(tank);
      }
      throw std::invalid_argument("rectangular planar model: modes must be in [1, 5]");
  }
}

/// One step's dense output as stored.
template <std::size_t Modes>
TankPlanarSensitivity::Stored stored_step(
    const TankDualModel<Modes>& m, const D8& t0, const D8& h,
    const DensePoly<typename TankStateOf<Modes>::Type>& x_poly) {
  constexpr std::size_t kSpin = TankStateOf<Modes>::kSpin;
  TankPlanarSensitivity::Stored st;
  st.t0 = t0;
  st.h = h;
  std::array<std::array<D8, kDenseTerms>, 4> sig;
  m.signals(x_poly, sig);
  for (std::size_t r = 0; r < 4; ++r) st.poly[r] = sig[r];
  for (std::size_t k = 0; k < kDenseTerms; ++k) st.poly[4][k] = x_poly[k][kSpin];
  for (std::size_t r = 0; r < 4; ++r) {
    for (std::size_t k = 0; k < kDenseTerms; ++k) st.value[r][k] = st.poly[r][k].x[0];
  }
  // The spin's rate: the derivative of its angle's interpolant over the step's length.
  for (std::size_t k = 0; k + 1 < kDenseTerms; ++k) {
    st.value[4][k] = static_cast<double>(k + 1) * st.poly[4][k + 1].x[0] / h.value();
  }
  return st;
}

}  // namespace

/// The integration of compute() (a friend: it reads the law's duals and writes the steps).
struct TankSensitivityPass {
  static void run(TankPlanarSensitivity& s, const std::vector<DualPiece>& list) {
    if (s.tank_.along_length.modes() <= static_cast<int>(kDefaultTankModes)) {
      run_sized<kDefaultTankModes>(s, list);
    } else {
      run_sized<kTankModes>(s, list);
    }
  }
  template <std::size_t Modes>
  static void run_sized(TankPlanarSensitivity& s, const std::vector<DualPiece>& list);
};

// flatten: the scheme and the dual arithmetic are inlined (their lane loops stay vectorised);
// the model's right-hand side is one virtual call per stage.
template <std::size_t Modes>
[[gnu::flatten]] void TankSensitivityPass::run_sized(TankPlanarSensitivity& s,
                                                     const std::vector<DualPiece>& list) {
  using TankState = typename TankStateOf<Modes>::Type;
  constexpr std::size_t kSpin = TankStateOf<Modes>::kSpin;
  const bool nonlinear = s.which_ == RectangularPlanarModel::kNonlinear;
  const std::unique_ptr<TankDualModel<Modes>> model =
      nonlinear ? dual_model_of<Modes, true>(s.tank_) : dual_model_of<Modes, false>(s.tank_);
  const TankDualModel<Modes>& m = *model;
  const double spin_scale = s.spin_gain_ != 0.0 ? 1.0 / s.tank_.along_length.fill_height : 0.0;
  const double nu = s.nu_;
  auto rhs = [&m, spin_scale, nu](const TankState& x, const TankState& v,
                                  const TankDualExcitation& e) {
    TankState out = m.rhs(x, v, e);
    if (spin_scale != 0.0) {
      // w' = sqrt(nu max(|theta'|, |w|)) / h (theta' - w) (ekman_rate).
      const D8& w = v[kSpin];
      const D8 at = dual_abs(e.theta_dot), aw = dual_abs(w);
      const D8 omega = at.value() >= aw.value() ? at : aw;
      out[kSpin] = (spin_scale * dual_sqrt(nu * omega)) * (e.theta_dot - w);
    }
    return out;
  };
  const TankFrame frame(s.path_, s.frame_angle_);
  const std::vector<std::size_t> counts =
      s.frozen_.steps(list, piece_steps(s.law_, s.path_, list, s.h_max_, s.steps_per_period_));
  s.steps_.clear();
  s.t0_values_.clear();
  TankState x(0.0), v(0.0);
  DopStep<TankState> step;
  for (std::size_t p = 0; p < list.size(); ++p) {
    const DualPiece& piece = list[p];
    const Dual7 length = piece.t_end - piece.t_begin;
    const std::size_t n = counts[p];
    const Dual7 h = length * (1.0 / static_cast<double>(n));
    const PieceDrive drive(s.path_, s.law_, piece);
    auto excitation = [&](const D8& t) { return frame.excitation(drive, t); };
    const D8 tb(piece.t_begin);
    const D8 hd(h);
    const TankState hh(hd);
    TankState f0 = rhs(x, v, excitation(tb));
    for (std::size_t j = 0; j < n; ++j) {
      const D8 t0 = tb + static_cast<double>(j) * hd;
      auto acc = [&](std::size_t i) { return excitation(t0 + kDopC[i] * hd); };
      dop853_step(rhs, acc, x, v, f0, hh, true, step, false);
      s.steps_.push_back(stored_step<Modes>(m, t0, hd, step.x_poly));
      s.t0_values_.push_back(t0.value());
      if (t0.value() + hd.value() >= s.until_) return;
      x = step.x1;
      v = step.v1;
      f0 = step.f1;
    }
  }
}

void TankPlanarSensitivity::compute(const double* d, double until) {
  until_ = until;
  const std::vector<DualPiece> list = law_.pieces(path_, rest_time_, dual_durations(d, true));
  motion_time_ = law_.t_start[kSegments].v;
  TankSensitivityPass::run(*this, list);
}

void TankPlanarSensitivity::freeze_steps(const double* d) {
  const std::vector<DualPiece> list = law_.pieces(path_, rest_time_, dual_durations(d, false));
  frozen_.freeze(list, piece_steps(law_, path_, list, h_max_, steps_per_period_));
}

std::size_t TankPlanarSensitivity::step_at(double t) const {
  return step_index(t0_values_, t);
}

double TankPlanarSensitivity::eta_highest(double t) const {
  const Stored& s = steps_[step_at(t)];
  const double theta = std::clamp((t - s.t0.value()) / s.h.value(), 0.0, 1.0);
  std::array<double, 5> r{};
  for (std::size_t k = 0; k < 5; ++k) r[k] = dense_value(s.value[k], theta);
  return std::abs(r[0]) + std::abs(r[2]) + std::abs(r[1] + r[3]) + spin_gain_ * r[4] * r[4];
}

void TankPlanarSensitivity::eta_at(const std::vector<double>& t, std::vector<double>& values,
                                   std::vector<std::array<double, kSegments>>& gradients) const {
  values.resize(t.size());
  gradients.resize(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Stored& s = steps_[step_at(t[i])];
    const D8 theta = (D8(t[i]) - s.t0) / s.h;
    const D8 odd_l = dense_value(s.poly[0], theta), odd_w = dense_value(s.poly[2], theta);
    const D8 even = dense_value(s.poly[1], theta) + dense_value(s.poly[3], theta);
    // The spin's rate: the angle interpolant's derivative by theta, over the step's length.
    D8 w_theta(0.0);
    for (std::size_t k = kDenseTerms - 1; k > 0; --k) {
      w_theta = w_theta * theta + static_cast<double>(k) * s.poly[4][k];
    }
    const D8 w = w_theta / s.h;
    const int so = sign_of(odd_l.value()), sw = sign_of(odd_w.value()), se = sign_of(even.value());
    values[i] = std::abs(odd_l.value()) + std::abs(odd_w.value()) + std::abs(even.value()) +
                spin_gain_ * w.value() * w.value();
    for (std::size_t k = 0; k < kSegments; ++k) {
      gradients[i][k] = so * odd_l.x[1 + k] + sw * odd_w.x[1 + k] + se * even.x[1 + k] +
                        2.0 * spin_gain_ * w.value() * w.x[1 + k];
    }
  }
}

double TankPlanarSensitivity::peak_time(double lo, double hi) const {
  if (!(hi > lo)) return lo;
  return find_max([this](double t) { return eta_highest(t); }, lo, hi, peak_step_).time;
}

std::vector<PlanarWindowPeak> TankPlanarSensitivity::window_peaks(double t_begin, double t_end,
                                                                  double window) const {
  std::vector<PlanarWindowPeak> out;
  if (!(t_end > t_begin)) return out;
  const auto n = static_cast<std::size_t>(std::ceil((t_end - t_begin) / window - 1e-9));
  for (std::size_t i = 0; i < n; ++i) {
    const double a = t_begin + static_cast<double>(i) * window;
    const double b = i + 1 == n ? t_end : std::min(t_end, a + window);
    const Peak p = find_max([this](double t) { return eta_highest(t); }, a, b, peak_step_);
    out.push_back({p.value, p.time});
  }
  return out;
}

}  // namespace slosh::detail
