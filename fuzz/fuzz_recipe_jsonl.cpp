// Fuzz target: JSON recipe tables of `slosh batch`, read both as JSON lines (one plan request per
// line) and as one JSON document (an array or {"requests": [...]}), then validation and
// plan-table rendering of every row (see recipe_table_target.hpp).

#include <cstddef>
#include <cstdint>

#include "recipe_table_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  slosh::fuzz::run_recipe_table(data, size, slosh::service::TableFormat::kJsonLines);
  slosh::fuzz::run_recipe_table(data, size, slosh::service::TableFormat::kJson);
  return 0;
}
