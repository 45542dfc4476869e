#pragma once
// The one error type of every scene kind's parser and builder.
#include <stdexcept>

namespace tailor {

// Any problem with a scene: the message names the scene file and the JSON key path,
// e.g. "beam.json: materials[1].poisson_ratio: expected a number in (-1, 0.5), got 0.5".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tailor
