// The filtering strategies through the API (fir_chain, shaper, iir; JDSMC 2022, [JDSMC] in
// docs/models.md, sec. 3-4). Every number of a plan is checked against a computation written here
// from the paper or from the plan's JSON `law` alone (nothing from slosh::core rebuilds the
// reference):
//  - the damped period T3 = 2 pi / (w1 sqrt(1 - zeta^2)), the FIR chain's durations, plateaus and
//    its acceleration (eq. 13 integrated), the shaper impulses (eq. 5-6 and the documented EI
//    amplitudes) and their residual (the Z_n formula of sec. 3.1), the IIR denominator (eq. 11-12)
//    and its unit DC gain;
//  - kinematics as the peaks of the JSON law sampled and refined here, the spectrum as a Simpson
//    quadrature of the JSON law times e^(-j w t), the stroke and rest-to-rest by integration;
//  - the law fed back to simulate (in process, over HTTP) gives the plan's prediction;
//  - validation messages of the new options and law types, written out literally;
//  - infeasible designs say why and return the uniform law;
//  - the real binary: `slosh plan`, `slosh export` of a general law, `slosh batch` with the new
//    option columns.
// Tests marked "Regression" guard two bugs this suite found (fixed).

#include <httplib.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"
#include "support/plan_errors.hpp"
#include "support/process.hpp"
#include "support/reference_integrators.hpp"
#include "support/rfc4180.hpp"
#include "support/server.hpp"

namespace slosh::api {
namespace test_filter_api {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr double kPi = std::numbers::pi;
constexpr double kStroke = 0.8;  // [m], the thesis format's stroke
/// Longest Simpson step of the reference integrals [s].
constexpr double kStep = 1e-4;

// ---------------------------------------------------------------------------------------------
// Requests.

/// The thesis format (R = 48.5 mm, h = 82 mm, water, 800 mm) with motion time T.
json thesis_format(double T) {
  json f = json::parse(R"({"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0})");
  f["motion_time_s"] = T;
  return f;
}

json plan_body(const std::string& strategy, double T, const json& options = json::object()) {
  return {{"format", thesis_format(T)}, {"strategy", strategy}, {"options", options}};
}

/// The in-process plan of a body (memoised: plans are deterministic and several tests share them).
const json& plan_of(const json& body) {
  static std::map<std::string, json> plans;
  const std::string text = body.dump();
  auto it = plans.find(text);
  if (it == plans.end()) it = plans.emplace(text, run_plan(parse_plan_request(body))).first;
  return it->second;
}

/// "%.3g", the precision of the planner's messages.
std::string g3(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

double omega1(const json& plan) {
  return plan["model"]["omega_rad_s"][0].get<double>();
}
double zeta(const json& plan) {
  return plan["model"]["zeta"].get<double>();
}
/// Damped period of mode 1 (paper eq. 5), from the model the plan reports.
double damped_period(const json& plan) {
  const double z = zeta(plan);
  return 2.0 * kPi / (omega1(plan) * std::sqrt(1.0 - z * z));
}

// ---------------------------------------------------------------------------------------------
// The JSON law rebuilt here: per piece a = c0 + c1 x + c2 x^2 + c3 x^3 + hc cos(W x) + hs sin(W x),
// x = t - t0.

struct Piece {
  double t0{}, t1{};
  std::array<double, 4> c{};
  double hc{}, hs{}, w{};
  [[nodiscard]] double a(double t) const {
    const double x = t - t0;
    return c[0] + x * (c[1] + x * (c[2] + x * c[3])) + hc * std::cos(w * x) + hs * std::sin(w * x);
  }
  [[nodiscard]] double j(double t) const {
    const double x = t - t0;
    return c[1] + x * (2.0 * c[2] + 3.0 * c[3] * x) - hc * w * std::sin(w * x) +
           hs * w * std::cos(w * x);
  }
};

/// Simpson on [lo, hi] with steps of at most kStep (and at least 2 intervals).
template <typename F>
auto integral(const F& f, double lo, double hi) -> decltype(f(lo)) {
  if (!(hi > lo)) return decltype(f(lo)){};
  const int n = 2 * std::max(1, static_cast<int>(std::ceil((hi - lo) / (2.0 * kStep))));
  return test::simpson(f, lo, hi, n);
}

/// Largest f on [lo, hi] when f is unimodal there: golden-section search, ends included.
double refine_max(const std::function<double(double)>& f, double lo, double hi) {
  if (!(hi > lo)) return f(lo);
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = lo, b = hi;
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 90; ++i) {
    if (f1 < f2) {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = f(x2);
    } else {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = f(x1);
    }
  }
  return std::max({f(lo), f(hi), f1, f2});
}

struct Peaks {
  double a_pos{}, a_neg{}, v{}, j{};
};

class JsonLaw {
 public:
  /// From the `law` member of a plan (seven_segment, piecewise_linear or piecewise).
  JsonLaw(const json& law, double stroke) {
    const std::string type = law.at("type").get<std::string>();
    if (type == "piecewise_linear") {
      const auto t = law.at("breakpoints_s").get<std::vector<double>>();
      const auto a = law.at("acceleration_m_s2").get<std::vector<double>>();
      if (t.size() != a.size() || t.size() < 2) throw std::runtime_error("bad piecewise_linear");
      for (std::size_t k = 0; k + 1 < t.size(); ++k) {
        Piece p;
        p.t0 = t[k];
        p.t1 = t[k + 1];
        p.c = {a[k], (a[k + 1] - a[k]) / (t[k + 1] - t[k]), 0.0, 0.0};
        pieces_.push_back(p);
      }
    } else if (type == "piecewise") {
      for (const json& item : law.at("pieces")) {
        Piece p;
        p.t0 = item.at("t_begin_s").get<double>();
        p.t1 = item.at("t_end_s").get<double>();
        const auto c = item.at("a_poly").get<std::vector<double>>();
        for (std::size_t i = 0; i < c.size() && i < 4; ++i) p.c[i] = c[i];
        if (item.contains("harmonic")) {
          p.hc = item["harmonic"].at("cos").get<double>();
          p.hs = item["harmonic"].at("sin").get<double>();
          p.w = item["harmonic"].at("omega_rad_s").get<double>();
        }
        pieces_.push_back(p);
      }
    } else if (type == "seven_segment") {
      // Levels 0, A, A, 0, 0, -B, -B, 0 with A, B for a unit peak velocity and v(T) = 0 (SPEC §3),
      // then scaled so that the position integrates to the stroke.
      const auto d = law.at("durations_s").get<std::array<double, 7>>();
      const double A = 1.0 / (d[0] / 2 + d[1] + d[2] / 2);
      const double B = 1.0 / (d[4] / 2 + d[5] + d[6] / 2);
      const std::array<double, 8> level{0.0, A, A, 0.0, 0.0, -B, -B, 0.0};
      double t = 0.0;
      for (std::size_t i = 0; i < 7; ++i) {
        if (d[i] > 0.0) {
          Piece p;
          p.t0 = t;
          p.t1 = t + d[i];
          p.c = {level[i], (level[i + 1] - level[i]) / d[i], 0.0, 0.0};
          pieces_.push_back(p);
        }
        t += d[i];
      }
      const double scale = stroke / position(T());
      for (Piece& p : pieces_) {
        for (double& c : p.c) c *= scale;
      }
    } else {
      throw std::runtime_error("unexpected law type " + type);
    }
  }

  [[nodiscard]] const std::vector<Piece>& pieces() const { return pieces_; }
  [[nodiscard]] double T() const { return pieces_.back().t1; }

  /// Acceleration; 0 outside the law; at a knot, the piece that starts there.
  [[nodiscard]] double a(double t) const {
    if (t < 0.0 || t > T()) return 0.0;
    auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                               [](double x, const Piece& p) { return x < p.t0; });
    return it == pieces_.begin() ? 0.0 : std::prev(it)->a(t);
  }
  [[nodiscard]] double velocity(double t) const {
    double v = 0.0;
    for (const Piece& p : pieces_) {
      v += integral([&](double x) { return p.a(x); }, p.t0, std::min(p.t1, t));
    }
    return v;
  }
  /// int_0^t (t - x) a(x) dx.
  [[nodiscard]] double position(double t) const {
    double s = 0.0;
    for (const Piece& p : pieces_) {
      s += integral([&](double x) { return (t - x) * p.a(x); }, p.t0, std::min(p.t1, t));
    }
    return s;
  }
  /// int a(t) e^(-j w t) dt.
  [[nodiscard]] std::complex<double> spectrum(double w) const {
    std::complex<double> X;
    for (const Piece& p : pieces_) {
      X += integral([&](double x) { return p.a(x) * std::polar(1.0, -w * x); }, p.t0, p.t1);
    }
    return X;
  }

