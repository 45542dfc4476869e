#pragma once
// Who may talk to the studio's server (problems/studio/http_server.hpp). The server listens on a
// loopback address only, and a request is served only when all of these hold:
//  - its path starts with the per-run token ("/<token>/..."), compared in constant time, so that
//    another local user or a web page that guesses the port cannot read or change anything;
//  - its Host header names a loopback address with the server's own port (a DNS-rebinding page
//    would send its own host name);
//  - its Origin header, when present, is that same loopback origin, and Sec-Fetch-Site, when
//    present, is not "cross-site" (a page from elsewhere cannot post messages).
// These are pure functions of the request's strings, so they are tested without a socket.
#include <string>
#include <string_view>

namespace tailor::studio {

// A random token of `bytes` bytes as lowercase hex, from std::random_device.
std::string random_token(int bytes = 16);

// Equality that takes the same time wherever the first difference is (for the token).
bool constant_time_equal(std::string_view a, std::string_view b);

// Whether `host` (a Host header: "127.0.0.1:8123", "localhost:8123", "[::1]:8123") names a
// loopback address with port `port`.
bool is_loopback_host(std::string_view host, int port);

struct RequestHeaders {
  std::string host, origin, fetch_site;  // Host, Origin, Sec-Fetch-Site ("" when absent)
};

// "" when the headers may be served by the server on `port`, else why not.
std::string refuse_headers(const RequestHeaders& headers, int port);

// Splits "/<token>/rest" into the token check and the rest ("" for "/<token>/"). Returns false
// (and leaves `rest` empty) when the path does not start with the token.
bool strip_token(std::string_view path, std::string_view token, std::string& rest);

}  // namespace tailor::studio
