#include "io.hpp"

#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace slosh::service {

std::string read_request_text(const std::string& path) {
  std::ostringstream buffer;
  if (path == "-") {
    buffer << std::cin.rdbuf();
    return buffer.str();
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read request file '" + path + "'");
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace slosh::service
