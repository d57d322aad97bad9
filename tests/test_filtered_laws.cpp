// The JDSMC filtering laws ([JDSMC] in docs/models.md, sec. 3.1, 3.4): shaper impulses against the
// paper's formulas, their residual vibration on the exact linear model, the convolution against a
// direct sum of shifted base laws, and the FIR chain against the 7-segment law and its spectrum
// zero.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include "slosh/core/law/filtered_laws.hpp"
#include "slosh/core/model/format.hpp"
#include "slosh/core/model/sloshing_model.hpp"
#include "slosh/core/response/response.hpp"
#include "slosh/core/response/spectrum.hpp"

namespace slosh {
namespace test_filtered_laws {

constexpr double kPi = std::numbers::pi;

// Amplitude of the free oscillation of mode 0 at t (envelope of exp(-sigma t)(c1 cos + c2 sin)).
double free_amplitude(const LinearResponse& r, const SloshingModel& m, double t) {
  const ModeState s = r.mode_state(0, t);
  const double w = m.omega1();
  const double sigma = m.zeta * w;
  const double wd = w * std::sqrt(1.0 - m.zeta * m.zeta);
  return std::hypot(s.x, (s.x_dot + sigma * s.x) / wd);
}

TEST(Shaper, ImpulsesFollowThePaperFormulas) {
  const double w = 19.3;
  for (double zeta : {0.0, 0.004, 0.05, 0.2}) {
    const double K = std::exp(-zeta * kPi / std::sqrt(1.0 - zeta * zeta));
    const double Td = 2.0 * kPi / (w * std::sqrt(1.0 - zeta * zeta));
    const std::vector<std::vector<double>> expected{
        {1.0 / (1.0 + K), K / (1.0 + K)},
        {1.0 / std::pow(1.0 + K, 2), 2.0 * K / std::pow(1.0 + K, 2), K * K / std::pow(1.0 + K, 2)},
        {1.0 / std::pow(1.0 + K, 3), 3.0 * K / std::pow(1.0 + K, 3),
         3.0 * K * K / std::pow(1.0 + K, 3), K * K * K / std::pow(1.0 + K, 3)}};
    const ShaperType types[] = {ShaperType::kZV, ShaperType::kZVD, ShaperType::kZVDD};
    for (int k = 0; k < 3; ++k) {
      const InputShaper s = make_shaper(types[k], w, zeta);
      ASSERT_EQ(s.impulses.size(), expected[k].size());
      double sum = 0.0;
      for (std::size_t j = 0; j < s.impulses.size(); ++j) {
        EXPECT_NEAR(s.impulses[j].time, Td * static_cast<double>(j) / 2.0, 1e-15);
        EXPECT_NEAR(s.impulses[j].amplitude, expected[k][j], 1e-15);
        sum += s.impulses[j].amplitude;
      }
      EXPECT_NEAR(sum, 1.0, 1e-15);
      EXPECT_NEAR(s.delay(), Td * static_cast<double>(k + 1) / 2.0, 1e-15);
      EXPECT_LT(shaper_residual(s, w, zeta), 1e-14) << to_string(types[k]) << " zeta " << zeta;
    }
  }
}

TEST(Shaper, EiLeavesExactlyItsResidualAndIsTheUndampedEiWithoutDamping) {
  const double w = 21.0;
  for (double V : {0.0, 0.05, 0.1}) {
    const InputShaper undamped = make_shaper(ShaperType::kEI, w, 0.0, V);
    ASSERT_EQ(undamped.impulses.size(), 3u);
    EXPECT_NEAR(undamped.impulses[0].amplitude, (1.0 + V) / 4.0, 1e-15);
    EXPECT_NEAR(undamped.impulses[1].amplitude, (1.0 - V) / 2.0, 1e-15);
    EXPECT_NEAR(undamped.impulses[2].amplitude, (1.0 + V) / 4.0, 1e-15);
    for (double zeta : {0.0, 0.005, 0.05}) {
      const InputShaper s = make_shaper(ShaperType::kEI, w, zeta, V);
      double sum = 0.0;
      for (const Impulse& i : s.impulses) sum += i.amplitude;
      EXPECT_NEAR(sum, 1.0, 1e-15);
      EXPECT_NEAR(shaper_residual(s, w, zeta), V, 1e-14);
      // Insensitivity: a +-10 % frequency error leaves far less than a ZV shaper does.
      const InputShaper zv = make_shaper(ShaperType::kZV, w, zeta);
      EXPECT_LT(shaper_residual(s, 1.1 * w, zeta), shaper_residual(zv, 1.1 * w, zeta));
      EXPECT_LT(shaper_residual(s, 0.9 * w, zeta), shaper_residual(zv, 0.9 * w, zeta));
    }
  }
}

TEST(Shaper, RejectsInvalidParameters) {
  EXPECT_THROW((void)make_shaper(ShaperType::kZV, 0.0, 0.01), std::invalid_argument);
  EXPECT_THROW((void)make_shaper(ShaperType::kZV, 10.0, 1.0), std::invalid_argument);
  EXPECT_THROW((void)make_shaper(ShaperType::kEI, 10.0, 0.01, 1.0), std::invalid_argument);
}

TEST(Convolve, EqualsTheSumOfShiftedBaseLaws) {
  const double w = 18.0;
  const MotionLaw bases[] = {make_poly5_law(0.8, 0.7), make_modified_trapezoid_law(0.8, 0.7),
                             SevenSegmentLaw(uniform_durations(0.7), 0.8).law(),
                             make_cycloidal_law(0.5, 0.6)};
  std::mt19937_64 rng(7);
  for (const MotionLaw& base : bases) {
    for (ShaperType type :
         {ShaperType::kZV, ShaperType::kZVD, ShaperType::kZVDD, ShaperType::kEI}) {
      const InputShaper s = make_shaper(type, w, 0.01);
      const MotionLaw shaped = convolve(base, s);
      EXPECT_NEAR(shaped.duration(), base.duration() + s.delay(), 1e-14);
      EXPECT_NEAR(shaped.stroke(), base.stroke(), 1e-12);
      std::uniform_real_distribution<double> t(0.0, shaped.duration());
      for (int k = 0; k < 200; ++k) {
        const double tk = t(rng);
        KinematicState expected;
        for (const Impulse& i : s.impulses) {
          const KinematicState b = base.at(tk - i.time);
          expected.position += i.amplitude * b.position;
          expected.velocity += i.amplitude * b.velocity;
          expected.acceleration += i.amplitude * b.acceleration;
        }
        const KinematicState got = shaped.at(tk);
        EXPECT_NEAR(got.position, expected.position, 1e-12) << base.name() << " t " << tk;
        EXPECT_NEAR(got.velocity, expected.velocity, 1e-11);
        EXPECT_NEAR(got.acceleration, expected.acceleration, 1e-9);
      }
    }
  }
}

TEST(Convolve, ShapedLawLeavesTheShaperResidualOnTheExactLinearModel) {
  Format f = thesis_format();
  ModelOptions o;
  o.modes = 1;
  const SloshingModel m = make_sloshing_model(f, o);
  for (ShaperType type : {ShaperType::kZV, ShaperType::kZVD, ShaperType::kZVDD, ShaperType::kEI}) {
    const InputShaper s = make_shaper(type, m.omega1(), m.zeta, 0.05);
    const double Tb = 1.0 - s.delay();
    const MotionLaw base = make_poly5_law(f.stroke, Tb);
    const MotionLaw shaped = convolve(base, s);
    EXPECT_NEAR(shaped.duration(), 1.0, 1e-14);
    const LinearResponse rb(m, base, 2.0);
    const LinearResponse rs(m, shaped, 2.0);
    // Each shifted copy leaves the base's residual z0 at its own end; at the shaped law's end
    // they add up to z0 times the shaper's residual sum (decay and phase since each copy ended).
    const double ratio = free_amplitude(rs, m, 1.0) / free_amplitude(rb, m, Tb);
    EXPECT_NEAR(ratio, shaper_residual(s, m.omega1(), m.zeta), 1e-8) << to_string(type);
    if (type != ShaperType::kEI) {
      EXPECT_LT(ratio, 1e-8);
    }
  }
}

TEST(FirChain, IsTheSevenSegmentLawWhenConditions14Hold) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 50; ++k) {
    const double t3 = 0.05 + 0.3 * u(rng);
    const double t2 = t3 * (1.0 + u(rng));
    const double t1 = (t2 + t3) * (1.0 + u(rng));
    const double stroke = 0.2 + u(rng);
    const FirChain chain = make_fir_chain(stroke, t1, t2, t3);
    ASSERT_TRUE(chain.durations.has_value());
    const SevenSegmentLaw seven(*chain.durations, stroke);
    EXPECT_NEAR(seven.motion_time(), t1 + t2 + t3, 1e-14);
    for (int i = 0; i <= 100; ++i) {
      const double t = (t1 + t2 + t3) * i / 100.0;
      const KinematicState a = chain.law.at(t);
      const KinematicState b = seven.law().at(t);
      EXPECT_NEAR(a.position, b.position, 1e-12);
      EXPECT_NEAR(a.velocity, b.velocity, 1e-11);
      EXPECT_NEAR(a.acceleration, b.acceleration, 1e-9 * seven.A());
    }
    EXPECT_NEAR(seven.A(), stroke / (t1 * t2), 1e-9 * seven.A());
  }
}

