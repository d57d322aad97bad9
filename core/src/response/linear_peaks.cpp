// Peaks of the exact linear response, found on the same sample grid as find_max() (<= 1 ms and
// <= 1/64 of the fastest period, both window ends included) with the same candidate rule, but
// sampled piece by piece by complex rotation and refined by Newton's method on the exact
// derivatives instead of golden sections on libm calls.
//
// On one law piece, with tau = t - t_begin, mode m is
//   x_m(tau) = p_m(tau) + h_m(tau) + Re(Z_m exp(lambda_m tau)),  lambda_m = -sigma_m + i wd_m,
// with Z_m = c1 - i c2, a cubic p_m and a harmonic h_m at the piece's single frequency W. So
//   eta(tau) = sum_m g_m p_m(tau) + sum_m g_m h_m(tau) + sum_m Re(g_m Z_m exp(lambda_m tau)):
// one cubic and one harmonic (their coefficients summed over the modes once per piece) plus one
// complex rotation z <- z E_m, E_m = exp(lambda_m h), per mode and sample. Each piece re-anchors
// the rotations at its first sample from the closed form, so the round-off of the rotations
// (about one ulp of |Z| per step) never carries over a breakpoint.
//
// The rest window ends early by the energy bound: after T the forcing is zero, and every mode's
// energy E_m = (x_m'^2 + w_m^2 x_m^2) / 2 has dE_m/dt = -2 zeta w_m x_m'^2 <= 0, so for every
// s >= t, |x_m(s)| <= sqrt(2 E_m(s)) / w_m <= sqrt(2 E_m(t)) / w_m and
//   |eta(s)| <= B(t) = sum_m |g_m| sqrt(x_m(t)^2 + (x_m'(t) / w_m)^2).
// B never increases. Once B(t_i) is at most the best sample so far, no later sample and no later
// refined peak can exceed the peak already found, and the scan stops (docs/models.md).

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "plain_complex.hpp"
#include "sincos.hpp"
#include "slosh/core/constants.hpp"
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

/// Newton steps below this are converged [s] (a few ulp of t near 1 s).
constexpr double kNewtonTolerance{1e-14};

/// Largest number of safeguarded Newton steps per candidate (bisection halves the bracket at
/// worst, so 60 steps reach the round-off of the bracket's ends).
constexpr int kMaxNewtonSteps{60};

/// The rest window's energy bound is tested every this many samples [-] (its square roots cost
/// as much as a sample; stopping up to this many samples late costs little).
constexpr std::size_t kBoundStride{8};

/// eta and its first two time derivatives at one instant.
struct EtaJet {
  double eta{}, d1{}, d2{};
};

/// x, x', x'' of one under-damped mode piece at tau.
EtaJet mode_jet(const LinearModePiece& p, double tau) {
  EtaJet j;
  j.eta = p.r[0] + tau * (p.r[1] + tau * (p.r[2] + tau * p.r[3]));
  j.d1 = p.r[1] + tau * (2.0 * p.r[2] + tau * 3.0 * p.r[3]);
  j.d2 = 2.0 * p.r[2] + 6.0 * p.r[3] * tau;
  if (p.W != 0.0) {
    const detail::SinCos sc = detail::fast_sincos(p.W * tau);
    const double W = p.W;
    const double a = p.P * sc.cos + p.Q * sc.sin;  // P cos + Q sin
    const double da = W * (p.Q * sc.cos - p.P * sc.sin);
    const double u = p.U * sc.cos + p.V * sc.sin;  // U cos + V sin
    const double du = W * (p.V * sc.cos - p.U * sc.sin);
    j.eta += a + tau * u;
    j.d1 += da + u + tau * du;
    j.d2 += -W * W * a + 2.0 * du - tau * W * W * u;
  }
  // Homogeneous part Re(Z e^{lambda tau}), Z = c1 - i c2.
  const detail::Complex lambda{-p.sigma, p.wd};
  const detail::Complex z =
      detail::Complex{p.c1, -p.c2} * detail::decay_rotation(p.sigma, p.wd, tau);
  const detail::Complex dz = lambda * z;
  const detail::Complex d2z = lambda * dz;
  j.eta += z.re;
  j.d1 += dz.re;
  j.d2 += d2z.re;
  return j;
}

/// Linear scans side by side [-]: one AVX vector of doubles.
constexpr std::size_t kScanLanes{4};

