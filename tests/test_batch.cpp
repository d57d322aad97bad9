// `slosh batch` end to end with the real binary: a seeded random recipe table with bad rows of
// every kind (exit 3, one output row per recipe in input order, error rows naming the column),
// every planned row checked against the in-process plan of the equivalent JSON request and
// against closed forms (plateau levels from an integration coded here, f1 from the dispersion
// relation), the SQLite cache on a re-run, RFC 4180 quoting (parsed by a reader written here),
// JSON lines in / JSON array out, the progress bar (file, forced, pseudo-terminal), --server
// against a real `slosh serve`, table-level errors, and POST /v1/plans/batch item by item.

#include <httplib.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slosh/api/plan.hpp"
#include "support/process.hpp"
#include "support/rfc4180.hpp"
#include "support/server.hpp"

extern char** environ;

namespace slosh {
namespace test_batch {

using nlohmann::json;
namespace fs = std::filesystem;
using test::Child;
using test::read_file;
using test::run_slosh;
using test::RunResult;
using test::Server;
using test::TempDir;
using test::write_file;

using test::Cell;
using test::parse_rfc4180;
using test::Record;

/// Quotes a cell for our own CSV writer when RFC 4180 requires it.
std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    out += c;
    if (c == '"') out += '"';
  }
  return out + "\"";
}

/// The documented columns of a plan table, in order.
const std::vector<std::string> kPlanColumns{"row",
                                            "recipe_id",
                                            "status",
                                            "key",
                                            "cached",
                                            "strategy",
                                            "law_type",
                                            "T1_s",
                                            "T2_s",
                                            "T3_s",
                                            "T4_s",
                                            "T5_s",
                                            "T6_s",
                                            "T7_s",
                                            "A_m_s2",
                                            "B_m_s2",
                                            "v_peak_m_s",
                                            "j_peak_m_s3",
                                            "f1_hz",
                                            "f1_length_hz",
                                            "f1_width_hz",
                                            "eta_motion_nonlinear_mm",
                                            "eta_rest_nonlinear_mm",
                                            "eta_motion_linear_mm",
                                            "eta_rest_linear_mm",
                                            "baseline_eta_motion_nonlinear_mm",
                                            "baseline_eta_rest_nonlinear_mm",
                                            "reduction_motion_pct",
                                            "reduction_rest_pct",
                                            "solve_ms",
                                            "message",
                                            "error_field",
                                            "version",
                                            "holds_from_pct",
                                            "holds_to_pct",
                                            "worst_eta_rest_mm",
                                            "container_shape",
                                            "length_mm",
                                            "width_mm",
                                            "orientation_deg",
                                            "motion_type",
                                            "arc_radius_mm",
                                            "arc_angle_deg",
                                            "container_turns",
                                            "path_length_mm",
                                            "path_json",
                                            "warnings"};
const std::set<std::string> kTextColumns{
    "recipe_id",   "status",  "key",         "strategy", "law_type",        "message",
    "error_field", "version", "motion_type", "warnings", "container_shape", "path_json"};

/// One row of a plan table by column name.
struct OutRow {
  std::map<std::string, Cell> cells;
  [[nodiscard]] const std::string& text(const std::string& column) const {
    return cells.at(column).text;
  }
  [[nodiscard]] double number(const std::string& column) const {
    const std::string& s = text(column);
    double v = std::nan("");
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size()) {
      ADD_FAILURE() << column << " = '" << s << "' is not a number";
      return std::nan("");
    }
    return v;
  }
};

