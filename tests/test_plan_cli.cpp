// `slosh plan` with format flags (a quick look without a request file), its text
// summary, `slosh fluids`, the help text, and warnings that name the model of the height they
// quote. The CLI tests run the real binary; the numbers are checked against the JSON plan of the
// equivalent request.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/format_json.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"
#include "support/process.hpp"

namespace slosh {
namespace test_plan_cli {

using nlohmann::json;
using test::run_slosh;
using test::RunResult;

const std::vector<std::string> kThesisFlags{
    "plan", "--radius", "48.5", "--fill",   "82",  "--fluid",    "water",      "--stroke",
    "800",  "--time",   "0.9",  "--height", "150", "--strategy", "multi_notch"};

json thesis_request() {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 0.9},
      "strategy": "multi_notch"})");
}

std::string fixed(double v, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

TEST(PlanCli, FormatFlagsPrintTheTextSummaryOfTheEquivalentRequest) {
  const RunResult text = run_slosh(kThesisFlags);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  const RunResult full = run_slosh({"plan", "--request", "-"}, thesis_request().dump());
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const json plan = json::parse(full.out);
  const std::string& t = text.out;
  EXPECT_NE(t.find("status      " + plan["status"].get<std::string>() + "\n"), std::string::npos);
  EXPECT_NE(t.find("key         " + plan["key"].get<std::string>()), std::string::npos) << t;
  std::string durations = "law         seven_segment, durations [s]:";
  for (const json& d : plan["durations_s"]) durations += " " + fixed(d.get<double>(), 4);
  EXPECT_NE(t.find(durations + "\n"), std::string::npos) << t;
  const json& p = plan["prediction"];
  const json& b = plan["baseline"];
  auto pair = [](const json& block, const char* figure, int digits) {
    return fixed(block["nonlinear"][figure].get<double>(), digits) + " / " +
           fixed(block["linear"][figure].get<double>(), digits) + " mm";
  };
  EXPECT_NE(t.find("  motion    " + pair(p, "eta_motion_mm", 1)), std::string::npos) << t;
  EXPECT_NE(t.find("(" + pair(b, "eta_motion_mm", 1) + ")"), std::string::npos) << t;
  EXPECT_NE(t.find("  rest      " + pair(p, "eta_rest_mm", 2)), std::string::npos) << t;
  EXPECT_NE(t.find("motion " + fixed(-plan["reduction_pct"]["motion"].get<double>(), 1) + " %"),
            std::string::npos)
      << t;
  EXPECT_NE(t.find("warnings    none\n"), std::string::npos) << t;
  // The text is a summary, not the JSON.
  EXPECT_LT(t.size(), 2000u);
}

TEST(PlanCli, FormatFlagsWithFormatJsonAreThePlanOfTheRequest) {
  const RunResult flags = run_slosh(with(kThesisFlags, {"--format", "json"}));
  const RunResult request = run_slosh({"plan", "--request", "-"}, thesis_request().dump());
  ASSERT_EQ(flags.exit_code, 0) << flags.err;
  json a = json::parse(flags.out), b = json::parse(request.out);
  EXPECT_EQ(a["key"], b["key"]);
  EXPECT_EQ(a["durations_s"], b["durations_s"]);
  EXPECT_EQ(a["prediction"], b["prediction"]);
  // The default strategy of the flags is auto; --request without --format stays JSON.
  const RunResult automatic =
      run_slosh({"plan", "--radius", "48.5", "--fill", "82", "--fluid", "water", "--stroke", "800",
                 "--time", "1", "--format", "json", "--view", "compact"});
  ASSERT_EQ(automatic.exit_code, 0) << automatic.err;
  EXPECT_EQ(json::parse(automatic.out)["strategy"], "auto");
  EXPECT_EQ(request.out.front(), '{');
}

TEST(PlanCli, RequestFileGivesTheTextSummaryWithFormatText) {
  const RunResult r =
      run_slosh({"plan", "--request", "-", "--format", "text"}, thesis_request().dump());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("plan        multi_notch on R 48.5 mm, h 82.0 mm, water, 800.0 mm in "
                        "0.900 s\nstatus      ",
                        0),
            0u)
      << r.out;
}

