#include "response/nonlinear_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <utility>

// One clone of the integration loops for AVX (a derivative lane set is two AVX vectors of
// doubles), chosen at load time where the CPU has it. No FMA and no reassociation, so both
// clones compute the same numbers bit for bit.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SLOSH_TANGENT_CLONES __attribute__((target_clones("avx", "default")))
#else
#define SLOSH_TANGENT_CLONES
#endif

namespace slosh::detail {

NonlinearSensitivity::NonlinearSensitivity(const SloshingModel& model, double stroke,
                                           double rest_time, const NonlinearOptions& options)
    : model_(model), stroke_(stroke), rest_time_(rest_time) {
  const double period = 2.0 * std::numbers::pi / model.omega1();
  h_max_ = std::min(options.max_step, period / options.steps_per_period);
}

bool NonlinearSensitivity::freeze_steps(const double* d) {
  std::array<std::size_t, kSegments> n{};
  for (std::size_t k = 0; k < kSegments; ++k) n[k] = step_count(d[k], h_max_, 1) + 1;
  const bool changed = !frozen_ || n != steps_;
  steps_ = n;
  frozen_ = true;
  return changed;
}

bool NonlinearSensitivity::outgrows_frozen_steps(const double* from, const double* at) const {
  for (std::size_t k = 0; k < kSegments; ++k) {
    if (step_count(at[k], h_max_, 1) > step_count(from[k], h_max_, 1) + 1) return true;
  }
  return false;
}

namespace {

/// xbar'' of eq. 2.35 with its partial derivatives: the value exactly as NonlinearResponse
/// computes it (nonlinear_rhs in double), the partials from the same formula differentiated.
struct RhsJet {
  double f, fx, fv, fa;
};

[[gnu::always_inline]] inline RhsJet rhs_jet(const SloshingModel& m, double x, double v, double a) {
  const double f = nonlinear_rhs(m, x, v, a);
  const double w = m.omega1();
  const double c2 = m.C * m.C;
  const double den = 1.0 + c2 * x * x;
  const double inv = 1.0 / den;
  // f = -num / den, so df = -(dnum + f dden) / den.
  const double num_x =
      4.0 * w * m.zeta * c2 * x * v + c2 * v * v + w * w * (1.0 + 3.0 * m.alpha * x * x);
  const double num_v = 2.0 * w * m.zeta * den + 2.0 * c2 * x * v;
  return {f, -(num_x + f * 2.0 * c2 * x) * inv, -num_v * inv, -inv / m.radius};
}

/// The state's derivatives with respect to N directions at once (the durations, or the state at
/// T for the rest window): a GCC vector of N doubles, which each clone lowers to its own vector
/// registers (two AVX or four SSE2 registers for N = 8).
typedef double Vec2 __attribute__((vector_size(2 * sizeof(double))));
typedef double Vec8 __attribute__((vector_size(8 * sizeof(double))));
template <std::size_t N>
struct VecOf;
template <>
struct VecOf<2> {
  using type = Vec2;
};
template <>
struct VecOf<8> {
  using type = Vec8;
};

template <std::size_t N>
struct Lanes {
  using Vec = typename VecOf<N>::type;
  Vec v{};
  Lanes() = default;
  Lanes(double c) : v(Vec{} + c) {}  // NOLINT: implicit, so the scheme's templates accept it
  [[nodiscard]] double operator[](std::size_t i) const { return v[i]; }
  double& operator[](std::size_t i) { return reinterpret_cast<double*>(&v)[i]; }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return from(a.v + b.v); }
  friend Lanes operator-(const Lanes& a, const Lanes& b) { return from(a.v - b.v); }
  friend Lanes operator*(double c, const Lanes& a) { return from(c * a.v); }
  friend Lanes operator*(const Lanes& a, double c) { return from(a.v * c); }
  static Lanes from(const Vec& x) {
    Lanes r;
    r.v = x;
    return r;
  }
};

/// No derivatives at all: the values alone, by the same operations as with derivatives (the
/// derivative operations compile to nothing), so they are the same to the last bit.
template <>
struct Lanes<0> {
  Lanes() = default;
  Lanes(double) {}  // NOLINT: implicit, as Lanes<N>'s
  friend Lanes operator+(const Lanes&, const Lanes&) { return {}; }
  friend Lanes operator-(const Lanes&, const Lanes&) { return {}; }
  friend Lanes operator*(double, const Lanes&) { return {}; }
  friend Lanes operator*(const Lanes&, double) { return {}; }
};

/// The 7 durations and a zero pad: two AVX vectors, no scalar tail.
constexpr std::size_t kLanes{8};
using Lanes8 = Lanes<kLanes>;

/// State (x, v) and x'' at a step start, each with its derivatives.
template <std::size_t N>
struct TangentState {
  double x{}, v{}, f{};
  Lanes<N> dx, dv, df;
};

/// The forcing of one step: the container acceleration at the stages (a[i] at t0 + c_i h) and
/// its derivatives, c[i] times the direction g (dA or dB on a segment, or zero).
template <std::size_t N>
struct StepForcing {
  std::array<double, kDopStages> a{};
  std::array<double, kDopStages> c{};
  Lanes<N> g;
};

/// One DOP853 step of (x, v) with its tangent (forward sensitivity) in N directions: the values
/// are those of dop853_step in double, operation for operation; the derivatives follow the same
/// stages linearised (the right-hand side by its partials, the stage sums by the same
/// coefficients). h has the derivative dh. Returns the new state; x's order-7 interpolant and its
/// derivatives go to xp, dxp.
template <std::size_t N, std::size_t... I>
[[gnu::always_inline]] inline void tangent_stages(
    const SloshingModel& m, const StepForcing<N>& fo, double h, const Lanes<N>& dh,
    const TangentState<N>& s, std::array<double, kDopStages>& kx,
    std::array<double, kDopStages>& kv, std::array<Lanes<N>, kDopStages>& dkx,
    std::array<Lanes<N>, kDopStages>& dkv, double& x_end, Lanes<N>& dx_end,
    std::index_sequence<I...>) {
  (
      [&] {
        constexpr std::size_t i = I + 1;
        using Seq = std::make_index_sequence<i>;
        const double sx = dop_impl::row_sum<kDopA, i>(kx, Seq{});
        const double sv = dop_impl::row_sum<kDopA, i>(kv, Seq{});
        const double xi = s.x + h * sx;
        const double vi = s.v + h * sv;
        const Lanes<N> dxi = s.dx + (dh * sx + h * dop_impl::row_sum<kDopA, i>(dkx, Seq{}));
        const Lanes<N> dvi = s.dv + (dh * sv + h * dop_impl::row_sum<kDopA, i>(dkv, Seq{}));
        if constexpr (i == 12) {
          x_end = xi;
          dx_end = dxi;
        }
        kx[i] = vi;
        dkx[i] = dvi;
        const RhsJet j = rhs_jet(m, xi, vi, fo.a[i]);
        kv[i] = j.f;
        dkv[i] = j.fx * dxi + j.fv * dvi + (j.fa * fo.c[i]) * fo.g;
      }(),
      ...);
}

template <std::size_t N>
[[gnu::always_inline]] inline void tangent_step(const SloshingModel& m, const StepForcing<N>& fo,
                                                double h, const Lanes<N>& dh, TangentState<N>& s,
                                                DensePoly<double>& xp,
                                                std::array<Lanes<N>, kDenseTerms>& dxp) {
  std::array<double, kDopStages> kx, kv;
  std::array<Lanes<N>, kDopStages> dkx, dkv;
  kx[0] = s.v;
  kv[0] = s.f;
  dkx[0] = s.dv;
  dkv[0] = s.df;
  double x1 = 0.0;
  Lanes<N> dx1;
  tangent_stages(m, fo, h, dh, s, kx, kv, dkx, dkv, x1, dx1, std::make_index_sequence<15>{});
  // x's interpolant, as dop853_step's (the stage rates of x are the stage values of v).
  using All = std::make_index_sequence<kDopStages>;
  const double dy = x1 - s.x;
  std::array<double, 7> F;
  F[0] = dy;
  F[1] = h * kx[0] - dy;
  F[2] = 2.0 * dy - h * (kx[12] + kx[0]);
  const std::array<double, 4> R{
      dop_impl::row_sum<kDopD, 0>(kx, All{}), dop_impl::row_sum<kDopD, 1>(kx, All{}),
      dop_impl::row_sum<kDopD, 2>(kx, All{}), dop_impl::row_sum<kDopD, 3>(kx, All{})};
  for (std::size_t r = 0; r < 4; ++r) F[3 + r] = h * R[r];
  xp = dop_impl::power_basis(s.x, F);
  const Lanes<N> ddy = dx1 - s.dx;
  std::array<Lanes<N>, 7> dF;
  dF[0] = ddy;
  dF[1] = (dh * kx[0] + h * dkx[0]) - ddy;
  dF[2] = 2.0 * ddy - (dh * (kx[12] + kx[0]) + h * (dkx[12] + dkx[0]));
  dF[3] = dh * R[0] + h * dop_impl::row_sum<kDopD, 0>(dkx, All{});
  dF[4] = dh * R[1] + h * dop_impl::row_sum<kDopD, 1>(dkx, All{});
  dF[5] = dh * R[2] + h * dop_impl::row_sum<kDopD, 2>(dkx, All{});
  dF[6] = dh * R[3] + h * dop_impl::row_sum<kDopD, 3>(dkx, All{});
  dxp = dop_impl::power_basis(s.dx, dF);
  s.x = x1;
  s.v = kx[12];
  s.f = kv[12];
  s.dx = dx1;
  s.dv = dkx[12];
  s.df = dkv[12];
}

/// The container acceleration on segment k at the fraction fr of it (ramps interpolate
/// linearly, exact for the constant-jerk law; plateaus hold A or -B) as value and the
/// coefficient of the segment's direction (dA on segments 0-2, dB on 4-6).
[[gnu::always_inline]] inline std::pair<double, double> segment_acceleration(double A, double B,
                                                                             std::size_t k,
                                                                             double fr) {
  switch (k) {
    case 0:
      return {A * fr, fr};
    case 1:
      return {A, 1.0};
    case 2:
      return {A * (1.0 - fr), 1.0 - fr};
    case 4:
      return {-(B * fr), -fr};
    case 5:
      return {-B, -1.0};
    case 6:
      return {-(B * (1.0 - fr)), -(1.0 - fr)};
    default:
      return {0.0, 0.0};
  }
}

Lanes8 lanes_of(const Dual7& a) {
  Lanes8 r;
  for (std::size_t i = 0; i < kSegments; ++i) r[i] = a.d[i];
  return r;
}

// Copies between the stored rows and the vectors (whole-vector moves, not lane by lane).
std::array<double, kLanes> array_of(const Lanes8& a) {
  std::array<double, kLanes> r;
  std::memcpy(r.data(), &a.v, sizeof r);
  return r;
}

Lanes8 from_array(const std::array<double, kLanes>& a) {
  Lanes8 r;
  std::memcpy(&r.v, a.data(), sizeof a);
  return r;
}

}  // namespace

