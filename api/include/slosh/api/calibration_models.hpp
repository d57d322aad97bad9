#pragma once
// Stored calibrations seen from a request: the fit as the text that is answered and stored,
// a stored calibration answered again, and options.model = "<name>" in plan, simulate, min-time
// and batch bodies replaced by the stored model object. The service stores and looks up bytes.

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "slosh/api/calibration_json.hpp"

namespace slosh::api {

/// A POST /v1/calibrations body (400 when it is not JSON, 422 as parse_calibration_request).
[[nodiscard]] CalibrationRequest parse_calibration_text(std::string_view text);

/// The fit of `request` rendered as its response body (run_calibration as JSON text).
[[nodiscard]] std::string run_calibration_text(const CalibrationRequest& request);

/// A fit the request named to be stored, as answered: `fit_text` with "stored": true when it
/// converged, else false with "not_stored" saying why (a plan naming it would apply parameters
/// the fit did not settle, so it is not stored). `storable` says which.
[[nodiscard]] std::string named_fit_reply(const std::string& fit_text, bool& storable);

/// A stored calibration's text as GET /v1/calibrations/{name} answers it (read and written
/// again, so the answer has the current rendering of the stored JSON).
[[nodiscard]] std::string stored_calibration_reply(std::string_view stored);

/// The stored calibration's JSON text under a name, or nullopt when none is stored.
using CalibrationLookup = std::function<std::optional<std::string>(const std::string& name)>;

/// `body` with options.model = "<name>" replaced by that stored calibration's "model" object;
/// the same text when the body is not JSON or names no model. Throws ApiError: 422 for an
/// invalid name, 404 for an unknown one, both naming options.model.
[[nodiscard]] std::string resolve_model_names(const std::string& body,
                                              const CalibrationLookup& lookup);

/// A POST /v1/plans/batch body with the stored model put in for every request whose
/// options.model names a stored calibration; a request naming an invalid or unknown one is left
/// as it is (its own item answers 422 or 404 on options.model).
[[nodiscard]] std::string resolve_batch_model_names(const std::string& body,
                                                    const CalibrationLookup& lookup);

}  // namespace slosh::api
