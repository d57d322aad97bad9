#include "storage/redis_url.hpp"

#include <algorithm>
#include <stdexcept>
#include <string_view>

namespace slosh::service {
namespace {

constexpr std::string_view kScheme = "redis://";
constexpr int kMaxDb = 15;  // Redis' default number of databases is 16

bool all_digits(std::string_view text) {
  return !text.empty() && text.size() <= 9 &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// `text` with the password of its user part replaced by "***" (for messages and logs).
std::string masked(const std::string& text) {
  if (!text.starts_with(kScheme)) return text;
  const std::size_t at = text.rfind('@');
  if (at == std::string::npos) return text;
  const std::string user = text.substr(kScheme.size(), at - kScheme.size());
  const std::size_t colon = user.find(':');
  return std::string(kScheme) +
         (colon == std::string::npos ? "***" : user.substr(0, colon) + ":***") + text.substr(at);
}

[[noreturn]] void refuse(const std::string& text, const std::string& reason) {
  throw std::invalid_argument(masked(text) + " is not a Redis URL: " + reason +
                              " (expected redis://host:port/db or "
                              "redis://:password@host:port/db)");
}

/// Splits "host[:port]" or "[v6]:port" into `url`.
void parse_host_port(const std::string& text, std::string_view hostport, RedisUrl& url) {
  std::string_view port_text;
  if (hostport.starts_with('[')) {
    const std::size_t close = hostport.find(']');
    if (close == std::string_view::npos) refuse(text, "the IPv6 address lacks its ']'");
    url.host = std::string(hostport.substr(1, close - 1));
    const std::string_view rest = hostport.substr(close + 1);
    if (!rest.empty() && !rest.starts_with(':')) refuse(text, "':port' must follow ']'");
    if (!rest.empty()) port_text = rest.substr(1);
    if (rest == ":") port_text = ":";  // an empty port is an error below
  } else {
    const std::size_t colon = hostport.find(':');
    url.host = std::string(hostport.substr(0, colon));
    if (colon != std::string_view::npos) {
      port_text = hostport.substr(colon + 1);
      if (port_text.empty()) port_text = ":";
    }
  }
  if (url.host.empty()) refuse(text, "the host is empty");
  if (port_text.empty()) return;
  const bool number = all_digits(port_text);
  const long port = number ? std::stol(std::string(port_text)) : 0;
  if (!number || port < 1 || port > 65535) {
    refuse(text, "the port '" + std::string(port_text == ":" ? "" : port_text) +
                     "' is not a number from 1 to 65535");
  }
  url.port = static_cast<int>(port);
}

}  // namespace

std::string RedisUrl::display() const {
  const bool v6 = host.find(':') != std::string::npos;
  return std::string(kScheme) + (password.empty() ? "" : ":***@") + (v6 ? "[" + host + "]" : host) +
         ":" + std::to_string(port) + "/" + std::to_string(db);
}

bool is_redis_url(const std::string& text) {
  return text.starts_with(kScheme);
}

RedisUrl parse_redis_url(const std::string& text) {
  if (!is_redis_url(text)) refuse(text, "it does not start with redis://");
  RedisUrl url;
  std::string_view rest = std::string_view(text).substr(kScheme.size());
  if (rest.find_first_of("?#") != std::string_view::npos) {
    refuse(text, "query parameters and fragments are not supported");
  }
  if (const std::size_t at = rest.rfind('@'); at != std::string_view::npos) {
    const std::string_view user = rest.substr(0, at);
    if (!user.starts_with(':')) {
      refuse(text, "a user name is not supported (write the password as ':password@')");
    }
    url.password = std::string(user.substr(1));
    if (url.password.empty()) refuse(text, "the password after ':' is empty");
    rest = rest.substr(at + 1);
  }
  const std::size_t slash = rest.find('/');
  parse_host_port(text, rest.substr(0, slash), url);
  if (slash != std::string_view::npos && slash + 1 < rest.size()) {
    const std::string_view db = rest.substr(slash + 1);
    const bool number = all_digits(db);
    const long value = number ? std::stol(std::string(db)) : -1;
    if (!number || value > kMaxDb) {
      refuse(text, "the database '" + std::string(db) + "' is not a number from 0 to " +
                       std::to_string(kMaxDb));
    }
    url.db = static_cast<int>(value);
  }
  return url;
}

}  // namespace slosh::service