/// Parses a plan table CSV: checks the header and the quoting rule (text quoted, numbers and
/// booleans bare, nulls empty) of every cell.
std::vector<OutRow> read_plan_csv(const std::string& text) {
  std::vector<Record> records;
  try {
    records = parse_rfc4180(text);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "the output is not RFC 4180 CSV: " << e.what() << "\n" << text;
    return {};
  }
  if (records.empty()) {
    ADD_FAILURE() << "empty plan table";
    return {};
  }
  std::vector<std::string> header;
  for (const Cell& c : records.front()) header.push_back(c.text);
  EXPECT_EQ(header, kPlanColumns);
  std::vector<OutRow> rows;
  for (std::size_t r = 1; r < records.size(); ++r) {
    if (records[r].size() != kPlanColumns.size()) {
      ADD_FAILURE() << "output row " << r << " has " << records[r].size() << " cells";
      continue;
    }
    OutRow row;
    for (std::size_t c = 0; c < kPlanColumns.size(); ++c) {
      const Cell& cell = records[r][c];
      const std::string& name = kPlanColumns[c];
      if (cell.text.empty() && !cell.quoted) {
        // null
      } else if (kTextColumns.contains(name)) {
        EXPECT_TRUE(cell.quoted) << "text cell " << name << " = " << cell.text << " is bare";
      } else {
        EXPECT_FALSE(cell.quoted) << "number cell " << name << " = " << cell.text << " is quoted";
      }
      row.cells[name] = cell;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

// ---------------------------------------------------------------------------------------------
// Independent references.

/// Plateau levels of a 7-segment law: with unit peak velocity A = 1 / (d1/2 + d2 + d3/2) and
/// B = 1 / (d5/2 + d6 + d7/2); the position reached is integrated segment by segment (cubic
/// Taylor steps, exact for a piecewise-constant jerk), then everything scales with the stroke.
struct Levels {
  double A, B, v_peak;
};
Levels independent_levels(const std::array<double, 7>& d, double stroke) {
  const double A1 = 1.0 / (d[0] / 2 + d[1] + d[2] / 2);
  const double B1 = 1.0 / (d[4] / 2 + d[5] + d[6] / 2);
  const std::array<double, 7> jerk{A1 / d[0], 0.0, -A1 / d[2], 0.0, -B1 / d[4], 0.0, B1 / d[6]};
  double s = 0.0, v = 0.0, a = 0.0;
  for (std::size_t i = 0; i < 7; ++i) {
    const double h = d[i];
    const double j = jerk[i];
    s += v * h + a * h * h / 2 + j * h * h * h / 6;
    v += a * h + j * h * h / 2;
    a += j * h;
  }
  const double scale = stroke / s;
  return {A1 * scale, B1 * scale, scale};
}

/// f1 of the first antisymmetric mode of an upright cylinder: w^2 = g xi/R tanh(xi h/R).
double f1_closed_form(double radius_m, double fill_m) {
  constexpr double g = 9.81;
  constexpr double xi = 1.841184;
  return std::sqrt(g * xi / radius_m * std::tanh(xi * fill_m / radius_m)) / (2 * std::numbers::pi);
}

// ---------------------------------------------------------------------------------------------
// The recipe table.

const std::vector<std::string> kRecipeColumns{
    "recipe_id",     "radius_mm",      "container_height_mm", "fill_height_mm", "fluid",
    "density_kg_m3", "viscosity_pa_s", "stroke_mm",           "motion_time_s",  "strategy",
    "weights",       "p_notch",        "eta_rest_max_mm",     "a_max",          "min_ramp_s",
    "damping"};

struct Recipe {
  std::map<std::string, std::string> cells;  // column -> cell (absent/empty = default)
  std::size_t dropped_cells{0};              // written with this many cells fewer
  bool bad{false};
  std::string error_field;  // expected error_field of a bad row ("" = none)
  std::string message_has;  // a text the message of a bad row must contain
  [[nodiscard]] std::string cell(const std::string& column) const {
    const auto it = cells.find(column);
    return it == cells.end() ? "" : it->second;
  }
  [[nodiscard]] std::string id() const { return cell("recipe_id"); }
};

std::string fixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

/// 50 seeded random formats with options on some rows; 8 rows broken in different ways and one
/// row repeating the recipe of the previous one under another id.
std::vector<Recipe> make_recipes() {
  std::mt19937 rng(20240611u);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  auto chance = [&](double p) { return uniform(0.0, 1.0) < p; };
  const std::array<std::string, 3> strategies{"notch", "multi_notch", "min_jerk_band"};
  const std::array<std::string, 4> fluids{"water", "ethanol", "milk", "olive_oil"};
  std::vector<Recipe> recipes(50);
  for (std::size_t i = 0; i < recipes.size(); ++i) {
    auto& c = recipes[i].cells;
    c["recipe_id"] = "R-" + std::to_string(1001 + i);
    c["radius_mm"] = fixed(uniform(30, 60), 1);
    const double fill = uniform(50, 120);
    c["fill_height_mm"] = fixed(fill, 1);
    if (chance(0.3)) c["container_height_mm"] = fixed(fill + uniform(20, 80), 1);
    if (chance(0.7)) {
      c["fluid"] = fluids[i % fluids.size()];
    } else {
      c["density_kg_m3"] = fixed(uniform(900, 1300), 0);
      c["viscosity_pa_s"] = fixed(uniform(0.001, 0.05), 4);
    }
    c["stroke_mm"] = fixed(uniform(300, 900), 0);
    c["motion_time_s"] = fixed(uniform(0.8, 1.4), 3);
    c["strategy"] = strategies[i % strategies.size()];
    if (chance(0.25)) {
      c["weights"] = std::to_string(1 + rng() % 3) + ";" + std::to_string(1 + rng() % 3) + ";" +
                     std::to_string(1 + rng() % 3);
    }
    if (chance(0.2)) c["p_notch"] = fixed(uniform(0.05, 0.3), 2);
    if (chance(0.2)) c["eta_rest_max_mm"] = fixed(uniform(1, 10), 1);
    if (chance(0.2)) c["a_max"] = fixed(uniform(6, 15), 1);
    if (chance(0.15)) c["min_ramp_s"] = fixed(uniform(0.02, 0.08), 3);
    if (chance(0.15)) c["damping"] = chance(0.5) ? "paper" : fixed(uniform(0.002, 0.01), 4);
  }
  auto breaks = [&](std::size_t i, const std::string& field, const std::string& has) -> Recipe& {
    recipes[i].bad = true;
    recipes[i].error_field = field;
    recipes[i].message_has = has;
    return recipes[i];
  };
  breaks(3, "radius_mm", "-12.5").cells["radius_mm"] = "-12.5";
  breaks(9, "stroke_mm", "8O0").cells["stroke_mm"] = "8O0";
  breaks(15, "fluid", "whisky").cells = [&] {
    auto c = recipes[15].cells;
    c.erase("density_kg_m3");
    c.erase("viscosity_pa_s");
    c["fluid"] = "whisky";
    return c;
  }();
  breaks(22, "", "row 23 has 14 cells, the header has 16").dropped_cells = 2;
  breaks(30, "p_notch", "p_notch = 2").cells["p_notch"] = "2";
  {
    Recipe& both = breaks(37, "fluid", "density_kg_m3");
    both.cells["fluid"] = "water";
    both.cells["density_kg_m3"] = "1000";
    both.cells["viscosity_pa_s"] = "0.001";
  }
  breaks(41, "weights", "-2").cells["weights"] = "1;-2;1";
  breaks(46, "strategy", "notchh").cells["strategy"] = "notchh";
  // Row 45 is row 44's recipe under another id: one solve, one cache entry.
  recipes[45].cells = recipes[44].cells;
  recipes[45].cells["recipe_id"] = "R-1046 (same as R-1045)";
  return recipes;
}

std::string recipes_csv(const std::vector<Recipe>& recipes) {
  std::string text;
  for (std::size_t c = 0; c < kRecipeColumns.size(); ++c) {
    text += (c == 0 ? "" : ",") + kRecipeColumns[c];
  }
  text += '\n';
  for (const Recipe& r : recipes) {
    const std::size_t n = kRecipeColumns.size() - r.dropped_cells;
    for (std::size_t c = 0; c < n; ++c) {
      text += (c == 0 ? "" : ",") + csv_cell(r.cell(kRecipeColumns[c]));
    }
    text += '\n';
  }
  return text;
}

double to_double(const std::string& s) {
  std::size_t used = 0;
  const double v = std::stod(s, &used);
  if (used != s.size()) throw std::runtime_error("not a number: " + s);
  return v;
}

/// The /v1/plans request a good recipe row stands for, built from its cells.
json request_of(const Recipe& r) {
  json body;
  body["format"]["container"]["radius_mm"] = to_double(r.cell("radius_mm"));
  if (!r.cell("container_height_mm").empty()) {
    body["format"]["container"]["height_mm"] = to_double(r.cell("container_height_mm"));
  }
  body["format"]["fill_height_mm"] = to_double(r.cell("fill_height_mm"));
  if (!r.cell("fluid").empty()) {
    body["format"]["fluid"] = r.cell("fluid");
  } else {
    body["format"]["fluid"] = {{"density_kg_m3", to_double(r.cell("density_kg_m3"))},
                               {"viscosity_pa_s", to_double(r.cell("viscosity_pa_s"))}};
  }
  body["format"]["stroke_mm"] = to_double(r.cell("stroke_mm"));
  body["format"]["motion_time_s"] = to_double(r.cell("motion_time_s"));
  body["strategy"] = r.cell("strategy");
  json options = json::object();
  if (const std::string w = r.cell("weights"); !w.empty()) {
    json list = json::array();
    std::size_t at = 0;
    while (at <= w.size()) {
      const std::size_t end = std::min(w.find(';', at), w.size());
      list.push_back(to_double(w.substr(at, end - at)));
      at = end + 1;
    }
    options["weights"] = list;
  }
  for (const char* name : {"p_notch", "eta_rest_max_mm", "min_ramp_s"}) {
    if (!r.cell(name).empty()) options[name] = to_double(r.cell(name));
  }
  if (!r.cell("a_max").empty()) options["limits"]["a_max"] = to_double(r.cell("a_max"));
  if (const std::string d = r.cell("damping"); !d.empty()) {
    options["damping"] = d == "paper" ? json("paper") : json{{"zeta", to_double(d)}};
  }
  if (!options.empty()) body["options"] = options;
  return body;
}

double rel_diff(double a, double b) {
  return std::abs(a - b) / std::max({1e-300, std::abs(a), std::abs(b)});
}

/// Checks one planned output row against a plan JSON (the in-process reference).
void expect_row_matches_plan(const OutRow& row, const json& plan, const std::string& where) {
  SCOPED_TRACE(where);
  EXPECT_EQ(row.text("status"), plan["status"].get<std::string>());
  EXPECT_EQ(row.text("key"), plan["key"].get<std::string>());
  EXPECT_EQ(row.text("strategy"), plan["strategy"].get<std::string>());
  EXPECT_EQ(row.text("message"), plan["message"].get<std::string>());
  EXPECT_EQ(row.text("error_field"), "");
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_DOUBLE_EQ(row.number("T" + std::to_string(i + 1) + "_s"),
                     plan["durations_s"][i].get<double>());
  }
  const json& k = plan["kinematics"];
  EXPECT_DOUBLE_EQ(row.number("A_m_s2"), k["a_max"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("B_m_s2"), k["a_min"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("v_peak_m_s"), k["v_peak"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("j_peak_m_s3"), k["j_peak"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("f1_hz"), plan["model"]["f_hz"][0].get<double>());
  const json& p = plan["prediction"];
  EXPECT_DOUBLE_EQ(row.number("eta_motion_nonlinear_mm"),
                   p["nonlinear"]["eta_motion_mm"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("eta_rest_nonlinear_mm"),
                   p["nonlinear"]["eta_rest_mm"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("eta_motion_linear_mm"), p["linear"]["eta_motion_mm"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("eta_rest_linear_mm"), p["linear"]["eta_rest_mm"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("baseline_eta_motion_nonlinear_mm"),
                   plan["baseline"]["nonlinear"]["eta_motion_mm"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("baseline_eta_rest_nonlinear_mm"),
                   plan["baseline"]["nonlinear"]["eta_rest_mm"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("reduction_motion_pct"),
                   plan["reduction_pct"]["motion"].get<double>());
  EXPECT_DOUBLE_EQ(row.number("reduction_rest_pct"), plan["reduction_pct"]["rest"].get<double>());
  EXPECT_GT(row.number("solve_ms"), 0.0);
}

/// SELECT key FROM plans of a cache file, opened read-only.
std::multiset<std::string> cached_keys(const fs::path& path) {
  std::multiset<std::string> keys;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT key FROM plans", -1, &stmt, nullptr) == SQLITE_OK) {
      while (sqlite3_step(stmt) == SQLITE_ROW) {
        keys.insert(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)));
      }
    } else {
      ADD_FAILURE() << sqlite3_errmsg(db);
    }
    sqlite3_finalize(stmt);
  } else {
    ADD_FAILURE() << "cannot open " << path;
  }
  sqlite3_close(db);
  return keys;
}

// ---------------------------------------------------------------------------------------------
// The 50-recipe table, run once per process (no cache) with its in-process reference plans.

class BatchTable : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    recipes_ = make_recipes();
    write_file(*dir_ / "recipes.csv", recipes_csv(recipes_));
    local_ = run_slosh({"batch", "--in", (*dir_ / "recipes.csv").string(), "--out",
                        (*dir_ / "plans.csv").string(), "--cache", ""});
    local_csv_ = read_file(*dir_ / "plans.csv");
    for (std::size_t i = 0; i < recipes_.size(); ++i) {
      if (!recipes_[i].bad)
        references_[i] = api::run_plan(api::parse_plan_request(request_of(recipes_[i])));
    }
  }
  static void TearDownTestSuite() { dir_.reset(); }

  static std::unique_ptr<TempDir> dir_;
  static std::vector<Recipe> recipes_;
  static RunResult local_;
  static std::string local_csv_;
  static std::map<std::size_t, json> references_;
};
std::unique_ptr<TempDir> BatchTable::dir_;
std::vector<Recipe> BatchTable::recipes_;
RunResult BatchTable::local_;
std::string BatchTable::local_csv_;
std::map<std::size_t, json> BatchTable::references_;

TEST_F(BatchTable, EveryRowInInputOrderErrorsNamedGoodRowsEqualTheJsonPlan) {
  EXPECT_EQ(local_.exit_code, 3) << local_.err;
  EXPECT_TRUE(local_.out.empty()) << local_.out;
  EXPECT_FALSE(fs::exists(*dir_ / "plans.csv.partial"));
  // stderr: the summary and the failed rows (1-based recipe numbers).
  EXPECT_NE(local_.err.find("slosh batch: 50 recipes, 42 planned"), std::string::npos)
      << local_.err;
  EXPECT_NE(local_.err.find("8 errors"), std::string::npos) << local_.err;
  EXPECT_NE(local_.err.find("slosh batch: rows 4, 10, 16, 23, 31, 38, 42, 47 could not be planned"),
            std::string::npos)
      << local_.err;

  const std::vector<OutRow> rows = read_plan_csv(local_csv_);
  ASSERT_EQ(rows.size(), recipes_.size()) << local_csv_;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const OutRow& row = rows[i];
    const Recipe& recipe = recipes_[i];
    SCOPED_TRACE("recipe " + recipe.id());
    EXPECT_EQ(row.text("row"), std::to_string(i + 1));
    EXPECT_EQ(row.text("recipe_id"), recipe.id());
    if (recipe.bad) {
      EXPECT_EQ(row.text("status"), "error");
      EXPECT_EQ(row.text("error_field"), recipe.error_field);
      EXPECT_NE(row.text("message").find(recipe.message_has), std::string::npos)
          << row.text("message");
      for (const char* empty :
           {"key", "cached", "strategy", "law_type", "T1_s", "A_m_s2", "solve_ms", "version"}) {
        EXPECT_EQ(row.text(empty), "") << empty;
      }
      continue;
    }
    const json& plan = references_.at(i);
    expect_row_matches_plan(row, plan, recipe.id());
    EXPECT_EQ(row.text("key"), api::recipe_key(api::parse_plan_request(request_of(recipe))));
    EXPECT_EQ(row.text("cached"), "false");
    // The table records which slosh planned it.
    EXPECT_EQ(row.text("version"), plan["version"].get<std::string>());
    EXPECT_EQ(row.text("version"), slosh::kVersion);
    double sum = 0.0;
    for (int k = 1; k <= 7; ++k) sum += row.number("T" + std::to_string(k) + "_s");
    EXPECT_NEAR(sum, to_double(recipe.cell("motion_time_s")), 1e-9);
  }
  // The repeated recipe: same key and figures under its own id.
  EXPECT_EQ(rows[45].text("key"), rows[44].text("key"));
  EXPECT_EQ(rows[45].text("T3_s"), rows[44].text("T3_s"));
}

TEST_F(BatchTable, ErrorMessagesNameTheValueAndTheRule) {
  const std::vector<OutRow> rows = read_plan_csv(local_csv_);
  ASSERT_EQ(rows.size(), 50u);
  // A cell that is not a number is refused with the column's range, as its JSON value is.
  EXPECT_EQ(rows[9].text("message"),
            "stroke_mm must be a number, got \"8O0\"; allowed 0.01 to 100000 mm");
  EXPECT_EQ(rows[22].text("message"), "row 23 has 14 cells, the header has 16");
  // Request paths are rewritten in the terms of the CSV columns.
  EXPECT_EQ(rows[3].text("message"), "radius_mm = -12.5 is out of range: allowed 1 to 2000 mm");
  EXPECT_EQ(rows[41].text("message"), "weights[1] = -2 is out of range: allowed 0 to 1000000");
  EXPECT_EQ(rows[37].text("message"),
            "fluid = \"water\" and density_kg_m3 = \"1000\": give either fluid or density_kg_m3 "
            "and viscosity_pa_s, not both");
}

TEST_F(BatchTable, UnitsAgreeWithClosedForms) {
  const std::vector<OutRow> rows = read_plan_csv(local_csv_);
  ASSERT_EQ(rows.size(), recipes_.size());
  std::size_t checked = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (recipes_[i].bad) continue;
    const OutRow& row = rows[i];
    const Recipe& recipe = recipes_[i];
    SCOPED_TRACE("recipe " + recipe.id());
    std::array<double, 7> d{};
    for (std::size_t k = 0; k < 7; ++k) d[k] = row.number("T" + std::to_string(k + 1) + "_s");
    const double stroke_m = to_double(recipe.cell("stroke_mm")) * 1e-3;
    // A, B [m/s^2] and v_peak [m/s] of the durations, from the integration above.
    const Levels levels = independent_levels(d, stroke_m);
    EXPECT_LT(rel_diff(row.number("A_m_s2"), levels.A), 1e-9);
    EXPECT_LT(rel_diff(row.number("B_m_s2"), levels.B), 1e-9);
    EXPECT_LT(rel_diff(row.number("v_peak_m_s"), levels.v_peak), 1e-9);
    // The same through the core class, from the printed durations.
    const SevenSegmentLaw law(d, stroke_m);
    EXPECT_LT(rel_diff(row.number("A_m_s2"), law.A()), 1e-12);
    // Peak jerk: the steepest ramp A/d1, A/d3, B/d5, B/d7 [m/s^3].
    const double j_peak =
        std::max({levels.A / d[0], levels.A / d[2], levels.B / d[4], levels.B / d[6]});
    EXPECT_LT(rel_diff(row.number("j_peak_m_s3"), j_peak), 1e-9);
    // f1 [Hz] from R and h in metres.
    EXPECT_LT(rel_diff(row.number("f1_hz"),
                       f1_closed_form(to_double(recipe.cell("radius_mm")) * 1e-3,
                                      to_double(recipe.cell("fill_height_mm")) * 1e-3)),
              1e-12);
    // Sloshing heights are in mm: of the order of 1-100 mm at these accelerations, and the
    // reduction is the percentage of the baseline.
    const double eta = row.number("eta_motion_nonlinear_mm");
    const double base = row.number("baseline_eta_motion_nonlinear_mm");
    EXPECT_GT(eta, 0.5);
    EXPECT_LT(eta, 500.0);
    EXPECT_NEAR(row.number("reduction_motion_pct"), 100.0 * (1.0 - eta / base), 1e-9);
    EXPECT_NEAR(row.number("reduction_rest_pct"),
                100.0 * (1.0 - row.number("eta_rest_nonlinear_mm") /
                                   row.number("baseline_eta_rest_nonlinear_mm")),
                1e-9);
    ++checked;
  }
  EXPECT_EQ(checked, 42u);
}

TEST_F(BatchTable, RerunWithTheSameCacheServesEveryGoodRowFromIt) {
  const fs::path cache = *dir_ / "cache.sqlite";
  const std::string in = (*dir_ / "recipes.csv").string();
  const RunResult first = run_slosh(
      {"batch", "--in", in, "--out", (*dir_ / "first.csv").string(), "--cache", cache.string()});
  ASSERT_EQ(first.exit_code, 3) << first.err;
  const RunResult second = run_slosh(
      {"batch", "--in", in, "--out", (*dir_ / "second.csv").string(), "--cache", cache.string()});
  ASSERT_EQ(second.exit_code, 3) << second.err;
  EXPECT_NE(second.err.find("42 planned (42 from cache"), std::string::npos) << second.err;
  const std::vector<OutRow> a = read_plan_csv(read_file(*dir_ / "first.csv"));
  const std::vector<OutRow> b = read_plan_csv(read_file(*dir_ / "second.csv"));
  ASSERT_EQ(a.size(), 50u);
  ASSERT_EQ(b.size(), 50u);
  std::multiset<std::string> expected_keys;
  std::set<std::string> distinct;
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(recipes_[i].id());
    if (recipes_[i].bad) {
      EXPECT_EQ(b[i].text("status"), "error");
      EXPECT_EQ(b[i].text("message"), a[i].text("message"));
      continue;
    }
    EXPECT_EQ(a[i].text("cached"), "false");
    EXPECT_EQ(b[i].text("cached"), "true");
    for (const std::string& column : kPlanColumns) {
      if (column == "cached" || column == "solve_ms") continue;
      EXPECT_EQ(b[i].text(column), a[i].text(column)) << column;
    }
    const std::string status = a[i].text("status");
    ASSERT_TRUE(status == "optimal" || status == "acceptable" || status == "infeasible") << status;
    if (distinct.insert(a[i].text("key")).second) expected_keys.insert(a[i].text("key"));
  }
  EXPECT_EQ(distinct.size(), 41u);  // 42 good rows, one repeated recipe
  EXPECT_EQ(cached_keys(cache), expected_keys);
}

TEST_F(BatchTable, JsonLinesInJsonArrayOutGivesTheSameResults) {
  // The good recipes as plan requests, one per line, with a malformed line after the fifth.
  std::string lines;
  std::vector<std::size_t> source;  // recipe index of each line; npos = the malformed one
  for (std::size_t i = 0; i < recipes_.size(); ++i) {
    if (recipes_[i].bad) continue;
    json line = request_of(recipes_[i]);
    line["recipe_id"] = recipes_[i].id();
    lines += line.dump() + "\n";
    source.push_back(i);
    if (source.size() == 5) {
      lines += "{\"recipe_id\": \"broken\", \"format\": \n";
      source.push_back(std::string::npos);
    }
  }
  write_file(*dir_ / "recipes.jsonl", lines);
  const RunResult r = run_slosh({"batch", "--in", (*dir_ / "recipes.jsonl").string(), "--out",
                                 (*dir_ / "plans.json").string(), "--full", "--cache", ""});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("row 6 could not be planned"), std::string::npos) << r.err;
  json out;
  ASSERT_NO_THROW(out = json::parse(read_file(*dir_ / "plans.json")));
  ASSERT_TRUE(out.is_array());
  ASSERT_EQ(out.size(), source.size());
  const std::vector<OutRow> csv_rows = read_plan_csv(local_csv_);
  ASSERT_EQ(csv_rows.size(), recipes_.size());
  for (std::size_t n = 0; n < out.size(); ++n) {
    const json& row = out[n];
    EXPECT_EQ(row["row"], n + 1);
    if (source[n] == std::string::npos) {
      EXPECT_EQ(row["status"], "error");
      EXPECT_EQ(row["error"]["code"], "malformed_json");
      EXPECT_EQ(row["message"].get<std::string>().rfind("line 6: the body is not valid JSON", 0),
                0u)
          << row["message"];
      EXPECT_TRUE(row["error_field"].is_null());
      continue;
    }
    const std::size_t i = source[n];
    SCOPED_TRACE(recipes_[i].id());
    EXPECT_EQ(row["recipe_id"], recipes_[i].id());
    // The same figures as the CSV path, and the whole plan equals the in-process one.
    const OutRow& c = csv_rows[i];
    EXPECT_EQ(row["key"], c.text("key"));
    EXPECT_EQ(row["status"], c.text("status"));
    EXPECT_EQ(row["cached"], false);
    for (std::size_t k = 0; k < 7; ++k) {
      EXPECT_EQ(row["durations_s"][k].get<double>(), c.number("T" + std::to_string(k + 1) + "_s"));
    }
    EXPECT_EQ(row["kinematics"]["a_max"].get<double>(), c.number("A_m_s2"));
    EXPECT_EQ(row["f1_hz"].get<double>(), c.number("f1_hz"));
    EXPECT_EQ(row["prediction"]["linear"]["eta_rest_mm"].get<double>(),
              c.number("eta_rest_linear_mm"));
    ASSERT_TRUE(row.contains("plan"));
    json plan = row["plan"];
    json reference = references_.at(i);
    plan["solver"].erase("solve_ms");
    reference["solver"].erase("solve_ms");
    EXPECT_EQ(plan, reference);
  }
}

TEST_F(BatchTable, JsonLinesErrorFieldIsTheRequestPath) {
  json bad = request_of(recipes_[0]);
  bad["format"]["container"]["radius_mm"] = -3;
  bad["recipe_id"] = "neg";
  json good = request_of(recipes_[1]);
  good["recipe_id"] = "ok";
  const RunResult r = run_slosh({"batch", "--in", "-", "--in-format", "jsonl", "--out", "-",
                                 "--out-format", "jsonl", "--cache", ""},
                                bad.dump() + "\n\n" + good.dump() + "\n");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  std::vector<json> rows;
  std::size_t at = 0;
  while (at < r.out.size()) {
    const std::size_t end = r.out.find('\n', at);
    ASSERT_NE(end, std::string::npos) << "unterminated line";
    rows.push_back(json::parse(r.out.substr(at, end - at)));
    at = end + 1;
  }
  ASSERT_EQ(rows.size(), 2u) << r.out;
  EXPECT_EQ(rows[0]["recipe_id"], "neg");
  EXPECT_EQ(rows[0]["error_field"], "format.container.radius_mm");
  EXPECT_EQ(rows[0]["message"],
            "format.container.radius_mm = -3 is out of range: allowed 1 to 2000 mm");
  EXPECT_EQ(rows[1]["recipe_id"], "ok");
  EXPECT_EQ(rows[1]["key"], references_.at(1)["key"]);
}

TEST_F(BatchTable, ServerModeGivesTheLocalTable) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const RunResult r =
      run_slosh({"batch", "--in", (*dir_ / "recipes.csv").string(), "--out",
                 (*dir_ / "remote.csv").string(), "--server", server.url(), "--chunk", "7"});
  EXPECT_EQ(r.exit_code, 3) << r.err << server.log();
  const std::vector<OutRow> remote = read_plan_csv(read_file(*dir_ / "remote.csv"));
  const std::vector<OutRow> local = read_plan_csv(local_csv_);
  ASSERT_EQ(remote.size(), local.size());
  for (std::size_t i = 0; i < local.size(); ++i) {
    SCOPED_TRACE(recipes_[i].id());
    for (const std::string& column : kPlanColumns) {
      if (column == "cached" || column == "solve_ms") continue;
      EXPECT_EQ(remote[i].text(column), local[i].text(column)) << column;
    }
  }
}

TEST(BatchServer, UnreachableServerStopsWithThePartialTable) {
  const TempDir dir;
  const std::vector<Recipe> recipes = make_recipes();
  write_file(dir / "recipes.csv", recipes_csv(recipes));
  const RunResult r =
      run_slosh({"batch", "--in", (dir / "recipes.csv").string(), "--out",
                 (dir / "plans.csv").string(), "--server", "http://127.0.0.1:1", "--chunk", "7"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "plans.csv"));
  ASSERT_TRUE(fs::exists(dir / "plans.csv.partial"));
  // Nothing was planned: the partial table holds the header only.
  EXPECT_EQ(read_plan_csv(read_file(dir / "plans.csv.partial")).size(), 0u);
  EXPECT_EQ(r.err.rfind("slosh batch: stopped after 0 of 50 recipes: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("slosh batch: the rows written so far are in " +
                       (dir / "plans.csv.partial").string()),
            std::string::npos)
      << r.err;
}

// ---------------------------------------------------------------------------------------------

TEST(BatchCsv, QuotedIdsRoundTripThroughTheOutput) {
  const TempDir dir;
  const std::vector<std::string> ids{"line 4, station \"B\"", "say \"\"hi\"\"", "  padded  "};
  std::string text =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\r\n";
  for (const std::string& id : ids) {
    // Quoted (the padded one too: RFC 4180 keeps its spaces).
    const std::string cell = csv_cell(id);
    text += (cell.front() == '"' ? cell : "\"" + cell + "\"") + ",48.5,82,water,800,1.0,notch\r\n";
  }
  write_file(dir / "in.csv", text);
  const RunResult r = run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out",
                                 (dir / "out.csv").string(), "--cache", ""});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const std::string out = read_file(dir / "out.csv");
  const std::vector<OutRow> rows = read_plan_csv(out);
  ASSERT_EQ(rows.size(), ids.size()) << out;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    EXPECT_EQ(rows[i].text("recipe_id"), ids[i]);
    EXPECT_EQ(rows[i].text("status"), "optimal");
    EXPECT_EQ(rows[i].text("key"), rows[0].text("key"));
  }
  // On the wire: the doubled quotes are doubled again.
  EXPECT_NE(out.find(",\"say \"\"\"\"hi\"\"\"\"\","), std::string::npos) << out;
}