/// The state of kScanLanes scans on one piece, lane l of every field at [l] (the rotations of
/// mode m at [m][l]), so that each operation of a sample is one vector operation over the lanes.
struct ScanLanes {
  std::array<double, kScanLanes> r0{}, r1{}, r2{}, r3{}, P{}, Q{}, U{}, V{};
  std::array<double, kScanLanes> hre{}, him{}, hsre{}, hsim{};  // exp(i W tau), exp(i W h)
  std::array<std::array<double, kScanLanes>, kMaxModes> zre{}, zim{}, sre{}, sim{};
  std::array<double, kScanLanes> best{};
  std::array<bool, kScanLanes> harmonic{}, free{};
};

#if defined(__GNUC__)
/// kScanLanes doubles, one per lane: every operation on it is the lanes' IEEE operation side by
/// side (two SSE2 or one AVX instruction).
using LaneVector = double __attribute__((vector_size(8 * kScanLanes)));
using LaneBits = long long __attribute__((vector_size(8 * kScanLanes)));

// The helpers below are always inlined into the lane clones, so no vector crosses a call (the
// ABI warning is about such calls).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
[[gnu::always_inline]] inline LaneVector load(const std::array<double, kScanLanes>& a) {
  LaneVector v;
  __builtin_memcpy(&v, a.data(), sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store(LaneVector v, std::array<double, kScanLanes>& a) {
  __builtin_memcpy(a.data(), &v, sizeof v);
}

/// One more step of every mode's rotation: z <- z exp(lambda h) (the complex product's operations).
SLOSH_LANE_CLONES void rotate_lanes(ScanLanes& s, std::size_t modes) {
  for (std::size_t m = 0; m < modes; ++m) {
    const LaneVector zr = load(s.zre[m]), zi = load(s.zim[m]);
    const LaneVector sr = load(s.sre[m]), si = load(s.sim[m]);
    store(zr * sr - zi * si, s.zre[m]);
    store(zr * si + zi * sr, s.zim[m]);
  }
}

/// Samples i0 .. i0 + count - 1 (count <= kBoundStride) of every lane on one piece starting at
/// `begin`, |eta| of lane l written to values[i kScanLanes + l]: the operations of
/// sample_modes(), in its order, per lane. The summed cubic of a free piece is zero, so it adds
/// exactly what sample_modes()' 0.0 does. The rotations advance after every sample but the last
/// unless rotate_last (the energy bound is then tested on them first).
SLOSH_LANE_CLONES void scan_block(ScanLanes& s, std::size_t modes, bool harmonic, double a,
                                  double b, double h, std::size_t n, double begin, std::size_t i0,
                                  std::size_t count, bool rotate_last, double* values) {
  std::array<LaneVector, kBoundStride> e;
  std::array<double, kBoundStride> tau{};
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t i = i0 + j;
    tau[j] = (i == n ? b : a + h * static_cast<double>(i)) - begin;
  }
  {
    const LaneVector r0 = load(s.r0), r1 = load(s.r1), r2 = load(s.r2), r3 = load(s.r3);
    for (std::size_t j = 0; j < count; ++j) {
      const double t = tau[j];
      e[j] = r0 + t * (r1 + t * (r2 + t * r3));
    }
  }
  if (harmonic) {
    const LaneVector P = load(s.P), Q = load(s.Q), U = load(s.U), V = load(s.V);
    const LaneVector sr = load(s.hsre), si = load(s.hsim);
    LaneVector hr = load(s.hre), hi = load(s.him);
    for (std::size_t j = 0; j < count; ++j) {
      const double t = tau[j];
      e[j] += P * hr + Q * hi + t * (U * hr + V * hi);
      const LaneVector re = hr * sr - hi * si;
      const LaneVector im = hr * si + hi * sr;
      hr = re;
      hi = im;
    }
    store(hr, s.hre);
    store(hi, s.him);
  }
  for (std::size_t m = 0; m < modes; ++m) {
    LaneVector zr = load(s.zre[m]), zi = load(s.zim[m]);
    const LaneVector sr = load(s.sre[m]), si = load(s.sim[m]);
    for (std::size_t j = 0; j < count; ++j) {
      e[j] += zr;
      if (j + 1 == count && !rotate_last) break;
      const LaneVector re = zr * sr - zi * si;
      const LaneVector im = zr * si + zi * sr;
      zr = re;
      zi = im;
    }
    store(zr, s.zre[m]);
    store(zi, s.zim[m]);
  }
  constexpr long long kMagnitude = 0x7fffffffffffffffLL;  // every bit but the sign
  LaneVector best = load(s.best);
  for (std::size_t j = 0; j < count; ++j) {
    const LaneVector v =
        reinterpret_cast<LaneVector>(reinterpret_cast<LaneBits>(e[j]) & kMagnitude);
    __builtin_memcpy(values + (i0 + j) * kScanLanes, &v, sizeof v);
    best = best < v ? v : best;  // std::max(best, v)
  }
  store(best, s.best);
}
#pragma GCC diagnostic pop
#else
#error "the linear report lanes need GCC or Clang vector extensions"
#endif

}  // namespace