/// The integration of compute(), one free function so that it can be cloned for AVX (its helpers
/// are inlined into it).
struct SensitivityPass {
  static void run(NonlinearSensitivity& s, const double* d, const PlateauLevelsT<Dual7>& lv);
  /// run() without the derivatives: the same values, a fraction of the work.
  static void run_values(NonlinearSensitivity& s, const double* d, double A, double B);
  struct Eta;

 private:
  /// The state at the end of the motion with its derivatives (N = kLanes, or none for N = 0),
  /// T and dT.
  template <std::size_t N>
  struct MotionEnd {
    TangentState<N> st;
    double t{};
    Lanes<N> dt;
  };
  template <std::size_t N>
  static void store(NonlinearSensitivity& s, double t0, const Lanes<N>& dt0, double h,
                    const Lanes<N>& dh, const DensePoly<double>& x,
                    const std::array<Lanes<N>, kDenseTerms>& dx);
  template <std::size_t N>
  static MotionEnd<N> motion(NonlinearSensitivity& s, const double* d, double A, double B,
                             const Lanes<N>& dA, const Lanes<N>& dB);
  template <std::size_t N>
  static void rest(NonlinearSensitivity& s, const MotionEnd<N>& end);
  template <std::size_t N>
  static void save_end(NonlinearSensitivity& s, const MotionEnd<N>& end);

