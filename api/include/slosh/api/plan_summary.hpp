#pragma once
// Short human summaries for `slosh plan --format text` and `slosh fluids --format text`: what a
// person reads on a terminal instead of the whole JSON (which `--format json` still prints).

#include <nlohmann/json.hpp>
#include <string>

namespace slosh::api {

/// A plan response (the JSON `slosh plan --format json` prints) as a few lines: strategy and
/// status, the message, the law (durations or law type), the plateau levels and peaks, eta
/// during and after the motion on both models with the uniform law's and the reductions, the
/// warnings (each already names its model) and the recipe key. Ends with a newline.
[[nodiscard]] std::string plan_summary_text(const nlohmann::json& plan);

/// The fluid catalogue (the GET /v1/fluids body) as a table: name, density, viscosity, source.
[[nodiscard]] std::string fluids_table_text(const nlohmann::json& fluids);

}  // namespace slosh::api
