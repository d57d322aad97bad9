// The export formats of SPEC §11 end to end: `slosh export` (the real binary) and GET
// /v1/plans/{key}/cam.csv and cam.st (a real server) write a master-axis cam table that follows a
// 7-segment law rebuilt here from the planned durations alone (constant-jerk integration), through
// the master speed; the structured-text file passes a small IEC 61131-3 grammar check written here
// (TYPE / STRUCT / VAR_GLOBAL CONSTANT / ARRAY initialiser, element count = declared bounds, every
// literal a valid ST real literal) and holds the same rows; the server's files are the CLI's bytes;
// every bad option is refused with its exact text, naming the option (CLI) or the query parameter
// (HTTP 422); and the routes are published in the OpenAPI document.

#include <httplib.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <future>
#include <random>
#include <regex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/version.hpp"
#include "export/cam_export.hpp"
#include "slosh/api/openapi.hpp"
#include "slosh/core/law/seven_segment.hpp"
#include "support/process.hpp"
#include "support/raw_client.hpp"
#include "support/reference_seven_segment.hpp"
#include "support/server.hpp"

namespace slosh {
namespace test_cam_export {

using nlohmann::json;
namespace fs = std::filesystem;
using test::read_file;
using test::run_slosh;
using test::RunResult;
using test::TempDir;
using test::write_file;

// ---------------------------------------------------------------------------------------------
// The reference law: tests/support/reference_seven_segment.hpp.
using Reference7 = test::ReferenceSevenSegment;
using State = test::LawState;

// ---------------------------------------------------------------------------------------------
// A small IEC 61131-3 grammar check of what `slosh export --format st` writes:
//   file      := TYPE ident ':' STRUCT { ident ':' LREAL ';' } END_STRUCT ';' END_TYPE
//                VAR_GLOBAL CONSTANT ident ':' ARRAY '[' int '..' int ']' OF ident ':='
//                '[' struct { ',' struct } ']' ';' END_VAR
//   struct    := '(' ident ':=' real { ',' ident ':=' real } ')'   (every member, in order)
//   real      := ['+'|'-'] digits '.' digits [('E'|'e') ['+'|'-'] digits]   (digits: 0-9 with
//                single '_' between digits)
// Comments (* ... *) may stand between tokens and do not nest.

struct Token {
  enum Kind { kIdent, kReal, kInteger, kSymbol, kEnd } kind{kEnd};
  std::string text;
};

bool ident_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
}

bool valid_real_literal(const std::string& text) {
  static const std::regex real(
      R"([+-]?[0-9](_?[0-9])*\.[0-9](_?[0-9])*([Ee][+-]?[0-9](_?[0-9])*)?)");
  return std::regex_match(text, real);
}

/// The tokens of `text` and the text of its comments; throws std::runtime_error on anything
/// outside the grammar's alphabet (e.g. "1E-3", "inf", ".5", an unclosed or nested comment).
std::vector<Token> st_tokens(const std::string& text, std::vector<std::string>& comments) {
  std::vector<Token> tokens;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c)) != 0) {
      ++i;
    } else if (text.compare(i, 2, "(*") == 0) {
      const std::size_t close = text.find("*)", i + 2);
      if (close == std::string::npos) throw std::runtime_error("unclosed comment");
      const std::string body = text.substr(i + 2, close - i - 2);
      if (body.find("(*") != std::string::npos) throw std::runtime_error("nested comment");
      comments.push_back(body);
      i = close + 2;
    } else if (std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_') {
      std::size_t j = i;
      while (j < text.size() && ident_char(text[j])) ++j;
      tokens.push_back({Token::kIdent, text.substr(i, j - i)});
      i = j;
    } else if (std::isdigit(static_cast<unsigned char>(c)) != 0 ||
               ((c == '-' || c == '+') && !tokens.empty() && tokens.back().text == ":=")) {
      std::size_t j = i + 1;
      while (j < text.size() &&
             (ident_char(text[j]) || text[j] == '.' || text[j] == '+' || text[j] == '-')) {
        if (text.compare(j, 2, "..") == 0) break;  // a subrange
        if ((text[j] == '+' || text[j] == '-') && text[j - 1] != 'E' && text[j - 1] != 'e') break;
        ++j;
      }
      const std::string number = text.substr(i, j - i);
      const bool integer = number.find_first_not_of("0123456789") == std::string::npos;
      if (!integer && !valid_real_literal(number)) {
        throw std::runtime_error("not an ST real literal: " + number);
      }
      tokens.push_back({integer ? Token::kInteger : Token::kReal, number});
      i = j;
    } else {
      static const std::array<std::string, 9> symbols{":=", "..", ":", ";", ",",
                                                      "(",  ")",  "[", "]"};
      const auto s = std::find_if(symbols.begin(), symbols.end(), [&](const std::string& sym) {
        return text.compare(i, sym.size(), sym) == 0;
      });
      if (s == symbols.end()) throw std::runtime_error(std::string("unexpected '") + c + "'");
      tokens.push_back({Token::kSymbol, *s});
      i += s->size();
    }
  }
  tokens.push_back({Token::kEnd, ""});
  return tokens;
}

/// What the grammar check reads of an ST cam file.
struct StFile {
  std::vector<std::string> comments;
  std::string type;
  std::vector<std::string> members;
  std::string name;
  long lo{}, hi{};
  std::vector<std::vector<double>> rows;
};

class StParser {
 public:
  explicit StParser(const std::string& text) : tokens_(st_tokens(text, file_.comments)) {}

  StFile parse() {
    keyword("TYPE");
    file_.type = ident();
    symbol(":");
    keyword("STRUCT");
    while (peek().text != "END_STRUCT") {
      file_.members.push_back(ident());
      symbol(":");
      keyword("LREAL");
      symbol(";");
    }
    keyword("END_STRUCT");
    symbol(";");
    keyword("END_TYPE");
    if (file_.members.empty()) fail("a STRUCT without members");
    keyword("VAR_GLOBAL");
    keyword("CONSTANT");
    file_.name = ident();
    symbol(":");
    keyword("ARRAY");
    symbol("[");
    file_.lo = integer();
    symbol("..");
    file_.hi = integer();
    symbol("]");
    keyword("OF");
    if (ident() != file_.type) fail("the ARRAY is not OF the declared TYPE");
    symbol(":=");
    symbol("[");
    do {
      file_.rows.push_back(structure());
    } while (accept(","));
    symbol("]");
    symbol(";");
    keyword("END_VAR");
    if (peek().kind != Token::kEnd) fail("text after END_VAR");
    if (static_cast<long>(file_.rows.size()) != file_.hi - file_.lo + 1) {
      fail("ARRAY[" + std::to_string(file_.lo) + ".." + std::to_string(file_.hi) + "] with " +
           std::to_string(file_.rows.size()) + " elements");
    }
    return file_;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(what + " at token " + std::to_string(at_) + " '" + tokens_[at_].text +
                             "'");
  }
  const Token& peek() const { return tokens_[at_]; }
  const Token& next() {
    const Token& t = tokens_[at_];
    if (t.kind != Token::kEnd) ++at_;
    return t;
  }
  void keyword(const std::string& word) {
    if (peek().kind != Token::kIdent || peek().text != word) fail("expected " + word);
    next();
  }
  void symbol(const std::string& s) {
    if (peek().kind != Token::kSymbol || peek().text != s) fail("expected '" + s + "'");
    next();
  }
  bool accept(const std::string& s) {
    if (peek().kind != Token::kSymbol || peek().text != s) return false;
    next();
    return true;
  }
  std::string ident() {
    if (peek().kind != Token::kIdent) fail("expected an identifier");
    return next().text;
  }
  long integer() {
    if (peek().kind != Token::kInteger) fail("expected an integer");
    return std::stol(next().text);
  }
  double real() {
    if (peek().kind != Token::kReal) fail("expected a real literal");
    std::string text = next().text;
    text.erase(std::remove(text.begin(), text.end(), '_'), text.end());
    if (text.front() == '+') text.erase(0, 1);
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || ptr != text.data() + text.size()) fail("unreadable real " + text);
    return v;
  }
  std::vector<double> structure() {
    symbol("(");
    std::vector<double> values;
    for (std::size_t m = 0; m < file_.members.size(); ++m) {
      if (m > 0) symbol(",");
      if (ident() != file_.members[m]) fail("member " + file_.members[m] + " expected");
      symbol(":=");
      values.push_back(real());
    }
    symbol(")");
    return values;
  }

  StFile file_;
  std::vector<Token> tokens_;
  std::size_t at_{0};
};

