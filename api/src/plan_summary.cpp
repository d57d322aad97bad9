#include "slosh/api/plan_summary.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace slosh::api {

namespace {

using nlohmann::json;

/// `value` with `digits` decimals, or "-" for a JSON null.
std::string num(const json& value, int digits) {
  if (!value.is_number()) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value.get<double>());
  return buffer;
}

std::string pad(std::string text, std::size_t width) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  return text;
}

/// "5.0 / 7.3 mm" style: nonlinear / linear of one figure of a prediction block.
std::string both(const json& block, const char* figure, int digits) {
  return num(block["nonlinear"][figure], digits) + " / " + num(block["linear"][figure], digits) +
         " mm";
}

/// A reduction in % as "-42.0 %": the plan's change relative to the uniform law.
std::string change(const json& reduction) {
  if (!reduction.is_number()) return "-";
  std::string text = num(json(-reduction.get<double>()), 1);
  if (text == "-0.0") text = "0.0";  // no change, or less than the digit shown
  return text + " %";
}

std::string law_line(const json& plan) {
  const json& law = plan["law"];
  std::string out = "law         " + law["type"].get<std::string>();
  if (plan["durations_s"].is_array()) {
    out += ", durations [s]:";
    for (const json& d : plan["durations_s"]) out += " " + num(d, 4);
  } else {
    out += " (a general law, not 7 segments: run it as a cam table, slosh export)";
  }
  return out + "\n";
}

/// Along a path A and B are the tangential acceleration's (the total is on the path line).
std::string kinematics_line(const json& k, bool along_path) {
  return "kinematics  A " + num(k["a_max"], 2) + " m/s^2, B " + num(k["a_min"], 2) + " m/s^2" +
         (along_path ? " (tangential s'')" : "") + ", v_peak " + num(k["v_peak"], 3) +
         " m/s, j_peak " + num(k["j_peak"], 1) + " m/s^3\n";
}

/// Along an arc or a path: its length, the wall angles of the nonlinear peaks and the peak
/// horizontal acceleration (tangential and normal together); nothing for a straight line.
std::string path_line(const json& plan) {
  const auto path = plan.find("path");
  if (path == plan.end()) return "";
  const json& p = (*path)["prediction"];
  return "path        " + (*path)["type"].get<std::string>() + " of " +
         num((*path)["length_mm"], 1) + " mm, container " +
         ((*path)["container_turns"].get<bool>() ? "turns" : "keeps its heading") +
         "; wave peaks at wall angle " + num(p["nonlinear"]["direction_motion_deg"], 0) +
         " deg (motion), " + num(p["nonlinear"]["direction_rest_deg"], 0) +
         " deg (rest); peak horizontal acceleration " + num(p["kinematics"]["a_total_peak"], 2) +
         " m/s^2 (tangential and normal " + num(p["kinematics"]["a_normal_peak"], 2) +
         " m/s^2 together: what limits.a_max bounds)\n";
}

bool has_code(const json& plan, const char* code) {
  const auto codes = plan.find("warning_codes");
  return codes != plan.end() && std::find(codes->begin(), codes->end(), code) != codes->end();
}

std::string prediction_lines(const json& plan) {
  const json& p = plan["prediction"];
  const json& b = plan["baseline"];
  const json& r = plan["reduction_pct"];
  std::string out = "eta [mm]    nonlinear / linear model (uniform law: nonlinear / linear)\n";
  // One decimal during the motion (tens of mm), two at rest (residual waves of a few mm).
  out += "  motion    " + pad(both(p, "eta_motion_mm", 1), 22) + "(" + both(b, "eta_motion_mm", 1) +
         ")\n";
  out +=
      "  rest      " + pad(both(p, "eta_rest_mm", 2), 22) + "(" + both(b, "eta_rest_mm", 2) + ")\n";
  out += "change vs uniform law: motion " + change(r["motion"]) + " / " +
         change(r["linear"]["motion"]) + ", rest " + change(r["rest"]) + " / " +
         change(r["linear"]["rest"]) +
         (r.value("model", "nonlinear") != "linear" ? " (nonlinear / linear)\n"
          : has_code(plan, "reductions_on_linear_model")
              ? " (linear / linear: the nonlinear model holds for one of the two laws only)\n"
              : " (linear / linear: the nonlinear model holds for neither law)\n");
  return out;
}

}  // namespace

std::string plan_summary_text(const json& plan) {
  const json& f = plan["format"];
  const json& box = f["container"];
  const std::string container = box.contains("length_mm")
                                    ? "L " + num(box["length_mm"], 1) + " x W " +
                                          num(box["width_mm"], 1) + " mm at " +
                                          num(box["orientation_deg"], 1) + " deg"
                                    : "R " + num(box["radius_mm"], 1) + " mm";
  std::string out = "plan        " + plan["strategy"].get<std::string>() + " on " + container +
                    ", h " + num(f["fill_height_mm"], 1) + " mm, " +
                    f["fluid"].value("name", std::string("custom fluid")) + ", " +
                    num(f["stroke_mm"], 1) + " mm in " + num(f["motion_time_s"], 3) + " s\n";
  out += "status      " + plan["status"].get<std::string>() + "\n";
  out += "message     " + plan["message"].get<std::string>() + "\n";
  if (plan.contains("candidates")) {
    for (const json& c : plan["candidates"]) {
      if (c.value("chosen", false)) out += "chosen      " + c["strategy"].get<std::string>() + "\n";
    }
  }
  out += law_line(plan) + kinematics_line(plan["kinematics"], plan.contains("path")) +
         path_line(plan) + prediction_lines(plan);
  if (plan["warnings"].empty()) out += "warnings    none\n";
  for (const json& w : plan["warnings"]) out += "warning     " + w.get<std::string>() + "\n";
  out += "key         " + plan["key"].get<std::string>() +
         " (GET /v1/plans/KEY; --format json prints the whole plan)\n";
  return out;
}

std::string fluids_table_text(const json& fluids) {
  std::string out = pad("name", 19) + pad("density [kg/m^3]", 18) + pad("viscosity [Pa s]", 18) +
                    "source (at " + num(fluids["temperature_c"], 0) + " C)\n";
  for (const json& f : fluids["fluids"]) {
    char viscosity[32];
    std::snprintf(viscosity, sizeof viscosity, "%.4g", f["viscosity_pa_s"].get<double>());
    out += pad(f["name"].get<std::string>(), 19) + pad(num(f["density_kg_m3"], 1), 18) +
           pad(viscosity, 18) + f["source"].get<std::string>() + "\n";
  }
  return out;
}

}  // namespace slosh::api