namespace detail {

/// The sampled-and-refined peak search of one window, for a response whose modes are all
/// under-damped.
class LinearPeakScan {
 public:
  LinearPeakScan(const std::vector<double>& gains, const std::vector<double>& piece_begin,
                 const std::vector<LinearModePiece>& coefficients)
      : gains_(gains), begin_(piece_begin), coef_(coefficients), modes_(gains.size()) {}

  /// max |eta| on [a, b] sampled at spacing <= step (as find_max()); `rest` allows the early
  /// end by the energy bound (only valid where the forcing is zero).
  Peak window(double a, double b, double step, bool rest) const {
    if (!(b > a)) return {std::abs(eta(a)), a};
    const auto n = static_cast<std::size_t>(std::ceil((b - a) / step));
    const double h = (b - a) / static_cast<double>(n);
    std::vector<double> values;
    values.reserve(n + 1);
    const std::size_t last = sample(a, b, h, n, rest, values);
    return pick(a, b, h, n, last, values.data(), 1, values.size(),
                rest ? curvature_bound(a) : INFINITY);
  }

  /// eta, eta', eta'' at t (0 for t <= 0, where the model is at rest).
  [[nodiscard]] EtaJet jet(double t) const {
    if (t <= 0.0) return {};
    const std::size_t k = piece_index(t);
    const double tau = t - begin_[k];
    EtaJet e;
    for (std::size_t m = 0; m < modes_; ++m) {
      const EtaJet j = mode_jet(coef_[k * modes_ + m], tau);
      e.eta += gains_[m] * j.eta;
      e.d1 += gains_[m] * j.d1;
      e.d2 += gains_[m] * j.d2;
    }
    return e;
  }

 private:
  [[nodiscard]] double eta(double t) const { return jet(t).eta; }

  [[nodiscard]] std::size_t piece_index(double t) const {
    const auto it = std::upper_bound(begin_.begin(), begin_.end(), t);
    return static_cast<std::size_t>(it - begin_.begin()) - 1;
  }

  /// Fills values[i] = |eta(t_i)|, t_i = a + h i (t_n = b), walking the pieces; returns the
  /// index of the last sample taken (n, or earlier when the energy bound ends a rest window).
  std::size_t sample(double a, double b, double h, std::size_t n, bool rest,
                     std::vector<double>& values) const {
    // The mode count as a constant: the rotations then live in registers, not in memory (each
    // sample's rotation would otherwise wait for the store of the previous one).
    switch (modes_) {
      case 1:
        return sample_modes<1>(a, b, h, n, rest, values);
      case 2:
        return sample_modes<2>(a, b, h, n, rest, values);
      case 3:
        return sample_modes<3>(a, b, h, n, rest, values);
      case 4:
        return sample_modes<4>(a, b, h, n, rest, values);
      case 5:
        return sample_modes<5>(a, b, h, n, rest, values);
      // Two directions of a rectangular tank side by side (LinearResponse::combined).
      case 6:
        return sample_modes<6>(a, b, h, n, rest, values);
      case 7:
        return sample_modes<7>(a, b, h, n, rest, values);
      case 8:
        return sample_modes<8>(a, b, h, n, rest, values);
      case 9:
        return sample_modes<9>(a, b, h, n, rest, values);
      default:
        return sample_modes<2 * kMaxModes>(a, b, h, n, rest, values);
    }
  }

  /// The particular part of one piece summed over the modes (one cubic r0..r3, one harmonic
  /// P cos + Q sin + tau (U cos + V sin) at the piece's frequency W), and the harmonic's
  /// rotation anchored at the piece's first sample: set up once per piece, so that each sample
  /// costs one cubic, one harmonic rotation and one rotation per mode.
  struct PieceSum {
    double r0{}, r1{}, r2{}, r3{}, P{}, Q{}, U{}, V{};
    bool harmonic{}, free{};        // free: no forcing on the piece (the energy bound applies)
    detail::Complex hz{}, hstep{};  // exp(i W tau) at the current sample, exp(i W h)
  };

