// The JSON validation layer of the API: every rejection names the field path, the value and the
// allowed range, carries the right error code and HTTP status, and a valid thesis request becomes
// the right SI values. Expected messages are written out literally (derived from api/src).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/fields.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::api {
namespace test_validation {

using nlohmann::json;

constexpr const char* kCatalogue =
    "water, ethanol, isopropanol, glycerol_water_50, milk, olive_oil, sunflower_oil, light_syrup";
constexpr const char* kLawTypes =
    "\"seven_segment\", \"seven_segment_uniform\", \"poly5\", \"modified_trapezoid\", "
    "\"cycloidal\", \"piecewise_linear\", \"piecewise\"";

/// The thesis format (R = 48.5 mm, h = 82 mm, water 1000 kg/m^3 and 1 mPa s, 800 mm in 1 s).
json base_request() {
  return json::parse(R"({
    "format": {"container": {"radius_mm": 48.5, "height_mm": 150},
               "fill_height_mm": 82,
               "fluid": {"density_kg_m3": 1000, "viscosity_pa_s": 0.001},
               "stroke_mm": 800, "motion_time_s": 1.0},
    "law": {"type": "seven_segment_uniform"}
  })");
}

/// Valid explicit 7-segment durations for T = 1 s.
json valid_durations() {
  return json::array({0.1, 0.15, 0.1, 0.3, 0.1, 0.15, 0.1});
}

/// The base request with the value at JSON pointer `pointer` replaced (or added).
json with(const std::string& pointer, const json& value) {
  json body = base_request();
  body[json::json_pointer(pointer)] = value;
  return body;
}

/// The base request with the member at `pointer` removed.
json without(const std::string& pointer) {
  json body = base_request();
  const json::json_pointer ptr(pointer);
  body[ptr.parent_pointer()].erase(ptr.back());
  return body;
}

/// The base request with an explicit seven_segment law.
json seven_segment_request(const json& durations) {
  json body = base_request();
  body["law"] = {{"type", "seven_segment"}, {"durations_s", durations}};
  return body;
}

/// The ApiError thrown by parse_simulate_request, if any.
std::optional<ApiError> rejection(const json& body) {
  try {
    (void)parse_simulate_request(body);
  } catch (const ApiError& e) {
    return e;
  }
  return std::nullopt;
}

/// Checks a 422 invalid_value rejection with the exact field path and message.
::testing::AssertionResult Rejects(const json& body, const std::string& field,
                                   const std::string& message) {
  const std::optional<ApiError> e = rejection(body);
  if (!e) return ::testing::AssertionFailure() << "accepted: " << body.dump();
  ::testing::AssertionResult result = ::testing::AssertionSuccess();
  if (e->code() != ErrorCode::kInvalidValue) {
    return ::testing::AssertionFailure()
           << "code " << to_string(e->code()) << ", message " << e->what();
  }
  if (e->status() != 422) return ::testing::AssertionFailure() << "status " << e->status();
  if (e->field() != field) {
    return ::testing::AssertionFailure()
           << "field\n  actual:   " << e->field() << "\n  expected: " << field;
  }
  if (std::string(e->what()) != message) {
    return ::testing::AssertionFailure()
           << "message\n  actual:   " << e->what() << "\n  expected: " << message;
  }
  return result;
}

/// Parses a body that must be accepted.
SimulateRequest accepted(const json& body) {
  try {
    return parse_simulate_request(body);
  } catch (const ApiError& e) {
    ADD_FAILURE() << "rejected " << body.dump() << ": " << e.what();
  }
  return {};
}

::testing::AssertionResult Accepts(const json& body) {
  const std::optional<ApiError> e = rejection(body);
  if (e) return ::testing::AssertionFailure() << "rejected: " << e->what();
  return ::testing::AssertionSuccess();
}

// ---------------------------------------------------------------------------------------------
// Valid requests.

TEST(ValidationValid, ThesisRequestParsesIntoSiUnits) {
  const SimulateRequest r = accepted(base_request());
  EXPECT_DOUBLE_EQ(r.format.container.radius, 0.0485);
  ASSERT_TRUE(r.format.container.height.has_value());
  EXPECT_DOUBLE_EQ(*r.format.container.height, 0.150);
  EXPECT_DOUBLE_EQ(r.format.fill_height, 0.082);
  EXPECT_EQ(r.format.fluid.name, "custom");
  EXPECT_EQ(r.format.fluid.density, 1000.0);
  EXPECT_EQ(r.format.fluid.viscosity, 0.001);
  EXPECT_DOUBLE_EQ(r.format.stroke, 0.8);
  EXPECT_EQ(r.format.motion_time, 1.0);
  EXPECT_EQ(r.law_type, LawType::kSevenSegmentUniform);
  EXPECT_FALSE(r.durations.has_value());
  EXPECT_EQ(r.options.model.modes, 3);
  EXPECT_EQ(r.options.model.damping, DampingCorrelation::kThesis);
  EXPECT_EQ(r.options.model.alpha, 0.58);
  EXPECT_EQ(r.options.rest_time, 1.0);
  EXPECT_FALSE(r.options.sample_period.has_value());
  EXPECT_EQ(r.min_ramp, 0.05);
}

TEST(ValidationValid, ContainerHeightIsOptional) {
  const SimulateRequest r = accepted(without("/format/container/height_mm"));
  EXPECT_FALSE(r.format.container.height.has_value());
  const SimulateRequest n = accepted(with("/format/container/height_mm", nullptr));
  EXPECT_FALSE(n.format.container.height.has_value());
}

TEST(ValidationValid, CatalogueWaterResolves) {
  const SimulateRequest r = accepted(with("/format/fluid", "water"));
  EXPECT_EQ(r.format.fluid.name, "water");
  EXPECT_EQ(r.format.fluid.density, 998.2);
  EXPECT_EQ(r.format.fluid.viscosity, 1.0016e-3);
  EXPECT_FALSE(r.format.fluid.source.empty());
}

TEST(ValidationValid, EveryCatalogueFluidResolves) {
  for (const char* name : {"water", "ethanol", "isopropanol", "glycerol_water_50", "milk",
                           "olive_oil", "sunflower_oil", "light_syrup"}) {
    const SimulateRequest r = accepted(with("/format/fluid", name));
    EXPECT_EQ(r.format.fluid.name, name);
  }
}

