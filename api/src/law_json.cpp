#include "slosh/api/law_json.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "slosh/api/error.hpp"
#include "slosh/api/exact_number.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/core/law/filtered_laws.hpp"

namespace slosh::api {

namespace {

constexpr double kDurationSumToleranceS = 1e-6;
/// The rounding of summing 7 durations: at most a few ulps of T (bound with margin).
constexpr double kSumRoundingUlps = 16.0;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
/// Consecutive pieces must meet within this [s] (they are snapped together).
constexpr double kPieceGapTolerance = 1e-9;
/// Acceleration values (the bound every planned law keeps, kMaxLawAcceleration) and polynomial
/// coefficients of a general law (m/s^2 per s^n: merely finite).
const Range kAcceleration{-kMaxLawAcceleration, kMaxLawAcceleration, "m/s^2"};
const Range kCoefficient{-1e30, 1e30, ""};
const Range kHarmonicOmega{0.0, 1e9, "rad/s"};
constexpr double kMinHarmonicOmega{1e-3};  // rad/s, when not 0
// Shortest piece [s]: the slope between two breakpoints is their difference over it (a
// subnormal duration made it infinite).
constexpr double kMinPieceDuration{1e-9};

LawType parse_law_type(const nlohmann::json& law, const std::string& path) {
  const std::string tpath = join_path(path, "type");
  std::string allowed;
  for (LawType t : enum_values<LawType>())
    allowed += (allowed.empty() ? "\"" : ", \"") + to_string(t) + "\"";
  auto it = law.find("type");
  if (it == law.end()) invalid(tpath, tpath + " is required: one of " + allowed);
  if (it->is_string()) {
    const auto name = it->get<std::string>();
    for (LawType t : enum_values<LawType>()) {
      if (name == to_string(t)) return t;
    }
  }
  invalid(tpath, tpath + " = " + show(*it) + " is not allowed: one of " + allowed);
}

const nlohmann::json& required_array(const nlohmann::json& law, const std::string& path,
                                     std::string_view key, std::size_t min_size,
                                     const std::string& what) {
  const std::string field = join_path(path, key);
  auto it = law.find(key);
  if (it == law.end() || !it->is_array() || it->size() < min_size ||
      it->size() > static_cast<std::size_t>(kMaxLawPieces) + 1) {
    invalid(field, field + " must be an array of " + what + ", got " +
                       (it == law.end() ? std::string("nothing") : show(*it)));
  }
  return *it;
}

Durations parse_durations(const nlohmann::json& law, const std::string& path, double motion_time,
                          double min_ramp) {
  const std::string dpath = join_path(path, "durations_s");
  auto it = law.find("durations_s");
  if (it == law.end() || !it->is_array() || it->size() != kSegments) {
    invalid(dpath, dpath +
                       " must be an array of 7 durations in s (sum = format.motion_time_s), got " +
                       (it == law.end() ? std::string("nothing") : show(*it)));
  }
  Durations d{};
  const Range ramp{min_ramp, motion_time, "s"};
  const Range plateau{0.0, motion_time, "s"};
  double sum = 0.0;
  for (std::size_t i = 0; i < kSegments; ++i) {
    const bool is_ramp = i % 2 == 0;
    const std::string field = dpath + "[" + std::to_string(i) + "]";
    const std::string hint =
        is_ramp ? " (segment " + std::to_string(i + 1) + " is a jerk ramp: >= options.min_ramp_s)"
                : "";
    d[i] = checked_number(&(*it)[i], field, is_ramp ? ramp : plateau, hint);
    sum += d[i];
  }
  if (std::abs(sum - motion_time) > kDurationSumToleranceS) {
    invalid(dpath, dpath + " sum to " + number_text(sum) + " s but format.motion_time_s = " +
                       number_text(motion_time) + " s: they must be equal (tolerance 1e-6 s)");
  }
  // A residual beyond rounding (up to the tolerance) is spread over the segments so that the law
  // ends at T. Durations whose sum is T but for the rounding of the additions (0.076 + 0.196 + ...
  // in doubles) are kept as given: scaling them by T / sum would only add noise to the caller's
  // numbers (0.076 -> 0.07599999999999998) and end the law no closer to T.
  if (std::abs(sum - motion_time) > kSumRoundingUlps * kEpsilon * motion_time) {
    for (double& x : d) x *= motion_time / sum;
  }
  return d;
}

// The breakpoints of a general law: start at 0, increase strictly, end at the motion time.
void check_end(double end, const std::string& field, double motion_time) {
  if (std::abs(end - motion_time) > kLawEndTolerance) {
    invalid(field, field + " = " + number_text(end) + " s must equal format.motion_time_s = " +
                       number_text(motion_time) + " s (tolerance 1e-6 s): the law ends there");
  }
}

MotionLaw parse_piecewise_linear(const nlohmann::json& law, const std::string& path,
                                 double motion_time) {
  const std::string bpath = join_path(path, "breakpoints_s");
  const std::string apath = join_path(path, "acceleration_m_s2");
  const nlohmann::json& b = required_array(law, path, "breakpoints_s", 2,
                                           "at least 2 increasing times in s, from 0 to "
                                           "format.motion_time_s");
  const nlohmann::json& a = required_array(law, path, "acceleration_m_s2", 2,
                                           "accelerations in m/s^2, one per breakpoint");
  if (a.size() != b.size()) {
    invalid(apath, apath + " has " + std::to_string(a.size()) + " values but " + bpath + " has " +
                       std::to_string(b.size()) + ": one acceleration per breakpoint");
  }
  const std::size_t n = b.size();
  std::vector<double> t(n), acc(n);
  const double end = motion_time + kLawEndTolerance;
  for (std::size_t k = 0; k < n; ++k) {
    const std::string field = bpath + "[" + std::to_string(k) + "]";
    if (k == 0) {
      if (!b[0].is_number() || b[0].get<double>() != 0.0) {
        invalid(field, field + " = " + show(b[0]) + " must be 0: the law starts at t = 0");
      }
      t[0] = 0.0;
    } else {
      // The last one is the motion time; every one is strictly after the previous one.
      if (k + 1 == n && b[k].is_number()) check_end(b[k].get<double>(), field, motion_time);
      t[k] = checked_number(&b[k], field, Range{t[k - 1] + kMinPieceDuration, end, "s"});
    }
    acc[k] = checked_number(&a[k], apath + "[" + std::to_string(k) + "]", kAcceleration);
  }
  return piecewise_linear_law("piecewise_linear", t, acc);
}

MotionLaw parse_piecewise(const nlohmann::json& law, const std::string& path, double motion_time) {
  const std::string ppath = join_path(path, "pieces");
  const nlohmann::json& list =
      required_array(law, path, "pieces", 1,
                     "pieces {\"t_begin_s\", \"t_end_s\", \"a_poly\": [c0..c3], \"harmonic\"?}");
  std::vector<LawPiece> pieces(list.size());
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = ppath + "[" + std::to_string(k) + "]";
    const nlohmann::json& item = list[k];
    require_object(item, at);
    reject_unknown_fields(item, at, {"t_begin_s", "t_end_s", "a_poly", "harmonic"});
    LawPiece& p = pieces[k];
    const double expected = k == 0 ? 0.0 : pieces[k - 1].t_end;
    p.t_begin =
        required_number(item, at, "t_begin_s",
                        Range{expected - kPieceGapTolerance, expected + kPieceGapTolerance, "s"});
    p.t_begin = expected;  // snapped: the pieces are contiguous
    p.t_end =
        required_number(item, at, "t_end_s",
                        Range{p.t_begin + kMinPieceDuration, motion_time + kLawEndTolerance, "s"});
    const std::string cpath = join_path(at, "a_poly");
    auto c = item.find("a_poly");
    if (c == item.end() || !c->is_array() || c->empty() || c->size() > 4) {
      invalid(cpath, cpath +
                         " must be an array of 1 to 4 coefficients c0..c3 (m/s^2 ... m/s^5), got " +
                         (c == item.end() ? std::string("nothing") : show(*c)));
    }
    for (std::size_t i = 0; i < c->size(); ++i) {
      p.poly[i] = checked_number(&(*c)[i], cpath + "[" + std::to_string(i) + "]", kCoefficient);
    }
    if (auto h = item.find("harmonic"); h != item.end() && !h->is_null()) {
      const std::string hpath = join_path(at, "harmonic");
      require_object(*h, hpath);
      reject_unknown_fields(*h, hpath, {"cos", "sin", "omega_rad_s"});
      p.harmonic_cos = required_number(*h, hpath, "cos", kAcceleration);
      p.harmonic_sin = required_number(*h, hpath, "sin", kAcceleration);
      p.harmonic_omega = required_number(*h, hpath, "omega_rad_s", kHarmonicOmega);
      // The harmonic integrates to cos/omega^2: a vanishing omega overflows the kinematics.
      if (p.harmonic_omega != 0.0 && p.harmonic_omega < kMinHarmonicOmega) {
        const std::string opath = join_path(hpath, "omega_rad_s");
        invalid(opath, opath + " = " + exact_number_text(p.harmonic_omega) +
                           " is out of range: allowed 0 (no harmonic) or " +
                           number_text(kMinHarmonicOmega) + " to 1e+09 rad/s");
      }
    }
  }
  check_end(pieces.back().t_end, ppath + "[" + std::to_string(pieces.size() - 1) + "].t_end_s",
            motion_time);
  return MotionLaw("piecewise", std::move(pieces));
}

// A general law must be rest-to-rest over the format's stroke.
void check_rest_to_rest(const MotionLaw& law, const std::string& field, double stroke) {
  const LawPiece& last = law.pieces().back();
  const KinematicState end = last.at(last.duration());
  // Written so that NaN fails.
  if (!(std::abs(end.velocity) <= kRestVelocityTolerance) ||
      !(std::abs(end.position - stroke) <= kRestPositionTolerance)) {
    invalid(field, field + " integrates to a final velocity of " + number_text(end.velocity) +
                       " m/s and a final position of " + number_text(end.position * 1e3) +
                       " mm: a law must end at rest (|v| <= 1e-6 m/s) at format.stroke_mm = " +
                       number_text(stroke * 1e3) + " mm (within 0.001 mm)");
  }
}

}  // namespace

