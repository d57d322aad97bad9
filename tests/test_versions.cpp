// Every plan states the slosh version that made it; the version is part of the recipe
// and min-time keys and of each row of the plan store, so an upgrade never serves an older
// planner's plan; `slosh --version`, GET /healthz and the plans agree with the project version of
// CMakeLists.txt. The keys are checked against a SHA-256 computed here (OpenSSL), the store through
// a SQLite connection of the test's own, the version against the build's source of truth.

#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <sqlite3.h>

#include <cstdio>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "cache/plan_cache.hpp"
#include "http/plan_service.hpp"
#include "slosh/api/min_time.hpp"
#include "slosh/api/plan.hpp"
#include "slosh/api/plan_reply.hpp"
#include "slosh/version.hpp"
#include "support/process.hpp"
#include "support/server.hpp"
#include "support/sqlite_query.hpp"

namespace slosh {
namespace test_versions {

using nlohmann::json;
using test::query;

constexpr const char* kOtherVersion = "0.0.1-older";

json thesis_request(const std::string& strategy = "multi_notch") {
  return json::parse(R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
                                    "fill_height_mm": 82, "fluid": "water",
                                    "stroke_mm": 800, "motion_time_s": 1.0},
                         "strategy": ")" +
                     strategy + R"("})");
}

/// The first 32 hex digits of the SHA-256 of `text`, computed here.
std::string sha256_32(const std::string& text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr);
  std::string hex;
  char byte[3];
  for (unsigned int i = 0; i < 16; ++i) {
    std::snprintf(byte, sizeof byte, "%02x", digest[i]);
    hex += byte;
  }
  return hex;
}

/// The project version CMakeLists.txt declares: the build's source of truth.
std::string project_version() {
  const std::string cmake = test::read_file(std::string(SLOSH_SOURCE_DIR) + "/CMakeLists.txt");
  std::smatch m;
  const std::regex declared(R"(project\(slosh VERSION ([0-9][0-9A-Za-z.+-]*))");
  return std::regex_search(cmake, m, declared) ? m[1].str() : "<none>";
}

using test::execute;

// ---- the keys -------------------------------------------------------------------------------

// The canonical text of the thesis recipe, pinned: the format in SI units (48.5 mm = 0.0485 m),
// every option with its default (SI), the strategy, the planner's numerics version and the slosh
// version. The key is its digest: a new version is a new key for every recipe.
TEST(Versions, TheRecipeKeyIsTheDigestOfTheCanonicalTextWithTheSloshVersion) {
  const api::PlanRequest request = api::parse_plan_request(thesis_request());
  const std::string expected =
      R"({"format":{"density_kg_m3":998.2,"fill_height_m":0.082,"fluid_name":"water",)"
      R"("height_m":0.15,"motion_time_s":1.0,"radius_m":0.0485,"stroke_m":0.8,)"
      R"("viscosity_pa_s":0.0010016},"options":{"a_max":null,"alpha":0.58,"band":0.15,)"
      R"("base":"poly5","damping":"thesis","eta_motion_max_m":null,"eta_rest_max_m":0.003,)"
      R"("fix_constant_velocity_zero":false,"iir_order":3,"iir_sample_period_s":0.001,)"
      R"("iir_tau":50.0,"j_max":null,"min_ramp_s":0.05,"modes":3,"n_band":51,)"
      R"("objective":"motion","p_notch":0.15,"plateau_min_s":[0.0,0.0],"residual":0.05,)"
      R"("rest_time_s":1.0,"shaper":"zv","solver":"auto","tol_rel":0.2,"v_max":null,)"
      R"("weights":[1.0,1.0,1.0]},"slosh_version":")" +
      std::string(kVersion) + R"(","strategy":"multi_notch","version":"plan-v18"})";
  EXPECT_EQ(api::canonical_recipe(request).dump(), expected);
  EXPECT_EQ(api::recipe_key(request), sha256_32(expected));
  // Planned by another version: the same recipe, another key.
  std::string other = expected;
  other.replace(other.find(std::string("\"") + kVersion + "\""), std::string(kVersion).size() + 2,
                std::string("\"") + kOtherVersion + "\"");
  EXPECT_EQ(api::recipe_key(request, api::plan_option_registry(), kOtherVersion), sha256_32(other));
  EXPECT_NE(api::recipe_key(request, api::plan_option_registry(), kOtherVersion),
            api::recipe_key(request));
}

TEST(Versions, TheMinTimeKeyHoldsTheVersion) {
  const json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800}, "eta_motion_max_mm": 40})");
  const api::MinTimeRequest request = api::parse_min_time_request(body, 10.0);
  EXPECT_NE(api::min_time_key(request, kOtherVersion), api::min_time_key(request));
  EXPECT_EQ(api::min_time_key(request, kVersion), api::min_time_key(request));
}

