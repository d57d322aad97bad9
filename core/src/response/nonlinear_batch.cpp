// nonlinear_peaks of several models side by side (the robustness report's frequency sweep).
//
// Every lane runs exactly the integration of nonlinear_peaks on its own model: its own step grid
// (the steps follow each lane's period), its own early end of the rest window. The lanes advance
// in lockstep by step index, so the DOP853 stages of all lanes are one loop over a small fixed
// array that the compiler vectorises; each lane's arithmetic is the scalar path's, operation for
// operation (no reassociation, no fused multiply-add: the clone built for AVX has no FMA), so
// every lane's peaks equal nonlinear_peaks' bit for bit. A lane that diverges or leaves the
// model's range is answered by nonlinear_peaks itself (its fine fallback grid).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "response/nonlinear_scheme.hpp"
#include "slosh/core/response/response.hpp"

// One clone of the lane loops for AVX (4 doubles a vector, no FMA, so the results are those of
// the baseline SSE2 clone bit for bit) chosen at load time where the CPU has it.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SLOSH_LANE_CLONES __attribute__((target_clones("avx", "default")))
#else
#define SLOSH_LANE_CLONES
#endif

namespace slosh {

namespace {

/// Lanes integrated side by side [-]: three AVX vectors of doubles, three independent chains of
/// stages (each stage waits for the division of the one before; the report's 20 points take two
/// rounds, measured faster than 4, 8, 10 or 16 lanes).
constexpr std::size_t kLanes{12};

/// A round with fewer models runs on the narrowest of these widths that holds them (the report's
/// 20 points: 12 + 8 lanes, not 12 + 12 with 4 idle ones integrating nothing). A lane's arithmetic
/// does not depend on the width, so the peaks are the same bit for bit.
constexpr std::size_t kNarrowLanes{8};
constexpr std::size_t kNarrowestLanes{4};

template <std::size_t N>
using LaneArray = std::array<double, N>;

/// The model parameters of eq. 2.35 per lane, and one step's inputs and outputs (N lanes).
template <std::size_t N>
struct LaneStep {
  LaneArray<N> w{}, zeta{}, c2{}, alpha{}, radius{};   // model
  LaneArray<N> x{}, v{}, f0{}, h{};                    // state at the step start, step [s]
  std::array<LaneArray<N>, detail::kDopStages> acc{};  // a(t0 + c_i h) [m/s^2]
  LaneArray<N> x1{}, v1{}, f1{};                       // state at the step end
  detail::DensePoly<LaneArray<N>> x_poly{};            // xbar(t0 + theta h), power basis
};

/// nonlinear_rhs of lane l, the same operations in the same order.
template <std::size_t N>
[[gnu::always_inline]] inline double lane_rhs(const LaneStep<N>& s, std::size_t l, double x,
                                              double v, double a) {
  const double w = s.w[l];
  const double c2 = s.c2[l];
  const double c2x2 = c2 * x * x;
  const double num = 2.0 * w * s.zeta[l] * v * (1.0 + c2x2) + c2 * x * v * v +
                     w * w * x * (1.0 + s.alpha[l] * x * x) + a / s.radius[l];
  return -num / (1.0 + c2x2);
}

/// sum_j table[R][j] k[j][l] over the non-zero coefficients, as dop_impl::row_sum.
template <const auto& kTable, std::size_t R, std::size_t N, std::size_t... J>
[[gnu::always_inline]] inline double lane_row_sum(
    const std::array<LaneArray<N>, detail::kDopStages>& k, std::size_t l,
    std::index_sequence<J...>) {
  double sum = 0.0;
  ((kTable[R][J] != 0.0 ? (void)(sum = sum + kTable[R][J] * k[J][l]) : (void)0), ...);
  return sum;
}

template <std::size_t N, std::size_t... I>
[[gnu::always_inline]] inline void lane_stages(LaneStep<N>& s,
                                               std::array<LaneArray<N>, detail::kDopStages>& kx,
                                               std::array<LaneArray<N>, detail::kDopStages>& kv,
                                               std::index_sequence<I...>) {
  (
      [&] {
        constexpr std::size_t i = I + 1;
        for (std::size_t l = 0; l < N; ++l) {
          const double xi = s.x[l] + s.h[l] * lane_row_sum<detail::kDopA, i>(
                                                  kx, l, std::make_index_sequence<i>{});
          const double vi = s.v[l] + s.h[l] * lane_row_sum<detail::kDopA, i>(
                                                  kv, l, std::make_index_sequence<i>{});
          if constexpr (i == 12) s.x1[l] = xi;
          kx[i][l] = vi;
          kv[i][l] = lane_rhs(s, l, xi, vi, s.acc[i][l]);
        }
      }(),
      ...);
}

// dop_impl::times_theta, times_one_minus_theta and q[0] += a, lane by lane.
template <std::size_t Deg, std::size_t N>
[[gnu::always_inline]] inline void lane_times_theta(detail::DensePoly<LaneArray<N>>& q) {
  for (std::size_t k = Deg + 1; k > 0; --k) q[k] = q[k - 1];
  q[0].fill(0.0);
}
template <std::size_t Deg, std::size_t N>
[[gnu::always_inline]] inline void lane_times_one_minus_theta(detail::DensePoly<LaneArray<N>>& q) {
  for (std::size_t k = Deg + 1; k > 0; --k) {
    for (std::size_t l = 0; l < N; ++l) q[k][l] = q[k][l] - q[k - 1][l];
  }
}
template <std::size_t N>
[[gnu::always_inline]] inline void lane_add(detail::DensePoly<LaneArray<N>>& q,
                                            const LaneArray<N>& a) {
  for (std::size_t l = 0; l < N; ++l) q[0][l] = q[0][l] + a[l];
}

/// One DOP853 step of every lane with the interpolant of xbar (dop853_step with dense output and
/// dense_rate false, lane by lane); the body of the lane_step overloads below.
template <std::size_t N>
[[gnu::always_inline]] inline void lane_step_body(LaneStep<N>& s) {
  std::array<LaneArray<N>, detail::kDopStages> kx, kv;
  kx[0] = s.v;
  kv[0] = s.f0;
  lane_stages(s, kx, kv, std::make_index_sequence<15>{});
  s.v1 = kx[12];
  s.f1 = kv[12];
  std::array<LaneArray<N>, 7> F;
  for (std::size_t l = 0; l < N; ++l) {
    const double h = s.h[l];
    const double dy = s.x1[l] - s.x[l];
    F[0][l] = dy;
    F[1][l] = h * kx[0][l] - dy;
    F[2][l] = 2.0 * dy - h * (kx[12][l] + kx[0][l]);
    F[3][l] =
        h * lane_row_sum<detail::kDopD, 0>(kx, l, std::make_index_sequence<detail::kDopStages>{});
    F[4][l] =
        h * lane_row_sum<detail::kDopD, 1>(kx, l, std::make_index_sequence<detail::kDopStages>{});
    F[5][l] =
        h * lane_row_sum<detail::kDopD, 2>(kx, l, std::make_index_sequence<detail::kDopStages>{});
    F[6][l] =
        h * lane_row_sum<detail::kDopD, 3>(kx, l, std::make_index_sequence<detail::kDopStages>{});
  }
  // dop_impl::power_basis lane by lane, the same operations in the same order.
  detail::DensePoly<LaneArray<N>>& q = s.x_poly;
  for (LaneArray<N>& c : q) c.fill(0.0);
  q[0] = F[6];
  lane_times_theta<0>(q);
  lane_add(q, F[5]);
  lane_times_one_minus_theta<1>(q);
  lane_add(q, F[4]);
  lane_times_theta<2>(q);
  lane_add(q, F[3]);
  lane_times_one_minus_theta<3>(q);
  lane_add(q, F[2]);
  lane_times_theta<4>(q);
  lane_add(q, F[1]);
  lane_times_one_minus_theta<5>(q);
  lane_add(q, F[0]);
  lane_times_theta<6>(q);
  lane_add(q, s.x);
}

// One function per width, each cloned for AVX (a template cannot carry target_clones).
SLOSH_LANE_CLONES void lane_step(LaneStep<kLanes>& s) {
  lane_step_body(s);
}
SLOSH_LANE_CLONES void lane_step(LaneStep<kNarrowLanes>& s) {
  lane_step_body(s);
}
SLOSH_LANE_CLONES void lane_step(LaneStep<kNarrowestLanes>& s) {
  lane_step_body(s);
}

/// Where one lane is on its grid.
struct LaneCursor {
  bool active{false};
  bool fallback{false};  // diverged or left the model's range: answered by nonlinear_peaks
  std::size_t piece{};   // index into the law's pieces, then the rest window
  std::size_t j{}, n{};  // step within the piece, steps of the piece
  double h{};
  const LawPiece* p{};
  bool in_rest{false};
  bool rest_found{false};
  double K{}, h_max{};
  SloshPeaks peaks;
};

/// Loads models[first + l] into lane l (its parameters, its step bound, a cursor before its first
/// piece); lanes past the last model stay inactive.
template <std::size_t N>
void load_lanes(const std::vector<SloshingModel>& models, std::size_t first,
                const NonlinearOptions& options, LaneStep<N>& s, std::array<LaneCursor, N>& cur) {
  for (std::size_t l = 0; l < N && first + l < models.size(); ++l) {
    const SloshingModel& m = models[first + l];
    s.w[l] = m.omega1();
    s.zeta[l] = m.zeta;
    s.c2[l] = m.C * m.C;
    s.alpha[l] = m.alpha;
    s.radius[l] = m.radius;
    const double period = 2.0 * std::numbers::pi / s.w[l];
    cur[l].active = true;
    cur[l].K = m.K;
    cur[l].h_max = std::min(options.max_step, period / options.steps_per_period);
    cur[l].piece = std::numeric_limits<std::size_t>::max();  // before the first piece
  }
  for (std::size_t l = 0; l < N; ++l) {
    if (cur[l].active) continue;
    // Idle lanes integrate a harmless model at rest.
    s.w[l] = s.radius[l] = 1.0;
  }
}

/// Sets every lane's step length and stage accelerations for its next step (an ended lane
/// integrates zeros); false when no lane is left. Inlined: it runs once per step.
template <std::size_t N>
[[gnu::always_inline]] inline bool load_step_inputs(LaneStep<N>& s,
                                                    const std::array<LaneCursor, N>& cur) {
  bool any = false;
  for (std::size_t l = 0; l < N; ++l) {
    const LaneCursor& c = cur[l];
    if (!c.active) {
      s.x[l] = s.v[l] = s.f0[l] = s.h[l] = 0.0;
      for (auto& a : s.acc) a[l] = 0.0;
      continue;
    }
    any = true;
    s.h[l] = c.h;
    const double tau = c.h * static_cast<double>(c.j);
    if (c.in_rest) {
      for (std::size_t i = 1; i < detail::kDopStages; ++i) s.acc[i][l] = 0.0;
    } else if (c.p->harmonic_omega == 0.0) {
      // LawPiece::acceleration's polynomial, the same operations, without its per-call branch
      // and loads: the 15 stages become a loop the compiler vectorises.
      const std::array<double, 4> q = c.p->poly;
      std::array<double, detail::kDopStages> a;
      for (std::size_t i = 1; i < detail::kDopStages; ++i) {
        const double t = tau + detail::kDopC[i] * c.h;
        a[i] = q[0] + t * (q[1] + t * (q[2] + t * q[3]));
      }
      for (std::size_t i = 1; i < detail::kDopStages; ++i) s.acc[i][l] = a[i];
    } else {
      for (std::size_t i = 1; i < detail::kDopStages; ++i) {
        s.acc[i][l] = c.p->acceleration(tau + detail::kDopC[i] * c.h);
      }
    }
  }
  return any;
}

/// Raises lane l's window peak to the step's maximum of K |xbar| (nonlinear_peaks' search: the
/// cheap bound of the polynomial skips the steps that cannot hold a new peak).
template <std::size_t N>
[[gnu::always_inline]] inline void raise_lane_peak(const LaneStep<N>& s, std::size_t l,
                                                   Peak& window, double K, double t0, double h) {
  detail::DensePoly<double> xp;
  for (std::size_t k = 0; k < detail::kDenseTerms; ++k) xp[k] = s.x_poly[k][l];
  if (K * detail::dense_abs_bound(xp) > window.value) {
    const detail::PolyMax m = detail::dense_max_abs(xp, 0.0, 1.0);
    if (K * m.value > window.value) window = {K * m.value, t0 + m.s * h};
  }
}

/// K times the largest |xbar| lane l's free motion from (x, v) can reach (nonlinear_peaks' energy
/// bound, the same operations): the rest window ends once it cannot exceed the peak found.
template <std::size_t N>
[[gnu::always_inline]] inline double lane_free_motion_bound(const LaneStep<N>& s, std::size_t l,
                                                            double K, double x, double v) {
  const double w = s.w[l];
  const double e =
      (0.5 * (1.0 + s.c2[l] * x * x) * v * v + w * w * x * x * (0.5 + 0.25 * s.alpha[l] * x * x)) /
      (w * w);
  return K * std::sqrt(2.0 * e / (0.5 + std::sqrt(0.25 + s.alpha[l] * e)));
}

/// Each lane's peaks into out[first + l]; a lane that diverged or left the model's range is
/// answered by nonlinear_peaks itself (its fine fallback grid).
template <std::size_t N>
void store_lanes(const std::vector<SloshingModel>& models, std::size_t first, const MotionLaw& law,
                 double rest_time, const NonlinearOptions& options, const LaneStep<N>& s,
                 const std::array<LaneCursor, N>& cur, std::vector<SloshPeaks>& out) {
  for (std::size_t l = 0; l < N && first + l < models.size(); ++l) {
    const LaneCursor& c = cur[l];
    const double top = std::max(c.peaks.motion.value, c.peaks.rest.value);
    if (c.fallback || !std::isfinite(s.x[l]) || !std::isfinite(s.v[l]) ||
        !(top <= detail::kModelRange * c.K)) {
      out[first + l] = nonlinear_peaks(models[first + l], law, rest_time, options);
    } else {
      out[first + l] = c.peaks;
    }
  }
}

/// Integrates up to N models (models[first + l]) side by side into out[first + l].
template <std::size_t N>
void run_lanes(const std::vector<SloshingModel>& models, std::size_t first, const MotionLaw& law,
               double rest_time, const NonlinearOptions& options, std::vector<SloshPeaks>& out) {
  const std::vector<LawPiece>& pieces = law.pieces();
  const std::size_t n_pieces = pieces.size() + 1;
  const double T = law.duration();
  const LawPiece rest{T, T + rest_time};
  LaneStep<N> s;
  std::array<LaneCursor, N> cur;
  load_lanes(models, first, options, s, cur);

  // Moves lane l to its next piece of positive length (or ends it).
  auto next_piece = [&](std::size_t l) {
    LaneCursor& c = cur[l];
    for (++c.piece; c.piece < n_pieces; ++c.piece) {
      c.in_rest = c.piece + 1 == n_pieces;
      c.p = c.in_rest ? &rest : &pieces[c.piece];
      const double L = c.p->duration();
      if (!(L > 0.0)) continue;
      const double hp =
          detail::piece_max_step(c.h_max, c.p->harmonic_omega, options.steps_per_period);
      c.n = step_count(L, hp, 1);
      c.h = L / static_cast<double>(c.n);
      c.j = 0;
      // The acceleration may jump at a piece start: the first stage is evaluated on this piece.
      s.f0[l] = lane_rhs(s, l, s.x[l], s.v[l], c.in_rest ? 0.0 : c.p->acceleration(0.0));
      return;
    }
    c.active = false;
  };
  for (std::size_t l = 0; l < N; ++l) {
    if (cur[l].active) next_piece(l);
  }

  while (load_step_inputs(s, cur)) {
    lane_step(s);
    for (std::size_t l = 0; l < N; ++l) {
      LaneCursor& c = cur[l];
      if (!c.active) continue;
      const double h = c.h;
      const double t0 = c.p->t_begin + h * static_cast<double>(c.j);
      raise_lane_peak(s, l, c.in_rest ? c.peaks.rest : c.peaks.motion, c.K, t0, h);
      const double x = s.x1[l], v = s.v1[l];
      s.x[l] = x;
      s.v[l] = v;
      s.f0[l] = s.f1[l];
      if (c.in_rest &&
          lane_free_motion_bound(s, l, c.K, x, v) * (1.0 + detail::kEnergyStopMargin) <=
              c.peaks.rest.value) {
        c.active = false;
        continue;
      }
      if (!std::isfinite(x)) {
        c.fallback = true;
        c.active = false;
        continue;
      }
      if (++c.j == c.n) next_piece(l);
    }
  }
  store_lanes(models, first, law, rest_time, options, s, cur, out);
}

}  // namespace

std::vector<SloshPeaks> nonlinear_peaks(const std::vector<SloshingModel>& models,
                                        const MotionLaw& law, double rest_time,
                                        const NonlinearOptions& options) {
  std::vector<SloshPeaks> out(models.size());
  for (std::size_t first = 0; first < models.size(); first += kLanes) {
    const std::size_t left = models.size() - first;
    if (left <= kNarrowestLanes) {
      run_lanes<kNarrowestLanes>(models, first, law, rest_time, options, out);
    } else if (left <= kNarrowLanes) {
      run_lanes<kNarrowLanes>(models, first, law, rest_time, options, out);
    } else {
      run_lanes<kLanes>(models, first, law, rest_time, options, out);
    }
  }
  return out;
}

}  // namespace slosh