// A line break inside a quoted id is valid CSV but would start a new line wherever the id is
// echoed (a log, a spreadsheet): the row is refused naming recipe_id, the rest is planned.
TEST(BatchCsv, IdsWithLineBreaksAreRefusedRows) {
  const TempDir dir;
  write_file(dir / "in.csv",
             "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\r\n"
             "\"two\nlines\",48.5,82,water,800,1.0,notch\r\n"
             "\"crlf\r\ninside\",48.5,82,water,800,1.0,notch\r\n"
             "ok,48.5,82,water,800,1.0,notch\r\n");
  const RunResult r = run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out",
                                 (dir / "out.csv").string(), "--cache", ""});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(read_file(dir / "out.csv"));
  ASSERT_EQ(rows.size(), 3u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(rows[i].text("status"), "error");
    EXPECT_EQ(rows[i].text("recipe_id"), "");
    EXPECT_EQ(rows[i].text("error_field"), "recipe_id");
  }
  EXPECT_EQ(rows[0].text("message"),
            "recipe_id must not hold control characters (NUL, tab, line breaks, ...), got "
            "\"two\\nlines\"");
  EXPECT_EQ(rows[1].text("message"),
            "recipe_id must not hold control characters (NUL, tab, line breaks, ...), got "
            "\"crlf\\r\\ninside\"");
  EXPECT_EQ(rows[2].text("status"), "optimal");
}