StFile parse_st(const std::string& text) {
  return StParser(text).parse();
}

// ---------------------------------------------------------------------------------------------
// Helpers of the CLI and HTTP tests.

const char* const kThesis = R"({"format": {"container": {"radius_mm": 48.5, "height_mm": 150},
    "fill_height_mm": 82, "fluid": "water", "stroke_mm": 800, "motion_time_s": 1.0},
    "strategy": "multi_notch"})";

const std::vector<std::string> kMasterArgs{"--master-period", "360", "--master-start", "30",
                                           "--master-end",    "210"};

json plan_of(const std::string& request) {
  const RunResult r = run_slosh({"plan", "--request", "-"}, request);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return json::parse(r.out);
}

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// `slosh export` of `request_file` to `out` with `extra` arguments (no cache).
RunResult export_to(const fs::path& request_file, const fs::path& out,
                    const std::vector<std::string>& extra) {
  return run_slosh(with(
      {"export", "--request", request_file.string(), "--out", out.string(), "--cache", ""}, extra));
}

std::vector<std::vector<double>> csv_rows(const std::string& content, std::string& header) {
  std::vector<std::vector<double>> rows;
  std::size_t at = content.find('\n');
  header = content.substr(0, at);
  while (at != std::string::npos && at + 1 < content.size()) {
    const std::size_t end = content.find('\n', at + 1);
    const std::string line = content.substr(at + 1, end - at - 1);
    std::vector<double> values;
    std::size_t from = 0;
    while (from <= line.size()) {
      const std::size_t comma = std::min(line.find(',', from), line.size());
      double v = std::nan("");
      const auto [ptr, ec] = std::from_chars(line.data() + from, line.data() + comma, v);
      if (ec != std::errc() || ptr != line.data() + comma) ADD_FAILURE() << "cell in " << line;
      values.push_back(v);
      from = comma + 1;
    }
    rows.push_back(values);
    at = end;
  }
  return rows;
}

json error_of(const RunResult& r) {
  try {
    return json::parse(r.err);
  } catch (const json::exception&) {
    ADD_FAILURE() << "stderr is not JSON: " << r.err;
  }
  return json::object();
}

/// Checks master-axis rows [master, mm, mm/unit, mm/unit^2, mm/unit^3] against the reference
/// through the master speed (rel: the printed precision).
void expect_master_rows(const std::vector<std::vector<double>>& rows, const Reference7& ref,
                        double stroke_mm, double start, double end, double step, double rel) {
  const double w = (end - start) / ref.T();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::vector<double>& r = rows[k];
    ASSERT_EQ(r.size(), 5u);
    const double theta = r[0];
    EXPECT_NEAR(theta, std::min(static_cast<double>(k) * step, 360.0), 1e-9) << k;
    if (theta < start || theta >= end) {
      EXPECT_EQ(r[1], theta < start ? 0.0 : stroke_mm) << theta;
      EXPECT_EQ(r[2], 0.0) << theta;
      EXPECT_EQ(r[3], 0.0) << theta;
      EXPECT_EQ(r[4], 0.0) << theta;
      continue;
    }
    const State s = ref.at((theta - start) / w);
    EXPECT_NEAR(r[1], s.s * 1e3, rel * stroke_mm) << theta;
    EXPECT_NEAR(r[2] * w, s.v * 1e3, rel * ref.v_peak() * 1e3) << theta;
    EXPECT_NEAR(r[3] * w * w, s.a * 1e3, rel * ref.a_peak() * 1e3) << theta;
    EXPECT_NEAR(r[4] * w * w * w, s.j * 1e3, rel * ref.max_jerk() * 1e3) << theta;
  }
}

// ---------------------------------------------------------------------------------------------

TEST(StRealLiteral, EveryValueIsAValidLiteralThatReadsBack) {
  using service::st_real_literal;
  EXPECT_EQ(st_real_literal(0.0), "0.0");
  EXPECT_EQ(st_real_literal(-0.0), "0.0");
  EXPECT_EQ(st_real_literal(100.0), "100.0");
  EXPECT_EQ(st_real_literal(-12.5), "-12.5");
  EXPECT_EQ(st_real_literal(0.1 + 0.2), "0.3");
  EXPECT_EQ(st_real_literal(3 * 0.1), "0.3");
  EXPECT_EQ(st_real_literal(1.25e-3), "0.00125");
  EXPECT_EQ(st_real_literal(1.25e-5), "1.25E-5");
  EXPECT_EQ(st_real_literal(1e-5), "1.0E-5");
  EXPECT_EQ(st_real_literal(-6.02e23), "-6.02E23");
  EXPECT_EQ(st_real_literal(1e22), "1.0E22");
  EXPECT_EQ(st_real_literal(123456789012345678.0), "1.23456789012346E17");
  EXPECT_EQ(st_real_literal(5e-324), "4.94065645841247E-324");
  EXPECT_THROW((void)st_real_literal(std::nan("")), std::invalid_argument);
  EXPECT_THROW((void)st_real_literal(HUGE_VAL), std::invalid_argument);
  EXPECT_THROW((void)st_real_literal(-HUGE_VAL), std::invalid_argument);
  std::mt19937_64 rng(99u);
  for (int i = 0; i < 20000; ++i) {
    const double mantissa = std::uniform_real_distribution<double>(-10.0, 10.0)(rng);
    const double v = std::ldexp(mantissa, std::uniform_int_distribution<int>(-200, 200)(rng));
    const std::string text = st_real_literal(v);
    ASSERT_TRUE(valid_real_literal(text)) << text;
    const double back = std::stod(text);
    ASSERT_NEAR(back, v, 1e-14 * std::abs(v)) << text;
  }
}

// A CSV cell is decimal (controllers' importers do not all read exponents) and reads back as the
// value exactly; a period of 0.3 ms writes 0.0003, not 3e-04.
TEST(CamCsvNumber, EveryValueIsDecimalAndReadsBack) {
  using service::csv_number;
  using service::kMaxCsvCell;
  EXPECT_EQ(csv_number(3 * 0.0001), "0.00030000000000000003");
  EXPECT_EQ(csv_number(0.0003), "0.0003");
  EXPECT_EQ(csv_number(1e-05), "0.00001");
  EXPECT_EQ(csv_number(800.0), "800");
  EXPECT_EQ(csv_number(-0.0), "0");
  EXPECT_EQ(csv_number(1e22), "10000000000000000000000");
  EXPECT_EQ(csv_number(3.6891160426209526e-06), "0.0000036891160426209526");
  EXPECT_EQ(csv_number(-3.6891160426209526e-06), "-3.6891160426209526e-06");  // 25 as decimal
  // Longer than a cell as decimal text: round-off residues keep the exponent.
  EXPECT_EQ(csv_number(1.2345678901234566e-13), "1.2345678901234566e-13");
  EXPECT_EQ(csv_number(1.25e-13), "0.000000000000125");
  EXPECT_EQ(csv_number(5e-324), "5e-324");
  std::mt19937_64 rng(7u);
  for (int i = 0; i < 20000; ++i) {
    const double mantissa = std::uniform_real_distribution<double>(-10.0, 10.0)(rng);
    const double v = std::ldexp(mantissa, std::uniform_int_distribution<int>(-60, 60)(rng));
    const std::string text = csv_number(v);
    ASSERT_LE(text.size(), kMaxCsvCell) << text;
    ASSERT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
    // Decimal wherever that fits a cell: every value of 1e-5 and more.
    if (std::abs(v) >= 1e-5) {
      ASSERT_EQ(text.find_first_of("eE"), std::string::npos) << text;
    }
  }
}