TEST(FirChain, RestToRestWithASpectralZeroAtTheDampedPeriod) {
  const double w = 19.0;
  const double t3 = 2.0 * kPi / w;  // zeta = 0: T3 is the period
  for (double t2 : {0.1, 0.25, 0.5}) {
    const double t1 = 1.0 - t3 - t2;  // (14) fails for some of these: the general law
    const FirChain chain = make_fir_chain(0.8, t1, t2, t3);
    EXPECT_NEAR(chain.law.duration(), 1.0, 1e-14);
    const KinematicState end = chain.law.at(chain.law.duration() - 1e-15);
    EXPECT_NEAR(chain.law.stroke(), 0.8, 1e-12);
    EXPECT_NEAR(end.velocity, 0.0, 1e-9);
    EXPECT_NEAR(end.acceleration, 0.0, 1e-6);
    // |X_a(w)| by Gauss-Legendre quadrature of the law: zero where the T3 window has its zero.
    const double reference = std::abs(acceleration_spectrum(chain.law, 0.5 * w));
    EXPECT_LT(std::abs(acceleration_spectrum(chain.law, w)), 1e-10 * reference);
    if (chain.durations) {
      EXPECT_LT(std::abs(seven_segment_spectrum(*chain.durations, 0.8, w)), 1e-10 * reference);
    }
  }
}

