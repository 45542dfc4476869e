#pragma once
// Arrays of the studio's replies in binary: IEEE single precision, little-endian whatever the
// machine, base64 (RFC 4648, with padding) so that they travel inside a JSON line. 5.3 characters
// a number instead of the ~10 of a float printed in decimal, and no decimal formatting and
// parsing at either end (the page reads them into a Float32Array).
#include <optional>
#include <string>
#include <vector>

namespace tailor::studio {

std::string encode_float32_base64(const std::vector<float>& values);

// The values back; nullopt when `text` is not base64 of a whole number of floats.
std::optional<std::vector<float>> decode_float32_base64(const std::string& text);

}  // namespace tailor::studio
