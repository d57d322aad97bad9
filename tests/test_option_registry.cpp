// The option registry: one entry per plan option drives the parser, the recipe key,
// the OpenAPI document and the CSV recipe columns. A fake option added to a copy of the registry
// must be parsed, keyed, documented and read from a CSV column without any other change; the
// recipe keys of the built-in options are pinned to the values computed before the registry
// (a changed key would invalidate every cached plan).

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/recipe_table.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/openapi.hpp"
#include "slosh/api/option_registry.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/recipe_row.hpp"
#include "slosh/api/routes.hpp"

namespace slosh::api {
namespace test_option_registry {

using nlohmann::json;

const char* kFormat =
    R"({"container": {"radius_mm": 48.5, "height_mm": 150}, "fill_height_mm": 82,
        "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0})";

json request(const std::string& rest = "") {
  return json::parse(std::string(R"({"format": )") + kFormat + rest + "}");
}

// The recipe part of the keys, computed with the code before the registry (commit 3f8474d):
// identical requests must keep identical recipes. The key is the SHA-256 of that recipe with the
// slosh version added: the digest of the canonical recipe without "slosh_version" is
// still the key of commit 3f8474d, and the key is the digest of it with "slosh_version":
// kVersion. The planner version in the recipe is "plan-v18" since a turned tank's design over
// both directions that rests above the uniform law gives way to a direction's own that rests
// lower; "plan-v17" was since a turned tank's design over
// both directions that is not usable gives way to a direction's own design and two first modes
// within 0.1 % of each other are notched double; "plan-v16" was since a bound met on a rectangular
// tank's linear figures standing in keeps time_domain and auto from optimal, the modal sum's
// convergence is said and a plan past its budget is time_limit; "plan-v15" was since a
// rectangular tank's steepness warning judges each direction on its own side, a fill height range
// beyond the models is said and an acceptable plan says why; "plan-v14" was since
// worse_than_baseline and auto's ranking compare the linear figures when a rectangular tank's
// nonlinear model holds for some of the laws only; "plan-v13" was since the reductions compare one
// model (both laws' linear figures) when a rectangular tank's nonlinear model holds for one of
// the plan's law and the uniform law only, and motion_too_short's floor bounds the linear
// eta_rest the plan reports; "plan-v12" was since every warning carries its kind
// (the plan's warning_codes), a wave deeper than the fill makes a plan `acceptable`, and a
// rectangular tank's motion is too short only when no law that moves one way can leave much less
// than the uniform law's residual wave; "plan-v11" was since a plan whose law spills, is
// worse than the uniform law or cannot act on a too short motion is `acceptable`, not `optimal`,
// and a rectangular tank's linear-theory warning judges the wave after the motion too; "plan-v10"
// was since fir_chain, iir, the shaper
// and min_jerk_band take a turned tank's second direction in by its engagement (its share of the
// residual wave over kFullDirectionShare) instead of in full from a 1e-8 share on; "plan-v9" was
// the strategies acting on both first modes of a turned rectangular tank, weighed by each
// direction's share, instead of designing at the middle of the two above a 5 % share; "plan-v8" was
// multi_notch leaving a run within 0.12 of the range of a poor optimum instead of 0.03 (an exact
// zero can then be another one, to 1e-14 of X_ref^2); "plan-v7" was time_domain's exchanged peaks
// as rows that follow their peak, on a line and along a path, and a robust time_domain plan's
// starting samples covering the whole rest window again ("plan-v6" was time_domain's starting
// samples of the rest window covering its first period only and multi_notch leaving a run at the
// mirror image of a known optimum and on its approach; "plan-v5" was time_domain's sensitivities as
// the scheme linearised in double instead of dual numbers, min_jerk_band's screening stopping its
// random starts once two in a row find nothing lower, every returned law keeping its bounds to the
// last ulp, filters without a law returning baseline's admissible law and the baseline guard
// comparing with that law; "plan-v4" was the spectral strategies' fewer starts and band rows,
// "plan-v3" the faster response schemes): the pinned keys are those of the same recipes with that
// version; everything else is unchanged.
std::string key_before_versions(const json& request) {
  json recipe = canonical_recipe(parse_plan_request(request));
  EXPECT_EQ(recipe.at("slosh_version"), kVersion);
  EXPECT_EQ(recipe_key(parse_plan_request(request)), sha256_key(recipe.dump()));
  recipe.erase("slosh_version");
  return sha256_key(recipe.dump());
}

TEST(OptionRegistry, RecipeKeysAreThoseBeforeTheRegistry) {
  EXPECT_EQ(key_before_versions(request()), "277473a48d3e3056c6f3283cc1bb34d1");
  EXPECT_EQ(key_before_versions(request(R"(, "strategy": "multi_notch")")),
            "7c1eb1ee1ee0fbfd2c8910955db900ac");
  EXPECT_EQ(key_before_versions(request(R"(, "options": {"damping": {"zeta": 0.1}})")),
            "7f723269d70c1d3dee89abf51c6ad94d");
  EXPECT_EQ(key_before_versions(request(R"(, "options": {"limits": {"a_max": 10}})")),
            "bcc72e24444cf42d33cd2e97a489381c");
  EXPECT_EQ(key_before_versions(request(
                R"(, "sample_period_s": 0.001, "options": {"p_notch": 0.2, "weights": [1, 2, 3],
                "band": 0.1, "n_band": 31, "tol_rel": 0.3, "eta_rest_max_mm": 2.5,
                "eta_motion_max_mm": 7, "objective": "rest", "rest_time_s": 2, "min_ramp_s": 0.04,
                "fix_constant_velocity_zero": true, "plateau_min_s": [0.01, 0.02],
                "limits": {"a_max": 10, "v_max": 3, "j_max": 250}, "damping": "paper",
                "alpha": 0.5, "modes": 2, "solver": "ipopt", "time_limit_s": 3,
                "base": "modified_trapezoid", "shaper": "ei", "residual": 0.1, "iir_order": 2,
                "iir_tau": 40, "iir_sample_period_s": 0.002})")),
            "bce8bc62a0523026e12e5312e7059163");
  EXPECT_EQ(key_before_versions(json::parse(
                R"({"format": {"container": {"radius_mm": 30}, "fill_height_mm": 40,
                "fluid": {"density_kg_m3": 1100, "viscosity_pa_s": 0.002, "name": "syrup"},
                "stroke_mm": 250.5, "motion_time_s": 0.7}, "strategy": "time_domain",
                "options": {"objective": "rest", "eta_motion_max_mm": 4.5,
                "limits": {"j_max": 300}}})")),
            "1b13006c2e0272b0860a9043cfb0c1dc");
}

TEST(OptionRegistry, ListsEveryOptionOnceInTheApiOrder) {
  const OptionRegistry& registry = plan_option_registry();
  const std::vector<std::string_view> keys = registry.option_keys();
  const std::vector<std::string_view> expected{"p_notch",
                                               "weights",
                                               "band",
                                               "n_band",
                                               "tol_rel",
                                               "eta_rest_max_mm",
                                               "eta_motion_max_mm",
                                               "objective",
                                               "rest_time_s",
                                               "min_ramp_s",
                                               "fix_constant_velocity_zero",
                                               "plateau_min_s",
                                               "limits",
                                               "drive_profile",
                                               "damping",
                                               "alpha",
                                               "modes",
                                               "solver",
                                               "time_limit_s",
                                               "base",
                                               "shaper",
                                               "residual",
                                               "iir_order",
                                               "iir_tau",
                                               "iir_sample_period_s",
                                               "robustness",
                                               "uncertainty",
                                               "model"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(registry.group_keys("limits"),
            (std::vector<std::string_view>{"a_max", "v_max", "j_max"}));
  EXPECT_EQ(registry.group_keys("uncertainty"),
            (std::vector<std::string_view>{"omega_error_pct", "fill_height_mm", "viscosity_pa_s",
                                           "sample_points"}));
  EXPECT_EQ(registry.group_keys("model"),
            (std::vector<std::string_view>{"omega_scale", "zeta", "alpha", "height_gain",
                                           "width_omega_scale", "width_zeta"}));
  std::set<std::string_view> recipe_names;
  for (const OptionSpec& o : registry.options()) {
    if (o.name == "time_limit_s") {
      EXPECT_TRUE(o.recipe_name.empty());  // the budget is not part of the recipe
    } else if (o.group == "model" && (o.name == "zeta" || o.name == "alpha")) {
      EXPECT_TRUE(o.recipe_name.empty());  // keyed as options.damping and options.alpha
    } else {
      EXPECT_TRUE(recipe_names.insert(o.recipe_name).second) << o.recipe_name;
    }
    EXPECT_TRUE(o.get && o.set) << o.name;
    EXPECT_FALSE(o.doc.empty()) << o.name;
  }
}

// ---- a fake option: one registry entry, nothing else -------------------------------------------

struct Sink {
  std::optional<double> value;  // SI (m)
};

OptionRegistry with_fake_option(Sink& sink) {
  OptionRegistry registry = plan_option_registry();
  OptionSpec fake;
  fake.name = "fake_gap_mm";
  fake.recipe_name = "fake_gap_m";
  fake.kind = OptionKind::kOptionalNumber;
  fake.range = Range{0.0, 50.0, "mm", true};
  fake.scale = 1e-3;
  fake.doc = "Fake option of the registry test: a gap";
  fake.get = [&sink](const PlanOptions&) { return sink.value ? json(*sink.value) : json(); };
  fake.set = [&sink](PlanOptions&, const json& v) { sink.value = v.get<double>(); };
  registry.add(fake);
  return registry;
}

TEST(OptionRegistry, AFakeOptionIsParsedWithTheStandardMessages) {
  Sink sink;
  const OptionRegistry registry = with_fake_option(sink);
  (void)parse_plan_request(request(R"(, "options": {"fake_gap_mm": 12.5})"), registry);
  ASSERT_TRUE(sink.value.has_value());
  EXPECT_DOUBLE_EQ(*sink.value, 0.0125);

  try {
    (void)parse_plan_request(request(R"(, "options": {"fake_gap_mm": 80})"), registry);
    FAIL() << "out of range accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field(), "options.fake_gap_mm");
    EXPECT_STREQ(e.what(), "options.fake_gap_mm = 80 is out of range: allowed > 0 and <= 50 mm");
  }
  // The built-in registry does not know it: the standard unknown-field message.
  try {
    (void)parse_plan_request(request(R"(, "options": {"fake_gap_mm": 12.5})"));
    FAIL() << "unknown option accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field(), "options.fake_gap_mm");
    EXPECT_NE(std::string(e.what()).find("is not a known field; allowed here: p_notch, weights"),
              std::string::npos)
        << e.what();
  }
}

TEST(OptionRegistry, AFakeOptionIsKeyed) {
  Sink sink;
  const OptionRegistry registry = with_fake_option(sink);
  const PlanRequest a = parse_plan_request(request(R"(, "options": {"fake_gap_mm": 5})"), registry);
  const json recipe = canonical_recipe(a, registry);
  EXPECT_EQ(recipe["options"]["fake_gap_m"], 0.005);
  const std::string key_a = recipe_key(a, registry);
  const PlanRequest b = parse_plan_request(request(R"(, "options": {"fake_gap_mm": 6})"), registry);
  EXPECT_NE(recipe_key(b, registry), key_a);
  sink.value = 0.005;
  EXPECT_EQ(recipe_key(b, registry), key_a);
}

TEST(OptionRegistry, AFakeOptionIsDocumented) {
  Sink sink;
  const json doc = openapi_document("test", with_fake_option(sink));
  const json& s = doc["components"]["schemas"]["PlanOptions"]["properties"]["fake_gap_mm"];
  EXPECT_EQ(s["type"], "number");
  EXPECT_EQ(s["minimum"], 0.0);
  EXPECT_EQ(s["maximum"], 50.0);
  EXPECT_EQ(s["exclusiveMinimum"], true);
  EXPECT_FALSE(s.contains("default"));  // unset by default
  EXPECT_EQ(s["description"],
            "Fake option of the registry test: a gap [mm]. Allowed: > 0 and <= 50 mm.");
  EXPECT_FALSE(
      openapi_document("test")["components"]["schemas"]["PlanOptions"]["properties"].contains(
          "fake_gap_mm"));
}

TEST(OptionRegistry, AFakeOptionIsACsvColumn) {
  Sink sink;
  const OptionRegistry registry = with_fake_option(sink);
  EXPECT_NE(recipe_column_names(registry).find(", fake_gap_mm"), std::string::npos);
  const std::string table =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy,fake_gap_mm\n"
      "a,48.5,82,water,800,1,auto,7.5\n"
      "b,48.5,82,water,800,1,auto,wide\n";
  const auto rows = service::read_recipe_table(table, service::TableFormat::kCsv, registry);
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_FALSE(rows[0].error.has_value()) << rows[0].error->what();
  EXPECT_EQ(rows[0].request.body()["options"]["fake_gap_mm"], 7.5);
  (void)parse_plan_request(rows[0].request.body(), registry);
  EXPECT_DOUBLE_EQ(sink.value.value(), 0.0075);
  // A cell that is not a number reaches the request as its text, which the option's own parser
  // refuses with its range (as it refuses that JSON value).
  ASSERT_FALSE(rows[1].error.has_value()) << rows[1].error->what();
  EXPECT_EQ(rows[1].request.body()["options"]["fake_gap_mm"], "wide");
  try {
    (void)parse_plan_request(rows[1].request.body(), registry);
    ADD_FAILURE() << "a gap of \"wide\" was parsed";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field(), "options.fake_gap_mm");
    EXPECT_STREQ(e.what(),
                 "options.fake_gap_mm must be a number, got \"wide\"; allowed > 0 and "
                 "<= 50 mm");
  }
  EXPECT_EQ(column_of_field("options.fake_gap_mm", registry), "fake_gap_mm");
  // The built-in registry has no such column.
  EXPECT_THROW((void)service::read_recipe_table(table, service::TableFormat::kCsv),
               service::TableError);
}

TEST(OptionRegistry, DefaultsOfTheSchemasAreThoseOfPlanOptions) {
  const json doc = openapi_document("test");
  const json& p = doc["components"]["schemas"]["PlanOptions"]["properties"];
  const PlanOptions d;
  EXPECT_EQ(p["p_notch"]["default"], d.p_notch);
  EXPECT_EQ(p["eta_rest_max_mm"]["default"], d.eta_rest_max * 1e3);
  EXPECT_EQ(p["iir_order"]["default"], static_cast<int>(d.iir_order));
  EXPECT_EQ(p["objective"]["default"], "motion");
  EXPECT_EQ(p["limits"]["oneOf"][0]["$ref"], "#/components/schemas/MachineLimits");
}

TEST(OptionRegistry, EveryOptionIsDocumentedAndACsvColumn) {
  const json doc = openapi_document("test");
  const json& schemas = doc["components"]["schemas"];
  const std::string columns = recipe_column_names();
  for (const OptionSpec& o : plan_option_registry().options()) {
    const std::string schema =
        o.group.empty() ? "PlanOptions"
                        : std::string(plan_option_registry().group(o.group)->schema_name);
    EXPECT_TRUE(schemas[schema]["properties"].contains(std::string(o.name))) << o.name;
    // The members of options.uncertainty are prefixed (fill_height_mm is also the format's), and
    // so are those of options.model (alpha is also an option of its own).
    const std::string column = (o.group == "uncertainty" ? "uncertainty_"
                                : o.group == "model"     ? "model_"
                                                         : "") +
                               std::string(o.name);
    EXPECT_NE(columns.find(", " + column), std::string::npos) << column;
  }
}

// ---- routes ------------------------------------------------------------------------------------

TEST(Routes, EveryRouteIsAnOpenApiOperation) {
  const json paths = openapi_document("test")["paths"];
  std::size_t operations = 0;
  for (const auto& [path, methods] : paths.items()) operations += methods.size();
  EXPECT_EQ(routes().size(), operations);
  // The API, min-time, the cam tables (CSV, ST), the page, assets, the batch jobs (5),
  // calibrations (POST, GET).
  EXPECT_EQ(routes().size(), 21u);
  std::set<Operation> seen;
  for (const Route& r : routes()) {
    const std::string method = r.method == "POST"     ? "post"
                               : r.method == "DELETE" ? "delete"
                                                      : "get";
    ASSERT_TRUE(paths.contains(std::string(r.path))) << r.path;
    const json& op = paths[std::string(r.path)][method];
    EXPECT_EQ(op["operationId"], r.operation_id);
    EXPECT_EQ(op["summary"], r.summary);
    EXPECT_TRUE(seen.insert(r.operation).second);
  }
  EXPECT_EQ(routes().front().path, "/v1/plans");
  EXPECT_EQ(routes()[2].path, "/v1/plans/{key}");
  EXPECT_EQ(routes()[2].method, "GET");
}

}  // namespace test_option_registry
}  // namespace slosh::api