ParsedLaw parse_law(const nlohmann::json& law, const std::string& path, const Format& format,
                    double min_ramp) {
  require_object(law, path);
  ParsedLaw out;
  out.type = parse_law_type(law, path);
  const double s = format.stroke;
  const double T = format.motion_time;
  std::vector<std::string_view> allowed{"type"};
  switch (out.type) {
    case LawType::kSevenSegment:
      allowed.push_back("durations_s");
      break;
    case LawType::kPiecewiseLinear:
      allowed.push_back("breakpoints_s");
      allowed.push_back("acceleration_m_s2");
      break;
    case LawType::kPiecewise:
      allowed.push_back("pieces");
      break;
    default:
      break;
  }
  // Another law type's member given null is absent, as every optional member is.
  nlohmann::json present = law;
  for (const char* key : {"durations_s", "breakpoints_s", "acceleration_m_s2", "pieces"}) {
    const auto member = present.find(key);
    if (member != present.end() && member->is_null()) present.erase(member);
  }
  for (const auto& [key, value] : present.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      const std::string field = join_path(path, key);
      const bool known = key == "durations_s" || key == "breakpoints_s" ||
                         key == "acceleration_m_s2" || key == "pieces";
      if (key == "durations_s") {
        invalid(field,
                field + " is only allowed with " + join_path(path, "type") + " \"seven_segment\"");
      }
      if (known) {
        invalid(field, field + " is not allowed with " + join_path(path, "type") + " \"" +
                           to_string(out.type) + "\"");
      }
    }
  }
  reject_unknown_fields(present, path, allowed);
  switch (out.type) {
    case LawType::kSevenSegment:
      out.durations = parse_durations(law, path, T, min_ramp);
      try {
        out.law = SevenSegmentLaw(*out.durations, s).law();
      } catch (const std::invalid_argument& e) {
        const std::string field = join_path(path, "durations_s");
        invalid(field, field + ": " + e.what());
      }
      break;
    case LawType::kSevenSegmentUniform:
      out.law = SevenSegmentLaw(uniform_durations(T), s).law();
      break;
    case LawType::kPoly5:
      out.law = make_poly5_law(s, T);
      break;
    case LawType::kModifiedTrapezoid:
      out.law = make_modified_trapezoid_law(s, T);
      break;
    case LawType::kCycloidal:
      out.law = make_cycloidal_law(s, T);
      break;
    case LawType::kPiecewiseLinear:
      out.law = parse_piecewise_linear(law, path, T);
      check_rest_to_rest(out.law, join_path(path, "acceleration_m_s2"), s);
      break;
    case LawType::kPiecewise:
      out.law = parse_piecewise(law, path, T);
      check_rest_to_rest(out.law, join_path(path, "pieces"), s);
      break;
  }
  return out;
}