TEST(Versions, EveryPlanAndMinTimeAnswerStatesTheVersion) {
  const json plan = api::run_plan(api::parse_plan_request(thesis_request("notch")));
  EXPECT_EQ(plan.at("version"), kVersion);
  EXPECT_EQ(plan.at("version"), project_version());
  // The stored plan keeps it (what the cache serves later).
  const api::StoredPlan stored = api::solve_for_storing(api::parse_plan_request(thesis_request()));
  EXPECT_EQ(json::parse(stored.body).at("version"), kVersion);
  const json body = json::parse(R"({"format": {"container": {"radius_mm": 48.5},
      "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800}, "eta_motion_max_mm": 40,
      "strategies": ["baseline"], "motion_time_max_s": 1.2})");
  const json answer = api::run_min_time(api::parse_min_time_request(body, 10.0));
  EXPECT_EQ(answer.at("version"), kVersion);
  ASSERT_TRUE(answer["strategies"][0]["plan"].is_object());
  EXPECT_EQ(answer["strategies"][0]["plan"]["version"], kVersion);
}

// ---- the plan store -------------------------------------------------------------------------

class VersionedStore : public ::testing::Test {
 protected:
  test::TempDir dir_;
  [[nodiscard]] std::string path() const { return (dir_ / "plans.sqlite").string(); }
};

// The digest of a row as the store writes it: of the key, the version and the body (checked
// against a row the store wrote below, so the rewrite test forges a row the store accepts as
// intact).
std::string row_digest(const std::string& key, const std::string& version,
                       const std::string& body) {
  return sha256_32(key + "\n" + version + "\n" + body);
}

TEST_F(VersionedStore, ARowWrittenByAnotherVersionIsNeverServed) {
  for (service::CacheTable table : {service::CacheTable::kPlans, service::CacheTable::kMinTime}) {
    SCOPED_TRACE(table == service::CacheTable::kPlans ? "plans" : "min_times");
    const std::string file = (dir_ / (table == service::CacheTable::kPlans ? "p" : "m")).string();
    {
      service::PlanCache older({.path = file, .table = table, .version = kOtherVersion});
      older.put("k", R"({"key":"k","by":"older"})");
      EXPECT_EQ(older.get("k"), R"({"key":"k","by":"older"})");
    }
    {
      service::PlanCache current({.path = file, .table = table});
      EXPECT_EQ(current.get("k"), std::nullopt);
      EXPECT_TRUE(current.storage_error().empty()) << current.storage_error();  // not a failure
      current.put("k", R"({"key":"k","by":"current"})");
      EXPECT_EQ(current.get("k"), R"({"key":"k","by":"current"})");
    }
    const std::string name = table == service::CacheTable::kPlans ? "plans" : "min_times";
    EXPECT_EQ(query(file, "SELECT version FROM " + name + " WHERE key = 'k'"), kVersion);
    // And the other way round: the older slosh does not serve the current one's answer.
    service::PlanCache older({.path = file, .table = table, .version = kOtherVersion});
    EXPECT_EQ(older.get("k"), std::nullopt);
  }
}

TEST_F(VersionedStore, ARowWhoseVersionIsRewrittenOnDiskIsNeverServed) {
  const std::string body = R"({"key":"k","marker":1})";
  {
    service::PlanCache cache({.path = path()});
    cache.put("k", body);
  }
  // The test's digest is the store's (so the forged row below passes the digest check).
  ASSERT_EQ(query(path(), "SELECT digest FROM plans WHERE key = 'k'"),
            row_digest("k", kVersion, body));
  ASSERT_EQ(query(path(), "SELECT version FROM plans WHERE key = 'k'"), kVersion);

  // Only the version changed: the digest catches it, the row is dropped.
  execute(path(), std::string("UPDATE plans SET version = '") + kOtherVersion + "'");
  {
    service::PlanCache cache({.path = path(), .memory_entries = 0});
    EXPECT_EQ(cache.get("k"), std::nullopt);
    EXPECT_NE(cache.storage_error().find("do not match their digest"), std::string::npos)
        << cache.storage_error();
    EXPECT_EQ(query(path(), "SELECT count(*) FROM plans"), "0");
    cache.put("k", body);
  }
  // Version and digest rewritten consistently (a row of another version, intact): not served
  // either, and kept for that version.
  execute(path(), std::string("UPDATE plans SET version = '") + kOtherVersion + "', digest = '" +
                      row_digest("k", kOtherVersion, body) + "'");
  service::PlanCache cache({.path = path(), .memory_entries = 0});
  EXPECT_EQ(cache.get("k"), std::nullopt);
  EXPECT_TRUE(cache.storage_error().empty()) << cache.storage_error();
  EXPECT_EQ(query(path(), "SELECT count(*) FROM plans"), "1");
  service::PlanCache older({.path = path(), .memory_entries = 0, .version = kOtherVersion});
  EXPECT_EQ(older.get("k"), body);
}

