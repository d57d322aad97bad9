#include "cli/batch_row_sink.hpp"

#include "slosh/api/error.hpp"

namespace slosh::service::batch_cli {

BatchResult row_error_result(const RecipeRow& row) {
  BatchResult r;
  r.error = api::error_from_json(row.error);
  return r;
}

}  // namespace slosh::service::batch_cli
