// The OpenAPI document of the service: every endpoint is there, every $ref resolves, the enums are
// what the parsers accept, the ranges are the parsers' ranges (read from api::ranges, and probed
// at the boundaries through parse_plan_request for the plan options), and real responses of
// run_plan / run_simulate, a real error envelope and the fluid catalogue fit their schemas
// (checked by a small validator written here for the keywords the document uses).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/error.hpp"
#include "slosh/api/format_json.hpp"
#include "slosh/api/job_request.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/openapi.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_view.hpp"
#include "slosh/api/simulate.hpp"
#include "slosh/api/spatial_simulate.hpp"
#include "slosh/core/model/fluid.hpp"
#include "slosh/core/strategy/planner.hpp"

namespace slosh::api {
namespace test_openapi {

using nlohmann::json;

const json& document() {
  static const json doc = openapi_document("9.8.7-test");
  return doc;
}

const json& schema(const std::string& name) {
  return document().at("components").at("schemas").at(name);
}

/// The target of a local reference "#/a/b"; null json when it does not resolve.
const json* resolve(const json& doc, const std::string& ref) {
  if (ref.rfind("#/", 0) != 0) return nullptr;
  const json::json_pointer pointer(ref.substr(1));
  return doc.contains(pointer) ? &doc.at(pointer) : nullptr;
}

/// `node` with $ref followed (one level chains included).
const json& deref(const json& node) {
  const json* n = &node;
  while (n->is_object() && n->contains("$ref")) {
    const json* target = resolve(document(), (*n)["$ref"].get<std::string>());
    if (target == nullptr) throw std::runtime_error("unresolved " + (*n)["$ref"].dump());
    n = target;
  }
  return *n;
}

void collect_refs(const json& node, std::vector<std::string>& refs) {
  if (node.is_object()) {
    for (const auto& [key, value] : node.items()) {
      if (key == "$ref" && value.is_string()) refs.push_back(value.get<std::string>());
      // Examples are data, not schema.
      if (key != "example") collect_refs(value, refs);
    }
  } else if (node.is_array()) {
    for (const auto& value : node) collect_refs(value, refs);
  }
}

/// A small validator for the keywords the document uses ($ref, oneOf, type, nullable, enum,
/// minimum/maximum with the 3.0 boolean exclusives, minItems/maxItems/items, minLength/maxLength,
/// properties/required/additionalProperties). `strict` also rejects object members missing from
/// `properties` (the response schemas leave additionalProperties open for new fields; the test
/// wants them documented all the same).
void validate(const json& schema_node, const json& value, const std::string& path, bool strict,
              std::vector<std::string>& errors) {
  const json& s = deref(schema_node);
  auto fail = [&](const std::string& what) { errors.push_back(path + ": " + what); };
  if (s.contains("oneOf")) {
    int matches = 0;
    for (const auto& alternative : s["oneOf"]) {
      std::vector<std::string> sub;
      validate(alternative, value, path, strict, sub);
      matches += sub.empty() ? 1 : 0;
    }
    if (matches != 1) fail("matches " + std::to_string(matches) + " oneOf alternatives");
    return;
  }
  if (value.is_null() && s.value("nullable", false)) return;
  if (s.contains("type")) {
    const std::string type = s["type"];
    const bool ok =
        type == "number" ? value.is_number()
        : type == "integer"
            ? value.is_number_integer() || (value.is_number_float() &&
                                            value.get<double>() == std::floor(value.get<double>()))
        : type == "string"  ? value.is_string()
        : type == "boolean" ? value.is_boolean()
        : type == "array"   ? value.is_array()
        : type == "object"  ? value.is_object()
                            : false;
    if (!ok) {
      fail("is not of type " + type + ": " + value.dump().substr(0, 60));
      return;
    }
  }
  if (s.contains("enum") && std::find(s["enum"].begin(), s["enum"].end(), value) == s["enum"].end())
    fail(value.dump() + " is not in the enum");
  if (value.is_number()) {
    const double x = value.get<double>();
    if (s.contains("minimum")) {
      const double lo = s["minimum"];
      if (s.value("exclusiveMinimum", false) ? !(x > lo) : !(x >= lo)) fail("below the minimum");
    }
    if (s.contains("maximum")) {
      const double hi = s["maximum"];
      if (s.value("exclusiveMaximum", false) ? !(x < hi) : !(x <= hi)) fail("above the maximum");
    }
  }
  if (value.is_string()) {
    const auto n = value.get<std::string>().size();
    if (s.contains("minLength") && n < s["minLength"].get<std::size_t>()) fail("too short");
    if (s.contains("maxLength") && n > s["maxLength"].get<std::size_t>()) fail("too long");
  }
  if (value.is_array()) {
    if (s.contains("minItems") && value.size() < s["minItems"].get<std::size_t>())
      fail("fewer than minItems");
    if (s.contains("maxItems") && value.size() > s["maxItems"].get<std::size_t>())
      fail("more than maxItems");
    if (s.contains("items")) {
      for (std::size_t i = 0; i < value.size(); ++i) {
        validate(s["items"], value[i], path + "[" + std::to_string(i) + "]", strict, errors);
      }
    }
  }
  if (value.is_object()) {
    for (const auto& key : s.value("required", json::array())) {
      if (!value.contains(key.get<std::string>())) fail("misses required " + key.dump());
    }
    const json properties = s.value("properties", json::object());
    const json additional = s.value("additionalProperties", json(true));
    for (const auto& [key, member] : value.items()) {
      const std::string member_path = path + "." + key;
      if (properties.contains(key)) {
        validate(properties[key], member, member_path, strict, errors);
      } else if (additional.is_object()) {
        validate(additional, member, member_path, strict, errors);
      } else if (additional == false || (strict && s.contains("properties"))) {
        fail("has the undocumented member \"" + key + "\"");
      }
    }
  }
}

std::vector<std::string> validation_errors(const std::string& schema_name, const json& value) {
  std::vector<std::string> errors;
  validate(schema(schema_name), value, schema_name, true, errors);
  return errors;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

json thesis_format() {
  return json::parse(R"({"container": {"radius_mm": 48.5, "height_mm": 150},
                         "fill_height_mm": 82, "fluid": "water",
                         "stroke_mm": 800, "motion_time_s": 1.0})");
}

json thesis_plan(const std::string& strategy) {
  return {{"format", thesis_format()}, {"strategy", strategy}, {"options", json::object()}};
}

/// The top-level check of a response against its schema: every required key present, every key
/// of the response named in the schema's properties.
void expect_top_level_keys(const std::string& schema_name, const json& response) {
  const json& s = schema(schema_name);
  ASSERT_TRUE(s.contains("required"));
  for (const auto& key : s["required"]) {
    EXPECT_TRUE(response.contains(key.get<std::string>())) << schema_name << " misses " << key;
  }
  for (const auto& [key, value] : response.items()) {
    EXPECT_TRUE(s["properties"].contains(key)) << schema_name << " does not document " << key;
  }
}

void expect_range(const json& s, const Range& r, const std::string& name) {
  SCOPED_TRACE(name);
  EXPECT_EQ(s.at("type"), "number");
  EXPECT_EQ(s.at("minimum").get<double>(), r.lo);
  EXPECT_EQ(s.at("maximum").get<double>(), r.hi);
  EXPECT_EQ(s.value("exclusiveMinimum", false), r.lo_open);
  EXPECT_EQ(s.value("exclusiveMaximum", false), r.hi_open);
}

TEST(OpenApiDocument, IsOpenApi303WithTheGivenVersion) {
  const json& doc = document();
  EXPECT_EQ(doc.at("openapi"), "3.0.3");
  EXPECT_EQ(doc.at("info").at("version"), "9.8.7-test");
  EXPECT_FALSE(doc.at("info").at("title").get<std::string>().empty());
  EXPECT_EQ(openapi_document("1.2.3")["info"]["version"], "1.2.3");
  // It is plain JSON: a round trip through text gives the same document.
  EXPECT_EQ(json::parse(dump_json(doc)), doc);
}

TEST(OpenApiDocument, DescribesEveryEndpointWithItsStatuses) {
  struct Endpoint {
    const char* path;
    const char* method;
    std::vector<std::string> statuses;
  };
  const std::vector<Endpoint> endpoints = {
      {"/v1/plans", "post", {"200", "400", "408", "413", "415", "422", "503", "504"}},
      {"/v1/plans/{key}", "get", {"200", "404"}},
      {"/v1/plans/batch", "post", {"200", "400", "408", "413", "415", "422"}},
      {"/v1/simulate", "post", {"200", "400", "408", "413", "415", "422"}},
      {"/v1/fluids", "get", {"200"}},
      {"/v1/openapi.json", "get", {"200"}},
      {"/healthz", "get", {"200"}},
      {"/readyz", "get", {"200", "503"}},
      {"/metrics", "get", {"200"}},
      {"/v1/batches", "post", {"202", "400", "413", "415", "422", "503"}},
      {"/v1/batches/{id}", "get", {"200", "404", "422"}},
      {"/v1/batches/{id}", "delete", {"200", "202", "404"}},
      {"/v1/batches/{id}/results.csv", "get", {"200", "404", "409", "422", "503"}},
      {"/v1/batches/{id}/results.jsonl", "get", {"200", "404", "409", "422", "503"}},
  };
  const json& paths = document().at("paths");
  std::set<std::string> operation_ids;
  for (const auto& e : endpoints) {
    SCOPED_TRACE(std::string(e.method) + " " + e.path);
    ASSERT_TRUE(paths.contains(e.path));
    ASSERT_TRUE(paths[e.path].contains(e.method));
    const json& op = paths[e.path][e.method];
    EXPECT_TRUE(operation_ids.insert(op.at("operationId").get<std::string>()).second);
    for (const auto& status : e.statuses) {
      ASSERT_TRUE(op.at("responses").contains(status)) << status;
      const json& response = deref(op["responses"][status]);
      EXPECT_TRUE(response.contains("description")) << status;
      // Every error answers with the envelope.
      if (status[0] == '4' || status[0] == '5') {
        if (std::string(e.path) == "/readyz") continue;
        EXPECT_EQ(response.at("content").at("application/json").at("schema").at("$ref"),
                  "#/components/schemas/ErrorEnvelope")
            << status;
      }
    }
  }
  // The request and response bodies of the planning endpoints.
  auto body_ref = [&](const char* path, const char* method) {
    return paths[path][method]["requestBody"]["content"]["application/json"]["schema"]["$ref"];
  };
  auto ok_ref = [&](const char* path, const char* method) {
    return paths[path][method]["responses"]["200"]["content"]["application/json"]["schema"]["$ref"];
  };
  EXPECT_EQ(body_ref("/v1/plans", "post"), "#/components/schemas/PlanRequest");
  // The plan endpoints answer the plan in the view of ?view=.
  const json either_view = json::parse(R"({"oneOf": [{"$ref": "#/components/schemas/PlanResponse"},
                                        {"$ref": "#/components/schemas/CompactPlan"}]})");
  auto ok_schema = [&](const char* path, const char* method) {
    return paths[path][method]["responses"]["200"]["content"]["application/json"]["schema"];
  };
  EXPECT_EQ(ok_schema("/v1/plans", "post"), either_view);
  EXPECT_EQ(ok_schema("/v1/plans/{key}", "get"), either_view);
  for (const auto& [path, method] : std::vector<std::pair<const char*, const char*>>{
           {"/v1/plans", "post"}, {"/v1/plans/{key}", "get"}, {"/v1/plans/batch", "post"}}) {
    bool has_view = false;
    for (const auto& p : paths[path][method]["parameters"]) {
      if (p["name"] != "view") continue;
      has_view = p["in"] == "query" && p["required"] == false;
      EXPECT_EQ(p["schema"]["enum"], json({"full", "compact"})) << path;
      EXPECT_EQ(p["schema"]["default"], "full") << path;
    }
    EXPECT_TRUE(has_view) << path;
  }
  // (null: the member left out, as for every optional request member)
  EXPECT_EQ(schema("BatchRequest")["properties"]["view"]["enum"],
            json({"full", "compact", nullptr}));
  EXPECT_EQ(body_ref("/v1/plans/batch", "post"), "#/components/schemas/BatchRequest");
  EXPECT_EQ(ok_ref("/v1/plans/batch", "post"), "#/components/schemas/BatchResponse");
  EXPECT_EQ(body_ref("/v1/simulate", "post"), "#/components/schemas/SimulateRequest");
  EXPECT_EQ(ok_ref("/v1/simulate", "post"), "#/components/schemas/SimulateResponse");
  EXPECT_TRUE(paths["/metrics"]["get"]["responses"]["200"]["content"].contains("text/plain"));
  // The 503 of POST /v1/plans carries Retry-After.
  const json& overloaded = deref(paths["/v1/plans"]["post"]["responses"]["503"]);
  EXPECT_EQ(overloaded.at("headers").at("Retry-After").at("schema").at("type"), "integer");
  // The path parameter of GET /v1/plans/{key}.
  bool has_key = false;
  for (const auto& p : paths["/v1/plans/{key}"]["get"]["parameters"]) {
    has_key = has_key || (p["name"] == "key" && p["in"] == "path" && p["required"] == true);
  }
  EXPECT_TRUE(has_key);
}