  /// PieceSum of the M modes c[0..M) (the summation order is the samplers' own), with the
  /// homogeneous rotations z_m = g_m Z_m exp(lambda_m tau0) re-anchored at tau0 from the closed
  /// form. Inlined into the samplers so their registers and code stay what they were.
  template <std::size_t M>
  [[gnu::always_inline]] PieceSum piece_sum(const LinearModePiece* c, double tau0, double h,
                                            std::array<detail::Complex, M>& z) const {
    PieceSum q;
    const double W = c[0].W;
    for (std::size_t m = 0; m < M; ++m) {
      const double g = gains_[m];
      q.r0 += g * c[m].r[0];
      q.r1 += g * c[m].r[1];
      q.r2 += g * c[m].r[2];
      q.r3 += g * c[m].r[3];
      q.P += g * c[m].P;
      q.Q += g * c[m].Q;
      q.U += g * c[m].U;
      q.V += g * c[m].V;
    }
    q.harmonic = W != 0.0;
    q.free = !q.harmonic && q.r0 == 0.0 && q.r1 == 0.0 && q.r2 == 0.0 && q.r3 == 0.0;
    for (std::size_t m = 0; m < M; ++m) {
      const detail::Complex rot = detail::decay_rotation(c[m].sigma, c[m].wd, tau0);
      z[m] = detail::Complex{gains_[m] * c[m].c1, -gains_[m] * c[m].c2} * rot;
    }
    if (q.harmonic) {
      const SinCos s0 = fast_sincos(W * tau0);
      q.hz = {s0.cos, s0.sin};
      const SinCos sh = fast_sincos(W * h);
      q.hstep = {sh.cos, sh.sin};
    }
    return q;
  }

  /// Rotation of every mode over one step, and the modes' natural frequencies |lambda_m| (the
  /// energy bound's scale): the same on every piece, so computed once per window.
  template <std::size_t M>
  [[gnu::always_inline]] void step_rotations(double h,
                                             std::array<detail::Complex, M>& step_rotation,
                                             std::array<double, M>& omega) const {
    for (std::size_t m = 0; m < M; ++m) {
      const LinearModePiece& p = coef_[m];
      step_rotation[m] = detail::decay_rotation(p.sigma, p.wd, h);
      omega[m] = std::sqrt(p.sigma * p.sigma + p.wd * p.wd);
    }
  }

  template <std::size_t M>
  std::size_t sample_modes(double a, double b, double h, std::size_t n, bool rest,
                           std::vector<double>& values) const {
    auto t_of = [&](std::size_t i) { return i == n ? b : a + h * static_cast<double>(i); };
    std::array<detail::Complex, M> step_rotation{}, z{};
    std::array<double, M> omega{};
    step_rotations<M>(h, step_rotation, omega);
    std::size_t i = 0;
    double best = -INFINITY;
    const std::size_t pieces = begin_.size();
    std::size_t k = 0;
    while (i <= n) {
      double t = t_of(i);
      if (t <= 0.0) {  // at rest before the motion starts
        values.push_back(0.0);
        best = std::max(best, 0.0);
        ++i;
        continue;
      }
      while (k + 1 < pieces && begin_[k + 1] <= t) ++k;
      const double next = k + 1 < pieces ? begin_[k + 1] : INFINITY;
      const LinearModePiece* c = &coef_[k * modes_];
      PieceSum q = piece_sum<M>(c, t - begin_[k], h, z);
      std::size_t since_bound = 0;
      for (; i <= n; ++i) {
        t = t_of(i);
        if (t >= next) break;
        double e = 0.0;
        if (!q.free) {
          const double tau = t - begin_[k];
          e = q.r0 + tau * (q.r1 + tau * (q.r2 + tau * q.r3));
          if (q.harmonic) {
            e += q.P * q.hz.re + q.Q * q.hz.im + tau * (q.U * q.hz.re + q.V * q.hz.im);
            q.hz = q.hz * q.hstep;
          }
        }
        for (std::size_t m = 0; m < M; ++m) e += z[m].re;
        const double v = std::abs(e);
        values.push_back(v);
        best = std::max(best, v);
        if (rest && q.free && ++since_bound == kBoundStride) {
          since_bound = 0;
          if (energy_bound(z, c, omega) <= best) {
            // One sample more, so the last sample of the scan has its right neighbour.
            if (i < n) values.push_back(std::abs(eta(t_of(i + 1))));
            return i;
          }
        }
        for (std::size_t m = 0; m < M; ++m) z[m] = z[m] * step_rotation[m];
      }
    }
    return n;
  }