  /// Peaks of a, -a, |v|, |j|: a grid of steps <= kStep on every piece, then a golden-section
  /// refinement around each piece's best grid point.
  [[nodiscard]] Peaks peaks() const {
    Peaks out;
    double v_start = 0.0;
    for (const Piece& p : pieces_) {
      const int n = std::max(1, static_cast<int>(std::ceil((p.t1 - p.t0) / kStep)));
      const double h = (p.t1 - p.t0) / n;
      std::vector<double> x(n + 1), v(n + 1);
      for (int i = 0; i <= n; ++i) x[i] = i == n ? p.t1 : p.t0 + i * h;
      v[0] = v_start;
      for (int i = 0; i < n; ++i) {
        v[i + 1] = v[i] + test::simpson([&](double t) { return p.a(t); }, x[i], x[i + 1], 2);
      }
      v_start = v[n];
      auto best = [&](const std::function<double(double)>& f,
                      const std::function<double(int, double)>& refined) {
        int at = 0;
        for (int i = 1; i <= n; ++i) {
          if (f(x[i]) > f(x[at])) at = i;
        }
        const int lo = std::max(0, at - 1);
        const int hi = std::min(n, at + 1);
        return refine_max([&](double t) { return refined(lo, t); }, x[lo], x[hi]);
      };
      auto on_grid_v = [&](double t) {
        const auto i = static_cast<std::size_t>(
            std::min<double>(n, std::max(0.0, std::round((t - p.t0) / h))));
        return v[i];
      };
      auto v_from = [&](int i, double t) {
        return v[i] + test::simpson([&](double y) { return p.a(y); }, x[i], t, 2);
      };
      out.a_pos = std::max(
          out.a_pos, best([&](double t) { return p.a(t); }, [&](int, double t) { return p.a(t); }));
      out.a_neg = std::max(out.a_neg, best([&](double t) { return -p.a(t); },
                                           [&](int, double t) { return -p.a(t); }));
      out.j = std::max(
          out.j, best([&](double t) { return p.j(t); }, [&](int, double t) { return p.j(t); }));
      out.j = std::max(
          out.j, best([&](double t) { return -p.j(t); }, [&](int, double t) { return -p.j(t); }));
      out.v = std::max(out.v, best(on_grid_v, v_from));
      out.v = std::max(out.v, best([&](double t) { return -on_grid_v(t); },
                                   [&](int i, double t) { return -v_from(i, t); }));
    }
    return out;
  }

 private:
  std::vector<Piece> pieces_;
};

/// The law's last time as written in its JSON.
double json_law_end(const json& law) {
  if (law["type"] == "piecewise_linear") return law["breakpoints_s"].back().get<double>();
  if (law["type"] == "piecewise") return law["pieces"].back()["t_end_s"].get<double>();
  double sum = 0.0;
  for (const json& d : law["durations_s"]) sum += d.get<double>();
  return sum;
}

// ---------------------------------------------------------------------------------------------
// References from the paper.

/// The FIR chain of eq. 13 on a step of `stroke`, integrated once: the acceleration
/// stroke / (T1 T2 T3) * sum over subsets S of {T1, T2, T3} of (-1)^|S| max(0, t - sum S).
double fir_chain_acceleration(double stroke, double T1, double T2, double T3, double t) {
  const std::array<double, 3> Ti{T1, T2, T3};
  double sum = 0.0;
  for (int mask = 0; mask < 8; ++mask) {
    double shift = 0.0;
    int count = 0;
    for (int i = 0; i < 3; ++i) {
      if ((mask >> i) & 1) {
        shift += Ti[static_cast<std::size_t>(i)];
        ++count;
      }
    }
    sum += (count % 2 == 0 ? 1.0 : -1.0) * std::max(0.0, t - shift);
  }
  return stroke / (T1 * T2 * T3) * sum;
}

/// A base law of duration Tb (0 outside [0, Tb]), scaled to the stroke by integration.
class BaseLaw {
 public:
  BaseLaw(const std::string& name, double stroke, double Tb) : name_(name), Tb_(Tb) {
    if (name == "poly5") {
      knots_ = {0.0, Tb};
    } else if (name == "modified_trapezoid") {
      knots_ = {0.0, Tb / 8, 3 * Tb / 8, 5 * Tb / 8, 7 * Tb / 8, Tb};
    } else if (name == "seven_segment_uniform") {
      for (int i = 0; i <= 7; ++i) knots_.push_back(Tb * i / 7.0);
    } else {
      throw std::runtime_error("unknown base " + name);
    }
    double s = 0.0;
    for (std::size_t k = 0; k + 1 < knots_.size(); ++k) {
      s += integral([&](double t) { return (Tb - t) * unit(t); }, knots_[k], knots_[k + 1]);
    }
    scale_ = stroke / s;
  }
  [[nodiscard]] double operator()(double t) const {
    return t < 0.0 || t > Tb_ ? 0.0 : scale_ * unit(t);
  }
  /// Peak acceleration * Tb^2 / stroke.
  [[nodiscard]] double scale() const { return scale_; }

 private:
  // Unit-level shapes: poly5 s = 10u^3 - 15u^4 + 6u^5; modified trapezoid with sine blends and
  // 1/8 splits; uniform 7-segment trapezoid.
  [[nodiscard]] double unit(double t) const {
    const double u = t / Tb_;
    if (name_ == "poly5") return 60 * u - 180 * u * u + 120 * u * u * u;
    if (name_ == "modified_trapezoid") {
      if (u < 1.0 / 8) return std::sin(4 * kPi * u);
      if (u < 3.0 / 8) return 1.0;
      if (u < 5.0 / 8) return std::cos(4 * kPi * (u - 3.0 / 8));
      if (u < 7.0 / 8) return -1.0;
      return -std::cos(4 * kPi * (u - 7.0 / 8));
    }
    const double x = 7.0 * u;  // 7-segment, unit plateaus
    if (x < 1) return x;
    if (x < 2) return 1.0;
    if (x < 3) return 3.0 - x;
    if (x < 4) return 0.0;
    if (x < 5) return -(x - 4.0);
    if (x < 6) return -1.0;
    return -(7.0 - x);
  }

  std::string name_;
  double Tb_;
  std::vector<double> knots_;
  double scale_{1.0};
};

struct Impulse {
  double t, amplitude;
};

/// The shaper of `type` for (omega, zeta): t_j = j Td / 2 (eq. 6), K of eq. 5; ZV/ZVD/ZVDD
/// binomial amplitudes; EI [p, q K, p K^2] with p (1 + K^2) + q K = 1, (2p - q) K^2 = V; MZV
/// [1 - 1/sqrt2, sqrt2 - 1, 1 - 1/sqrt2] compensated by K^(3/4) per impulse at t_j = 3 j Td / 8.
std::vector<Impulse> shaper_reference(const std::string& type, double w, double z, double V) {
  const double Td = 2.0 * kPi / (w * std::sqrt(1.0 - z * z));
  const double K = std::exp(-z * kPi / std::sqrt(1.0 - z * z));
  std::vector<double> A;
  if (type == "zv") {
    A = {1.0, K};
  } else if (type == "zvd") {
    A = {1.0, 2 * K, K * K};
  } else if (type == "zvdd") {
    A = {1.0, 3 * K, 3 * K * K, K * K * K};
  } else if (type == "mzv") {
    const double a = 1.0 - 1.0 / std::sqrt(2.0), Km = std::pow(K, 0.75);
    A = {a, (std::sqrt(2.0) - 1.0) * Km, a * Km * Km};
  } else {
    const double p = (1.0 + V / K) / ((1.0 + K) * (1.0 + K));
    const double q = 2.0 * p - V / (K * K);
    A = {p, q * K, p * K * K};
  }
  double sum = 0.0;
  for (double x : A) sum += x;
  std::vector<Impulse> out;
  for (std::size_t j = 0; j < A.size(); ++j) {
    const double spacing = type == "mzv" ? 0.375 * Td : Td / 2.0;
    out.push_back({spacing * static_cast<double>(j), type == "ei" ? A[j] : A[j] / sum});
  }
  return out;
}

/// Residual vibration of a mode after an impulse train (paper sec. 3.1: Z_n divided by the
/// residual of one unit impulse, omega / sqrt(1 - zeta^2)).
double shaper_residual(const std::vector<Impulse>& impulses, double w, double z) {
  const double tN = impulses.back().t;
  const double wd = w * std::sqrt(1.0 - z * z);
  double c = 0.0, s = 0.0;
  for (const Impulse& i : impulses) {
    const double B = i.amplitude * std::exp(-z * w * (tN - i.t));
    c += B * std::cos(wd * (tN - i.t));
    s += B * std::sin(wd * (tN - i.t));
  }
  return std::hypot(c, s);
}

// ---------------------------------------------------------------------------------------------
// Checks every filter plan shares.

