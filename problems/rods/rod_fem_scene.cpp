// Rods next to an FEM body in one scene (declared in problems/rods/rod_scene.hpp): the static
// scene's model (build_static_model) and the rods in one Model with the FEM DOFs and parameters
// first, one Newton solve for both. The FEM terms enter through PrefixTerm, which evaluates a
// term of the FEM model on the leading slice of the combined state and parameters.
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>

#include "forward/mesh/mesh_io.hpp"
#include "problems/fem/static_scene.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

namespace {

// A term of a model over the first n DOFs and the first np parameters, inside a larger model.
class PrefixTerm final : public EnergyTerm {
 public:
  PrefixTerm(std::shared_ptr<const Model> owner, const EnergyTerm& inner, int n, int np)
      : owner_(std::move(owner)), inner_(inner), n_(n), np_(np) {}
  std::string name() const override { return inner_.name(); }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    EnergyRequest r = request;
    Vector g;
    if (request.gradient) {
      g = Vector::Zero(n_);
      r.gradient = &g;
    }
    inner_.evaluate(x.head(n_), p.head(np_), r);
    if (request.gradient) request.gradient->head(n_) += g;
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override {
    Vector gp = Vector::Zero(np_);
    inner_.add_param_gradient(x.head(n_), p.head(np_), gp);
    gradient_p.head(np_) += gp;
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override {
    inner_.add_mixed(x.head(n_), p.head(np_), mixed);
  }
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override {
    Vector gp = Vector::Zero(np_);
    inner_.add_mixed_transpose_times(x.head(n_), p.head(np_), w.head(n_), gp);
    gradient_p.head(np_) += gp;
  }
  void add_low_rank_hessian(const Vector& x, const Vector& p, LowRankHessian& update,
                            HessianMode mode) const override {
    LowRankHessian inner;
    inner_.add_low_rank_hessian(x.head(n_), p.head(np_), inner, mode);
    if (inner.empty()) return;
    Matrix F = Matrix::Zero(x.size(), inner.factors.cols());
    F.topRows(n_) = inner.factors;
    update.append(F, inner.core);
  }
  bool hessian_is_constant() const override { return inner_.hessian_is_constant(); }
  std::uint64_t hessian_revision() const override { return inner_.hessian_revision(); }
  double max_step(const Vector& x, const Vector& dx) const override {
    return inner_.max_step(x.head(n_), dx.head(n_));
  }

 private:
  std::shared_ptr<const Model> owner_;  // keeps inner_ alive
  const EnergyTerm& inner_;
  int n_, np_;
};

[[noreturn]] void scene_fail(const std::string& source, const std::string& what) {
  throw SceneError(source + ": " + what);
}

}  // namespace

RodFemSimulation simulate_rods_with_fem(const SceneNode& root, const std::string& directory,
                                        const std::string& out_dir, std::ostream* log) {
  const std::string& source = root.source();
  for (const char* key : {"dynamics", "inverse"})
    if (root.has(key)) root.at(key).fail("not implemented for a scene with both rods and a mesh");
  // The FEM body: the static scene's keys only (the rest belongs to the rods).
  nlohmann::json fem = nlohmann::json::object();
  for (const char* key : {"name", "description", "mesh", "materials", "dirichlet", "loads", "solver"})
    if (root.has(key)) fem[key] = root.at(key).json();
  const Scene scene = parse_scene(SceneNode(fem, source, ""), directory);
  require_linear_elements(scene, "a mesh coupled to rods");
  const StaticSetup setup = setup_static_scene(scene);
  require_supported(scene, setup);  // a body free to move rigidly has no equilibrium (nor do free rods)
  if (setup.solver.load_steps > 1)
    root.at("solver")
        .at("load_steps")
        .fail("a scene with rods and a mesh is solved in one step (load_steps 1)");
  RodSceneSpec spec = parse_rod_scene(root);
  spec.source = source;
  if (spec.load_steps > 1) root.at("load_steps").fail("a scene with rods and a mesh is solved in one step");
  const std::shared_ptr<const Model> fem_model = build_static_model(setup, 1.0);
  const Elimination& fe = fem_model->elimination();
  if (!fe.is_selection() || fem_model->has_prescribed_parameters())
    scene_fail(source, "the mesh's constraints must be plain Dirichlet conditions next to rods");
  RodModelPrefix prefix;
  prefix.dofs = fem_model->num_dofs();
  for (const auto& block : fem_model->parameter_layout().blocks())
    prefix.parameter_blocks.emplace_back(block.name, block.size);
  prefix.values = fe.offset();
  for (int i = 0; i < fe.num_dofs(); ++i)
    if (fe.row_begin()[static_cast<std::size_t>(i) + 1] == fe.row_begin()[static_cast<std::size_t>(i)])
      prefix.fixed_dofs.push_back(i);
  // Free FEM DOFs start at their rest positions.
  const Vector fem_rest = setup.rest_state();
  for (int i = 0; i < fe.num_dofs(); ++i)
    if (fe.row_begin()[static_cast<std::size_t>(i) + 1] > fe.row_begin()[static_cast<std::size_t>(i)])
      prefix.values[i] = fem_rest[i];
  RodSceneModel m = build_rod_model(spec, prefix);
  const int np = fem_model->parameter_layout().size();
  const Vector fem_p = setup.parameters();
  if (fem_p.size() != np) scene_fail(source, "internal: FEM parameter layout mismatch");
  m.p.head(np) = fem_p;
  for (const auto& term : fem_model->terms())
    m.model->add(std::make_unique<PrefixTerm>(fem_model, *term, prefix.dofs, np));
  RodFemSimulation out;
  out.fem_dofs = prefix.dofs;
  out.rods = solve_rod_model(m, spec, out_dir, log);
  // The body, deformed, with its displacement.
  const int dim = setup.dim(), nv = setup.mesh.num_vertices();
  Eigen::MatrixXd positions(nv, dim), displacement(nv, dim);
  for (int v = 0; v < nv; ++v)
    for (int c = 0; c < dim; ++c) {
      positions(v, c) = out.rods.state[dim * v + c];
      displacement(v, c) = positions(v, c) - fem_rest[dim * v + c];
    }
  VtkFields fields;
  fields.point["displacement"] = displacement;
  out.fem_vtu_path = (std::filesystem::path(out_dir) / "result.vtu").string();
  write_vtu(out.fem_vtu_path, setup.mesh, fields, &positions);
  if (log) *log << "wrote " << out.fem_vtu_path << "\n";
  return out;
}

}  // namespace tailor
