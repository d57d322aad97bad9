#include "http/library_replies.hpp"

#include <algorithm>
#include <array>
#include <cctype>
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
  if (req.get_header_value("Connection") != "close" &&
      res.get_header_value("Connection") != "close") {
    res.set_header("Connection", "close");
  }
}

namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string_view trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

}  // namespace

std::string framing_error(std::string_view head, std::size_t max_body_bytes) {
  std::size_t at = head.find("\r\n");
  if (at == std::string_view::npos) return {};
  int content_lengths = 0;
  bool transfer_encoding = false;
  for (int line_number = 2;; ++line_number) {
    const std::size_t from = at + 2;
    at = head.find("\r\n", from);
    if (at == std::string_view::npos || at == from) break;  // the head's end
    const std::string_view line = head.substr(from, at - from);
    const std::string where =
        "the request is framed ambiguously: header line " + std::to_string(line_number);
    if (line.front() == ' ' || line.front() == '\t') {
      return where + " continues the previous one (obsolete line folding)";
    }
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) return where + " has no ':'";
    const std::string_view name = line.substr(0, colon);
    if (name.find_first_of(" \t") != std::string_view::npos) {
      return where + " has white space in its field name";
    }
    const std::string key = lower(name);
    const std::string_view value = trimmed(line.substr(colon + 1));
    if (key == "content-length") {
      if (++content_lengths > 1) {
        return "the request is framed ambiguously: Content-Length is given more than once";
      }
      if (value.empty() || value.size() > 18 ||
          value.find_first_not_of("0123456789") != std::string_view::npos) {
        return "Content-Length = \"" + std::string(value.substr(0, 32)) +
               "\" is not a length: a whole number of bytes, at most " +
               std::to_string(max_body_bytes);
      }
    } else if (key == "transfer-encoding") {
      if (transfer_encoding) {
        return "the request is framed ambiguously: Transfer-Encoding is given more than once";
      }
      transfer_encoding = true;
      if (lower(value) != "chunked") {
        return "the request is framed ambiguously: Transfer-Encoding \"" +
               std::string(value.substr(0, 40)) + "\" is not supported (only chunked)";
      }
    }
  }
  if (transfer_encoding && content_lengths > 0) {
    return "the request declares both Content-Length and Transfer-Encoding: send one of them "
           "(RFC 9112 6.3)";
  }
  return {};
}

bool asks_to_close(const httplib::Request& req) {
  for (const auto& [name, value] : req.headers) {
    if (lower(name) != "connection") continue;
    std::string_view rest = value;
    while (!rest.empty()) {
      const std::size_t comma = rest.find(',');
      if (lower(trimmed(rest.substr(0, comma))) == "close") return true;
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    }
  }
  return false;
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
