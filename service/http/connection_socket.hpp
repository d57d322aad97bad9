#pragma once
// The socket of the connection a request came on: the HTTP library does not expose it, and the
// service needs it to tell whether the client closed its side before the reply was written.

#include <string>

#include "http/connection_reaper.hpp"

namespace slosh::service {

/// The socket of the connection from `peer` ("address:port") that the calling thread answers; -1
/// when there is none. Found once per connection by the reaper's listing of the descriptors and
/// kept per thread (a connection is answered by one thread), one getpeername confirming it is
/// still that connection at the next request.
[[nodiscard]] int connection_socket(const ConnectionReaper& reaper, const std::string& peer);

}  // namespace slosh::service
