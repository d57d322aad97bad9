// Numbers in responses are not noise-tainted where an exact value exists. Every input a
// response echoes (the format in mm and s and its fluid, rest_time_s; simulate's law: its
// duration, stroke and given durations; the min-time limits) comes back as the request's own
// number, for seeded random formats of 'nice' numbers as a packaging engineer types them (48.5 mm,
// 82 mm, 0.73 s) — not 48.49999999999999 after mm -> m -> mm, nor 0.9999999999999998 as a sum of
// segments. The requests are JSON texts parsed as the service parses them; the check is bit
// equality with the request's number and, literally, no run of 9s or 0s in the echo's text.
// SLOSH_PROPERTY_FORMATS=N runs N formats instead of 40.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/simulate.hpp"
#include "support/random_format.hpp"

namespace slosh::api {
namespace test_clean_numbers {

using nlohmann::json;

constexpr std::uint64_t kSeed{19};
constexpr int kDefaultFormats{40};

int format_count() {
  return test::property_format_count(kDefaultFormats);
}

/// A 'nice' decimal: k / 10^decimals for a uniform k in [lo, hi], as text ("48.5", "82", "0.73").
std::string nice(std::mt19937_64& rng, long lo, long hi, int decimals) {
  const long k = std::uniform_int_distribution<long>(lo, hi)(rng);
  std::string digits = std::to_string(k);
  if (decimals == 0) return digits;
  if (digits.size() <= static_cast<std::size_t>(decimals)) {
    digits.insert(0, static_cast<std::size_t>(decimals) + 1 - digits.size(), '0');
  }
  digits.insert(digits.size() - static_cast<std::size_t>(decimals), ".");
  while (digits.back() == '0') digits.pop_back();
  if (digits.back() == '.') digits.pop_back();
  return digits;
}

/// Noise: a run of six 9s, or of six 0s before a last digit, in a number's shortest text.
bool noisy(const std::string& text) {
  static const std::regex noise("9{6,}|0{6,}[1-9]");
  return std::regex_search(text, noise);
}

/// The echo `echoed` of the request's number `given` at `path`: the same double, clean text.
void expect_echo(const json& echoed, const json& given, const std::string& path) {
  ASSERT_TRUE(echoed.is_number()) << path << " = " << echoed;
  EXPECT_EQ(echoed.get<double>(), given.get<double>())
      << path << ": " << dump_json(echoed) << " echoes " << dump_json(given);
  EXPECT_FALSE(noisy(dump_json(echoed))) << path << " = " << dump_json(echoed);
}

struct NiceFormat {
  json format;  ///< the request's format, parsed from text
  json rest;    ///< rest_time_s
};

NiceFormat random_format(std::mt19937_64& rng) {
  const std::string radius = nice(rng, 150, 600, 1);  // 15.0 .. 60.0 mm
  const long r10 = std::lround(10 * std::stod(radius));
  const std::string fill = nice(rng, r10 / 2, 5 * r10 / 2, 1);  // h/R 0.5 .. 2.5
  const long h10 = std::lround(10 * std::stod(fill));
  const std::string height = nice(rng, h10 + 100, h10 + 2000, 1);  // 10 .. 200 mm of free board
  const bool custom = std::uniform_int_distribution<int>(0, 1)(rng) == 1;
  const std::string fluid = custom ? R"({"density_kg_m3": )" + nice(rng, 8000, 14000, 1) +
                                         R"(, "viscosity_pa_s": )" + nice(rng, 5, 200, 4) + "}"
                                   : R"("water")";
  NiceFormat f;
  f.format = json::parse(R"({"container": {"radius_mm": )" + radius + R"(, "height_mm": )" +
                         height + "}, \"fill_height_mm\": " + fill + R"(, "fluid": )" + fluid +
                         R"(, "stroke_mm": )" + nice(rng, 1000, 8000, 1) +
                         R"(, "motion_time_s": )" + nice(rng, 60, 200, 2) + "}");
  f.rest = json::parse(nice(rng, 5, 20, 1));  // 0.5 .. 2 s
  return f;
}

void expect_format_echo(const json& echoed, const json& given, bool with_time) {
  expect_echo(echoed["container"]["radius_mm"], given["container"]["radius_mm"], "radius_mm");
  expect_echo(echoed["container"]["height_mm"], given["container"]["height_mm"], "height_mm");
  expect_echo(echoed["fill_height_mm"], given["fill_height_mm"], "fill_height_mm");
  expect_echo(echoed["stroke_mm"], given["stroke_mm"], "stroke_mm");
  if (with_time) expect_echo(echoed["motion_time_s"], given["motion_time_s"], "motion_time_s");
  if (given["fluid"].is_object()) {
    expect_echo(echoed["fluid"]["density_kg_m3"], given["fluid"]["density_kg_m3"], "density");
    expect_echo(echoed["fluid"]["viscosity_pa_s"], given["fluid"]["viscosity_pa_s"], "viscosity");
  }
}

/// How many of the format's lengths a plain metres * 1e3 echo would have tainted.
int naive_noise(const json& format) {
  int n = 0;
  for (const json* v : {&format["container"]["radius_mm"], &format["container"]["height_mm"],
                        &format["fill_height_mm"], &format["stroke_mm"]}) {
    const double mm = v->get<double>();
    n += (mm * 1e-3) * 1e3 != mm ? 1 : 0;
  }
  return n;
}

TEST(CleanNumbers, EchoedInputsOfPlansAreTheRequestsOwnNumbers) {
  std::mt19937_64 rng(kSeed);
  int naive = 0;
  for (int k = 0; k < format_count(); ++k) {
    const NiceFormat f = random_format(rng);
    SCOPED_TRACE(f.format.dump());
    naive += naive_noise(f.format);
    // The format echo does not depend on the strategy: the quick baseline, and an optimised law
    // every fifth format.
    json request{{"format", f.format},
                 {"strategy", k % 5 == 0 ? "multi_notch" : "baseline"},
                 {"options", {{"rest_time_s", f.rest}}}};
    const json plan = run_plan(parse_plan_request(request));
    expect_format_echo(plan["format"], f.format, true);
    expect_echo(plan["rest_time_s"], f.rest, "rest_time_s");
  }
  // The formats exercise lengths whose naive round trip is noisy (the test can fail).
  EXPECT_GT(naive, format_count() / 4);
}

TEST(CleanNumbers, EchoedInputsOfSimulationsAreTheRequestsOwnNumbers) {
  std::mt19937_64 rng(kSeed + 1);
  int rescaled = 0;
  for (int k = 0; k < format_count(); ++k) {
    const NiceFormat f = random_format(rng);
    SCOPED_TRACE(f.format.dump());
    const double T = f.format["motion_time_s"].get<double>();
    // Nice durations in ms summing to T in decimal: ramps of 50 ms or more.
    const long total = std::lround(T * 1000);
    std::vector<long> ms(7, 0);
    long used = 0;
    for (int i = 0; i < 7; i += 2) {
      ms[i] = std::uniform_int_distribution<long>(50, total / 5)(rng);
      used += ms[i];
    }
    ms[1] = std::uniform_int_distribution<long>(0, total - used)(rng);
    ms[5] = std::uniform_int_distribution<long>(0, total - used - ms[1])(rng);
    ms[3] = total - used - ms[1] - ms[5];
    json durations = json::array();
    double sum = 0.0;
    for (long m : ms) {
      durations.push_back(json::parse(nice(rng, m, m, 3)));
      sum += durations.back().get<double>();
    }
    rescaled += sum != T ? 1 : 0;
    for (const char* type :
         {"seven_segment", "seven_segment_uniform", "poly5", "modified_trapezoid", "cycloidal"}) {
      SCOPED_TRACE(type);
      json law{{"type", type}};
      if (std::string(type) == "seven_segment") law["durations_s"] = durations;
      const json request{{"format", f.format}, {"law", law}, {"rest_time_s", f.rest}};
      const json out = run_simulate(parse_simulate_request(request));
      expect_format_echo(out["format"], f.format, true);
      expect_echo(out["rest_time_s"], f.rest, "rest_time_s");
      expect_echo(out["law"]["duration_s"], f.format["motion_time_s"], "law.duration_s");
      expect_echo(out["law"]["stroke_mm"], f.format["stroke_mm"], "law.stroke_mm");
      if (law.contains("durations_s")) {
        for (std::size_t i = 0; i < 7; ++i) {
          expect_echo(out["law"]["durations_s"][i], durations[i],
                      "law.durations_s[" + std::to_string(i) + "]");
        }
      }
    }
  }
  // Durations whose double sum misses T by rounding (which a rescale by T / sum tainted).
  EXPECT_GT(rescaled, format_count() / 5);
}

TEST(CleanNumbers, EchoedInputsOfMinTimeAnswersAreTheRequestsOwnNumbers) {
  std::mt19937_64 rng(kSeed + 2);
  for (int k = 0; k < 4; ++k) {
    const NiceFormat f = random_format(rng);
    json format = f.format;
    const json t_max = format["motion_time_s"];
    format.erase("motion_time_s");
    const json eta_motion = json::parse(nice(rng, 50, 800, 1));
    const json eta_rest = json::parse(nice(rng, 1, 50, 1));
    const json body{{"format", format},
                    {"motion_time_max_s", t_max},
                    {"eta_motion_max_mm", eta_motion},
                    {"eta_rest_max_mm", eta_rest},
                    {"strategies", {"baseline"}},
                    {"options", {{"rest_time_s", f.rest}}}};
    SCOPED_TRACE(body.dump());
    const json answer = run_min_time(parse_min_time_request(body, 10.0));
    expect_format_echo(answer["format"], format, false);
    expect_echo(answer["motion_time_max_s"], t_max, "motion_time_max_s");
    expect_echo(answer["limits"]["eta_motion_max_mm"], eta_motion, "limits.eta_motion_max_mm");
    expect_echo(answer["limits"]["eta_rest_max_mm"], eta_rest, "limits.eta_rest_max_mm");
    expect_echo(answer["limits"]["rest_time_s"], f.rest, "limits.rest_time_s");
  }
}

// The issue's examples: T = 1 s echoes 1.0, not the sum of the segments; the thesis format's
// lengths as given; and lengths whose naive mm -> m -> mm round trip is noisy.
TEST(CleanNumbers, TheIssuesExamplesEchoAsGiven) {
  const json format = json::parse(R"({"container": {"radius_mm": 48.5, "height_mm": 51},
      "fill_height_mm": 35.5, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1})");
  for (const char* type : {"seven_segment_uniform", "poly5"}) {
    const json out =
        run_simulate(parse_simulate_request({{"format", format}, {"law", {{"type", type}}}}));
    EXPECT_EQ(dump_json(out["law"]["duration_s"]), "1.0") << type;
    EXPECT_EQ(dump_json(out["law"]["stroke_mm"]), "800.0") << type;
    EXPECT_EQ(dump_json(out["format"]["container"]["radius_mm"]), "48.5");
    EXPECT_EQ(dump_json(out["format"]["container"]["height_mm"]), "51.0");
    EXPECT_EQ(dump_json(out["format"]["fill_height_mm"]), "35.5");
  }
  // What a metres * 1e3 echo gave for these two, and a sum of T / 7 seven times.
  EXPECT_EQ(dump_json(json(51 * 1e-3 * 1e3)), "51.00000000000001");
  EXPECT_EQ(dump_json(json(35.5 * 1e-3 * 1e3)), "35.50000000000001");
  double sum = 0.0;
  for (int i = 0; i < 7; ++i) sum += 1.0 / 7.0;
  EXPECT_NE(sum, 1.0);
}

// mm_of inverts the parser's mm * 1e-3 for every double, and finds the nice decimals.
TEST(CleanNumbers, MillimetresOfMetresAreTheShortestExactDecimal) {
  std::mt19937_64 rng(kSeed + 3);
  for (int i = 0; i < 100000; ++i) {
    const int decimals = std::uniform_int_distribution<int>(0, 4)(rng);
    const json given = json::parse(nice(rng, 1, 10000000, decimals));
    const double mm = given.get<double>();
    ASSERT_EQ(mm_of(mm * 1e-3), mm) << dump_json(given);
    ASSERT_EQ(mm_of(-mm * 1e-3), -mm) << dump_json(given);
  }
  // Any length the parser can produce (any double of mm, read as mm * 1e-3) is recovered exactly:
  // read again, the echo gives the same metres.
  std::uniform_real_distribution<double> any(1e-6, 1e6);
  for (int i = 0; i < 100000; ++i) {
    const double metres = any(rng) * 1e-3;
    const double mm = mm_of(metres);
    ASSERT_EQ(mm * 1e-3, metres) << metres;
    ASSERT_LE(std::abs(mm - metres * 1e3), 4 * std::numeric_limits<double>::epsilon() * mm);
  }
  // A computed length that no mm value converts to keeps its product.
  std::uniform_real_distribution<double> computed(1e-9, 1e3);
  for (int i = 0; i < 10000; ++i) {
    const double metres = computed(rng);
    const double mm = mm_of(metres);
    ASSERT_TRUE(mm * 1e-3 == metres || mm == metres * 1e3) << metres;
  }
  EXPECT_EQ(mm_of(0.0), 0.0);
  EXPECT_TRUE(std::isnan(mm_of(std::nan(""))));
  EXPECT_EQ(mm_of(std::numeric_limits<double>::infinity()),
            std::numeric_limits<double>::infinity());
}

}  // namespace test_clean_numbers
}  // namespace slosh::api
