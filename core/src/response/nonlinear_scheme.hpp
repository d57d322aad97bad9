#pragma once
// The numerical scheme of the nonlinear model, shared by NonlinearResponse (doubles),
// NonlinearSensitivity (dual numbers over the durations) and CalibrationResponse (dual numbers
// over the model parameters), so all integrate exactly the same discrete response (internal to
// the core).
//
// The scheme is the explicit Runge-Kutta method of Dormand and Prince of order 8 with its
// order-7 dense output (DOP853), taken with fixed steps: on every law piece the container
// acceleration is smooth, so the piece is cut into equal steps of at most a fixed fraction of
// the period and no step crosses a piece boundary (where the jerk, or the acceleration, jumps and
// the order would be lost). Coefficients: E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary
// Differential Equations I", 2nd ed., Springer 1993, sec. II.5 and II.6 (Dormand and Prince's
// 8(5,3) pair, table of the authors' code DOP853, version of 1996-10-11, and its dense output
// "CONTD8" with the three extra stages).

#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

#include "slosh/core/model/sloshing_model.hpp"

namespace slosh::detail {

/// xbar'' of eq. 2.35 for the container acceleration a [m/s^2], any scalar type.
template <typename S, typename A>
S nonlinear_rhs(const SloshingModel& m, const S& x, const S& v, const A& a) {
  const double w = m.omega1();
  const double c2 = m.C * m.C;
  const S c2x2 = c2 * x * x;
  const S num = 2.0 * w * m.zeta * v * (1.0 + c2x2) + c2 * x * v * v +
                w * w * x * (1.0 + m.alpha * x * x) + a / m.radius;
  return -num / (1.0 + c2x2);
}

/// Stages of one DOP853 step: 12 for the step, the 13th is f at the step end (first stage of the
/// next step), 14..16 serve the dense output only.
inline constexpr std::size_t kDopStages{16};

/// Nodes c_i (fraction of the step where stage i evaluates the forcing).
inline constexpr std::array<double, kDopStages> kDopC{0.0,
                                                      0.526001519587677318785587544488e-01,
                                                      0.789002279381515978178381316732e-01,
                                                      0.118350341907227396726757197510,
                                                      0.281649658092772603273242802490,
                                                      0.333333333333333333333333333333,
                                                      0.25,
                                                      0.307692307692307692307692307692,
                                                      0.651282051282051282051282051282,
                                                      0.6,
                                                      0.857142857142857142857142857142,
                                                      1.0,
                                                      1.0,
                                                      0.1,
                                                      0.2,
                                                      0.777777777777777777777777777778};

/// Runge-Kutta matrix a_ij (row 12 holds the weights b_j of the order-8 solution).
inline constexpr std::array<std::array<double, kDopStages>, kDopStages> kDopA{{
    {},
    {5.26001519587677318785587544488e-2},
    {1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2},
    {2.95875854768068491816892993775e-2, 0.0, 8.87627564304205475450678981324e-2},
    {2.41365134159266685502369798665e-1, 0.0, -8.84549479328286085344864962717e-1,
     9.24834003261792003115737966543e-1},
    {3.7037037037037037037037037037e-2, 0.0, 0.0, 1.70828608729473871279604482173e-1,
     1.25467687566822425016691814123e-1},
    {3.7109375e-2, 0.0, 0.0, 1.70252211019544039314978060272e-1, 6.02165389804559606850219397283e-2,
     -1.7578125e-2},
    {3.70920001185047927108779319836e-2, 0.0, 0.0, 1.70383925712239993810214054705e-1,
     1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
     8.27378916381402288758473766002e-3},
    {6.24110958716075717114429577812e-1, 0.0, 0.0, -3.36089262944694129406857109825,
     -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
     2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1},
    {4.77662536438264365890433908527e-1, 0.0, 0.0, -2.48811461997166764192642586468,
     -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
     1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
     -2.03312017085086261358222928593e-2},
    {-9.3714243008598732571704021658e-1, 0.0, 0.0, 5.18637242884406370830023853209,
     1.09143734899672957818500254654, -8.14978701074692612513997267357,
     -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
     2.49360555267965238987089396762, -3.0467644718982195003823669022},
    {2.27331014751653820792359768449, 0.0, 0.0, -1.05344954667372501984066689879e1,
     -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
     2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
     -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
     6.43392746015763530355970484046e-1},
    {5.42937341165687622380535766363e-2, 0.0, 0.0, 0.0, 0.0, 4.45031289275240888144113950566,
     1.89151789931450038304281599044, -5.8012039600105847814672114227,
     3.1116436695781989440891606237e-1, -1.52160949662516078556178806805e-1,
     2.01365400804030348374776537501e-1, 4.47106157277725905176885569043e-2},
    {5.61675022830479523392909219681e-2, 0.0, 0.0, 0.0, 0.0, 0.0,
     2.53500210216624811088794765333e-1, -2.46239037470802489917441475441e-1,
     -1.24191423263816360469010140626e-1, 1.5329179827876569731206322685e-1,
     8.20105229563468988491666602057e-3, 7.56789766054569976138603589584e-3, -8.298e-3},
    {3.18346481635021405060768473261e-2, 0.0, 0.0, 0.0, 0.0, 2.83009096723667755288322961402e-2,
     5.35419883074385676223797384372e-2, -5.49237485713909884646569340306e-2, 0.0, 0.0,
     -1.08347328697249322858509316994e-4, 3.82571090835658412954920192323e-4,
     -3.40465008687404560802977114492e-4, 1.41312443674632500278074618366e-1},
    {-4.28896301583791923408573538692e-1, 0.0, 0.0, 0.0, 0.0, -4.69762141536116384314449447206,
     7.68342119606259904184240953878, 4.06898981839711007970213554331,
     3.56727187455281109270669543021e-1, 0.0, 0.0, 0.0, -1.39902416515901462129418009734e-3,
     2.9475147891527723389556272149, -9.15095847217987001081870187138},
}};

/// Dense-output coefficients d_ij of the 4 highest terms of the order-7 interpolant.
inline constexpr std::array<std::array<double, kDopStages>, 4> kDopD{{
    {-0.84289382761090128651353491142e1, 0.0, 0.0, 0.0, 0.0, 0.56671495351937776962531783590,
     -0.30689499459498916912797304727e1, 0.23846676565120698287728149680e1,
     0.21170345824450282767155149946e1, -0.87139158377797299206789907490,
     0.22404374302607882758541771650e1, 0.63157877876946881815570249290,
     -0.88990336451333310820698117400e-1, 0.18148505520854727256656404962e2,
     -0.91946323924783554000451984436e1, -0.44360363875948939664310572000e1},
    {0.10427508642579134603413151009e2, 0.0, 0.0, 0.0, 0.0, 0.24228349177525818288430175319e3,
     0.16520045171727028198505394887e3, -0.37454675472269020279518312152e3,
     -0.22113666853125306036270938578e2, 0.77334326684722638389603898808e1,
     -0.30674084731089398182061213626e2, -0.93321305264302278729567221706e1,
     0.15697238121770843886131091075e2, -0.31139403219565177677282850411e2,
     -0.93529243588444783865713862664e1, 0.35816841486394083752465898540e2},
    {0.19985053242002433820987653617e2, 0.0, 0.0, 0.0, 0.0, -0.38703730874935176555105901742e3,
     -0.18917813819516756882830838328e3, 0.52780815920542364900561016686e3,
     -0.11573902539959630126141871134e2, 0.68812326946963000169666922661e1,
     -0.10006050966910838403183860980e1, 0.77771377980534432092869265740,
     -0.27782057523535084065932004339e1, -0.60196695231264120758267380846e2,
     0.84320405506677161018159903784e2, 0.11992291136182789328035130030e2},
    {-0.25693933462703749003312586129e2, 0.0, 0.0, 0.0, 0.0, -0.15418974869023643374053993627e3,
     -0.23152937917604549567536039109e3, 0.35763911791061412378285349910e3,
     0.93405324183624310003907691704e2, -0.37458323136451633156875139351e2,
     0.10409964950896230045147246184e3, 0.29840293426660503123344363579e2,
     -0.43533456590011143754432175058e2, 0.96324553959188282948394950600e2,
     -0.39177261675615439165231486172e2, -0.14972683625798562581422125276e3},
}};

/// Degree of the dense output in theta [-].
inline constexpr std::size_t kDenseTerms{8};

/// Largest |xbar| the fast paths answer for [-]: a fluid displacement of the container radius,
/// far beyond the model's range (plans stay below 0.3). Beyond it nonlinear_peaks answers on its
/// fine low-order grid, and the batch hands the lane to it.
inline constexpr double kModelRange{1.0};

/// Relative margin of the rest window's stopping test: the bound is that of the exact solution
/// from the integrated state, the integrated trajectory departs from it by far less (< 1e-7 of
/// the peak), so a later integrated maximum cannot exceed the one found.
inline constexpr double kEnergyStopMargin{1e-6};

/// A polynomial in the step fraction theta in [0, 1]: sum c_k theta^k.
template <typename S>
using DensePoly = std::array<S, kDenseTerms>;

/// One DOP853 step of (x, v): the end state and the interpolants of x and v over the step.
template <typename S>
struct DopStep {
  S x1, v1;  ///< state at the step end
  S f1;      ///< xbar'' at the step end (the next step's first stage when the forcing is smooth)
  DensePoly<S> x_poly, v_poly;  ///< x(t0 + theta h), v(t0 + theta h), power basis in theta
};

namespace dop_impl {

// sum_j a_rj k_j over the non-zero coefficients of row R (the zero tests are constants: the
// dead products are not compiled, which matters for dual numbers).
template <const auto& kTable, std::size_t R, typename S, std::size_t... J>
S row_sum(const std::array<S, kDopStages>& k, std::index_sequence<J...>) {
  S sum(0.0);
  ((kTable[R][J] != 0.0 ? (void)(sum = sum + kTable[R][J] * k[J]) : (void)0), ...);
  return sum;
}

template <typename S, typename Rhs, typename Acc, std::size_t... I>
void stages(const Rhs& rhs, const Acc& acc, const S& x, const S& v, const S& h,
            std::array<S, kDopStages>& kx, std::array<S, kDopStages>& kv, S& x_end,
            std::index_sequence<I...>) {
  // Stage i = I + 1: kx_i = v_i (the state's rate), kv_i = f(x_i, v_i, a(t0 + c_i h)).
  (
      [&] {
        constexpr std::size_t i = I + 1;
        const S xi = x + h * row_sum<kDopA, i>(kx, std::make_index_sequence<i>{});
        const S vi = v + h * row_sum<kDopA, i>(kv, std::make_index_sequence<i>{});
        if constexpr (i == 12) x_end = xi;  // row 12 holds the weights: the order-8 solution
        kx[i] = vi;
        kv[i] = rhs(xi, vi, acc(i));
      }(),
      ...);
}

// q <- theta q and q <- (1 - theta) q for q of degree Deg (a constant, so the shifts unroll into
// register moves instead of a memmove per step).
template <std::size_t Deg, typename S>
void times_theta(DensePoly<S>& q) {
  for (std::size_t k = Deg + 1; k > 0; --k) q[k] = q[k - 1];
  q[0] = S(0.0);
}
template <std::size_t Deg, typename S>
void times_one_minus_theta(DensePoly<S>& q) {
  for (std::size_t k = Deg + 1; k > 0; --k) q[k] = q[k] - q[k - 1];
}

// y0 + theta (F0 + (1 - theta) (F1 + theta (F2 + (1 - theta) (F3 + theta (F4 + (1 - theta)
// (F5 + theta F6)))))) expanded to the power basis in theta.
template <typename S>
DensePoly<S> power_basis(const S& y0, const std::array<S, 7>& F) {
  DensePoly<S> q;
  for (S& c : q) c = S(0.0);
  q[0] = F[6];
  times_theta<0>(q);
  q[0] = q[0] + F[5];
  times_one_minus_theta<1>(q);
  q[0] = q[0] + F[4];
  times_theta<2>(q);
  q[0] = q[0] + F[3];
  times_one_minus_theta<3>(q);
  q[0] = q[0] + F[2];
  times_theta<4>(q);
  q[0] = q[0] + F[1];
  times_one_minus_theta<5>(q);
  q[0] = q[0] + F[0];
  times_theta<6>(q);
  q[0] = q[0] + y0;
  return q;
}

}  // namespace dop_impl

/// One DOP853 step of x'' = rhs(x, x', a) from (x, v) with f0 = rhs at the start, step h.
/// `acc(i)` is the container acceleration at t0 + kDopC[i] h (called for i = 1..15; any type
/// rhs accepts). With `dense` false the three extra stages and the interpolants are skipped;
/// with `dense_rate` false only x's interpolant is built (v_poly is left as it was).
template <typename S, typename Rhs, typename Acc>
void dop853_step(const Rhs& rhs, const Acc& acc, const S& x, const S& v, const S& f0, const S& h,
                 bool dense, DopStep<S>& out, bool dense_rate = true) {
  std::array<S, kDopStages> kx, kv;
  kx[0] = v;
  kv[0] = f0;
  S x_end(0.0);
  if (dense) {
    dop_impl::stages(rhs, acc, x, v, h, kx, kv, x_end, std::make_index_sequence<15>{});
  } else {
    dop_impl::stages(rhs, acc, x, v, h, kx, kv, x_end, std::make_index_sequence<12>{});
  }
  out.x1 = x_end;
  out.v1 = kx[12];
  out.f1 = kv[12];
  if (!dense) return;
  auto interpolant = [&](const S& y0, const S& y1, const std::array<S, kDopStages>& k) {
    std::array<S, 7> F;
    const S dy = y1 - y0;
    F[0] = dy;
    F[1] = h * k[0] - dy;
    F[2] = 2.0 * dy - h * (k[12] + k[0]);
    F[3] = h * dop_impl::row_sum<kDopD, 0>(k, std::make_index_sequence<kDopStages>{});
    F[4] = h * dop_impl::row_sum<kDopD, 1>(k, std::make_index_sequence<kDopStages>{});
    F[5] = h * dop_impl::row_sum<kDopD, 2>(k, std::make_index_sequence<kDopStages>{});
    F[6] = h * dop_impl::row_sum<kDopD, 3>(k, std::make_index_sequence<kDopStages>{});
    return dop_impl::power_basis(y0, F);
  };
  out.x_poly = interpolant(x, out.x1, kx);
  if (dense_rate) out.v_poly = interpolant(v, out.v1, kv);
}

/// p(theta) by Horner, any scalar type.
template <typename S, typename T>
S dense_value(const DensePoly<S>& p, const T& theta) {
  S r = p[kDenseTerms - 1];
  for (std::size_t k = kDenseTerms - 1; k > 0; --k) r = r * theta + p[k - 1];
  return r;
}

/// The largest |p(s)| over s in [lo, hi] (0 <= lo <= hi <= 1) and where: the ends and every
/// extremum inside, located as a root of p' (sign changes of p' on 4 sub-intervals, each root
/// refined by Newton's method kept inside its bracket). `value` is -1 when lo > hi.
struct PolyMax {
  double value{-1.0};
  double s{};
};
PolyMax dense_max_abs(const DensePoly<double>& p, double lo, double hi);

/// An upper bound of |p(s)| over s in [0, 1]: sum |p_k|. A step whose bound does not exceed the
/// peak found so far cannot hold a larger one, and is not searched (most steps: on a step of
/// 1/40 of the period the bound is within ~20 % of |x| only near the turning points).
inline double dense_abs_bound(const DensePoly<double>& p) {
  double b = 0.0;
  for (double c : p) b += std::abs(c);
  return b;
}

/// Step count of a law piece of length L: equal steps of at most h_max [s], at least one.
/// A piece carrying a harmonic of W rad/s also keeps steps_per_period steps per 2 pi / W.
inline double piece_max_step(double h_max, double harmonic_omega, double steps_per_period) {
  if (harmonic_omega == 0.0) return h_max;
  const double h_w = 2.0 * 3.141592653589793 / std::abs(harmonic_omega) / steps_per_period;
  return h_w < h_max ? h_w : h_max;
}

}  // namespace slosh::detail