 public:
  /// window() of every scan in `scans` (at most kLanes, all with `modes` modes, the same piece
  /// starts) over one grid, the scans side by side as the lanes of one vector: out[l] equals
  /// scans[l]->window(a, b, step, rest) bit for bit (each lane does its own sample()'s
  /// operations in the same order, without fused multiply-adds).
  static void window_lanes(std::size_t modes, const std::vector<const LinearPeakScan*>& scans,
                           double a, double b, double step, bool rest, std::vector<Peak>& out) {
    const std::size_t lanes = scans.size();
    out.resize(lanes);
    if (!(b > a)) {
      for (std::size_t l = 0; l < lanes; ++l) out[l] = {std::abs(scans[l]->eta(a)), a};
      return;
    }
    const auto n = static_cast<std::size_t>(std::ceil((b - a) / step));
    const double h = (b - a) / static_cast<double>(n);
    // Sample i of lane l at values[i kLanes + l]; left uninitialised (only written entries are
    // read), since the rest window's grid runs to the end of the rest time.
    std::unique_ptr<double[]> values(new double[(n + 2) * kLanes]);
    std::array<std::size_t, kLanes> last{};
    sample_lanes(scans, modes, a, b, h, n, rest, values.get(), last);
    for (std::size_t l = 0; l < lanes; ++l) {
      const std::size_t count = last[l] == n ? n + 1 : last[l] + 2;
      out[l] = scans[l]->pick(a, b, h, n, last[l], values.get() + l, kLanes, count,
                              rest ? scans[l]->curvature_bound(a) : INFINITY);
    }
  }

  /// Scans side by side per vector [-].
  static constexpr std::size_t kLanes{kScanLanes};

 private:
  /// The PieceSum of lane l's piece c (piece_sum with the mode count as a constant), written into
  /// the lanes' state.
  template <std::size_t M>
  void load_piece(const LinearModePiece* c, double tau0, double h, ScanLanes& s,
                  std::size_t l) const {
    std::array<detail::Complex, M> z{};
    const PieceSum q = piece_sum<M>(c, tau0, h, z);
    s.r0[l] = q.r0;
    s.r1[l] = q.r1;
    s.r2[l] = q.r2;
    s.r3[l] = q.r3;
    // A lane without the harmonic adds exactly +0 (its samples are finite), as if it had none.
    s.P[l] = q.harmonic ? q.P : 0.0;
    s.Q[l] = q.harmonic ? q.Q : 0.0;
    s.U[l] = q.harmonic ? q.U : 0.0;
    s.V[l] = q.harmonic ? q.V : 0.0;
    s.hre[l] = q.harmonic ? q.hz.re : 1.0;
    s.him[l] = q.harmonic ? q.hz.im : 0.0;
    s.hsre[l] = q.harmonic ? q.hstep.re : 1.0;
    s.hsim[l] = q.harmonic ? q.hstep.im : 0.0;
    s.harmonic[l] = q.harmonic;
    s.free[l] = q.free;
    for (std::size_t m = 0; m < M; ++m) {
      s.zre[m][l] = z[m].re;
      s.zim[m][l] = z[m].im;
    }
  }

  void load_piece(std::size_t modes, const LinearModePiece* c, double tau0, double h, ScanLanes& s,
                  std::size_t l) const {
    switch (modes) {
      case 1:
        return load_piece<1>(c, tau0, h, s, l);
      case 2:
        return load_piece<2>(c, tau0, h, s, l);
      case 3:
        return load_piece<3>(c, tau0, h, s, l);
      case 4:
        return load_piece<4>(c, tau0, h, s, l);
      default:
        return load_piece<kMaxModes>(c, tau0, h, s, l);
    }
  }

  /// The first sample index in [i, n + 1) at or after `next` on the grid t_i = a + h i (t_n = b),
  /// n + 1 when none (t_i increases with i): estimated, then corrected onto the exact comparison.
  static std::size_t first_sample_from(double next, double a, double b, double h, std::size_t n,
                                       std::size_t i) {
    auto t_of = [&](std::size_t j) { return j == n ? b : a + h * static_cast<double>(j); };
    if (!(next <= b)) return n + 1;
    const double guess = std::ceil((next - a) / h);
    std::size_t end = guess <= static_cast<double>(i)       ? i
                      : guess >= static_cast<double>(n + 1) ? n + 1
                                                            : static_cast<std::size_t>(guess);
    while (end > i && t_of(end - 1) >= next) --end;
    while (end <= n && t_of(end) < next) ++end;
    return end;
  }

  /// energy_bound() of lane l (the same operations).
  static double lane_energy_bound(const ScanLanes& s, std::size_t l, std::size_t modes,
                                  const LinearModePiece* c,
                                  const std::array<double, kMaxModes>& omega) {
    double bound = 0.0;
    for (std::size_t m = 0; m < modes; ++m) {
      const double x = s.zre[m][l];
      const double v = (-c[m].sigma * s.zre[m][l] - c[m].wd * s.zim[m][l]) / omega[m];
      bound += std::sqrt(x * x + v * v);
    }
    return bound;
  }