TEST(ValidationValid, ExplicitOptionsAreApplied) {
  json body = seven_segment_request(valid_durations());
  body["options"] = {
      {"modes", 5}, {"alpha", 0.5}, {"damping", {{"zeta", 0.01}}}, {"min_ramp_s", 0.06}};
  body["rest_time_s"] = 2.5;
  body["sample_period_s"] = 0.01;
  const SimulateRequest r = accepted(body);
  EXPECT_EQ(r.options.model.modes, 5);
  EXPECT_EQ(r.options.model.alpha, 0.5);
  EXPECT_EQ(r.options.model.damping, DampingCorrelation::kExplicit);
  EXPECT_EQ(r.options.model.explicit_zeta, 0.01);
  EXPECT_EQ(r.min_ramp, 0.06);
  EXPECT_EQ(r.options.rest_time, 2.5);
  ASSERT_TRUE(r.options.sample_period.has_value());
  EXPECT_EQ(*r.options.sample_period, 0.01);
  EXPECT_EQ(r.law_type, LawType::kSevenSegment);
  ASSERT_TRUE(r.durations.has_value());
  const double expected[] = {0.1, 0.15, 0.1, 0.3, 0.1, 0.15, 0.1};
  for (std::size_t i = 0; i < 7; ++i) EXPECT_NEAR((*r.durations)[i], expected[i], 1e-15) << i;
}

TEST(ValidationValid, DampingNamesMapToCorrelations) {
  const std::pair<const char*, DampingCorrelation> cases[] = {
      {"thesis", DampingCorrelation::kThesis},
      {"paper", DampingCorrelation::kPaper},
      {"eq227", DampingCorrelation::kEq227},
      {"eq228", DampingCorrelation::kEq228},
  };
  for (const auto& [name, correlation] : cases) {
    const SimulateRequest r = accepted(with("/options", {{"damping", name}}));
    EXPECT_EQ(r.options.model.damping, correlation) << name;
  }
}

TEST(ValidationValid, LawTypesMapToEnum) {
  const std::pair<const char*, LawType> cases[] = {
      {"seven_segment_uniform", LawType::kSevenSegmentUniform},
      {"poly5", LawType::kPoly5},
      {"modified_trapezoid", LawType::kModifiedTrapezoid},
      {"cycloidal", LawType::kCycloidal},
  };
  for (const auto& [name, type] : cases) {
    const SimulateRequest r = accepted(with("/law/type", name));
    EXPECT_EQ(r.law_type, type) << name;
    EXPECT_FALSE(r.durations.has_value()) << name;
  }
}

TEST(ValidationValid, DurationsWithinToleranceAreRescaledToTheMotionTime) {
  const SimulateRequest r =
      accepted(seven_segment_request(json::array({0.1, 0.15, 0.1, 0.3, 0.1, 0.15, 0.1000005})));
  ASSERT_TRUE(r.durations.has_value());
  double sum = 0.0;
  for (double d : *r.durations) sum += d;
  EXPECT_NEAR(sum, 1.0, 1e-14);
  EXPECT_NEAR((*r.durations)[6], 0.1000005 / 1.0000005, 1e-15);
}

TEST(ValidationValid, NullOptionalMembersTakeTheirDefaults) {
  json body = base_request();
  body["options"] = {
      {"modes", nullptr}, {"alpha", nullptr}, {"damping", nullptr}, {"min_ramp_s", nullptr}};
  body["rest_time_s"] = nullptr;
  body["sample_period_s"] = nullptr;
  const SimulateRequest r = accepted(body);
  EXPECT_EQ(r.options.model.modes, 3);
  EXPECT_EQ(r.options.model.alpha, 0.58);
  EXPECT_EQ(r.options.model.damping, DampingCorrelation::kThesis);
  EXPECT_EQ(r.min_ramp, 0.05);
  EXPECT_EQ(r.options.rest_time, 1.0);
  EXPECT_FALSE(r.options.sample_period.has_value());
}

// Closed bounds accept the exact limit, open bounds reject it (rejections are below).
TEST(ValidationValid, ClosedBoundsAcceptTheExactLimits) {
  EXPECT_TRUE(Accepts(with("/format/container/radius_mm", 1)));
  EXPECT_TRUE(Accepts(with("/format/container/radius_mm", 2000)));
  EXPECT_TRUE(Accepts(with("/format/container/height_mm", 10000)));
  EXPECT_TRUE(Accepts(with("/format/container/height_mm", 82.001)));
  json deepest = without("/format/container/height_mm");
  deepest["format"]["fill_height_mm"] = 5000;
  EXPECT_TRUE(Accepts(deepest));
  EXPECT_TRUE(Accepts(with("/format/stroke_mm", 100000)));
  EXPECT_TRUE(Accepts(with("/format/motion_time_s", 0.05)));
  EXPECT_TRUE(Accepts(with("/format/motion_time_s", 60)));
  EXPECT_TRUE(Accepts(with("/format/fluid/density_kg_m3", 100)));
  EXPECT_TRUE(Accepts(with("/format/fluid/density_kg_m3", 20000)));
  EXPECT_TRUE(Accepts(with("/format/fluid/viscosity_pa_s", 10)));
  EXPECT_TRUE(Accepts(with("/options", {{"damping", {{"zeta", 0}}}})));
  EXPECT_TRUE(Accepts(with("/options", {{"damping", {{"zeta", 0.4999}}}})));
  EXPECT_TRUE(Accepts(with("/options", {{"alpha", 0}})));
  EXPECT_TRUE(Accepts(with("/options", {{"alpha", 2}})));
  EXPECT_TRUE(Accepts(with("/options", {{"modes", 1}})));
  EXPECT_TRUE(Accepts(with("/options", {{"modes", 5}})));
  EXPECT_TRUE(Accepts(with("/options", {{"modes", 3.0}})));
  EXPECT_TRUE(Accepts(with("/options", {{"min_ramp_s", 0.001}})));
  EXPECT_TRUE(Accepts(with("/options", {{"min_ramp_s", 0.25}})));  // T / 4
  EXPECT_TRUE(Accepts(with("/rest_time_s", 0)));
  EXPECT_TRUE(Accepts(with("/rest_time_s", 60)));
  EXPECT_TRUE(Accepts(with("/sample_period_s", 1e-4)));
  EXPECT_TRUE(Accepts(with("/sample_period_s", 1)));
  EXPECT_TRUE(Accepts(seven_segment_request(json::array({0.05, 0.2, 0.05, 0.4, 0.05, 0.2, 0.05}))));
  EXPECT_TRUE(Accepts(seven_segment_request(json::array({0.25, 0, 0.25, 0, 0.25, 0, 0.25}))));
}

TEST(ValidationValid, NullOptionsTakeTheDefaults) {
  json body = seven_segment_request(valid_durations());
  body["options"] = nullptr;
  const SimulateRequest r = accepted(body);
  EXPECT_EQ(r.options.model.modes, 3);
  EXPECT_EQ(r.options.model.alpha, 0.58);
  EXPECT_EQ(r.options.model.damping, DampingCorrelation::kThesis);
  EXPECT_EQ(r.min_ramp, 0.05);
  // The default min_ramp_s still applies to the ramps.
  json short_ramp = seven_segment_request(json::array({0.04, 0.16, 0.1, 0.3, 0.1, 0.2, 0.1}));
  short_ramp["options"] = nullptr;
  EXPECT_TRUE(Rejects(short_ramp, "law.durations_s[0]",
                      "law.durations_s[0] = 0.04 is out of range: allowed 0.05 to 1 s (segment 1 "
                      "is a jerk ramp: >= options.min_ramp_s)"));
}

