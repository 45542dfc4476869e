// The reduced functional of a scene's inverse problem: tailor._tailor.Functional. J(z), dJ/dz
// and Hessian-vector products are those the optimizer back-ends of `tailor run` see, and
// taylor_test() is `tailor gradcheck`'s test (forward solves tightened to the round-off floor).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>

#include "adjoint/taylor_test.hpp"
#include "bindings.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/study.hpp"

namespace py = pybind11;

namespace tailor::python {
namespace {

class Functional {
 public:
  explicit Functional(const SceneDocument& doc) {
    const SceneFile& file = doc.file;
    if (!file.document.is_object() || !file.document.contains("inverse"))
      throw SceneError(file.source +
                       ": (top level): the scene has no \"inverse\" section (a reduced functional needs one; "
                       "see docs/scenes.md)");
    Study made = Study::from_json(file.document, file.source, file.directory());
    if (!file.path.empty() && !made.scene().contains("name")) made.scene()["name"] = file.stem();
    // Building the problem may take seconds (synthetic observations are forward solves): a
    // stream that drops the solves' lines and checks Python's signals on each makes Ctrl-C
    // stop it with KeyboardInterrupt.
    PythonStream interruptible(py::none(), /*check_signals=*/true);
    made.build_progress(&interruptible);
    study_ = std::make_unique<Study>(std::move(made));
    problem_ = without_gil([&] { return &study_->problem(); });
  }

  int size() const { return problem_->num_design(); }
  double value(const Vector& z) {
    check_size(z, "z");
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    return problem_->functional->value(z);
  }
  std::pair<double, Vector> value_and_gradient(const Vector& z) {
    check_size(z, "z");
    Vector gradient(z.size());
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    const double value = problem_->functional->value_and_gradient(z, gradient);
    return {value, std::move(gradient)};
  }
  Vector gradient(const Vector& z) { return value_and_gradient(z).second; }
  bool has_hessian_vector() const { return problem_->functional->has_hessian_vector(); }
  Vector hessian_vector_product(const Vector& z, const Vector& v) {
    check_size(z, "z");
    check_size(v, "v");
    if (!has_hessian_vector())
      throw std::invalid_argument(problem_->scene_source +
                                  ": this objective has no Hessian-vector products (a term without second "
                                  "derivatives)");
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    return problem_->functional->hessian_vector(z, v);
  }
  // Gauss-Newton products (dr/dz)^T (dr/dz) v of a least-squares objective J = 1/2 |r|^2, as
  // newton_cg uses them (StaticFunctional::gauss_newton_vector), and the residuals r(z).
  bool has_gauss_newton_vector() const { return problem_->functional->has_gauss_newton_vector(); }
  Vector gauss_newton_vector_product(const Vector& z, const Vector& v) {
    check_size(z, "z");
    check_size(v, "v");
    if (!has_gauss_newton_vector())
      throw std::invalid_argument(problem_->scene_source +
                                  ": this objective has no Gauss-Newton products (it is not least squares)");
    if (!v.allFinite()) throw std::invalid_argument(problem_->scene_source + ": v has non-finite entries");
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    return problem_->functional->gauss_newton_vector(z, v);
  }
  Vector residuals(const Vector& z) {
    check_size(z, "z");
    if (!problem_->functional->has_residuals())
      throw std::invalid_argument(problem_->scene_source +
                                  ": this objective has no residual form (it is not least squares)");
    Vector r;
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    problem_->functional->residuals(z, r, nullptr);
    return r;
  }
  // Each objective term's weighted value at z (as report.json's objective.terms of `tailor run`).
  py::list objective_terms(const Vector& z) {
    check_size(z, "z");
    std::vector<double> values;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      problem_->functional->value(z);
      const StaticFunctional& f = *problem_->functional;
      for (const ObjectiveTermInfo& t : problem_->terms)
        values.push_back(t.coefficient * t.term->value(f.state(), f.parameters()));
    }
    py::list terms;
    for (std::size_t k = 0; k < problem_->terms.size(); ++k) {
      const ObjectiveTermInfo& t = problem_->terms[k];
      py::dict d;
      d["key"] = t.key;
      d["type"] = t.type;
      d["weight"] = t.weight;
      d["coefficient"] = t.coefficient;
      d["value"] = values[k];
      terms.append(d);
    }
    return terms;
  }
  // The equilibrium at z as displacements from the rest positions (num_vertices x dim; with
  // quadratic elements the vertices', the head of the state, and dL/du acts on them), and the
  // products with its derivative: vjp(z, dL/du) = (du/dz)^T dL/du (one adjoint solve) and
  // jvp(z, dz) = (du/dz) dz (one tangent solve), as StaticFunctional::state_vjp / state_jvp.
  Eigen::MatrixXd state(const Vector& z) {
    check_size(z, "z");
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    problem_->functional->value(z);
    return as_vertex_rows(problem_->functional->state() - problem_->setup.rest_state());
  }
  Vector vjp(const Vector& z, const Eigen::MatrixXd& dL_du) {
    check_size(z, "z");
    const Eigen::MatrixXd& X = problem_->setup.mesh.rest_positions;
    if (dL_du.rows() != X.rows() || dL_du.cols() != X.cols())
      throw std::invalid_argument(problem_->scene_source + ": dL_du has shape (" +
                                  std::to_string(dL_du.rows()) + ", " + std::to_string(dL_du.cols()) +
                                  "), the state (" + std::to_string(X.rows()) + ", " +
                                  std::to_string(X.cols()) + ")");
    vertex_dofs(problem_->model->num_dofs());  // throws for a state with DOFs besides the mesh's
    if (!dL_du.allFinite())
      throw std::invalid_argument(problem_->scene_source + ": dL_du has non-finite entries");
    Vector w = Vector::Zero(problem_->model->num_dofs());  // zero on edge nodes (quadratic elements)
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(w.data(), X.rows(),
                                                                                       X.cols()) = dL_du;
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    return problem_->functional->state_vjp(z, w);
  }
  Eigen::MatrixXd jvp(const Vector& z, const Vector& dz) {
    check_size(z, "z");
    check_size(dz, "dz");
    if (!dz.allFinite()) throw std::invalid_argument(problem_->scene_source + ": dz has non-finite entries");
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    return as_vertex_rows(problem_->functional->state_jvp(z, dz));
  }
  py::object bounds() const {
    if (problem_->bounds.lower.size() == 0) return py::none();
    return py::make_tuple(problem_->bounds.lower, problem_->bounds.upper);
  }
  // As Study::taylor_test (and tailor gradcheck): J(z + h dz) is only as accurate as the
  // equilibrium, so the forward solves are tightened to the round-off floor for the test and
  // put back afterwards. At z0 unless z is given; of the Hessian-vector products with hessian.
  py::dict taylor_test(std::optional<Vector> z, std::optional<unsigned> seed, std::optional<double> min_rate,
                       bool hessian) {
    if (z) check_size(*z, "z");
    if (hessian && !has_hessian_vector())
      throw std::invalid_argument(problem_->scene_source +
                                  ": this objective has no Hessian-vector products to test");
    TaylorTestOptions options = problem_->spec.gradcheck;
    if (seed) options.seed = *seed;
    if (min_rate) options.min_rate = *min_rate;
    const TaylorTestResult r = [&] {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(mutex_);
      NewtonOptions& newton = problem_->functional->newton_options();
      const NewtonOptions kept = newton;
      const double tighter = 1e-14 / newton.relative_tolerance;
      if (tighter < 1.0) {
        newton.relative_tolerance *= tighter;
        newton.absolute_tolerance *= tighter;
      }
      struct Restore {
        NewtonOptions& options;
        NewtonOptions kept;
        ~Restore() { options = kept; }
      } restore{newton, kept};
      const Vector& at = z ? *z : problem_->z0;
      return hessian ? taylor_test_hessian(*problem_->functional, at, options)
                     : tailor::taylor_test(*problem_->functional, at, options);
    }();
    // A design the functional cannot evaluate is the caller's error, as in value(z); a failure at
    // a step of the test is the test's result.
    if (r.status == TaylorStatus::evaluation_failed && r.rows.empty()) throw EvaluationError(r.message);
    return taylor_result_dict(r);
  }
  py::dict counters() const { return counters_dict(problem_->functional->counters()); }
  const InverseProblem& problem() const { return *problem_; }

