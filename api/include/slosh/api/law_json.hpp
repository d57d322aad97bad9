#pragma once
// Motion laws as JSON, both ways: the `law` member of a plan response and of a simulate request.
// A plan's `law` is exactly what simulate and export accept, so any planned law can be re-checked
// or exported unchanged:
//   {"type": "seven_segment", "durations_s": [7]}
//   {"type": "piecewise_linear", "breakpoints_s": [n], "acceleration_m_s2": [n]}
//     acceleration linear between the breakpoints (the FIR chain, shaped 7-segment laws, IIR laws)
//   {"type": "piecewise", "pieces": [{"t_begin_s", "t_end_s", "a_poly": [c0, c1, c2, c3],
//                                     "harmonic": {"cos", "sin", "omega_rad_s"}}]}
//     a = c0 + c1 tau + c2 tau^2 + c3 tau^3 + cos * cos(omega tau) + sin * sin(omega tau) with
//     tau = t - t_begin_s (shaped poly5 and modified-trapezoid laws)
//   {"type": "seven_segment_uniform" | "poly5" | "modified_trapezoid" | "cycloidal"}

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "slosh/core/enum_names.hpp"
#include "slosh/core/law/motion_law.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/model/format.hpp"

namespace slosh::api {

/// Law types of the JSON contract.
enum class LawType {
  kSevenSegment,
  kSevenSegmentUniform,
  kPoly5,
  kModifiedTrapezoid,
  kCycloidal,
  kPiecewiseLinear,
  kPiecewise,
};

}  // namespace slosh::api

template <>
struct slosh::EnumNames<slosh::api::LawType> {
  using E = slosh::api::LawType;
  static constexpr std::array<EnumName<E>, 7> table{{
      {E::kSevenSegment, "seven_segment"},
      {E::kSevenSegmentUniform, "seven_segment_uniform"},
      {E::kPoly5, "poly5"},
      {E::kModifiedTrapezoid, "modified_trapezoid"},
      {E::kCycloidal, "cycloidal"},
      {E::kPiecewiseLinear, "piecewise_linear"},
      {E::kPiecewise, "piecewise"},
  }};
};

namespace slosh::api {

[[nodiscard]] inline std::string to_string(LawType type) {
  return std::string(name_of(type));
}

/// Most pieces (or breakpoints) a general law may have.
constexpr int kMaxLawPieces{200000};
/// A general law must end at rest at the stroke within these [m/s], [m].
constexpr double kRestVelocityTolerance{1e-6};
constexpr double kRestPositionTolerance{1e-6};
/// Its last breakpoint must be the motion time within this [s].
constexpr double kLawEndTolerance{1e-6};

/// A validated law.
struct ParsedLaw {
  LawType type{LawType::kSevenSegment};
  std::optional<Durations> durations;  ///< kSevenSegment
  MotionLaw law;
};

/// Validates the `law` object at `path` against the format (its stroke and motion time);
/// `min_ramp` bounds the ramps of 7-segment durations. Throws ApiError(kInvalidValue) naming the
/// field, the value and the allowed range.
[[nodiscard]] ParsedLaw parse_law(const nlohmann::json& law, const std::string& path,
                                  const Format& format, double min_ramp);

/// The JSON type of a law: seven_segment when `durations` are given, else piecewise_linear when
/// the acceleration is continuous and linear on every piece, else piecewise.
[[nodiscard]] LawType law_type_of(const MotionLaw& law, const std::optional<Durations>& durations);

/// The `law` object of a law, of type law_type_of(law, durations).
[[nodiscard]] nlohmann::json law_json(const MotionLaw& law,
                                      const std::optional<Durations>& durations);

}  // namespace slosh::api
