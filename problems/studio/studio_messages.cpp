#include "problems/studio/studio_messages.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "problems/studio/float32_base64.hpp"

namespace tailor::studio {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// A message field that is missing or of the wrong shape.
struct BadMessage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

json error(const std::string& message) { return {{"type", "error"}, {"message", message}}; }

// Numbers as floats: the page draws in single precision, and the replies get half as long.
template <class Vector>
json floats(const Vector& values) {
  json out = json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) out.push_back(static_cast<float>(values[i]));
  return out;
}

// The message's "arrays": "json" (the default: numbers) or "float32-base64" (the large arrays of
// the reply as strings, problems/studio/float32_base64.hpp).
bool binary_arrays(const json& message) {
  const auto found = message.find("arrays");
  if (found == message.end()) return false;
  if (found->is_string() && *found == "json") return false;
  if (found->is_string() && *found == "float32-base64") return true;
  throw BadMessage("\"arrays\" must be \"json\" or \"float32-base64\"");
}

json float_array(const Eigen::VectorXf& values, bool binary) {
  if (!binary) return floats(values);
  return encode_float32_base64(std::vector<float>(values.data(), values.data() + values.size()));
}

std::vector<Eigen::VectorXd> parse_targets(const json& message, std::size_t handles, int dim) {
  const auto found = message.find("targets");
  if (found == message.end() || !found->is_array())
    throw BadMessage("retarget: \"targets\" must be an array of " + std::to_string(handles) + " displacements");
  if (found->size() != handles)
    throw BadMessage("retarget: \"targets\" has " + std::to_string(found->size()) + " entries, the scene has " +
                     std::to_string(handles) + " handles");
  std::vector<Eigen::VectorXd> targets;
  for (std::size_t h = 0; h < handles; ++h) {
    const json& t = (*found)[h];
    if (!t.is_array() || t.size() != static_cast<std::size_t>(dim))
      throw BadMessage("retarget: targets[" + std::to_string(h) + "] must be " + std::to_string(dim) + " numbers");
    Eigen::VectorXd v(dim);
    for (int k = 0; k < dim; ++k) {
      if (!t[static_cast<std::size_t>(k)].is_number())
        throw BadMessage("retarget: targets[" + std::to_string(h) + "][" + std::to_string(k) + "] is not a number");
      v[k] = t[static_cast<std::size_t>(k)].get<double>();
      if (!std::isfinite(v[k])) throw BadMessage("retarget: targets[" + std::to_string(h) + "] is not finite");
    }
    if (!(v.norm() > 0.0)) throw BadMessage("retarget: targets[" + std::to_string(h) + "] must not be zero");
    targets.push_back(v);
  }
  return targets;
}

json output_files(const fs::path& folder) {
  json files = json::array();
  std::error_code error;
  if (!fs::is_directory(folder, error)) return files;
  constexpr std::size_t kMaxFiles = 5000;
  for (auto it = fs::recursive_directory_iterator(folder, error); !error && it != fs::recursive_directory_iterator();
       it.increment(error)) {
    if (!it->is_regular_file(error) || it->is_symlink(error)) continue;
    files.push_back({{"path", fs::relative(it->path(), folder).generic_string()}, {"bytes", it->file_size(error)}});
    if (files.size() >= kMaxFiles) break;
  }
  return files;
}

}  // namespace

StudioMessages::StudioMessages(std::unique_ptr<DesignSession> design, fs::path output_folder, std::string title)
    : design_(std::move(design)), output_folder_(std::move(output_folder)), title_(std::move(title)) {}

long StudioMessages::arrive(long sequence) {
  if (sequence <= 0) return ++newest_;
  long seen = newest_.load();
  while (seen < sequence && !newest_.compare_exchange_weak(seen, sequence)) {
  }
  return sequence;
}

json StudioMessages::handle(const std::string& text, const Emit& emit) {
  json message;
  try {
    message = json::parse(text);
  } catch (const json::exception& e) {  // a syntax error, or a number out of range
    return error(std::string("the message is not JSON: ") + e.what());
  }
  if (!message.is_object() || !message.contains("type") || !message["type"].is_string())
    return error("a message is a JSON object with a string \"type\"");
  const std::string type = message["type"];
  try {
    if (type == "hello") return hello();
    if (type != "scene" && type != "retarget" && type != "full_check" && type != "save")
      return error("unknown message type \"" + type + "\"");
    if (!design_) return error("\"" + type + "\" needs a handle scene with inverse.design.reduction; this is a result viewer");
    if (type == "scene") return scene(binary_arrays(message));
    if (type == "retarget") return retarget(message, emit);
    if (type == "full_check") return full_check();
    return save(emit);
  } catch (const BadMessage& e) {
    return error(e.what());
  } catch (const std::exception& e) {  // the computation failed; the state is unchanged
    return error(type + " failed: " + e.what());
  }
}

json StudioMessages::hello() const {
  return {{"type", "hello"},
          {"mode", design_ ? "design" : "results"},
          {"title", title_},
          {"output_folder", output_folder_.filename().string()},
          {"files", output_files(output_folder_)}};
}