// Samples at 0, dt, ..., T + rest (both ends): floor((T + rest) / dt) + 1 <= 50000.
TEST(ValidationValid, SampleCountAtTheLimitIsAccepted) {
  // Exactly representable: dt = 2^-10 s, T + rest = 49999 dt -> 50000 samples.
  json exact = with("/format/motion_time_s", 10);
  exact["sample_period_s"] = 1.0 / 1024.0;
  exact["rest_time_s"] = (49999.0 - 10240.0) / 1024.0;  // 38.8271484375 s
  EXPECT_TRUE(Accepts(exact));
  // Decimal: 10 s + 39.999 s at 1 ms is 49999 periods (the quotient is not exact in binary).
  json decimal = with("/format/motion_time_s", 10);
  decimal["rest_time_s"] = 39.999;
  decimal["sample_period_s"] = 1e-3;
  EXPECT_TRUE(Accepts(decimal));
}

TEST(ValidationValid, SampleCountAtTheLimitIsWhatSimulateReturns) {
  json body = with("/format/motion_time_s", 10);
  body["sample_period_s"] = 1.0 / 1024.0;
  body["rest_time_s"] = (49999.0 - 10240.0) / 1024.0;
  ASSERT_TRUE(Accepts(body));
  const json out = run_simulate(parse_simulate_request(body));
  ASSERT_TRUE(out.contains("series"));
  EXPECT_EQ(out["series"]["t_s"].size(), 50000u);
  EXPECT_DOUBLE_EQ(out["series"]["t_s"].back().get<double>(), 49999.0 / 1024.0);
}

TEST(ValidationValid, CustomFluidNameIsEchoed) {
  const SimulateRequest r = accepted(with("/format/fluid/name", "honey 1:1"));
  EXPECT_EQ(r.format.fluid.name, "honey 1:1");
  EXPECT_EQ(r.format.fluid.density, 1000.0);
  EXPECT_EQ(format_json(r.format)["fluid"]["name"], json("honey 1:1"));
  // Without a name (or with null) the fluid is "custom".
  const SimulateRequest plain = accepted(base_request());
  EXPECT_EQ(format_json(plain.format)["fluid"]["name"], json("custom"));
  EXPECT_EQ(accepted(with("/format/fluid/name", nullptr)).format.fluid.name, "custom");
  // 1 and 64 characters are the limits.
  EXPECT_EQ(accepted(with("/format/fluid/name", "x")).format.fluid.name, "x");
  const std::string longest(64, 'n');
  EXPECT_EQ(accepted(with("/format/fluid/name", longest)).format.fluid.name, longest);
  // Non-ASCII text is kept intact (32 x U+00E9 = 64 bytes).
  std::string accents;
  for (int i = 0; i < 32; ++i) accents += "\xc3\xa9";
  EXPECT_EQ(accepted(with("/format/fluid/name", accents)).format.fluid.name, accents);
}

// ---------------------------------------------------------------------------------------------
// Body level: malformed JSON (400) and non-object bodies (422).

TEST(ValidationBody, MalformedJsonIs400) {
  try {
    (void)parse_json_body("{");
    FAIL() << "accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.code(), ErrorCode::kMalformedJson);
    EXPECT_EQ(e.status(), 400);
    EXPECT_EQ(e.field(), "");
    EXPECT_STREQ(e.what(),
                 "the body is not valid JSON: parse error at "
                 "line 1, column 2: syntax error while parsing object key - unexpected end of "
                 "input; expected string literal");
    const json envelope = error_envelope(e);
    EXPECT_EQ(envelope["error"]["code"], json("malformed_json"));
    EXPECT_TRUE(envelope["error"]["field"].is_null());
  }
}