TEST(OpenApiDocument, EveryRefResolvesAndEverySchemaIsUsed) {
  std::vector<std::string> refs;
  collect_refs(document(), refs);
  EXPECT_GT(refs.size(), 50u);
  std::set<std::string> used;
  for (const auto& r : refs) {
    EXPECT_NE(resolve(document(), r), nullptr) << r;
    used.insert(r);
  }
  for (const auto& [name, s] : document()["components"]["schemas"].items()) {
    EXPECT_TRUE(used.count("#/components/schemas/" + name)) << name << " is never referenced";
  }
  for (const auto& [name, r] : document()["components"]["responses"].items()) {
    EXPECT_TRUE(used.count("#/components/responses/" + name)) << name << " is never referenced";
  }
}

TEST(OpenApiSchemas, StrategyEnumIsExactlyWhatTheParserAccepts) {
  const json& names = schema("Strategy").at("enum");
  const std::set<std::string> expected{"baseline",      "notch",       "multi_notch",
                                       "min_jerk_band", "time_domain", "fir_chain",
                                       "shaper",        "iir",         "auto"};
  EXPECT_EQ(names.get<std::set<std::string>>(), expected);
  EXPECT_EQ(names.size(), 9u);
  for (const auto& n : names) {
    const auto parsed = parse_strategy(n.get<std::string>());
    ASSERT_TRUE(parsed.has_value()) << n;
    EXPECT_EQ(to_string(*parsed), n.get<std::string>());
  }
  for (const char* bad : {"", "Auto", "multinotch", "multi-notch", "time_domain ", "none"}) {
    EXPECT_FALSE(parse_strategy(bad).has_value()) << bad;
  }
  EXPECT_EQ(schema("Strategy").at("default"), "auto");
}

