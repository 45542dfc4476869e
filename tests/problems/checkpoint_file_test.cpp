// DIR/checkpoint.json (problems/optimizer_checkpoint.hpp): every number read back to the bit,
// written through a temporary file that does not stay behind, and clear errors (SceneError,
// exit 2 in the CLI) for a missing or damaged file and for a checkpoint of another run.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/optimizer_checkpoint.hpp"

namespace tailor::checkpoint_file_test {
namespace {

using tailor::testing::TempFolder;
using ::testing::HasSubstr;

CheckpointOwner owner() {
  return {"inverse", "bar", "scenes/bar.json", 3, "3D mesh, 45 vertices, 64 elements; design per_material"};
}

OptimizerCheckpoint checkpoint() {
  OptimizerCheckpoint c;
  c.backend = OptimizerBackend::gradient_descent;
  c.iteration = 2;
  c.z = Eigen::Vector3d(0.1, -1.0 / 3.0, 1e-300);
  c.objective = 2.0 / 7.0;
  c.best_z = c.z;
  c.best_objective = c.objective;
  c.best_violation = 0.0;
  for (int i = 0; i <= 2; ++i) {
    OptimizerIteration row;
    row.iteration = i;
    row.objective = 1.0 / (3.0 + i);
    row.gradient_norm = i == 1 ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(2.0) * i;
    row.step_norm = 0.1 * i;
    row.seconds = 0.01 * i;
    row.forward_solves = 3 * i;
    row.adjoint_solves = i;
    c.history.push_back(row);
  }
  c.evaluations = 7;
  c.failed_evaluations = 1;
  c.seconds = 0.123456789;
  c.counters = {7, 6, 2, 0.1, 0.05};
  c.backend_state["step"] = 1.0 / 3.0;
  return c;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no SceneError";
}

TEST(CheckpointFile, RoundTripsEveryNumberExactly) {
  TempFolder folder("checkpoint_roundtrip");
  const OptimizerCheckpoint c = checkpoint();
  write_checkpoint_json(folder / "checkpoint.json", owner(), c);
  EXPECT_FALSE(std::filesystem::exists(folder / "checkpoint.json.tmp"));

  const CheckpointFile file = read_checkpoint_json(folder.str());  // the folder finds the file
  EXPECT_EQ(file.path, folder / "checkpoint.json");
  EXPECT_EQ(file.owner.kind, "inverse");
  EXPECT_EQ(file.owner.scene_name, "bar");
  EXPECT_EQ(file.owner.design_size, 3);
  EXPECT_EQ(file.owner.problem, owner().problem);
  const OptimizerCheckpoint& r = file.checkpoint;
  EXPECT_EQ(r.backend, c.backend);
  EXPECT_EQ(r.iteration, c.iteration);
  EXPECT_EQ(r.z, c.z);  // bitwise
  EXPECT_EQ(r.objective, c.objective);
  EXPECT_EQ(r.best_z, c.best_z);
  EXPECT_EQ(r.best_objective, c.best_objective);
  ASSERT_EQ(r.history.size(), c.history.size());
  for (std::size_t i = 0; i < c.history.size(); ++i) {
    EXPECT_EQ(r.history[i].objective, c.history[i].objective);
    EXPECT_EQ(r.history[i].step_norm, c.history[i].step_norm);
    EXPECT_EQ(r.history[i].seconds, c.history[i].seconds);
    EXPECT_EQ(r.history[i].forward_solves, c.history[i].forward_solves);
  }
  EXPECT_TRUE(std::isnan(r.history[1].gradient_norm));  // JSON null
  EXPECT_EQ(r.history[2].gradient_norm, c.history[2].gradient_norm);
  EXPECT_EQ(r.evaluations, 7);
  EXPECT_EQ(r.failed_evaluations, 1);
  EXPECT_EQ(r.seconds, c.seconds);
  EXPECT_EQ(r.counters.forward_solves, 6);
  EXPECT_EQ(r.counters.adjoint_seconds, 0.05);
  EXPECT_EQ(r.backend_state, c.backend_state);

  // A second write replaces the first.
  OptimizerCheckpoint later = c;
  later.iteration = 3;
  later.history.push_back(later.history.back());
  later.history.back().iteration = 3;
  write_checkpoint_json(folder / "checkpoint.json", owner(), later);
  EXPECT_EQ(read_checkpoint_json(folder / "checkpoint.json").checkpoint.iteration, 3);
}

TEST(CheckpointFile, MissingOrDamagedFilesAreSceneErrors) {
  TempFolder folder("checkpoint_errors");
  EXPECT_THAT(error_of([&] { read_checkpoint_json(folder.str()); }),
              HasSubstr(folder / "checkpoint.json" + ": cannot open the checkpoint"));
  std::ofstream(folder / "checkpoint.json") << "{\"checkpoint_format\": 1, \"kind\": ";
  EXPECT_THAT(error_of([&] { read_checkpoint_json(folder.str()); }),
              HasSubstr("not a checkpoint (invalid JSON"));
  std::ofstream(folder / "checkpoint.json") << "{\"checkpoint_format\": 99}";
  EXPECT_THAT(error_of([&] { read_checkpoint_json(folder.str()); }),
              HasSubstr("checkpoint_format: this tailor reads checkpoint format 1, got 99"));

  // A design of the wrong length, and a history that stops short of the iteration.
  write_checkpoint_json(folder / "checkpoint.json", owner(), checkpoint());
  std::ifstream in(folder / "checkpoint.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string wrong = text;
  wrong.replace(wrong.find("\"design_size\": 3"), 16, "\"design_size\": 4");
  std::ofstream(folder / "checkpoint.json") << wrong;
  EXPECT_THAT(error_of([&] { read_checkpoint_json(folder.str()); }),
              HasSubstr("checkpoint.json: design: has 3 entries, design_size is 4"));
  wrong = text;
  wrong.replace(wrong.find("\"iteration\": 2"), 14, "\"iteration\": 5");
  std::ofstream(folder / "checkpoint.json") << wrong;
  EXPECT_THAT(error_of([&] { read_checkpoint_json(folder.str()); }),
              HasSubstr("history: does not end at the checkpoint's iteration 5"));
}

TEST(CheckpointFile, ACheckpointOfAnotherRunIsRefusedWithTheDifferences) {
  TempFolder folder("checkpoint_owner");
  write_checkpoint_json(folder / "checkpoint.json", owner(), checkpoint());
  const CheckpointFile file = read_checkpoint_json(folder.str());
  EXPECT_NO_THROW(check_checkpoint(file, owner(), OptimizerBackend::gradient_descent));

  CheckpointOwner other = owner();
  other.scene_name = "plate";
  other.design_size = 4;
  const std::string message = error_of([&] { check_checkpoint(file, other, OptimizerBackend::nlopt_lbfgs); });
  EXPECT_THAT(message,
              HasSubstr("the checkpoint belongs to another run (written for scene scenes/bar.json)"));
  EXPECT_THAT(message, HasSubstr("scene 'bar' (this run: 'plate')"));
  EXPECT_THAT(message, HasSubstr("design size '3' (this run: '4')"));
  EXPECT_THAT(message, HasSubstr("back-end 'gradient_descent' (this run: 'nlopt_lbfgs')"));
  other = owner();
  other.problem = "3D mesh, 46 vertices";
  EXPECT_THAT(error_of([&] { check_checkpoint(file, other, OptimizerBackend::gradient_descent); }),
              HasSubstr("problem '3D mesh, 45 vertices, 64 elements; design per_material'"));
}

}  // namespace
}  // namespace tailor::checkpoint_file_test
