#pragma once
// What the service adds to the answers cpp-httplib shapes itself: the message of a status the
// library answers before any handler runs, and the close of a connection whose request body is
// left unread.

#include <httplib.h>

#include <string>
#include <string_view>

namespace slosh::service {

/// The message of a status the HTTP library answers itself (a request line that is not HTTP, one
/// over 8192 bytes, a bad Range; "HTTP <status>" for another).
[[nodiscard]] std::string framework_message(int status);

/// Asks the client to close the connection after this answer, whose request body is left unread
/// (it would be read as the next request): "Connection: close", set once (the library adds its
/// own when the request asked for "Connection: close").
void close_after_answer(const httplib::Request& req, httplib::Response& res);

/// Why the request head `head` (request line, header lines, CRLF each) is framed ambiguously, ""
/// when it is not: the whole message of its 400 (a Content-Length that is not a length names
/// `max_body_bytes`, as a body's refusal does). The library reads some heads one way where a proxy
/// could read them another (and the bytes after them as a request of their own), so each is
/// refused: a header line without ':', with white space in its field name or folded onto the
/// previous one (RFC 9112 5.1, 5.2); a Content-Length given twice or not a number; a
/// Transfer-Encoding other than chunked, given twice or beside a Content-Length (RFC
/// 9112 6.1, 6.3).
[[nodiscard]] std::string framing_error(std::string_view head, std::size_t max_body_bytes);

/// Whether `req` asks to close the connection: a `close` token in any Connection header, in any
/// case (the library reads only a whole value "close").
[[nodiscard]] bool asks_to_close(const httplib::Request& req);

/// Whether a framework answer of `status` leaves the connection's next bytes unknown: a request
/// line or headers the library could not read (400, 501 for an unknown method), a body it did not
/// read (413) or a request cut short (408, 414). The connection ends after it.
[[nodiscard]] bool ends_connection(int status);

/// Whether `req` comes with a body the library does not read: it reads one for POST, PUT, PATCH
/// and DELETE only. The bytes of such a body would be parsed as the next request.
[[nodiscard]] bool has_unread_body(const httplib::Request& req);

}  // namespace slosh::service