 private:
  void check_size(const Vector& z, const char* name) const {
    if (z.size() != size())
      throw std::invalid_argument(problem_->scene_source + ": " + name + " has " + std::to_string(z.size()) +
                                  " entries, the design has " + std::to_string(size()));
  }
  // How many of a state's `model_dofs` DOFs are the vertices' (at its head): all of them, or with
  // quadratic elements those before the edge nodes'. Throws for states with other DOFs.
  Eigen::Index vertex_dofs(Eigen::Index model_dofs) const {
    const Eigen::Index n = problem_->setup.mesh.rest_positions.size();
    if (model_dofs == n || (problem_->setup.quadratic && model_dofs == problem_->setup.num_dofs())) return n;
    throw std::invalid_argument(problem_->scene_source + ": the model has " + std::to_string(model_dofs) +
                                " DOFs beyond the mesh's nodes; state products need a mesh-only state");
  }
  // Interleaved DOFs (x0 y0 z0 x1 ...) as one row per vertex.
  Eigen::MatrixXd as_vertex_rows(const Vector& x) const {
    const Eigen::MatrixXd& X = problem_->setup.mesh.rest_positions;
    vertex_dofs(x.size());
    return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        x.data(), X.rows(), X.cols());
  }
  std::unique_ptr<Study> study_;
  InverseProblem* problem_ = nullptr;
  // The GIL is released while J is evaluated: Python threads sharing a functional take turns.
  std::mutex mutex_;
};

}  // namespace