 public:
  /// The rest window from the motion end saved by run() (NonlinearSensitivity::complete_rest).
  static void finish_rest(NonlinearSensitivity& s);
  static void finish_rest_values(NonlinearSensitivity& s);

 private:
  template <std::size_t N>
  static void finish(NonlinearSensitivity& s);
};

template <std::size_t N>
[[gnu::always_inline]] inline void SensitivityPass::store(
    NonlinearSensitivity& s, double t0, const Lanes<N>& dt0, double h, const Lanes<N>& dh,
    const DensePoly<double>& x, const std::array<Lanes<N>, kDenseTerms>& dx) {
  s.tv_.push_back(t0);
  s.hv_.push_back(h);
  s.xv_.push_back(x);
  if constexpr (N > 0) {
    s.dt_.push_back(array_of(dt0));
    s.dh_.push_back(array_of(dh));
    std::array<std::array<double, kLanes>, kDenseTerms> terms;
    for (std::size_t k = 0; k < kDenseTerms; ++k) terms[k] = array_of(dx[k]);
    s.dx_.push_back(terms);
  }
}

// The 7 segments, each in its equal steps; h_k = d_k / n_k moves with d_k, the acceleration with
// A (segments 0-2) or B (4-6).
template <std::size_t N>
[[gnu::always_inline]] inline SensitivityPass::MotionEnd<N> SensitivityPass::motion(
    NonlinearSensitivity& s, const double* d, double A, double B, const Lanes<N>& dA,
    const Lanes<N>& dB) {
  MotionEnd<N> e;
  TangentState<N>& st = e.st;
  DensePoly<double> xp;
  std::array<Lanes<N>, kDenseTerms> dxp;
  StepForcing<N> fo;
  for (std::size_t k = 0; k < kSegments; ++k) {
    // A segment of zero length still takes one (empty) step so that its derivatives (the flow
    // of the state over dT_k) are carried; NonlinearResponse skips it, the values agree.
    const std::size_t own = step_count(d[k], s.h_max_, 1);
    const std::size_t n = s.frozen_ ? std::max(own, s.steps_[k]) : own;
    const double inv_n = 1.0 / static_cast<double>(n);
    const double h = d[k] * inv_n;
    Lanes<N> dh;
    if constexpr (N > 0) dh[k] = inv_n;
    fo.g = k < 3 ? dA : k > 3 ? dB : Lanes<N>{};
    const double t_begin = e.t;
    const Lanes<N> dt_begin = e.dt;
    // As NonlinearResponse: the first stage of a segment is evaluated on that segment.
    const auto [a0, c0] = segment_acceleration(A, B, k, 0.0);
    const RhsJet j0 = rhs_jet(s.model_, st.x, st.v, a0);
    st.f = j0.f;
    st.df = j0.fx * st.dx + j0.fv * st.dv + (j0.fa * c0) * fo.g;
    for (std::size_t j = 0; j < n; ++j) {
      const double jd = static_cast<double>(j);
      for (std::size_t i = 1; i < kDopStages; ++i) {
        const auto [a, c] = segment_acceleration(A, B, k, (jd + kDopC[i]) * inv_n);
        fo.a[i] = a;
        fo.c[i] = c;
      }
      tangent_step(s.model_, fo, h, dh, st, xp, dxp);
      store(s, t_begin + h * jd, dt_begin + dh * jd, h, dh, xp, dxp);
    }
    e.t = t_begin + d[k];
    if constexpr (N > 0) e.dt[k] += 1.0;
  }
  return e;
}

