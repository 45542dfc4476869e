#include "problems/fem/study.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "forward/mesh/mesh.hpp"
#include "problems/fem/inverse_scene.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

namespace select {
nlohmann::json plane(const std::string& axis, double value) {
  return {{"plane", {{"axis", axis}, {"value", value}}}};
}
nlohmann::json box(std::vector<double> min, std::vector<double> max) {
  return {{"box", {{"min", std::move(min)}, {"max", std::move(max)}}}};
}
nlohmann::json list(std::vector<int> ids) { return {{"list", std::move(ids)}}; }
nlohmann::json boundary() { return {{"boundary", true}}; }
nlohmann::json all() { return "all"; }
nlohmann::json region(int region) { return {{"region", region}}; }
nlohmann::json element_box(std::vector<double> min, std::vector<double> max) { return box(min, max); }
}  // namespace select

Study::Study() : document_(nlohmann::json::object()) {}

Study Study::from_file(const std::string& path) {
  const std::string directory = std::filesystem::path(path).parent_path().string();
  Study study = from_json(read_scene_document(path), path, directory);
  if (!study.document_.contains("name"))
    study.document_["name"] = std::filesystem::path(path).stem().string();
  return study;
}

Study Study::from_json(nlohmann::json scene, const std::string& source, const std::string& directory) {
  if (!scene.is_object())
    throw SceneError(source + ": (top level): expected a JSON object, got " + describe_json(scene));
  Study study;
  study.document_ = std::move(scene);
  study.source_ = source;
  study.directory_ = directory;
  return study;
}

void Study::check_unbuilt(const char* what) const {
  if (scene_ || problem_)
    throw std::logic_error(std::string("Study::") + what +
                           ": the problem is built already (change the study first)");
}

nlohmann::json& Study::scene() {
  check_unbuilt("scene");
  return document_;
}

nlohmann::json& Study::inverse() {
  nlohmann::json& section = document_["inverse"];
  if (section.is_null()) section = nlohmann::json::object();
  return section;
}

Study& Study::mesh_box(std::vector<double> min, std::vector<double> max, std::vector<int> cells) {
  check_unbuilt("mesh_box");
  document_["mesh"] = {{min.size() == 2 ? "rectangle" : "box",
                        {{"min", std::move(min)}, {"max", std::move(max)}, {"cells", std::move(cells)}}}};
  return *this;
}

Study& Study::mesh_file(const std::string& path) {
  check_unbuilt("mesh_file");
  document_["mesh"] = {{"file", path}};
  return *this;
}

Study& Study::material(nlohmann::json elements, const std::string& model, double youngs_modulus,
                       double poisson_ratio, double density) {
  check_unbuilt("material");
  nlohmann::json m = {{"elements", std::move(elements)},
                      {"model", model},
                      {"youngs_modulus", youngs_modulus},
                      {"poisson_ratio", poisson_ratio}};
  if (density != 0.0) m["density"] = density;
  document_["materials"].push_back(std::move(m));
  return *this;
}

Study& Study::fix(nlohmann::json vertices) {
  check_unbuilt("fix");
  document_["dirichlet"].push_back({{"vertices", std::move(vertices)}});
  return *this;
}

Study& Study::prescribe(nlohmann::json vertices, std::vector<double> displacement) {
  check_unbuilt("prescribe");
  document_["dirichlet"].push_back(
      {{"vertices", std::move(vertices)}, {"displacement", std::move(displacement)}});
  return *this;
}

Study& Study::traction(nlohmann::json faces, std::vector<double> traction) {
  check_unbuilt("traction");
  document_["loads"]["tractions"].push_back({{"faces", std::move(faces)}, {"traction", std::move(traction)}});
  return *this;
}

Study& Study::force(nlohmann::json vertices, std::vector<double> force) {
  check_unbuilt("force");
  document_["loads"]["nodal"].push_back({{"vertices", std::move(vertices)}, {"force", std::move(force)}});
  return *this;
}

Study& Study::design(nlohmann::json design) {
  check_unbuilt("design");
  inverse()["design"] = std::move(design);
  extensions_.element_map = nullptr;
  return *this;
}

Study& Study::design(ParameterizationPtr element_map, Vector z0, Bounds bounds) {
  check_unbuilt("design");
  if (!element_map) throw std::invalid_argument("Study::design: no design map");
  extensions_.element_map = std::move(element_map);
  extensions_.z0 = std::move(z0);
  extensions_.bounds = std::move(bounds);
  return *this;
}

Study& Study::objective(nlohmann::json term) {
  check_unbuilt("objective");
  inverse()["objective"].push_back(std::move(term));
  return *this;
}

Study& Study::objective(const std::string& name, ObjectiveFactory make, double weight) {
  check_unbuilt("objective");
  if (!make) throw std::invalid_argument("Study::objective: '" + name + "' has no factory");
  if (!(weight >= 0.0))
    throw std::invalid_argument("Study::objective: the weight of '" + name + "' must be >= 0");
  extensions_.objective_terms.push_back({name, weight, std::move(make)});
  return *this;
}

Study& Study::energy(EnergyTermFactory make) {
  check_unbuilt("energy");
  if (!make) throw std::invalid_argument("Study::energy: no factory");
  extensions_.energy_terms.push_back(std::move(make));
  return *this;
}

Study& Study::optimizer(nlohmann::json optimizer) {
  check_unbuilt("optimizer");
  inverse()["optimizer"] = std::move(optimizer);
  return *this;
}

Study& Study::constraint(ConstraintFactory make) {
  check_unbuilt("constraint");
  if (!make) throw std::invalid_argument("Study::constraint: no factory");
  constraints_.push_back(std::move(make));
  return *this;
}

