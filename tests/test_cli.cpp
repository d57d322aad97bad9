// The `slosh` binary end to end: version and help, `simulate` from a file and from stdin (same JSON
// as the in-process API), exit codes and the error envelope on stderr, every law type, the sampled
// series, and a `serve` smoke test (health endpoints, graceful SIGTERM).

#include <fcntl.h>
#include <httplib.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/simulate.hpp"
#include "support/process.hpp"

namespace slosh {
namespace test_cli {

using nlohmann::json;
namespace fs = std::filesystem;
using test::Child;
using test::read_file;
using test::run_slosh;
using test::RunResult;
using test::spawn;
using test::TempDir;
using test::wait_for_port;
using test::write_file;

/// The thesis format with the uniform 7-segment law and fluid given by its properties.
json thesis_request() {
  return json::parse(R"({
    "format": {"container": {"radius_mm": 48.5},
               "fill_height_mm": 82,
               "fluid": {"density_kg_m3": 1000, "viscosity_pa_s": 0.001},
               "stroke_mm": 800, "motion_time_s": 1.0},
    "law": {"type": "seven_segment_uniform"}
  })");
}

/// Runs `slosh simulate --request FILE` on `body`.
RunResult simulate_file(const json& body) {
  const TempDir dir;
  write_file(dir / "request.json", body.dump());
  return run_slosh({"simulate", "--request", (dir / "request.json").string()});
}

/// Parses text that must be JSON; a test failure otherwise.
json parse_or_fail(const std::string& text) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    ADD_FAILURE() << "not JSON (" << e.what() << "):\n" << text;
  }
  return json::object();
}

// ---------------------------------------------------------------------------------------------

