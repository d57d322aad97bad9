#pragma once
// The law of a rendered plan, read back for export (the CLI's `slosh export` and the service's
// GET /v1/plans/{key}/cam.csv share it).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slosh/api/law_json.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "slosh/core/solve/nlp_solver.hpp"

namespace slosh::api {

/// A plan's law with what an export reports of the plan.
struct PlanLaw {
  std::string key;
  std::string strategy;  ///< the plan's strategy name (empty when the text has none)
  bool cached{false};
  SolveStatus status{SolveStatus::kFailed};
  std::string message;
  std::vector<std::string> warnings;  ///< the plan's warnings, as it gave them
  LawType type{LawType::kSevenSegment};
  MotionLaw law;
  std::optional<SevenSegmentLaw> seven;  ///< when the law is a 7-segment law
  double stroke{};                       ///< [m]
};

/// Reads the law of a plan response (or of a stored plan). The law is validated like a simulate
/// request's, ramps only above the 1 ms floor: an infeasible fir_chain law's ramps (T3) may be
/// shorter than min_ramp_s. Throws ApiError when the text is not a plan with a law.
[[nodiscard]] PlanLaw plan_law(std::string_view plan_text);

/// Whether a plan of this status may be exported without asking: its law meets the requested
/// limits (optimal, acceptable).
[[nodiscard]] bool exportable(SolveStatus status);

/// The refusal of a plan that is not exportable, naming its status and message.
[[nodiscard]] std::string not_exportable_message(const PlanLaw& plan,
                                                 std::string_view how_to_force);

}  // namespace slosh::api
