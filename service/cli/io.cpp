#include "cli/io.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace slosh::service {

std::string read_request_text(const std::string& path, const std::string& what) {
  std::ostringstream buffer;
  if (path == "-") {
    buffer << std::cin.rdbuf();
    return buffer.str();
  }
  // An ifstream opens a directory on Linux and reads nothing: say what is wrong instead of
  // letting the JSON parser report "unexpected end of input".
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw std::runtime_error("cannot read " + what + " file '" + path + "': it is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + what + " file '" + path + "'");
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace slosh::service