TEST_F(VersionedStore, ALayoutThreeStoreIsEmptiedOnUpgrade) {
  // A store of the slosh before versions (layout 3: digests of key and body, no version), with
  // rows intact by its own rule: whichever planner made them, they are not served.
  const std::string body = R"({"key":"k"})";
  execute(path(),
          "CREATE TABLE plans(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER NOT "
          "NULL, digest TEXT NOT NULL DEFAULT '');"
          "CREATE TABLE min_times(key TEXT PRIMARY KEY, body TEXT NOT NULL, created_unix INTEGER "
          "NOT NULL, digest TEXT NOT NULL DEFAULT '');"
          "INSERT INTO plans VALUES('k', '" +
              body + "', 1, '" + sha256_32("k\n" + body) +
              "');"
              "INSERT INTO min_times VALUES('m', '{}', 1, '" +
              sha256_32("m\n{}") + "'); PRAGMA user_version = 3");
  {
    service::PlanCache plans({.path = path()});
    EXPECT_TRUE(plans.storage_error().empty()) << plans.storage_error();
    EXPECT_EQ(plans.get("k"), std::nullopt);
    service::PlanCache min_times({.path = path(), .table = service::CacheTable::kMinTime});
    EXPECT_EQ(min_times.get("m"), std::nullopt);
    plans.put("k", body);
  }
  EXPECT_EQ(query(path(), "PRAGMA user_version"), "4");
  EXPECT_EQ(query(path(), "SELECT count(*) FROM min_times"), "0");
  EXPECT_EQ(query(path(), "SELECT version FROM plans WHERE key = 'k'"), kVersion);
  service::PlanCache reopened({.path = path(), .memory_entries = 0});  // layout 4 is kept
  EXPECT_EQ(reopened.get("k"), body);
}

// An upgrade with the store of an older slosh: its plan of the same recipe (even one stored under
// the key the current slosh computes) is neither served by POST nor by GET.
TEST_F(VersionedStore, AServiceNeverAnswersWithAnOlderPlannersPlan) {
  const api::PlanRequest request = api::parse_plan_request(thesis_request("notch"));
  const std::string old_key = api::recipe_key(request, api::plan_option_registry(), kOtherVersion);
  const std::string new_key = api::recipe_key(request);
  const std::string forged = R"({"key":")" + new_key + R"(","version":")" + kOtherVersion +
                             R"(","marker":"older planner"})";
  {
    service::PlanCache older({.path = path(), .version = kOtherVersion});
    older.put(old_key, R"({"key":")" + old_key + R"(","marker":"older planner"})");
    older.put(new_key, forged);
  }
  service::ServerConfig config;
  config.cache_path = path();
  config.workers = 1;
  service::PlanService service(config);
  EXPECT_EQ(service.get_plan(old_key, "").status, 404);
  EXPECT_EQ(service.get_plan(new_key, "").status, 404);
  const service::Reply reply = service.post_plan(thesis_request("notch").dump(), "");
  ASSERT_EQ(reply.status, 200) << reply.body;
  const json plan = json::parse(reply.body);
  EXPECT_EQ(plan["cached"], false);
  EXPECT_EQ(plan["key"], new_key);
  EXPECT_EQ(plan["version"], kVersion);
  EXPECT_FALSE(plan.contains("marker"));
  EXPECT_EQ(query(path(), "SELECT version FROM plans WHERE key = '" + new_key + "'"), kVersion);
}

// ---- the binary and the server agree ----------------------------------------------------------

TEST(Versions, TheBinaryTheServerAndThePlansStateTheProjectVersion) {
  const std::string version = project_version();
  ASSERT_NE(version, "<none>");
  EXPECT_EQ(version, kVersion);
  const test::RunResult printed = test::run_slosh({"--version"});
  EXPECT_EQ(printed.exit_code, 0);
  EXPECT_EQ(printed.out, "slosh " + version + "\n");

  test::Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client client = server.client();
  const auto health = client.Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(json::parse(health->body).at("version"), version);
  const auto plan = client.Post("/v1/plans", thesis_request("notch").dump(), "application/json");
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->status, 200) << plan->body;
  EXPECT_EQ(json::parse(plan->body).at("version"), version);
  const auto openapi = client.Get("/v1/openapi.json");
  ASSERT_TRUE(openapi);
  EXPECT_EQ(json::parse(openapi->body)["info"]["version"], version);
  // The plan store's row records it too.
  const std::string key = json::parse(plan->body).at("key");
  EXPECT_EQ(server.stop(), 0);
  EXPECT_EQ(
      query(server.cache_file().string(), "SELECT version FROM plans WHERE key = '" + key + "'"),
      version);

  const test::RunResult cli =
      test::run_slosh({"plan", "--request", "-"}, thesis_request("notch").dump());
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  EXPECT_EQ(json::parse(cli.out).at("version"), version);
}

}  // namespace test_versions
}  // namespace slosh
