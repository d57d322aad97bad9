// `slosh`: the command-line entry point (serve, plan, simulate, min-time, calibrate, batch,
// export).

#include <CLI/CLI.hpp>

#include <iostream>
#include <optional>
#include <string>

#include "cli/batch_command.hpp"
#include "cli/batch_interrupt.hpp"
#include "cli/cli_commands.hpp"
#include "cli/export_command.hpp"
#include "cli/setting_flags.hpp"
#include "config/config.hpp"
#include "config/version.hpp"
#include "http/http_server.hpp"
#include "storage/state_dir.hpp"

namespace {

using slosh::service::ServerConfig;

// Everything the command line sets; precedence: embedded defaults < --config file < SLOSH_*
// environment < flags.
struct CliArgs {
  const ServerConfig defaults{};
  std::string config_path;
  std::optional<std::string> host;
  std::optional<int> port;
  std::string port_file;
  std::optional<std::size_t> workers, queue;
  std::optional<std::string> cache;
  std::optional<std::string> log_format, replica_id;  // slosh serve
  std::optional<std::string> cache_local;
  std::optional<std::size_t> cache_ttl_s, redis_timeout_ms;
  bool redis_required{false};
  std::string request = "-";
  std::string trajectory;                       // slosh simulate --trajectory
  slosh::service::PlanCommandOptions plan;      // slosh plan (but --request)
  slosh::service::MotionFlags min_time_motion;  // slosh min-time's move flags
  std::string fluids_format = "text";
  slosh::service::BatchCommandOptions batch;
  std::string batch_progress = "auto";
  slosh::service::ExportCommandOptions export_options;
  std::string export_format = "csv";
};

std::string cache_help(const CliArgs& a, const std::string& what) {
  return what + ", \"\" = " + (what.starts_with("SQLite file") ? "memory only" : "none") +
         " [default " + a.defaults.cache_path +
         ", XDG_STATE_HOME defaulting to ~/.local/state; env " +
         slosh::service::setting_limits("cache").env + "]";
}

// The settings of the Redis shared cache level (ServerConfig documents them).
void add_redis_options(CLI::App& serve, CliArgs& a) {
  using slosh::service::add_setting_option;
  using slosh::service::setting_help;
  add_setting_option(serve, "--cache-local", "cache_local", a.cache_local,
                     setting_help("With --cache redis://...: SQLite file of this replica's local "
                                  "level between memory and Redis (get: memory, SQLite, Redis, "
                                  "hits promoted to the faster levels; put: all)",
                                  "cache_local", a.defaults, "none: memory and Redis"));
  add_setting_option(serve, "--cache-ttl-s", "cache_ttl_s", a.cache_ttl_s,
                     setting_help("Expiry of the plans written to Redis [s], 0 = none",
                                  "cache_ttl_s", a.defaults));
  add_setting_option(serve, "--redis-timeout-ms", "redis_timeout_ms", a.redis_timeout_ms,
                     setting_help("Longest a Redis command may take, connecting included [ms]; "
                                  "beyond, the request goes on from the local levels",
                                  "redis_timeout_ms", a.defaults));
  serve.add_flag("--redis-required", a.redis_required,
                 std::string("/readyz answers 503 while Redis is down (default: 200 with status "
                             "degraded; env ") +
                     slosh::service::setting_limits("redis_required").env + "=true)");
}

CLI::App* add_serve(CLI::App& app, CliArgs& a) {
  using slosh::service::add_setting_option;
  using slosh::service::setting_help;
  auto* serve = app.add_subcommand("serve", "Run the HTTP/JSON service");
  serve->add_option("--config", a.config_path, "JSON config file (see config/slosh.json)");
  add_setting_option(*serve, "--host", "host", a.host,
                     setting_help("Bind address", "host", a.defaults));
  add_setting_option(*serve, "--port", "port", a.port,
                     setting_help("TCP port, 0 = any free port", "port", a.defaults));
  serve->add_option("--port-file", a.port_file, "Write the bound port to this file");
  add_setting_option(*serve, "--workers", "workers", a.workers,
                     setting_help("Solve workers, 0 = the cores", "workers", a.defaults));
  add_setting_option(*serve, "--queue", "queue", a.queue,
                     setting_help("Solves that may wait; beyond, 503", "queue", a.defaults));
  serve->add_option("--cache", a.cache,
                    cache_help(a,
                               "SQLite file of the plan cache, or redis://host:port/db (or "
                               "redis://:password@host:port/db): a Redis shared by several "
                               "replicas behind the memory LRU"));
  add_setting_option(*serve, "--log-format", "log_format", a.log_format,
                     setting_help("Log lines: text, or json (one JSON object per line)",
                                  "log_format", a.defaults));
  add_setting_option(*serve, "--replica-id", "replica_id", a.replica_id,
                     setting_help("Name in the X-Slosh-Replica response header, \"\" = the host "
                                  "name",
                                  "replica_id", a.defaults));
  add_redis_options(*serve, a);
  return serve;
}

CLI::App* add_request_command(CLI::App& app, CliArgs& a, const std::string& name,
                              const std::string& help) {
  auto* command = app.add_subcommand(name, help);
  command->add_option("--request", a.request, "Request JSON file, or - for stdin")
      ->capture_default_str();
  return command;
}

CLI::App* add_simulate(CLI::App& app, CliArgs& a) {
  auto* simulate = add_request_command(
      app, a, "simulate",
      "Simulate a motion law on a format (JSON in, the /v1/simulate response out)");
  simulate->add_option("--trajectory", a.trajectory,
                       "Trajectory CSV as format.motion: t_s,x_mm,y_mm[,z_mm][,theta_deg] or "
                       "t_s,x_m,y_m,z_m,qx,qy,qz,qw (the request then gives no law nor stroke_mm "
                       "and motion_time_s)");
  return simulate;
}

// The move flags of plan and min-time (MotionFlags), one table for both; `instead_of` is what
// they replace ("--stroke", or the request's format.stroke_mm).
void add_motion_flags(CLI::App& command, slosh::service::MotionFlags& m,
                      const std::string& instead_of) {
  command.add_option("--arc-radius", m.arc_radius_mm,
                     "Instead of " + instead_of +
                         ", an arc (rotary table, carousel, curved track): its radius [mm]");
  command.add_option("--arc-angle", m.arc_angle_deg,
                     "The arc's angle [deg], signed (left positive), e.g. 90 for a 90-degree "
                     "index");
  command.add_option("--turns", m.turns,
                     "true (default): the container turns with the table; false: it keeps its "
                     "heading (a carriage on a curved track)");
  command.add_option("--motion", m.motion_path,
                     "Instead of " + instead_of +
                         ", a JSON file holding format.motion (a line, an arc or a path of lines "
                         "and arcs)");
}

CLI::App* add_plan(CLI::App& app, CliArgs& a) {
  auto* plan = add_request_command(
      app, a, "plan",
      "Plan the motion law of a format: the 7 durations of an optimised 7-segment law, or a "
      "general law of the same time for the filtering strategies (fir_chain, shaper, iir; auto "
      "may choose one). Request JSON in (--request) or the format as flags (--radius ...); the "
      "/v1/plans response or a short text summary out");
  auto& q = a.plan.quick;
  plan->add_option("--radius", q.radius_mm, "Format flags: container radius [mm] (a cylinder)");
  plan->add_option("--length", q.length_mm,
                   "Or a rectangular container: its side L [mm] (along the motion at "
                   "orientation 0)");
  plan->add_option("--width", q.width_mm, "Rectangular container: its side W [mm]");
  plan->add_option("--orientation", q.orientation_deg,
                   "Rectangular container: angle of L to the motion [deg], -180 to 180 "
                   "[default 0]");
  plan->add_option("--fill", q.fill_mm, "Fill height [mm]");
  plan->add_option("--height", q.height_mm, "Container height [mm] (optional; the free board)");
  plan->add_option("--fluid", q.fluid, "Catalogue fluid (slosh fluids), e.g. water");
  plan->add_option("--density", q.density_kg_m3, "Custom fluid instead: density [kg/m^3]");
  plan->add_option("--viscosity", q.viscosity_pa_s, "Custom fluid: dynamic viscosity [Pa s]");
  plan->add_option("--stroke", q.stroke_mm, "Stroke [mm]");
  plan->add_option("--time", q.time_s, "Motion time [s]");
  add_motion_flags(*plan, q, "--stroke");
  plan->add_option("--strategy", q.strategy,
                   "baseline, notch, multi_notch, min_jerk_band, time_domain, fir_chain, shaper, "
                   "iir or auto [default auto]");
  plan->add_option("--format", a.plan.format,
                   "json: the /v1/plans response; text: status, law, eta on both models, "
                   "reductions, warnings [default: json with --request, text with format flags]")
      ->check(CLI::IsMember({"text", "json"}));
  plan->add_option("--view", a.plan.view,
                   "JSON output: full (default): the whole plan; compact: key, status, strategy, "
                   "law, kinematics, predictions, warnings, version and the robustness interval "
                   "and worst eta (as ?view=compact)");
  return plan;
}

// The options of `slosh batch --server`: where, in what chunks, and how long a busy or silent
// service is borne.
void add_batch_server_options(CLI::App& batch, CliArgs& a) {
  batch.add_option(
      "--server", a.batch.server,
      "Send the table to a running service (http://host:port) instead of solving here");
  batch
      .add_option(
          "--chunk", a.batch.chunk,
          "Recipes per request in --server mode (plan mode; min_time sends one recipe a request)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  batch
      .add_option("--retries", a.batch.retries,
                  "--server: times a call the service answers 503 (not now) is sent again, each "
                  "after its Retry-After, before the run stops")
      ->check(CLI::Range(0, slosh::service::kMaxRetries))
      ->capture_default_str();
  batch
      .add_option("--give-up-after", a.batch.give_up_after_s,
                  "--server: seconds a started job is polled while the service does not answer "
                  "at all (a paused replica) before the run stops, leaving the job alone")
      ->check(CLI::Range(slosh::service::kMinGiveUpAfterS, slosh::service::kMaxGiveUpAfterS))
      ->capture_default_str();
}

CLI::App* add_batch(CLI::App& app, CliArgs& a) {
  auto* batch = app.add_subcommand(
      "batch", "Plan a recipe table (CSV or JSON lines in, a plan table as CSV or JSON out)");
  batch->add_option("--in", a.batch.in, "Recipe table file, or - for stdin")->capture_default_str();
  batch->add_option("--out", a.batch.out, "Plan table file, or - for stdout")
      ->capture_default_str();
  batch
      ->add_option("--in-format", a.batch.in_format,
                   "Recipe table format (auto: from the extension .csv/.jsonl/.ndjson/.json)")
      ->check(CLI::IsMember({"auto", "csv", "jsonl", "json"}))
      ->capture_default_str();
  batch
      ->add_option("--out-format", a.batch.out_format,
                   "Plan table format (auto: from the extension; csv for -)")
      ->check(CLI::IsMember({"auto", "csv", "jsonl", "json"}))
      ->capture_default_str();
  batch->add_option("--config", a.config_path, "JSON config file (workers, cache, solve budget)");
  slosh::service::add_setting_option(
      *batch, "--workers", "workers", a.workers,
      slosh::service::setting_help("Parallel solves, 0 = the cores", "workers", a.defaults));
  batch->add_option("--cache", a.cache,
                    cache_help(a, "SQLite plan cache shared with `slosh serve`"));
  add_batch_server_options(*batch, a);
  batch
      ->add_option("--progress", a.batch_progress,
                   "Progress bar on stderr: auto (when stderr is a terminal), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}))
      ->capture_default_str();
  batch->add_flag("--full", a.batch.full, "JSON output: add the whole plan to each row");
  batch->add_option("--view", a.batch.view,
                    "JSON output: add the plan to each row in this view: full (as --full) or "
                    "compact (as ?view=compact)");
  batch
      ->add_option("--mode", a.batch.mode,
                   "plan: a plan per recipe; min_time: each strategy's minimum motion time per "
                   "recipe (motion_time_s = the upper end of the search; T_min per strategy, "
                   "winner, gain)")
      ->check(CLI::IsMember({"plan", "min_time"}))
      ->capture_default_str();
  return batch;
}

// The cam table options of `slosh export` (CamOptions in cam_export.hpp).
void add_cam_options(CLI::App& export_cmd, CliArgs& a) {
  auto& c = a.export_options.cam;
  export_cmd
      .add_option("--format", a.export_format,
                  "Cam table file: csv, or st (IEC 61131-3 structured text: a TYPE of a cam "
                  "point and a VAR_GLOBAL CONSTANT array of the rows)")
      ->check(CLI::IsMember({"csv", "st"}))
      ->capture_default_str();
  export_cmd.add_option("--period-ms", c.period_ms,
                        "Time-based table: controller cycle [ms], in [0.01, 1000] [default 1]");
  export_cmd.add_option("--master-period", c.master_period,
                        "Master-axis table instead: length of the master cycle [master units, "
                        "e.g. 360 degrees], > 0; the table covers [0, period]: 0 before the "
                        "start, the law from start to end at constant master speed, the stroke "
                        "after the end");
  export_cmd.add_option("--master-start", c.master_start,
                        "Master position where the motion starts, 0 <= start < end");
  export_cmd.add_option("--master-end", c.master_end,
                        "Master position where the motion ends at the stroke, end <= period");
  export_cmd.add_option("--master-step", c.master_step,
                        "Master distance between rows, > 0 [default period / 360]; rows are "
                        "added at start, end and period when they are off the grid");
  export_cmd.add_option("--st-name", c.st_name,
                        "--format st: identifier of the ARRAY constant [default SLOSH_CAM]");
}

CLI::App* add_export(CLI::App& app, CliArgs& a) {
  auto& o = a.export_options;
  auto* export_cmd = app.add_subcommand(
      "export",
      "Cam table of a plan or a law (time-based: t, position, velocity, acceleration, jerk; or "
      "on a master axis) as CSV or IEC 61131-3 structured text");
  export_cmd
      ->add_option("--request", o.request,
                   "Plan request (solved or read from the cache) or simulate request with \"law\"; "
                   "- for stdin")
      ->capture_default_str();
  export_cmd->add_option("--out", o.out, "Cam table file (CSV or ST), or - for stdout")->required();
  add_cam_options(*export_cmd, a);
  export_cmd->add_option("--segments", o.segments,
                         "Also write the 7-segment table (durations, jerks, A, B) to this CSV");
  export_cmd->add_flag("--allow-infeasible", o.allow_infeasible,
                       "Export an infeasible or time-limited plan (its best reachable law) too");
  export_cmd->add_option("--config", a.config_path, "JSON config file (cache, solve budget)");
  export_cmd->add_option("--cache", a.cache,
                         cache_help(a, "SQLite plan cache shared with `slosh serve`"));
  return export_cmd;
}

// The configuration layers of the commands that use one; nullopt (after a message) when a layer
// is invalid.
std::optional<ServerConfig> layered_config(const CliArgs& a, const std::string& command) {
  ServerConfig server = a.defaults;
  try {
    if (!a.config_path.empty()) slosh::service::apply_config_file(a.config_path, server);
    slosh::service::apply_environment(slosh::service::slosh_environment(), server);
  } catch (const std::exception& e) {
    std::cerr << "slosh " << command << ": " << e.what() << '\n';
    return std::nullopt;
  }
  if (a.workers) server.workers = *a.workers;
  if (a.cache) server.cache_path = *a.cache;
  if (a.cache_local) server.cache_local = *a.cache_local;
  if (a.cache_ttl_s) server.cache_ttl_s = *a.cache_ttl_s;
  if (a.redis_timeout_ms) server.redis_timeout_ms = *a.redis_timeout_ms;
  if (a.redis_required) server.redis_required = true;
  // `batch --server` solves nothing here: it opens no plan store.
  if (command == "batch" && !a.batch.server.empty()) return server;
  try {  // ${XDG_STATE_HOME}/slosh/...: the per-user state directory, created on demand (0700)
    if (a.cache) slosh::service::check_cache("--cache", *a.cache);
    slosh::service::check_cache_levels(server);
    const std::string configured = server.cache_path;
    server.cache_path =
        slosh::service::resolve_cache_path(configured, slosh::service::state_environment());
    slosh::service::ensure_state_directory(configured, server.cache_path);
  } catch (const std::exception& e) {
    std::cerr << "slosh " << command << ": " << e.what() << '\n';
    return std::nullopt;
  }
  return server;
}

slosh::service::ProgressMode progress_mode(const std::string& name) {
  return name == "always"  ? slosh::service::ProgressMode::kAlways
         : name == "never" ? slosh::service::ProgressMode::kNever
                           : slosh::service::ProgressMode::kAuto;
}

// `slosh serve` with the layered settings `server` and the command line's overrides.
int run_serve(const CliArgs& a, const ServerConfig& server) {
  ServerConfig s = server;
  if (a.host) s.host = *a.host;
  if (a.port) s.port = *a.port;
  if (a.queue) s.queue = *a.queue;
  try {
    if (a.log_format) slosh::service::apply_setting("log_format", "--log-format", *a.log_format, s);
    if (a.replica_id) slosh::service::apply_setting("replica_id", "--replica-id", *a.replica_id, s);
  } catch (const std::exception& e) {
    std::cerr << "slosh serve: " << e.what() << '\n';
    return slosh::service::kExitInvalidInput;
  }
  try {
    return slosh::service::run_server(s, a.port_file);
  } catch (const std::exception& e) {  // e.g. the system refused the worker threads
    std::cerr << "slosh serve: cannot run: " << e.what() << '\n';
    return 1;
  }
}

// Ctrl-C is only noted until the command is known: `batch --server` must see an interrupt from
// the process's first instant (to cancel a job it may post, and to end with exit 130 and its
// message). Priority 101, the first a program may use: before the program's own static
// initialisers, command-line parsing and the configuration layers (only the loader and the shared
// libraries' initialisers come first).
[[gnu::constructor(101)]] void note_interrupts_first() {
  slosh::service::batch_cli::note_interrupts();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"slosh: anti-sloshing motion-law planner for packaging machines"};
  app.set_version_flag("--version", std::string("slosh ") + slosh::kVersion);
  app.require_subcommand(1);
  CliArgs a;
  auto* serve = add_serve(app, a);
  auto* simulate = add_simulate(app, a);
  auto* plan = add_plan(app, a);
  auto* fluids = app.add_subcommand("fluids", "List the fluid catalogue (names for --fluid)");
  fluids->add_option("--format", a.fluids_format, "text (a table) or json (the /v1/fluids body)")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  auto* min_time = add_request_command(
      app, a, "min-time",
      "Minimum motion time of a format per strategy (JSON in, the /v1/min-time response out)");
  add_motion_flags(*min_time, a.min_time_motion, "the request's format.stroke_mm");
  auto* calibrate = add_request_command(
      app, a, "calibrate",
      "Fit the model to bench measurements (JSON in, the /v1/calibrations response out)");
  auto* batch = add_batch(app, a);
  auto* export_cmd = add_export(app, a);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : slosh::service::kExitInvalidInput;
  }
  // Every other command ends at Ctrl-C as the default action does.
  if (!*batch || a.batch.server.empty()) slosh::service::batch_cli::restore_interrupts();
  if (*simulate) return slosh::service::run_simulate_command(a.request, a.trajectory);
  if (*plan) {
    a.plan.request_path = a.request;
    a.plan.request_given = plan->get_option("--request")->count() > 0;
    return slosh::service::run_plan_command(a.plan);
  }
  if (*fluids) return slosh::service::run_fluids_command(a.fluids_format);
  if (*min_time) return slosh::service::run_min_time_command(a.request, a.min_time_motion);
  if (*calibrate) return slosh::service::run_calibrate_command(a.request);
  const std::optional<ServerConfig> server =
      layered_config(a, app.get_subcommands().front()->get_name());
  if (!server) return slosh::service::kExitInvalidInput;
  if (*serve) return run_serve(a, *server);
  if (*batch) {
    a.batch.config = *server;
    a.batch.progress = progress_mode(a.batch_progress);
    return slosh::service::run_batch_command(a.batch);
  }
  if (*export_cmd) {
    a.export_options.config = *server;
    a.export_options.cam.format = a.export_format == "st" ? slosh::service::CamFileFormat::kSt
                                                          : slosh::service::CamFileFormat::kCsv;
    return slosh::service::run_export_command(a.export_options);
  }
  return slosh::service::kExitInvalidInput;
}