TEST(StGrammarCheck, RefusesWhatAnIecCompilerWouldRefuse) {
  const std::string good =
      "(* header *)\nTYPE\n  P :\n  STRUCT\n    a : LREAL; (* x *)\n    b : LREAL;\n  "
      "END_STRUCT;\nEND_TYPE\nVAR_GLOBAL CONSTANT\n  C : ARRAY[0..1] OF P := [\n    (a := 0.0, b "
      ":= -1.5E-3),\n    (a := 1_000.0, b := 2.0)\n  ];\nEND_VAR\n";
  const StFile file = parse_st(good);
  EXPECT_EQ(file.type, "P");
  EXPECT_EQ(file.members, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(file.name, "C");
  ASSERT_EQ(file.rows.size(), 2u);
  EXPECT_EQ(file.rows[0][1], -1.5e-3);
  EXPECT_EQ(file.rows[1][0], 1000.0);
  auto broken = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  EXPECT_THROW(parse_st(broken("-1.5E-3", "-1E-3")), std::runtime_error);      // no point
  EXPECT_THROW(parse_st(broken("-1.5E-3", "1.")), std::runtime_error);         // no digit after
  EXPECT_THROW(parse_st(broken("-1.5E-3", ".5")), std::runtime_error);         // no digit before
  EXPECT_THROW(parse_st(broken("-1.5E-3", "nan")), std::runtime_error);        // not a literal
  EXPECT_THROW(parse_st(broken("-1.5E-3", "inf")), std::runtime_error);        // not a literal
  EXPECT_THROW(parse_st(broken("-1.5E-3", "1.5E+-3")), std::runtime_error);    // bad exponent
  EXPECT_THROW(parse_st(broken("-1.5E-3", "1")), std::runtime_error);          // an integer
  EXPECT_THROW(parse_st(broken("[0..1]", "[0..2]")), std::runtime_error);      // count
  EXPECT_THROW(parse_st(broken("OF P", "OF Q")), std::runtime_error);          // type
  EXPECT_THROW(parse_st(broken("b := 2.0", "c := 2.0")), std::runtime_error);  // member
  EXPECT_THROW(parse_st(broken("END_VAR", "")), std::runtime_error);
  EXPECT_THROW(parse_st(broken("END_STRUCT;", "END_STRUCT")), std::runtime_error);
  EXPECT_THROW(parse_st(broken("(* x *)", "(* (* x *)")), std::runtime_error);  // nested
  EXPECT_THROW(parse_st(broken("(* header *)", "(* header")), std::runtime_error);
}

// ---------------------------------------------------------------------------------------------
// `slosh export` with the real binary.

class ExportMaster : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    plan_ = plan_of(kThesis);
    write_file(*dir_ / "request.json", kThesis);
    csv_run_ = export_to(*dir_ / "request.json", *dir_ / "cam.csv", kMasterArgs);
    st_run_ = export_to(*dir_ / "request.json", *dir_ / "cam.st",
                        with(kMasterArgs, {"--format", "st", "--st-name", "Transfer_Cam_1"}));
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static Reference7 reference() {
    return Reference7(plan_["durations_s"].get<Durations>(),
                      plan_["format"]["stroke_mm"].get<double>() * 1e-3);
  }

  static std::unique_ptr<TempDir> dir_;
  static json plan_;
  static RunResult csv_run_, st_run_;
};
std::unique_ptr<TempDir> ExportMaster::dir_;
json ExportMaster::plan_;
RunResult ExportMaster::csv_run_;
RunResult ExportMaster::st_run_;

TEST_F(ExportMaster, CsvFollowsThePlannedLawThroughTheMasterSpeed) {
  ASSERT_EQ(csv_run_.exit_code, 0) << csv_run_.err;
  EXPECT_EQ(csv_run_.err, "");
  std::string header;
  const auto rows = csv_rows(read_file(*dir_ / "cam.csv"), header);
  EXPECT_EQ(header,
            "master,position_mm,velocity_mm_per_unit,acceleration_mm_per_unit2,jerk_mm_per_unit3");
  ASSERT_EQ(rows.size(), 361u);  // 0..360 degrees, the default step 360 / 360
  const Reference7 ref = reference();
  ASSERT_NEAR(ref.T(), 1.0, 1e-12);
  expect_master_rows(rows, ref, 800.0, 30.0, 210.0, 1.0, 1e-11);
  // The motion ends on the row of master_end, on the stroke exactly.
  EXPECT_EQ(rows[210][0], 210.0);
  EXPECT_EQ(rows[210][1], 800.0);
  EXPECT_LT(rows[209][1], 800.0);
  EXPECT_GT(rows[31][1], 0.0);
  EXPECT_EQ(rows[30][1], 0.0);
  EXPECT_NEAR(rows[30][4] * std::pow(180.0, 3), ref.at(0.0).j * 1e3, 1e-11 * ref.max_jerk() * 1e3);
  const json summary = json::parse(csv_run_.out);
  EXPECT_EQ(summary["table"], "master");
  EXPECT_EQ(summary["file_format"], "csv");
  EXPECT_EQ(summary["key"], plan_["key"]);
  EXPECT_EQ(summary["samples"], 361);
  EXPECT_EQ(summary["master"], json::parse(R"({"period": 360.0, "start": 30.0, "end": 210.0,
      "step": 1.0, "speed_per_s": 180.0, "equidistant": true})"));
  EXPECT_FALSE(summary.contains("period_s"));
  EXPECT_FALSE(summary.contains("end_time_s"));
  EXPECT_EQ(summary["warnings"], json::array());
}

TEST_F(ExportMaster, StFileParsesAndHoldsTheRowsOfTheCsv) {
  ASSERT_EQ(st_run_.exit_code, 0) << st_run_.err;
  const json summary = json::parse(st_run_.out);
  EXPECT_EQ(summary["file_format"], "st");
  EXPECT_EQ(summary["samples"], 361);
  const std::string text = read_file(*dir_ / "cam.st");
  StFile st;
  try {
    st = parse_st(text);
  } catch (const std::exception& e) {
    FAIL() << e.what() << "\n" << text.substr(0, 2000);
  }
  EXPECT_EQ(st.type, "SLOSH_MASTER_CAM_POINT");
  EXPECT_EQ(st.name, "Transfer_Cam_1");
  EXPECT_EQ(st.members,
            (std::vector<std::string>{"master", "position_mm", "velocity_mm_per_unit",
                                      "acceleration_mm_per_unit2", "jerk_mm_per_unit3"}));
  EXPECT_EQ(st.lo, 0);
  EXPECT_EQ(st.hi, 360);
  // The rows follow the law to the 15 digits printed, and are the CSV's to its 12.
  expect_master_rows(st.rows, reference(), 800.0, 30.0, 210.0, 1.0, 1e-12);
  std::string header;
  const auto csv = csv_rows(read_file(*dir_ / "cam.csv"), header);
  ASSERT_EQ(csv.size(), st.rows.size());
  for (std::size_t k = 0; k < csv.size(); ++k) {
    for (std::size_t c = 0; c < 5; ++c) {
      EXPECT_NEAR(st.rows[k][c], csv[k][c], 6e-12 * std::abs(csv[k][c]) + 1e-300) << k << "," << c;
    }
  }
  // The header: format, strategy, recipe key, slosh version (that of `slosh --version`).
  ASSERT_FALSE(st.comments.empty());
  const std::string& head = st.comments.front();
  EXPECT_NE(head.find("IEC 61131-3 structured text"), std::string::npos) << head;
  EXPECT_NE(head.find("format: master-axis cam table over one master period, 361 points, step 1 "
                      "master units (equidistant)"),
            std::string::npos)
      << head;
  EXPECT_NE(head.find("\n   strategy: multi_notch\n"), std::string::npos) << head;
  EXPECT_NE(head.find("\n   recipe key: " + plan_["key"].get<std::string>() + "\n"),
            std::string::npos)
      << head;
  EXPECT_NE(head.find(std::string("\n   slosh version: ") + kVersion + "\n"), std::string::npos)
      << head;
  EXPECT_NE(head.find("master axis: period 360, motion from 30 to 210 at 180 master units/s"),
            std::string::npos)
      << head;
  EXPECT_EQ(run_slosh({"--version"}).out, std::string("slosh ") + kVersion + "\n");
}

