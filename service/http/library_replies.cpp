#include "http/library_replies.hpp"

#include <algorithm>
#include <array>
#include <string_view>

namespace slosh::service {

std::string framework_message(int status) {
  switch (status) {
    case 400:
      return "the request is not valid HTTP (request line, method or headers)";
    case 414:
      return "the request line is longer than the limit of 8192 bytes";
    case 416:
      return "the Range header is not valid; this service answers whole bodies only";
    default:
      return "HTTP " + std::to_string(status);
  }
}

void close_after_answer(const httplib::Request& req, httplib::Response& res) {
  if (req.get_header_value("Connection") != "close") res.set_header("Connection", "close");
}

bool ends_connection(int status) {
  return status == 400 || status == 408 || status == 413 || status == 414 || status == 501;
}

bool has_unread_body(const httplib::Request& req) {
  static constexpr std::array<std::string_view, 4> kRead{"POST", "PUT", "PATCH", "DELETE"};
  if (std::find(kRead.begin(), kRead.end(), req.method) != kRead.end()) return false;
  const std::string length = req.get_header_value("Content-Length");
  return (!length.empty() && length != "0") || req.has_header("Transfer-Encoding");
}

}  // namespace slosh::service