// The rest window has no forcing: its states depend on the durations only through the state at
// T, so it is integrated with derivatives with respect to (x_T, v_T) and chained (a quarter of
// the work of carrying all 7 directions).
template <std::size_t N>
[[gnu::always_inline]] inline void SensitivityPass::rest(NonlinearSensitivity& s,
                                                         const MotionEnd<N>& end) {
  // Derivatives with respect to (x_T, v_T), or none.
  constexpr std::size_t M = N > 0 ? 2 : 0;
  const auto n_rest = step_count(s.rest_time_, s.h_max_, 1);
  const double h_rest = s.rest_time_ / static_cast<double>(n_rest);
  TangentState<M> r;
  r.x = end.st.x;
  r.v = end.st.v;
  if constexpr (M > 0) {
    r.dx[0] = 1.0;
    r.dv[1] = 1.0;
  }
  const RhsJet j0 = rhs_jet(s.model_, r.x, r.v, 0.0);
  r.f = j0.f;
  r.df = j0.fx * r.dx + j0.fv * r.dv;
  const StepForcing<M> rest_forcing{};
  const Lanes<M> no_dh;
  DensePoly<double> rp;
  std::array<Lanes<M>, kDenseTerms> drp;
  std::array<Lanes<N>, kDenseTerms> dxp;
  s.complete_ = true;
  for (std::size_t j = 0; j < n_rest; ++j) {
    if (j > 0 && end.t + h_rest * static_cast<double>(j) > s.until_) {
      s.complete_ = false;
      break;
    }
    tangent_step(s.model_, rest_forcing, h_rest, no_dh, r, rp, drp);
    if constexpr (N > 0) {
      for (std::size_t k = 0; k < kDenseTerms; ++k) {
        dxp[k] = drp[k][0] * end.st.dx + drp[k][1] * end.st.dv;
      }
    }
    store<N>(s, end.t + h_rest * static_cast<double>(j), end.dt, h_rest, Lanes<N>{}, rp, dxp);
  }
}