TEST(BatchCsv, ByteOrderMarkAndCrlfAreAccepted) {
  const std::string lf =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
      "a,48.5,82,water,800,1.0,notch\n"
      "b,40,70,ethanol,600,0.9,multi_notch\n";
  std::string crlf = "\xEF\xBB\xBF";
  for (char c : lf) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const RunResult a = run_slosh({"batch", "--cache", ""}, lf);
  const RunResult b = run_slosh({"batch", "--cache", ""}, crlf);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const std::vector<OutRow> ra = read_plan_csv(a.out);
  const std::vector<OutRow> rb = read_plan_csv(b.out);
  ASSERT_EQ(ra.size(), 2u);
  ASSERT_EQ(rb.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(rb[i].text("recipe_id"), ra[i].text("recipe_id"));
    EXPECT_EQ(rb[i].text("key"), ra[i].text("key"));
  }
  EXPECT_EQ(ra[0].text("recipe_id"), "a");
}

// The recipe_id of a row that cannot be read is the cell of the recipe_id column, wherever that
// column is in the header.
TEST(BatchCsv, RecipeIdOfABadRowComesFromItsColumn) {
  const std::string text =
      "radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy,recipe_id\n"
      "x48.5,82,water,800,1.0,notch,first\n"
      "48.5,82,water,800,1.0,notch,second\n"
      "48.5,82,water,800,1.0,notch,third,extra\n";
  const RunResult r = run_slosh({"batch", "--cache", ""}, text);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(r.out);
  ASSERT_EQ(rows.size(), 3u) << r.out;
  EXPECT_EQ(rows[0].text("error_field"), "radius_mm");
  EXPECT_EQ(rows[0].text("recipe_id"), "first");
  EXPECT_EQ(rows[1].text("recipe_id"), "second");
  EXPECT_EQ(rows[1].text("status"), "optimal");
  EXPECT_EQ(rows[2].text("message"), "row 3 has 8 cells, the header has 7");
  EXPECT_EQ(rows[2].text("recipe_id"), "third");
}