LawType law_type_of(const MotionLaw& law, const std::optional<Durations>& durations) {
  if (durations) return LawType::kSevenSegment;
  const auto& pieces = law.pieces();
  double peak = 0.0;
  for (const LawPiece& p : pieces) peak = std::max(peak, std::abs(p.poly[0]));
  bool linear = true;
  for (std::size_t k = 0; k < pieces.size() && linear; ++k) {
    const LawPiece& p = pieces[k];
    linear = p.poly[2] == 0.0 && p.poly[3] == 0.0 &&
             (p.harmonic_omega == 0.0 || (p.harmonic_cos == 0.0 && p.harmonic_sin == 0.0));
    if (linear && k + 1 < pieces.size()) {
      const double end = p.poly[0] + p.poly[1] * p.duration();
      linear = std::abs(end - pieces[k + 1].poly[0]) <= 1e-12 * (1.0 + peak);
    }
  }
  return linear ? LawType::kPiecewiseLinear : LawType::kPiecewise;
}

nlohmann::json law_json(const MotionLaw& law, const std::optional<Durations>& durations) {
  const LawType type = law_type_of(law, durations);
  if (type == LawType::kSevenSegment) {
    return {{"type", to_string(type)}, {"durations_s", *durations}};
  }
  const auto& pieces = law.pieces();
  if (type == LawType::kPiecewiseLinear) {
    std::vector<double> t{0.0}, a{pieces.empty() ? 0.0 : pieces.front().poly[0]};
    for (const LawPiece& p : pieces) {
      t.push_back(p.t_end);
      a.push_back(p.poly[0] + p.poly[1] * p.duration());
    }
    return {{"type", to_string(LawType::kPiecewiseLinear)},
            {"breakpoints_s", t},
            {"acceleration_m_s2", a}};
  }
  nlohmann::json list = nlohmann::json::array();
  for (const LawPiece& p : pieces) {
    nlohmann::json item{{"t_begin_s", p.t_begin}, {"t_end_s", p.t_end}, {"a_poly", p.poly}};
    if (p.harmonic_omega != 0.0) {
      item["harmonic"] = {
          {"cos", p.harmonic_cos}, {"sin", p.harmonic_sin}, {"omega_rad_s", p.harmonic_omega}};
    }
    list.push_back(std::move(item));
  }
  return {{"type", to_string(LawType::kPiecewise)}, {"pieces", list}};
}

}  // namespace slosh::api