TEST(ExportStCli, TimeBasedStFileOfALawRequest) {
  // A poly5 law request: the rows against the quintic's closed form, written here.
  const TempDir dir;
  write_file(dir / "law.json", R"({"format": {"container": {"radius_mm": 40},
      "fill_height_mm": 70, "fluid": "water", "stroke_mm": 500, "motion_time_s": 0.8},
      "law": {"type": "poly5"}})");
  const RunResult r =
      export_to(dir / "law.json", dir / "cam.st", {"--format", "st", "--period-ms", "2.5"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const StFile st = parse_st(read_file(dir / "cam.st"));
  EXPECT_EQ(st.type, "SLOSH_CAM_POINT");
  EXPECT_EQ(st.name, "SLOSH_CAM");
  EXPECT_EQ(st.members, (std::vector<std::string>{"t_s", "position_mm", "velocity_mm_s",
                                                  "acceleration_mm_s2", "jerk_mm_s3"}));
  ASSERT_EQ(st.rows.size(), 321u);  // 0.8 s every 2.5 ms
  const double S = 500.0, T = 0.8;
  for (std::size_t k = 0; k < st.rows.size(); ++k) {
    const std::vector<double>& row = st.rows[k];
    EXPECT_NEAR(row[0], static_cast<double>(k) * 0.0025, 1e-15);
    const double u = row[0] / T;
    if (k + 1 == st.rows.size()) {
      EXPECT_EQ(row, (std::vector<double>{0.8, S, 0.0, 0.0, 0.0}));
      continue;
    }
    EXPECT_NEAR(row[1], S * u * u * u * (10 - 15 * u + 6 * u * u), 1e-12 * S);
    EXPECT_NEAR(row[2], S / T * 30 * u * u * (1 - u) * (1 - u), 1e-12 * S / T);
    EXPECT_NEAR(row[3], S / (T * T) * 60 * u * (1 - 3 * u + 2 * u * u), 1e-12 * S / (T * T));
    EXPECT_NEAR(row[4], S / (T * T * T) * 60 * (1 - 6 * u + 6 * u * u), 1e-11 * S / (T * T * T));
  }
  const std::string& head = st.comments.front();
  EXPECT_NE(head.find("format: time-based cam table, 321 points, one every 2.5 ms"),
            std::string::npos)
      << head;
  EXPECT_NE(head.find("strategy: none (a law request, not a plan)"), std::string::npos) << head;
  EXPECT_NE(head.find("law: poly5, stroke 500 mm, motion time 0.8 s"), std::string::npos) << head;
  const json summary = json::parse(r.out);
  EXPECT_EQ(summary["table"], "time");
  EXPECT_EQ(summary["file_format"], "st");
  EXPECT_EQ(summary["period_s"], 0.0025);
}

TEST(ExportMasterCli, OffGridPositionsGetRowsAndAWarning) {
  const TempDir dir;
  write_file(dir / "request.json", kThesis);
  const RunResult r = export_to(dir / "request.json", dir / "cam.csv",
                                {"--master-period", "360", "--master-start", "30.5", "--master-end",
                                 "210.25", "--master-step", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = json::parse(r.out);
  const std::string warning =
      "--master-start 30.5 and --master-end 210.25 are not a multiple of --master-step 1: rows "
      "are added there, so the rows are not equidistant (load the table as a non-equidistant "
      "cam)";
  EXPECT_EQ(summary["warnings"], json::array({warning}));
  EXPECT_EQ(summary["master"]["equidistant"], false);
  EXPECT_EQ(summary["samples"], 363);
  std::string header;
  const auto rows = csv_rows(read_file(dir / "cam.csv"), header);
  ASSERT_EQ(rows.size(), 363u);
  EXPECT_EQ(rows[31][0], 30.5);
  EXPECT_EQ(rows[31][1], 0.0);
  EXPECT_EQ(rows[212][0], 210.25);
  EXPECT_EQ(rows[212][1], 800.0);
  EXPECT_LT(rows[211][1], 800.0);
  // To stdout: the warning goes to stderr.
  const RunResult to_stdout =
      run_slosh({"export", "--request", (dir / "request.json").string(), "--out", "-", "--cache",
                 "", "--master-period", "360", "--master-start", "30.5", "--master-end", "210.25"});
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_EQ(to_stdout.err, "slosh export: warning: " + warning + "\n");
  EXPECT_EQ(to_stdout.out, read_file(dir / "cam.csv"));
}

TEST(ExportMasterCli, BadOptionsAreRefusedNamingTheOptionTheValueAndTheRange) {
  const TempDir dir;
  write_file(dir / "request.json", kThesis);
  const std::string relation =
      " master units (0 <= --master-start < --master-end <= --master-period, --master-end - "
      "--master-start >= 1e-06)";
  const std::string missing =
      " is missing: a master-axis table needs --master-period, --master-start and --master-end";
  struct Case {
    std::vector<std::string> args;
    std::string field;
    std::string message;
  };
  const std::vector<Case> cases{
      {{"--master-period", "0", "--master-start", "30", "--master-end", "210"},
       "--master-period",
       "--master-period = 0 is out of range: allowed >= 1e-06 master units"},
      {{"--master-period", "nan", "--master-start", "30", "--master-end", "210"},
       "--master-period",
       "--master-period = nan is not finite: allowed >= 1e-06 master units"},
      {{"--master-period", "360", "--master-start", "-1", "--master-end", "210"},
       "--master-start",
       "--master-start = -1 is out of range [0, 360)" + relation},
      {{"--master-period", "360", "--master-start", "360", "--master-end", "210"},
       "--master-start",
       "--master-start = 360 is out of range [0, 360)" + relation},
      {{"--master-period", "360", "--master-start", "30", "--master-end", "400"},
       "--master-end",
       "--master-end = 400 is out of range (30, 360]" + relation},
      {{"--master-period", "360", "--master-start", "250", "--master-end", "210"},
       "--master-end",
       "--master-end = 210 is out of range (250, 360]" + relation},
      {with(kMasterArgs, {"--master-step", "0"}), "--master-step",
       "--master-step = 0 is out of range: allowed > 0 master units"},
      {with(kMasterArgs, {"--master-step", "-0.5"}), "--master-step",
       "--master-step = -0.5 is out of range: allowed > 0 master units"},
      {with(kMasterArgs, {"--master-step", "1e-5"}), "--master-step",
       "--master-step = 1e-05 gives more than 10000000 rows over the master period 360: allowed "
       ">= 3.600001081e-05 master units"},
      {{"--master-period", "360", "--master-start", "30"},
       "--master-end",
       "--master-end" + missing},
      {{"--master-step", "2"}, "--master-period", "--master-period" + missing},
      {{"--master-period", "360", "--master-end", "210"},
       "--master-start",
       "--master-start" + missing},
      {with(kMasterArgs, {"--period-ms", "2"}), "--period-ms",
       "--period-ms applies to a time-based table: a master-axis table (--master-period) has a "
       "row every --master-step"},
      {{"--st-name", "CAM"}, "--st-name", "--st-name applies to the structured-text format only"},
      {{"--format", "st", "--st-name", "1CAM"},
       "--st-name",
       "--st-name = 1CAM is not an IEC 61131-3 identifier: letters, digits and single "
       "underscores, not starting with a digit nor ending with an underscore, at most 64 "
       "characters"},
      {{"--format", "st", "--st-name", "MY__CAM"},
       "--st-name",
       "--st-name = MY__CAM is not an IEC 61131-3 identifier: letters, digits and single "
       "underscores, not starting with a digit nor ending with an underscore, at most 64 "
       "characters"},
      {{"--format", "st", "--st-name", "end_var"},
       "--st-name",
       "--st-name = end_var is reserved: END_VAR is an IEC 61131-3 keyword (identifiers are not "
       "case-sensitive)"},
      {{"--format", "st", "--st-name", "slosh_cam_point"},
       "--st-name",
       "--st-name = slosh_cam_point is reserved: SLOSH_CAM_POINT is the structure type every slosh "
       "export declares (identifiers are not case-sensitive)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.message);
    const RunResult r = export_to(dir / "request.json", dir / "cam.out", c.args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(
        error_of(r),
        json({{"error", {{"code", "invalid_value"}, {"field", c.field}, {"message", c.message}}}}));
    EXPECT_FALSE(fs::exists(dir / "cam.out"));
  }
  const RunResult format = export_to(dir / "request.json", dir / "cam.out", {"--format", "xml"});
  EXPECT_EQ(format.exit_code, 2);
  EXPECT_EQ(format.err.rfind("--format: xml not in {csv,st}\n", 0), 0u) << format.err;
  EXPECT_FALSE(fs::exists(dir / "cam.out"));
}

// ---------------------------------------------------------------------------------------------
// GET /v1/plans/{key}/cam.csv and cam.st on a real server.

class CamRoutes : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = std::make_unique<test::Server>(std::vector<std::string>{"--workers", "1"});
    httplib::Client client = server_->client();
    const auto planned = client.Post("/v1/plans", kThesis, "application/json");
    ASSERT_TRUE(planned);
    ASSERT_EQ(planned->status, 200) << planned->body;
    key_ = json::parse(planned->body)["key"];
  }
  static void TearDownTestSuite() { server_.reset(); }

  /// The error object of GET /v1/plans/{key}/`route`, which must answer 422.
  static json error_of_get(const std::string& route) {
    const auto res = server_->client().Get("/v1/plans/" + key_ + "/" + route);
    EXPECT_TRUE(res);
    if (!res) return json();
    EXPECT_EQ(res->status, 422) << route << ": " << res->body;
    return json::parse(res->body)["error"];
  }
  /// GET `route` answers 422 with exactly this field and message.
  static void expect_error(const std::string& route, const std::string& field,
                           const std::string& message) {
    EXPECT_EQ(error_of_get(route),
              json({{"code", "invalid_value"}, {"field", field}, {"message", message}}))
        << route;
  }

  static std::unique_ptr<test::Server> server_;
  static std::string key_;
};
std::unique_ptr<test::Server> CamRoutes::server_;
std::string CamRoutes::key_;

TEST_F(CamRoutes, MasterCsvAndStAreTheFilesOfSloshExport) {
  httplib::Client client = server_->client();
  const TempDir dir;
  write_file(dir / "request.json", kThesis);
  struct Case {
    std::string route;
    std::vector<std::string> args;
    std::string type;
    std::string file;
  };
  const std::string master = "master_period=360&master_start=30&master_end=210";
  const std::vector<Case> cases{
      {"cam.csv?" + master, kMasterArgs, "text/csv; charset=utf-8", "master.csv"},
      {"cam.csv?" + master + "&master_step=0.5", with(kMasterArgs, {"--master-step", "0.5"}),
       "text/csv; charset=utf-8", "master.csv"},
      {"cam.st", {"--format", "st"}, "text/plain; charset=utf-8", "1ms.st"},
      {"cam.st?period_ms=4",
       {"--format", "st", "--period-ms", "4"},
       "text/plain; charset=utf-8",
       "4ms.st"},
      {"cam.st?" + master + "&st_name=FILLER_CAM",
       with(kMasterArgs, {"--format", "st", "--st-name", "FILLER_CAM"}),
       "text/plain; charset=utf-8", "master.st"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.route);
    const auto res = client.Get("/v1/plans/" + key_ + "/" + c.route);
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), c.type);
    EXPECT_EQ(res->get_header_value("Content-Disposition"),
              "attachment; filename=\"cam-" + key_ + "-" + c.file + "\"");
    const RunResult exported = export_to(dir / "request.json", dir / "cam.out", c.args);
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
    EXPECT_EQ(res->body, read_file(dir / "cam.out"));
    if (c.type.starts_with("text/plain")) {
      EXPECT_NO_THROW((void)parse_st(res->body));
    }
  }
  // The master ST of the server follows the planned law too.
  const auto st = client.Get("/v1/plans/" + key_ + "/cam.st?" + master);
  ASSERT_TRUE(st);
  const StFile file = parse_st(st->body);
  const json plan = json::parse(client.Get("/v1/plans/" + key_)->body);
  const Reference7 ref(plan["durations_s"].get<Durations>(), 0.8);
  expect_master_rows(file.rows, ref, 800.0, 30.0, 210.0, 1.0, 1e-12);
}

TEST_F(CamRoutes, QueryErrorsAre422NamingTheParameter) {
  httplib::Client client = server_->client();
  const std::string relation =
      " master units (0 <= master_start < master_end <= master_period, master_end - master_start "
      ">= 1e-06)";
  for (const char* route : {"cam.csv", "cam.st"}) {
    const std::string r = std::string(route) + "?";
    expect_error(r + "master_period=360&master_start=abc&master_end=210", "master_start",
                 "master_start = abc is not a decimal number [master units]");
    expect_error(r + "master_period=360&master_start=30&master_end=210&master_step=1x",
                 "master_step", "master_step = 1x is not a decimal number [master units]");
    expect_error(r + "master_period=-360&master_start=30&master_end=210", "master_period",
                 "master_period = -360 is out of range: allowed >= 1e-06 master units");
    expect_error(r + "master_period=360&master_start=30&master_end=361", "master_end",
                 "master_end = 361 is out of range (30, 360]" + relation);
    expect_error(r + "master_period=360&master_start=400&master_end=410", "master_start",
                 "master_start = 400 is out of range [0, 360)" + relation);
    expect_error(r + "master_period=360&master_start=30", "master_end",
                 "master_end is missing: a master-axis table needs master_period, master_start "
                 "and master_end");
    expect_error(r + "master_period=360&master_start=30&master_end=210&period_ms=1", "period_ms",
                 "period_ms applies to a time-based table: a master-axis table (master_period) "
                 "has a row every master_step");
    // The served tables are bounded (200 000 rows); slosh export writes longer ones.
    expect_error(r + "master_period=360&master_start=30&master_end=210&master_step=0.001",
                 "master_step",
                 "master_step = 0.001 gives more than 200000 rows over the master period 360: "
                 "allowed >= 0.001800027001 master units here (slosh export writes longer "
                 "tables)");
  }
  const auto bounded = client.Get("/v1/plans/" + key_ +
                                  "/cam.csv?master_period=360&master_start=30&master_end=210&"
                                  "master_step=0.001800027001");
  ASSERT_TRUE(bounded);
  EXPECT_EQ(bounded->status, 200);
  // 199 997 grid points, master_start, master_end and master_period, and the header.
  EXPECT_EQ(std::count(bounded->body.begin(), bounded->body.end(), '\n'), 200000 + 1);
  // The one rule for query parameters: st_name is not one of cam.csv's, and cam.st takes it.
  expect_error("cam.csv?st_name=CAM", "st_name",
               "st_name is not a query parameter of GET /v1/plans/{key}/cam.csv (GET "
               "/v1/plans/{key}/cam.st takes it); allowed here: period_ms, master_period, "
               "master_start, master_end, master_step, allow_infeasible");
  expect_error("cam.st?st_name=TYPE", "st_name",
               "st_name = TYPE is reserved: TYPE is an IEC 61131-3 keyword (identifiers are not "
               "case-sensitive)");
  expect_error("cam.st?period_ms=0", "period_ms", "period_ms = 0 is out of range [0.01, 1000] ms");
  const auto unknown = client.Get("/v1/plans/0123456789abcdef/cam.st");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(json::parse(unknown->body)["error"]["field"], "key");
}

// Regression: the query numbers were read with std::stod (hex "0x10", "inf", "nan", a
// leading "+" or space accepted; 4.9e-324 called "not a number"), a repeated parameter was
// resolved silently (the first one won) and an empty st_name fell back to the default.
TEST_F(CamRoutes, QueryNumbersAreDecimalNumbersAndEachParameterIsGivenOnce) {
  httplib::Client client = server_->client();
  const std::string axis = "master_start=30&master_end=210";
  for (const char* route : {"cam.csv", "cam.st"}) {
    const std::string r = std::string(route) + "?";
    struct Case {
      std::string query;  // URL-encoded
      std::string shown;  // as the message quotes it
    };
    for (const Case& c : std::vector<Case>{{"0x10", "0x10"},
                                           {"0X1p3", "0X1p3"},
                                           {"inf", "inf"},
                                           {"-infinity", "-infinity"},
                                           {"nan", "nan"},
                                           {"NaN", "NaN"},
                                           {"%2B360", "+360"},
                                           {"%20360", " 360"},
                                           {"360%20", "360 "},
                                           {"360.0.0", "360.0.0"},
                                           {"1e", "1e"},
                                           {".", "."},
                                           {"-", "-"},
                                           {"", "(empty)"}}) {
      expect_error(r + "master_period=" + c.query + "&" + axis, "master_period",
                   "master_period = " + c.shown + " is not a decimal number [master units]");
    }
    expect_error(r + "period_ms=0x10", "period_ms",
                 "period_ms = 0x10 is not a decimal number [ms]");
    expect_error(r + "master_period=360&master_start=30&master_end=210&master_step=inf",
                 "master_step", "master_step = inf is not a decimal number [master units]");
    expect_error(r + "master_period=1e400&" + axis, "master_period",
                 "master_period = 1e400 is beyond the range of a double: a number is 0 or of a "
                 "magnitude from 4.9e-324 to 1.8e+308 [master units]");
    expect_error(r + "master_period=360&master_start=1e-400&master_end=210", "master_start",
                 "master_start = 1e-400 is beyond the range of a double: a number is 0 or of a "
                 "magnitude from 4.9e-324 to 1.8e+308 [master units]");
    // Repeated parameters are refused, never resolved.
    expect_error(r + "master_period=360&master_period=720&" + axis, "master_period",
                 "master_period is given twice (360 and 720): give each query parameter once");
    expect_error(r + "master_period=360&" + axis + "&master_end=210", "master_end",
                 "master_end is given twice (210 and 210): give each query parameter once");
    expect_error(r + "period_ms=1&period_ms=2&period_ms=3&period_ms=4", "period_ms",
                 "period_ms is given 4 times (1, 2, 3, ...): give each query parameter once");
    expect_error(r + "allow_infeasible=true&allow_infeasible=false", "allow_infeasible",
                 "allow_infeasible is given twice (true and false): give each query parameter "
                 "once");
    expect_error(r + "allow_infeasible=", "allow_infeasible",
                 "allow_infeasible = (empty) is not allowed: one of \"true\", \"false\"");
  }
  expect_error("cam.st?st_name=", "st_name",
               "st_name = (empty) is not an IEC 61131-3 identifier: letters, digits and single "
               "underscores, not starting with a digit nor ending with an underscore, at most 64 "
               "characters");
  expect_error("cam.st?st_name=A&st_name=B", "st_name",
               "st_name is given twice (A and B): give each query parameter once");
  // Decimal numbers as people write them are read, a denormal one too (it is a number: the
  // start 4.9e-324 lies in [0, 360)); and a denormal period is refused for what it is.
  for (const char* ok : {"master_period=360&master_start=30&master_end=210.0",
                         "master_period=360.&master_start=.5e2&master_end=2.1E2",
                         "master_period=360&master_start=-0&master_end=210",
                         "master_period=360&master_start=4.9e-324&master_end=210"}) {
    const auto res = client.Get("/v1/plans/" + key_ + "/cam.csv?" + ok);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200) << ok << ": " << res->body.substr(0, 200);
  }
  const auto denormal =
      client.Get("/v1/plans/" + key_ + "/cam.csv?master_period=360&master_start=4.9e-324&" +
                 "master_end=210&master_step=30");
  ASSERT_TRUE(denormal);
  ASSERT_EQ(denormal->status, 200);
  // The motion starts on its own row, written as the number it is.
  EXPECT_NE(denormal->body.find("\n5e-324,0,0,0,"), std::string::npos) << denormal->body;
  expect_error("cam.csv?master_period=4.9e-324&master_start=0&master_end=4.9e-324", "master_period",
               "master_period = 5e-324 is out of range: allowed >= 1e-06 master units");
}