// A row's refusal names the CSV columns throughout (not a JSON path beside a column) and the
// conflict the row has: a rectangular row with a radius and no sides has a radius too many, a
// cylinder row with an orientation an orientation too many.
TEST(BatchCsv, ContainerRefusalsNameTheColumnsAndTheRealConflict) {
  const std::string text =
      "recipe_id,container_shape,radius_mm,length_mm,width_mm,orientation_deg,fill_height_mm,"
      "fluid,stroke_mm,motion_time_s,strategy\n"
      "rect-radius,rectangular,40,,,0,50,water,200,1.0,baseline\n"
      "cyl-sides,cylinder,,120,80,0,50,water,200,1.0,baseline\n"
      "cyl-turned,cylinder,40,,,30,50,water,200,1.0,baseline\n"
      "both,,40,120,80,0,50,water,200,1.0,baseline\n";
  const RunResult r = run_slosh({"batch", "--cache", ""}, text);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(r.out);
  ASSERT_EQ(rows.size(), 4u) << r.out;
  EXPECT_EQ(rows[0].text("error_field"), "radius_mm");
  EXPECT_EQ(rows[0].text("message"),
            "radius_mm belongs to a cylinder: a container with container_shape = "
            "\"rectangular\" has length_mm, width_mm and orientation_deg (leave container_shape "
            "out for a cylinder)");
  EXPECT_EQ(rows[1].text("error_field"), "length_mm");
  EXPECT_EQ(rows[1].text("message"),
            "length_mm belongs to a rectangular container: give container_shape = "
            "\"rectangular\" (the cylinder has radius_mm)");
  EXPECT_EQ(rows[2].text("error_field"), "orientation_deg");
  EXPECT_EQ(rows[2].text("message"),
            "orientation_deg belongs to a rectangular container: give container_shape = "
            "\"rectangular\" (the cylinder has radius_mm)");
  // Both shapes in one row: the shape is named by its column, not as a JSON member.
  EXPECT_EQ(rows[3].text("error_field"), "length_mm");
  EXPECT_EQ(rows[3].text("message"),
            "radius_mm and length_mm are both given: a container is a cylinder (radius_mm) or "
            "rectangular (container_shape = \"rectangular\" with length_mm, width_mm and "
            "orientation_deg), not both");
}

