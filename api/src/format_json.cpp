#include "slosh/api/format_json.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "slosh/api/control_characters.hpp"
#include "slosh/api/error.hpp"
#include "slosh/core/model/fluid.hpp"
#include "slosh/core/response/rectangular_response.hpp"

namespace slosh::api {

namespace {

std::string catalogue_names() {
  std::string names;
  for (const Fluid& f : fluid_catalogue()) names += (names.empty() ? "" : ", ") + f.name;
  return names;
}

// Number of characters (code points) of a valid UTF-8 text.
std::size_t utf8_length(const std::string& text) {
  std::size_t n = 0;
  for (unsigned char c : text) n += (c & 0xC0) != 0x80 ? 1 : 0;
  return n;
}

/// True for a rectangular container: "shape" when given, else "cylinder". A container with both
/// the cylinder's radius and a rectangle's side is refused by name, whatever its shape.
bool container_shape(const nlohmann::json& c, const std::string& path) {
  const std::string spath = join_path(path, "shape");
  bool rectangular = false;
  if (const nlohmann::json* shape = given_member(c, "shape")) {
    if (!shape->is_string() || (*shape != "cylinder" && *shape != "rectangular")) {
      invalid(spath, spath + " = " + show(*shape) +
                         " is not allowed: one of \"cylinder\", \"rectangular\"");
    }
    rectangular = *shape == "rectangular";
  }
  // A radius with an orientation but no side is not this conflict: it is a cylinder turned (the
  // orientation belongs to a rectangle) or a rectangle with a radius instead of its sides, which
  // parse_container names.
  for (std::string_view side : {"length_mm", "width_mm"}) {
    if (given_member(c, "radius_mm") == nullptr || given_member(c, side) == nullptr) continue;
    const std::string field = join_path(path, rectangular ? "radius_mm" : side);
    invalid(field, join_path(path, "radius_mm") + " and " + join_path(path, side) +
                       " are both given: a container is a cylinder (radius_mm) or rectangular (" +
                       join_path(path, "shape") +
                       " = \"rectangular\" with length_mm, width_mm and orientation_deg), not "
                       "both");
  }
  return rectangular;
}

/// `c` without the other shape's members given null (read as left out, as every optional
/// member's null is: a form that sends each field, blanks as null, names them all).
nlohmann::json without_other_shapes_nulls(const nlohmann::json& c, bool rectangular) {
  nlohmann::json out = c;
  const std::vector<std::string_view> other =
      rectangular ? std::vector<std::string_view>{"radius_mm"}
                  : std::vector<std::string_view>{"length_mm", "width_mm", "orientation_deg"};
  for (std::string_view key : other) {
    const auto it = out.find(std::string(key));
    if (it != out.end() && it->is_null()) out.erase(it);
  }
  return out;
}

/// The container of a format (parse_format).
Container parse_container(const nlohmann::json& given, const std::string& path) {
  const bool rectangular = container_shape(given, path);
  const nlohmann::json c = without_other_shapes_nulls(given, rectangular);
  Container out;
  if (!rectangular) {
    for (std::string_view side : {"length_mm", "width_mm", "orientation_deg"}) {
      if (given_member(c, side) == nullptr) continue;
      const std::string field = join_path(path, side);
      invalid(field, field + " belongs to a rectangular container: give " +
                         join_path(path, "shape") + " = \"rectangular\" (the cylinder has " +
                         "radius_mm)");
    }
    // (The cylinder's list without "shape" unless given: its refusals read as they always have.)
    if (find_member(c, "shape") != nullptr) {  // given, or null (absent)
      reject_unknown_fields(c, path, {"shape", "radius_mm", "height_mm"});
    } else {
      reject_unknown_fields(c, path, {"radius_mm", "height_mm"});
    }
    out.radius = required_number(c, path, "radius_mm", ranges::kRadiusMm) * 1e-3;
    return out;
  }
  if (given_member(c, "radius_mm") != nullptr) {
    const std::string field = join_path(path, "radius_mm");
    invalid(field, field + " belongs to a cylinder: a container with " + join_path(path, "shape") +
                       " = \"rectangular\" has length_mm, width_mm and orientation_deg (leave " +
                       join_path(path, "shape") + " out for a cylinder)");
  }
  reject_unknown_fields(c, path,
                        {"shape", "length_mm", "width_mm", "height_mm", "orientation_deg"});
  RectangularTank t;
  t.length = required_number(c, path, "length_mm", ranges::kSideMm) * 1e-3;
  t.width = required_number(c, path, "width_mm", ranges::kSideMm) * 1e-3;
  t.orientation_deg = optional_number(c, path, "orientation_deg", ranges::kOrientationDeg, 0.0);
  // One spelling per direction of motion, so that one direction has one recipe key and one
  // echo: -0 is 0 and -180 is 180 (the same angle). 0 and 180 (or 90 and -90) are not merged:
  // they move the tank the other way round, and the answer's signed components differ.
  if (t.orientation_deg == 0.0) t.orientation_deg = 0.0;
  if (t.orientation_deg == -180.0) t.orientation_deg = 180.0;
  out.rectangular = t;
  return out;
}

}  // namespace

Fluid parse_fluid(const nlohmann::json& fluid, const std::string& path) {
  if (fluid.is_string()) {
    const auto name = fluid.get<std::string>();
    if (auto f = find_fluid(name)) return *f;
    invalid(path, path + " = " + show(fluid) +
                      " is not in the catalogue; allowed: " + catalogue_names() +
                      ", or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}");
  }
  if (!fluid.is_object()) {
    invalid(path, path + " must be a catalogue name (" + catalogue_names() +
                      ") or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}, got " +
                      show(fluid));
  }
  reject_unknown_fields(fluid, path, {"density_kg_m3", "viscosity_pa_s", "name"});
  Fluid f;
  f.name = "custom";
  if (auto name = fluid.find("name"); name != fluid.end() && !name->is_null()) {
    const std::string npath = join_path(path, "name");
    if (!name->is_string() || name->get<std::string>().empty() ||
        utf8_length(name->get<std::string>()) > 64) {
      invalid(npath, npath + " must be a text of 1 to 64 characters, got " + show(*name));
    }
    f.name = name->get<std::string>();
    refuse_control_characters(npath, f.name);  // echoed into plans, tables and logs
  }
  f.density = required_number(fluid, path, "density_kg_m3", ranges::kDensity);
  f.viscosity = required_number(fluid, path, "viscosity_pa_s", ranges::kViscosity);
  f.source = "given by the caller";
  return f;
}

Format parse_format(const nlohmann::json& format, const std::string& path) {
  require_object(format, path);
  reject_unknown_fields(format, path,
                        {"container", "fill_height_mm", "fluid", "stroke_mm", "motion_time_s"});
  const std::string cpath = join_path(path, "container");
  auto it = format.find("container");
  if (it == format.end())
    invalid(cpath, cpath + " is required: {\"radius_mm\"} and optionally \"height_mm\"");
  require_object(*it, cpath);
  Format f;
  f.container = parse_container(*it, cpath);
  const double fill_mm = required_number(format, path, "fill_height_mm", ranges::kFillHeightMm);
  f.fill_height = fill_mm * 1e-3;
  if (it->contains("height_mm") && !(*it)["height_mm"].is_null()) {
    const Range height_range{fill_mm, ranges::kContainerHeightMm.hi, "mm", true};
    f.container.height = required_number(*it, cpath, "height_mm", height_range) * 1e-3;
  }
  const std::string fpath = join_path(path, "fluid");
  auto fl = format.find("fluid");
  if (fl == format.end()) {
    invalid(fpath, fpath + " is required: a catalogue name (" + catalogue_names() +
                       ") or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}");
  }
  f.fluid = parse_fluid(*fl, fpath);
  f.stroke = required_number(format, path, "stroke_mm", ranges::kStrokeMm) * 1e-3;
  f.motion_time = required_number(format, path, "motion_time_s", ranges::kMotionTimeS);
  return f;
}

Format parse_request_format(const nlohmann::json& body) {
  if (!body.contains("format")) {
    invalid("format",
            "format is required: {\"container\", \"fill_height_mm\", \"fluid\", \"stroke_mm\", "
            "\"motion_time_s\"}");
  }
  return parse_format(body["format"], "format");
}

void parse_model_options(const nlohmann::json& options, const std::string& path,
                         ModelOptions& model) {
  model.modes = optional_integer(options, path, "modes", 1, static_cast<int>(kMaxModes), 3);
  model.alpha = optional_number(options, path, "alpha", ranges::kAlpha, kDefaultAlpha);
  parse_damping(options, path, model);
}

void parse_calibrated_model(const nlohmann::json& options, const std::string& path,
                            ModelOptions& model) {
  const nlohmann::json* m = given_member(options, "model");
  if (m == nullptr) return;
  const std::string mpath = join_path(path, "model");
  require_object(*m, mpath);
  reject_unknown_fields(
      *m, mpath,
      {"omega_scale", "zeta", "alpha", "height_gain", "width_omega_scale", "width_zeta"});
  for (const auto& [member, top] :
       {std::pair<std::string_view, std::string_view>{"alpha", "alpha"}, {"zeta", "damping"}}) {
    if (given_member(*m, member) != nullptr && given_member(options, top) != nullptr) {
      const std::string field = join_path(mpath, member);
      invalid(field,
              field + " and " + join_path(path, top) + " both set the model: give one of them");
    }
  }
  model.omega_scale = optional_number(*m, mpath, "omega_scale", ranges::kModelScale, 1.0);
  if (given_member(*m, "zeta") != nullptr) {
    model.damping = DampingCorrelation::kExplicit;
    model.explicit_zeta = required_number(*m, mpath, "zeta", ranges::kZeta);
  }
  if (given_member(*m, "alpha") != nullptr) {
    model.alpha = required_number(*m, mpath, "alpha", ranges::kAlpha);
  }
  model.height_gain = optional_number(*m, mpath, "height_gain", ranges::kModelScale, 1.0);
  if (given_member(*m, "width_omega_scale") != nullptr) {
    model.width_omega_scale = required_number(*m, mpath, "width_omega_scale", ranges::kModelScale);
  }
  if (given_member(*m, "width_zeta") != nullptr) {
    model.width_zeta = required_number(*m, mpath, "width_zeta", ranges::kZeta);
  }
}

void parse_damping(const nlohmann::json& options, const std::string& path, ModelOptions& model) {
  const std::string dpath = join_path(path, "damping");
  const nlohmann::json* it = given_member(options, "damping");
  if (it == nullptr) {
    model.damping = DampingCorrelation::kThesis;
    return;
  }
  if (it->is_string()) {
    const auto name = enum_from_name<DampingCorrelation>(it->get<std::string>());
    if (name && *name != DampingCorrelation::kExplicit) {
      model.damping = *name;
      return;
    }
  } else if (it->is_object()) {
    reject_unknown_fields(*it, dpath, {"zeta"});
    model.damping = DampingCorrelation::kExplicit;
    model.explicit_zeta = required_number(*it, dpath, "zeta", ranges::kZeta);
    return;
  }
  std::vector<std::string> names = enum_names<DampingCorrelation>();
  std::erase(names, name_of(DampingCorrelation::kExplicit));  // given as {"zeta": z}
  invalid(dpath, dpath + " = " + show(*it) + " is not allowed: one of " + quoted_names(names) +
                     " or {\"zeta\": z} with 0 <= z < 0.5");
}

void refuse_cylinder_model_options(const Format& format, const nlohmann::json& options,
                                   const std::string& path) {
  if (!options.is_object()) return;
  const nlohmann::json* model = given_member(options, "model");
  if (!format.container.rectangular && model != nullptr && model->is_object()) {
    // A cylinder has one set of modes: a width of its own is a rectangular tank's.
    for (const char* member : {"width_omega_scale", "width_zeta"}) {
      if (given_member(*model, member) != nullptr) {
        const std::string model_path = join_path(path, "model");
        const std::string field = join_path(model_path, member);
        // The members it offers by their paths, which a recipe table's refusal names by their
        // columns.
        invalid(field, field +
                           " applies to a rectangular container only (the scale or damping of "
                           "its modes along the width): a cylinder's modes take " +
                           join_path(model_path, "omega_scale") + " and " +
                           join_path(model_path, "zeta"));
      }
    }
  }
  if (!format.container.rectangular) return;
  const std::string why =
      " applies to the cylinder's model only: a rectangular container's damping is its "
      "boundary layer's unless a zeta is given, and its nonlinear coefficient follows from its "
      "depth (docs/models.md)";
  const std::string dpath = join_path(path, "damping");
  if (const nlohmann::json* d = given_member(options, "damping"); d != nullptr && d->is_string()) {
    invalid(dpath, dpath + " = " + show(*d) + why);
  }
  if (given_member(options, "alpha") != nullptr) {
    invalid(join_path(path, "alpha"), join_path(path, "alpha") + why);
  }
  const nlohmann::json* m = given_member(options, "model");
  if (m != nullptr && m->is_object() && given_member(*m, "alpha") != nullptr) {
    const std::string apath = join_path(join_path(path, "model"), "alpha");
    invalid(apath, apath + why);
  }
}

nlohmann::json format_json(const Format& f) {
  // The lengths as the request gave them (mm_of undoes parse_format's mm * 1e-3 exactly).
  nlohmann::json container{{"radius_mm", mm_of(f.container.radius)}};
  if (const auto& t = f.container.rectangular) {
    container = {{"shape", "rectangular"},
                 {"length_mm", mm_of(t->length)},
                 {"width_mm", mm_of(t->width)},
                 {"orientation_deg", t->orientation_deg}};
  }
  if (f.container.height) container["height_mm"] = mm_of(*f.container.height);
  return {{"container", container},
          {"fill_height_mm", mm_of(f.fill_height)},
          {"fluid",
           {{"name", f.fluid.name},
            {"density_kg_m3", f.fluid.density},
            {"viscosity_pa_s", f.fluid.viscosity}}},
          {"stroke_mm", mm_of(f.stroke)},
          {"motion_time_s", f.motion_time}};
}

nlohmann::json model_json(const SloshingModel& m, const ModelOptions& options) {
  nlohmann::json f_hz = nlohmann::json::array();
  for (double w : m.omega) f_hz.push_back(w / (2.0 * std::numbers::pi));
  nlohmann::json out = {{"omega_rad_s", m.omega},
                        {"f_hz", f_hz},
                        {"zeta", m.zeta},
                        {"damping", to_string(options.damping)},
                        {"C", m.C},
                        {"alpha", m.alpha},
                        {"K_mm", m.K * 1e3},
                        {"sloshing_mass_kg", m.mass},
                        {"fluid_mass_kg", m.fluid_mass},
                        {"eta_gain", m.eta_gain}};
  // A calibrated model (options.model) says so; f_hz, K_mm and eta_gain include it.
  if (options.omega_scale != 1.0 || options.height_gain != 1.0 || options.width_omega_scale ||
      options.width_zeta) {
    out["calibration"] = {{"omega_scale", options.omega_scale},
                          {"height_gain", options.height_gain}};
    if (options.width_omega_scale)
      out["calibration"]["width_omega_scale"] = *options.width_omega_scale;
    if (options.width_zeta) out["calibration"]["width_zeta"] = *options.width_zeta;
  }
  return out;
}

void add_rectangular_model(nlohmann::json& out_model, const RectangularModel& model,
                           const ModelOptions& options) {
  out_model["rectangular"] = rectangular_model_json(model);
  // The tank's own damping unless given: the cylinder's correlations do not apply to it.
  if (options.damping != DampingCorrelation::kExplicit) out_model["damping"] = "rectangular";
}

nlohmann::json rectangular_model_json(const RectangularModel& model) {
  const AxisComponents c = axis_components(model.orientation_deg);
  nlohmann::json out = nlohmann::json::object();
  auto direction = [](const SloshingModel& m, double component) {
    nlohmann::json f_hz = nlohmann::json::array();
    for (double w : m.omega) f_hz.push_back(w / (2.0 * std::numbers::pi));
    return nlohmann::json{{"excited", component != 0.0},
                          {"component", component},
                          {"side_mm", m.radius * 1e3},
                          {"omega_rad_s", m.omega},
                          {"f_hz", f_hz},
                          {"zeta", m.zeta},
                          {"alpha", m.alpha},
                          {"K_mm", m.K * 1e3},
                          {"sloshing_mass_kg", m.mass},
                          {"eta_gain", m.eta_gain}};
  };
  out["length"] = direction(model.along_length, c.along_length);
  out["width"] = direction(model.along_width, c.along_width);
  out["orientation_deg"] = model.orientation_deg;
  return out;
}

nlohmann::json fluids_json() {
  nlohmann::json list = nlohmann::json::array();
  for (const Fluid& f : fluid_catalogue()) {
    list.push_back({{"name", f.name},
                    {"density_kg_m3", f.density},
                    {"viscosity_pa_s", f.viscosity},
                    {"source", f.source}});
  }
  return {{"fluids", list}, {"temperature_c", 20}};
}

}  // namespace slosh::api
