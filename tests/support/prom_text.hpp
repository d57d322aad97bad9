#pragma once
// A small strict parser of the Prometheus text exposition format (0.0.4) for the metrics tests:
// every sample belongs to a family declared by "# HELP" and "# TYPE" lines before it, names and
// labels are well formed, no series repeats, and a histogram's buckets are cumulative
// (non-decreasing in le), end with le="+Inf" equal to its _count, and come with a _sum.

#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace slosh::test {

struct PromSample {
  std::string name;                           ///< the sample's metric name (with _bucket etc.)
  std::map<std::string, std::string> labels;  ///< label name -> unescaped value
  double value{};
};

struct PromText {
  std::map<std::string, std::string> types;  ///< family -> counter, gauge, histogram, ...
  std::vector<PromSample> samples;
  /// The value of the sample `name` with exactly `labels`; NAN when absent.
  [[nodiscard]] double value(const std::string& name,
                             const std::map<std::string, std::string>& labels = {}) const {
    for (const PromSample& s : samples) {
      if (s.name == name && s.labels == labels) return s.value;
    }
    return NAN;
  }
};

namespace prom_detail {

inline bool name_char(char c, bool first) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':' ||
         (!first && c >= '0' && c <= '9');
}

inline std::string read_name(const std::string& line, std::size_t& i) {
  const std::size_t start = i;
  while (i < line.size() && name_char(line[i], i == start)) ++i;
  if (i == start) throw std::runtime_error("expected a name at column " + std::to_string(i));
  return line.substr(start, i - start);
}

inline double parse_value(const std::string& text) {
  if (text == "+Inf") return INFINITY;
  if (text == "-Inf") return -INFINITY;
  if (text == "NaN") return NAN;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw std::runtime_error("not a number: '" + text + "'");
  return v;
}

inline std::map<std::string, std::string> read_labels(const std::string& line, std::size_t& i) {
  std::map<std::string, std::string> labels;
  if (i >= line.size() || line[i] != '{') return labels;
  ++i;
  while (i < line.size() && line[i] != '}') {
    const std::string key = read_name(line, i);
    if (line.substr(i, 2) != "=\"") throw std::runtime_error("expected =\" after " + key);
    i += 2;
    std::string value;
    while (i < line.size() && line[i] != '"') {
      if (line[i] == '\\') {
        ++i;
        if (i >= line.size()) break;
        value += line[i] == 'n' ? '\n' : line[i];
        if (line[i] != 'n' && line[i] != '\\' && line[i] != '"') {
          throw std::runtime_error("bad escape in label " + key);
        }
      } else {
        value += line[i];
      }
      ++i;
    }
    if (i >= line.size()) throw std::runtime_error("unterminated label value");
    ++i;
    if (!labels.emplace(key, value).second) throw std::runtime_error("repeated label " + key);
    if (i < line.size() && line[i] == ',') ++i;
  }
  if (i >= line.size()) throw std::runtime_error("unterminated labels");
  ++i;
  return labels;
}

// The family a sample name belongs to (a histogram's _bucket, _sum, _count).
inline std::string family_of(const std::string& name,
                             const std::map<std::string, std::string>& types) {
  for (const char* suffix : {"_bucket", "_sum", "_count"}) {
    const std::string s(suffix);
    if (name.size() > s.size() && name.ends_with(s)) {
      const std::string base = name.substr(0, name.size() - s.size());
      if (auto it = types.find(base); it != types.end() && it->second == "histogram") return base;
    }
  }
  return name;
}

inline void check_histograms(const PromText& text) {
  // series (family + labels without le) -> (le, count) in order of appearance
  std::map<std::string, std::vector<std::pair<double, double>>> buckets;
  std::map<std::string, double> counts;
  std::set<std::string> sums;
  for (const PromSample& s : text.samples) {
    const std::string family = family_of(s.name, text.types);
    if (family == s.name) continue;
    auto labels = s.labels;
    std::string le;
    if (s.name.ends_with("_bucket")) {
      if (!labels.count("le")) throw std::runtime_error(s.name + " without le");
      le = labels["le"];
      labels.erase("le");
    }
    std::ostringstream key;
    key << family;
    for (const auto& [k, v] : labels) key << ',' << k << '=' << v;
    if (s.name.ends_with("_bucket")) buckets[key.str()].push_back({parse_value(le), s.value});
    if (s.name.ends_with("_count")) counts[key.str()] = s.value;
    if (s.name.ends_with("_sum")) sums.insert(key.str());
  }
  for (const auto& [series, list] : buckets) {
    for (std::size_t i = 1; i < list.size(); ++i) {
      if (!(list[i].first > list[i - 1].first) || list[i].second < list[i - 1].second) {
        throw std::runtime_error(series + ": buckets not increasing in le or not cumulative");
      }
    }
    if (list.empty() || !std::isinf(list.back().first)) {
      throw std::runtime_error(series + ": no le=\"+Inf\" bucket");
    }
    if (!counts.count(series) || counts[series] != list.back().second) {
      throw std::runtime_error(series + ": +Inf bucket differs from _count");
    }
    if (!sums.count(series)) throw std::runtime_error(series + ": no _sum");
  }
  if (counts.size() != buckets.size()) throw std::runtime_error("a _count without buckets");
}

}  // namespace prom_detail

/// Parses `body` strictly; throws std::runtime_error naming the line on any violation.
inline PromText parse_prom_text(const std::string& body) {
  using namespace prom_detail;
  PromText out;
  std::set<std::string> helped;
  std::set<std::string> series;
  std::istringstream in(body);
  std::size_t number = 0;
  if (!body.empty() && body.back() != '\n') throw std::runtime_error("no final newline");
  for (std::string line; std::getline(in, line);) {
    ++number;
    const std::string where = "line " + std::to_string(number) + " '" + line + "': ";
    try {
      if (line.empty()) throw std::runtime_error("empty line");
      if (line.starts_with("# HELP ") || line.starts_with("# TYPE ")) {
        std::size_t i = 7;
        const std::string name = read_name(line, i);
        if (i >= line.size() || line[i] != ' ') throw std::runtime_error("no text after the name");
        const std::string rest = line.substr(i + 1);
        if (line[2] == 'H') {
          if (!helped.insert(name).second) throw std::runtime_error("second HELP");
        } else {
          static const std::set<std::string> kinds{"counter", "gauge", "histogram", "summary",
                                                   "untyped"};
          if (!kinds.count(rest)) throw std::runtime_error("unknown type " + rest);
          if (!helped.count(name)) throw std::runtime_error("TYPE before HELP");
          if (!out.types.emplace(name, rest).second) throw std::runtime_error("second TYPE");
        }
        continue;
      }
      if (line[0] == '#') throw std::runtime_error("a comment that is neither HELP nor TYPE");
      std::size_t i = 0;
      PromSample s;
      s.name = read_name(line, i);
      s.labels = read_labels(line, i);
      if (i >= line.size() || line[i] != ' ') throw std::runtime_error("no value");
      s.value = parse_value(line.substr(i + 1));
      const std::string family = family_of(s.name, out.types);
      if (!out.types.count(family)) throw std::runtime_error("sample before its TYPE");
      if (out.types[family] == "counter" && !(s.value >= 0)) {
        throw std::runtime_error("negative counter");
      }
      if (!series.insert(line.substr(0, i)).second) throw std::runtime_error("repeated series");
      out.samples.push_back(std::move(s));
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(where + e.what());
    }
  }
  check_histograms(out);
  return out;
}

}  // namespace slosh::test
