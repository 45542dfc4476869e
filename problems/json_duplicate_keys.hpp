#pragma once
// Duplicate object keys in a JSON text. The JSON library keeps the last value of a repeated key
// and drops the other without a word, so a scene that says "youngs_modulus" twice would run with
// one of the two values silently. parse_scene_document refuses such a text with both positions.
#include <optional>
#include <string>

namespace tailor {

struct DuplicateKey {
  std::string path;               // the repeated member's key path, as SceneNode writes it
  int first_line = 0, first_column = 0;  // 1-based, of the first occurrence's opening quote
  int line = 0, column = 0;              // of the second
};

// The first repeated key of an object in `json_text`, which must be valid JSON (call after a
// successful parse); nullopt when every object's keys are distinct. Columns count bytes.
std::optional<DuplicateKey> find_duplicate_key(const std::string& json_text);

}  // namespace tailor
