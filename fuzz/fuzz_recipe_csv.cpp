// Fuzz target: CSV recipe tables of `slosh batch` (libcsv through service::read_recipe_table),
// then validation and plan-table rendering of every row (see recipe_table_target.hpp).

#include <cstddef>
#include <cstdint>

#include "recipe_table_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  slosh::fuzz::run_recipe_table(data, size, slosh::service::TableFormat::kCsv);
  return 0;
}