  /// sample_modes() of every lane, the samples of lane l written to values[i kLanes + l]; the
  /// sample after a lane's early end is its exact |eta| (as sample_modes() appends it), later
  /// entries of that lane are not read.
  static void sample_lanes(const std::vector<const LinearPeakScan*>& scans, std::size_t modes,
                           double a, double b, double h, std::size_t n, bool rest, double* values,
                           std::array<std::size_t, kLanes>& last) {
    const std::size_t lanes = scans.size();
    auto t_of = [&](std::size_t i) { return i == n ? b : a + h * static_cast<double>(i); };
    ScanLanes s{};
    std::array<std::array<double, kMaxModes>, kLanes> omega{};
    for (std::size_t l = 0; l < lanes; ++l) {
      for (std::size_t m = 0; m < modes; ++m) {
        const LinearModePiece& p = scans[l]->coef_[m];
        const detail::Complex r = detail::decay_rotation(p.sigma, p.wd, h);
        s.sre[m][l] = r.re;
        s.sim[m][l] = r.im;
        omega[l][m] = std::sqrt(p.sigma * p.sigma + p.wd * p.wd);
      }
    }
    s.best.fill(-INFINITY);
    last.fill(n);
    std::array<bool, kLanes> stopped{};
    std::size_t running = lanes;
    auto finish = [&] {
      for (std::size_t l = 0; l < lanes; ++l) {
        if (last[l] < n)
          values[(last[l] + 1) * kLanes + l] = std::abs(scans[l]->eta(t_of(last[l] + 1)));
      }
    };
    const std::vector<double>& begin = scans[0]->begin_;
    const std::size_t pieces = begin.size();
    std::size_t i = 0;
    std::size_t k = 0;
    while (i <= n) {
      const double t = t_of(i);
      if (t <= 0.0) {  // at rest before the motion starts
        for (std::size_t l = 0; l < kLanes; ++l) {
          values[i * kLanes + l] = 0.0;
          s.best[l] = std::max(s.best[l], 0.0);
        }
        ++i;
        continue;
      }
      while (k + 1 < pieces && begin[k + 1] <= t) ++k;
      const double next = k + 1 < pieces ? begin[k + 1] : INFINITY;
      std::array<const LinearModePiece*, kLanes> c{};
      for (std::size_t l = 0; l < lanes; ++l) {
        c[l] = &scans[l]->coef_[k * modes];
        scans[l]->load_piece(modes, c[l], t - begin[k], h, s, l);
      }
      const bool harmonic =
          std::any_of(s.harmonic.begin(), s.harmonic.begin() + lanes, [](bool x) { return x; });
      const std::size_t end = first_sample_from(next, a, b, h, n, i);
      // Blocks of kBoundStride samples from the piece's first, the energy bound tested after
      // each full block where a running lane is free (sample_modes()' every kBoundStride-th).
      while (i < end) {
        const std::size_t count = std::min(kBoundStride, end - i);
        bool test = false;
        if (rest && count == kBoundStride) {
          for (std::size_t l = 0; l < lanes; ++l) test = test || (s.free[l] && !stopped[l]);
        }
        scan_block(s, modes, harmonic, a, b, h, n, begin[k], i, count, !test, values);
        i += count;
        if (!test) continue;
        for (std::size_t l = 0; l < lanes; ++l) {
          if (stopped[l] || !s.free[l]) continue;
          if (lane_energy_bound(s, l, modes, c[l], omega[l]) <= s.best[l]) {
            last[l] = i - 1;
            stopped[l] = true;
            --running;
          }
        }
        if (running == 0) return finish();
        rotate_lanes(s, modes);
      }
    }
    finish();
  }

 private:
  /// B(t) = sum_m |g_m| sqrt(x_m^2 + (x_m' / w_m)^2) on a free piece, from the rotations
  /// z_m = g_m Z_m exp(lambda_m tau) (so g_m x_m = Re z_m, g_m x_m' = Re(lambda_m z_m)).
  template <std::size_t M>
  [[nodiscard]] static double energy_bound(const std::array<detail::Complex, M>& z,
                                           const LinearModePiece* c,
                                           const std::array<double, M>& omega) {
    double bound = 0.0;
    for (std::size_t m = 0; m < M; ++m) {
      const double x = z[m].re;
      const double v = (-c[m].sigma * z[m].re - c[m].wd * z[m].im) / omega[m];
      bound += std::sqrt(x * x + v * v);
    }
    return bound;
  }

