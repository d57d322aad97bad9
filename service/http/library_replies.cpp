#include "http/library_replies.hpp"

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

}  // namespace slosh::service