TEST(OpenApiSchemas, FluidEnumIsTheCatalogue) {
  std::vector<std::string> catalogue;
  for (const Fluid& f : fluid_catalogue()) catalogue.push_back(f.name);
  ASSERT_FALSE(catalogue.empty());
  EXPECT_EQ(schema("FluidName").at("enum").get<std::vector<std::string>>(), catalogue);
  // Format.fluid is a catalogue name or a custom fluid.
  const json& fluid = deref(schema("Format")["properties"]["fluid"]);
  ASSERT_EQ(fluid.at("oneOf").size(), 2u);
  EXPECT_EQ(fluid["oneOf"][0]["$ref"], "#/components/schemas/FluidName");
  EXPECT_EQ(fluid["oneOf"][1]["$ref"], "#/components/schemas/CustomFluid");
}

TEST(OpenApiSchemas, FormatRangesAreTheParserRanges) {
  const json& format = schema("Format")["properties"];
  const json& container = schema("Container")["properties"];
  const json& custom = schema("CustomFluid")["properties"];
  expect_range(container.at("radius_mm"), ranges::kRadiusMm, "radius_mm");
  expect_range(container.at("height_mm"), ranges::kContainerHeightMm, "height_mm");
  expect_range(format.at("fill_height_mm"), ranges::kFillHeightMm, "fill_height_mm");
  expect_range(format.at("stroke_mm"), ranges::kStrokeMm, "stroke_mm");
  expect_range(format.at("motion_time_s"), ranges::kMotionTimeS, "motion_time_s");
  expect_range(custom.at("density_kg_m3"), ranges::kDensity, "density_kg_m3");
  expect_range(custom.at("viscosity_pa_s"), ranges::kViscosity, "viscosity_pa_s");
  expect_range(schema("ExplicitDamping")["properties"].at("zeta"), ranges::kZeta, "zeta");
  expect_range(schema("PlanOptions")["properties"].at("alpha"), ranges::kAlpha, "alpha");
  expect_range(schema("SimulateRequest")["properties"].at("rest_time_s"), ranges::kRestTimeS,
               "simulate rest_time_s");
  expect_range(schema("SimulateRequest")["properties"].at("sample_period_s"),
               ranges::kSamplePeriodS, "simulate sample_period_s");
  expect_range(schema("PlanRequest")["properties"].at("sample_period_s"), ranges::kSamplePeriodS,
               "plan sample_period_s");
  EXPECT_EQ(schema("Format").at("required").size(), 5u);
  EXPECT_EQ(schema("Container").at("required"), json::array({"radius_mm"}));
}

TEST(OpenApiSchemas, RequestObjectsAreClosedAndListOnlyFieldsTheParserKnows) {
  for (const char* name :
       {"PlanRequest", "PlanOptions", "MachineLimits", "Format", "Container", "CustomFluid",
        "ExplicitDamping", "SimulateRequest", "SimulateOptions", "LawSpec", "BatchRequest"}) {
    EXPECT_EQ(schema(name).at("additionalProperties"), false) << name;
  }
  // Every documented member is known to the parser (null = absent for optional members; a
  // required one fails as required, never as unknown).
  auto not_unknown = [](const std::function<void()>& parse, const std::string& field) {
    try {
      parse();
    } catch (const ApiError& e) {
      EXPECT_EQ(std::string(e.what()).find("is not a known field"), std::string::npos)
          << field << ": " << e.what();
    }
  };
  for (const auto& [key, s] : schema("PlanOptions")["properties"].items()) {
    json body = thesis_plan("notch");
    body["options"][key] = nullptr;
    not_unknown([&] { (void)parse_plan_request(body); }, "options." + key);
  }
  for (const auto& [key, s] : schema("PlanRequest")["properties"].items()) {
    json body = thesis_plan("notch");
    if (key != "format") body[key] = nullptr;
    not_unknown([&] { (void)parse_plan_request(body); }, key);
  }
  for (const auto& [key, s] : schema("MachineLimits")["properties"].items()) {
    json body = thesis_plan("notch");
    body["options"]["limits"][key] = nullptr;
    not_unknown([&] { (void)parse_plan_request(body); }, "options.limits." + key);
  }
  for (const auto& [key, s] : schema("Format")["properties"].items()) {
    json body = thesis_plan("notch");
    body["format"][key] = nullptr;
    not_unknown([&] { (void)parse_plan_request(body); }, "format." + key);
  }
  const json simulate = schema("SimulateRequest")["example"];
  for (const auto& [key, s] : schema("SimulateOptions")["properties"].items()) {
    json body = simulate;
    body["options"][key] = nullptr;
    not_unknown([&] { (void)parse_simulate_request(body); }, "options." + key);
  }
  for (const auto& [key, s] : schema("SimulateRequest")["properties"].items()) {
    json body = simulate;
    body[key] = nullptr;
    not_unknown([&] { (void)parse_simulate_request(body); }, key);
  }
}