template <std::size_t N>
[[gnu::always_inline]] inline void SensitivityPass::save_end(NonlinearSensitivity& s,
                                                             const MotionEnd<N>& end) {
  s.motion_time_ = end.t;
  s.end_x_ = end.st.x;
  s.end_v_ = end.st.v;
  s.end_t_ = end.t;
  if constexpr (N > 0) {
    s.end_dx_ = array_of(end.st.dx);
    s.end_dv_ = array_of(end.st.dv);
    s.end_dt_ = array_of(end.dt);
  }
  s.motion_steps_ = s.tv_.size();
}

// flatten: every helper is inlined, so the AVX clone's lane loops are AVX as well.
SLOSH_TANGENT_CLONES [[gnu::flatten]] void SensitivityPass::run(NonlinearSensitivity& s,
                                                                const double* d,
                                                                const PlateauLevelsT<Dual7>& lv) {
  const MotionEnd<kLanes> end =
      motion<kLanes>(s, d, lv.A.v, lv.B.v, lanes_of(lv.A), lanes_of(lv.B));
  save_end(s, end);
  rest(s, end);
}

[[gnu::flatten]] void SensitivityPass::run_values(NonlinearSensitivity& s, const double* d,
                                                  double A, double B) {
  const MotionEnd<0> end = motion<0>(s, d, A, B, Lanes<0>{}, Lanes<0>{});
  save_end(s, end);
  rest(s, end);
}

