// The JDSMC paper's filtering strategies ([JDSMC] in docs/models.md, sec. 3.1, 3.3, 3.4, 4):
// closed-form laws of the prescribed duration, checked against the machine limits and the 7-segment
// options that apply to them.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

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
      return std::string("the law's peak ") + k.what + " " + sig3(k.value) + " " + k.unit +
             " exceeds limits." + k.name + " = " + sig3(*k.limit) + " " + k.unit;
    }
  }
  return {};
}

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

FilterOutcome design_fir_chain(const StrategyContext& c) {
  const double S = c.format.stroke, T = c.format.motion_time;
  if (std::string why = over_damped(c, "fir_chain"); !why.empty()) return no_law(c, why);
  const double T3 = damped_period(c.design_model.omega1(), c.design_model.zeta);
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
  const FirChain chain = make_fir_chain(S, T1, T2, T3);
  FilterOutcome o;
  o.design = FirChainDesign{T1, T2, T3, chain.durations.has_value()};
  o.detail = "T3 = " + sig3(T3) + " s (the damped period of mode 1), T1 = " + sig3(T1) +
             " s, T2 = " + sig3(T2) + " s" + choice;
  if (chain.durations) {
    // T1 + T2 + T3 is the motion time only to round-off: the sum is closed on T itself.
    o.durations = clean_durations(*chain.durations, c.format.motion_time);
    o.law = SevenSegmentLaw(*o.durations, S).law();
    o.detail += ": conditions (14) hold, a 7-segment law";
  } else {
    o.law = chain.law;
    o.detail += ": conditions (14) need T >= 4 T3 = " + sig3(4.0 * T3) + " s (T = " + sig3(T) +
                " s), so the law is not a 7-segment law (acceleration ramps without plateaus)";
  }
  const KinematicSummary peaks = o.law.summary();
  if (std::string why = beyond_any_machine(peaks); !why.empty()) {
    FilterOutcome none = no_law(c, "fir_chain with " + o.detail + ": " + why);
    none.design = o.design;
    return none;
  }
  check_limits(c, peaks, &o);
  if (o.status != SolveStatus::kOptimal || !o.durations) return o;
  // The 7-segment options that constrain its durations.
  const Durations& d = *o.durations;
  std::string broken;
  if (T3 < c.options.min_ramp * (1.0 - kLimitSlack)) {
    broken = "its ramps T3 = " + sig3(T3) +
             " s are shorter than min_ramp_s = " + sig3(c.options.min_ramp) + " s";
  } else if (d[1] < c.options.plateau_min[0] * (1.0 - kLimitSlack) ||
             d[5] < c.options.plateau_min[1] * (1.0 - kLimitSlack)) {
    broken = "its plateaus T2 - T3 = " + sig3(d[1]) + " s are shorter than plateau_min_s = [" +
             sig3(c.options.plateau_min[0]) + ", " + sig3(c.options.plateau_min[1]) + "] s";
  } else if (c.options.fix_constant_velocity_zero && d[3] > 1e-9 * T) {
    broken = "its constant-velocity segment is " + sig3(d[3]) +
             " s but fix_constant_velocity_zero is set";
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

/// Every mode the shaper must cancel: the design model's first, or a turned tank's two.
std::vector<std::pair<double, double>> shaped_modes(const StrategyContext& c) {
  if (c.over_directions && !c.robust()) {
    return {{c.direction_omega[0], c.direction_zeta[0]},
            {c.direction_omega[1], c.direction_zeta[1]}};
  }
  return {{c.design_model.omega1(), c.design_model.zeta}};
}

InputShaper shaper_for(const StrategyContext& c, std::string* choice) {
  const PlanOptions& opt = c.options;
  const double w = c.design_model.omega1(), z = c.design_model.zeta;
  if (c.over_directions && !c.robust()) {
    // A turned tank: a shaper at the middle of its two first modes cancels neither; one per
    // direction, convolved, cancels both (at the sum of their delays).
    const double f = 0.5 / std::numbers::pi;
    *choice = "one per direction, at " + sig3(c.direction_omega[0] * f) + " and " +
              sig3(c.direction_omega[1] * f) + " Hz, convolved";
    return convolved(
        make_shaper(opt.shaper, c.direction_omega[0], c.direction_zeta[0], opt.residual),
        make_shaper(opt.shaper, c.direction_omega[1], c.direction_zeta[1], opt.residual));
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
  for (const auto& [omega, zeta] : shaped_modes(c)) {
    residual = std::max(residual, shaper_residual(shaper, omega, zeta));
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
      : !c.robust()      ? " at both directions' first modes"
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
  const IirFilter filter = make_iir_filter(opt.iir_order, c.design_model.omega1(),
                                           c.design_model.zeta, opt.iir_tau, opt.iir_sample_period);
  const IirLaw law = make_iir_law(
      [&](double duration) { return make_base_law(opt.base, S, duration); }, filter, S, T);
  const std::string name = "order-" + std::to_string(static_cast<int>(opt.iir_order)) +
                           " IIR filter (tau = " + sig3(opt.iir_tau) +
                           " 1/s, T_s = " + ms(opt.iir_sample_period) + ")";
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