py::dict taylor_result_dict(const TaylorTestResult& r) {
  py::list rows;
  for (const TaylorRow& row : r.rows) {
    py::dict d;
    d["step"] = row.step;
    d["value"] = row.value;
    d["remainder0"] = row.remainder0;
    d["remainder1"] = row.remainder1;
    d["rate0"] = row.rate0;
    d["rate1"] = row.rate1;
    d["round_off"] = row.round_off;
    d["noise"] = row.noise;
    d["judged"] = row.judged;
    rows.append(d);
  }
  py::dict d;
  d["status"] = to_string(r.status);
  d["passed"] = r.passed();
  d["message"] = r.message;
  d["value"] = r.value;
  d["directional_derivative"] = r.directional_derivative;
  d["rate0"] = r.rate0;
  d["rate1"] = r.rate1;
  d["step"] = r.step;
  d["direction"] = r.direction;
  d["rows"] = rows;
  d["table"] = r.table();
  return d;
}

void check_design_size(const std::string& source, const Vector& v, int size, const char* name) {
  if (v.size() != size)
    throw std::invalid_argument(source + ": " + name + " has " + std::to_string(v.size()) +
                                " entries, the design has " + std::to_string(size));
}

py::dict counters_dict(const FunctionalCounters& c) {
  py::dict d;
  d["evaluations"] = c.evaluations;
  d["forward_solves"] = c.forward_solves;
  d["adjoint_solves"] = c.adjoint_solves;
  d["forward_seconds"] = c.forward_seconds;
  d["adjoint_seconds"] = c.adjoint_seconds;
  return d;
}

py::dict optimizer_dict(const OptimizerOptions& o) {
  py::dict d;
  d["backend"] = to_string(o.backend);
  d["max_iterations"] = o.max_iterations;
  d["gradient_tolerance"] = o.gradient_tolerance;
  d["objective_tolerance"] = o.objective_tolerance;
  d["step_tolerance"] = o.step_tolerance;
  d["time_limit"] = o.time_limit_seconds;
  d["curvature"] = to_string(o.curvature);
  return d;
}

void bind_functional(py::module_& m) {
  py::class_<Functional>(m, "Functional",
                         "The reduced functional J(z) of a scene's inverse problem (docs/python.md).")
      .def(py::init<const SceneDocument&>(), py::arg("scene"))
      .def_property_readonly("size", &Functional::size)
      .def("value", &Functional::value, py::arg("z"))
      .def("gradient", &Functional::gradient, py::arg("z"))
      .def("value_and_gradient", &Functional::value_and_gradient, py::arg("z"))
      .def_property_readonly("has_hessian_vector", &Functional::has_hessian_vector)
      .def("hessian_vector_product", &Functional::hessian_vector_product, py::arg("z"), py::arg("v"))
      .def_property_readonly("has_gauss_newton_vector", &Functional::has_gauss_newton_vector)
      .def("gauss_newton_vector_product", &Functional::gauss_newton_vector_product, py::arg("z"),
           py::arg("v"))
      .def("residuals", &Functional::residuals, py::arg("z"))
      .def("objective_terms", &Functional::objective_terms, py::arg("z"))
      .def("state", &Functional::state, py::arg("z"))
      .def("vjp", &Functional::vjp, py::arg("z"), py::arg("dL_du"))
      .def("jvp", &Functional::jvp, py::arg("z"), py::arg("dz"))
      .def_property_readonly("bounds", &Functional::bounds)
      .def_property_readonly("optimizer",
                             [](const Functional& f) { return optimizer_dict(f.problem().spec.optimizer); })
      .def_property_readonly("x0", [](const Functional& f) { return f.problem().z0; })
      .def_property_readonly("design_labels", [](const Functional& f) { return f.problem().design_labels; })
      .def(
          "design_values", [](const Functional& f, const Vector& z) { return f.problem().design_values(z); },
          py::arg("z"))
      .def(
          "youngs_modulus",
          [](const Functional& f, const Vector& z) { return f.problem().youngs_modulus(z); }, py::arg("z"))
      .def_property_readonly("truth",
                             [](const Functional& f) -> py::object {
                               if (f.problem().truth.size() == 0) return py::none();
                               return py::cast(f.problem().truth);
                             })
      .def_property_readonly("counters", &Functional::counters)
      // Views of the problem's mesh, kept alive by the functional.
      .def_property_readonly(
          "rest_positions",
          [](const Functional& f) -> const Eigen::MatrixXd& { return f.problem().setup.mesh.rest_positions; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "poisson_ratio",
          [](const Functional& f) -> const Eigen::VectorXd& { return f.problem().setup.poisson_ratio; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "elements",
          [](const Functional& f) -> const Eigen::MatrixXi& { return f.problem().setup.mesh.elements; },
          py::return_value_policy::reference_internal)
      .def("taylor_test", &Functional::taylor_test, py::arg("z") = py::none(), py::arg("seed") = py::none(),
           py::arg("min_rate") = py::none(), py::arg("hessian") = false);
}

}  // namespace tailor::python