// A request reads an optional member given null as absent; every closed (request) object's
// optional typed members say so (nullable), and the parser agrees for each of them: null parses
// to the same request as leaving the member out.
TEST(OpenApiSchemas, OptionalRequestMembersAreNullableAsTheParserReadsThem) {
  int closed = 0;
  int untyped = 0;
  for (const auto& [name, s] : document().at("components").at("schemas").items()) {
    if (s.value("additionalProperties", true) != false) continue;
    ++closed;
    const json required = s.value("required", json::array());
    for (const auto& [key, property] : s.at("properties").items()) {
      const bool optional = std::find(required.begin(), required.end(), key) == required.end();
      if (!optional) continue;
      if (property.contains("type")) {
        EXPECT_TRUE(property.value("nullable", false)) << name << "." << key;
        continue;
      }
      // A $ref or a oneOf: null is one of its alternatives, exactly one.
      std::vector<std::string> errors;
      validate(property, nullptr, name + "." + key, true, errors);
      EXPECT_TRUE(errors.empty()) << ::testing::PrintToString(errors);
      ++untyped;
    }
  }
  EXPECT_GE(closed, 10);
  EXPECT_GE(untyped, 9);  // options, strategy, damping, limits, model, uncertainty, motion, ...
  // And the parser reads those null as absent.
  for (const char* member : {"options", "strategy"}) {
    json body = thesis_plan("notch");
    body[member] = nullptr;
    json without = thesis_plan("notch");
    without.erase(member);
    EXPECT_EQ(canonical_recipe(parse_plan_request(body)),
              canonical_recipe(parse_plan_request(without)))
        << member;
  }
  json no_motion = thesis_plan("notch");
  no_motion["format"]["motion"] = nullptr;
  EXPECT_EQ(canonical_recipe(parse_plan_request(no_motion)),
            canonical_recipe(parse_plan_request(thesis_plan("notch"))));
  // The rectangular container's orientation, the member the hostile pass found undocumented.
  json cup = thesis_plan("notch");
  cup["format"]["container"] = {{"shape", "rectangular"}, {"length_mm", 120}, {"width_mm", 80}};
  json with_null = cup;
  with_null["format"]["container"]["orientation_deg"] = nullptr;
  EXPECT_EQ(canonical_recipe(parse_plan_request(with_null)),
            canonical_recipe(parse_plan_request(cup)));
  for (const auto& [key, property] : schema("PlanOptions")["properties"].items()) {
    json body = thesis_plan("notch");
    body["options"][key] = nullptr;
    EXPECT_EQ(canonical_recipe(parse_plan_request(body)),
              canonical_recipe(parse_plan_request(thesis_plan("notch"))))
        << "options." << key;
  }
  // A nullable enum lists null: OpenAPI 3.0's nullable does not widen an enum.
  const json& shape = schema("Container")["properties"]["shape"];
  EXPECT_NE(std::find(shape["enum"].begin(), shape["enum"].end(), nullptr), shape["enum"].end());
  // The cylinder's shape given null is the cylinder, as when left out.
  json cylinder = thesis_plan("notch");
  cylinder["format"]["container"]["shape"] = nullptr;
  EXPECT_EQ(canonical_recipe(parse_plan_request(cylinder)),
            canonical_recipe(parse_plan_request(thesis_plan("notch"))));
  // Another law type's members given null are absent.
  json simulate = schema("SimulateRequest")["example"];
  simulate["law"] = {{"type", "seven_segment_uniform"},
                     {"durations_s", nullptr},
                     {"breakpoints_s", nullptr},
                     {"acceleration_m_s2", nullptr},
                     {"pieces", nullptr}};
  EXPECT_NO_THROW((void)parse_simulate_request(simulate));
  // A batch job's requests, table and table_format given null are absent.
  const auto reads = [](const std::string& body) {
    std::string format;
    (void)parse_job_request(body, 10,
                            [&](const std::string&, const std::string& f, bool) { format = f; });
    return format;
  };
  const std::string one = dump_json(json::array({thesis_plan("notch")}));
  EXPECT_EQ(reads(R"({"requests": )" + one + R"(, "table": null, "table_format": null})"), "json");
  EXPECT_EQ(reads(R"({"table": "recipe_id\n", "table_format": "csv", "requests": null})"), "csv");
}

// Every numeric bound of the plan options, probed through the parser: at the bound the value is
// accepted unless the bound is exclusive; just beyond it is rejected naming the field.
TEST(OpenApiSchemas, PlanOptionBoundsAreThoseTheParserEnforces) {
  // T = 60 s so that no relation with the motion time (min_ramp_s <= T/4) interferes.
  json base = thesis_plan("notch");
  base["format"]["motion_time_s"] = ranges::kMotionTimeS.hi;
  ASSERT_NO_THROW((void)parse_plan_request(base));

  struct Probe {
    std::string field;                  // as the parser names it
    json schema;                        // the property's schema
    std::function<json(json)> request;  // the request with the value put in place
  };
  std::vector<Probe> probes;
  for (const auto& [key, s] : schema("PlanOptions")["properties"].items()) {
    const json& p = deref(s);
    if (!p.is_object() || !p.contains("type")) continue;
    const std::string k = key;
    if (p["type"] == "number" || p["type"] == "integer") {
      probes.push_back({"options." + k, p, [base, k](json v) {
                          json b = base;
                          b["options"][k] = v;
                          return b;
                        }});
    }
  }
  for (const auto& [key, s] : schema("MachineLimits")["properties"].items()) {
    const std::string k = key;
    probes.push_back({"options.limits." + k, s, [base, k](json v) {
                        json b = base;
                        b["options"]["limits"][k] = v;
                        return b;
                      }});
  }
  probes.push_back({"options.weights[0]", schema("PlanOptions")["properties"]["weights"]["items"],
                    [base](json v) {
                      json b = base;
                      b["options"]["weights"] = {v, 1, 1};
                      return b;
                    }});
  ASSERT_GE(probes.size(), 15u);

  for (const auto& probe : probes) {
    SCOPED_TRACE(probe.field);
    const json& s = probe.schema;
    ASSERT_TRUE(s.contains("minimum") && s.contains("maximum"));
    const bool integer = s["type"] == "integer";
    for (const bool upper : {false, true}) {
      const double bound = s[upper ? "maximum" : "minimum"].get<double>();
      const bool exclusive = s.value(upper ? "exclusiveMaximum" : "exclusiveMinimum", false);
      const double step = integer ? 1.0 : std::max(std::abs(bound) * 1e-9, 1e-12);
      const double beyond = upper ? bound + step : bound - step;
      const json at_value = integer ? json(static_cast<int>(bound)) : json(bound);
      const json beyond_value = integer ? json(static_cast<int>(beyond)) : json(beyond);
      if (exclusive) {
        EXPECT_THROW((void)parse_plan_request(probe.request(at_value)), ApiError) << bound;
      } else {
        EXPECT_NO_THROW((void)parse_plan_request(probe.request(at_value))) << bound;
      }
      try {
        (void)parse_plan_request(probe.request(beyond_value));
        ADD_FAILURE() << "accepted " << beyond_value;
      } catch (const ApiError& e) {
        EXPECT_EQ(e.field(), probe.field) << e.what();
      }
    }
  }
}

