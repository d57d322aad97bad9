#include "slosh/api/recipe_motion.hpp"

#include <string_view>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"

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
  // A recipe table moves along a line, an arc or a path (a sampled trajectory is simulate's).
  if (type != "line" && type != "arc" && type != "path") {
    throw CellError{"motion_type", "motion_type = " + show(motion["type"]) +
                                       " is not allowed: one of \"line\", \"arc\", \"path\""};
  }
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

json motion_row_figures(const json& plan) {
  json row{{"motion_type", nullptr},     {"arc_radius_mm", nullptr},  {"arc_angle_deg", nullptr},
           {"container_turns", nullptr}, {"path_length_mm", nullptr}, {"path_json", nullptr}};
  const json* format = find_member(plan, "format");
  if (format == nullptr || !format->is_object()) return row;
  if (const json* stroke = find_member(*format, "stroke_mm")) row["path_length_mm"] = *stroke;
  const json* motion = find_member(*format, "motion");
  if (motion == nullptr || !motion->is_object() || !motion->contains("type")) {
    row["motion_type"] = "line";
    return row;
  }
  row["motion_type"] = (*motion)["type"];
  if ((*motion)["type"] == "arc") {
    row["arc_radius_mm"] = motion->value("radius_mm", json(nullptr));
    row["arc_angle_deg"] = motion->value("angle_deg", json(nullptr));
  }
  // The path itself, as the path_json cell that gives it: two paths of one length (a turn left
  // or right, an arc before or after a line) are otherwise the same row. Compact JSON text, so
  // the CSV cell holds it whole and reads back as the input column.
  if (const json* segments = find_member(*motion, "segments")) {
    if ((*motion)["type"] == "path") row["path_json"] = dump_json(*segments);
  }
  // The plan's path block says whether the container turns (the echo may leave the default out).
  if (const json* path = find_member(plan, "path")) {
    if (const json* turns = find_member(*path, "container_turns")) row["container_turns"] = *turns;
  }
  return row;
}

}  // namespace slosh::api