// The scene without its inverse section through parse_scene, then the section (completed by
// what C++ gave) through parse_inverse_section: one parser, one set of messages.
const Scene& Study::parsed_scene() {
  if (scene_) return *scene_;
  nlohmann::json document = document_;
  nlohmann::json section = document.contains("inverse") ? document["inverse"] : nlohmann::json::object();
  document.erase("inverse");
  Scene scene = parse_scene(SceneNode(document, source_, ""), directory_);
  if (scene.name.empty()) scene.name = "study";
  if (!section.is_object())
    throw SceneError(source_ + ": inverse: expected an object, got " + describe_json(section));
  if (!section.contains("objective")) section["objective"] = nlohmann::json::array();
  if (extensions_.element_map && !section.contains("design"))
    section["design"] = {{"parameter", "youngs_modulus"}, {"granularity", "per_element"}};
  const bool other_data = !extensions_.objective_terms.empty();
  scene.inverse = std::make_shared<const InverseSpec>(
      parse_inverse_section(SceneNode(section, scene.source, "inverse"), scene.directory, other_data));
  scene_ = std::move(scene);
  return *scene_;
}

Study& Study::build_progress(std::ostream* progress) {
  check_unbuilt("build_progress");
  build_progress_ = progress;
  return *this;
}

InverseProblem& Study::problem() {
  if (problem_) return *problem_;
  parsed_scene();
  if (!build_progress_) return *(problem_ = build_inverse_problem(*scene_, extensions_));
  // The progress stream only while the problem is built: its solves afterwards print nothing.
  Scene scene = *scene_;
  scene.solver.newton.progress = build_progress_;
  problem_ = build_inverse_problem(scene, extensions_);
  problem_->setup.solver.newton.progress = nullptr;
  problem_->functional->newton_options().progress = nullptr;
  build_progress_ = nullptr;  // for this build only (a later one, after run(), prints nothing)
  return *problem_;
}

std::vector<EnergyTermCheck> Study::check_energy_terms(unsigned seed) {
  return check_static_scene(problem().setup, seed);
}

TaylorTestResult Study::taylor_test(std::optional<TaylorTestOptions> options) {
  InverseProblem& p = problem();
  // As gradcheck_problem: J(z + h dz) is only as accurate as the equilibrium.
  // The run keeps the problem's own tolerances: they are put back afterwards.
  NewtonOptions& newton = p.functional->newton_options();
  const NewtonOptions kept = newton;
  const double tighter = 1e-14 / newton.relative_tolerance;
  if (tighter < 1.0) {
    newton.relative_tolerance *= tighter;
    newton.absolute_tolerance *= tighter;
  }
  TaylorTestResult result = tailor::taylor_test(*p.functional, p.z0, options.value_or(p.spec.gradcheck));
  newton = kept;
  return result;
}

InverseRun Study::run(const std::string& out_dir, std::ostream* log, std::ostream* progress) {
  problem();
  std::vector<Constraint> constraints;
  for (const ConstraintFactory& make : constraints_) constraints.push_back(make(*problem_));
  InverseRun result = run_inverse_problem(std::move(problem_), out_dir, log, progress, {}, constraints);
  scene_.reset();
  return result;
}

namespace {

// sum_e V_e E_e / sum_e V_e with E = the "youngs_modulus" block of p(z).
class MeanYoungsModulus final : public ReducedFunctional {
 public:
  explicit MeanYoungsModulus(const InverseProblem& problem)
      : map_(problem.parameterization), offset_(problem.youngs_offset) {
    weights_ = element_volumes(problem.setup.mesh).cwiseAbs();
    weights_ /= weights_.sum();
  }
  int size() const override { return map_->num_design(); }
  double value(const Vector& z) override {
    ++counters_.evaluations;
    return weights_.dot(map_->apply(z).segment(offset_, weights_.size()));
  }
  double value_and_gradient(const Vector& z, Vector& gradient) override {
    Vector w = Vector::Zero(map_->num_params());
    w.segment(offset_, weights_.size()) = weights_;
    gradient = map_->jacobian_transpose_times(z, w);
    return value(z);
  }

 private:
  ParameterizationPtr map_;
  int offset_;
  Vector weights_;
};

Constraint make_constraint(std::shared_ptr<ReducedFunctional> f, double bound, double sign, bool equality,
                           std::string name) {
  if (!f) throw std::invalid_argument("constraint '" + name + "': no functional");
  const double scale = bound != 0.0 ? std::abs(bound) : 1.0;
  Constraint c;
  c.name = std::move(name);
  c.equality = equality;
  c.evaluate = [f, bound, scale, sign](const Vector& z, Vector* gradient) {
    double value = 0.0;
    if (gradient) {
      value = f->value_and_gradient(z, *gradient);
      *gradient *= sign / scale;
    } else {
      value = f->value(z);
    }
    return sign * (value - bound) / scale;
  };
  return c;
}

}  // namespace

std::shared_ptr<ReducedFunctional> mean_youngs_modulus(const InverseProblem& problem) {
  return std::make_shared<MeanYoungsModulus>(problem);
}

std::shared_ptr<ReducedFunctional> state_functional(const InverseProblem& problem, ObjectivePtr objective) {
  return make_static_functional(problem, std::move(objective));
}

Constraint at_most(std::shared_ptr<ReducedFunctional> f, double bound, std::string name) {
  return make_constraint(std::move(f), bound, 1.0, false, std::move(name));
}
Constraint at_least(std::shared_ptr<ReducedFunctional> f, double bound, std::string name) {
  return make_constraint(std::move(f), bound, -1.0, false, std::move(name));
}
Constraint equal_to(std::shared_ptr<ReducedFunctional> f, double bound, std::string name) {
  return make_constraint(std::move(f), bound, 1.0, true, std::move(name));
}

}  // namespace tailor