/// `law` against its kinematics, the stroke and the spectrum of the response.
void expect_law_consistent(const json& plan, double T) {
  SCOPED_TRACE(plan["strategy"].get<std::string>() + " " + plan["law"]["type"].get<std::string>());
  const JsonLaw law(plan["law"], kStroke);
  EXPECT_NEAR(json_law_end(plan["law"]), T, 1e-12);
  EXPECT_NEAR(law.velocity(T), 0.0, 1e-9);
  EXPECT_NEAR(law.position(T), kStroke, 1e-9);

  const Peaks p = law.peaks();
  const json& k = plan["kinematics"];
  EXPECT_NEAR(k["a_max"].get<double>(), p.a_pos, 1e-9 * p.a_pos);
  EXPECT_NEAR(k["a_min"].get<double>(), p.a_neg, 1e-9 * p.a_neg);
  EXPECT_NEAR(k["v_peak"].get<double>(), p.v, 1e-9 * p.v);
  EXPECT_NEAR(k["j_peak"].get<double>(), p.j, 1e-9 * p.j);

  // The spectrum grid: 512 points from 0 to 5 f1; amplitudes against the quadrature.
  const json& sp = plan["spectrum"];
  ASSERT_EQ(sp["f_hz"].size(), 512u);
  ASSERT_EQ(sp["amplitude"].size(), 512u);
  const double f1 = omega1(plan) / (2.0 * kPi);
  double peak = 0.0;
  for (const json& x : sp["amplitude"]) peak = std::max(peak, x.get<double>());
  for (int i : {0, 37, 102, 103, 150, 300, 511}) {
    const auto idx = static_cast<std::size_t>(i);
    const double f = sp["f_hz"][idx].get<double>();
    EXPECT_NEAR(f, 5.0 * f1 * i / 511.0, 1e-12 * f1) << i;
    const double X = std::abs(law.spectrum(2.0 * kPi * f));
    EXPECT_NEAR(sp["amplitude"][idx].get<double>(), X, 1e-8 * X + 1e-10 * peak) << i;
  }
}

/// A general law: the 7-segment fields are null and the law is not seven_segment.
void expect_general_law_fields(const json& plan) {
  EXPECT_TRUE(plan["durations_s"].is_null());
  EXPECT_TRUE(plan["durations_pct"].is_null());
  EXPECT_TRUE(plan["switch_times_s"].is_null());
  EXPECT_TRUE(plan["kinematics"]["jerks_m_s3"].is_null());
  EXPECT_NE(plan["law"]["type"], "seven_segment");
}

// ---------------------------------------------------------------------------------------------
// fir_chain

TEST(FirChainPlan, ShortMotionIsTheGeneralLawOfEquation13) {
  const double T = 1.0;
  const json& plan = plan_of(plan_body("fir_chain", T));
  EXPECT_EQ(plan["status"], "optimal");
  EXPECT_EQ(plan["strategy"], "fir_chain");
  const double T3 = damped_period(plan);
  ASSERT_GT(4.0 * T3, T);  // conditions (14) cannot hold: T1 = T2 = (T - T3) / 2
  const double T1 = (T - T3) / 2.0;
  expect_general_law_fields(plan);
  EXPECT_EQ(plan["law"]["type"], "piecewise_linear");
  const json& d = plan["design"];
  EXPECT_EQ(d["method"], "fir_chain");
  EXPECT_NEAR(d["t3_s"].get<double>(), T3, 1e-12);
  EXPECT_NEAR(d["t1_s"].get<double>(), T1, 1e-12);
  EXPECT_NEAR(d["t2_s"].get<double>(), T1, 1e-12);
  EXPECT_EQ(d["conditions_14"], false);

  const JsonLaw law(plan["law"], kStroke);
  for (int i = 0; i <= 400; ++i) {
    const double t = T * i / 400.0;
    EXPECT_NEAR(law.a(t), fir_chain_acceleration(kStroke, T1, T1, T3, t), 1e-9) << t;
  }
  // With T3 < T1 = T2 the acceleration peaks at S / T1^2; the jerk steps of T1 and T2 coincide,
  // so after T1 it is -2 S / (T1^2 T3).
  EXPECT_NEAR(plan["kinematics"]["a_max"].get<double>(), kStroke / (T1 * T1), 1e-9);
  EXPECT_NEAR(plan["kinematics"]["j_peak"].get<double>(), 2.0 * kStroke / (T1 * T1 * T3), 1e-9);
  expect_law_consistent(plan, T);
}

TEST(FirChainPlan, LongMotionIsTheSevenSegmentLawOfTheClosedForm) {
  const double T = 1.6;
  const json& plan = plan_of(plan_body("fir_chain", T));
  EXPECT_EQ(plan["status"], "optimal");
  const double T3 = damped_period(plan);
  ASSERT_LT(4.0 * T3, T);
  const std::array<double, 7> expected{T3, T / 2 - 2 * T3, T3, 0.0, T3, T / 2 - 2 * T3, T3};
  ASSERT_EQ(plan["law"]["type"], "seven_segment");
  ASSERT_EQ(plan["durations_s"].size(), 7u);
  EXPECT_EQ(plan["law"]["durations_s"], plan["durations_s"]);
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_NEAR(plan["durations_s"][i].get<double>(), expected[i], 1e-12) << i;
  }
  const json& d = plan["design"];
  EXPECT_EQ(d["conditions_14"], true);
  const double T1 = T / 2, T2 = T / 2 - T3;
  EXPECT_NEAR(d["t1_s"].get<double>(), T1, 1e-12);
  EXPECT_NEAR(d["t2_s"].get<double>(), T2, 1e-12);
  EXPECT_NEAR(d["t3_s"].get<double>(), T3, 1e-12);
  // The trapezoid of the chain: plateaus S / (T1 T2), peak velocity S / T1, jerk S / (T1 T2 T3).
  const json& k = plan["kinematics"];
  EXPECT_NEAR(k["a_max"].get<double>(), kStroke / (T1 * T2), 1e-9);
  EXPECT_NEAR(k["a_min"].get<double>(), kStroke / (T1 * T2), 1e-9);
  EXPECT_NEAR(k["v_peak"].get<double>(), kStroke / T1, 1e-9);
  EXPECT_NEAR(k["j_peak"].get<double>(), kStroke / (T1 * T2 * T3), 1e-9);
  ASSERT_EQ(k["jerks_m_s3"].size(), 7u);
  const JsonLaw law(plan["law"], kStroke);
  for (int i = 0; i <= 400; ++i) {
    const double t = T * i / 400.0;
    EXPECT_NEAR(law.a(t), fir_chain_acceleration(kStroke, T1, T2, T3, t), 1e-9) << t;
  }
  expect_law_consistent(plan, T);
}

// ---------------------------------------------------------------------------------------------
// shaper

TEST(ShaperPlan, EveryShaperOnEveryBaseIsTheConvolutionOfTheClosedForms) {
  const double T = 1.0;
  for (const char* base : {"poly5", "modified_trapezoid", "seven_segment_uniform"}) {
    for (const char* type : {"zv", "mzv", "zvd", "zvdd", "ei"}) {
      SCOPED_TRACE(std::string(type) + " on " + base);
      const json& plan = plan_of(plan_body("shaper", T, {{"shaper", type}, {"base", base}}));
      EXPECT_EQ(plan["status"], "optimal");
      EXPECT_EQ(plan["strategy"], "shaper");
      expect_general_law_fields(plan);
      // Polynomial bases with continuous linear pieces come out piecewise_linear.
      EXPECT_EQ(plan["law"]["type"],
                std::string(base) == "seven_segment_uniform" ? "piecewise_linear" : "piecewise");

      const json& d = plan["design"];
      EXPECT_EQ(d["method"], "shaper");
      EXPECT_EQ(d["shaper"], type);
      EXPECT_EQ(d["base"], base);
      const std::vector<Impulse> ref = shaper_reference(type, omega1(plan), zeta(plan), 0.05);
      ASSERT_EQ(d["impulses"].size(), ref.size());
      double sum = 0.0;
      std::vector<Impulse> got;
      for (std::size_t j = 0; j < ref.size(); ++j) {
        const json& i = d["impulses"][j];
        got.push_back({i["t_s"].get<double>(), i["amplitude"].get<double>()});
        EXPECT_NEAR(got[j].t, ref[j].t, 1e-12) << j;
        EXPECT_NEAR(got[j].amplitude, ref[j].amplitude, 1e-12) << j;
        sum += got[j].amplitude;
      }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      const double delay = d["delay_s"].get<double>();
      EXPECT_EQ(got.back().t, delay);
      const double Tb = d["base_duration_s"].get<double>();
      EXPECT_NEAR(Tb + delay, T, 1e-15);
      EXPECT_NEAR(d["residual_at_f1"].get<double>(), shaper_residual(got, omega1(plan), zeta(plan)),
                  1e-12);
      EXPECT_NEAR(d["residual_at_f1"].get<double>(), std::string(type) == "ei" ? 0.05 : 0.0, 1e-12);

      // The law is sum_j A_j base(t - t_j).
      const BaseLaw b(base, kStroke, Tb);
      const JsonLaw law(plan["law"], kStroke);
      const double a_scale = b.scale() / (Tb * Tb);
      for (int i = 0; i <= 300; ++i) {
        const double t = T * i / 300.0;
        double expected = 0.0;
        for (const Impulse& imp : got) expected += imp.amplitude * b(t - imp.t);
        EXPECT_NEAR(law.a(t), expected, 1e-9 * a_scale) << t;
      }
      expect_law_consistent(plan, T);
    }
  }
}

