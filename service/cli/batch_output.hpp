#pragma once
// The output table of `slosh batch`: written to "<out>.partial" and renamed into place only when
// complete, so that a stopped run never leaves a table that looks whole.

#include <fstream>
#include <iostream>
#include <ostream>
#include <string>

namespace slosh::service::batch_cli {

// The output table: written to <out>.partial and renamed when complete (stdout for "-").
class BatchOutput {
 public:
  /// Creates "<out>.partial" (nothing for "-", stdout).
  explicit BatchOutput(const std::string& out);
  [[nodiscard]] bool to_stdout() const { return out_ == "-"; }
  [[nodiscard]] bool opened() const { return to_stdout() || static_cast<bool>(file_); }
  /// Why the partial file could not be created (the OS's reason), when !opened().
  [[nodiscard]] const std::string& open_error() const { return open_error_; }
  [[nodiscard]] const std::string& out() const { return out_; }
  [[nodiscard]] const std::string& partial() const { return partial_; }
  std::ostream& stream() { return to_stdout() ? std::cout : file_; }
  /// Closes and renames the partial file; false (after a message) when it cannot.
  bool commit();

 private:
  std::string out_;
  std::string partial_;
  std::ofstream file_;
  std::string open_error_;
};

}  // namespace slosh::service::batch_cli
