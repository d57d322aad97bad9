#include "cli_commands.hpp"

#include <exception>
#include <iostream>

#include "io.hpp"
#include "slosh/api/error.hpp"
#include "slosh/api/simulate.hpp"

namespace slosh::service {

namespace {

template <typename Body>
int print_json_or_error(Body&& body) {
  try {
    std::cout << api::dump_json(body(), 2) << '\n';
    return kExitOk;
  } catch (const api::ApiError& e) {
    std::cerr << api::dump_json(api::error_envelope(e), 2) << '\n';
    return e.status() < 500 ? kExitInvalidInput : kExitFailure;
  } catch (const std::exception& e) {
    const api::ApiError wrapped(api::ErrorCode::kInternal, "", e.what());
    std::cerr << api::dump_json(api::error_envelope(wrapped), 2) << '\n';
    return kExitFailure;
  }
}

}  // namespace

int run_simulate_command(const std::string& request_path) {
  return print_json_or_error([&] {
    std::string text;
    try {
      text = read_request_text(request_path);
    } catch (const std::exception& e) {
      throw api::ApiError(api::ErrorCode::kInvalidValue, "--request", e.what());
    }
    return api::run_simulate(api::parse_simulate_request(api::parse_json_body(text)));
  });
}

}  // namespace slosh::service
