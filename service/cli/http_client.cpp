#include "cli/http_client.hpp"

#include <httplib.h>

#include <regex>

namespace slosh::service {

struct HttpClient::Impl {
  explicit Impl(const std::string& scheme_host_port) : client(scheme_host_port) {}
  httplib::Client client;
};

HttpClient::HttpClient(const std::string& base_url, std::chrono::seconds timeout)
    : base_url_(base_url) {
  static const std::regex url(
      R"(^http://([A-Za-z0-9.\-]+|\[[0-9A-Fa-f:.]+\])(:[0-9]{1,5})?(/.*)?$)");
  std::smatch m;
  if (!std::regex_match(base_url, m, url)) {
    throw std::invalid_argument("--server " + base_url +
                                " is not a URL of the form http://host[:port][/prefix]");
  }
  prefix_ = m[3].str();
  while (!prefix_.empty() && prefix_.back() == '/') prefix_.pop_back();
  impl_ = std::make_unique<Impl>("http://" + m[1].str() + m[2].str());
  set_timeout(timeout);
  impl_->client.set_keep_alive(true);
}

void HttpClient::set_timeout(std::chrono::milliseconds timeout) {
  impl_->client.set_connection_timeout(timeout);
  impl_->client.set_read_timeout(timeout);
  impl_->client.set_write_timeout(timeout);
}

HttpClient::~HttpClient() = default;

namespace {

HttpReply reply_of(const httplib::Result& result, const std::string& base_url) {
  if (!result) {
    throw HttpError("cannot reach " + base_url + " (" + httplib::to_string(result.error()) +
                    " error): is `slosh serve` running there?");
  }
  HttpReply reply;
  reply.status = result->status;
  reply.body = result->body;
  reply.retry_after = result->get_header_value("Retry-After");
  reply.location = result->get_header_value("Location");
  return reply;
}

}  // namespace

HttpReply HttpClient::post_json(const std::string& path, const std::string& body) {
  return reply_of(impl_->client.Post(prefix_ + path, body, "application/json"), base_url_);
}

HttpReply HttpClient::get(const std::string& path) {
  return reply_of(impl_->client.Get(prefix_ + path), base_url_);
}

HttpReply HttpClient::del(const std::string& path) {
  return reply_of(impl_->client.Delete(prefix_ + path), base_url_);
}

}  // namespace slosh::service