TEST(ValidationBody, OtherMalformedBodiesAre400) {
  for (const char* text :
       {"", "   ", "{\"format\": }", "[1, 2", "nul", "{'a': 1}", "{\"a\": 1} trailing"}) {
    try {
      (void)parse_json_body(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ApiError& e) {
      EXPECT_EQ(e.code(), ErrorCode::kMalformedJson) << text;
      EXPECT_EQ(e.status(), 400) << text;
      EXPECT_EQ(std::string(e.what()).rfind("the body is not valid JSON: ", 0), 0u) << e.what();
    }
  }
}

TEST(ValidationBody, WellFormedJsonParses) {
  const json parsed = parse_json_body(base_request().dump());
  EXPECT_EQ(parsed, base_request());
}

// A number that overflows a double (nlohmann out_of_range 406, not a parse_error) is a malformed
// body too.
TEST(ValidationBody, NumberOverflowIsMalformedJson) {
  for (const char* number : {"1e400", "-1e400"}) {
    try {
      (void)parse_json_body(std::string("{\"rest_time_s\": ") + number + "}");
      ADD_FAILURE() << "accepted " << number;
    } catch (const ApiError& e) {
      EXPECT_EQ(e.code(), ErrorCode::kMalformedJson);
      EXPECT_EQ(e.status(), 400);
      EXPECT_EQ(e.field(), "");
      EXPECT_EQ(std::string(e.what()), std::string("the body is not valid JSON: number "
                                                   "overflow parsing '") +
                                           number + "'");
    }
  }
}

// Invalid UTF-8 in the body is malformed; the parser's message quotes the raw byte, and the
// envelope still serialises with dump_json (the byte becomes U+FFFD).
TEST(ValidationBody, InvalidUtf8IsMalformedJsonAndTheEnvelopeSerialises) {
  try {
    (void)parse_json_body("{\"format\": \"\xff\"}");
    FAIL() << "accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.code(), ErrorCode::kMalformedJson);
    const std::string text = dump_json(error_envelope(e));
    EXPECT_EQ(text.rfind("{\"error\":{\"code\":\"malformed_json\"", 0), 0u) << text;
    EXPECT_EQ(text.find('\xff'), std::string::npos);
    const json back = json::parse(text);  // valid UTF-8
    EXPECT_EQ(back["error"]["message"].get<std::string>().rfind("the body is not valid JSON: ", 0),
              0u);
  }
}

TEST(ValidationBody, NonObjectBodiesAre422) {
  EXPECT_TRUE(Rejects(json::array({1, 2}), "", "the request must be a JSON object, got [1,2]"));
  EXPECT_TRUE(Rejects(parse_json_body("null"), "", "the request must be a JSON object, got null"));
  EXPECT_TRUE(
      Rejects(parse_json_body("\"text\""), "", "the request must be a JSON object, got \"text\""));
  EXPECT_TRUE(Rejects(parse_json_body("42"), "", "the request must be a JSON object, got 42"));
}

TEST(ValidationBody, UnknownTopLevelField) {
  json body = base_request();
  body["sample_period"] = 0.01;
  EXPECT_TRUE(Rejects(body, "sample_period",
                      "sample_period is not a known field; allowed here: format, law, "
                      "rest_time_s, sample_period_s, options"));
}

TEST(ValidationBody, FormatRequiredAndObject) {
  EXPECT_TRUE(Rejects(without("/format"), "format",
                      "format is required: {\"container\", \"fill_height_mm\", \"fluid\", "
                      "\"stroke_mm\", \"motion_time_s\"}"));
  EXPECT_TRUE(Rejects(with("/format", 3), "format", "format must be a JSON object, got 3"));
  EXPECT_TRUE(
      Rejects(with("/format", nullptr), "format", "format must be a JSON object, got null"));
}

// ---------------------------------------------------------------------------------------------
// format

TEST(ValidationFormat, UnknownFieldTypo) {
  json body = base_request();
  body["format"]["fill_height"] = 82;
  EXPECT_TRUE(Rejects(body, "format.fill_height",
                      "format.fill_height is not a known field; allowed here: container, "
                      "fill_height_mm, fluid, stroke_mm, motion_time_s"));
}

TEST(ValidationFormat, Container) {
  EXPECT_TRUE(Rejects(without("/format/container"), "format.container",
                      "format.container is required: {\"radius_mm\"} and optionally "
                      "\"height_mm\""));
  EXPECT_TRUE(Rejects(with("/format/container", nullptr), "format.container",
                      "format.container must be a JSON object, got null"));
  EXPECT_TRUE(Rejects(with("/format/container", "big"), "format.container",
                      "format.container must be a JSON object, got \"big\""));
  EXPECT_TRUE(Rejects(with("/format/container", json::array({48.5, 150})), "format.container",
                      "format.container must be a JSON object, got [48.5,150]"));
}

TEST(ValidationFormat, RadiusTypoIsAnUnknownField) {
  EXPECT_TRUE(Rejects(with("/format/container", {{"radius", 48.5}, {"height_mm", 150}}),
                      "format.container.radius",
                      "format.container.radius is not a known field; allowed here: radius_mm, "
                      "height_mm"));
}

TEST(ValidationFormat, Radius) {
  const std::string f = "format.container.radius_mm";
  EXPECT_TRUE(Rejects(without("/format/container/radius_mm"), f,
                      f + " is required: a number, allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", nullptr), f,
                      f + " is required: a number, allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", "48.5"), f,
                      f + " must be a number, got \"48.5\"; allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", true), f,
                      f + " must be a number, got true; allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", -3), f,
                      "format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", 0.999), f,
                      f + " = 0.999 is out of range: allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", 2000.5), f,
                      f + " = 2000.5 is out of range: allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", std::numeric_limits<double>::quiet_NaN()),
                      f, f + " = nan is out of range: allowed 1 to 2000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/radius_mm", std::numeric_limits<double>::infinity()),
                      f, f + " = inf is out of range: allowed 1 to 2000 mm"));
}

TEST(ValidationFormat, FillHeight) {
  const std::string f = "format.fill_height_mm";
  EXPECT_TRUE(Rejects(without("/format/fill_height_mm"), f,
                      f + " is required: a number, allowed 1 to 5000 mm"));
  EXPECT_TRUE(Rejects(with("/format/fill_height_mm", false), f,
                      f + " must be a number, got false; allowed 1 to 5000 mm"));
  EXPECT_TRUE(Rejects(with("/format/fill_height_mm", 0), f,
                      f + " = 0 is out of range: allowed 1 to 5000 mm"));
  EXPECT_TRUE(Rejects(with("/format/fill_height_mm", -1), f,
                      f + " = -1 is out of range: allowed 1 to 5000 mm"));
  EXPECT_TRUE(Rejects(with("/format/fill_height_mm", 5000.5), f,
                      f + " = 5000.5 is out of range: allowed 1 to 5000 mm"));
  // A film of 0.07 mm gave null predictions.
  EXPECT_TRUE(Rejects(with("/format/fill_height_mm", 0.07), f,
                      f + " = 0.07 is out of range: allowed 1 to 5000 mm"));
}

TEST(ValidationFormat, ContainerHeightMustExceedFillHeight) {
  const std::string f = "format.container.height_mm";
  EXPECT_TRUE(Rejects(with("/format/container/height_mm", 50), f,
                      f + " = 50 is out of range: allowed > 82 and <= 10000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/height_mm", 82), f,
                      f + " = 82 is out of range: allowed > 82 and <= 10000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/height_mm", 10000.5), f,
                      f + " = 10000.5 is out of range: allowed > 82 and <= 10000 mm"));
  EXPECT_TRUE(Rejects(with("/format/container/height_mm", "150"), f,
                      f + " must be a number, got \"150\"; allowed > 82 and <= 10000 mm"));
  json body = with("/format/fill_height_mm", 82.5);
  body["format"]["container"]["height_mm"] = 80;
  EXPECT_TRUE(Rejects(body, f, f + " = 80 is out of range: allowed > 82.5 and <= 10000 mm"));
}

TEST(ValidationFormat, Stroke) {
  const std::string f = "format.stroke_mm";
  EXPECT_TRUE(Rejects(without("/format/stroke_mm"), f,
                      f + " is required: a number, allowed 0.01 to 100000 mm"));
  EXPECT_TRUE(Rejects(with("/format/stroke_mm", json::array({800})), f,
                      f + " must be a number, got [800]; allowed 0.01 to 100000 mm"));
  EXPECT_TRUE(Rejects(with("/format/stroke_mm", 0), f,
                      f + " = 0 is out of range: allowed 0.01 to 100000 mm"));
  EXPECT_TRUE(Rejects(with("/format/stroke_mm", 100000.5), f,
                      f + " = 100000.5 is out of range: allowed 0.01 to 100000 mm"));
  // The smallest denormal stroke gave a 500.
  EXPECT_TRUE(Rejects(with("/format/stroke_mm", 5e-324), f,
                      f + " = 4.940656458e-324 is out of range: allowed 0.01 to 100000 mm"));
}

TEST(ValidationFormat, MotionTime) {
  const std::string f = "format.motion_time_s";
  EXPECT_TRUE(Rejects(without("/format/motion_time_s"), f,
                      f + " is required: a number, allowed 0.05 to 60 s"));
  EXPECT_TRUE(Rejects(with("/format/motion_time_s", "1"), f,
                      f + " must be a number, got \"1\"; allowed 0.05 to 60 s"));
  EXPECT_TRUE(Rejects(with("/format/motion_time_s", 0.04), f,
                      f + " = 0.04 is out of range: allowed 0.05 to 60 s"));
  EXPECT_TRUE(Rejects(with("/format/motion_time_s", 60.5), f,
                      f + " = 60.5 is out of range: allowed 0.05 to 60 s"));
}