  /// A bound on |eta''| over [t, end of the response] when no forcing acts from t on (the rest
  /// window), else infinity. There eta = sum_m Re z_m with z_m = g_m Z_m exp(lambda_m tau), so
  /// |eta''| <= sum_m |lambda_m|^2 |z_m(s)| <= sum_m w_m^2 |z_m(t)| for every s >= t (|z_m| only
  /// decays); the factor 1 + 1e-6 covers the round-off of the closed form.
  [[nodiscard]] double curvature_bound(double t) const {
    if (!(t > 0.0)) return INFINITY;
    const std::size_t k = piece_index(t);
    const double tau = t - begin_[k];
    double bound = 0.0;
    for (std::size_t m = 0; m < modes_; ++m) {
      const LinearModePiece& p = coef_[k * modes_ + m];
      if (p.damping != LinearModePiece::Damping::kUnder || p.W != 0.0 || p.r[0] != 0.0 ||
          p.r[1] != 0.0 || p.r[2] != 0.0 || p.r[3] != 0.0 || p.P != 0.0 || p.Q != 0.0 ||
          p.U != 0.0 || p.V != 0.0) {
        return INFINITY;
      }
      const double z = std::abs(gains_[m]) * std::hypot(p.c1, p.c2) * std::exp(-p.sigma * tau);
      bound += (p.sigma * p.sigma + p.wd * p.wd) * z;
    }
    return std::isfinite(bound) ? bound * (1.0 + 1e-6) : INFINITY;
  }

  /// find_max()'s candidate rule over samples 0..last, sample i at values[i stride] (`count`
  /// samples: last + 1, or one more, the right neighbour of the last).
  ///
  /// With `curvature` a bound on |eta''| over the window, the candidate with the largest sample
  /// is refined first, and a candidate whose bracket cannot hold more is not refined: at the
  /// maximum t* of |eta| inside a bracket eta'(t*) = 0 and the nearest sample is at most h/2
  /// away, so |eta(t*)| <= (largest of the bracket's samples) + curvature h^2 / 8. Leaving out
  /// candidates strictly below the best found changes nothing (the first of the largest wins).
  Peak pick(double a, double b, double h, std::size_t n, std::size_t last, const double* values,
            std::size_t stride, std::size_t count, double curvature) const {
    auto t_of = [&](std::size_t i) { return i == n ? b : a + h * static_cast<double>(i); };
    auto value = [&](std::size_t i) { return values[i * stride]; };
    double best_sample = value(0);  // as std::max_element: the first of the largest
    for (std::size_t i = 1; i < count; ++i) {
      if (best_sample < value(i)) best_sample = value(i);
    }
    const double threshold = best_sample - kRefineFraction * std::abs(best_sample);
    // 0: not a candidate, 1: a flat candidate, 2: a candidate to refine.
    auto kind = [&](std::size_t i) {
      if (value(i) < threshold) return 0;
      const bool left_ok = i == 0 || value(i) >= value(i - 1);
      const bool right_ok = i == n || value(i) >= value(i + 1);
      if (!left_ok || !right_ok) return 0;
      const bool flat =
          (i == 0 || value(i) == value(i - 1)) && (i == n || value(i) == value(i + 1));
      return flat ? 1 : 2;
    };
    auto refined = [&](std::size_t i) {
      const double lo = t_of(i == 0 ? 0 : i - 1);
      const double hi = t_of(std::min(i + 1, n));
      Peak p = refine(lo, hi, t_of(i));
      if (value(i) > p.value) p = {value(i), t_of(i)};
      return p;
    };
    constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    std::size_t first = kNone;
    Peak first_peak;
    const double slack = curvature * h * h / 8.0;
    if (std::isfinite(slack)) {
      for (std::size_t i = 0; i <= last; ++i) {
        if (kind(i) == 2 && (first == kNone || value(i) > value(first))) first = i;
      }
      if (first != kNone) first_peak = refined(first);
    }
    Peak best{value(0), a};
    if (last == n && value(n) > best.value) best = {value(n), b};
    for (std::size_t i = 0; i <= last; ++i) {
      const int k = kind(i);
      if (k == 0) continue;
      if (k == 1) {
        if (value(i) > best.value) best = {value(i), t_of(i)};
        continue;
      }
      Peak p;
      if (i == first) {
        p = first_peak;
      } else {
        if (first != kNone) {
          const double top =
              std::max({value(i == 0 ? 0 : i - 1), value(i), value(std::min(i + 1, n))});
          // The relative 1e-9 covers the samples' round-off (the rotations drift by ulps).
          if ((top + slack) * (1.0 + 1e-9) < first_peak.value) continue;
        }
        p = refined(i);
      }
      if (p.value > best.value) best = p;
    }
    return best;
  }