// F_IIR of eq. 8 / eq. 9 in controllable canonical form, integrated by RK4 at Ts / 400 with the
// input interpolated linearly between its samples (what a first-order hold feeds the filter).
std::vector<double> continuous_iir(IirOrder order, double w, double zeta, double tau, double Ts,
                                   const std::vector<double>& u, std::size_t n_out) {
  const int n = order == IirOrder::kSecond ? 2 : 3;
  std::array<double, 3> den{};  // s^n + den[n-1] s^(n-1) + ... + den[0]
  std::array<double, 3> num{};  // strictly proper numerator coefficients
  double direct = 0.0;
  if (n == 2) {
    den = {tau * tau, 2.0 * tau, 0.0};
    const double g = tau * tau / (w * w);
    direct = g;
    num = {g * (w * w - tau * tau), g * (2.0 * zeta * w - 2.0 * tau), 0.0};
  } else {
    den = {tau * tau * tau, 3.0 * tau * tau, 3.0 * tau};
    const double g = tau * tau * tau / (w * w);
    num = {g * w * w, g * 2.0 * zeta * w, g};
  }
  auto input = [&](double t) {
    const double k = t / Ts;
    const auto i = static_cast<long>(std::floor(k));
    if (i < 0) return u.front();
    if (i + 1 >= static_cast<long>(u.size())) return u.back();
    const double f = k - static_cast<double>(i);
    return (1.0 - f) * u[static_cast<std::size_t>(i)] + f * u[static_cast<std::size_t>(i + 1)];
  };
  using State = std::array<double, 3>;
  auto rhs = [&](double t, const State& x) {
    State d{};
    for (int i = 0; i + 1 < n; ++i)
      d[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i + 1)];
    double last = input(t);
    for (int i = 0; i < n; ++i)
      last -= den[static_cast<std::size_t>(i)] * x[static_cast<std::size_t>(i)];
    d[static_cast<std::size_t>(n - 1)] = last;
    return d;
  };
  // Start at rest on u(0): the state whose output is u(0) with zero derivatives.
  State x{};
  x[0] = u.front() / den[0];
  std::vector<double> y(n_out);
  const int sub = 400;
  const double h = Ts / sub;
  double t = 0.0;
  for (std::size_t k = 0; k < n_out; ++k) {
    double out = direct * input(t);
    for (int i = 0; i < n; ++i)
      out += num[static_cast<std::size_t>(i)] * x[static_cast<std::size_t>(i)];
    y[k] = out;
    for (int s = 0; s < sub; ++s) {
      auto add = [](const State& a, const State& b, double c) {
        return State{a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2]};
      };
      const State k1 = rhs(t, x);
      const State k2 = rhs(t + h / 2, add(x, k1, h / 2));
      const State k3 = rhs(t + h / 2, add(x, k2, h / 2));
      const State k4 = rhs(t + h, add(x, k3, h));
      for (std::size_t i = 0; i < 3; ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      t += h;
    }
    t = static_cast<double>(k + 1) * Ts;
  }
  return y;
}