TEST(OpenApiSchemas, PlanOptionDefaultsAreTheParserDefaults) {
  const PlanRequest r = parse_plan_request(thesis_plan("notch"));
  const json& p = schema("PlanOptions")["properties"];
  const PlanOptions& o = r.options;
  EXPECT_EQ(p["p_notch"]["default"].get<double>(), o.p_notch);
  EXPECT_EQ(p["weights"]["default"], json(o.weights));
  EXPECT_EQ(p["band"]["default"].get<double>(), o.band);
  EXPECT_EQ(p["n_band"]["default"].get<int>(), o.n_band);
  EXPECT_EQ(p["tol_rel"]["default"].get<double>(), o.tol_rel);
  EXPECT_DOUBLE_EQ(p["eta_rest_max_mm"]["default"].get<double>() * 1e-3, o.eta_rest_max);
  EXPECT_EQ(p["objective"]["default"], "motion");
  EXPECT_EQ(o.objective, TimeDomainObjective::kMotion);
  EXPECT_EQ(p["rest_time_s"]["default"].get<double>(), o.rest_time);
  EXPECT_EQ(p["min_ramp_s"]["default"].get<double>(), o.min_ramp);
  EXPECT_EQ(p["fix_constant_velocity_zero"]["default"].get<bool>(), o.fix_constant_velocity_zero);
  EXPECT_EQ(p["plateau_min_s"]["default"], json(o.plateau_min));
  EXPECT_EQ(p["solver"]["default"], to_string(o.solver));
  EXPECT_EQ(p["time_limit_s"]["default"].get<double>(), o.time_limit);
  EXPECT_EQ(p["modes"]["default"].get<int>(), o.model.modes);
  EXPECT_EQ(p["alpha"]["default"].get<double>(), o.model.alpha);
  // (An optional member that is a $ref admits null as a second alternative.)
  EXPECT_EQ(deref(p["damping"]["oneOf"][0])["default"], to_string(o.model.damping));
  EXPECT_FALSE(o.limits.a_max || o.limits.v_max || o.limits.j_max);
  EXPECT_EQ(p["base"]["default"], to_string(o.base));
  EXPECT_EQ(p["shaper"]["default"], to_string(o.shaper));
  EXPECT_EQ(p["residual"]["default"].get<double>(), o.residual);
  EXPECT_EQ(p["iir_order"]["default"].get<int>(), static_cast<int>(o.iir_order));
  EXPECT_EQ(p["iir_tau"]["default"].get<double>(), o.iir_tau);
  EXPECT_EQ(p["iir_sample_period_s"]["default"].get<double>(), o.iir_sample_period);
  EXPECT_EQ(r.strategy, Strategy::kNotch);
  EXPECT_EQ(parse_plan_request(json{{"format", thesis_format()}}).strategy,
            parse_strategy(schema("Strategy")["default"].get<std::string>()));
}

TEST(OpenApiResponses, PlanResponsesFitThePlanResponseSchema) {
  json body = thesis_plan("multi_notch");
  body["sample_period_s"] = 0.01;  // series
  const json multi = run_plan(parse_plan_request(body));
  expect_top_level_keys("PlanResponse", multi);
  EXPECT_TRUE(multi.contains("series"));
  EXPECT_TRUE(multi["spectrum"]["markers"].contains("notch_hz"));
  const auto errors = validation_errors("PlanResponse", multi);
  EXPECT_TRUE(errors.empty()) << joined(errors);

  const json automatic = run_plan(parse_plan_request(thesis_plan("auto")));  // candidates
  expect_top_level_keys("PlanResponse", automatic);
  ASSERT_TRUE(automatic.contains("candidates"));
  const auto auto_errors = validation_errors("PlanResponse", automatic);
  EXPECT_TRUE(auto_errors.empty()) << joined(auto_errors);

  // The filtering strategies: a 7-segment law (fir_chain on a long motion), piecewise_linear
  // (iir, fir_chain without (14)) and piecewise (shaper on poly5) laws, with their design.
  for (const auto& [strategy, T] : std::vector<std::pair<std::string, double>>{
           {"fir_chain", 1.0}, {"fir_chain", 1.5}, {"shaper", 1.0}, {"iir", 1.0}}) {
    json request = thesis_plan(strategy);
    request["format"]["motion_time_s"] = T;
    const json plan = run_plan(parse_plan_request(request));
    const auto filter_errors = validation_errors("PlanResponse", plan);
    EXPECT_TRUE(filter_errors.empty()) << strategy << ": " << joined(filter_errors);
    EXPECT_TRUE(plan.contains("design")) << strategy;
    const auto law_errors = validation_errors("LawSpec", plan["law"]);
    EXPECT_TRUE(law_errors.empty()) << strategy << ": " << joined(law_errors);
  }

  // A batch result wraps either a plan or an error.
  const json batch{{"results",
                    {{{"index", 0}, {"plan", multi}},
                     {{"index", 1},
                      {"error", error_envelope(ApiError(ErrorCode::kInvalidValue,
                                                        "requests[1].format", "bad"))["error"]}}}}};
  const auto batch_errors = validation_errors("BatchResponse", batch);
  EXPECT_TRUE(batch_errors.empty()) << joined(batch_errors);

  // The validator is not vacuous: a missing required key and an undocumented one are found.
  json broken = multi;
  broken.erase("durations_s");
  broken["kinematics"]["surprise"] = 1;
  broken["prediction"]["linear"]["eta_rest_mm"] = "3";
  EXPECT_EQ(validation_errors("PlanResponse", broken).size(), 3u)
      << joined(validation_errors("PlanResponse", broken));
}

