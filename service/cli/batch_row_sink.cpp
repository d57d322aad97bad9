#include "cli/batch_row_sink.hpp"

namespace slosh::service::batch_cli {

BatchResult row_error_result(const RecipeRow& row) {
  BatchResult r;
  r.error = row.error;
  return r;
}

}  // namespace slosh::service::batch_cli