TEST(ShaperPlan, ModifiedTrapezoidReferenceHasItsTextbookPeak) {
  // Sanity of the reference used above: C_a = a_peak T^2 / S = 4.888 for the modified trapezoid.
  const BaseLaw b("modified_trapezoid", 1.0, 1.0);
  EXPECT_NEAR(b.scale(), 4.888, 5e-4);
  EXPECT_NEAR(BaseLaw("poly5", 1.0, 1.0).scale(), 1.0, 1e-12);
}

TEST(ShaperPlan, EiResidualFollowsTheOption) {
  const json& plan = plan_of(plan_body("shaper", 1.0, {{"shaper", "ei"}, {"residual", 0.12}}));
  EXPECT_EQ(plan["status"], "optimal");
  const json& d = plan["design"];
  const std::vector<Impulse> ref = shaper_reference("ei", omega1(plan), zeta(plan), 0.12);
  ASSERT_EQ(d["impulses"].size(), 3u);
  for (std::size_t j = 0; j < 3; ++j) {
    EXPECT_NEAR(d["impulses"][j]["amplitude"].get<double>(), ref[j].amplitude, 1e-12) << j;
  }
  EXPECT_NEAR(d["residual_at_f1"].get<double>(), 0.12, 1e-12);
  EXPECT_NEAR(shaper_residual(ref, omega1(plan), zeta(plan)), 0.12, 1e-12);
}

TEST(ShaperPlan, MultiHumpShapersLeaveZeroOrVAtF1AndConvolveExactly) {
  const double T = 1.2;
  for (const auto& [type, V] : {std::pair<std::string, double>{"ei2", 0.05}, {"ei3", 0.1}}) {
    SCOPED_TRACE(type);
    const json& plan = plan_of(plan_body("shaper", T, {{"shaper", type}, {"residual", V}}));
    // ei3 leaves the 10 % asked for at f1, more at rest than the uniform law: acceptable.
    EXPECT_EQ(plan["status"], type == "ei2" ? "optimal" : "acceptable") << plan["message"];
    const json& d = plan["design"];
    EXPECT_EQ(d["shaper"], type);
    ASSERT_EQ(d["impulses"].size(), type == "ei2" ? 4u : 5u);
    std::vector<Impulse> got;
    double sum = 0.0;
    for (const json& i : d["impulses"]) {
      got.push_back({i["t_s"].get<double>(), i["amplitude"].get<double>()});
      EXPECT_GT(got.back().amplitude, 0.0);
      if (got.size() > 1) {
        EXPECT_GT(got.back().t, got[got.size() - 2].t);
      }
      sum += got.back().amplitude;
    }
    EXPECT_EQ(got.front().t, 0.0);
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_EQ(got.back().t, d["delay_s"].get<double>());
    // ei2 cancels f1; ei3 has its middle hump, of height V, there.
    const double at_f1 = shaper_residual(got, omega1(plan), zeta(plan));
    EXPECT_NEAR(at_f1, type == "ei2" ? 0.0 : V, 1e-12);
    EXPECT_NEAR(d["residual_at_f1"].get<double>(), at_f1, 1e-12);
    const double Tb = d["base_duration_s"].get<double>();
    const BaseLaw b("poly5", kStroke, Tb);
    const JsonLaw law(plan["law"], kStroke);
    for (int i = 0; i <= 300; ++i) {
      const double t = T * i / 300.0;
      double expected = 0.0;
      for (const Impulse& imp : got) expected += imp.amplitude * b(t - imp.t);
      EXPECT_NEAR(law.a(t), expected, 1e-9 * b.scale() / (Tb * Tb)) << t;
    }
    expect_law_consistent(plan, T);
  }
}

// ---------------------------------------------------------------------------------------------
// iir

TEST(IirPlan, OrdersTwoAndThreeGiveSampledLawsOfThePrescribedDuration) {
  const double T = 1.0;
  for (int order : {2, 3}) {
    for (const char* base : {"poly5", "modified_trapezoid"}) {
      SCOPED_TRACE("order " + std::to_string(order) + " on " + base);
      const json& plan = plan_of(plan_body("iir", T, {{"iir_order", order}, {"base", base}}));
      EXPECT_EQ(plan["status"], "optimal");
      EXPECT_EQ(plan["strategy"], "iir");
      expect_general_law_fields(plan);
      ASSERT_EQ(plan["law"]["type"], "piecewise_linear");
      const json& d = plan["design"];
      EXPECT_EQ(d["method"], "iir");
      EXPECT_EQ(d["order"], order);
      EXPECT_EQ(d["tau"], 50.0);
      EXPECT_EQ(d["sample_period_s"], 0.001);
      EXPECT_EQ(d["base"], base);
      const double Ts = 0.001;
      const double Tf = d["filtered_duration_s"].get<double>();
      EXPECT_GT(Tf, T - Ts);
      EXPECT_LE(Tf, T);
      EXPECT_NEAR(d["base_duration_s"].get<double>() + d["delay_s"].get<double>(), Tf, 1e-12);
      EXPECT_GE(d["iterations"].get<int>(), 1);
      EXPECT_GE(d["correction_pct"].get<double>(), 0.0);

      // Denominator of eq. 11 / 12: (1 - e z^-1)^n with e = exp(-tau Ts); unit DC gain.
      const double e = std::exp(-50.0 * Ts);
      const std::vector<double> a_ref = order == 2
                                            ? std::vector<double>{-2 * e, e * e}
                                            : std::vector<double>{-3 * e, 3 * e * e, -e * e * e};
      ASSERT_EQ(d["a"].size(), a_ref.size());
      ASSERT_EQ(d["b"].size(), a_ref.size() + 2);
      double den = 1.0, num = 0.0;
      for (std::size_t i = 0; i < a_ref.size(); ++i) {
        EXPECT_NEAR(d["a"][i].get<double>(), a_ref[i], 1e-12) << i;
        den += d["a"][i].get<double>();
      }
      for (const json& b : d["b"]) num += b.get<double>();
      EXPECT_NEAR(num / den, 1.0, 1e-6);

      // Breakpoints on the sample grid, the last one exactly at T.
      const json& t = plan["law"]["breakpoints_s"];
      ASSERT_GE(t.size(), 2u);
      EXPECT_EQ(t.back().get<double>(), T);
      for (std::size_t k = 0; k + 1 < t.size(); ++k) {
        EXPECT_NEAR(t[k].get<double>(), Ts * static_cast<double>(k), 1e-12) << k;
      }
      EXPECT_EQ(plan["law"]["acceleration_m_s2"].back().get<double>(), 0.0);
      expect_law_consistent(plan, T);
    }
  }
}

TEST(IirPlan, OptionsReachTheDesign) {
  const json& plan = plan_of(
      plan_body("iir", 1.0, {{"iir_order", 2}, {"iir_tau", 80}, {"iir_sample_period_s", 0.002}}));
  EXPECT_EQ(plan["status"], "optimal");
  const json& d = plan["design"];
  EXPECT_EQ(d["order"], 2);
  EXPECT_EQ(d["tau"], 80.0);
  EXPECT_EQ(d["sample_period_s"], 0.002);
  const double e = std::exp(-80.0 * 0.002);
  EXPECT_NEAR(d["a"][0].get<double>(), -2 * e, 1e-12);
  EXPECT_NEAR(d["a"][1].get<double>(), e * e, 1e-12);
  const json& t = plan["law"]["breakpoints_s"];
  EXPECT_NEAR(t[1].get<double>(), 0.002, 1e-15);
  EXPECT_GT(d["filtered_duration_s"].get<double>(), 1.0 - 0.002);
  expect_law_consistent(plan, 1.0);
}

// ---------------------------------------------------------------------------------------------
// auto

TEST(AutoPlan, PicksTheShaperByTheRuleOfSpec5AndReportsLawTypes) {
  const json& plan = plan_of(plan_body("auto", 1.0));
  const json& c = plan["candidates"];
  ASSERT_EQ(c.size(), 7u);
  const std::vector<std::string> order{"baseline",    "notch",     "multi_notch", "min_jerk_band",
                                       "time_domain", "fir_chain", "shaper"};
  // The rule applied here to the candidates' predictions.
  double best_motion = INFINITY;
  for (const json& k : c) {
    if (k["status"] == "optimal" || k["status"] == "acceptable") {
      best_motion =
          std::min(best_motion, k["prediction"]["nonlinear"]["eta_motion_mm"].get<double>());
    }
  }
  std::size_t chosen = c.size();
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_EQ(c[i]["strategy"], order[i]);
    const json& pred = c[i]["prediction"]["nonlinear"];
    if ((c[i]["status"] == "optimal" || c[i]["status"] == "acceptable") &&
        pred["eta_motion_mm"].get<double>() <= 1.05 * best_motion &&
        (chosen == c.size() ||
         pred["eta_rest_mm"].get<double>() <
             c[chosen]["prediction"]["nonlinear"]["eta_rest_mm"].get<double>())) {
      chosen = i;
    }
    const bool seven = c[i]["law_type"] == "seven_segment";
    EXPECT_EQ(seven, !c[i]["durations_s"].is_null()) << order[i];
  }
  ASSERT_LT(chosen, c.size());
  EXPECT_EQ(order[chosen], "shaper");
  EXPECT_EQ(c[chosen]["chosen"], true);
  EXPECT_EQ(c[5]["law_type"], "piecewise_linear");  // fir_chain on T = 1 s < 4 T3
  EXPECT_EQ(c[6]["law_type"], "piecewise");         // zv on poly5
  // The law and design are the ones of the shaper strategy alone.
  const json& alone = plan_of(plan_body("shaper", 1.0));
  EXPECT_EQ(plan["law"], alone["law"]);
  EXPECT_EQ(plan["design"], alone["design"]);
  EXPECT_EQ(plan["prediction"], alone["prediction"]);
  expect_general_law_fields(plan);
}