template <std::size_t N>
[[gnu::always_inline]] inline void SensitivityPass::finish(NonlinearSensitivity& s) {
  MotionEnd<N> end;
  end.st.x = s.end_x_;
  end.st.v = s.end_v_;
  if constexpr (N > 0) {
    end.st.dx = from_array(s.end_dx_);
    end.st.dv = from_array(s.end_dv_);
    end.dt = from_array(s.end_dt_);
    s.dt_.resize(s.motion_steps_);
    s.dh_.resize(s.motion_steps_);
    s.dx_.resize(s.motion_steps_);
  }
  end.t = s.end_t_;
  s.tv_.resize(s.motion_steps_);
  s.hv_.resize(s.motion_steps_);
  s.xv_.resize(s.motion_steps_);
  s.until_ = INFINITY;
  rest(s, end);
}

SLOSH_TANGENT_CLONES [[gnu::flatten]] void SensitivityPass::finish_rest(NonlinearSensitivity& s) {
  finish<kLanes>(s);
}

[[gnu::flatten]] void SensitivityPass::finish_rest_values(NonlinearSensitivity& s) {
  finish<0>(s);
}

void NonlinearSensitivity::complete_rest() {
  if (complete_) return;
  if (gradients_) {
    SensitivityPass::finish_rest(*this);
  } else {
    SensitivityPass::finish_rest_values(*this);
  }
}

void NonlinearSensitivity::compute(const double* d, double until, bool gradients) {
  until_ = until;
  gradients_ = gradients;
  std::array<Dual7, kSegments> dd;
  for (std::size_t i = 0; i < kSegments; ++i) dd[i] = Dual7::variable(d[i], i);
  // The plateaus as duals either way: their values are the same bits as with derivatives.
  const auto lv = plateau_levels(dd, Dual7(stroke_));
  tv_.clear();
  hv_.clear();
  xv_.clear();
  dt_.clear();
  dh_.clear();
  dx_.clear();
  if (gradients) {
    SensitivityPass::run(*this, d, lv);
  } else {
    SensitivityPass::run_values(*this, d, lv.A.v, lv.B.v);
  }
}

Dual7 NonlinearSensitivity::x_at(std::size_t i, double t) const {
  // s = (t - t0) / h with t0 and h moving with the durations; then the interpolant at s.
  const double h = hv_[i];
  const auto& dt0 = dt_[i];
  const auto& dh = dh_[i];
  double s = 1.0;
  std::array<double, kSegments> ds{};
  if (h > 0.0) {
    const double inv = 1.0 / h;
    s = (t - tv_[i]) * inv;
    for (std::size_t l = 0; l < kSegments; ++l) ds[l] = (-dt0[l] - s * dh[l]) * inv;
  }
  const DensePoly<double>& p = xv_[i];
  const auto& dp = dx_[i];
  Dual7 r(p[kDenseTerms - 1]);
  std::copy_n(dp[kDenseTerms - 1].begin(), kSegments, r.d.begin());
  for (std::size_t k = kDenseTerms - 1; k > 0; --k) {
    const double rv = r.v;
    r.v = rv * s + p[k - 1];
    for (std::size_t l = 0; l < kSegments; ++l) r.d[l] = r.d[l] * s + rv * ds[l] + dp[k - 1][l];
  }
  return r;
}
/// The interpolant of step i at time t with its derivatives (x_at's operations lane by lane), and
/// the loop of abs_eta_at over the samples; one free function, cloned for AVX as the integration.
struct SensitivityPass::Eta {
  static void abs_at(const NonlinearSensitivity& s, const std::vector<double>& t,
                     std::vector<double>* values,
                     std::vector<std::array<double, kSegments>>* gradients);
};

