#pragma once
// DIR/checkpoint.json of `tailor run`: an OptimizerCheckpoint (optimizers/checkpoint.hpp) with
// what it belongs to, written atomically (a temporary file renamed over the old one, so that a
// run killed while writing leaves the previous checkpoint intact) and read back by
// `tailor run --resume DIR`. The layout is documented in docs/scenes.md ("Checkpoints").
#include <string>

#include "optimizers/checkpoint.hpp"

namespace tailor {

inline constexpr const char* kCheckpointFileName = "checkpoint.json";
// Version of the checkpoint layout; a checkpoint of another version is refused.
inline constexpr int kCheckpointFormatVersion = 1;

// What a checkpoint belongs to; a resume checks that the scene it continues is the same.
struct CheckpointOwner {
  std::string kind;  // "inverse"
  std::string scene_name;
  std::string scene_source;  // for messages only: a scene may be moved between runs
  int design_size = 0;
  // A description of the problem that has to match as well (mesh size, design granularity).
  std::string problem;
};

struct CheckpointFile {
  std::string path;
  CheckpointOwner owner;
  OptimizerCheckpoint checkpoint;
};

// Throws std::runtime_error when the file cannot be written.
void write_checkpoint_json(const std::string& path, const CheckpointOwner& owner,
                           const OptimizerCheckpoint& checkpoint);

// Reads `folder`/checkpoint.json (or `folder` itself when it is a file). Throws SceneError
// (bad input) when it is missing or not a checkpoint, naming the file and the key.
CheckpointFile read_checkpoint_json(const std::string& folder);

// Throws SceneError unless `file` belongs to `expected` and the back-end `backend`: same kind,
// scene name, design size, problem description and back-end (the message names each difference).
void check_checkpoint(const CheckpointFile& file, const CheckpointOwner& expected, OptimizerBackend backend);

}  // namespace tailor