// The compact view of real plans (a 7-segment law with warnings, a general law) fits
// CompactPlan with no undocumented member, and a batch result tells the two views apart (oneOf).
TEST(OpenApiResponses, CompactPlansFitTheCompactPlanSchema) {
  json request = thesis_plan("multi_notch");
  request["format"]["container"]["height_mm"] = 100;  // free board 18 mm: a warning
  const json multi = run_plan(parse_plan_request(request));
  ASSERT_FALSE(multi["warnings"].empty());
  json shaper_request = thesis_plan("shaper");
  const json shaper = run_plan(parse_plan_request(shaper_request));
  ASSERT_NE(shaper["law"]["type"], "seven_segment");
  for (const json* plan : {&multi, &shaper}) {
    const json compact = compact_plan(*plan);
    expect_top_level_keys("CompactPlan", compact);
    const auto errors = validation_errors("CompactPlan", compact);
    EXPECT_TRUE(errors.empty()) << joined(errors);
    // The views do not pass for each other.
    EXPECT_FALSE(validation_errors("PlanResponse", compact).empty());
    EXPECT_FALSE(validation_errors("CompactPlan", *plan).empty());
  }
  const json batch{
      {"results",
       {{{"index", 0}, {"plan", compact_plan(multi)}}, {{"index", 1}, {"plan", multi}}}}};
  const auto batch_errors = validation_errors("BatchResponse", batch);
  EXPECT_TRUE(batch_errors.empty()) << joined(batch_errors);
  // Every plan states its version.
  EXPECT_EQ(multi["version"], kVersion);
  EXPECT_TRUE(std::find(schema("PlanResponse")["required"].begin(),
                        schema("PlanResponse")["required"].end(),
                        "version") != schema("PlanResponse")["required"].end());
}

// Plans with an uncertainty range (uncertainty, worst_case, auto's candidates with
// theirs), without the report (robustness false), and where the nonlinear model diverges over the
// range (nulls in the report and the worst case) fit PlanResponse, their compact views
// CompactPlan; the Uncertainty request object is closed and its bounds are the parser's.
TEST(OpenApiResponses, RobustAndUncertainPlansFitThePlanResponseSchema) {
  json robust = thesis_plan("auto");
  robust["options"]["uncertainty"] = {{"omega_error_pct", 5}, {"fill_height_mm", {75, 90}}};
  json off = thesis_plan("multi_notch");
  off["options"]["robustness"] = false;
  const json diverging = json::parse(R"({"format": {"container": {"radius_mm": 5},
      "fill_height_mm": 6, "fluid": "water", "stroke_mm": 5000, "motion_time_s": 0.05},
      "strategy": "fir_chain", "options": {"min_ramp_s": 0.007, "limits": {"a_max": 0.001}}})");
  for (const json* body : std::vector<const json*>{&robust, &off, &diverging}) {
    const json plan = run_plan(parse_plan_request(*body));
    SCOPED_TRACE(body->dump());
    expect_top_level_keys("PlanResponse", plan);
    const auto errors = validation_errors("PlanResponse", plan);
    EXPECT_TRUE(errors.empty()) << joined(errors);
    const auto compact_errors = validation_errors("CompactPlan", compact_plan(plan));
    EXPECT_TRUE(compact_errors.empty()) << joined(compact_errors);
    EXPECT_EQ(plan.contains("robustness"), body != &off);
    EXPECT_EQ(plan.contains("uncertainty"), body == &robust);
    if (body == &robust) {
      for (const json& c : plan["candidates"]) EXPECT_TRUE(c.contains("worst_case"));
    }
    if (body == &diverging) {
      EXPECT_TRUE(plan["robustness"]["worst"]["nonlinear"].is_null());
    }
  }
}

TEST(OpenApiSchemas, TheUncertaintyObjectIsClosedWithTheParsersBounds) {
  const json& u = schema("Uncertainty");
  EXPECT_EQ(u.at("additionalProperties"), false);
  EXPECT_EQ(schema("PlanOptions")["properties"]["uncertainty"]["oneOf"][0]["$ref"],
            "#/components/schemas/Uncertainty");
  EXPECT_EQ(schema("PlanOptions")["properties"]["robustness"]["type"], "boolean");
  EXPECT_EQ(schema("PlanOptions")["properties"]["robustness"]["default"], true);
  // Probed through the parser, without a container height (the widest fill heights).
  json base = thesis_plan("notch");
  base["format"]["container"].erase("height_mm");
  struct Probe {
    std::string field;
    json schema;
    std::function<json(double)> value;
  };
  const json& p = u["properties"];
  const std::vector<Probe> probes{
      {"omega_error_pct", p["omega_error_pct"], [](double v) { return json(v); }},
      {"sample_points", p["sample_points"], [](double v) { return json(static_cast<int>(v)); }},
      // Each end of a range alone moves, the other stays at the nominal value.
      {"fill_height_mm[0]", p["fill_height_mm"]["items"],
       [](double v) {
         return json::array({v, 82});
       }},
      {"fill_height_mm[1]", p["fill_height_mm"]["items"],
       [](double v) {
         return json::array({82, v});
       }},
      {"viscosity_pa_s[0]", p["viscosity_pa_s"]["items"],
       [](double v) {
         return json::array({v, 0.0010016});
       }},
      {"viscosity_pa_s[1]", p["viscosity_pa_s"]["items"],
       [](double v) {
         return json::array({0.0010016, v});
       }},
  };
  for (const Probe& probe : probes) {
    SCOPED_TRACE(probe.field);
    const std::string member = probe.field.substr(0, probe.field.find('['));
    auto body_with = [&](double v) {
      json b = base;
      b["options"]["uncertainty"][member] = probe.value(v);
      return b;
    };
    const bool integer = probe.schema.value("type", "") == "integer";
    ASSERT_TRUE(probe.schema.contains("minimum") && probe.schema.contains("maximum"));
    for (const char* bound : {"minimum", "maximum"}) {
      const double at = probe.schema[bound].get<double>();
      const double step = integer ? 1.0 : std::max(std::abs(at) * 1e-9, 1e-12);
      const double beyond = std::string(bound) == "minimum" ? at - step : at + step;
      // At the bound the value passes the item's range (a range may still be refused as a
      // whole: a bound beyond the nominal value is the other end's business).
      try {
        (void)parse_plan_request(body_with(at));
      } catch (const ApiError& e) {
        EXPECT_NE(e.field(), "options.uncertainty." + probe.field) << e.what();
      }
      try {
        (void)parse_plan_request(body_with(beyond));
        ADD_FAILURE() << "accepted " << beyond;
      } catch (const ApiError& e) {
        EXPECT_EQ(e.field(), "options.uncertainty." + probe.field) << e.what();
      }
    }
  }
}

