#pragma once
// CLI11 checks of flag values for `tailor` and the programs in bench/, with messages that say
// what was expected and what was given: "--count: expected an integer from 1 to 100000, got
// '0'". A value must be the whole argument ("12x" and "1.5" are not integers) and finite. The
// checks add nothing to the flag's type name in the help text (the help says the range).
#include <CLI/CLI.hpp>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "forward/core/format_number.hpp"

namespace tailor::cli {

// An integer in [min, max] (max defaults to "no upper bound" for an int).
inline CLI::Validator integer_in(long long min, long long max = std::numeric_limits<int>::max()) {
  const std::string expected = max == std::numeric_limits<int>::max()
                                   ? "an integer >= " + std::to_string(min)
                                   : "an integer from " + std::to_string(min) + " to " + std::to_string(max);
  return CLI::Validator(
      [min, max, expected](std::string& text) -> std::string {
        long long value = 0;
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (text.empty() || error != std::errc() || stop != end || value < min || value > max)
          return "expected " + expected + ", got '" + text + "'";
        return {};
      },
      /*validator_desc=*/"");
}

// A finite number > min (strictly) or >= min.
inline CLI::Validator number_above(double min, bool inclusive = false) {
  const std::string expected = std::string("a number ") + (inclusive ? ">= " : "> ") + format_number(min);
  return CLI::Validator(
      [min, inclusive, expected](std::string& text) -> std::string {
        char* stop = nullptr;
        errno = 0;
        const double value = std::strtod(text.c_str(), &stop);
        const bool whole = !text.empty() && stop == text.c_str() + text.size() && errno == 0;
        if (!whole || !std::isfinite(value) || (inclusive ? value < min : value <= min))
          return "expected " + expected + ", got '" + text + "'";
        return {};
      },
      /*validator_desc=*/"");
}

inline CLI::Validator number_at_least(double min) { return number_above(min, /*inclusive=*/true); }

// One of the given words.
inline CLI::Validator one_of(const std::vector<std::string>& words) {
  std::string expected;
  for (const std::string& w : words) expected += (expected.empty() ? "" : ", ") + w;
  return CLI::Validator(
      [words, expected](std::string& text) -> std::string {
        for (const std::string& w : words)
          if (text == w) return {};
        return "expected one of " + expected + ", got '" + text + "'";
      },
      /*validator_desc=*/"");
}

}  // namespace tailor::cli