SLOSH_TANGENT_CLONES [[gnu::flatten]] void SensitivityPass::Eta::abs_at(
    const NonlinearSensitivity& s, const std::vector<double>& t, std::vector<double>* values,
    std::vector<std::array<double, kSegments>>* gradients) {
  values->resize(t.size());
  if (gradients != nullptr) gradients->resize(t.size());
  const double t_last = s.tv_.back() + s.hv_.back();
  std::size_t i = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double tk = std::clamp(t[k], 0.0, t_last);
    // The step holding tk (the later of two at a shared end; empty steps are passed over).
    while (i + 1 < s.tv_.size() && (s.tv_[i] + s.hv_[i] < tk || s.hv_[i] <= 0.0)) ++i;
    const double h = s.hv_[i];
    double theta = 1.0;
    if (h > 0.0) theta = (tk - s.tv_[i]) * (1.0 / h);
    const DensePoly<double>& p = s.xv_[i];
    double rv = p[kDenseTerms - 1];
    for (std::size_t j = kDenseTerms - 1; j > 0; --j) rv = rv * theta + p[j - 1];
    const double sign = rv < 0.0 ? -1.0 : 1.0;
    (*values)[k] = s.model_.K * (sign * rv);
    if (gradients == nullptr) continue;
    // The same Horner scheme on the derivatives, with those of theta.
    Lanes8 ds;
    if (h > 0.0) {
      const double inv = 1.0 / h;
      ds = (Lanes8(0.0) - from_array(s.dt_[i]) - theta * from_array(s.dh_[i])) * inv;
    }
    const auto& dp = s.dx_[i];
    double pv = p[kDenseTerms - 1];
    Lanes8 rd = from_array(dp[kDenseTerms - 1]);
    for (std::size_t j = kDenseTerms - 1; j > 0; --j) {
      rd = (rd * theta + pv * ds) + from_array(dp[j - 1]);
      pv = pv * theta + p[j - 1];
    }
    const std::array<double, kLanes> g = array_of(s.model_.K * (sign * rd));
    std::copy_n(g.begin(), kSegments, (*gradients)[k].begin());
  }
}

void NonlinearSensitivity::abs_eta_at(const std::vector<double>& t, std::vector<double>* values,
                                      std::vector<std::array<double, kSegments>>* gradients) const {
  SensitivityPass::Eta::abs_at(*this, t, values, gradients);
}

WindowPeak NonlinearSensitivity::window_peak(double t_begin, double t_end) const {
  t_begin = std::max(t_begin, 0.0);
  t_end = std::min(t_end, tv_.back() + hv_.back());
  double best = -1.0;
  double best_time = t_begin;
  std::size_t best_step = 0;
  // First step that can hold t_begin.
  std::size_t i =
      static_cast<std::size_t>(std::upper_bound(tv_.begin(), tv_.end(), t_begin) - tv_.begin());
  i = i == 0 ? 0 : i - 1;
  for (; i < tv_.size() && tv_[i] <= t_end; ++i) {
    const double H = hv_[i];
    if (H <= 0.0 || !(dense_abs_bound(xv_[i]) > best)) continue;
    const double s_lo = std::max(0.0, (t_begin - tv_[i]) / H);
    const double s_hi = std::min(1.0, (t_end - tv_[i]) / H);
    const PolyMax m = dense_max_abs(xv_[i], s_lo, s_hi);
    if (m.value > best) {
      best = m.value;
      best_time = tv_[i] + m.s * H;
      best_step = i;
    }
  }
  WindowPeak out;
  out.time = best_time;
  if (!gradients_) {
    // The value x_at would give (the same operations), without derivatives.
    const double h = hv_[best_step];
    const double s = h > 0.0 ? (best_time - tv_[best_step]) * (1.0 / h) : 1.0;
    out.value = model_.K * std::abs(dense_value(xv_[best_step], s));
    out.gradient.fill(0.0);
    return out;
  }
  Dual7 xs = x_at(best_step, best_time);
  if (xs.v < 0.0) xs = -xs;
  out.value = model_.K * xs.v;
  out.time = best_time;
  for (std::size_t k = 0; k < kSegments; ++k) out.gradient[k] = model_.K * xs.d[k];
  return out;
}

}  // namespace slosh::detail