// ---------------------------------------------------------------------------------------------
// Recipe key

TEST(FilterRecipeKey, EveryNewOptionChangesTheKeyAndItsDefaultDoesNot) {
  const std::string key = recipe_key(parse_plan_request(plan_body("shaper", 1.0)));
  const json defaults{{"base", "poly5"}, {"shaper", "zv"}, {"residual", 0.05},
                      {"iir_order", 3},  {"iir_tau", 50},  {"iir_sample_period_s", 0.001}};
  EXPECT_EQ(key, recipe_key(parse_plan_request(plan_body("shaper", 1.0, defaults))));
  for (const auto& [name, value] : defaults.items()) {
    json one = json::object();
    one[name] = value;
    EXPECT_EQ(key, recipe_key(parse_plan_request(plan_body("shaper", 1.0, one)))) << name;
  }
  const std::vector<std::pair<std::string, json>> changes{{"base", "modified_trapezoid"},
                                                          {"base", "seven_segment_uniform"},
                                                          {"shaper", "zvd"},
                                                          {"shaper", "zvdd"},
                                                          {"shaper", "ei"},
                                                          {"residual", 0.1},
                                                          {"iir_order", 2},
                                                          {"iir_tau", 51},
                                                          {"iir_sample_period_s", 0.002}};
  std::vector<std::string> keys{key};
  for (const auto& [name, value] : changes) {
    json one = json::object();
    one[name] = value;
    const std::string k = recipe_key(parse_plan_request(plan_body("shaper", 1.0, one)));
    EXPECT_TRUE(std::find(keys.begin(), keys.end(), k) == keys.end()) << name << " " << value;
    keys.push_back(k);
  }
  EXPECT_NE(key, recipe_key(parse_plan_request(plan_body("iir", 1.0))));
  EXPECT_NE(key, recipe_key(parse_plan_request(plan_body("fir_chain", 1.0))));
  // The key of the response is the request's.
  EXPECT_EQ(plan_of(plan_body("shaper", 1.0))["key"], key);
}

// ---------------------------------------------------------------------------------------------
// The plan's law back through simulate.

void expect_same_prediction(const json& simulated, const json& plan) {
  for (const char* model : {"nonlinear", "linear"}) {
    for (const char* peak : {"eta_motion_mm", "eta_rest_mm"}) {
      const double p = plan["prediction"][model][peak].get<double>();
      const double s = simulated["prediction"][model][peak].get<double>();
      EXPECT_NEAR(s, p, 1e-9 * std::abs(p)) << model << " " << peak;
    }
  }
  for (const char* k : {"a_max", "a_min", "v_peak", "j_peak"}) {
    const double p = plan["kinematics"][k].get<double>();
    EXPECT_NEAR(simulated["kinematics"][k].get<double>(), p, 1e-9 * p) << k;
  }
}

TEST(FilterRoundTrip, ThePlannedLawSimulatesToThePlansPrediction) {
  const std::vector<json> bodies{
      plan_body("fir_chain", 1.0),
      plan_body("fir_chain", 1.6),
      plan_body("shaper", 1.0),
      plan_body("shaper", 1.0, {{"shaper", "ei"}, {"base", "modified_trapezoid"}}),
      plan_body("shaper", 1.0, {{"shaper", "zvd"}, {"base", "seven_segment_uniform"}}),
      plan_body("iir", 1.0, {{"iir_order", 2}}),
      plan_body("iir", 1.0, {{"iir_order", 3}, {"base", "modified_trapezoid"}}),
  };
  for (const json& body : bodies) {
    SCOPED_TRACE(body.dump());
    const json& plan = plan_of(body);
    ASSERT_EQ(plan["status"], "optimal");
    const json request{{"format", body["format"]}, {"law", plan["law"]}};
    json simulated;
    try {
      simulated = run_simulate(parse_simulate_request(request));
    } catch (const ApiError& e) {
      ADD_FAILURE() << "simulate rejected the plan's law: " << e.field() << ": " << e.what();
      continue;
    }
    EXPECT_EQ(simulated["law"]["type"], plan["law"]["type"]);
    EXPECT_NEAR(simulated["law"]["duration_s"].get<double>(), body["format"]["motion_time_s"],
                1e-12);
    EXPECT_NEAR(simulated["law"]["stroke_mm"].get<double>(), 800.0, 1e-9);
    expect_same_prediction(simulated, plan);
  }
}

// Regression (found by this suite): a plan on a valid but violent format (2 m in 0.3 s) returned
// an optimal iir law with samples above the 1e4 m/s^2 simulate then accepted, so simulate and
// export rejected the plan's own law. Every planned law stays within kMaxLawAcceleration, the
// bound simulate accepts.
TEST(FilterRoundTrip, EveryOptimalPlanLawIsAcceptedBySimulate) {
  json body = plan_body("iir", 0.3);
  body["format"]["container"] = {{"radius_mm", 150}, {"height_mm", 150}};
  body["format"]["fill_height_mm"] = 100;
  body["format"]["stroke_mm"] = 2000;
  const json& plan = plan_of(body);
  // The filter is designed exactly, but its law spills and sloshes more than the uniform law:
  // acceptable, not optimal. Its law is the plan's all the same.
  ASSERT_EQ(plan["status"], "acceptable") << plan["message"];
  const json request{{"format", body["format"]}, {"law", plan["law"]}};
  try {
    (void)parse_simulate_request(request);
  } catch (const ApiError& e) {
    ADD_FAILURE() << "simulate rejects the law of an optimal plan: " << e.field() << ": "
                  << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Validation of the new plan options.

TEST(FilterOptionValidation, OutOfRangeAndWrongTypeNameFieldValueAndRange) {
  struct Case {
    const char* key;
    json value;
    double T;
    const char* message;
  };
  const char* period_hint = " (the upper bound is min(0.01 s, format.motion_time_s / 20))";
  const std::vector<Case> cases{
      {"iir_order", 4, 1.0,
       "options.iir_order = 4 is out of range: allowed an integer from 2 to 3"},
      {"iir_order", 1, 1.0,
       "options.iir_order = 1 is out of range: allowed an integer from 2 to 3"},
      {"iir_order", 2.5, 1.0,
       "options.iir_order = 2.5 is not an integer: allowed an integer from 2 to 3"},
      {"iir_order", "3", 1.0, "options.iir_order must be an integer from 2 to 3, got \"3\""},
      {"iir_tau", 0.5, 1.0, "options.iir_tau = 0.5 is out of range: allowed 1 to 1000 1/s"},
      {"iir_tau", 1000.5, 1.0, "options.iir_tau = 1000.5 is out of range: allowed 1 to 1000 1/s"},
      {"iir_tau", "fast", 1.0,
       "options.iir_tau must be a number, got \"fast\"; allowed 1 to 1000 1/s"},
      {"residual", 1, 1.0, "options.residual = 1 is out of range: allowed >= 0 and < 1"},
      {"residual", -0.01, 1.0, "options.residual = -0.01 is out of range: allowed >= 0 and < 1"},
      {"shaper", "zvx", 1.0,
       "options.shaper = \"zvx\" is not allowed: one of \"zv\", \"mzv\", \"zvd\", \"zvdd\", "
       "\"ei\", \"ei2\", \"ei3\""},
      {"shaper", 2, 1.0,
       "options.shaper = 2 is not allowed: one of \"zv\", \"mzv\", \"zvd\", \"zvdd\", \"ei\", "
       "\"ei2\", \"ei3\""},
      {"base", "cubic", 1.0,
       "options.base = \"cubic\" is not allowed: one of \"poly5\", \"modified_trapezoid\", "
       "\"seven_segment_uniform\""},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.key) + " = " + c.value.dump());
    json body = plan_body("iir", c.T);
    body["options"][c.key] = c.value;
    const ApiError e = test::plan_parse_error(body);
    EXPECT_EQ(e.code(), ErrorCode::kInvalidValue);
    EXPECT_EQ(e.status(), 422);
    EXPECT_EQ(e.field(), std::string("options.") + c.key);
    EXPECT_STREQ(e.what(), c.message);
  }
  // The sample period: at most min(0.01 s, T / 20).
  {
    json body = plan_body("iir", 0.1, {{"min_ramp_s", 0.02}, {"iir_sample_period_s", 0.006}});
    const ApiError e = test::plan_parse_error(body);
    EXPECT_EQ(e.field(), "options.iir_sample_period_s");
    EXPECT_EQ(std::string(e.what()),
              std::string("options.iir_sample_period_s = 0.006 is out of range: allowed 0.0001 "
                          "to 0.005 s") +
                  period_hint);
  }
  {
    json body = plan_body("iir", 1.0, {{"iir_sample_period_s", 0.02}});
    const ApiError e = test::plan_parse_error(body);
    EXPECT_EQ(e.field(), "options.iir_sample_period_s");
    EXPECT_EQ(std::string(e.what()),
              std::string("options.iir_sample_period_s = 0.02 is out of range: allowed 0.0001 to "
                          "0.01 s") +
                  period_hint);
  }
  {
    json body = plan_body("iir", 1.0, {{"iir_sample_period_s", 5e-5}});
    const ApiError e = test::plan_parse_error(body);
    EXPECT_EQ(e.field(), "options.iir_sample_period_s");
    EXPECT_EQ(std::string(e.what()),
              std::string("options.iir_sample_period_s = 5e-05 is out of range: allowed 0.0001 to "
                          "0.01 s") +
                  period_hint);
  }
}

