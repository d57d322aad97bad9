// Fuzz target: JSON recipe tables of `slosh batch`, read both as JSON lines (one plan request per
// line) and as one JSON document (an array or {"requests": [...]}), then validation and
// plan-table rendering of every row (see recipe_table_target.hpp).

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "recipe_table_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Deep nesting: the product will answer it with an error itself (see fuzz_support.hpp).
  if (slosh::fuzz::skip_deep_json(std::string_view(reinterpret_cast<const char*>(data), size))) {
    return -1;
  }
  slosh::fuzz::run_recipe_table(data, size, slosh::service::TableFormat::kJsonLines);
  slosh::fuzz::run_recipe_table(data, size, slosh::service::TableFormat::kJson);
  return 0;
}