// ---------------------------------------------------------------------------------------------
// format.fluid

TEST(ValidationFluid, Missing) {
  EXPECT_TRUE(Rejects(without("/format/fluid"), "format.fluid",
                      std::string("format.fluid is required: a catalogue name (") + kCatalogue +
                          ") or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}"));
}

TEST(ValidationFluid, UnknownName) {
  EXPECT_TRUE(Rejects(with("/format/fluid", "mercury"), "format.fluid",
                      std::string("format.fluid = \"mercury\" is not in the catalogue; allowed: ") +
                          kCatalogue + ", or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}"));
  // Names are exact and lower case.
  EXPECT_TRUE(Rejects(with("/format/fluid", "Water"), "format.fluid",
                      std::string("format.fluid = \"Water\" is not in the catalogue; allowed: ") +
                          kCatalogue + ", or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}"));
}

TEST(ValidationFluid, WrongType) {
  EXPECT_TRUE(Rejects(with("/format/fluid", 5), "format.fluid",
                      std::string("format.fluid must be a catalogue name (") + kCatalogue +
                          ") or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}, got 5"));
  EXPECT_TRUE(Rejects(with("/format/fluid", nullptr), "format.fluid",
                      std::string("format.fluid must be a catalogue name (") + kCatalogue +
                          ") or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}, got null"));
}

TEST(ValidationFluid, CustomFluidFields) {
  EXPECT_TRUE(Rejects(without("/format/fluid/viscosity_pa_s"), "format.fluid.viscosity_pa_s",
                      "format.fluid.viscosity_pa_s is required: a number, allowed > 0 and <= 10 "
                      "Pa·s"));
  EXPECT_TRUE(Rejects(without("/format/fluid/density_kg_m3"), "format.fluid.density_kg_m3",
                      "format.fluid.density_kg_m3 is required: a number, allowed 100 to 20000 "
                      "kg/m^3"));
  EXPECT_TRUE(Rejects(with("/format/fluid/density_kg_m3", 99), "format.fluid.density_kg_m3",
                      "format.fluid.density_kg_m3 = 99 is out of range: allowed 100 to 20000 "
                      "kg/m^3"));
  EXPECT_TRUE(Rejects(with("/format/fluid/density_kg_m3", 20001), "format.fluid.density_kg_m3",
                      "format.fluid.density_kg_m3 = 20001 is out of range: allowed 100 to 20000 "
                      "kg/m^3"));
  EXPECT_TRUE(Rejects(with("/format/fluid/viscosity_pa_s", 0), "format.fluid.viscosity_pa_s",
                      "format.fluid.viscosity_pa_s = 0 is out of range: allowed > 0 and <= 10 "
                      "Pa·s"));
  EXPECT_TRUE(Rejects(with("/format/fluid/viscosity_pa_s", 10.5), "format.fluid.viscosity_pa_s",
                      "format.fluid.viscosity_pa_s = 10.5 is out of range: allowed > 0 and <= 10 "
                      "Pa·s"));
  EXPECT_TRUE(Rejects(with("/format/fluid/viscosity_pa_s", "0.001"), "format.fluid.viscosity_pa_s",
                      "format.fluid.viscosity_pa_s must be a number, got \"0.001\"; allowed > 0 "
                      "and <= 10 Pa·s"));
}

TEST(ValidationFluid, CustomFluidName) {
  const std::string f = "format.fluid.name";
  const std::string head = f + " must be a text of 1 to 64 characters, got ";
  EXPECT_TRUE(Rejects(with("/format/fluid/name", ""), f, head + "\"\""));
  EXPECT_TRUE(Rejects(with("/format/fluid/name", 5), f, head + "5"));
  EXPECT_TRUE(Rejects(with("/format/fluid/name", false), f, head + "false"));
  EXPECT_TRUE(Rejects(with("/format/fluid/name", json::array({"water"})), f, head + "[\"water\"]"));
  EXPECT_TRUE(
      Rejects(with("/format/fluid/name", {{"en", "water"}}), f, head + "{\"en\":\"water\"}"));
  // 65 characters; the value is shown cut to 57 bytes and "...".
  EXPECT_TRUE(Rejects(with("/format/fluid/name", std::string(65, 'n')), f,
                      head + "\"" + std::string(56, 'n') + "..."));
  // The name is checked before the numbers.
  EXPECT_TRUE(Rejects(with("/format/fluid", {{"name", ""}}), f, head + "\"\""));
}

// The limit is documented in characters but counted in bytes: 64 x U+00E9 (128 bytes) is
// rejected with "must be a text of 1 to 64 characters". Enable when the length is counted in
// characters (code points).
TEST(ValidationFluid, CustomFluidNameLimitCountsCharacters) {
  std::string accents;
  for (int i = 0; i < 64; ++i) accents += "\xc3\xa9";  // U+00E9
  EXPECT_TRUE(Accepts(with("/format/fluid/name", accents)));
}

TEST(ValidationFluid, CustomFluidTypo) {
  EXPECT_TRUE(Rejects(with("/format/fluid", {{"density_kg_m3", 1000}, {"viscosity", 0.001}}),
                      "format.fluid.viscosity",
                      "format.fluid.viscosity is not a known field; allowed here: "
                      "density_kg_m3, viscosity_pa_s, name"));
}

// ---------------------------------------------------------------------------------------------
// options

TEST(ValidationOptions, ObjectAndTypo) {
  EXPECT_TRUE(
      Rejects(with("/options", json::array()), "options", "options must be a JSON object, got []"));
  EXPECT_TRUE(Rejects(with("/options", {{"mode", 3}}), "options.mode",
                      "options.mode is not a known field; allowed here: modes, damping, alpha, "
                      "model, min_ramp_s"));
}

TEST(ValidationOptions, Modes) {
  const std::string f = "options.modes";
  EXPECT_TRUE(Rejects(with("/options", {{"modes", 0}}), f,
                      f + " = 0 is out of range: allowed an integer from 1 to 5"));
  EXPECT_TRUE(Rejects(with("/options", {{"modes", 6}}), f,
                      f + " = 6 is out of range: allowed an integer from 1 to 5"));
  EXPECT_TRUE(Rejects(with("/options", {{"modes", -1}}), f,
                      f + " = -1 is out of range: allowed an integer from 1 to 5"));
  EXPECT_TRUE(Rejects(with("/options", {{"modes", 1e10}}), f,
                      f + " = 1e+10 is out of range: allowed an integer from 1 to 5"));
  EXPECT_TRUE(Rejects(with("/options", {{"modes", 2.5}}), f,
                      f + " = 2.5 is not an integer: allowed an integer from 1 to 5"));
  EXPECT_TRUE(Rejects(with("/options", {{"modes", 0.5}}), f,
                      f + " = 0.5 is not an integer: allowed an integer from 1 to 5"));
  EXPECT_TRUE(Rejects(with("/options", {{"modes", "3"}}), f,
                      f + " must be an integer from 1 to 5, got \"3\""));
  EXPECT_TRUE(Rejects(with("/options", {{"modes", true}}), f,
                      f + " must be an integer from 1 to 5, got true"));
}

