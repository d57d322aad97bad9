#pragma once
// The cam table file of a rendered plan as GET /v1/plans/{key}/cam.csv and cam.st serve it: the
// same bytes `slosh export` writes with the same options, within a row bound that keeps a request's
// memory small.

#include <cstddef>
#include <functional>
#include <string>

#include "export/cam_export.hpp"

namespace slosh::service {

/// Most rows GET /v1/plans/{key}/cam.csv and cam.st serve (about 12 MB of CSV); `slosh export`
/// has no such bound (only kCamMaxSamples).
inline constexpr std::size_t kMaxServedCamRows{200000};

/// The cam table file of a rendered plan (GET /v1/plans/{key}/cam.csv and cam.st): the same
/// bytes as `slosh export` with the same options (named as query_option_names()); more than
/// kMaxServedCamRows rows is refused (naming period_ms or master_step). Throws ApiError naming
/// the parameter, or allow_infeasible for an infeasible or time-limited plan when
/// `allow_infeasible` is false. Once the options and the plan are accepted, and before anything
/// is sampled, `admit` (when set) is called with an upper bound of the bytes the export holds
/// (cam_export_bytes); it refuses the export by throwing (e.g. ApiError kOverloaded).
[[nodiscard]] std::string plan_cam_file(const std::string& plan_text, const CamOptions& options,
                                        bool allow_infeasible,
                                        const std::function<void(std::size_t)>& admit = {});

}  // namespace slosh::service