// A refusal of two members names their group as its field ("options", which no column holds);
// its message names each member by its column all the same.
TEST(BatchCsv, AGroupsRefusalNamesItsMembersByTheirColumns) {
  const std::string text =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy,plateau_min_s\n"
      "bad,48.5,82,water,800,1.0,notch,0.5;0.6\n";
  const RunResult r = run_slosh({"batch", "--cache", ""}, text);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(r.out);
  ASSERT_EQ(rows.size(), 1u) << r.out;
  // The group, options, has no column: the row names the columns of the members it refuses.
  EXPECT_EQ(rows[0].text("error_field"), "min_ramp_s;plateau_min_s");
  EXPECT_EQ(rows[0].text("message"),
            "min_ramp_s = 0.05 s and plateau_min_s = [0.5, 0.6] s need 4 ramps + 2 plateaus = "
            "1.3 s, more than the motion time 1 s: allowed min_ramp_s <= (T - plateau minimums) / "
            "4 = -0.025 s");
}

// A range of the model given along an arc is refused by its column (not the group
// options.uncertainty, which has none).
TEST(BatchCsv, AnUncertaintyRangeAlongAnArcIsRefusedByItsColumn) {
  const std::string text =
      "recipe_id,radius_mm,fill_height_mm,fluid,motion_time_s,strategy,"
      "uncertainty_omega_error_pct,motion_type,arc_radius_mm,arc_angle_deg\n"
      "u_arc,48.5,82,water,1.0,notch,10,arc,300,90\n";
  const RunResult r = run_slosh({"batch", "--cache", ""}, text);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(r.out);
  ASSERT_EQ(rows.size(), 1u) << r.out;
  EXPECT_EQ(rows[0].text("error_field"), "uncertainty_omega_error_pct");
  EXPECT_EQ(rows[0].text("message"),
            "uncertainty_omega_error_pct is not available along an arc or a path yet: a plan "
            "along a path is verified at the nominal model (leave options.uncertainty out, or "
            "plan on a straight line)");
}

// A cylinder's row given a tank's width calibration is offered the cylinder's own columns.
TEST(BatchCsv, AWidthCalibrationOnACylinderOffersTheCylindersColumns) {
  const std::string text =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy,"
      "model_width_zeta\n"
      "round,48.5,82,water,800,1.0,notch,0.01\n";
  const RunResult r = run_slosh({"batch", "--cache", ""}, text);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(r.out);
  ASSERT_EQ(rows.size(), 1u) << r.out;
  EXPECT_EQ(rows[0].text("error_field"), "model_width_zeta");
  EXPECT_EQ(rows[0].text("message"),
            "model_width_zeta applies to a rectangular container only (the scale or damping of "
            "its modes along the width): a cylinder's modes take model_omega_scale and "
            "model_zeta");
}

// A table of round and rectangular containers reads back which container each row planned, and
// a tank's first frequency along each side: sqrt(g k tanh(k h)) / 2 pi with k = pi / side, the
// rectangular tank's first mode written again here.
TEST(BatchCsv, RowsSayWhichContainerTheyPlanned) {
  const std::string text =
      "recipe_id,container_shape,radius_mm,length_mm,width_mm,orientation_deg,fill_height_mm,"
      "fluid,stroke_mm,motion_time_s,strategy\n"
      "round,,48.5,,,,82,water,800,1.0,baseline\n"
      "cup,rectangular,,120,80,30,50,water,200,1.0,baseline\n";
  const RunResult r = run_slosh({"batch", "--cache", ""}, text);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(r.out);
  ASSERT_EQ(rows.size(), 2u) << r.out;
  EXPECT_EQ(rows[0].text("container_shape"), "cylinder");
  for (const char* empty : {"length_mm", "width_mm", "orientation_deg", "f1_length_hz"}) {
    EXPECT_EQ(rows[0].text(empty), "") << empty;
  }
  EXPECT_EQ(rows[1].text("container_shape"), "rectangular");
  EXPECT_EQ(rows[1].number("length_mm"), 120.0);
  EXPECT_EQ(rows[1].number("width_mm"), 80.0);
  EXPECT_EQ(rows[1].number("orientation_deg"), 30.0);
  const auto first_mode_hz = [](double side, double fill) {
    const double k = std::numbers::pi / side;
    return std::sqrt(9.81 * k * std::tanh(k * fill)) / (2.0 * std::numbers::pi);
  };
  EXPECT_NEAR(rows[1].number("f1_length_hz"), first_mode_hz(0.12, 0.05), 1e-9);
  EXPECT_NEAR(rows[1].number("f1_width_hz"), first_mode_hz(0.08, 0.05), 1e-9);
}

// Two paths of one length (500 mm: a line then a left or a right quarter arc, or the arc first)
// are told apart by their rows: each echoes its path as the path_json cell that gave it, which
// reads back as the segments of its input row; a line row leaves the cell empty.
TEST(BatchCsv, PathRowsEchoTheirPath) {
  const std::vector<std::string> paths{
      R"([{"line_mm": 200}, {"arc": {"radius_mm": 191, "angle_deg": 90}}])",
      R"([{"line_mm": 200}, {"arc": {"radius_mm": 191, "angle_deg": -90}}])",
      R"([{"arc": {"radius_mm": 191, "angle_deg": 90}}, {"line_mm": 200}])"};
  std::string text =
      "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,motion_type,path_json,"
      "strategy\n"
      "line,48.5,82,water,500,1.2,,,baseline\n";
  for (std::size_t i = 0; i < paths.size(); ++i) {
    std::string cell;
    for (const char c : paths[i]) cell += c == '"' ? std::string("\"\"") : std::string(1, c);
    text += "p" + std::to_string(i) + ",48.5,82,water,,1.2,path,\"" + cell + "\",baseline\n";
  }
  const RunResult r = run_slosh({"batch", "--cache", ""}, text);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<OutRow> rows = read_plan_csv(r.out);
  ASSERT_EQ(rows.size(), 1 + paths.size()) << r.out;
  EXPECT_EQ(rows[0].text("motion_type"), "line");
  EXPECT_EQ(rows[0].text("path_json"), "");
  EXPECT_FALSE(rows[0].cells.at("path_json").quoted);
  const double length = 200.0 + 191.0 * std::numbers::pi / 2.0;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const OutRow& row = rows[1 + i];
    EXPECT_EQ(row.text("status"), "optimal") << row.text("message");
    EXPECT_NEAR(row.number("path_length_mm"), length, 1e-9);
    const nlohmann::json echoed = nlohmann::json::parse(row.text("path_json"), nullptr, false);
    EXPECT_EQ(echoed, nlohmann::json::parse(paths[i])) << row.text("path_json");
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_NE(row.text("path_json"), rows[1 + j].text("path_json")) << i << ' ' << j;
    }
  }
}

