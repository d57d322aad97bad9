#include "support/paths.hpp"

namespace slosh::test {
const char* binary_path() {
  return SLOSH_BINARY_PATH;
}
const char* source_dir() {
  return SLOSH_SOURCE_PATH;
}
}  // namespace slosh::test