TEST(FilterOptionValidation, BoundsAndDefaults) {
  const PlanRequest d = parse_plan_request(plan_body("iir", 1.0));
  EXPECT_EQ(to_string(d.options.base), "poly5");
  EXPECT_EQ(to_string(d.options.shaper), "zv");
  EXPECT_EQ(d.options.residual, 0.05);
  EXPECT_EQ(static_cast<int>(d.options.iir_order), 3);
  EXPECT_EQ(d.options.iir_tau, 50.0);
  EXPECT_EQ(d.options.iir_sample_period, 0.001);
  // Closed bounds are accepted; T / 20 is the period's upper bound for short motions.
  const PlanRequest r = parse_plan_request(plan_body("iir", 0.1,
                                                     {{"min_ramp_s", 0.02},
                                                      {"iir_sample_period_s", 0.005},
                                                      {"iir_tau", 1000},
                                                      {"iir_order", 2.0},
                                                      {"residual", 0},
                                                      {"base", "seven_segment_uniform"},
                                                      {"shaper", "zvdd"}}));
  EXPECT_EQ(r.options.iir_sample_period, 0.005);
  EXPECT_EQ(r.options.iir_tau, 1000.0);
  EXPECT_EQ(static_cast<int>(r.options.iir_order), 2);
  EXPECT_EQ(r.options.residual, 0.0);
  EXPECT_EQ(to_string(r.options.base), "seven_segment_uniform");
  EXPECT_EQ(to_string(r.options.shaper), "zvdd");
  EXPECT_EQ(parse_plan_request(plan_body("iir", 1.0, {{"iir_tau", 1}})).options.iir_tau, 1.0);
  EXPECT_EQ(parse_plan_request(plan_body("iir", 1.0, {{"iir_sample_period_s", 1e-4}}))
                .options.iir_sample_period,
            1e-4);
}

// ---------------------------------------------------------------------------------------------
// Validation of general laws in simulate requests.

json simulate_body(const json& law, double stroke_mm = 800) {
  json f = thesis_format(1.0);
  f["stroke_mm"] = stroke_mm;
  return {{"format", f}, {"law", law}};
}

