#pragma once
// The median, for every place that summarizes repeated measurements or rates (the Taylor test,
// the derivative checks, the benches): one definition for the whole tree.
#include <algorithm>
#include <limits>
#include <vector>

namespace tailor {

// The middle value (the mean of the two middle values for an even count); NaN when empty.
inline double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  const double upper = values[middle];
  if (values.size() % 2) return upper;
  return 0.5 * (*std::max_element(values.begin(), values.begin() + middle) + upper);
}

}  // namespace tailor
