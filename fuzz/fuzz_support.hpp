#pragma once
// Shared helpers of the fuzz targets (fuzz/*.cpp). Each target defines LLVMFuzzerTestOneInput; it
// is linked either with libFuzzer (clang, SLOSH_BUILD_FUZZERS) or with replay_main.cpp (the
// normal build, where ctest replays fuzz/corpus/<target> and fuzz/regressions/<target>).
//
// A finding is anything that stops the process: a sanitizer report, a stack overflow, an
// exception other than api::ApiError escaping the entry points (the service would turn it into a
// 500 instead of a 4xx), or a broken invariant checked below (require() aborts).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"

namespace slosh::fuzz {

/// Aborts with `what` when `ok` is false (a crash libFuzzer reports with its input).
inline void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
    std::abort();
  }
}

/// Every number in `value` is finite (SPEC §7: never a null where a number belongs; nlohmann
/// writes NaN and infinity as null).
inline bool all_finite(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::number_float:
      return std::isfinite(value.get<double>());
    case nlohmann::json::value_t::array:
    case nlohmann::json::value_t::object:
      for (const auto& item : value) {
        if (!all_finite(item)) return false;
      }
      return true;
    default:
      return true;
  }
}

/// What a service does with an ApiError: render the one envelope. It must be valid JSON text with
/// a 4xx status, a known code and a non-empty message.
inline void check_envelope(const api::ApiError& e) {
  require(e.status() == 400 || e.status() == 422, "a request error is a 400 or a 422");
  const std::string text = api::dump_json(api::error_envelope(e));
  const nlohmann::json back = nlohmann::json::parse(text, nullptr, false);
  require(!back.is_discarded(), "the error envelope is valid JSON");
  require(back["error"]["message"].is_string(), "the error envelope has a message");
  require(!back["error"]["message"].get<std::string>().empty(),
          "the error envelope has a non-empty message");
}

}  // namespace slosh::fuzz