TEST(PlanCli, ConflictingAndMissingFlagsExit2WithExactTexts) {
  struct Case {
    std::vector<std::string> args;
    std::string err;
  };
  const std::vector<Case> cases{
      {{"plan", "--request", "x.json", "--radius", "48.5", "--strategy", "notch"},
       "slosh plan: --request cannot be combined with the format flags (--radius, --strategy): "
       "give the format either as a request file or as flags\n"},
      {{"plan", "--radius", "48.5", "--fill", "82"},
       "slosh plan: the format flags need --radius, --fill, --fluid (or --density and "
       "--viscosity), --stroke and --time: missing --fluid, --stroke, --time\n"},
      {{"plan", "--radius", "48.5", "--fill", "82", "--density", "1000", "--stroke", "800",
        "--time", "1"},
       "slosh plan: the format flags need --radius, --fill, --fluid (or --density and "
       "--viscosity), --stroke and --time: missing --viscosity\n"},
      {{"plan", "--radius", "48.5", "--fill", "82", "--fluid", "water", "--viscosity", "0.001",
        "--stroke", "800", "--time", "1"},
       "slosh plan: --fluid cannot be combined with --density/--viscosity: name a catalogue "
       "fluid (slosh fluids) or give a custom one\n"},
      {{"plan", "--radius", "48.5", "--fill", "82", "--fluid", "water", "--stroke", "800", "--time",
        "1", "--view", "compact"},
       "slosh plan: --view applies to the JSON output: add --format json\n"},
      {{"plan", "--radius", "-3", "--fill", "82", "--fluid", "water", "--stroke", "800", "--time",
        "1"},
       "slosh plan: format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm (flag "
       "--radius)\n"},
      {{"plan", "--radius", "48.5", "--fill", "82", "--fluid", "water", "--stroke", "800", "--time",
        "1", "--strategy", "fast"},
       ""},  // the parser's message, checked below to name --strategy
  };
  for (const Case& c : cases) {
    const RunResult r = run_slosh(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args[2];
    EXPECT_TRUE(r.out.empty()) << r.out;
    if (!c.err.empty()) {
      EXPECT_EQ(r.err, c.err);
    } else {
      EXPECT_NE(r.err.find("strategy = \"fast\""), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("(flag --strategy)\n"), std::string::npos) << r.err;
    }
  }
}

// The uniform law against itself changes nothing: "0.0 %", never "-0.0 %".
TEST(PlanCli, BaselinesChangeIsZeroWithoutASign) {
  const RunResult r = run_slosh({"plan", "--radius", "48.5", "--fill", "82", "--fluid", "water",
                                 "--stroke", "800", "--time", "1", "--strategy", "baseline"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("change vs uniform law: motion 0.0 % / 0.0 %, rest 0.0 % / 0.0 %"),
            std::string::npos)
      << r.out;
}

TEST(PlanCli, HelpSaysFilteringStrategiesReturnGeneralLaws) {
  const RunResult r = run_slosh({"plan", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.find("Plan the 7-segment law"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("general law"), std::string::npos) << r.out;
  for (const char* flag : {"--radius", "--fill", "--height", "--fluid", "--density", "--viscosity",
                           "--stroke", "--time", "--strategy", "--format"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  }
}

TEST(FluidsCli, ListsTheCatalogueAsTextAndAsTheApiJson) {
  const RunResult j = run_slosh({"fluids", "--format", "json"});
  ASSERT_EQ(j.exit_code, 0);
  EXPECT_EQ(json::parse(j.out), api::fluids_json());
  const RunResult t = run_slosh({"fluids"});
  ASSERT_EQ(t.exit_code, 0);
  const json fluids = api::fluids_json()["fluids"];
  ASSERT_EQ(static_cast<std::size_t>(std::count(t.out.begin(), t.out.end(), '\n')),
            fluids.size() + 1);
  for (const json& f : fluids) {
    const std::regex row("\n" + f["name"].get<std::string>() + " +" +
                         fixed(f["density_kg_m3"].get<double>(), 1) + " +");
    EXPECT_TRUE(std::regex_search(t.out, row)) << f["name"];
    EXPECT_NE(t.out.find(f["source"].get<std::string>()), std::string::npos);
  }
}

// Every warning quoting a predicted height names the model whose figure it quotes, and the
// figure is that model's prediction (and the other quoted one the other model's).
void expect_spill_warning_matches(const json& response) {
  const std::regex spill(
      "predicted sloshing height during the motion ([0-9.]+) mm \\((linear|nonlinear) model; "
      "(linear|nonlinear) model ([0-9.]+) mm\\) exceeds the free board ([0-9.]+) mm");
  int found = 0;
  for (const json& w : response["warnings"]) {
    const std::string text = w;
    std::smatch m;
    if (text.find("predicted sloshing height") == std::string::npos) continue;
    ASSERT_TRUE(std::regex_search(text, m, spill)) << text;
    ++found;
    const json& p = response["prediction"];
    EXPECT_NE(m[2].str(), m[3].str());
    const double quoted = p[m[2].str()]["eta_motion_mm"];
    const double other = p[m[3].str()]["eta_motion_mm"];
    EXPECT_EQ(m[1].str(), fixed(quoted, 1)) << text;
    EXPECT_EQ(m[4].str(), fixed(other, 1)) << text;
    EXPECT_GE(quoted, other) << text;
    const json& f = response["format"];
    const double board =
        f["container"]["height_mm"].get<double>() - f["fill_height_mm"].get<double>();
    EXPECT_EQ(m[5].str(), fixed(board, 1));
    EXPECT_GT(quoted, board);
  }
  EXPECT_EQ(found, 1) << response["warnings"].dump();
}

TEST(WarningModels, SpillWarningsQuoteTheModelOfTheirFigure) {
  // The four acceptance formats on a container whose free board the baseline overflows.
  const std::pair<double, double> formats[] = {{800, 1.0}, {800, 0.9}, {800, 0.8}, {500, 0.7}};
  for (const auto& [stroke, T] : formats) {
    json request = thesis_request();
    request["format"]["container"]["height_mm"] = 100;
    request["format"]["stroke_mm"] = stroke;
    request["format"]["motion_time_s"] = T;
    request["strategy"] = "baseline";
    SCOPED_TRACE(std::to_string(stroke) + " mm in " + std::to_string(T) + " s");
    expect_spill_warning_matches(api::run_plan(api::parse_plan_request(request)));
    json simulate = request;
    simulate.erase("strategy");
    simulate["law"] = {{"type", "poly5"}};
    expect_spill_warning_matches(api::run_simulate(api::parse_simulate_request(simulate)));
  }
  // Through the binary too, on the case (800 mm in 0.9 s, 38 mm of free board).
  const RunResult r =
      run_slosh({"plan", "--radius", "48.5", "--fill", "82", "--fluid", "water", "--stroke", "800",
                 "--time", "0.9", "--height", "120", "--strategy", "baseline"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("warning     predicted sloshing height during the motion 77.3 mm (linear "
                       "model; nonlinear model 58.2 mm) exceeds the free board 38.0 mm"),
            std::string::npos)
      << r.out;
}

}  // namespace test_plan_cli
}  // namespace slosh