TEST(ValidationOptions, Alpha) {
  const std::string f = "options.alpha";
  EXPECT_TRUE(Rejects(with("/options", {{"alpha", -0.1}}), f,
                      f + " = -0.1 is out of range: allowed 0 to 2"));
  EXPECT_TRUE(
      Rejects(with("/options", {{"alpha", 2.5}}), f, f + " = 2.5 is out of range: allowed 0 to 2"));
  EXPECT_TRUE(Rejects(with("/options", {{"alpha", "high"}}), f,
                      f + " must be a number, got \"high\"; allowed 0 to 2"));
}

TEST(ValidationOptions, DampingName) {
  const std::string tail =
      " is not allowed: one of \"thesis\", \"paper\", \"eq227\", \"eq228\" or {\"zeta\": z} with "
      "0 <= z < 0.5";
  EXPECT_TRUE(Rejects(with("/options", {{"damping", "thesys"}}), "options.damping",
                      "options.damping = \"thesys\"" + tail));
  EXPECT_TRUE(Rejects(with("/options", {{"damping", "explicit"}}), "options.damping",
                      "options.damping = \"explicit\"" + tail));
  EXPECT_TRUE(Rejects(with("/options", {{"damping", 0.005}}), "options.damping",
                      "options.damping = 0.005" + tail));
  EXPECT_TRUE(Rejects(with("/options", {{"damping", json::array({0.005})}}), "options.damping",
                      "options.damping = [0.005]" + tail));
}

TEST(ValidationOptions, ExplicitZeta) {
  const std::string f = "options.damping.zeta";
  EXPECT_TRUE(Rejects(with("/options", {{"damping", {{"zeta", 0.5}}}}), f,
                      f + " = 0.5 is out of range: allowed >= 0 and < 0.5"));
  EXPECT_TRUE(Rejects(with("/options", {{"damping", {{"zeta", -0.01}}}}), f,
                      f + " = -0.01 is out of range: allowed >= 0 and < 0.5"));
  EXPECT_TRUE(Rejects(with("/options", {{"damping", json::object()}}), f,
                      f + " is required: a number, allowed >= 0 and < 0.5"));
  EXPECT_TRUE(Rejects(with("/options", {{"damping", {{"zeta", "0.01"}}}}), f,
                      f + " must be a number, got \"0.01\"; allowed >= 0 and < 0.5"));
  EXPECT_TRUE(Rejects(with("/options", {{"damping", {{"z", 0.01}}}}), "options.damping.z",
                      "options.damping.z is not a known field; allowed here: zeta"));
}

TEST(ValidationOptions, MinRampDependsOnTheMotionTime) {
  const std::string f = "options.min_ramp_s";
  EXPECT_TRUE(Rejects(with("/options", {{"min_ramp_s", 0.0005}}), f,
                      f + " = 0.0005 is out of range: allowed 0.001 to 0.25 s (the upper bound is "
                          "format.motion_time_s / 4: four ramps must fit)"));
  EXPECT_TRUE(Rejects(with("/options", {{"min_ramp_s", 0.3}}), f,
                      f + " = 0.3 is out of range: allowed 0.001 to 0.25 s (the upper bound is "
                          "format.motion_time_s / 4: four ramps must fit)"));
  json body = with("/options", {{"min_ramp_s", 0.6}});
  body["format"]["motion_time_s"] = 2;
  EXPECT_TRUE(Rejects(body, f,
                      f + " = 0.6 is out of range: allowed 0.001 to 0.5 s (the upper bound is "
                          "format.motion_time_s / 4: four ramps must fit)"));
  EXPECT_TRUE(Rejects(with("/options", {{"min_ramp_s", "0.05"}}), f,
                      f + " must be a number, got \"0.05\"; allowed 0.001 to 0.25 s (the upper "
                          "bound is format.motion_time_s / 4: four ramps must fit)"));
}

// ---------------------------------------------------------------------------------------------
// law

TEST(ValidationLaw, RequiredObjectAndTypo) {
  EXPECT_TRUE(
      Rejects(without("/law"), "law", "law is required: {\"type\": ..., \"durations_s\": [...]}"));
  EXPECT_TRUE(Rejects(with("/law", "poly5"), "law", "law must be a JSON object, got \"poly5\""));
  EXPECT_TRUE(Rejects(with("/law", {{"type", "seven_segment"}, {"duration_s", valid_durations()}}),
                      "law.duration_s",
                      "law.duration_s is not a known field; allowed here: type, durations_s"));
}

TEST(ValidationLaw, Type) {
  const std::string allowed = std::string("one of ") + kLawTypes;
  EXPECT_TRUE(
      Rejects(with("/law", json::object()), "law.type", "law.type is required: " + allowed));
  EXPECT_TRUE(Rejects(with("/law/type", "trapezoid"), "law.type",
                      "law.type = \"trapezoid\" is not allowed: " + allowed));
  EXPECT_TRUE(Rejects(with("/law/type", 7), "law.type", "law.type = 7 is not allowed: " + allowed));
  EXPECT_TRUE(Rejects(with("/law/type", nullptr), "law.type",
                      "law.type = null is not allowed: " + allowed));
}

TEST(ValidationLaw, DurationsOnlyWithSevenSegment) {
  for (const char* type : {"seven_segment_uniform", "poly5", "modified_trapezoid", "cycloidal"}) {
    EXPECT_TRUE(Rejects(with("/law", {{"type", type}, {"durations_s", valid_durations()}}),
                        "law.durations_s",
                        "law.durations_s is only allowed with law.type \"seven_segment\""))
        << type;
  }
}

TEST(ValidationDurations, MissingOrWrongShape) {
  const std::string f = "law.durations_s";
  const std::string head =
      "law.durations_s must be an array of 7 durations in s (sum = format.motion_time_s), got ";
  EXPECT_TRUE(Rejects(with("/law/type", "seven_segment"), f, head + "nothing"));
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.2, 0.2, 0.2, 0.2, 0.2, 0.2})), f,
                      head + "[0.2,0.2,0.2,0.2,0.2,0.2]"));
  EXPECT_TRUE(Rejects(seven_segment_request("uniform"), f, head + "\"uniform\""));
  EXPECT_TRUE(Rejects(seven_segment_request(nullptr), f, head + "null"));
  // Long values are cut to 60 characters.
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.142857, 0.142857, 0.142857, 0.142857,
                                                         0.142857, 0.142857, 0.142857, 0.1})),
                      f, head + "[0.142857,0.142857,0.142857,0.142857,0.142857,0.142857,0...."));
}

