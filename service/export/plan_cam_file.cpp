#include "export/plan_cam_file.hpp"

#include <cmath>
#include <optional>
#include <string>

#include "export/path_cam_export.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/export_request.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/motion_json.hpp"
#include "slosh/api/plan_law.hpp"

namespace slosh::service {

std::string plan_cam_file(const std::string& plan_text, const CamOptions& options,
                          bool allow_infeasible, const std::function<void(std::size_t)>& admit) {
  const CamTableSpec spec = resolve_cam_options(options, query_option_names(), kMaxServedCamRows,
                                                " here (slosh export writes longer tables)");
  const api::PlanLaw plan = api::plan_law(plan_text);
  // The whole table is built in memory: at most kMaxServedCamRows rows per request.
  const double duration = plan.law.duration();
  const double period_ms = spec.period_ms;
  const double shortest_ms = 1e3 * duration / static_cast<double>(kMaxServedCamRows - 2);
  if (!spec.master && duration / (period_ms * 1e-3) > static_cast<double>(kMaxServedCamRows - 2)) {
    throw api::ApiError(
        api::ErrorCode::kInvalidValue, "period_ms",
        "period_ms = " + master_value_text(period_ms) + " gives more than " +
            std::to_string(kMaxServedCamRows) + " rows over the " + api::number_text(duration) +
            " s motion: allowed >= " + api::number_text(std::ceil(shortest_ms * 1e3) / 1e3) +
            " ms here (slosh export writes longer tables)");
  }
  if (!allow_infeasible && !api::exportable(plan.status)) {
    throw api::ApiError(api::ErrorCode::kInvalidValue, "allow_infeasible",
                        api::not_exportable_message(plan, "add allow_infeasible=true"));
  }
  // A plan along an arc or a path: its table carries the pose (as slosh export writes it).
  const std::optional<api::SpatialMotion> motion = api::plan_path_motion(plan_text);
  if (admit) {
    const std::size_t bytes =
        cam_export_bytes(spec, cam_rows(spec, duration, query_option_names()));
    admit(motion ? kPathCamWidthFactor * bytes : bytes);
  }
  const CamTable table = sample_cam(plan.law, plan.stroke, spec, query_option_names());
  CamSource source{api::to_string(plan.type), plan.strategy, plan.key, plan.stroke, duration, {}};
  if (motion) return path_cam_file(table, *motion->path, source, spec);
  return cam_file(table, source, spec);
}

}  // namespace slosh::service
