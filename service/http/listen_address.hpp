#pragma once
// Why the service could not listen on --host:--port, in words an operator can act on.

#include <string>

namespace slosh::service {

/// The message of a failed bind of `host`:`port`: "<host> is not an address ..." when `host` is
/// neither an IPv4 or IPv6 address nor a name that resolves (e.g. 999.1.1.1), else the port
/// conflict ("is another slosh or another service using the port?").
[[nodiscard]] std::string bind_failure_message(const std::string& host, int port);

}  // namespace slosh::service