TEST(ValidationDurations, ElementsMustBeNumbers) {
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({"a", 0.15, 0.1, 0.3, 0.1, 0.15, 0.1})),
                      "law.durations_s[0]",
                      "law.durations_s[0] must be a number, got \"a\"; allowed 0.05 to 1 s"));
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.1, "x", 0.1, 0.3, 0.1, 0.15, 0.1})),
                      "law.durations_s[1]",
                      "law.durations_s[1] must be a number, got \"x\"; allowed 0 to 1 s"));
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.1, 0.15, nullptr, 0.3, 0.1, 0.15, 0.1})),
                      "law.durations_s[2]",
                      "law.durations_s[2] is required: a number, allowed 0.05 to 1 s"));
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.1, 0.15, 0.1, 0.3, 0.1, 0.15, true})),
                      "law.durations_s[6]",
                      "law.durations_s[6] must be a number, got true; allowed 0.05 to 1 s"));
}

TEST(ValidationDurations, RampsBelowTheMinimumRamp) {
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.04, 0.16, 0.1, 0.3, 0.1, 0.2, 0.1})),
                      "law.durations_s[0]",
                      "law.durations_s[0] = 0.04 is out of range: allowed 0.05 to 1 s (segment 1 "
                      "is a jerk ramp: >= options.min_ramp_s)"));
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.1, 0.2, 0.1, 0.3, 0.1, 0.16, 0.04})),
                      "law.durations_s[6]",
                      "law.durations_s[6] = 0.04 is out of range: allowed 0.05 to 1 s (segment 7 "
                      "is a jerk ramp: >= options.min_ramp_s)"));
  json body = seven_segment_request(json::array({0.1, 0.15, 0.1, 0.3, 0.08, 0.17, 0.1}));
  body["options"] = {{"min_ramp_s", 0.09}};
  EXPECT_TRUE(Rejects(body, "law.durations_s[4]",
                      "law.durations_s[4] = 0.08 is out of range: allowed 0.09 to 1 s (segment 5 "
                      "is a jerk ramp: >= options.min_ramp_s)"));
  // Negative ramps are below the minimum too.
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.1, 0.2, -0.1, 0.3, 0.1, 0.2, 0.2})),
                      "law.durations_s[2]",
                      "law.durations_s[2] = -0.1 is out of range: allowed 0.05 to 1 s (segment 3 "
                      "is a jerk ramp: >= options.min_ramp_s)"));
  // A smaller min_ramp_s admits the same ramp.
  body["options"]["min_ramp_s"] = 0.08;
  EXPECT_TRUE(Accepts(body));
}

TEST(ValidationDurations, RampLongerThanTheMotion) {
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({1.5, 0.15, 0.1, 0.3, 0.1, 0.15, 0.1})),
                      "law.durations_s[0]",
                      "law.durations_s[0] = 1.5 is out of range: allowed 0.05 to 1 s"));
}

TEST(ValidationDurations, NegativePlateau) {
  EXPECT_TRUE(Rejects(seven_segment_request(json::array({0.1, 0.2, 0.1, -0.1, 0.3, 0.3, 0.1})),
                      "law.durations_s[3]",
                      "law.durations_s[3] = -0.1 is out of range: allowed 0 to 1 s"));
}

TEST(ValidationDurations, SumMustEqualTheMotionTime) {
  EXPECT_TRUE(
      Rejects(seven_segment_request(json::array({0.125, 0.125, 0.125, 0.125, 0.125, 0.125, 0.125})),
              "law.durations_s",
              "law.durations_s sum to 0.875 s but format.motion_time_s = 1 s: they must "
              "be equal (tolerance 1e-6 s)"));
  EXPECT_TRUE(
      Rejects(seven_segment_request(json::array({0.25, 0.25, 0.25, 0.25, 0.25, 0.25, 0.25})),
              "law.durations_s",
              "law.durations_s sum to 1.75 s but format.motion_time_s = 1 s: they must "
              "be equal (tolerance 1e-6 s)"));
  // Just outside the tolerance: 10 significant digits show the difference.
  EXPECT_TRUE(
      Rejects(seven_segment_request(json::array({0.1, 0.15, 0.1, 0.3, 0.1, 0.15, 0.1000015})),
              "law.durations_s",
              "law.durations_s sum to 1.0000015 s but format.motion_time_s = 1 s: they must be "
              "equal (tolerance 1e-6 s)"));
  json body = seven_segment_request(json::array({0.3, 0.2, 0.3, 0.4, 0.3, 0.2, 0.3}));
  body["format"]["motion_time_s"] = 1.9999;
  EXPECT_TRUE(Rejects(body, "law.durations_s",
                      "law.durations_s sum to 2 s but format.motion_time_s = 1.9999 s: they must "
                      "be equal (tolerance 1e-6 s)"));
}

TEST(ValidationFields, NumberTextHasTenSignificantDigits) {
  EXPECT_EQ(number_text(1.0), "1");
  EXPECT_EQ(number_text(0.875), "0.875");
  EXPECT_EQ(number_text(-3.0), "-3");
  EXPECT_EQ(number_text(1.0000015), "1.0000015");
  EXPECT_EQ(number_text(1.0 / 3.0), "0.3333333333");
  EXPECT_EQ(number_text(123456789.26), "123456789.3");
  EXPECT_EQ(number_text(1e-4), "0.0001");
  EXPECT_EQ(number_text(5e-5), "5e-05");
  EXPECT_EQ(number_text(1e10), "1e+10");
  EXPECT_EQ(number_text(std::numeric_limits<double>::infinity()), "inf");
}

// ---------------------------------------------------------------------------------------------
// rest_time_s, sample_period_s

TEST(ValidationSeries, RestTime) {
  EXPECT_TRUE(Rejects(with("/rest_time_s", -1), "rest_time_s",
                      "rest_time_s = -1 is out of range: allowed 0 to 60 s"));
  EXPECT_TRUE(Rejects(with("/rest_time_s", 60.5), "rest_time_s",
                      "rest_time_s = 60.5 is out of range: allowed 0 to 60 s"));
  EXPECT_TRUE(Rejects(with("/rest_time_s", "1"), "rest_time_s",
                      "rest_time_s must be a number, got \"1\"; allowed 0 to 60 s"));
}

