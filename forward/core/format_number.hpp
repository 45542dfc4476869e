#pragma once
// A number as text for messages and tables: one function for the whole tree. The default "%g"
// is what `std::ostream << value` writes (six significant digits); pass a printf conversion
// for one double ("%.3e", "%.2f") for another form.
#include <cstdio>
#include <string>

namespace tailor {

inline std::string format_number(double value, const char* format = "%g") {
  const int length = std::snprintf(nullptr, 0, format, value);
  if (length < 0) return "?";
  std::string text(static_cast<std::size_t>(length), '\0');
  std::snprintf(text.data(), text.size() + 1, format, value);
  return text;
}

// Three significant decimals in exponent form ("1.234e-05"): residuals and norms in progress lines.
inline std::string format_scientific(double value) { return format_number(value, "%.3e"); }

}  // namespace tailor