::testing::AssertionResult Rejects(const json& body, const std::string& field,
                                   const std::string& message) {
  try {
    (void)parse_simulate_request(body);
  } catch (const ApiError& e) {
    if (e.code() != ErrorCode::kInvalidValue || e.status() != 422) {
      return ::testing::AssertionFailure() << "status " << e.status() << ": " << e.what();
    }
    if (e.field() != field) {
      return ::testing::AssertionFailure()
             << "field\n  actual:   " << e.field() << "\n  expected: " << field;
    }
    if (std::string(e.what()) != message) {
      return ::testing::AssertionFailure()
             << "message\n  actual:   " << e.what() << "\n  expected: " << message;
    }
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "accepted: " << body.dump();
}

::testing::AssertionResult Accepts(const json& body) {
  try {
    (void)parse_simulate_request(body);
  } catch (const ApiError& e) {
    return ::testing::AssertionFailure() << "rejected: " << e.field() << ": " << e.what();
  }
  return ::testing::AssertionSuccess();
}

json linear_law(const std::vector<double>& t, const std::vector<double>& a) {
  return {{"type", "piecewise_linear"}, {"breakpoints_s", t}, {"acceleration_m_s2", a}};
}

/// A triangle up, a triangle down (peak 8 m/s^2): v goes 0, 1, 2, 1, 0 m/s at the breakpoints
/// (dyadic numbers: exact), and s(T) = int (T - t) a(t) dt = 1 m.
json bang_bang_law() {
  return linear_law({0, 0.25, 0.5, 0.75, 1.0}, {0, 8, 0, -8, 0});
}

TEST(SimulateLawValidation, ValidGeneralLawsAreAcceptedAndSimulated) {
  // The bang-bang law over 1000 mm: a peak 8, v peak 2 (at T/2), jerk 32.
  const json out = run_simulate(parse_simulate_request(simulate_body(bang_bang_law(), 1000)));
  EXPECT_EQ(out["law"]["type"], "piecewise_linear");
  EXPECT_NEAR(out["kinematics"]["a_max"].get<double>(), 8.0, 1e-12);
  EXPECT_NEAR(out["kinematics"]["a_min"].get<double>(), 8.0, 1e-12);
  EXPECT_NEAR(out["kinematics"]["v_peak"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(out["kinematics"]["j_peak"].get<double>(), 32.0, 1e-12);
  // Poly5 written as one cubic piece (a = S/T^2 (60u - 180u^2 + 120u^3)) simulates like "poly5".
  const double S = 0.8;
  const json cubic{
      {"type", "piecewise"},
      {"pieces",
       {{{"t_begin_s", 0.0}, {"t_end_s", 1.0}, {"a_poly", {0.0, 60 * S, -180 * S, 120 * S}}}}}};
  const json a = run_simulate(parse_simulate_request(simulate_body(cubic)));
  const json b = run_simulate(parse_simulate_request(simulate_body({{"type", "poly5"}})));
  EXPECT_EQ(a["law"]["type"], "piecewise");
  for (const char* model : {"nonlinear", "linear"}) {
    for (const char* peak : {"eta_motion_mm", "eta_rest_mm"}) {
      EXPECT_NEAR(a["prediction"][model][peak].get<double>(),
                  b["prediction"][model][peak].get<double>(),
                  1e-9 * b["prediction"][model][peak].get<double>())
          << model << " " << peak;
    }
  }
}

TEST(SimulateLawValidation, PiecewiseLinearErrors) {
  EXPECT_TRUE(Rejects(simulate_body(linear_law({0, 0.5, 1.0}, {0, 1})), "law.acceleration_m_s2",
                      "law.acceleration_m_s2 has 2 values but law.breakpoints_s has 3: one "
                      "acceleration per breakpoint"));
  EXPECT_TRUE(Rejects(simulate_body(linear_law({0.1, 0.5, 1.0}, {0, 1, 0})), "law.breakpoints_s[0]",
                      "law.breakpoints_s[0] = 0.1 must be 0: the law starts at t = 0"));
  EXPECT_TRUE(Rejects(simulate_body(linear_law({0, 0.9}, {0, 0})), "law.breakpoints_s[1]",
                      "law.breakpoints_s[1] = 0.9 s must equal format.motion_time_s = 1 s "
                      "(tolerance 1e-6 s): the law ends there"));
  EXPECT_TRUE(Rejects(simulate_body(linear_law({0, 0.5, 1.1}, {0, 0, 0})), "law.breakpoints_s[2]",
                      "law.breakpoints_s[2] = 1.1 s must equal format.motion_time_s = 1 s "
                      "(tolerance 1e-6 s): the law ends there"));
  // Non-increasing: the field and the lower bound (the upper bound: the regression test below).
  try {
    (void)parse_simulate_request(simulate_body(linear_law({0, 0.5, 0.5, 1.0}, {0, 1, 1, 0})));
    ADD_FAILURE() << "non-increasing breakpoints accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field(), "law.breakpoints_s[2]");
    EXPECT_EQ(std::string(e.what()).rfind("law.breakpoints_s[2] = 0.5 is out of range: allowed "
                                          "0.500000001 to ",
                                          0),
              0u)
        << e.what();
  }
  // Not rest-to-rest: a triangle leaves v = 0.5 m/s and s = int (1 - t) a dt = 0.25 m.
  EXPECT_TRUE(Rejects(simulate_body(linear_law({0, 0.5, 1.0}, {0, 1, 0})), "law.acceleration_m_s2",
                      "law.acceleration_m_s2 integrates to a final velocity of 0.5 m/s and a final "
                      "position of 250 mm: a law must end at rest (|v| <= 1e-6 m/s) at "
                      "format.stroke_mm = 800 mm (within 0.001 mm)"));
  // At rest, but 1000 mm away instead of 800 mm.
  EXPECT_TRUE(Rejects(simulate_body(bang_bang_law()), "law.acceleration_m_s2",
                      "law.acceleration_m_s2 integrates to a final velocity of 0 m/s and a final "
                      "position of 1000 mm: a law must end at rest (|v| <= 1e-6 m/s) at "
                      "format.stroke_mm = 800 mm (within 0.001 mm)"));
  EXPECT_TRUE(Rejects(simulate_body(bang_bang_law(), 1000.002), "law.acceleration_m_s2",
                      "law.acceleration_m_s2 integrates to a final velocity of 0 m/s and a final "
                      "position of 1000 mm: a law must end at rest (|v| <= 1e-6 m/s) at "
                      "format.stroke_mm = 1000.002 mm (within 0.001 mm)"));
  // The other law types' members are not allowed.
  json with_pieces = bang_bang_law();
  with_pieces["pieces"] = json::array();
  EXPECT_TRUE(Rejects(simulate_body(with_pieces), "law.pieces",
                      "law.pieces is not allowed with law.type \"piecewise_linear\""));
}

// Regression (found by this suite): the range a breakpoint message stated ran up to T + 1 s,
// and a breakpoint beyond T was accepted until a later one was blamed for it.
TEST(SimulateLawValidation, BreakpointRangeEndsAtTheMotionTime) {
  try {
    (void)parse_simulate_request(simulate_body(linear_law({0, 0.5, 0.5, 1.0}, {0, 1, 1, 0})));
    ADD_FAILURE() << "non-increasing breakpoints accepted";
  } catch (const ApiError& e) {
    const std::string text = e.what();
    const auto at = text.find(" to ");
    ASSERT_NE(at, std::string::npos) << text;
    EXPECT_NEAR(std::stod(text.substr(at + 4)), 1.0, 1e-6) << text;
  }
  try {
    (void)parse_simulate_request(simulate_body(linear_law({0, 1.5, 1.0}, {0, 0, 0})));
    ADD_FAILURE() << "a breakpoint after the motion time accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field(), "law.breakpoints_s[1]") << e.what();
  }
}

TEST(SimulateLawValidation, PiecewiseErrors) {
  const json piece0{{"t_begin_s", 0.0}, {"t_end_s", 0.5}, {"a_poly", {1.0}}};
  json law{{"type", "piecewise"}, {"pieces", {piece0}}, {"durations_s", {0.5, 0.5}}};
  EXPECT_TRUE(Rejects(simulate_body(law), "law.durations_s",
                      "law.durations_s is only allowed with law.type \"seven_segment\""));
  law.erase("durations_s");
  law["breakpoints_s"] = {0, 1};
  EXPECT_TRUE(Rejects(simulate_body(law), "law.breakpoints_s",
                      "law.breakpoints_s is not allowed with law.type \"piecewise\""));
  // Pieces must be contiguous: the second starts where the first ends (within 1e-9 s).
  const json gap{{"type", "piecewise"},
                 {"pieces", {piece0, {{"t_begin_s", 0.6}, {"t_end_s", 1.0}, {"a_poly", {-1.0}}}}}};
  EXPECT_TRUE(Rejects(simulate_body(gap), "law.pieces[1].t_begin_s",
                      "law.pieces[1].t_begin_s = 0.6 is out of range: allowed 0.499999999 to "
                      "0.500000001 s"));
  const json five{
      {"type", "piecewise"},
      {"pieces", {{{"t_begin_s", 0.0}, {"t_end_s", 1.0}, {"a_poly", {1, 2, 3, 4, 5}}}}}};
  EXPECT_TRUE(Rejects(simulate_body(five), "law.pieces[0].a_poly",
                      "law.pieces[0].a_poly must be an array of 1 to 4 coefficients c0..c3 "
                      "(m/s^2 ... m/s^5), got [1,2,3,4,5]"));
  const json short_law{{"type", "piecewise"}, {"pieces", {piece0}}};
  EXPECT_TRUE(Rejects(simulate_body(short_law), "law.pieces[0].t_end_s",
                      "law.pieces[0].t_end_s = 0.5 s must equal format.motion_time_s = 1 s "
                      "(tolerance 1e-6 s): the law ends there"));
  // A square wave +1 / -1 ends at rest but 250 mm from the start.
  const json square{
      {"type", "piecewise"},
      {"pieces", {piece0, {{"t_begin_s", 0.5}, {"t_end_s", 1.0}, {"a_poly", {-1.0}}}}}};
  EXPECT_TRUE(Rejects(simulate_body(square), "law.pieces",
                      "law.pieces integrates to a final velocity of 0 m/s and a final position of "
                      "250 mm: a law must end at rest (|v| <= 1e-6 m/s) at format.stroke_mm = 800 "
                      "mm (within 0.001 mm)"));
  EXPECT_TRUE(Accepts(simulate_body(square, 250)));
}

// ---------------------------------------------------------------------------------------------
// Infeasible designs.

/// The uniform 7-segment law of T.
void expect_uniform_law(const json& plan, double T) {
  ASSERT_EQ(plan["law"]["type"], "seven_segment");
  ASSERT_EQ(plan["law"]["durations_s"].size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_NEAR(plan["law"]["durations_s"][i].get<double>(), T / 7.0, 1e-15) << i;
    EXPECT_NEAR(plan["durations_s"][i].get<double>(), T / 7.0, 1e-15) << i;
  }
  EXPECT_NE(plan["message"].get<std::string>().find(
                "the law returned is the uniform 7-segment law, not a solution"),
            std::string::npos)
      << plan["message"];
}

TEST(FilterInfeasible, ShaperLongerThanTheMotion) {
  const double T = 0.4;
  const json& plan = plan_of(plan_body("shaper", T, {{"shaper", "zvdd"}}));
  EXPECT_EQ(plan["status"], "infeasible");
  const double delay = 1.5 * damped_period(plan);  // 4 impulses, Td / 2 apart
  ASSERT_GT(delay, T);
  EXPECT_NEAR(plan["design"]["delay_s"].get<double>(), delay, 1e-12);
  EXPECT_NE(plan["message"].get<std::string>().find(
                "the zvdd shaper delays the law by " + g3(delay) + " s of T = " + g3(T) +
                " s, leaving less than the 1 ms a base law needs"),
            std::string::npos)
      << plan["message"];
  expect_uniform_law(plan, T);
}

TEST(FilterInfeasible, IirDelayLongerThanTheMotion) {
  const double T = 0.5;
  const json& plan = plan_of(plan_body("iir", T, {{"iir_tau", 1}}));
  EXPECT_EQ(plan["status"], "infeasible");
  const double delay = plan["design"]["delay_s"].get<double>();
  EXPECT_GT(delay, T);
  EXPECT_NE(
      plan["message"].get<std::string>().find(
          "the order-3 IIR filter (tau = 1 1/s, T_s = 1 ms) delays a poly5 law by " + g3(delay) +
          " s of T = " + g3(T) + " s, leaving less than the 1 ms a base law needs"),
      std::string::npos)
      << plan["message"];
  expect_uniform_law(plan, T);
}

TEST(FilterInfeasible, FirChainAboveTheAccelerationLimit) {
  const double T = 1.0;
  const json& plan = plan_of(plan_body("fir_chain", T, {{"limits", {{"a_max", 7}}}}));
  EXPECT_EQ(plan["status"], "infeasible");
  const double T1 = (T - damped_period(plan)) / 2.0;
  const double peak = kStroke / (T1 * T1);
  ASSERT_GT(peak, 7.0);
  EXPECT_NE(plan["message"].get<std::string>().find("the law's peak acceleration " + g3(peak) +
                                                    " m/s^2 exceeds limits.a_max = 7 m/s^2"),
            std::string::npos)
      << plan["message"];
  // Below the peak the same chain is optimal.
  EXPECT_EQ(plan_of(plan_body("fir_chain", T, {{"limits", {{"a_max", 7.1}}}}))["status"],
            "optimal");
}

// ---------------------------------------------------------------------------------------------
// The real binary.

using test::read_file;
using test::run_slosh;
using test::RunResult;
using test::TempDir;
using test::write_file;

json parse_or_fail(const std::string& text) {
  try {
    return json::parse(text);
  } catch (const json::exception&) {
    ADD_FAILURE() << "not JSON: " << text.substr(0, 300);
  }
  return json::object();
}

TEST(FilterCli, PlanPrintsTheShaperPlan) {
  const json body = plan_body("shaper", 1.0, {{"shaper", "zvd"}, {"base", "modified_trapezoid"}});
  const RunResult r = run_slosh({"plan", "--request", "-"}, body.dump());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = parse_or_fail(r.out);
  const json& in_process = plan_of(body);
  EXPECT_EQ(out["strategy"], "shaper");
  EXPECT_EQ(out["status"], "optimal");
  EXPECT_EQ(out["key"], in_process["key"]);
  EXPECT_EQ(out["law"], in_process["law"]);
  EXPECT_EQ(out["design"], in_process["design"]);
  EXPECT_EQ(out["prediction"], in_process["prediction"]);
  EXPECT_TRUE(out["durations_s"].is_null());
}

TEST(FilterCli, ExportWritesTheCamTableOfTheShapedLaw) {
  const TempDir dir;
  const json body = plan_body("shaper", 1.0, {{"shaper", "zvd"}});
  write_file(dir / "request.json", body.dump());
  const RunResult r = run_slosh({"export", "--request", (dir / "request.json").string(), "--out",
                                 (dir / "cam.csv").string(), "--cache", ""});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = parse_or_fail(r.out);
  EXPECT_EQ(summary["source"], "plan");
  EXPECT_EQ(summary["law"], "piecewise");
  EXPECT_EQ(summary["status"], "optimal");
  EXPECT_EQ(summary["samples"], 1001);

  const JsonLaw law(plan_of(body)["law"], kStroke);
  const auto rows = test::csv_texts(read_file(dir / "cam.csv"));
  ASSERT_EQ(rows.size(), 1002u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"t_s", "position_mm", "velocity_mm_s",
                                               "acceleration_mm_s2", "jerk_mm_s3"}));
  for (std::size_t k = 1; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 5u) << k;
    const double t = std::stod(rows[k][0]);
    EXPECT_NEAR(t, 0.001 * static_cast<double>(k - 1), 1e-12) << k;
    EXPECT_NEAR(std::stod(rows[k][1]), law.position(t) * 1e3, 1e-6) << t;
    EXPECT_NEAR(std::stod(rows[k][2]), law.velocity(t) * 1e3, 1e-6) << t;
    EXPECT_NEAR(std::stod(rows[k][3]), law.a(t) * 1e3, 1e-6) << t;
  }
  EXPECT_EQ(rows.back()[0], "1");
  EXPECT_EQ(rows.back()[1], "800");
  EXPECT_EQ(rows.back()[2], "0");

  // No 7-segment table for a general law: exit 2 naming --segments, nothing written.
  const RunResult s = run_slosh({"export", "--request", (dir / "request.json").string(), "--out",
                                 (dir / "cam2.csv").string(), "--segments",
                                 (dir / "seg.csv").string(), "--cache", ""});
  EXPECT_EQ(s.exit_code, 2) << s.err;
  EXPECT_EQ(s.out, "");
  EXPECT_EQ(parse_or_fail(s.err),
            json({{"error",
                   {{"code", "invalid_value"},
                    {"field", "--segments"},
                    {"message",
                     "--segments: the law piecewise is not a 7-segment law; it has no segment "
                     "table"}}}}));
  EXPECT_FALSE(fs::exists(dir / "cam2.csv"));
  EXPECT_FALSE(fs::exists(dir / "seg.csv"));
}