TEST(OpenApiResponses, SimulateResponsesFitTheSimulateResponseSchema) {
  json body = schema("SimulateRequest")["example"];
  body["sample_period_s"] = 0.01;
  const json seven = run_simulate(parse_simulate_request(body));
  expect_top_level_keys("SimulateResponse", seven);
  EXPECT_TRUE(seven.contains("series"));
  const auto errors = validation_errors("SimulateResponse", seven);
  EXPECT_TRUE(errors.empty()) << joined(errors);

  json poly = {{"format", thesis_format()}, {"law", {{"type", "poly5"}}}};
  poly["format"]["fluid"] = {{"density_kg_m3", 1100}, {"viscosity_pa_s", 0.004}};
  poly["options"] = {{"damping", {{"zeta", 0.01}}}};
  const json out = run_simulate(parse_simulate_request(poly));
  expect_top_level_keys("SimulateResponse", out);
  const auto poly_errors = validation_errors("SimulateResponse", out);
  EXPECT_TRUE(poly_errors.empty()) << joined(poly_errors);
}

// Simulate along a path and along a sampled trajectory (format.motion): the response and the
// requests fit their schemas.
TEST(OpenApiResponses, SpatialSimulateResponsesFitTheSimulateResponseSchema) {
  json arc = {{"format", thesis_format()}, {"law", {{"type", "seven_segment_uniform"}}}};
  arc["format"].erase("stroke_mm");
  arc["format"]["motion"] = {
      {"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", true}};
  json samples = {{"type", "trajectory"},
                  {"t_s", json::array()},
                  {"x_mm", json::array()},
                  {"y_mm", json::array()},
                  {"theta_deg", json::array()}};
  for (int i = 0; i <= 100; ++i) {
    samples["t_s"].push_back(i * 0.01);
    samples["x_mm"].push_back(50.0 * std::sin(i * 0.01));
    samples["y_mm"].push_back(0.0);
    samples["theta_deg"].push_back(i * 0.5);
  }
  json trajectory = {{"format", thesis_format()}};
  trajectory["format"].erase("stroke_mm");
  trajectory["format"].erase("motion_time_s");
  trajectory["format"]["motion"] = samples;
  for (const json& body : {arc, trajectory}) {
    EXPECT_TRUE(validation_errors("SimulateRequest", body).empty())
        << joined(validation_errors("SimulateRequest", body));
    const json out = simulate_response(body);
    expect_top_level_keys("SimulateResponse", out);
    const auto errors = validation_errors("SimulateResponse", out);
    EXPECT_TRUE(errors.empty()) << joined(errors);
  }
}

TEST(OpenApiResponses, ErrorEnvelopeFluidsAndExamplesFitTheirSchemas) {
  // A real 422 from the parser.
  json bad = thesis_plan("notch");
  bad["format"]["container"]["radius_mm"] = -3;
  try {
    (void)parse_plan_request(bad);
    ADD_FAILURE() << "accepted";
  } catch (const ApiError& e) {
    const auto errors = validation_errors("ErrorEnvelope", error_envelope(e));
    EXPECT_TRUE(errors.empty()) << joined(errors);
  }
  // A malformed body: field null.
  try {
    (void)parse_json_body("{\"format\": ");
    ADD_FAILURE() << "accepted";
  } catch (const ApiError& e) {
    const json envelope = error_envelope(e);
    EXPECT_TRUE(envelope["error"]["field"].is_null());
    const auto errors = validation_errors("ErrorEnvelope", envelope);
    EXPECT_TRUE(errors.empty()) << joined(errors);
  }
  // The codes of the enum are exactly those of ErrorCode: every error the service sends is
  // documented, including the ones of the HTTP layer (405, 408, 415, 501, ...).
  std::set<std::string> documented;
  for (const auto& code : schema("Error")["properties"]["code"]["enum"]) {
    documented.insert(code.get<std::string>());
  }
  std::set<std::string> codes;
  std::set<int> statuses;
  for (const ErrorCodeInfo& row : kErrorCodes) {
    codes.insert(std::string(row.name));
    statuses.insert(row.status);
  }
  EXPECT_EQ(documented, codes);
  EXPECT_EQ(statuses, (std::set<int>{400, 404, 405, 408, 409, 413, 414, 415, 416, 422, 431, 499,
                                     500, 501, 503, 504}));

  const auto fluid_errors = validation_errors("FluidsResponse", fluids_json());
  EXPECT_TRUE(fluid_errors.empty()) << joined(fluid_errors);

  // The examples are valid requests, for the schema and for the parser.
  const json plan_example = schema("PlanRequest")["example"];
  const auto plan_errors = validation_errors("PlanRequest", plan_example);
  EXPECT_TRUE(plan_errors.empty()) << joined(plan_errors);
  EXPECT_NO_THROW((void)parse_plan_request(plan_example));
  const json simulate_example = schema("SimulateRequest")["example"];
  const auto simulate_errors = validation_errors("SimulateRequest", simulate_example);
  EXPECT_TRUE(simulate_errors.empty()) << joined(simulate_errors);
  EXPECT_NO_THROW((void)parse_simulate_request(simulate_example));
  // And a typo is caught by the schema as by the parser.
  json typo = plan_example;
  typo["format"]["container"]["radius"] = 48.5;
  EXPECT_FALSE(validation_errors("PlanRequest", typo).empty());
  EXPECT_THROW((void)parse_plan_request(typo), ApiError);
}

}  // namespace test_openapi
}  // namespace slosh::api

namespace slosh::api {
namespace test_openapi {

// Along an arc a plan and a min-time search echo the canonical motion in their format: every
// member documented (FormatEcho's motion), the echo holding the motion.
TEST(OpenApiResponses, PlansAndSearchesAlongAnArcEchoTheirMotion) {
  const json arc{{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}};
  json body = thesis_plan("notch");
  body["format"].erase("stroke_mm");
  body["format"]["motion"] = arc;
  const json plan = run_plan(parse_plan_request(body));
  ASSERT_TRUE(plan["format"].contains("motion")) << plan["format"].dump();
  EXPECT_EQ(plan["format"]["motion"]["radius_mm"], 300);
  const auto errors = validation_errors("PlanResponse", plan);
  EXPECT_TRUE(errors.empty()) << joined(errors);
  const auto echo_errors = validation_errors("FormatEcho", plan["format"]);
  EXPECT_TRUE(echo_errors.empty()) << joined(echo_errors);
  // The compact plans: an arc as it is, a path summarised.
  const auto compact_errors = validation_errors("CompactPlan", compact_plan(plan));
  EXPECT_TRUE(compact_errors.empty()) << joined(compact_errors);
  body["format"]["motion"] = json::parse(R"({"type": "path", "segments": [{"line_mm": 200},
      {"arc": {"radius_mm": 150, "angle_deg": 90}}, {"line_mm": 150},
      {"arc": {"radius_mm": 120, "angle_deg": -60}}]})");
  const json compact_path = compact_plan(run_plan(parse_plan_request(body)));
  ASSERT_EQ(compact_path["law"]["motion"]["segment_count"], 4);
  const auto path_errors = validation_errors("CompactPlan", compact_path);
  EXPECT_TRUE(path_errors.empty()) << joined(path_errors);

