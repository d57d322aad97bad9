#pragma once
// What the batch-job tests (one replica, shared jobs, the cluster) read in a job's answers: the
// cells of a plan table's CSV line, the table without the cells that depend on the run (cached,
// solve_ms), so two runs of one table compare equal, and whether a job record is final.

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace slosh::test {

/// A quote-aware split of one CSV line into its cells (cells keep their quotes).
inline std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') quoted = !quoted;
    if (ch == ',' && !quoted) {
      cells.emplace_back();
    } else {
      cells.back() += ch;
    }
  }
  return cells;
}

/// The lines of a CSV plan table without the cached and solve_ms cells.
inline std::vector<std::string> csv_without_timing(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  std::vector<std::size_t> skip;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = csv_cells(line);
    if (skip.empty()) {
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (cells[i] == "cached" || cells[i] == "solve_ms") skip.push_back(i);
      }
    }
    std::string kept;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (std::find(skip.begin(), skip.end(), i) == skip.end()) kept += cells[i] + ",";
    }
    lines.push_back(kept);
  }
  return lines;
}

/// Whether a job record (null while its replica answers anything but 200) is done, cancelled or
/// failed.
inline bool is_final_record(const nlohmann::json& record) {
  const std::string state = record.is_object() ? record.value("state", "") : "";
  return state == "done" || state == "cancelled" || state == "failed";
}

}  // namespace slosh::test
