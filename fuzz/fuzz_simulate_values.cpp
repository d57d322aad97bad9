// Fuzz target: in-range simulate requests. The fuzz bytes choose the values of a request that is
// valid by construction (every field within its documented range, durations summing to T, general
// laws made rest-to-rest at the stroke), including the edges of each range, and the request is
// validated and simulated. SPEC §7: in-range input never yields a 500 or a null where a number
// belongs, so the response must have only finite numbers. A 422 is allowed only for the relations
// this generator does not model (e.g. a general law's peak acceleration above the bound).
// The window is kept short (T <= 2 s, rest <= 1 s) so that an iteration stays cheap.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/model/fluid.hpp"

namespace {

using nlohmann::json;

/// Reads choices from the fuzz bytes (zeros once they run out).
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint32_t next(int bytes) {
    std::uint32_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | (at_ < size_ ? data_[at_++] : 0u);
    return v;
  }
  std::size_t pick(std::size_t n) { return n == 0 ? 0 : next(1) % n; }
  bool flag() { return (next(1) & 1u) != 0; }
  double unit() { return next(3) / 16777215.0; }
  /// A value of [lo, hi] (lo excluded when lo_open): often an edge, else log- or linear-uniform.
  double in(double lo, double hi, bool lo_open = false) {
    const double low = lo_open ? std::nextafter(lo, hi) : lo;
    switch (next(1) % 8) {
      case 0:
        return low;
      case 1:
        return hi;
      case 2:
        return std::nextafter(hi, lo);
      case 3:
        if (low > 0.0) return std::exp(std::log(low) + unit() * (std::log(hi) - std::log(low)));
        [[fallthrough]];
      default:
        return std::clamp(low + unit() * (hi - low), low, hi);
    }
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_{0};
};

json format_of(Bytes& b, double T) {
  const double fill = b.in(0.0, 5000.0, true);
  json container{{"radius_mm", b.in(1.0, 2000.0)}};
  if (b.flag()) container["height_mm"] = b.in(fill, 10000.0, true);
  json fluid;
  const auto catalogue = slosh::fluid_catalogue();
  if (b.flag()) {
    fluid = catalogue[b.pick(catalogue.size())].name;
  } else {
    fluid = {{"density_kg_m3", b.in(100.0, 20000.0)}, {"viscosity_pa_s", b.in(0.0, 10.0, true)}};
  }
  return {{"container", container},
          {"fill_height_mm", fill},
          {"fluid", fluid},
          {"stroke_mm", b.in(0.0, 100000.0, true)},
          {"motion_time_s", T}};
}

/// Strictly increasing times 0 = t0 < ... < t_n = T.
std::vector<double> breakpoints(Bytes& b, double T, std::size_t pieces) {
  std::vector<double> t{0.0};
  for (std::size_t k = 1; k < pieces; ++k) t.push_back(b.unit() * T);
  t.push_back(T);
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

/// End velocity and position of `pieces` (exact integration by the product's MotionLaw).
std::pair<double, double> end_state(const std::vector<slosh::LawPiece>& pieces) {
  const slosh::MotionLaw law("probe", pieces);
  const slosh::LawPiece& last = law.pieces().back();
  const slosh::KinematicState end = last.at(last.duration());
  return {end.velocity, end.position};
}

/// Adjusts two coefficients (`first`, `second` select them) so that the law ends at rest at
/// `stroke`: the end state is linear in every coefficient.
template <typename First, typename Second>
bool make_rest_to_rest(std::vector<slosh::LawPiece>& pieces, double stroke, First first,
                       Second second) {
  const auto [v0, s0] = end_state(pieces);
  first(pieces) += 1.0;
  const auto [v1, s1] = end_state(pieces);
  first(pieces) -= 1.0;
  second(pieces) += 1.0;
  const auto [v2, s2] = end_state(pieces);
  second(pieces) -= 1.0;
  const double a11 = v1 - v0, a21 = s1 - s0, a12 = v2 - v0, a22 = s2 - s0;
  const double det = a11 * a22 - a12 * a21;
  if (!std::isfinite(det) || std::abs(det) < 1e-12) return false;
  const double rv = -v0, rs = stroke - s0;
  first(pieces) += (rv * a22 - a12 * rs) / det;
  second(pieces) += (a11 * rs - a21 * rv) / det;
  return true;
}

json law_of(Bytes& b, double T, double stroke_m, double min_ramp) {
  const std::string types[] = {
      "seven_segment", "seven_segment_uniform", "poly5",    "modified_trapezoid",
      "cycloidal",     "piecewise_linear",      "piecewise"};
  const std::string type = types[b.pick(7)];
  json law{{"type", type}};
  if (type == "seven_segment") {
    double w[7], total = 0.0;
    for (double& x : w) total += (x = b.in(0.0, 1.0));
    const double free = T - 4.0 * min_ramp;
    json d = json::array();
    for (int i = 0; i < 7; ++i) {
      const double share = total > 0.0 ? w[i] / total : 1.0 / 7.0;
      d.push_back(share * free + (i % 2 == 0 ? min_ramp : 0.0));
    }
    law["durations_s"] = d;
  } else if (type == "piecewise_linear" || type == "piecewise") {
    const std::vector<double> t = breakpoints(b, T, 1 + b.pick(12));
    std::vector<slosh::LawPiece> pieces(t.size() - 1);
    const bool linear = type == "piecewise_linear";
    std::vector<double> acc(t.size());
    for (double& a : acc) a = b.in(-100.0, 100.0);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      slosh::LawPiece& p = pieces[k];
      p.t_begin = t[k];
      p.t_end = t[k + 1];
      if (linear) {
        p.poly = {acc[k], (acc[k + 1] - acc[k]) / (t[k + 1] - t[k]), 0.0, 0.0};
      } else {
        for (double& c : p.poly) c = b.in(-1e3, 1e3);
        if (b.flag()) {
          p.harmonic_cos = b.in(-100.0, 100.0);
          p.harmonic_sin = b.in(-100.0, 100.0);
          p.harmonic_omega = b.in(0.0, 1e4);
        }
      }
    }
    if (linear) {
      // The accelerations at two breakpoints are the unknowns; a breakpoint value enters the
      // slopes of both neighbouring pieces, so rebuild the pieces from `acc` on every probe.
      if (acc.size() < 3) return law;  // a single linear piece cannot be rest-to-rest in general
      const std::size_t i = 1 + b.pick(acc.size() - 2);
      const std::size_t j = i == 1 ? acc.size() - 1 : 0;
      auto rebuild = [&](std::vector<slosh::LawPiece>& ps) {
        for (std::size_t k = 0; k < ps.size(); ++k) {
          ps[k].poly = {acc[k], (acc[k + 1] - acc[k]) / (t[k + 1] - t[k]), 0.0, 0.0};
        }
      };
      // Linear in acc: probe with unit changes of acc[i] and acc[j].
      rebuild(pieces);
      const auto [v0, s0] = end_state(pieces);
      acc[i] += 1.0;
      rebuild(pieces);
      const auto [v1, s1] = end_state(pieces);
      acc[i] -= 1.0;
      acc[j] += 1.0;
      rebuild(pieces);
      const auto [v2, s2] = end_state(pieces);
      acc[j] -= 1.0;
      const double a11 = v1 - v0, a21 = s1 - s0, a12 = v2 - v0, a22 = s2 - s0;
      const double det = a11 * a22 - a12 * a21;
      if (std::isfinite(det) && std::abs(det) > 1e-12) {
        acc[i] += (-v0 * a22 - a12 * (stroke_m - s0)) / det;
        acc[j] += (a11 * (stroke_m - s0) + a21 * v0) / det;
      }
      law["breakpoints_s"] = t;
      law["acceleration_m_s2"] = acc;
    } else {
      const std::size_t last = pieces.size() - 1;
      auto c0_first = [](std::vector<slosh::LawPiece>& ps) -> double& { return ps[0].poly[0]; };
      auto c_second = [last](std::vector<slosh::LawPiece>& ps) -> double& {
        return last == 0 ? ps[0].poly[1] : ps[last].poly[0];
      };
      (void)make_rest_to_rest(pieces, stroke_m, c0_first, c_second);
      json list = json::array();
      for (const slosh::LawPiece& p : pieces) {
        json item{{"t_begin_s", p.t_begin}, {"t_end_s", p.t_end}, {"a_poly", p.poly}};
        if (p.harmonic_omega != 0.0) {
          item["harmonic"] = {
              {"cos", p.harmonic_cos}, {"sin", p.harmonic_sin}, {"omega_rad_s", p.harmonic_omega}};
        }
        list.push_back(item);
      }
      law["pieces"] = list;
    }
  }
  return law;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slosh;
  Bytes b(data, size);
  const double T = b.in(0.05, 2.0);
  json body{{"format", format_of(b, T)}};
  const double min_ramp = b.flag() ? b.in(0.001, T / 4.0) : kDefaultMinRamp;
  json options{{"modes", 1 + static_cast<int>(b.pick(5))}, {"alpha", b.in(0.0, 2.0)}};
  const char* damping[] = {"thesis", "paper", "eq227", "eq228"};
  const std::size_t d = b.pick(5);
  options["damping"] = d < 4 ? json(damping[d]) : json{{"zeta", b.in(0.0, 0.4999)}};
  if (min_ramp != kDefaultMinRamp) options["min_ramp_s"] = min_ramp;
  body["options"] = options;
  body["rest_time_s"] = b.in(0.0, 1.0);
  if (b.flag()) body["sample_period_s"] = b.in(1e-3, 1.0);
  body["law"] =
      law_of(b, T, body["format"]["stroke_mm"].get<double>() * 1e-3, std::min(min_ramp, T / 4.0));
  try {
    const api::SimulateRequest request = api::parse_simulate_request(body);
    const json response = api::run_simulate(request);
    if (!fuzz::all_finite(response)) {
      std::fprintf(stderr, "request: %s\n", body.dump().c_str());
      fuzz::require(false, "an in-range simulate request gives only finite numbers");
    }
  } catch (const api::ApiError& e) {
    fuzz::check_envelope(e);
  }
  return 0;
}