  json search{{"format",
               {{"container", {{"radius_mm", 48.5}, {"height_mm", 150}}},
                {"fill_height_mm", 82},
                {"fluid", "water"},
                {"motion", arc}}},
              {"strategies", {"baseline"}},
              {"motion_time_max_s", 3.0}};
  const json out = run_min_time(parse_min_time_request(search, 10.0));
  ASSERT_TRUE(out["format"].contains("motion")) << out["format"].dump();
  const auto search_errors = validation_errors("MinTimeResponse", out);
  EXPECT_TRUE(search_errors.empty()) << joined(search_errors);
}

// A rectangular container along an arc and a trajectory: simulate (with its series), plan and
// min-time answers fit their schemas.
TEST(OpenApiResponses, RectangularContainersAlongSpatialMotionsFitTheirSchemas) {
  const json cup{{"shape", "rectangular"},
                 {"length_mm", 120},
                 {"width_mm", 80},
                 {"height_mm", 150},
                 {"orientation_deg", 30}};
  const json arc{{"type", "arc"}, {"radius_mm", 300}, {"angle_deg", 90}, {"container_turns", true}};
  json simulate = {{"format",
                    {{"container", cup},
                     {"fill_height_mm", 50},
                     {"fluid", "water"},
                     {"motion_time_s", 1.5},
                     {"motion", arc}}},
                   {"law", {{"type", "seven_segment_uniform"}}},
                   {"sample_period_s", 0.01}};
  json samples = {{"type", "trajectory"},
                  {"t_s", json::array()},
                  {"x_mm", json::array()},
                  {"y_mm", json::array()},
                  {"theta_deg", json::array()}};
  for (int i = 0; i <= 100; ++i) {
    samples["t_s"].push_back(i * 0.01);
    samples["x_mm"].push_back(50.0 * std::sin(i * 0.01));
    samples["y_mm"].push_back(0.0);
    samples["theta_deg"].push_back(i * 0.5);
  }
  json trajectory = {
      {"format",
       {{"container", cup}, {"fill_height_mm", 50}, {"fluid", "water"}, {"motion", samples}}}};
  for (const json& body : {simulate, trajectory}) {
    const json out = simulate_response(body);
    ASSERT_TRUE(out["prediction"].contains("directions")) << out.dump();
    const auto errors = validation_errors("SimulateResponse", out);
    EXPECT_TRUE(errors.empty()) << joined(errors);
  }
  json plan_body = {{"format",
                     {{"container", cup},
                      {"fill_height_mm", 50},
                      {"fluid", "water"},
                      {"motion_time_s", 1.5},
                      {"motion", arc}}},
                    {"strategy", "auto"}};
  const json plan = run_plan(parse_plan_request(plan_body));
  EXPECT_NE(plan["message"].get<std::string>().find("the tank's models"), std::string::npos)
      << plan["message"];
  const auto plan_errors = validation_errors("PlanResponse", plan);
  EXPECT_TRUE(plan_errors.empty()) << joined(plan_errors);
  json search{
      {"format", {{"container", cup}, {"fill_height_mm", 50}, {"fluid", "water"}, {"motion", arc}}},
      {"strategies", {"baseline"}},
      {"motion_time_max_s", 3.0}};
  const json out = run_min_time(parse_min_time_request(search, 10.0));
  const auto search_errors = validation_errors("MinTimeResponse", out);
  EXPECT_TRUE(search_errors.empty()) << joined(search_errors);
}

TEST(OpenApiResponses, MinTimeResponsesFitTheMinTimeResponseSchema) {
  // A feasible search (with its plan) and an infeasible one (the best point and its plan).
  json body{{"format",
             {{"container", {{"radius_mm", 48.5}, {"height_mm", 150}}},
              {"fill_height_mm", 82},
              {"fluid", "water"},
              {"stroke_mm", 800}}},
            {"strategies", {"shaper", "baseline"}},
            {"motion_time_max_s", 1.0},
            {"eta_rest_max_mm", 0.5}};
  const json out = run_min_time(parse_min_time_request(body, 10.0));
  expect_top_level_keys("MinTimeResponse", out);
  const auto errors = validation_errors("MinTimeResponse", out);
  EXPECT_TRUE(errors.empty()) << joined(errors);
  ASSERT_EQ(out["strategies"].size(), 2u);
  for (const json& s : out["strategies"]) {
    expect_top_level_keys("MinTimeStrategyResult", s);
    ASSERT_TRUE(s["plan"].is_object()) << s["strategy"];
    const auto plan_errors = validation_errors("PlanResponse", s["plan"]);
    EXPECT_TRUE(plan_errors.empty()) << joined(plan_errors);
  }
  EXPECT_EQ(out["strategies"][1]["status"], "infeasible");  // uniform law, eta_rest <= 0.5 mm
  EXPECT_TRUE(out["strategies"][1]["best"].is_object());
  // The request schema is closed and lists exactly what the parser accepts at the top level.
  const json& request = schema("MinTimeRequest");
  EXPECT_EQ(request["additionalProperties"], false);
  json probe = body;
  probe["zzz"] = 1;
  std::string allowed;
  try {
    (void)parse_min_time_request(probe, 10.0);
  } catch (const ApiError& e) {
    allowed = e.what();
  }
  const std::string prefix = "zzz is not a known field; allowed here: ";
  ASSERT_EQ(allowed.rfind(prefix, 0), 0u) << allowed;
  std::set<std::string> parser, documented;
  std::string list = allowed.substr(prefix.size()) + ", ";
  for (std::size_t at = 0, comma; (comma = list.find(", ", at)) != std::string::npos;
       at = comma + 2) {
    parser.insert(list.substr(at, comma - at));
  }
  for (const auto& [key, value] : request["properties"].items()) documented.insert(key);
  EXPECT_EQ(parser, documented);
}

}  // namespace test_openapi
}  // namespace slosh::api