TEST(Iir, DifferenceEquationsMatchTheContinuousFilterOnAFirstOrderHoldInput) {
  const double w = 19.35, zeta = 0.0046;
  for (IirOrder order : {IirOrder::kSecond, IirOrder::kThird}) {
    for (double tau : {40.0, 50.0, 100.0}) {
      for (double Ts : {1e-3, 5e-4}) {
        const MotionLaw base = make_poly5_law(0.8, 0.8);
        std::vector<double> u;
        for (int k = 0; k * Ts <= 0.8 + 1e-12; ++k) u.push_back(base.at(k * Ts).position);
        const std::size_t n_out = u.size() + static_cast<std::size_t>(0.4 / Ts);
        const IirFilter f = make_iir_filter(order, w, zeta, tau, Ts);
        long double dc_num = 0.0, dc_den = 1.0;
        for (long double b : f.b) dc_num += b;
        for (long double a : f.a) dc_den += a;
        EXPECT_NEAR(static_cast<double>(dc_num / dc_den), 1.0, 1e-11) << "DC gain";
        const std::vector<double> y = apply_iir(f, u, n_out);
        const std::vector<double> ref = continuous_iir(order, w, zeta, tau, Ts, u, n_out);
        double worst = 0.0;
        for (std::size_t k = 0; k < n_out; ++k) worst = std::max(worst, std::abs(y[k] - ref[k]));
        EXPECT_LT(worst, 1e-9) << "order " << static_cast<int>(order) << " tau " << tau << " Ts "
                               << Ts;
        EXPECT_NEAR(y.back(), 0.8, 1e-6);
      }
    }
  }
}

// The IIR law of a prescribed duration: exactly T long, filtered part within one sample of T,
// rest-to-rest exactly, a small correction, and mode 1 left nearly still after the motion.
TEST(IirLaw, PrescribedDurationRestToRestAndLittleResidual) {
  const Format f = thesis_format();
  ModelOptions o;
  o.modes = 1;
  const SloshingModel m = make_sloshing_model(f, o);
  for (BaseLaw base_type :
       {BaseLaw::kPoly5, BaseLaw::kModifiedTrapezoid, BaseLaw::kSevenSegmentUniform}) {
    for (IirOrder order : {IirOrder::kSecond, IirOrder::kThird}) {
      for (double T : {0.8, 1.0, 1.2345}) {
        const double Ts = 1e-3;
        const IirFilter filter = make_iir_filter(order, m.omega1(), m.zeta, 50.0, Ts);
        auto base = [&](double d) { return make_base_law(base_type, f.stroke, d); };
        const IirLaw law = make_iir_law(base, filter, f.stroke, T);
        const std::string what = to_string(base_type) + " order " +
                                 std::to_string(static_cast<int>(order)) + " T " +
                                 std::to_string(T);
        ASSERT_TRUE(law.fits) << what;
        EXPECT_EQ(law.law.duration(), T) << what;
        EXPECT_LE(law.filtered_duration, T + 1e-12) << what;
        EXPECT_GT(law.filtered_duration, T - Ts - 1e-12) << what;
        EXPECT_NEAR(law.base_duration + law.delay, law.filtered_duration, 1e-12) << what;
        // The paper's figure: ~0.19 s at tau = 50 on a 1 s law.
        EXPECT_GT(law.delay, 0.08) << what;
        EXPECT_LT(law.delay, 0.35) << what;
        const KinematicState end = law.law.pieces().back().at(law.law.pieces().back().duration());
        EXPECT_NEAR(end.position, f.stroke, 1e-12) << what;
        EXPECT_NEAR(end.velocity, 0.0, 1e-12) << what;
        EXPECT_LT(law.correction, 1e-3) << what;
        // Breakpoints on the sample grid, then T.
        const std::vector<double> b = law.law.breakpoints();
        EXPECT_EQ(b.back(), T);
        for (std::size_t k = 0; k + 1 < b.size(); ++k) {
          ASSERT_NEAR(b[k], static_cast<double>(k) * Ts, 1e-12) << what;
        }
        // Mode 1 is driven like a critically damped system: the residual is a small part of the
        // base law's of the same duration.
        const LinearResponse filtered(m, law.law, 2.0);
        const LinearResponse plain(m, base(T), 2.0);
        EXPECT_LT(free_amplitude(filtered, m, T), 0.03 * free_amplitude(plain, m, T)) << what;
      }
    }
  }
}

TEST(IirLaw, DoesNotFitWhenTheDelayExceedsTheMotionTime) {
  const Format f = thesis_format();
  const SloshingModel m = make_sloshing_model(f, ModelOptions{});
  const IirFilter filter = make_iir_filter(IirOrder::kThird, m.omega1(), m.zeta, 5.0, 1e-3);
  const IirLaw law =
      make_iir_law([&](double d) { return make_poly5_law(f.stroke, d); }, filter, f.stroke, 0.5);
  EXPECT_FALSE(law.fits);
  EXPECT_GT(law.delay, 0.5);
  EXPECT_TRUE(law.law.pieces().empty());
}

}  // namespace test_filtered_laws
}  // namespace slosh