// Regression: st_name accepted the names of IEC 61131-3 standard function blocks and
// functions (TON, CTU, R_TRIG, SIN, REAL_TO_INT, ...), which a PLC project already declares.
TEST_F(CamRoutes, StNamesOfKeywordsTypesAndStandardBlocksAreRefusedWhateverTheirCase) {
  httplib::Client client = server_->client();
  const TempDir dir;
  write_file(dir / "request.json", kThesis);
  struct Case {
    std::string name;
    std::string reason;
  };
  const std::string keyword = "an IEC 61131-3 keyword";
  const std::string type = "an IEC 61131-3 elementary or generic data type";
  const std::string block = "an IEC 61131-3 standard function block";
  const std::string function = "an IEC 61131-3 standard function";
  const std::string conversion = "an IEC 61131-3 standard type conversion function";
  const std::vector<Case> cases{
      {"TON", block},
      {"ton", block},
      {"Tof", block},
      {"TP", block},
      {"CTU", block},
      {"ctd", block},
      {"CTUD", block},
      {"R_Trig", block},
      {"F_TRIG", block},
      {"SR", block},
      {"rs", block},
      {"CTU_DINT", block},
      {"END_VAR", keyword},
      {"array", keyword},
      {"Of", keyword},
      {"STRUCT", keyword},
      {"type", keyword},
      {"VAR", keyword},
      {"var_input", keyword},
      {"IF", keyword},
      {"then", keyword},
      {"END_FUNCTION_BLOCK", keyword},
      {"INT", type},
      {"REAL", type},
      {"lreal", type},
      {"TIME", type},
      {"Any_Num", type},
      {"SIN", function},
      {"limit", function},
      {"MUX", function},
      {"REAL_TO_INT", conversion},
      {"to_dint", conversion},
      {"TRUNC_INT", conversion},
      {"BCD_TO_WORD", conversion},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::string upper = c.name;
    std::transform(upper.begin(), upper.end(), upper.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
    const std::string why =
        " is reserved: " + upper + " is " + c.reason + " (identifiers are not case-sensitive)";
    const auto res = client.Get("/v1/plans/" + key_ + "/cam.st?st_name=" + c.name);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 422);
    EXPECT_EQ(json::parse(res->body)["error"], json({{"code", "invalid_value"},
                                                     {"field", "st_name"},
                                                     {"message", "st_name = " + c.name + why}}));
    const RunResult r =
        export_to(dir / "request.json", dir / "cam.st", {"--format", "st", "--st-name", c.name});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(error_of(r), json({{"error",
                                  {{"code", "invalid_value"},
                                   {"field", "--st-name"},
                                   {"message", "--st-name = " + c.name + why}}}}));
  }
  // Names that only contain one of them are fine.
  for (const char* ok : {"TON_CAM", "MY_TYPE", "CAM_OF_LINE_2", "INTERVAL_CAM", "TIME_TO_GO"}) {
    const auto res = client.Get("/v1/plans/" + key_ + "/cam.st?st_name=" + ok);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200) << ok << ": " << res->body.substr(0, 300);
  }
}