TEST(FilterHttp, IirPlanIsServedThenCachedAndItsLawSimulates) {
  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  auto client = server.client();
  const json body = plan_body("iir", 1.0, {{"iir_order", 2}});
  const auto first = client.Post("/v1/plans", body.dump(), "application/json");
  ASSERT_TRUE(first) << httplib::to_string(first.error());
  ASSERT_EQ(first->status, 200) << first->body;
  const json a = parse_or_fail(first->body);
  EXPECT_EQ(a["cached"], false);
  EXPECT_EQ(a["status"], "optimal");
  EXPECT_EQ(a["law"]["type"], "piecewise_linear");
  EXPECT_EQ(a["design"]["method"], "iir");
  EXPECT_EQ(a["law"], plan_of(body)["law"]);

  const auto second = client.Post("/v1/plans", body.dump(), "application/json");
  ASSERT_TRUE(second);
  ASSERT_EQ(second->status, 200);
  json b = parse_or_fail(second->body);
  EXPECT_EQ(b["cached"], true);
  b["cached"] = false;
  EXPECT_EQ(b, a);

  const json sim{{"format", body["format"]}, {"law", a["law"]}};
  const auto simulated = client.Post("/v1/simulate", sim.dump(), "application/json");
  ASSERT_TRUE(simulated);
  ASSERT_EQ(simulated->status, 200) << simulated->body;
  expect_same_prediction(parse_or_fail(simulated->body), a);
}

TEST(FilterCli, BatchPlansTheNewStrategiesWithTheirOptionColumns) {
  const TempDir dir;
  write_file(dir / "in.csv",
             "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy,base,"
             "shaper,residual,iir_order,iir_tau,iir_sample_period_s\n"
             "s1,48.5,82,water,800,1.0,shaper,modified_trapezoid,ei,0.1,,,\n"
             "i1,48.5,82,water,800,1.0,iir,poly5,,,2,80,0.002\n"
             "f1,48.5,82,water,800,1.0,fir_chain,,,,,,\n"
             "f2,48.5,82,water,800,1.6,fir_chain,,,,,,\n"
             "bad,48.5,82,water,800,1.0,iir,,,,4,,\n");
  const RunResult r = run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out",
                                 (dir / "out.csv").string(), "--cache", "", "--progress", "never"});
  EXPECT_EQ(r.exit_code, 3) << r.err;  // one row could not be planned
  const auto rows = test::csv_texts(read_file(dir / "out.csv"));
  ASSERT_EQ(rows.size(), 6u);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < rows[0].size(); ++i) col[rows[0][i]] = i;
  for (const char* c :
       {"recipe_id", "status", "key", "strategy", "law_type", "T1_s", "T7_s", "A_m_s2", "B_m_s2",
        "v_peak_m_s", "j_peak_m_s3", "error_field", "message"}) {
    ASSERT_TRUE(col.contains(c)) << c;
  }
  auto cell = [&](std::size_t row, const std::string& name) { return rows[row][col.at(name)]; };

  // The same recipes as JSON requests (no container height: the CSV gives none).
  auto request = [](double T, const std::string& strategy, const json& options) {
    json f = json::parse(R"({"container": {"radius_mm": 48.5}, "fill_height_mm": 82,
        "fluid": "water", "stroke_mm": 800})");
    f["motion_time_s"] = T;
    return json{{"format", f}, {"strategy", strategy}, {"options", options}};
  };
  const std::vector<std::pair<json, std::string>> expected{
      {request(1.0, "shaper",
               {{"base", "modified_trapezoid"}, {"shaper", "ei"}, {"residual", 0.1}}),
       "piecewise"},
      {request(
           1.0, "iir",
           {{"base", "poly5"}, {"iir_order", 2}, {"iir_tau", 80}, {"iir_sample_period_s", 0.002}}),
       "piecewise_linear"},
      {request(1.0, "fir_chain", json::object()), "piecewise_linear"},
      {request(1.6, "fir_chain", json::object()), "seven_segment"},
  };
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const std::size_t row = i + 1;
    SCOPED_TRACE(cell(row, "recipe_id"));
    const json& plan = plan_of(expected[i].first);
    EXPECT_EQ(cell(row, "status"), "optimal");
    EXPECT_EQ(cell(row, "strategy"), expected[i].first["strategy"]);
    EXPECT_EQ(cell(row, "law_type"), expected[i].second);
    EXPECT_EQ(cell(row, "key"), recipe_key(parse_plan_request(expected[i].first)));
    EXPECT_EQ(std::stod(cell(row, "A_m_s2")), plan["kinematics"]["a_max"].get<double>());
    EXPECT_EQ(std::stod(cell(row, "B_m_s2")), plan["kinematics"]["a_min"].get<double>());
    EXPECT_EQ(std::stod(cell(row, "v_peak_m_s")), plan["kinematics"]["v_peak"].get<double>());
    EXPECT_EQ(std::stod(cell(row, "j_peak_m_s3")), plan["kinematics"]["j_peak"].get<double>());
    for (int k = 1; k <= 7; ++k) {
      const std::string name = "T" + std::to_string(k) + "_s";
      if (expected[i].second == "seven_segment") {
        EXPECT_EQ(std::stod(cell(row, name)),
                  plan["durations_s"][static_cast<std::size_t>(k - 1)].get<double>())
            << name;
      } else {
        EXPECT_EQ(cell(row, name), "") << name;
      }
    }
  }
  // f2: the closed-form durations [T3, T/2 - 2 T3, T3, 0, ...] with T = 1.6 s.
  const double T3 = damped_period(plan_of(expected[3].first));
  EXPECT_NEAR(std::stod(cell(4, "T1_s")), T3, 1e-12);
  EXPECT_NEAR(std::stod(cell(4, "T2_s")), 0.8 - 2 * T3, 1e-12);
  EXPECT_NEAR(std::stod(cell(4, "T4_s")), 0.0, 1e-12);
  // The bad iir_order, in the CSV's own terms.
  EXPECT_EQ(cell(5, "status"), "error");
  EXPECT_EQ(cell(5, "error_field"), "iir_order");
  EXPECT_EQ(cell(5, "message"), "iir_order = 4 is out of range: allowed an integer from 2 to 3");
  EXPECT_EQ(cell(5, "law_type"), "");
}

}  // namespace test_filter_api
}  // namespace slosh::api
