#include "slosh/api/calibration_models.hpp"

#include <nlohmann/json.hpp>

#include "slosh/api/calibration_container.hpp"
#include "slosh/api/calibration_json.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {

namespace {

// Whether `request` is an object whose options.model is a string (a stored calibration's name).
bool names_a_model(const nlohmann::json& request) {
  const auto* options = request.is_object() ? given_member(request, "options") : nullptr;
  if (options == nullptr || !options->is_object()) return false;
  const auto* model = given_member(*options, "model");
  return model != nullptr && model->is_string();
}

// The body as its endpoint parses it, or discarded when that parse refuses it (malformed, too
// deep, a member given twice): the endpoint then refuses the body as sent, never a rewritten
// copy from which the repeated member was dropped.
nlohmann::json parsed_or_discarded(std::string_view body) {
  try {
    return parse_json_body(body);
  } catch (const ApiError&) {
    return nlohmann::json(nlohmann::json::value_t::discarded);
  }
}

// A rectangular container's calibration along one side stored before calibration-v2 was fitted
// on its dominant mode alone (its "parameters" carry the held alpha, which the per-direction fit
// of v2 never reports), with numbers off those of simulate's model that v2 fits (the gain by up
// to 13 %, zeta by up to 50 %, docs/calibration.md): refused, never mixed with this release's
// fits. The other stored fits (cylinders, turned tanks) have v2's numbers and are applied.
void refuse_superseded_fit(const nlohmann::json& stored, const std::string& name) {
  if (given_member(stored, "fit_version") != nullptr) return;
  const nlohmann::json* container = given_member(stored, "container");
  const nlohmann::json* parameters = given_member(stored, "parameters");
  if (container == nullptr || !container->is_object() || parameters == nullptr ||
      !parameters->is_object() || given_member(*parameters, "alpha") == nullptr ||
      container->value("shape", "") != "rectangular") {
    return;
  }
  invalid("options.model",
          "options.model = \"" + name +
              "\" is a rectangular container's calibration stored by an older release, fitted "
              "on its dominant mode alone (its frequency scale, damping and height gain are not "
              "those of simulate's model of the tank): calibrate it again (fit_version " +
              std::string(kCalibrationFitVersion) + ")");
}

// `body` with its options.model name replaced by the stored model (unchanged when it names none).
nlohmann::json resolve_model_name(nlohmann::json body, const CalibrationLookup& lookup) {
  if (!body.is_object() || !body.contains("options") || !body["options"].is_object()) return body;
  nlohmann::json& options = body["options"];
  if (!options.contains("model") || !options["model"].is_string()) return body;
  const std::string name = options["model"].get<std::string>();
  validate_calibration_name(name, "options.model");
  const std::optional<std::string> text = lookup(name);
  const nlohmann::json stored =
      text ? nlohmann::json::parse(*text, nullptr, false) : nlohmann::json();
  if (!text || !stored.contains("model")) {
    throw ApiError(ErrorCode::kNotFound, "options.model",
                   "options.model = \"" + name +
                       "\": no stored calibration of that name (POST /v1/calibrations "
                       "with \"name\" stores one)");
  }
  refuse_superseded_fit(stored, name);
  check_calibrated_container(stored, body, name);
  options["model"] = stored["model"];
  return body;
}

}  // namespace

CalibrationRequest parse_calibration_text(std::string_view text) {
  return parse_calibration_request(parse_json_body(text));
}

std::string run_calibration_text(const CalibrationRequest& request) {
  return dump_json(run_calibration(request));
}

std::string named_fit_reply(const std::string& fit_text, bool& storable) {
  nlohmann::json fit = nlohmann::json::parse(fit_text);
  const std::string status = fit.value("status", std::string());
  storable = status == "converged";
  fit["stored"] = storable;
  if (storable) {
    fit["not_stored"] = nullptr;
  } else {
    fit["not_stored"] = "the fit did not converge (status " + status + " after " +
                        std::to_string(fit.value("iterations", 0)) + " iterations, sigma " +
                        number_text(fit.value("sigma_mm", 0.0)) +
                        " mm): a plan naming it would apply parameters the fit did not settle, "
                        "so it is not stored; raise fit.max_iterations or check the moves, then "
                        "calibrate again";
  }
  return dump_json(fit);
}

std::string stored_calibration_reply(std::string_view stored) {
  return dump_json(nlohmann::json::parse(stored, nullptr, false));
}

std::string resolve_model_names(const std::string& body, const CalibrationLookup& lookup) {
  if (body.find("\"model\"") == std::string::npos) return body;
  const nlohmann::json parsed = parsed_or_discarded(body);
  if (parsed.is_discarded()) return body;  // the endpoint reports the malformed body itself
  if (!names_a_model(parsed)) return body;
  return dump_json(resolve_model_name(parsed, lookup));
}

std::string resolve_batch_model_names(const std::string& body, const CalibrationLookup& lookup) {
  if (body.find("\"model\"") == std::string::npos) return body;
  nlohmann::json parsed = parsed_or_discarded(body);
  if (parsed.is_discarded() || !parsed.is_object() || !parsed.contains("requests") ||
      !parsed["requests"].is_array()) {
    return body;  // the endpoint reports the body itself
  }
  bool changed = false;
  for (nlohmann::json& request : parsed["requests"]) {
    if (!names_a_model(request)) continue;
    try {
      request = resolve_model_name(request, lookup);
      changed = true;
    } catch (const ApiError&) {
      // left as given: the item's own parse names options.model
    }
  }
  return changed ? dump_json(parsed) : body;
}

}  // namespace slosh::api