// Regression: a master period of 1e308 over a 0.5 s motion overflowed the master speed
// (master_end - master_start) / T to inf: a table of zeros, "speed_per_s": null in the summary
// and "inf" in the ST header. Refused at master_period, in the CLI and over HTTP alike.
TEST_F(CamRoutes, AMasterSpeedThatIsNotAFiniteNumberIsRefusedAtTheMasterPeriod) {
  httplib::Client client = server_->client();
  json request = json::parse(kThesis);
  request["format"]["motion_time_s"] = 0.5;
  const auto planned = client.Post("/v1/plans", request.dump(), "application/json");
  ASSERT_TRUE(planned);
  ASSERT_EQ(planned->status, 200) << planned->body;
  const std::string key = json::parse(planned->body)["key"];
  const TempDir dir;
  write_file(dir / "request.json", request.dump());
  struct Case {
    std::string period, end, step, speed, verdict;
  };
  const std::vector<Case> cases{
      {"1e308", "1e308", "1e306", "inf", "not finite"},
      {"1.7976931348623157e308", "1.7976931348623157e308", "1e306", "inf", "not finite"},
      {"1e31", "1e30", "1e29", "2e+30", "out of range"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.period);
    const std::string shown = c.period == "1e308"  ? "1e+308"
                              : c.period == "1e31" ? "1e+31"
                                                   : "1.7976931348623157e+308";
    const std::string message = " = " + shown + " makes the master speed (%end - %start) / " +
                                "motion time = " + c.speed + " master units/s over the 0.5 s " +
                                "motion, which is " + c.verdict +
                                ": allowed [1e-30, 1e+30] master units/s, i.e. %end - %start " +
                                "in [5e-31, 5e+29] master units";
    auto named = [&](const std::string& prefix, const std::string& end, const std::string& start) {
      std::string text = prefix + message;
      for (std::size_t at; (at = text.find("%end")) != std::string::npos;) {
        text.replace(at, 4, end);
      }
      for (std::size_t at; (at = text.find("%start")) != std::string::npos;) {
        text.replace(at, 6, start);
      }
      return text;
    };
    for (const char* route : {"cam.csv", "cam.st"}) {
      const auto res = client.Get("/v1/plans/" + key + "/" + route + "?master_period=" + c.period +
                                  "&master_start=0&master_end=" + c.end + "&master_step=" + c.step);
      ASSERT_TRUE(res);
      EXPECT_EQ(res->status, 422) << res->body.substr(0, 300);
      EXPECT_EQ(json::parse(res->body)["error"],
                json({{"code", "invalid_value"},
                      {"field", "master_period"},
                      {"message", named("master_period", "master_end", "master_start")}}));
    }
    for (const char* format : {"csv", "st"}) {
      const RunResult r =
          export_to(dir / "request.json", dir / "cam.out",
                    {"--format", format, "--master-period", c.period, "--master-start", "0",
                     "--master-end", c.end, "--master-step", c.step});
      EXPECT_EQ(r.exit_code, 2) << r.out.substr(0, 300);
      EXPECT_EQ(r.out, "");
      EXPECT_EQ(
          error_of(r),
          json({{"error",
                 {{"code", "invalid_value"},
                  {"field", "--master-period"},
                  {"message", named("--master-period", "--master-end", "--master-start")}}}}));
      EXPECT_FALSE(fs::exists(dir / "cam.out"));
    }
  }
  // At the fastest speed allowed (5e29 over 0.5 s), the summary's speed is a number.
  const RunResult fast = export_to(dir / "request.json", dir / "cam.out",
                                   {"--master-period", "5e29", "--master-start", "0",
                                    "--master-end", "5e29", "--master-step", "5e27"});
  ASSERT_EQ(fast.exit_code, 0) << fast.err;
  EXPECT_EQ(json::parse(fast.out)["master"]["speed_per_s"], 1e30);
}

