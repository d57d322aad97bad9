#include "cli/batch_output.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

namespace slosh::service::batch_cli {

BatchOutput::BatchOutput(const std::string& out) : out_(out), partial_(out + ".partial") {
  if (to_stdout()) return;
  errno = 0;
  file_.open(partial_, std::ios::binary | std::ios::trunc);
  if (!file_) open_error_ = errno != 0 ? std::strerror(errno) : "it cannot be opened";
}

bool BatchOutput::commit() {
  if (to_stdout()) return true;
  file_.close();
  if (!file_ || std::rename(partial_.c_str(), out_.c_str()) != 0) {
    std::cerr << "slosh batch: cannot write '" << out_ << "' (the table is in " << partial_
              << ")\n";
    return false;
  }
  return true;
}

}  // namespace slosh::service::batch_cli
