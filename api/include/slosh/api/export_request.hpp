#pragma once
// The request of `slosh export`: a simulate request with a "law" (that law is exported as given)
// or a plan request (its plan is solved or read from the cache, then exported).

#include <optional>
#include <string_view>

#include "slosh/api/simulate.hpp"

namespace slosh::api {

/// `text` read as the body of `slosh export --request`: the simulate request when the body is an
/// object with a "law" member; nullopt for a plan request, which is checked here (its errors name
/// its fields) and handed on as text. ApiError for invalid JSON or an invalid request.
[[nodiscard]] std::optional<SimulateRequest> parse_export_request(std::string_view text);

}  // namespace slosh::api
