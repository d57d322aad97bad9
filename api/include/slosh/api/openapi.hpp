#pragma once
// The OpenAPI 3.0.3 description of the HTTP service (GET /v1/openapi.json, SPEC §7).

#include <string>

#include <nlohmann/json.hpp>

#include "slosh/api/option_registry.hpp"

namespace slosh::api {

/// Largest number of plan requests of one POST /v1/plans/batch the document advertises (the
/// service's default `batch_max`; a server may be configured otherwise).
inline constexpr int kOpenApiBatchMax{1000};

/// The whole API as an OpenAPI 3.0.3 document: every endpoint, request and response schema with
/// the ranges and defaults the parsers enforce, the error envelope and its codes. `version` is
/// the service version reported in `info.version`.
/// The plan option schemas come from `registry`.
[[nodiscard]] nlohmann::json openapi_document(
    const std::string& version, const OptionRegistry& registry = plan_option_registry());

}  // namespace slosh::api
