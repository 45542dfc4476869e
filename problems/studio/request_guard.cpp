#include "problems/studio/request_guard.hpp"

#include <charconv>
#include <random>

namespace tailor::studio {

std::string random_token(int bytes) {
  std::random_device device;  // the system's entropy source (/dev/urandom on Linux)
  static constexpr char hex[] = "0123456789abcdef";
  std::string token;
  for (int i = 0; i < bytes; ++i) {
    const unsigned byte = device() & 0xffu;
    token += hex[byte >> 4];
    token += hex[byte & 0xfu];
  }
  return token;
}

bool constant_time_equal(std::string_view a, std::string_view b) {
  unsigned char difference = a.size() == b.size() ? 0 : 1;
  const std::size_t n = a.size() < b.size() ? a.size() : b.size();
  for (std::size_t i = 0; i < n; ++i)
    difference |= static_cast<unsigned char>(static_cast<unsigned char>(a[i]) ^ static_cast<unsigned char>(b[i]));
  return difference == 0;
}

bool is_loopback_host(std::string_view host, int port) {
  const std::size_t colon = host.rfind(':');
  if (colon == std::string_view::npos) return false;  // a browser always names the port here
  const std::string_view name = host.substr(0, colon), digits = host.substr(colon + 1);
  int value = -1;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error != std::errc() || end != digits.data() + digits.size() || value != port) return false;
  return name == "127.0.0.1" || name == "localhost" || name == "[::1]";
}

std::string refuse_headers(const RequestHeaders& headers, int port) {
  if (!is_loopback_host(headers.host, port))
    return "the Host header '" + headers.host + "' is not this server's loopback address";
  if (!headers.origin.empty()) {
    const std::string_view origin = headers.origin;
    constexpr std::string_view scheme = "http://";
    if (origin.substr(0, scheme.size()) != scheme || !is_loopback_host(origin.substr(scheme.size()), port))
      return "cross-origin request from '" + headers.origin + "'";
  }
  if (headers.fetch_site == "cross-site") return "cross-site request";
  return "";
}

bool strip_token(std::string_view path, std::string_view token, std::string& rest) {
  rest.clear();
  if (path.empty() || path[0] != '/') return false;
  path.remove_prefix(1);
  const std::size_t slash = path.find('/');
  const std::string_view given = path.substr(0, slash);
  if (token.empty() || !constant_time_equal(given, token)) return false;
  if (slash != std::string_view::npos) rest = std::string(path.substr(slash + 1));
  return true;
}

}  // namespace tailor::studio
