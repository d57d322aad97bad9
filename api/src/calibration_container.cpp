#include "slosh/api/calibration_container.hpp"

#include <algorithm>
#include <optional>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/core/response/rectangular_response.hpp"

namespace slosh::api {

namespace {

using nlohmann::json;

/// The directions a motion at `orientation_deg` drives, as fitted_container_json names them.
json directions_of(double orientation_deg) {
  const AxisComponents c = axis_components(orientation_deg);
  json out = json::array();
  if (c.along_length != 0.0) out.push_back("length");
  if (c.along_width != 0.0) out.push_back("width");
  return out;
}

/// The request's container in the form of fitted_container_json, or nullopt when it is not
/// readable (the endpoint's own parse refuses it then).
std::optional<json> requested_container(const json& body) {
  const json* format = body.is_object() ? given_member(body, "format") : nullptr;
  const json* c = format && format->is_object() ? given_member(*format, "container") : nullptr;
  if (c == nullptr || !c->is_object()) return std::nullopt;
  const json* shape = given_member(*c, "shape");
  const bool rectangular = shape != nullptr && *shape == "rectangular";
  if (shape != nullptr && !rectangular && *shape != "cylinder") return std::nullopt;
  auto number = [c](const char* name) -> const json* {
    const json* v = given_member(*c, name);
    return v != nullptr && v->is_number() ? v : nullptr;
  };
  if (!rectangular) {
    const json* radius = number("radius_mm");
    if (radius == nullptr) return std::nullopt;
    return json{{"shape", "cylinder"}, {"radius_mm", *radius}};
  }
  const json* length = number("length_mm");
  const json* width = number("width_mm");
  const json* orientation = number("orientation_deg");
  if (length == nullptr || width == nullptr) return std::nullopt;
  if (given_member(*c, "orientation_deg") != nullptr && orientation == nullptr) return std::nullopt;
  // Along an arc, a path or a trajectory the tank turns against its path (or the path turns
  // under it): both directions are driven, whatever the orientation.
  const json* motion = given_member(*format, "motion");
  const json* type =
      motion != nullptr && motion->is_object() ? given_member(*motion, "type") : nullptr;
  const bool spatial = type != nullptr && *type != "line";
  return json{
      {"shape", "rectangular"},
      {"length_mm", *length},
      {"width_mm", *width},
      {"directions", spatial ? json::array({"length", "width"})
                             : directions_of(orientation ? orientation->get<double>() : 0.0)}};
}

std::string describe(const json& c) {
  if (c.value("shape", "") != "rectangular") {
    return "a cylinder of radius " + number_text(c.value("radius_mm", 0.0)) + " mm";
  }
  const json& d = c["directions"];
  const std::string moved =
      d.size() == 2 ? "both of its sides" : "its " + d.front().get<std::string>();
  return "a rectangular container " + number_text(c.value("length_mm", 0.0)) + " x " +
         number_text(c.value("width_mm", 0.0)) + " mm moved along " + moved;
}

/// Whether the request's container is the fitted one and moves only directions it measured.
bool covered(const json& fitted, const json& requested) {
  if (fitted.value("shape", "") != requested["shape"]) return false;
  if (requested["shape"] == "cylinder")
    return fitted.value("radius_mm", json()) == requested["radius_mm"];
  if (fitted.value("length_mm", json()) != requested["length_mm"] ||
      fitted.value("width_mm", json()) != requested["width_mm"]) {
    return false;
  }
  const json measured = fitted.value("directions", json::array());
  for (const json& d : requested["directions"]) {
    if (std::find(measured.begin(), measured.end(), d) == measured.end()) return false;
  }
  return true;
}

}  // namespace

json fitted_container_json(const Format& format) {
  if (!format.container.rectangular) {
    return {{"shape", "cylinder"}, {"radius_mm", mm_of(format.container.radius)}};
  }
  const RectangularTank& t = *format.container.rectangular;
  return {{"shape", "rectangular"},
          {"length_mm", mm_of(t.length)},
          {"width_mm", mm_of(t.width)},
          {"directions", directions_of(t.orientation_deg)}};
}

void check_calibrated_container(const json& stored, const json& body, const std::string& name) {
  const json* fitted = given_member(stored, "container");
  if (fitted == nullptr || !fitted->is_object()) return;
  const std::optional<json> requested = requested_container(body);
  if (!requested || covered(*fitted, *requested)) return;
  invalid("options.model", "options.model = \"" + name + "\" was fitted on " + describe(*fitted) +
                               "; this request's container is " + describe(*requested) +
                               ": a calibration applies only to the container and the "
                               "directions it was measured on (calibrate this one, or give its "
                               "numbers as an options.model object)");
}

}  // namespace slosh::api