TEST(CliBasics, VersionPrintsNameAndSemver) {
  const RunResult r = run_slosh({"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::regex_match(r.out, std::regex(R"(^slosh [0-9]+\.[0-9]+\.[0-9]+\n$)"))) << r.out;
}

TEST(CliBasics, HelpListsTheSubcommands) {
  const RunResult r = run_slosh({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("serve"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("simulate"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("plan"), std::string::npos) << r.out;
}

TEST(CliBasics, MissingSubcommandIsInvalidInput) {
  const RunResult r = run_slosh({});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CliBasics, UnknownSubcommandIsInvalidInput) {
  const RunResult r = run_slosh({"simulat"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// The serve flags check the ranges of the settings table: each bound written here once, checked
// on the flag (the real binary, just outside and the help), and on the environment variable the
// help names (the same table read by apply_environment), so the two cannot drift apart.
TEST(CliServeFlags, RangesAndEnvironmentNamesAreTheSettingsTables) {
  struct Case {
    const char* flag;
    const char* env;
    long long lo, hi;
  };
  const Case cases[] = {{"--port", "SLOSH_PORT", 0, 65535},
                        {"--workers", "SLOSH_WORKERS", 0, 1024},
                        {"--queue", "SLOSH_QUEUE", 1, 100000},
                        {"--cache-ttl-s", "SLOSH_CACHE_TTL_S", 0, 315360000},
                        {"--redis-timeout-ms", "SLOSH_REDIS_TIMEOUT_MS", 1, 60000}};
  const RunResult help = run_slosh({"serve", "--help"});
  ASSERT_EQ(help.exit_code, 0) << help.err;
  for (const Case& c : cases) {
    const std::string range = std::to_string(c.lo) + " to " + std::to_string(c.hi);
    for (const long long outside : {c.lo - 1, c.hi + 1}) {
      const std::string value = std::to_string(outside);
      const RunResult flag = run_slosh({"serve", c.flag, value});
      EXPECT_EQ(flag.exit_code, 2) << c.flag;
      EXPECT_EQ(flag.err, std::string(c.flag) + ": Value " + value + " not in range " + range +
                              "\nRun with --help for more information.\n");
      service::ServerConfig config;
      try {
        service::apply_environment({{c.env, value}}, config);
        ADD_FAILURE() << c.env << " = " << value << " was accepted";
      } catch (const std::runtime_error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.substr(0, std::string(c.env).size() + 3 + value.size()),
                  std::string(c.env) + " = " + value)
            << message;
        EXPECT_TRUE(message.ends_with(": allowed " + range)) << message;
      }
    }
    service::ServerConfig config;
    EXPECT_NO_THROW(service::apply_environment({{c.env, std::to_string(c.hi)}}, config));
    EXPECT_NE(help.out.find(std::string("env ") + c.env + "]"), std::string::npos) << c.flag;
  }
}

// ---------------------------------------------------------------------------------------------

TEST(CliSimulate, ThesisFormatMatchesReferenceAndInProcessApi) {
  const json body = thesis_request();
  const RunResult r = simulate_file(body);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const json out = parse_or_fail(r.out);
  ASSERT_TRUE(out.contains("model")) << r.out;
  EXPECT_NEAR(out["model"]["omega_rad_s"][0].get<double>(), 19.260, 5e-4);
  EXPECT_NEAR(out["model"]["zeta"].get<double>(), 4.43e-3, 5e-6);

  const json in_process = api::run_simulate(api::parse_simulate_request(body));
  EXPECT_EQ(out["prediction"], in_process["prediction"]);
  EXPECT_EQ(out["kinematics"], in_process["kinematics"]);
  EXPECT_EQ(out["model"], in_process["model"]);
  // Same document, byte for byte (the CLI prints api::dump_json(.., 2) and a newline).
  EXPECT_EQ(r.out, api::dump_json(in_process, 2) + "\n");
  // The numbers are real predictions, not placeholders.
  EXPECT_GT(out["prediction"]["nonlinear"]["eta_rest_mm"].get<double>(), 0.0);
  EXPECT_GT(out["prediction"]["linear"]["eta_motion_mm"].get<double>(), 0.0);
}

TEST(CliSimulate, StdinGivesTheSameOutputAsAFile) {
  const json body = thesis_request();
  const RunResult from_file = simulate_file(body);
  const RunResult from_stdin = run_slosh({"simulate", "--request", "-"}, body.dump());
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  ASSERT_EQ(from_stdin.exit_code, 0) << from_stdin.err;
  EXPECT_FALSE(from_stdin.out.empty());
  EXPECT_EQ(from_stdin.out, from_file.out);
}

TEST(CliSimulate, InvalidValueExits2WithEnvelopeOnStderr) {
  json body = thesis_request();
  body["format"]["container"]["radius_mm"] = -3;
  const RunResult r = simulate_file(body);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  const json err = parse_or_fail(r.err);
  EXPECT_EQ(err, json::parse(R"({"error": {
      "code": "invalid_value",
      "message": "format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm",
      "field": "format.container.radius_mm"}})"));
}

TEST(CliSimulate, ADirectoryAsRequestIsNamedNotAParseError) {
  const TempDir dir;
  std::filesystem::create_directory(dir / "req");
  const std::string path = (dir / "req").string();
  const RunResult r = run_slosh({"simulate", "--request", path});
  EXPECT_EQ(r.exit_code, 2);
  const json err = parse_or_fail(r.err);
  EXPECT_EQ(err["error"]["field"], json("--request"));
  EXPECT_EQ(err["error"]["message"],
            json("cannot read request file '" + path + "': it is a directory"));
}

TEST(CliSimulate, MalformedJsonExits2) {
  const RunResult r = run_slosh({"simulate", "--request", "-"}, "{\"format\": ");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  const json err = parse_or_fail(r.err);
  ASSERT_TRUE(err.contains("error")) << r.err;
  EXPECT_EQ(err["error"]["code"], json("malformed_json"));
  EXPECT_TRUE(err["error"]["field"].is_null());
  EXPECT_EQ(err["error"]["message"].get<std::string>().rfind("the body is not valid JSON: ", 0),
            0u);
}

TEST(CliSimulate, MissingRequestFileExits2NamingThePath) {
  const TempDir dir;
  const std::string path = (dir / "no_such_request.json").string();
  const RunResult r = run_slosh({"simulate", "--request", path});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  const json err = parse_or_fail(r.err);
  ASSERT_TRUE(err.contains("error")) << r.err;
  EXPECT_EQ(err["error"]["code"], json("invalid_value"));
  EXPECT_EQ(err["error"]["field"], json("--request"));
  EXPECT_EQ(err["error"]["message"], json("cannot read request file '" + path + "'"));
}

// An overflowing number (nlohmann out_of_range, not parse_error) is malformed JSON too.
TEST(CliSimulate, NumberOverflowIsMalformedJson) {
  const RunResult r = run_slosh({"simulate", "--request", "-"}, "{\"rest_time_s\": 1e400}");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(parse_or_fail(r.err), json::parse(R"({"error": {
      "code": "malformed_json",
      "message": "the body is not valid JSON: number overflow parsing '1e400'",
      "field": null}})"));
}

// A long non-ASCII value is cut on a UTF-8 boundary: the envelope is valid JSON and UTF-8.
TEST(CliSimulate, LongNonAsciiValueGivesAnEnvelope) {
  json body = thesis_request();
  std::string name = "a";
  for (int i = 0; i < 40; ++i) name += "\xc3\xa9";  // U+00E9
  body["format"]["fluid"] = name;
  const RunResult r = simulate_file(body);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  const json err = parse_or_fail(r.err);
  EXPECT_EQ(err["error"]["field"], json("format.fluid"));
  // "a" and 27 whole U+00E9 (57 bytes with the opening quote would split the 28th).
  std::string kept = "a";
  for (int i = 0; i < 27; ++i) kept += "\xc3\xa9";
  EXPECT_EQ(err["error"]["message"],
            json("format.fluid = \"" + kept +
                 "... is not in the catalogue; allowed: water, ethanol, isopropanol, "
                 "glycerol_water_50, milk, olive_oil, sunflower_oil, light_syrup, or "
                 "{\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}"));
}

// Invalid UTF-8 in the body: the parser's message quotes the raw byte; the CLI still prints a
// valid JSON envelope (the byte replaced by U+FFFD) and exits 2.
TEST(CliSimulate, InvalidUtf8BodyGivesAValidEnvelope) {
  const RunResult r = run_slosh({"simulate", "--request", "-"}, "{\"format\": \"\xff\"}");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(r.err.find('\xff'), std::string::npos);
  const json err = parse_or_fail(r.err);
  ASSERT_TRUE(err.contains("error")) << r.err;
  EXPECT_EQ(err["error"]["code"], json("malformed_json"));
  EXPECT_TRUE(err["error"]["field"].is_null());
}

TEST(CliSimulate, TooManySamplesExits2) {
  json body = thesis_request();
  body["format"]["motion_time_s"] = 10;
  body["rest_time_s"] = 10;
  body["sample_period_s"] = 1e-4;
  const RunResult r = simulate_file(body);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(parse_or_fail(r.err), json::parse(R"({"error": {
      "code": "invalid_value",
      "message": "sample_period_s = 0.0001 s gives 200001 samples over 20 s; at most 50000 are returned: use >= 0.0004000080002 s",
      "field": "sample_period_s"}})"));
}

TEST(CliSimulate, CustomFluidNameIsEchoed) {
  for (const std::string name : {"glycerine 85 %",
                                 "eau sucr\xc3\xa9"
                                 "e"}) {
    json body = thesis_request();
    body["format"]["fluid"]["name"] = name;
    const RunResult r = simulate_file(body);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json out = parse_or_fail(r.out);
    EXPECT_EQ(out["format"]["fluid"], json::parse(R"({"name": ")" + name + R"(",
        "density_kg_m3": 1000, "viscosity_pa_s": 0.001})"));
  }
  const RunResult plain = simulate_file(thesis_request());
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(parse_or_fail(plain.out)["format"]["fluid"]["name"], json("custom"));

  json empty = thesis_request();
  empty["format"]["fluid"]["name"] = "";
  const RunResult rejected = simulate_file(empty);
  EXPECT_EQ(rejected.exit_code, 2);
  EXPECT_EQ(parse_or_fail(rejected.err), json::parse(R"({"error": {
      "code": "invalid_value",
      "message": "format.fluid.name must be a text of 1 to 64 characters, got \"\"",
      "field": "format.fluid.name"}})"));
}

TEST(CliSimulate, NullOptionsGiveTheDefaultOutput) {
  json body = thesis_request();
  body["options"] = nullptr;
  const RunResult with_null = simulate_file(body);
  const RunResult without = simulate_file(thesis_request());
  ASSERT_EQ(with_null.exit_code, 0) << with_null.err;
  ASSERT_EQ(without.exit_code, 0) << without.err;
  EXPECT_EQ(with_null.out, without.out);
  EXPECT_EQ(parse_or_fail(with_null.out)["model"]["damping"], json("thesis"));
}

struct LawCase {
  const char* type;
  json durations;  // null: none
};

TEST(CliSimulate, EveryLawTypeRunsTheStroke) {
  const LawCase cases[] = {
      {"seven_segment", json::array({0.1, 0.15, 0.1, 0.3, 0.1, 0.15, 0.1})},
      {"seven_segment_uniform", nullptr},
      {"poly5", nullptr},
      {"modified_trapezoid", nullptr},
      {"cycloidal", nullptr},
  };
  for (const LawCase& c : cases) {
    json body = thesis_request();
    body["law"] = {{"type", c.type}};
    if (!c.durations.is_null()) body["law"]["durations_s"] = c.durations;
    const RunResult r = simulate_file(body);
    ASSERT_EQ(r.exit_code, 0) << c.type << ": " << r.err;
    const json out = parse_or_fail(r.out);
    ASSERT_TRUE(out.contains("law")) << c.type;
    EXPECT_EQ(out["law"]["type"], json(c.type));
    EXPECT_NEAR(out["law"]["stroke_mm"].get<double>(), 800.0, 1e-9) << c.type;
    EXPECT_NEAR(out["law"]["duration_s"].get<double>(), 1.0, 1e-12) << c.type;
    EXPECT_GT(out["kinematics"]["v_peak"].get<double>(), 0.8) << c.type;  // > mean speed s/T
    EXPECT_GT(out["prediction"]["nonlinear"]["eta_motion_mm"].get<double>(), 0.0) << c.type;
    if (!c.durations.is_null()) {
      ASSERT_EQ(out["law"]["durations_s"].size(), 7u);
      for (std::size_t i = 0; i < 7; ++i) {
        EXPECT_NEAR(out["law"]["durations_s"][i].get<double>(), c.durations[i].get<double>(),
                    1e-15);
      }
    }
  }
}

TEST(CliSimulate, SamplePeriodGivesTheSeries) {
  json body = thesis_request();
  body["sample_period_s"] = 0.01;
  const RunResult r = simulate_file(body);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = parse_or_fail(r.out);
  ASSERT_TRUE(out.contains("series")) << r.out.substr(0, 2000);
  const json& series = out["series"];
  // [0, T + rest] = [0, 2 s] at 10 ms, both ends included: 201 samples.
  constexpr std::size_t kSamples = 201;
  for (const char* name : {"t_s", "a", "v", "s", "eta_linear_mm", "eta_nonlinear_mm"}) {
    ASSERT_TRUE(series.contains(name)) << name;
    EXPECT_EQ(series[name].size(), kSamples) << name;
  }
  for (std::size_t i = 0; i < kSamples; ++i) {
    EXPECT_NEAR(series["t_s"][i].get<double>(), 0.01 * static_cast<double>(i), 1e-12) << i;
  }
  EXPECT_EQ(series["s"][0].get<double>(), 0.0);
  EXPECT_NEAR(series["s"][kSamples - 1].get<double>(), 0.8, 1e-12);  // metres, at rest
  EXPECT_NEAR(series["v"][kSamples - 1].get<double>(), 0.0, 1e-12);
  EXPECT_EQ(series["units"], json::parse(R"({"t_s": "s", "a": "m/s^2", "v": "m/s", "s": "m",
      "eta_linear_mm": "mm", "eta_nonlinear_mm": "mm"})"));
  // Every series member has its unit, and only those.
  EXPECT_EQ(series.size(), 7u);
  for (const auto& [name, values] : series.items()) {
    if (name != "units") {
      EXPECT_TRUE(series["units"].contains(name)) << name;
    }
  }

  // Without sample_period_s there is no series.
  const RunResult plain = simulate_file(thesis_request());
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_FALSE(parse_or_fail(plain.out).contains("series"));
}

// ---------------------------------------------------------------------------------------------

/// A plan request on the thesis format.
json plan_request(const std::string& strategy) {
  json body = json::parse(R"({
    "format": {"container": {"radius_mm": 48.5},
               "fill_height_mm": 82,
               "fluid": {"density_kg_m3": 1000, "viscosity_pa_s": 0.001},
               "stroke_mm": 800, "motion_time_s": 1.0}
  })");
  body["strategy"] = strategy;
  return body;
}

RunResult plan_file(const json& body) {
  const TempDir dir;
  write_file(dir / "request.json", body.dump());
  return run_slosh({"plan", "--request", (dir / "request.json").string()});
}

TEST(CliPlan, PredictionsAreThoseOfSimulatingThePlannedLaw) {
  const RunResult r = plan_file(plan_request("min_jerk_band"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const json out = parse_or_fail(r.out);
  ASSERT_EQ(out["status"], "optimal") << out["message"];
  // `slosh simulate` on the returned durations and on the uniform law gives the plan's numbers.
  json sim = thesis_request();
  sim["law"] = {{"type", "seven_segment"}, {"durations_s", out["durations_s"]}};
  const RunResult planned = simulate_file(sim);
  ASSERT_EQ(planned.exit_code, 0) << planned.err;
  const json p = parse_or_fail(planned.out);
  for (const char* model : {"linear", "nonlinear"}) {
    for (const char* peak : {"eta_motion_mm", "eta_rest_mm"}) {
      EXPECT_NEAR(out["prediction"][model][peak].get<double>(),
                  p["prediction"][model][peak].get<double>(), 1e-9)
          << model << " " << peak;
    }
  }
  const json b = parse_or_fail(simulate_file(thesis_request()).out);
  EXPECT_NEAR(out["baseline"]["nonlinear"]["eta_rest_mm"].get<double>(),
              b["prediction"]["nonlinear"]["eta_rest_mm"].get<double>(), 1e-9);
  EXPECT_LT(out["prediction"]["nonlinear"]["eta_rest_mm"].get<double>(),
            0.5 * b["prediction"]["nonlinear"]["eta_rest_mm"].get<double>());
}

TEST(CliPlan, StdinAndFileGiveTheSamePlan) {
  const json body = plan_request("multi_notch");
  json a = parse_or_fail(plan_file(body).out);
  const RunResult r = run_slosh({"plan", "--request", "-"}, body.dump());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  json b = parse_or_fail(r.out);
  a["solver"].erase("solve_ms");
  b["solver"].erase("solve_ms");
  EXPECT_EQ(a, b);  // deterministic: every number identical
}

TEST(CliPlan, InvalidStrategyExits2WithEnvelope) {
  const RunResult r = plan_file(plan_request("fastest"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  const json err = parse_or_fail(r.err);
  EXPECT_EQ(err["error"]["code"], "invalid_value");
  EXPECT_EQ(err["error"]["field"], "strategy");
  EXPECT_EQ(err["error"]["message"],
            "strategy = \"fastest\" is not allowed: one of \"baseline\", \"notch\", "
            "\"multi_notch\", \"min_jerk_band\", \"time_domain\", \"fir_chain\", \"shaper\", "
            "\"iir\", \"auto\"");
}

TEST(CliPlan, UnreachableConstraintIsAPlanWithStatusInfeasible) {
  json body = plan_request("time_domain");
  body["format"]["motion_time_s"] = 0.5;
  body["options"] = {{"eta_rest_max_mm", 0.1}};
  const RunResult r = plan_file(body);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = parse_or_fail(r.out);
  EXPECT_EQ(out["status"], "infeasible");
  const std::string message = out["message"];
  EXPECT_NE(message.find("no law found that meets eta_rest <= 0.1 mm in 0.5 s: the best found is"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("lengthen the motion or relax the limit"), std::string::npos) << message;
  double sum = 0.0;
  for (const auto& d : out["durations_s"]) sum += d.get<double>();
  EXPECT_NEAR(sum, 0.5, 1e-12);
}

// ---------------------------------------------------------------------------------------------

TEST(CliServe, HealthEndpointsAndGracefulSigterm) {
  const TempDir dir;
  const fs::path port_file = dir / "port";
  write_file(dir / "stdin", "");
  Child child(spawn({"serve", "--host", "127.0.0.1", "--port", "0", "--port-file",
                     port_file.string(), "--cache", (dir / "plans.sqlite").string()},
                    dir / "stdin", dir / "stdout", dir / "stderr"));
  ASSERT_GT(child.pid(), 0);
  const int port = wait_for_port(port_file, child, std::chrono::seconds(10));
  ASSERT_GT(port, 0) << "no port file; stderr:\n"
                     << read_file(dir / "stderr") << "\nstdout:\n"
                     << read_file(dir / "stdout");
  ASSERT_LE(port, 65535);

  httplib::Client client("127.0.0.1", port);
  client.set_connection_timeout(5, 0);
  client.set_read_timeout(5, 0);

  const httplib::Result health = client.Get("/healthz");
  ASSERT_TRUE(health) << httplib::to_string(health.error());
  EXPECT_EQ(health->status, 200);
  EXPECT_EQ(health->get_header_value("Content-Type"), "application/json");
  const json health_body = parse_or_fail(health->body);
  EXPECT_EQ(health_body["status"], json("ok"));
  ASSERT_TRUE(health_body.contains("version") && health_body["version"].is_string())
      << health->body;
  const RunResult version = run_slosh({"--version"});
  EXPECT_EQ("slosh " + health_body["version"].get<std::string>() + "\n", version.out);

  const httplib::Result ready = client.Get("/readyz");
  ASSERT_TRUE(ready) << httplib::to_string(ready.error());
  EXPECT_EQ(ready->status, 200);

  const httplib::Result missing = client.Get("/no/such/endpoint");
  ASSERT_TRUE(missing) << httplib::to_string(missing.error());
  EXPECT_EQ(missing->status, 404);

  ASSERT_EQ(::kill(child.pid(), SIGTERM), 0);
  const std::optional<int> code = child.wait_for(std::chrono::seconds(5));
  ASSERT_TRUE(code.has_value()) << "still running 5 s after SIGTERM";
  EXPECT_EQ(*code, 0) << read_file(dir / "stderr");
}

}  // namespace test_cli
}  // namespace slosh
