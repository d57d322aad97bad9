#include "slosh/api/recipe_motion.hpp"

#include <string_view>

#include "slosh/api/error.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

// The columns that give members of an arc or of a path, by the member they set.
struct MemberColumn {
  std::string_view member;
  std::string_view column;
  std::string_view type;  // the motion type it belongs to ("" = arc and path)
};
constexpr MemberColumn kMembers[] = {{"radius_mm", "arc_radius_mm", "arc"},
                                     {"angle_deg", "arc_angle_deg", "arc"},
                                     {"segments", "path_json", "path"},
                                     {"container_turns", "container_turns", ""}};

std::string first_member_column(const json& motion) {
  for (const MemberColumn& m : kMembers) {
    if (motion.contains(m.member)) return std::string(m.column);
  }
  return "motion_type";
}

}  // namespace

const std::vector<RecipeColumn>& motion_recipe_columns() {
  static const std::vector<RecipeColumn> columns{
      {"motion_type", "/format/motion/type", CellKind::kText},
      {"arc_radius_mm", "/format/motion/radius_mm", CellKind::kNumber},
      {"arc_angle_deg", "/format/motion/angle_deg", CellKind::kNumber},
      {"container_turns", "/format/motion/container_turns", CellKind::kBool},
      {"path_json", "/format/motion/segments", CellKind::kJson},
  };
  return columns;
}

void complete_row_motion(json& request) {
  if (!request.contains("format") || !request["format"].contains("motion")) return;
  json& format = request["format"];
  json& motion = format["motion"];
  if (!motion.contains("type")) {
    const std::string column = first_member_column(motion);
    throw CellError{column, column +
                                " is given but motion_type is not: give motion_type arc or "
                                "path with it"};
  }
  const std::string type = motion["type"].is_string() ? motion["type"].get<std::string>() : "";
  for (const MemberColumn& m : kMembers) {
    const bool belongs = m.type.empty() ? type != "line" : m.type == type;
    if (motion.contains(m.member) && !belongs) {
      throw CellError{std::string(m.column), std::string(m.column) +
                                                 " is given but motion_type is " +
                                                 show(motion["type"]) + ": leave it empty"};
    }
  }
  if (type == "line") {  // the straight line: its stroke_mm, the same request as without
    format.erase("motion");
    return;
  }
  if ((type == "arc" || type == "path") && format.contains("stroke_mm")) {
    throw CellError{"stroke_mm", "stroke_mm is given but motion_type is " + type + ": the " + type +
                                     "'s length is the stroke; leave it empty"};
  }
}

}  // namespace slosh::api