// Regression: odd master values gave refusals whose texts contradicted themselves: an empty
// allowed range ("[360.0000005, 360]"), a value rounded onto its bound ("--master-end = 360 is
// out of range (30, 360]" for 360.0000000001), and a bound that reads below the refused step.
TEST(ExportMasterCli, OddValuesAreRefusedWithTheValueVisiblyOutsideANonEmptyRange) {
  const TempDir dir;
  write_file(dir / "request.json", kThesis);
  const std::string relation =
      " master units (0 <= --master-start < --master-end <= --master-period, --master-end - "
      "--master-start >= 1e-06)";
  struct Case {
    std::vector<std::string> args;
    std::string field;
    std::string message;
  };
  const std::vector<Case> cases{
      {{"--master-period", "360", "--master-start", "359.9999995", "--master-end", "360"},
       "--master-start",
       "--master-start = 359.9999995 is out of range [0, 359.999999]" + relation},
      {{"--master-period", "360", "--master-start", "30", "--master-end", "360.0000000001"},
       "--master-end",
       "--master-end = 360.0000000001 is out of range (30, 360]" + relation},
      {{"--master-period", "360", "--master-start", "30", "--master-end", "30.0000000001"},
       "--master-end",
       "--master-end = 30.0000000001 is out of range [30.000001, 360]" + relation},
      {{"--master-period", "360", "--master-start", "359.99999900000006", "--master-end", "360"},
       "--master-start",
       "--master-start = 359.99999900000006 is out of range [0, 359.999999]" + relation},
      {{"--master-period", "4.9e-324", "--master-start", "0", "--master-end", "4.9e-324"},
       "--master-period",
       "--master-period = 5e-324 is out of range: allowed >= 1e-06 master units"},
      {{"--master-period", "1e-7", "--master-start", "0", "--master-end", "1e-7"},
       "--master-period",
       "--master-period = 1e-07 is out of range: allowed >= 1e-06 master units"},
      {with(kMasterArgs, {"--master-step", "3.6000010800001e-05"}), "--master-step",
       "--master-step = 3.6000010800001e-05 gives more than 10000000 rows over the master "
       "period 360: allowed >= 3.600001081e-05 master units"},
      {with(kMasterArgs, {"--period-ms", "2"}), "--period-ms",
       "--period-ms applies to a time-based table: a master-axis table (--master-period) has a "
       "row every --master-step"},
      {{"--period-ms", "1000.0000000001"},
       "--period-ms",
       "--period-ms = 1000.0000000001 is out of range [0.01, 1000] ms"},
      {{"--period-ms", "0.0099999999999"},
       "--period-ms",
       "--period-ms = 0.0099999999999 is out of range [0.01, 1000] ms"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.message);
    const RunResult r = export_to(dir / "request.json", dir / "cam.out", c.args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(
        error_of(r),
        json({{"error", {{"code", "invalid_value"}, {"field", c.field}, {"message", c.message}}}}));
    EXPECT_FALSE(fs::exists(dir / "cam.out"));
  }
  // A denormal start is a number in [0, 360): exported.
  const RunResult denormal =
      export_to(dir / "request.json", dir / "cam.out",
                {"--master-period", "360", "--master-start", "4.9e-324", "--master-end", "210"});
  EXPECT_EQ(denormal.exit_code, 0) << denormal.err;
}

// Regression: the CSV had 12 significant digits, so a stroke of more digits did not land in
// the last row exactly. Every number is the shortest text that reads back as the value, and the
// rows at the stroke hold it as the request gave it, in the CLI and over HTTP alike.
TEST(CamCsv, TheLastRowHoldsAStrokeOfManyDigitsExactly) {
  json request = json::parse(kThesis);
  request["format"]["stroke_mm"] = 800.123456789012;
  const test::Server server({"--workers", "1"});
  httplib::Client client = server.client();
  const auto planned = client.Post("/v1/plans", request.dump(), "application/json");
  ASSERT_TRUE(planned);
  ASSERT_EQ(planned->status, 200) << planned->body;
  const std::string key = json::parse(planned->body)["key"];
  const TempDir dir;
  write_file(dir / "request.json", request.dump());
  struct Case {
    std::string query;
    std::vector<std::string> args;
  };
  const std::vector<Case> cases{
      {"", {}},
      {"?period_ms=0.7", {"--period-ms", "0.7"}},
      {"?master_period=360&master_start=30&master_end=210", kMasterArgs},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.query);
    const auto res = client.Get("/v1/plans/" + key + "/cam.csv" + c.query);
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body.substr(0, 300);
    const RunResult r = export_to(dir / "request.json", dir / "cam.csv", c.args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string file = read_file(dir / "cam.csv");
    EXPECT_EQ(res->body, file);
    std::string header;
    const auto rows = csv_rows(file, header);
    ASSERT_GT(rows.size(), 2u);
    EXPECT_EQ(rows.back()[1], 800.123456789012);
    const std::size_t last = file.rfind('\n', file.size() - 2);
    const std::string line = file.substr(last + 1);
    EXPECT_NE(line.find(",800.123456789012,0,0,0\n"), std::string::npos) << line;
    // Every cell is the shortest decimal text of its number (no digit more than it needs), or
    // its shortest exponent form where the decimal one passes 24 characters.
    std::size_t checked = 0;
    for (std::size_t at = file.find('\n') + 1; at < file.size() && checked < 4000;) {
      const std::size_t end = file.find_first_of(",\n", at);
      const std::string text = file.substr(at, end - at);
      double v = 0.0;
      std::from_chars(text.data(), text.data() + text.size(), v);
      std::array<char, 64> shortest{};
      auto printed = std::to_chars(shortest.data(), shortest.data() + shortest.size(), v,
                                   std::chars_format::fixed);
      if (printed.ptr - shortest.data() > 24) {
        printed = std::to_chars(shortest.data(), shortest.data() + shortest.size(), v);
      }
      EXPECT_EQ(text, v == 0.0 ? std::string("0") : std::string(shortest.data(), printed.ptr));
      at = end + 1;
      ++checked;
    }
  }
}

// Regression: concurrent cam exports had no global memory bound (200 parallel requests for
// 200 000-row tables reached more than 3 GB). Each export reserves an upper bound of its bytes
// in cam_export_bytes until its response is written; one that does not fit is a 503 with
// Retry-After. A client that does not read a large table holds its share until the server gives
// up writing or the client goes away.
TEST(CamExportBudget, ExportsBeyondTheBudgetAre503UntilTheExportsInFlightAreDone) {
  const TempDir dir;
  write_file(dir / "config.json", R"({"cam_export_bytes": 1048576, "write_timeout_s": 60})");
  test::Server server({"--workers", "1", "--config", (dir / "config.json").string()});
  ASSERT_GT(server.port(), 0) << server.log();
  httplib::Client client = server.client();
  const auto planned = client.Post("/v1/plans", kThesis, "application/json");
  ASSERT_TRUE(planned);
  ASSERT_EQ(planned->status, 200) << planned->body;
  const std::string key = json::parse(planned->body)["key"];
  const std::string small =
      "/v1/plans/" + key + "/cam.csv?master_period=360&master_start=30&master_end=210";
  auto gauge = [&](const std::string& series) {
    const auto metrics = client.Get("/metrics");
    return metrics ? test::metric(metrics->body, series) : -1.0;
  };
  auto wait_for_gauge = [&](const std::string& series, double value) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (gauge(series) != value && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return gauge(series);
  };
  auto concurrently = [&](int n) {
    std::vector<std::future<httplib::Result>> replies;
    for (int i = 0; i < n; ++i) {
      replies.push_back(std::async(std::launch::async, [&] { return server.client().Get(small); }));
    }
    return replies;
  };
  EXPECT_EQ(gauge("slosh_cam_export_budget_bytes"), 1048576.0);
  {
    // A client asks for a 200 000-row ST table (about 40 MB, more than the whole budget, which it
    // takes alone) and does not read it.
    test::Raw holder(server.port());
    ASSERT_TRUE(holder.connected());
    ASSERT_TRUE(holder.send("GET /v1/plans/" + key +
                            "/cam.st?master_period=360&master_start=30&master_end=210&"
                            "master_step=0.001800027001 HTTP/1.1\r\nHost: x\r\n\r\n"));
    ASSERT_EQ(wait_for_gauge("slosh_cam_export_bytes", 1048576.0), 1048576.0);
    auto replies = concurrently(8);
    for (auto& reply : replies) {
      const httplib::Result res = reply.get();
      ASSERT_TRUE(res);
      EXPECT_EQ(res->status, 503);
      EXPECT_EQ(res->get_header_value("Retry-After"), "1");
      EXPECT_EQ(json::parse(res->body),
                json::parse(R"({"error": {"code": "overloaded", "field": null, "message":
                  "the cam exports in flight hold 1048576 of the 1048576 bytes allowed (cam_export_bytes); this table needs up to 67068: retry later"}})"));
    }
    EXPECT_EQ(gauge("slosh_cam_export_refusals_total"), 8.0);
    const auto health = client.Get("/healthz");  // the rest of the service answers at once
    ASSERT_TRUE(health);
    EXPECT_EQ(health->status, 200);
  }  // the holder hangs up: the server's write fails and the reservation is released
  ASSERT_EQ(wait_for_gauge("slosh_cam_export_bytes", 0.0), 0.0);
  // Eight small tables fit together (8 x 67068 bytes of 1 MiB).
  const auto expected = client.Get(small);
  ASSERT_TRUE(expected);
  ASSERT_EQ(expected->status, 200);
  auto replies = concurrently(8);
  for (auto& reply : replies) {
    const httplib::Result res = reply.get();
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200) << res->body.substr(0, 300);
    EXPECT_EQ(res->body, expected->body);
  }
  EXPECT_EQ(wait_for_gauge("slosh_cam_export_bytes", 0.0), 0.0);
  EXPECT_EQ(gauge("slosh_cam_export_refusals_total"), 8.0);
}