TEST(ValidationSeries, SamplePeriod) {
  EXPECT_TRUE(Rejects(with("/sample_period_s", 5e-5), "sample_period_s",
                      "sample_period_s = 5e-05 is out of range: allowed 0.0001 to 1 s"));
  EXPECT_TRUE(Rejects(with("/sample_period_s", 1.5), "sample_period_s",
                      "sample_period_s = 1.5 is out of range: allowed 0.0001 to 1 s"));
  EXPECT_TRUE(Rejects(with("/sample_period_s", "1ms"), "sample_period_s",
                      "sample_period_s must be a number, got \"1ms\"; allowed 0.0001 to 1 s"));
}

TEST(ValidationSeries, TooManySamples) {
  json body = with("/format/motion_time_s", 10);
  body["rest_time_s"] = 15;
  body["sample_period_s"] = 1e-4;
  EXPECT_TRUE(Rejects(body, "sample_period_s",
                      "sample_period_s = 0.0001 s gives 250001 samples over 25 s; at most 50000 "
                      "are returned: use >= 0.0005000100002 s"));
}

TEST(ValidationSeries, OneSampleOverTheLimitIsRejected) {
  // 10 s + 40 s at 1 ms: 50000 periods, 50001 samples with both ends.
  json decimal = with("/format/motion_time_s", 10);
  decimal["rest_time_s"] = 40;
  decimal["sample_period_s"] = 1e-3;
  EXPECT_TRUE(Rejects(decimal, "sample_period_s",
                      "sample_period_s = 0.001 s gives 50001 samples over 50 s; at most 50000 "
                      "are returned: use >= 0.00100002 s"));
  // Exactly representable: T + rest = 50000 dt with dt = 2^-10 s.
  json exact = with("/format/motion_time_s", 10);
  exact["sample_period_s"] = 1.0 / 1024.0;
  exact["rest_time_s"] = (50000.0 - 10240.0) / 1024.0;  // 38.828125 s
  const std::optional<ApiError> e = rejection(exact);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field(), "sample_period_s");
  EXPECT_EQ(std::string(e->what()).rfind("sample_period_s = 0.0009765625 s gives 50001 "
                                         "samples over 48.828125 s; at most 50000 are returned",
                                         0),
            0u)
      << e->what();
  // The suggested period is accepted.
  json suggested = decimal;
  suggested["sample_period_s"] = 0.00100002;
  EXPECT_TRUE(Accepts(suggested));
}

// ---------------------------------------------------------------------------------------------
// The error type and its envelope.

TEST(ValidationEnvelope, CarriesCodeMessageAndField) {
  const std::optional<ApiError> e = rejection(with("/format/container/radius_mm", -3));
  ASSERT_TRUE(e.has_value());
  const json envelope = error_envelope(*e);
  EXPECT_EQ(envelope, json::parse(R"({"error": {"code": "invalid_value",
                            "message": "format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm",
                            "field": "format.container.radius_mm"}})"));
}

TEST(ValidationEnvelope, EmptyFieldIsNull) {
  const std::optional<ApiError> e = rejection(json::array());
  ASSERT_TRUE(e.has_value());
  const json envelope = error_envelope(*e);
  EXPECT_TRUE(envelope["error"]["field"].is_null());
  EXPECT_EQ(envelope["error"]["code"], json("invalid_value"));
  EXPECT_EQ(envelope["error"]["message"], json("the request must be a JSON object, got []"));
}

TEST(ValidationEnvelope, StatusAndNameOfEveryCode) {
  const std::tuple<ErrorCode, int, const char*> cases[] = {
      {ErrorCode::kMalformedJson, 400, "malformed_json"},
      {ErrorCode::kInvalidValue, 422, "invalid_value"},
      {ErrorCode::kNotFound, 404, "not_found"},
      {ErrorCode::kPayloadTooLarge, 413, "payload_too_large"},
      {ErrorCode::kOverloaded, 503, "overloaded"},
      {ErrorCode::kTimeout, 504, "timeout"},
      {ErrorCode::kInternal, 500, "internal"},
  };
  for (const auto& [code, status, name] : cases) {
    EXPECT_EQ(http_status(code), status) << name;
    EXPECT_EQ(to_string(code), name);
    EXPECT_EQ(ApiError(code, "x", "m").status(), status) << name;
  }
}

// show() cuts long values to 57 bytes + "..." on a UTF-8 boundary, so the envelope stays valid
// UTF-8 (the strict dump() would throw type_error 316 otherwise).
TEST(ValidationEnvelope, LongNonAsciiValueStillSerialises) {
  const std::string tail = std::string(" is not in the catalogue; allowed: ") + kCatalogue +
                           ", or {\"density_kg_m3\", \"viscosity_pa_s\", \"name\"?}";
  std::string e_acute = "a";  // "a" + 40 x U+00E9: byte 57 is the 2nd byte of the 28th
  for (int i = 0; i < 40; ++i) e_acute += "\xc3\xa9";
  std::string euro;  // 30 x U+20AC (3 bytes): byte 57 is the 3rd byte of the 19th
  for (int i = 0; i < 30; ++i) euro += "\xe2\x82\xac";
  std::string smile;  // 20 x U+1F600 (4 bytes): byte 57 starts the 15th, no step back
  for (int i = 0; i < 20; ++i) smile += "\xf0\x9f\x98\x80";
  const std::pair<std::string, std::string> cases[] = {
      {e_acute, e_acute.substr(0, 1 + 2 * 27)},
      {euro, euro.substr(0, 3 * 18)},
      {smile, smile.substr(0, 4 * 14)},
  };
  for (const auto& [value, kept] : cases) {
    const std::optional<ApiError> e = rejection(with("/format/fluid", value));
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(std::string(e->what()), "format.fluid = \"" + kept + "..." + tail);
    EXPECT_NO_THROW((void)error_envelope(*e).dump());
    EXPECT_EQ(dump_json(error_envelope(*e)), error_envelope(*e).dump());
  }
}

TEST(ValidationEnvelope, ShortValuesAreShownWhole) {
  EXPECT_EQ(show(json("abc")), "\"abc\"");
  const std::string sixty = "\"" + std::string(58, 'x') + "\"";  // exactly 60 bytes
  EXPECT_EQ(show(json(std::string(58, 'x'))), sixty);
  EXPECT_EQ(show(json(std::string(59, 'x'))), "\"" + std::string(56, 'x') + "...");
}

TEST(ValidationEnvelope, DumpJsonReplacesInvalidUtf8) {
  const json value{{"k", std::string("a\xff b")}};
  EXPECT_THROW((void)value.dump(), json::type_error);
  EXPECT_EQ(dump_json(value), "{\"k\":\"a\xef\xbf\xbd b\"}");
  EXPECT_EQ(dump_json(json{{"k", 1}}, 2), "{\n  \"k\": 1\n}");
}

}  // namespace test_validation
}  // namespace slosh::api