// ---------------------------------------------------------------------------------------------

const std::string kSmallTable =
    "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
    "a,48.5,82,water,800,1.0,notch\n"
    "b,40,70,ethanol,600,0.9,multi_notch\n"
    "c,55,100,milk,700,1.2,min_jerk_band\n";

TEST(BatchProgress, AlwaysDrawsTheBarOnStderr) {
  const TempDir dir;
  write_file(dir / "in.csv", kSmallTable);
  const RunResult r =
      run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out", (dir / "out.csv").string(),
                 "--progress", "always", "--cache", ""});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("recipes/s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3/3 100%"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("slosh batch: 3 recipes, 3 planned (0 from cache"), std::string::npos)
      << r.err;
  EXPECT_EQ(read_plan_csv(read_file(dir / "out.csv")).size(), 3u);
}

TEST(BatchProgress, AutoWithoutATerminalKeepsStderrSilent) {
  const TempDir dir;
  write_file(dir / "in.csv", kSmallTable);
  const RunResult r = run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out",
                                 (dir / "out.csv").string(), "--cache", ""});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(read_plan_csv(read_file(dir / "out.csv")).size(), 3u);
}

TEST(BatchProgress, NeverPrintsOnlyTheSummaryOfFailedRows) {
  const RunResult r = run_slosh({"batch", "--progress", "never", "--cache", ""},
                                kSmallTable + "d,-1,82,water,800,1.0,notch\n");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("recipes/s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("slosh batch: row 4 could not be planned"), std::string::npos) << r.err;
  EXPECT_EQ(read_plan_csv(r.out).size(), 4u);
}

TEST(BatchProgress, AutoDrawsTheBarOnATerminal) {
  const TempDir dir;
  write_file(dir / "in.csv", kSmallTable);
  std::vector<std::string> args{
      SLOSH_BINARY, "batch", "--in", (dir / "in.csv").string(), "--out", (dir / "out.csv").string(),
      "--cache",    ""};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_storage{"TERM=xterm"};
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::string(*e).rfind("TERM=", 0) != 0) env_storage.emplace_back(*e);
  }
  std::vector<char*> envp;
  for (std::string& e : env_storage) envp.push_back(e.data());
  envp.push_back(nullptr);

  int master = -1;
  const pid_t pid = ::forkpty(&master, nullptr, nullptr, nullptr);
  if (pid == 0) {
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  Child child(pid);
  std::string seen;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{master, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) {
      if (child.wait_for(std::chrono::milliseconds(0))) break;
      continue;
    }
    char buffer[4096];
    const ssize_t n = ::read(master, buffer, sizeof buffer);
    if (n <= 0) break;  // EIO: the child closed the terminal
    seen.append(buffer, static_cast<std::size_t>(n));
  }
  const std::optional<int> code = child.wait_for(std::chrono::seconds(10));
  ::close(master);
  EXPECT_EQ(code, 0) << seen;
  EXPECT_NE(seen.find("recipes/s"), std::string::npos) << seen;
  EXPECT_NE(seen.find("3/3 100%"), std::string::npos) << seen;
  EXPECT_EQ(read_plan_csv(read_file(dir / "out.csv")).size(), 3u);
}

// ---------------------------------------------------------------------------------------------
// Table-level errors: exit 2, one message on stderr, nothing written.

struct TableErrorCase {
  std::string name;
  std::string table;
  std::string out_name;
  std::string expected_err;  // exact; "{OUT}" stands for the output path
};

TEST(BatchTableErrors, Exit2WithTheExactMessageAndNoOutput) {
  const std::string allowed =
      "recipe_id, radius_mm, container_shape, length_mm, width_mm, orientation_deg, "
      "container_height_mm, fill_height_mm, fluid, density_kg_m3, "
      "viscosity_pa_s, stroke_mm, motion_time_s, motion_type, arc_radius_mm, arc_angle_deg, "
      "container_turns, path_json, strategy, p_notch, weights, band, n_band, "
      "tol_rel, eta_rest_max_mm, eta_motion_max_mm, objective, rest_time_s, min_ramp_s, "
      "fix_constant_velocity_zero, plateau_min_s, a_max, v_max, j_max, drive_profile, damping, "
      "alpha, "
      "modes, "
      "solver, time_limit_s, base, shaper, residual, iir_order, iir_tau, iir_sample_period_s, "
      "robustness, uncertainty_omega_error_pct, uncertainty_fill_height_mm, "
      "uncertainty_viscosity_pa_s, uncertainty_sample_points, model_omega_scale, model_zeta, "
      "model_alpha, model_height_gain, model_width_omega_scale, model_width_zeta";
  const std::vector<TableErrorCase> cases{
      {"unknown column",
       "recipe_id,radius,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
       "a,48.5,82,water,800,1.0,notch\n",
       "out.csv",
       "slosh batch: recipe table: unknown column \"radius\" (column 2 of the header); allowed: " +
           allowed + "\n"},
      {"missing required column",
       "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s\n"
       "a,48.5,82,water,800,1.0\n",
       "out.csv",
       "slosh batch: recipe table: missing column \"strategy\"; required: recipe_id, radius_mm, "
       "fill_height_mm, fluid (or density_kg_m3 and viscosity_pa_s), stroke_mm, motion_time_s, "
       "strategy\n"},
      {"neither a radius nor sides",
       "recipe_id,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
       "a,82,water,800,1.0,notch\n",
       "out.csv",
       "slosh batch: recipe table: missing column \"radius_mm\" (or length_mm and width_mm for "
       "rectangular containers); required: recipe_id, radius_mm, fill_height_mm, fluid (or "
       "density_kg_m3 and viscosity_pa_s), stroke_mm, motion_time_s, strategy\n"},
      {"missing required column of a rectangular table",
       "recipe_id,container_shape,length_mm,width_mm,fill_height_mm,fluid,stroke_mm,"
       "motion_time_s\n"
       "a,rectangular,120,80,50,water,200,1.0\n",
       "out.csv",
       "slosh batch: recipe table: missing column \"strategy\"; required: recipe_id, length_mm, "
       "width_mm, fill_height_mm, fluid (or density_kg_m3 and viscosity_pa_s), stroke_mm, "
       "motion_time_s, strategy\n"},
      {"missing fluid",
       "recipe_id,radius_mm,fill_height_mm,density_kg_m3,stroke_mm,motion_time_s,strategy\n"
       "a,48.5,82,1000,800,1.0,notch\n",
       "out.csv",
       "slosh batch: recipe table: missing column \"fluid\" (or both density_kg_m3 and "
       "viscosity_pa_s)\n"},
      {"duplicate column",
       "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy,radius_mm\n"
       "a,48.5,82,water,800,1.0,notch,48.5\n",
       "out.csv", "slosh batch: recipe table: column \"radius_mm\" appears twice\n"},
      {"unknown output extension", kSmallTable, "out.txt",
       "slosh batch: cannot tell the table format of \"{OUT}\" from its extension: use .csv, "
       ".jsonl, .ndjson or .json, or give the format\n"},
      {"empty table", "", "out.csv",
       "slosh batch: recipe table: the CSV is empty (no header row)\n"},
  };
  for (const TableErrorCase& c : cases) {
    SCOPED_TRACE(c.name);
    const TempDir dir;
    write_file(dir / "in.csv", c.table);
    const std::string out = (dir / c.out_name).string();
    const RunResult r =
        run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out", out, "--cache", ""});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    std::string expected = c.expected_err;
    if (const auto at = expected.find("{OUT}"); at != std::string::npos) {
      expected.replace(at, 5, out);
    }
    EXPECT_EQ(r.err, expected);
    EXPECT_EQ(r.out, "");
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out + ".partial"));
  }
}

