// The JDSMC paper's filtering strategies ([JDSMC] in docs/models.md, sec. 3.1, 3.3, 3.4, 4):
// closed-form laws of the prescribed duration, checked against the machine limits and the 7-segment
// options that apply to them.

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "slosh/core/strategy/rectangular_plan.hpp"
#include "strategy/strategies.hpp"
#include "text.hpp"

namespace slosh::detail {

std::string limit_violation(const MachineLimits& lim, double a_peak, double v_peak, double j_peak,
                            double slack) {
  const struct {
    const char* name;
    const char* what;
    const char* unit;
    std::optional<double> limit;
    double value;
  } checks[] = {{"a_max", "acceleration", "m/s^2", lim.a_max, a_peak},
                {"v_max", "velocity", "m/s", lim.v_max, v_peak},
                {"j_max", "jerk", "m/s^3", lim.j_max, j_peak}};
  for (const auto& k : checks) {
    if (k.limit && k.value > *k.limit * (1.0 + slack)) {
      return std::string("the law's peak ") + k.what + " " + sig_above(k.value, *k.limit) + " " +
             k.unit + " exceeds limits." + k.name + " = " + precise(*k.limit) + " " + k.unit;
    }
  }
  return {};
}

namespace {

/// v > 0 rounded down to 3 significant digits, as text: a bound that the value keeps.
std::string sig3_below(double v) {
  const double scale = std::pow(10.0, 2.0 - std::floor(std::log10(v)));
  return sig3(std::floor(v * scale) / scale);
}

}  // namespace

namespace {

/// Relative slack of the limit checks (round-off of the closed forms) [-].
constexpr double kLimitSlack{1e-9};

/// The uniform 7-segment law, returned when a method has no law for the format; when the
/// options exclude it (min_ramp above T/7, ...), baseline's admissible law instead.
FilterOutcome no_law(const StrategyContext& c, std::string why) {
  FilterOutcome o;
  o.status = SolveStatus::kInfeasible;
  const bool uniform = c.space.uniform_inside();
  o.durations = c.space.nearest_uniform();
  o.law = SevenSegmentLaw(*o.durations, c.format.stroke).law();
  o.detail = std::move(why) + (uniform ? "; the law returned is the uniform 7-segment law, not a "
                                         "solution"
                                       : "; the law returned is baseline's (the uniform law breaks "
                                         "the options: every segment at its minimum plus an equal "
                                         "share), not a solution");
  return o;
}

/// When the law is beyond any machine (|a| > kMaxLawAcceleration), the sentence saying so.
std::string beyond_any_machine(const KinematicSummary& k) {
  const double a = std::max(k.a_peak_positive, k.a_peak_negative);
  if (a <= kMaxLawAcceleration) return {};
  return "the law would reach " + sig3(a) + " m/s^2, beyond the " + sig3(kMaxLawAcceleration) +
         " m/s^2 any law may have";
}

/// Marks the outcome infeasible when the law (whose peaks are `k`) exceeds a limit.
void check_limits(const StrategyContext& c, const KinematicSummary& k, FilterOutcome* o) {
  const std::string violation =
      limit_violation(c.options.limits, std::max(k.a_peak_positive, k.a_peak_negative), k.v_peak,
                      k.j_peak, kLimitSlack);
  if (violation.empty()) {
    o->status = SolveStatus::kOptimal;
    return;
  }
  o->status = SolveStatus::kInfeasible;
  o->detail += "; " + violation + ": lengthen the motion or raise the limit";
}

std::string ms(double seconds) {
  return sig3(seconds * 1e3) + " ms";
}

/// For a mode 1 that does not oscillate (zeta >= 1: critically or over-damped), the sentence
/// saying why `method` has no law; empty otherwise.
std::string over_damped(const StrategyContext& c, const std::string& method) {
  if (c.design_model.zeta < 1.0) return {};
  return method +
         " cancels the oscillation of mode 1, but with zeta = " + sig3(c.design_model.zeta) +
         " (>= 1: " + (c.design_model.zeta == 1.0 ? "critically" : "over") +
         "-damped, a viscous liquid) mode 1 does not oscillate: there is nothing to cancel and "
         "the design is undefined; use baseline, notch, multi_notch or time_domain instead";
}

}  // namespace

namespace {

std::string hz(double omega) {
  return sig3(omega / (2.0 * std::numbers::pi)) + " Hz";
}

/// A turned tank (both directions excited): true when the filters cancel each direction's first
/// mode rather than one design mode. Under an uncertainty range too: one design mode would lie
/// between the two directions and cancel neither.
bool per_direction(const StrategyContext& c) {
  return c.over_directions && c.direction_zeta[0] < 1.0 && c.direction_zeta[1] < 1.0;
}

/// Direction k's first-mode frequency the filters are designed at [rad/s]: its own, at the
/// middle of an uncertainty range's frequency factors (as one design mode is).
double design_omega_of(const StrategyContext& c, std::size_t k) {
  return c.direction_omega[k] * (c.range ? c.range->scale_mid() : 1.0);
}

/// "the length's f1 = 2.37 Hz" (", the middle of its range" under an uncertainty range).
std::string direction_f1(const StrategyContext& c, std::size_t k) {
  return std::string("the ") + c.direction_name[k] + "'s f1 = " + hz(design_omega_of(c, k)) +
         (c.range ? " (the middle of its range)" : "");
}

/// fir_chain on a turned tank: two of the three filters last the two directions' damped
/// periods (a rectangular filter of duration P has its spectral zeros at 2 pi k / P, so each
/// cancels one direction's first mode), the third the rest of T; ordered longest first so that
/// conditions (14) decide whether the law is a 7-segment law. Nullopt when T is not longer than
/// the two periods together.
std::optional<std::array<double, 3>> fir_chain_both(const StrategyContext& c) {
  const double Pa = damped_period(design_omega_of(c, 0), c.direction_zeta[0]);
  const double Pb = damped_period(design_omega_of(c, 1), c.direction_zeta[1]);
  const double rest = c.format.motion_time - Pa - Pb;
  if (!(rest > 0.0)) return std::nullopt;
  std::array<double, 3> t{rest, Pa, Pb};
  std::sort(t.begin(), t.end(), std::greater<>());
  return t;
}

}  // namespace

/// The chain of filters T1, T2, T3 checked against the limits and options; `how` says how they
/// were chosen, `left` (empty or "; ...") which mode the chain leaves.
FilterOutcome fir_chain_of(const StrategyContext& c, double T1, double T2, double T3,
                           const std::string& how, const std::string& left, bool two_modes);

namespace {

// A turned tank whose second direction is below kFullDirectionShare: the chain moves from the
// first direction's own (T1, T2, its period T3) toward the two periods by the engagement e, one
// filter's duration from T2 to the second direction's period (T1 taking the rest of T):
// continuous in the share, the first mode cancelled throughout.
FilterOutcome fir_chain_engaged(const StrategyContext& c, double T2, double T3) {
  const double T = c.format.motion_time;
  const double e = c.direction_engagement;
  const double Pb = damped_period(design_omega_of(c, 1), c.direction_zeta[1]);
  const double T2e = (1.0 - e) * T2 + e * Pb;
  std::array<double, 3> t{T - T3 - T2e, T2e, T3};
  std::sort(t.begin(), t.end(), std::greater<>());
  return fir_chain_of(c, t[0], t[1], t[2],
                      "T1, T2, T3 = " + sig3(t[0]) + ", " + sig3(t[1]) + ", " + sig3(t[2]) +
                          " s: the damped period of " + direction_f1(c, 0) +
                          ", which it cancels, and one filter moved from " + sig3(T2) +
                          " s toward the damped period of " + direction_f1(c, 1) + " by " +
                          percent(e) + " (its share " + sig3(c.direction_weight[1]) +
                          " of the residual wave is below " + sig3(kFullDirectionShare) + ")",
                      "", true);
}

}  // namespace

FilterOutcome design_fir_chain(const StrategyContext& c) {
  const double S = c.format.stroke, T = c.format.motion_time;
  if (std::string why = over_damped(c, "fir_chain"); !why.empty()) return no_law(c, why);
  // On a turned tank: both directions' modes cancelled when T allows, else the most excited
  // direction's alone (never the middle of the two, which cancels neither), and the plan says
  // which mode is left.
  std::optional<std::array<double, 3>> both;
  std::string left;
  const bool directions = per_direction(c);
  if (directions) {
    both = fir_chain_both(c);
    if (!both) {
      const double Pa = damped_period(design_omega_of(c, 0), c.direction_zeta[0]);
      const double Pb = damped_period(design_omega_of(c, 1), c.direction_zeta[1]);
      left = "; it cancels " + direction_f1(c, 0) + " only: cancelling " + direction_f1(c, 1) +
             " (share " + sig3(c.direction_weight[1]) +
             " of the residual wave) as well needs T > " + sig3(Pa + Pb) +
             " s, the sum of both damped periods";
    }
  }
  if (both && c.direction_engagement >= 1.0)
    return fir_chain_of(c, (*both)[0], (*both)[1], (*both)[2],
                        "T1, T2, T3 = " + sig3((*both)[0]) + ", " + sig3((*both)[1]) + ", " +
                            sig3((*both)[2]) + " s: two of them the damped periods of " +
                            direction_f1(c, 0) + " and " + direction_f1(c, 1) +
                            ", which they cancel",
                        "", true);
  const double design_omega = directions ? design_omega_of(c, 0) : c.design_model.omega1();
  const double design_zeta = directions ? c.direction_zeta[0] : c.design_model.zeta;
  const double T3 = damped_period(design_omega, design_zeta);
  if (!(T > T3)) {
    FilterOutcome o =
        no_law(c, "fir_chain needs T > T3: the damped period of mode 1 is T3 = " + sig3(T3) +
                      " s, not shorter than T = " + sig3(T) + " s");
    o.design = FirChainDesign{0.0, 0.0, T3, false};
    return o;
  }
  // T1 + T2 = T - T3. Conditions (14) (T2 >= T3, T1 >= T2 + T3) hold for T1 in [T/2, T - 2 T3]
  // when T >= 4 T3; T1 = T/2 gives the least peak acceleration S / (T1 T2) and jerk, a longer T1
  // the least velocity S / T1 (taken only as far as limits.v_max needs).
  double T1 = 0.5 * T;
  std::string choice;
  const bool trapezoid_possible = T >= 4.0 * T3 * (1.0 - 1e-12);
  if (trapezoid_possible) {
    const auto& v_max = c.options.limits.v_max;
    if (v_max && S / T1 > *v_max && !c.options.fix_constant_velocity_zero) {
      T1 = std::min(S / *v_max, T - 2.0 * T3);
      choice = " (T1 lengthened from T/2 for limits.v_max)";
    }
  } else {
    T1 = 0.5 * (T - T3);
    choice = " (T1 = T2: the least peak acceleration)";
  }
  const double T2 = std::max(T - T3 - T1, 0.0);
  if (both) return fir_chain_engaged(c, T2, T3);
  FilterOutcome o = fir_chain_of(c, T1, T2, T3,
                                 "T3 = " + sig3(T3) + " s (the damped period of " +
                                     (directions ? direction_f1(c, 0) : std::string("mode 1")) +
                                     "), T1 = " + sig3(T1) + " s, T2 = " + sig3(T2) + " s" + choice,
                                 left, false);
  // A mode left uncancelled: the law is what fir_chain can do, not what it promises.
  if (!left.empty() && o.status == SolveStatus::kOptimal) o.status = SolveStatus::kAcceptable;
  return o;
}

FilterOutcome fir_chain_of(const StrategyContext& c, double T1, double T2, double T3,
                           const std::string& how, const std::string& left, bool two_modes) {
  const double S = c.format.stroke, T = c.format.motion_time;
  const FirChain chain = make_fir_chain(S, T1, T2, T3);
  FilterOutcome o;
  o.design = FirChainDesign{T1, T2, T3, chain.durations.has_value()};
  o.detail = how;
  if (chain.durations) {
    // T1 + T2 + T3 is the motion time only to round-off: the sum is closed on T itself.
    o.durations = clean_durations(*chain.durations, c.format.motion_time);
    o.law = SevenSegmentLaw(*o.durations, S).law();
    o.detail += ": conditions (14) hold, a 7-segment law";
  } else {
    o.law = chain.law;
    o.detail += (two_modes ? ": conditions (14) need T1 >= T2 + T3 (T = " + sig3(T) + " s)"
                           : ": conditions (14) need T >= 4 T3 = " + sig3(4.0 * T3) +
                                 " s (T = " + sig3(T) + " s)") +
                ", so the law is not a 7-segment law (acceleration ramps without plateaus)";
  }
  const KinematicSummary peaks = o.law.summary();
  if (std::string why = beyond_any_machine(peaks); !why.empty()) {
    FilterOutcome none = no_law(c, "fir_chain with " + o.detail + ": " + why);
    none.design = o.design;
    return none;
  }
  // The mode it leaves leads: it is why the plan is only acceptable.
  if (!left.empty()) o.detail = left.substr(left.find_first_not_of("; ")) + "; " + o.detail;
  check_limits(c, peaks, &o);
  if (o.status != SolveStatus::kOptimal || !o.durations) return o;
  // The 7-segment options that constrain its durations.
  const Durations& d = *o.durations;
  std::string broken;
  if (T3 < c.options.min_ramp * (1.0 - kLimitSlack)) {
    broken = "its ramps T3 = " + sig3(T3) +
             " s are shorter than min_ramp_s = " + sig3(c.options.min_ramp) +
             " s (a min_ramp_s of at most " + sig3(T3) + " s admits the law)";
  } else if (d[1] < c.options.plateau_min[0] * (1.0 - kLimitSlack) ||
             d[5] < c.options.plateau_min[1] * (1.0 - kLimitSlack)) {
    broken = "its plateaus T2 - T3 = " + sig3(d[1]) + " s are shorter than plateau_min_s = [" +
             sig3(c.options.plateau_min[0]) + ", " + sig3(c.options.plateau_min[1]) +
             "] s (plateau_min_s of at most " + sig3_below(std::min(d[1], d[5])) +
             " s admits the law)";
  } else if (c.options.fix_constant_velocity_zero && d[3] > 1e-9 * T) {
    broken = "its constant-velocity segment is " + sig3(d[3]) +
             " s but fix_constant_velocity_zero is set (without it the law is admitted)";
  }
  if (!broken.empty()) {
    // SPEC §5: no durations that break the admissibility rules; the law is still reported.
    o.status = SolveStatus::kInfeasible;
    o.detail += "; " + broken;
    o.durations.reset();
  }
  return o;
}

namespace {

/// The shaper families in the order of their delay (ZV 1/2, MZV 3/4, ZVD and EI 1, ZVDD and
/// 2-hump EI 3/2, 3-hump EI 2 damped periods), shortest first.
constexpr std::array<ShaperType, 7> kShapersByDelay{
    ShaperType::kZV,   ShaperType::kMZV, ShaperType::kZVD, ShaperType::kEI,
    ShaperType::kZVDD, ShaperType::kEI2, ShaperType::kEI3,
};

/// The shaper `shaper` plans: the option, or with an uncertainty range (and no family named) the
/// shortest family whose residual over [omega_lo, omega_hi] at the range's least damping stays
/// <= the option `residual` V, designed at the middle of the range; when none does, the one of
/// least worst residual. `choice` gets the sentence saying so (empty for the option).
/// The shaper that cancels both modes a and b: every pair of their impulses, at the sum of the
/// times with the product of the amplitudes (the transfer function is the product, zero at each
/// mode's frequency).
InputShaper convolved(const InputShaper& a, const InputShaper& b) {
  InputShaper out{a.type, {}, a.exact_design && b.exact_design};
  for (const Impulse& i : a.impulses) {
    for (const Impulse& j : b.impulses)
      out.impulses.push_back({i.time + j.time, i.amplitude * j.amplitude});
  }
  std::sort(out.impulses.begin(), out.impulses.end(),
            [](const Impulse& x, const Impulse& y) { return x.time < y.time; });
  return out;
}

/// `s` with its impulse times scaled by `factor`: the same family designed at omega / factor.
/// Toward factor 0 it nears the single unit impulse (no shaping).
InputShaper time_scaled(InputShaper s, double factor) {
  for (Impulse& i : s.impulses) i.time *= factor;
  return s;
}

/// A mode the shaper must cancel, and the weight its residual is judged by.
struct ShapedMode {
  double omega, zeta, weight;
};

/// Every mode the shaper must cancel: the design model's first, or a turned tank's two; the
/// second direction's residual weighed by its share of the residual wave while it enters the
/// design only partly (direction_engagement below 1).
std::vector<ShapedMode> shaped_modes(const StrategyContext& c) {
  if (c.over_directions && !c.robust()) {
    const double second = c.direction_engagement < 1.0 ? c.direction_weight[1] : 1.0;
    return {{c.direction_omega[0], c.direction_zeta[0], 1.0},
            {c.direction_omega[1], c.direction_zeta[1], second}};
  }
  return {{c.design_model.omega1(), c.design_model.zeta, 1.0}};
}

InputShaper shaper_for(const StrategyContext& c, std::string* choice) {
  const PlanOptions& opt = c.options;
  const double w = c.design_model.omega1(), z = c.design_model.zeta;
  if (c.over_directions && !c.robust()) {
    // A turned tank: a shaper at the middle of its two first modes cancels neither; one per
    // direction, convolved, cancels both (at the sum of their delays). Below
    // kFullDirectionShare the second direction's shaper is timed at its engagement (designed at
    // omega / engagement): its delay, and the law, go continuously to the first direction's
    // shaper alone as the share goes to 0.
    const double f = 0.5 / std::numbers::pi;
    const double e = c.direction_engagement;
    *choice = "one per direction, at " + sig3(c.direction_omega[0] * f) + " and " +
              sig3(c.direction_omega[1] * f) + " Hz, convolved";
    if (e < 1.0) {
      *choice += "; the " + std::string(c.direction_name[1]) + "'s, at a share " +
                 sig3(c.direction_weight[1]) + " of the residual wave, timed at " + percent(e) +
                 " of its delay";
    }
    return convolved(
        make_shaper(opt.shaper, c.direction_omega[0], c.direction_zeta[0], opt.residual),
        time_scaled(
            make_shaper(opt.shaper, c.direction_omega[1], c.direction_zeta[1], opt.residual), e));
  }
  if (!c.robust() || !opt.shaper_for_range) return make_shaper(opt.shaper, w, z, opt.residual);
  const UncertaintyRange& r = *c.range;
  std::optional<InputShaper> best;
  double best_worst = INFINITY;
  for (ShaperType type : kShapersByDelay) {
    InputShaper s = make_shaper(type, w, z, opt.residual);
    const double worst = max_residual_over(s, r.omega_lo, r.omega_hi, r.zeta_lo);
    if (worst < best_worst) {
      best_worst = worst;
      best = std::move(s);
    }
    if (worst <= opt.residual * (1.0 + 1e-9)) break;
  }
  const double f = 0.5 / std::numbers::pi;
  *choice = "chosen for the range " + sig3(r.omega_lo * f) + "-" + sig3(r.omega_hi * f) + " Hz: " +
            (best_worst <= opt.residual * (1.0 + 1e-9)
                 ? "the shortest family whose residual stays <= " + percent(opt.residual)
                 : "no family keeps the residual <= " + percent(opt.residual) +
                       "; the least worst residual") +
            " (" + percent(best_worst) + " at worst)";
  return *best;
}

}  // namespace

FilterOutcome design_shaper(const StrategyContext& c) {
  const PlanOptions& opt = c.options;
  const double S = c.format.stroke, T = c.format.motion_time;
  const std::string family = c.robust() && opt.shaper_for_range
                                 ? "the shaper"
                                 : "the " + to_string(opt.shaper) + " shaper";
  if (std::string why = over_damped(c, family); !why.empty()) return no_law(c, why);
  std::string choice;
  const InputShaper shaper = shaper_for(c, &choice);
  const double Tb = T - shaper.delay();
  const std::string name =
      to_string(shaper.type) + " shaper" + (choice.empty() ? "" : " (" + choice + ")");
  double residual = 0.0;
  for (const ShapedMode& m : shaped_modes(c)) {
    residual = std::max(residual, m.weight * shaper_residual(shaper, m.omega, m.zeta));
  }
  if (!(Tb >= kMinBaseDuration)) {
    FilterOutcome o = no_law(c, "the " + name + " delays the law by " + sig3(shaper.delay()) +
                                    " s of T = " + sig3(T) +
                                    " s, leaving less than the 1 ms a base law needs; use a "
                                    "shorter shaper (zv) or lengthen the motion");
    o.design = ShaperDesign{opt.base, shaper, 0.0, residual};
    return o;
  }
  FilterOutcome o;
  o.law = convolve(make_base_law(opt.base, S, Tb), shaper);
  const KinematicSummary peaks = o.law.summary();
  if (std::string why = beyond_any_machine(peaks); !why.empty()) {
    FilterOutcome none =
        no_law(c, "the " + name + " leaves " + sig3(Tb) + " s for the base law: " + why +
                      "; use a shorter shaper (zv) or lengthen the motion");
    none.design = ShaperDesign{opt.base, shaper, Tb, residual};
    return none;
  }
  o.design = ShaperDesign{opt.base, shaper, Tb, residual};
  // Below 1e-9 the residual is round-off: the ZV family cancels mode 1 exactly.
  // On a turned tank under an uncertainty range the shaper is tuned between the two directions'
  // first modes: neither of them is cancelled exactly, and the text must not claim so.
  const std::string at =
      !c.over_directions ? " at f1"
      : !c.robust()
          ? std::string(" at both directions' first modes") +
                (c.direction_engagement < 1.0
                     ? " (the " + std::string(c.direction_name[1]) + "'s weighed by its share)"
                     : "")
          : " at " + sig3(c.design_model.omega1() / (2.0 * std::numbers::pi)) +
                " Hz, the middle of the two directions' first modes (each keeps a "
                "residual)";
  const std::string residual_text =
      (residual < 1e-9 ? "no residual" : "residual " + percent(residual)) + at;
  o.detail = name + " (" + std::to_string(shaper.impulses.size()) + " impulses over " +
             ms(shaper.delay()) + ", " + residual_text + ") on a " + to_string(opt.base) +
             " base law of " + sig3(Tb) + " s";
  check_limits(c, peaks, &o);
  return o;
}

namespace {

/// The filter f then g: the product of their transfer functions, times one sample of delay.
/// apply_iir runs y(k) = -sum a_i y(k-1-i) + sum b_i u(k+1-i), the transfer function
/// z B(1/z) / A(1/z) with A = 1 + sum a_i z^-(i+1); the cascade's z^2 Bf Bg / (Af Ag) is one
/// sample ahead of what that form holds, so the product is taken with one sample of delay
/// (z Bf Bg / (Af Ag)), which keeps every zero and the unit DC gain (the delay compensation
/// absorbs the sample).
IirFilter cascade(const IirFilter& f, const IirFilter& g) {
  auto multiply = [](const std::vector<long double>& p, const std::vector<long double>& q) {
    std::vector<long double> out(p.size() + q.size() - 1, 0.0L);
    for (std::size_t i = 0; i < p.size(); ++i) {
      for (std::size_t j = 0; j < q.size(); ++j) out[i + j] += p[i] * q[j];
    }
    return out;
  };
  auto with_one = [](const std::vector<long double>& a) {
    std::vector<long double> out{1.0L};
    out.insert(out.end(), a.begin(), a.end());
    return out;
  };
  IirFilter out = f;
  const std::vector<long double> a = multiply(with_one(f.a), with_one(g.a));
  out.a.assign(a.begin() + 1, a.end());
  out.b = multiply(f.b, g.b);
  return out;
}

/// The second factor of a turned tank's cascade at engagement e: (1 - e) z + e f. cascade()
/// takes its product with one sample of delay, so the cascade is (1 - e) h + e (h f cascaded):
/// the first direction's filter h alone at e = 0, both at e = 1, and continuous between. With
/// f's form z B(1/z) / A(1/z), the numerator (1 - e) z A(1/z) + e z B(1/z) is z C(1/z) with
/// C = e B + (1 - e) (1, a_1, ..., a_n).
IirFilter engaged(IirFilter f, double e) {
  if (e >= 1.0) return f;
  const auto le = static_cast<long double>(e);
  std::vector<long double> c(std::max(f.b.size(), f.a.size() + 1), 0.0L);
  for (std::size_t i = 0; i < f.b.size(); ++i) c[i] += le * f.b[i];
  c[0] += 1.0L - le;
  for (std::size_t i = 0; i < f.a.size(); ++i) c[i + 1] += (1.0L - le) * f.a[i];
  f.b = std::move(c);
  return f;
}

}  // namespace

FilterOutcome design_iir(const StrategyContext& c) {
  const PlanOptions& opt = c.options;
  const double S = c.format.stroke, T = c.format.motion_time;
  if (std::string why = over_damped(c, "the IIR filter"); !why.empty()) return no_law(c, why);
  if (T / opt.iir_sample_period > kIirMaxSamples) {
    const auto samples = static_cast<long long>(std::ceil(T / opt.iir_sample_period - 1e-9));
    return no_law(
        c, "iir_sample_period_s = " + ms(opt.iir_sample_period) + " gives " +
               std::to_string(samples) + " samples over T = " + sig3(T) + " s, more than the " +
               std::to_string(kIirMaxSamples) +
               " the iir strategy plans: use iir_sample_period_s >= " + ms(T / kIirMaxSamples));
  }
  // On a turned tank one filter per direction, in cascade: each cancels its direction's first
  // mode (a filter at the middle of the two would cancel neither).
  // Below kFullDirectionShare the second filter enters by its engagement e (engaged): unit DC
  // gain, continuous in the share, the first filter alone at share 0.
  const bool directions = per_direction(c);
  const IirFilter filter =
      directions
          ? cascade(
                make_iir_filter(opt.iir_order, design_omega_of(c, 0), c.direction_zeta[0],
                                opt.iir_tau, opt.iir_sample_period),
                engaged(make_iir_filter(opt.iir_order, design_omega_of(c, 1), c.direction_zeta[1],
                                        opt.iir_tau, opt.iir_sample_period),
                        c.direction_engagement))
          : make_iir_filter(opt.iir_order, c.design_model.omega1(), c.design_model.zeta,
                            opt.iir_tau, opt.iir_sample_period);
  const IirLaw law = make_iir_law(
      [&](double duration) { return make_base_law(opt.base, S, duration); }, filter, S, T);
  const std::string name =
      (directions ? "two order-" : "order-") + std::to_string(static_cast<int>(opt.iir_order)) +
      (directions ? " IIR filters in cascade (at " + direction_f1(c, 0) + " and " +
                        direction_f1(c, 1) + ", each cancelling its mode; "
                  : " IIR filter (") +
      "tau = " + sig3(opt.iir_tau) + " 1/s, T_s = " + ms(opt.iir_sample_period) + ")";
  IirDesign design{
      opt.base,       filter,        law.base_duration, law.delay, law.filtered_duration,
      law.iterations, law.correction};
  if (!law.fits) {
    FilterOutcome o = no_law(c, "the " + name + " delays a " + to_string(opt.base) + " law by " +
                                    sig3(law.delay) + " s of T = " + sig3(T) +
                                    " s, leaving less than the 1 ms a base law needs; raise tau "
                                    "or lengthen the motion");
    o.design = design;
    return o;
  }
  const KinematicSummary peaks = law.law.summary();
  if (std::string why = beyond_any_machine(peaks); !why.empty()) {
    FilterOutcome none =
        no_law(c, "the " + name + ": " + why + "; raise tau or lengthen the motion");
    none.design = design;
    return none;
  }
  FilterOutcome o;
  o.law = law.law;
  o.design = design;
  o.detail = name + " on a " + to_string(opt.base) + " base law of " + sig3(law.base_duration) +
             " s (delay " + sig3(law.delay) + " s after " + std::to_string(law.iterations) +
             " passes; rest-to-rest correction " + percent(law.correction) +
             " of the peak acceleration)";
  check_limits(c, peaks, &o);
  return o;
}

}  // namespace slosh::detail
