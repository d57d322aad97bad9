#pragma once
// The motion columns of CSV recipe tables (SPEC §14): a row moves along a straight line (the
// stroke_mm column, as before), a rotary table's arc or a path of lines and arcs. The cells land
// in format.motion of the row's request, so the request's own checks name the member and the
// table names its column (format.motion.radius_mm -> arc_radius_mm).
//
// Columns (all optional; a table without them is a table of straight lines):
// - motion_type: "line" (default: the row's stroke_mm), "arc" or "path";
// - arc_radius_mm, arc_angle_deg: the arc (radius > 0, signed angle, left positive), type arc;
// - container_turns: true/false, whether the container turns with the table or the path
//   (default: true on an arc, false on a path);
// - path_json: the path's segments as a JSON array
//   ([{"line_mm": 200}, {"arc": {"radius_mm": 100, "angle_deg": 90}}]), type path.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/recipe_row.hpp"

namespace slosh::api {

/// The motion columns, after the format's and before the strategy's in recipe_columns().
[[nodiscard]] const std::vector<RecipeColumn>& motion_recipe_columns();

/// Completes the motion of a row's request built from its cells: a row without motion cells, or
/// of motion_type "line" alone, keeps its stroke_mm (no format.motion); an arc or a path gets
/// format.motion with its type and members. Throws CellError naming the column for motion cells
/// of another type (arc_radius_mm on a path), a missing motion_type, or stroke_mm with an arc or
/// a path (the motion's length is the stroke).
void complete_row_motion(nlohmann::json& request);

/// The motion figures of a rendered plan a table row shows: motion_type ("line" for a plan of
/// stroke_mm, else the type of format.motion), arc_radius_mm and arc_angle_deg (an arc; null
/// otherwise), container_turns (an arc or a path; null on a line), path_length_mm (the length
/// the law moves, format.stroke_mm) and path_json (a path's segments as compact JSON text, the
/// path_json cell that gives them; null otherwise); all null when the plan has no format (a
/// compact view).
[[nodiscard]] nlohmann::json motion_row_figures(const nlohmann::json& plan);

}  // namespace slosh::api