  /// The maximum of |eta| in [lo, hi] around the sample at t0: a safeguarded Newton iteration on
  /// s eta' = 0 (s the sign of eta there) when s eta' falls from positive to negative across the
  /// bracket; otherwise (the maximum sits at a bracket end, or the bracket holds more than one
  /// extremum) the golden section of find_max().
  [[nodiscard]] Peak refine(double lo, double hi, double t0) const {
    const EtaJet j0 = jet(t0);
    const double s = j0.eta < 0.0 ? -1.0 : 1.0;
    const double g_lo = s * jet(lo).d1;
    const double g_hi = s * jet(hi).d1;
    if (!(g_lo > 0.0 && g_hi < 0.0) || j0.eta == 0.0) {
      return refine_max([this](double t) { return std::abs(eta(t)); }, lo, hi);
    }
    double t = t0;
    EtaJet j = j0;
    for (int it = 0; it < kMaxNewtonSteps; ++it) {
      const double g = s * j.d1;
      if (g > 0.0)
        lo = t;
      else if (g < 0.0)
        hi = t;
      else
        break;
      const double dg = s * j.d2;
      double next = dg < 0.0 ? t - g / dg : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      const double moved = std::abs(next - t);
      t = next;
      j = jet(t);
      if (moved < kNewtonTolerance || hi - lo < kNewtonTolerance) break;
    }
    return {std::abs(j.eta), t};
  }

  /// find_max()'s default refine_fraction.
  static constexpr double kRefineFraction{0.05};

  const std::vector<double>& gains_;
  const std::vector<double>& begin_;
  const std::vector<LinearModePiece>& coef_;
  std::size_t modes_;
};

}  // namespace detail

std::vector<SloshPeaks> LinearResponse::peaks_of(const std::vector<LinearResponse>& responses) {
  std::vector<SloshPeaks> out(responses.size());
  // Lanes: responses that share the sample grid, the piece starts and the mode count, all modes
  // under-damped (the others take peaks() alone).
  auto lane_ready = [](const LinearResponse& r) {
    return !r.gains_.empty() && r.gains_.size() <= kMaxModes &&
           std::all_of(r.coefficients_.begin(), r.coefficients_.end(),
                       [](const LinearModePiece& p) {
                         return p.damping == LinearModePiece::Damping::kUnder;
                       });
  };
  std::vector<detail::LinearPeakScan> scans;
  scans.reserve(responses.size());
  for (const LinearResponse& r : responses)
    scans.emplace_back(r.gains_, r.piece_begin_, r.coefficients_);
  std::vector<bool> done(responses.size(), false);
  for (std::size_t i = 0; i < responses.size(); ++i) {
    if (done[i]) continue;
    const LinearResponse& r = responses[i];
    if (!lane_ready(r)) {
      out[i] = r.peaks();
      done[i] = true;
      continue;
    }
    std::vector<std::size_t> group{i};
    for (std::size_t j = i + 1;
         j < responses.size() && group.size() < detail::LinearPeakScan::kLanes; ++j) {
      const LinearResponse& q = responses[j];
      if (done[j] || !lane_ready(q) || q.peak_step_ != r.peak_step_ ||
          q.motion_time_ != r.motion_time_ || q.end_time_ != r.end_time_ ||
          q.gains_.size() != r.gains_.size() || q.piece_begin_ != r.piece_begin_) {
        continue;
      }
      group.push_back(j);
    }
    std::vector<const detail::LinearPeakScan*> lanes;
    for (std::size_t j : group) {
      lanes.push_back(&scans[j]);
      done[j] = true;
    }
    std::vector<Peak> motion, rest;
    using Scan = detail::LinearPeakScan;
    Scan::window_lanes(r.gains_.size(), lanes, 0.0, r.motion_time_, r.peak_step_, false, motion);
    Scan::window_lanes(r.gains_.size(), lanes, r.motion_time_, r.end_time_, r.peak_step_, true,
                       rest);
    for (std::size_t g = 0; g < group.size(); ++g) out[group[g]] = {motion[g], rest[g]};
  }
  return out;
}

SloshPeaks LinearResponse::peaks() const {
  const bool under_damped = std::all_of(
      coefficients_.begin(), coefficients_.end(),
      [](const LinearModePiece& p) { return p.damping == LinearModePiece::Damping::kUnder; });
  if (!under_damped || gains_.empty() || gains_.size() > 2 * kMaxModes) {
    auto abs_eta = [this](double t) { return std::abs(eta(t)); };
    return {find_max(abs_eta, 0.0, motion_time_, peak_step_),
            find_max(abs_eta, motion_time_, end_time_, peak_step_)};
  }
  const detail::LinearPeakScan scan(gains_, piece_begin_, coefficients_);
  return {scan.window(0.0, motion_time_, peak_step_, false),
          scan.window(motion_time_, end_time_, peak_step_, true)};
}

}  // namespace slosh
