#pragma once
// `slosh batch --server URL` of a two-recipe table (t.csv) into o.jsonl, run as a child process
// in a scratch folder: the fault and stop tests of the batch CLI drive it against a scripted or
// real service, then read its exit code, its stderr and the table it wrote.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "support/process.hpp"

namespace slosh::test {

struct BatchServerRun {
  TempDir dir;
  std::unique_ptr<Child> child;
  /// Starts the run; `flags` go after the command's own (e.g. {"--retries", "5"}).
  explicit BatchServerRun(const std::string& server, const std::vector<std::string>& flags = {}) {
    write_file(dir / "t.csv",
               "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
               "a,48.5,82,water,800,1.5,notch\n"
               "b,48.5,82,water,800,1.6,notch\n");
    write_file(dir / "stdin", "");
    std::vector<std::string> args{"batch",
                                  "--in",
                                  (dir / "t.csv").string(),
                                  "--out",
                                  (dir / "o.jsonl").string(),
                                  "--server",
                                  server,
                                  "--progress",
                                  "never"};
    args.insert(args.end(), flags.begin(), flags.end());
    child = std::make_unique<Child>(spawn(args, dir / "stdin", dir / "stdout", dir / "stderr"));
  }
  [[nodiscard]] std::string err() const { return read_file(dir / "stderr"); }
  /// The line that names the partial output file as empty (nothing was written before the stop).
  [[nodiscard]] std::string empty_partial_line() const {
    return "slosh batch: the rows written so far are in " + (dir / "o.jsonl.partial").string() +
           " (none: it is empty)\n";
  }
};

}  // namespace slosh::test