json StudioMessages::scene(bool binary) {
  const std::lock_guard<std::mutex> lock(computing_);  // the design's state changes under a retarget
  const SurfaceMesh& surface = design_->surface();
  const Mesh& mesh = design_->design().setup.mesh;
  json positions = json::array();
  for (int v : surface.vertices)
    for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(mesh.rest_positions(v, k)));
  json triangles = json::array();
  for (Eigen::Index f = 0; f < surface.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) triangles.push_back(surface.triangles(f, k));
  json handles = json::array();
  const auto& design_handles = design_->design().handles;
  for (std::size_t h = 0; h < design_handles.size(); ++h) {
    handles.push_back({{"key", design_handles[h].key},
                       {"rest_centre", floats(design_->handle_rest_centre(static_cast<int>(h)))},
                       {"force", floats(design_handles[h].force)},
                       {"scene_target", floats(design_handles[h].target)}});
  }
  json reply = design_reply(design_->state(), binary);
  reply["type"] = "scene";
  reply["positions"] = positions;
  reply["triangles"] = triangles;
  reply["handles"] = handles;
  reply["elements"] = mesh.num_elements();
  return reply;
}

json StudioMessages::design_reply(const DesignState& state, bool binary) const {
  const SurfaceMesh& surface = design_->surface();
  Eigen::VectorXf surface_modulus(surface.owners.size());
  for (Eigen::Index f = 0; f < surface.owners.size(); ++f)
    surface_modulus[f] = static_cast<float>(state.youngs_modulus[surface.owners[f]]);
  Eigen::VectorXf displacement(3 * static_cast<Eigen::Index>(surface.vertices.size()));
  for (std::size_t i = 0; i < surface.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k)
      displacement[3 * static_cast<Eigen::Index>(i) + k] =
          static_cast<float>(state.displacement[3 * surface.vertices[i] + k]);
  json targets = json::array();
  for (const Eigen::VectorXd& t : design_->targets()) targets.push_back(floats(t));
  return {{"type", "design"},
          {"arrays", binary ? "float32-base64" : "json"},
          {"youngs_modulus", float_array(surface_modulus, binary)},
          {"youngs_modulus_range", {state.youngs_modulus.minCoeff(), state.youngs_modulus.maxCoeff()}},
          {"displacement", float_array(displacement, binary)},
          {"targets", targets},
          {"reduced_errors", state.reduced_errors},
          {"iterations", state.iterations},
          {"evaluations", state.evaluations},
          {"seconds", state.seconds},
          {"optimizer_seconds", state.optimizer_seconds},
          {"status", state.status},
          {"message", state.message}};
}

json StudioMessages::retarget(const json& message, const Emit& emit) {
  const auto arrived = std::chrono::steady_clock::now();
  const std::vector<Eigen::VectorXd> targets =
      parse_targets(message, design_->design().handles.size(), design_->design().setup.dim());
  long sequence = 0;
  if (const auto found = message.find("sequence"); found != message.end()) {
    if (!found->is_number_integer() || found->get<long>() <= 0)
      throw BadMessage("retarget: \"sequence\" must be a positive integer");
    sequence = found->get<long>();
  }
  const bool binary = binary_arrays(message);
  const long request = arrive(sequence);
  const std::lock_guard<std::mutex> lock(computing_);
  if (!is_newest(request)) return {{"type", "superseded"}, {"request", request}};
  auto last = std::chrono::steady_clock::now();
  // Waiting for the computation this one supersedes to stop (the page's latency profile).
  const double queued_seconds = std::chrono::duration<double>(last - arrived).count();
  bool first = true;
  const DesignState& state = design_->redesign(targets, [&](int iteration, double objective) {
    const auto now = std::chrono::steady_clock::now();
    // The first iteration, then a line every 50 ms: a few lines a second, not one per iteration.
    if (emit && (first || now - last > std::chrono::milliseconds(50))) {
      emit({{"type", "progress"}, {"request", request}, {"iteration", iteration}, {"objective", objective}});
      last = now;
      first = false;
    }
    return is_newest(request);
  });
  if (state.superseded) return {{"type", "superseded"}, {"request", request}};
  json reply = design_reply(state, binary);
  reply["request"] = request;
  reply["queued_seconds"] = queued_seconds;
  return reply;
}

json StudioMessages::full_check() {
  const std::lock_guard<std::mutex> lock(computing_);
  const FullSpaceCheck check = design_->check_full_space();
  return {{"type", "full_check"},
          {"converged", check.converged},
          {"message", check.message},
          {"seconds", check.seconds},
          {"full_errors", check.handle_errors},
          {"reduced_errors", design_->state().reduced_errors}};
}

json StudioMessages::save(const Emit& emit) {
  const std::lock_guard<std::mutex> lock(computing_);
  if (emit) emit({{"type", "progress"}, {"message", "designing from w = 0 and checking in full space, as tailor run"}});
  const std::string report = design_->save(output_folder_.string());
  return {{"type", "saved"},
          {"report", fs::relative(report, output_folder_).generic_string()},
          {"vtu", "result.vtu"},
          {"files", output_files(output_folder_)}};
}

StudioEndpoints endpoints(StudioMessages& messages) {
  return {messages.output_folder(),
          [&messages](const std::string& text, const std::function<void(const std::string&)>& emit) {
            return messages.handle(text, [&emit](const json& progress) { emit(progress.dump()); }).dump();
          }};
}

}  // namespace tailor::studio