TEST(CamRoutesOpenApi, BothRoutesArePublishedWithTheirParameters) {
  const json doc = api::openapi_document("1.2.3");
  const json& paths = doc.at("paths");
  const std::vector<std::string> common{
      "key",        "period_ms",   "master_period",   "master_start",
      "master_end", "master_step", "allow_infeasible"};
  for (const char* path : {"/v1/plans/{key}/cam.csv", "/v1/plans/{key}/cam.st"}) {
    SCOPED_TRACE(path);
    ASSERT_TRUE(paths.contains(path));
    const json& op = paths[path].at("get");
    std::vector<std::string> names;
    for (const json& p : op.at("parameters")) {
      names.push_back(p.at("name"));
      EXPECT_EQ(p.at("in"), p.at("name") == "key" ? "path" : "query");
    }
    std::vector<std::string> expected = common;
    if (std::string(path).ends_with(".st")) expected.push_back("st_name");
    EXPECT_EQ(names, expected);
    for (const char* status : {"200", "404", "422", "500", "503"}) {
      EXPECT_TRUE(op.at("responses").contains(status)) << status;
    }
    const std::string type = std::string(path).ends_with(".st") ? "text/plain" : "text/csv";
    EXPECT_TRUE(op["responses"]["200"]["content"].contains(type));
  }
  EXPECT_EQ(paths["/v1/plans/{key}/cam.st"]["get"]["operationId"], "getCamTableSt");
  EXPECT_EQ(paths["/v1/plans/{key}/cam.csv"]["get"]["operationId"], "getCamTable");
}

}  // namespace test_cam_export
}  // namespace slosh
