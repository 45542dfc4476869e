#include "problems/studio/design_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "forward/mesh/mesh_io.hpp"
#include "forward/solve/threads.hpp"
#include "optimizers/checkpoint.hpp"

namespace tailor::studio {
namespace {

// Thrown from the optimizer's per-iteration callback to stop a superseded design.
struct Superseded : std::runtime_error {
  Superseded() : std::runtime_error("superseded by a newer request") {}
};
// ... and to end a drag's design once it has settled (see DesignSession::redesign).
struct Settled : std::runtime_error {
  Settled() : std::runtime_error("settled: the handle error fell by less than the interactive tolerance") {}
};

}  // namespace

SurfaceMesh extract_surface(const Mesh& mesh) {
  SurfaceMesh surface;
  Eigen::VectorXi owners;
  const Eigen::MatrixXi facets = boundary_facets(mesh, &owners);
  std::vector<int> compact(static_cast<std::size_t>(mesh.num_vertices()), -1);
  surface.triangles.resize(facets.rows(), facets.cols());
  for (Eigen::Index f = 0; f < facets.rows(); ++f)
    for (Eigen::Index k = 0; k < facets.cols(); ++k) {
      int& index = compact[static_cast<std::size_t>(facets(f, k))];
      if (index < 0) {
        index = static_cast<int>(surface.vertices.size());
        surface.vertices.push_back(facets(f, k));
      }
      surface.triangles(f, k) = index;
    }
  surface.owners = owners;
  return surface;
}

DesignSession::DesignSession(const Scene& scene) : design_(build_reduced_design(scene)) {
  if (design_.setup.dim() != 3) throw std::invalid_argument("tailor studio designs 3D (tet) scenes");
  surface_ = extract_surface(design_.setup.mesh);
  for (const ReducedDesignHandle& h : design_.handles) targets_.push_back(h.target);
  state_.w = Vector::Zero(design_.num_design());
  state_.youngs_modulus = design_.youngs_modulus(state_.w);
  state_.displacement = Vector::Zero(design_.setup.num_dofs());
  state_.status = "not designed";
}

Eigen::VectorXd DesignSession::handle_rest_centre(int handle) const {
  const ReducedDesignHandle& h = design_.handles.at(static_cast<std::size_t>(handle));
  Eigen::VectorXd centre = Eigen::VectorXd::Zero(design_.setup.dim());
  for (int v : h.vertices) centre += design_.setup.mesh.rest_positions.row(v).transpose();
  return centre / static_cast<double>(h.vertices.size());
}

const DesignState& DesignSession::redesign(const std::vector<Eigen::VectorXd>& targets,
                                           const std::function<bool(int, double)>& keep_going) {
  const auto start = std::chrono::steady_clock::now();
  // The thread counts are per thread in OpenMP: the server's worker threads take the process's.
  set_thread_settings(thread_settings());
  set_handle_targets(design_, targets);  // validates; throws before anything changes
  OptimizerOptions options = design_.optimizer;
  options.progress = nullptr;
  options.checkpoint_every = 1;
  std::vector<double> objectives;
  options.on_checkpoint = [&](const OptimizerCheckpoint& c) {
    if (keep_going && !keep_going(c.iteration, c.objective)) throw Superseded();
    // sqrt(2 J): the handles' relative error (with the smoothness term), dimensionless.
    objectives.push_back(std::sqrt(2.0 * std::max(c.objective, 0.0)));
    const std::size_t n = objectives.size();
    if (n > kSettleWindow && objectives[n - 1 - kSettleWindow] - objectives[n - 1] <= kSettleTolerance) throw Settled();
  };
  OptimizerResult result = minimize(*design_.functional, state_.w, Bounds{}, {}, options);
  const auto stopped_by = [&](const std::exception& reason) {
    return result.status == OptimizerStatus::failed && result.message.find(reason.what()) != std::string::npos;
  };
  const bool superseded = stopped_by(Superseded());
  if (stopped_by(Settled())) {
    result.status = OptimizerStatus::converged;
    result.message = Settled().what();
  }
  if (superseded) {
    set_handle_targets(design_, targets_);  // back to the last finished design's targets
    state_.superseded = true;
    return state_;
  }
  DesignState next;
  next.w = result.z;
  next.youngs_modulus = design_.youngs_modulus(next.w);
  next.iterations = result.history.empty() ? 0 : result.history.back().iteration;
  next.status = to_string(result.status);
  next.message = result.message;
  next.evaluations = result.evaluations;
  next.optimizer_seconds = result.seconds;
  try {
    next.displacement = design_.reduced_displacement(design_.functional->solve(next.w));
    next.reduced_errors = design_.handle_errors(next.displacement);
  } catch (const EvaluationError& e) {
    set_handle_targets(design_, targets_);
    throw std::runtime_error(std::string("the reduced equilibrium at the new design failed: ") + e.what());
  }
  next.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  targets_ = targets;
  state_ = std::move(next);
  return state_;
}

FullSpaceCheck DesignSession::check_full_space() const {
  return full_space_check(design_, state_.w, &state_.displacement);
}

std::string DesignSession::save(const std::string& out_dir) {
  const ReducedDesignRun run = run_reduced_design(design_, out_dir);
  const Mesh& mesh = design_.setup.mesh;
  const Vector displacement = run.q.size() > 0 ? design_.reduced_displacement(run.q) : state_.displacement;
  const Eigen::MatrixXd rows = displacement.reshaped(design_.setup.dim(), mesh.num_vertices()).transpose();
  VtkFields fields;
  fields.cell["youngs_modulus"] = design_.youngs_modulus(run.result.z);
  fields.point["displacement"] = rows;
  const Eigen::MatrixXd positions = mesh.rest_positions + rows;
  write_vtu((std::filesystem::path(out_dir) / "result.vtu").string(), mesh, fields, &positions);
  return run.report_path;
}

}  // namespace tailor::studio