TEST(BatchTableErrors, UnterminatedQuoteIsAMalformedTable) {
  const TempDir dir;
  write_file(dir / "in.csv", kSmallTable + "\"d,48.5,82,water,800,1.0,notch\n");
  const RunResult r = run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out",
                                 (dir / "out.csv").string(), "--cache", ""});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // Header + 3 rows were complete when the quote opened.
  EXPECT_EQ(r.err.rfind("slosh batch: recipe table: the CSV is malformed after 4 complete "
                        "record(s) (",
                        0),
            0u)
      << r.err;
  const std::string tail = "): a quote inside an unquoted cell, or a quoted cell never closed\n";
  ASSERT_GE(r.err.size(), tail.size());
  EXPECT_EQ(r.err.substr(r.err.size() - tail.size()), tail) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.csv"));
  EXPECT_FALSE(fs::exists(dir / "out.csv.partial"));
}

// An output in a directory that does not exist: refused at once, naming the path and the OS's
// reason, before any plan is solved (the cache file the run would fill is not even created).
TEST(BatchTableErrors, AnOutputThatCannotBeCreatedIsRefusedNamingThePathAndWhyBeforeAnyWork) {
  const TempDir dir;
  write_file(dir / "in.csv", kSmallTable);
  const std::string out = (dir / "missing" / "plans.csv").string();
  const RunResult r = run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out", out,
                                 "--cache", (dir / "cache.sqlite").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err, "slosh batch: cannot write the output table '" + out + "': creating '" + out +
                       ".partial' (where it is written before it is renamed) failed: " +
                       std::strerror(ENOENT) + "; nothing was planned\n");
  EXPECT_EQ(r.out, "");
  EXPECT_FALSE(fs::exists(dir / "missing"));
  EXPECT_FALSE(fs::exists(dir / "cache.sqlite"));
}

TEST(BatchTableErrors, MissingInputFileAndBadOptions) {
  const TempDir dir;
  const std::string missing = (dir / "nope.csv").string();
  const RunResult r = run_slosh({"batch", "--in", missing, "--out", (dir / "o.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "slosh batch: cannot read the recipe table '" + missing + "'\n");
  EXPECT_FALSE(fs::exists(dir / "o.csv.partial"));

  write_file(dir / "in.csv", kSmallTable);
  const RunResult chunk = run_slosh({"batch", "--in", (dir / "in.csv").string(), "--server",
                                     "http://127.0.0.1:1", "--chunk", "0"});
  EXPECT_EQ(chunk.exit_code, 2) << chunk.err;
  EXPECT_NE(chunk.err.find("--chunk"), std::string::npos) << chunk.err;
  const RunResult format =
      run_slosh({"batch", "--in", (dir / "in.csv").string(), "--out-format", "xml", "--cache", ""});
  EXPECT_EQ(format.exit_code, 2) << format.err;
  EXPECT_EQ(format.out, "");
}

// ---------------------------------------------------------------------------------------------
// POST /v1/plans/batch item by item (test_service.cpp covers one bad format item and the empty
// list).

TEST(BatchEndpoint, MixedItemsAnswerInRequestOrderWithPrefixedFields) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  const std::vector<Recipe> recipes = make_recipes();
  const json good0 = request_of(recipes[0]);
  const json good1 = request_of(recipes[1]);
  json infeasible = request_of(recipes[2]);
  infeasible["options"]["limits"]["a_max"] = 0.5;  // far below the 2 s/T^2 minimum
  json unknown = request_of(recipes[4]);
  unknown["options"]["pnotch"] = 0.1;
  json weights = request_of(recipes[5]);
  weights["options"]["weights"] = {1, -2, 1};
  const json items = json::array({good0, 42, infeasible, unknown, weights, good1, good0});
  const auto reply =
      server.client().Post("/v1/plans/batch", json{{"requests", items}}.dump(), "application/json");
  ASSERT_TRUE(reply) << server.log();
  ASSERT_EQ(reply->status, 200) << reply->body;
  const json out = json::parse(reply->body);
  ASSERT_EQ(out["results"].size(), items.size()) << reply->body;
  for (std::size_t i = 0; i < items.size(); ++i) EXPECT_EQ(out["results"][i]["index"], i);

  for (std::size_t i : {std::size_t{0}, std::size_t{2}, std::size_t{5}, std::size_t{6}}) {
    SCOPED_TRACE(i);
    const json& result = out["results"][i];
    ASSERT_TRUE(result.contains("plan")) << result.dump().substr(0, 300);
    EXPECT_FALSE(result.contains("error"));
    const json reference = api::run_plan(api::parse_plan_request(items[i]));
    EXPECT_EQ(result["plan"]["key"], reference["key"]);
    EXPECT_EQ(result["plan"]["status"], reference["status"]);
    EXPECT_EQ(result["plan"]["durations_s"], reference["durations_s"]);
  }
  EXPECT_EQ(out["results"][2]["plan"]["status"], "infeasible");
  EXPECT_NE(out["results"][0]["plan"]["key"], out["results"][5]["plan"]["key"]);
  EXPECT_EQ(out["results"][6]["plan"]["key"], out["results"][0]["plan"]["key"]);

  EXPECT_EQ(out["results"][1]["error"],
            json({{"code", "invalid_value"},
                  {"message", "the request must be a JSON object, got 42"},
                  {"field", "requests[1]"}}));
  EXPECT_EQ(out["results"][3]["error"]["field"], "requests[3].options.pnotch");
  EXPECT_EQ(out["results"][4]["error"]["field"], "requests[4].options.weights[1]");
  // The message names the path as the field does, inside the batch.
  EXPECT_EQ(out["results"][4]["error"]["message"],
            "requests[4].options.weights[1] = -2 is out of range: allowed 0 to 1000000");
  for (std::size_t i : {std::size_t{1}, std::size_t{3}, std::size_t{4}}) {
    EXPECT_FALSE(out["results"][i].contains("plan")) << i;
  }
}

TEST(BatchEndpoint, BodyErrorsAre422) {
  Server server;
  ASSERT_GT(server.port(), 0) << server.log();
  auto client = server.client();
  const auto not_list =
      client.Post("/v1/plans/batch", R"({"requests": {"a": 1}})", "application/json");
  ASSERT_TRUE(not_list);
  EXPECT_EQ(not_list->status, 422);
  EXPECT_EQ(json::parse(not_list->body)["error"]["field"], "requests");
  const auto extra =
      client.Post("/v1/plans/batch", R"({"requests": [], "chunk": 1})", "application/json");
  ASSERT_TRUE(extra);
  EXPECT_EQ(extra->status, 422);
  EXPECT_EQ(json::parse(extra->body)["error"]["field"], "chunk");
}

TEST(BatchCli, FullNeedsAJsonOutput) {
  const TempDir dir;
  write_file(dir / "t.csv",
             "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
             "a,48.5,82,water,800,1.0,notch\n");
  const RunResult r = run_slosh({"batch", "--in", (dir / "t.csv").string(), "--out",
                                 (dir / "p.csv").string(), "--cache", "", "--full"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "slosh batch: --full adds the whole plan to JSON rows: use a .json or .jsonl output\n");
  EXPECT_FALSE(fs::exists(dir / "p.csv"));
}

TEST(BatchCli, JsonLinesErrorsNameTheFileLine) {
  const RunResult r = run_slosh({"batch", "--in", "-", "--in-format", "jsonl", "--out", "-",
                                 "--out-format", "jsonl", "--cache", ""},
                                "\n\n{\"format\": \n");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const json row = json::parse(r.out);
  EXPECT_EQ(row["row"], 1);
  const std::string message = row["message"];
  EXPECT_EQ(message.rfind("line 3: the body is not valid JSON: ", 0), 0u) << message;
}

}  // namespace test_batch
}  // namespace slosh
