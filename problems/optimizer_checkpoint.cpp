#include "problems/optimizer_checkpoint.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "problems/json_text.hpp"
#include "problems/optimizer_report.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"
#include "tailor_version.hpp"

namespace tailor {
namespace {

using Json = nlohmann::ordered_json;

// Non-finite numbers are written as null (JSON has no NaN); read back as NaN.
double number_or_nan(const SceneNode& node) {
  return node.json().is_null() ? std::numeric_limits<double>::quiet_NaN() : node.number();
}

Vector read_vector(const SceneNode& node) {
  const std::vector<SceneNode> items = node.items();
  Vector v(static_cast<Eigen::Index>(items.size()));
  for (std::size_t k = 0; k < items.size(); ++k) v[static_cast<Eigen::Index>(k)] = items[k].number();
  return v;
}

OptimizerIteration read_row(const SceneNode& node) {
  OptimizerIteration row;
  row.iteration = node.at("iteration").integer(0);
  row.objective = number_or_nan(node.at("objective"));
  row.gradient_norm = number_or_nan(node.at("gradient_norm"));
  row.step_norm = number_or_nan(node.at("step"));
  row.seconds = node.at("seconds").non_negative();
  row.forward_solves = node.at("forward_solves").integer(0);
  row.adjoint_solves = node.at("adjoint_solves").integer(0);
  return row;
}

}  // namespace

void write_checkpoint_json(const std::string& path, const CheckpointOwner& owner,
                           const OptimizerCheckpoint& c) {
  Json document;
  document["checkpoint_format"] = kCheckpointFormatVersion;
  document["tailor_version"] = version_string;
  document["kind"] = owner.kind;
  document["scene"] = {{"name", owner.scene_name}, {"source", owner.scene_source}};
  document["problem"] = owner.problem;
  document["design_size"] = owner.design_size;
  document["backend"] = to_string(c.backend);
  document["iteration"] = c.iteration;
  document["design"] = to_json(c.z);
  document["objective"] = c.objective;
  document["best"] = {{"design", c.best_z.size() > 0 ? to_json(c.best_z) : Json(nullptr)},
                      {"objective", c.best_objective},
                      {"violation", c.best_violation}};
  Json state = Json::object();
  for (const auto& [name, value] : c.backend_state) state[name] = value;
  document["backend_state"] = state;
  document["evaluations"] = c.evaluations;
  document["failed_evaluations"] = c.failed_evaluations;
  document["seconds"] = c.seconds;
  document["solves"] = {{"evaluations", c.counters.evaluations},
                        {"forward", c.counters.forward_solves},
                        {"adjoint", c.counters.adjoint_solves},
                        {"forward_seconds", c.counters.forward_seconds},
                        {"adjoint_seconds", c.counters.adjoint_seconds}};
  OptimizerResult rows;
  rows.history = c.history;
  document["history"] = optimizer_history_json(rows);
  write_text_file_atomically(path, dump_json(document, 1) + "\n");
}

CheckpointFile read_checkpoint_json(const std::string& folder) {
  std::error_code error;
  CheckpointFile file;
  file.path = std::filesystem::is_directory(folder, error)
                  ? (std::filesystem::path(folder) / kCheckpointFileName).string()
                  : folder;
  std::ifstream in(file.path);
  if (!in)
    throw SceneError(file.path + ": cannot open the checkpoint (tailor run writes " + kCheckpointFileName +
                     " into its output folder every checkpoint_every iterations)");
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json document;
  try {
    document = parse_json(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw SceneError(file.path + ": not a checkpoint (invalid JSON: " + e.what() + ")");
  }
  const SceneNode root(document, file.path, "");
  if (!document.is_object()) root.fail("not a checkpoint (expected a JSON object)");
  const int format = root.at("checkpoint_format").integer(0);
  if (format != kCheckpointFormatVersion)
    root.at("checkpoint_format")
        .fail("this tailor reads checkpoint format " + std::to_string(kCheckpointFormatVersion) + ", got " +
              std::to_string(format));
  file.owner.kind = root.at("kind").string();
  file.owner.scene_name = root.at("scene").at("name").string();
  file.owner.scene_source = root.at("scene").at("source").string();
  file.owner.problem = root.at("problem").string();
  file.owner.design_size = root.at("design_size").integer(0);

  OptimizerCheckpoint& c = file.checkpoint;
  const SceneNode backend = root.at("backend");
  try {
    c.backend = parse_optimizer_backend(backend.string());
  } catch (const std::invalid_argument& e) {
    backend.fail(e.what());
  }
  c.iteration = root.at("iteration").integer(0);
  c.z = read_vector(root.at("design"));
  if (c.z.size() != file.owner.design_size)
    root.at("design").fail("has " + std::to_string(c.z.size()) + " entries, design_size is " +
                           std::to_string(file.owner.design_size));
  c.objective = number_or_nan(root.at("objective"));
  const SceneNode best = root.at("best");
  if (!best.at("design").json().is_null()) c.best_z = read_vector(best.at("design"));
  if (c.best_z.size() != 0 && c.best_z.size() != c.z.size())
    best.at("design").fail("has " + std::to_string(c.best_z.size()) + " entries, design_size is " +
                           std::to_string(c.z.size()));
  c.best_objective = number_or_nan(best.at("objective"));
  c.best_violation = number_or_nan(best.at("violation"));
  const SceneNode state = root.at("backend_state");
  if (!state.json().is_object()) state.fail("expected an object");
  for (const auto& [name, value] : state.json().items())
    c.backend_state[name] = state.at(name.c_str()).number();
  c.evaluations = root.at("evaluations").integer(0);
  c.failed_evaluations = root.at("failed_evaluations").integer(0);
  c.seconds = root.at("seconds").non_negative();
  const SceneNode solves = root.at("solves");
  c.counters.evaluations = solves.at("evaluations").integer(0);
  c.counters.forward_solves = solves.at("forward").integer(0);
  c.counters.adjoint_solves = solves.at("adjoint").integer(0);
  c.counters.forward_seconds = solves.at("forward_seconds").non_negative();
  c.counters.adjoint_seconds = solves.at("adjoint_seconds").non_negative();
  for (const SceneNode& row : root.at("history").items()) c.history.push_back(read_row(row));
  if (c.history.empty() || c.history.back().iteration != c.iteration)
    root.at("history").fail("does not end at the checkpoint's iteration " + std::to_string(c.iteration));
  for (std::size_t k = 0; k < c.history.size(); ++k)
    if (c.history[k].iteration != static_cast<int>(k))
      root.at("history").items()[k].at("iteration").fail("expected " + std::to_string(k));
  return file;
}

void check_checkpoint(const CheckpointFile& file, const CheckpointOwner& expected, OptimizerBackend backend) {
  const CheckpointOwner& got = file.owner;
  std::string differences;
  auto differs = [&](const std::string& what, const std::string& here, const std::string& there) {
    if (here == there) return;
    differences += (differences.empty() ? "" : "; ") + what + " '" + there + "' (this run: '" + here + "')";
  };
  differs("kind", expected.kind, got.kind);
  differs("scene", expected.scene_name, got.scene_name);
  differs("design size", std::to_string(expected.design_size), std::to_string(got.design_size));
  differs("problem", expected.problem, got.problem);
  differs("back-end", to_string(backend), to_string(file.checkpoint.backend));
  if (!differences.empty())
    throw SceneError(file.path + ": the checkpoint belongs to another run (written for scene " +
                     got.scene_source + "): " + differences);
}

}  // namespace tailor
