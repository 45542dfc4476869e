// The reduced functional of a dynamic scene's trajectory objective: tailor._tailor.DynamicFunctional.
// J(z) and dJ/dz are those `tailor gradcheck` tests on the scene (problems/fem/dynamic_commands.hpp:
// per-element log E and log density, and Rayleigh's alpha and beta, through the time-dependent
// adjoint). The state is the trajectory: state(z) gives the displacements of every stored state
// n = 0 ... N from the rest positions, shape (N + 1, num_vertices, dim), and vjp(z, dL_dU) the
// design gradient of any scalar L of it, given dL/dU of the same shape, by one backward pass over
// the same trajectory (TransientFunctional::objective_gradient with PositionCotangents), and
// jvp(z, dz) the trajectory's directional derivative of that shape by one forward tangent pass
// through the steps (TransientFunctional::trajectory_jvp), its exact transpose.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>

#include "bindings.hpp"
#include "problems/fem/dynamic_commands.hpp"
#include "problems/scene_error.hpp"

namespace py = pybind11;

namespace tailor::python {
namespace {

class DynamicFunctional {
  void check_size(const Vector& z, const char* name) const { check_design_size(source_, z, size(), name); }

 public:
  explicit DynamicFunctional(const SceneDocument& doc) : source_(doc.file.source) {
    const Scene scene = parse_mesh_scene(doc);
    if (!scene.dynamics || !scene.dynamics->objective)
      throw SceneError(source_ +
                       ": dynamics.objective: a dynamic scene's functional() needs its trajectory "
                       "objective (docs/scenes.md)");
    design_ = without_gil([&] { return build_dynamic_design(scene); });
  }

  TransientFunctional& f() const { return *design_->functional; }
  const DynamicDesign& design() const { return *design_; }
  int size() const { return f().size(); }

  double value(const Vector& z) {
    check_size(z, "z");
    return locked(mutex_, [&] { return f().value(z); });
  }
  std::pair<double, Vector> value_and_gradient(const Vector& z) {
    check_size(z, "z");
    return locked(mutex_, [&] {
      Vector g;
      const double v = f().value_and_gradient(z, g);
      return std::make_pair(v, g);
    });
  }
  Vector gradient(const Vector& z) { return value_and_gradient(z).second; }

  // Displacements of the stored states from the rest positions: (N + 1, num_vertices, dim).
  py::array_t<double> state(const Vector& z) {
    check_size(z, "z");
    const Eigen::Index n = rest().size();
    const Matrix rows = locked(mutex_, [&] {
      f().value(z);
      const std::vector<DynamicState>& states = f().stored_states();
      Matrix out(static_cast<Eigen::Index>(states.size()), n);
      for (std::size_t k = 0; k < states.size(); ++k)
        out.row(static_cast<Eigen::Index>(k)) = (states[k].x.head(n) - rest()).transpose();
      return out;
    });
    const Eigen::MatrixXd& X = design_->scene_model.setup.mesh.rest_positions;
    py::array_t<double> out({static_cast<py::ssize_t>(rows.rows()), static_cast<py::ssize_t>(X.rows()),
                             static_cast<py::ssize_t>(X.cols())});
    double* data = out.mutable_data();
    for (Eigen::Index k = 0; k < rows.rows(); ++k)
      for (Eigen::Index i = 0; i < n; ++i) data[k * n + i] = rows(k, i);
    return out;
  }

  // (dU/dz)^T dL_dU, dL_dU with the shape of state(z).
  Vector vjp(const Vector& z, const py::array_t<double, py::array::c_style | py::array::forcecast>& dL_dU) {
    check_size(z, "z");
    const Eigen::MatrixXd& X = design_->scene_model.setup.mesh.rest_positions;
    const Eigen::Index n = rest().size(), states = design_->steps + 1;
    if (dL_dU.ndim() != 3 || dL_dU.shape(0) != states || dL_dU.shape(1) != X.rows() ||
        dL_dU.shape(2) != X.cols())
      throw std::invalid_argument(source_ + ": dL_dU has shape " + shape_text(dL_dU) + ", the trajectory (" +
                                  std::to_string(states) + ", " + std::to_string(X.rows()) + ", " +
                                  std::to_string(X.cols()) + ")");
    const int dofs = design_->scene_model.model->num_dofs();
    Matrix weights = Matrix::Zero(states, dofs);
    const double* data = dL_dU.data();
    for (Eigen::Index k = 0; k < states; ++k)
      for (Eigen::Index i = 0; i < n; ++i) weights(k, i) = data[k * n + i];
    if (!weights.allFinite()) throw std::invalid_argument(source_ + ": dL_dU has non-finite entries");
    auto cotangents = std::make_shared<PositionCotangents>(std::move(weights));
    return locked(mutex_, [&] { return f().objective_gradient(z, cotangents); });
  }

  // (dU/dz) dz, of the shape of state(z).
  py::array_t<double> jvp(const Vector& z, const Vector& dz) {
    check_size(z, "z");
    check_size(dz, "dz");
    if (!dz.allFinite()) throw std::invalid_argument(source_ + ": dz has non-finite entries");
    const Eigen::Index n = rest().size();
    const Matrix rows = locked(mutex_, [&] { return Matrix(f().trajectory_jvp(z, dz).leftCols(n)); });
    const Eigen::MatrixXd& X = design_->scene_model.setup.mesh.rest_positions;
    py::array_t<double> out({static_cast<py::ssize_t>(rows.rows()), static_cast<py::ssize_t>(X.rows()),
                             static_cast<py::ssize_t>(X.cols())});
    double* data = out.mutable_data();
    for (Eigen::Index k = 0; k < rows.rows(); ++k)
      for (Eigen::Index i = 0; i < n; ++i) data[k * n + i] = rows(k, i);
    return out;
  }

  py::dict taylor_test(std::optional<Vector> z, std::optional<unsigned> seed,
                       std::optional<double> min_rate) {
    if (z) check_size(*z, "z");
    TaylorTestOptions options;
    if (seed) options.seed = *seed;
    if (min_rate) options.min_rate = *min_rate;
    const TaylorTestResult r =
        locked(mutex_, [&] { return tailor::taylor_test(f(), z ? *z : design_->z0, options); });
    if (r.status == TaylorStatus::evaluation_failed && r.rows.empty()) throw EvaluationError(r.message);
    return taylor_result_dict(r);
  }
  py::dict counters() const { return counters_dict(f().counters()); }

 private:
  const Vector& rest() const { return design_->scene_model.rest; }
  static std::string shape_text(const py::array& a) {
    std::string text = "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
    return text + (a.ndim() == 1 ? ",)" : ")");
  }

  std::string source_;
  std::unique_ptr<DynamicDesign> design_;
  std::mutex mutex_;
};

}  // namespace

void bind_dynamic_functional(py::module_& m) {
  py::class_<DynamicFunctional>(
      m, "DynamicFunctional",
      "The reduced functional J(z) of a dynamic scene's trajectory objective (docs/python.md).")
      .def(py::init<const SceneDocument&>(), py::arg("scene"))
      .def_property_readonly("size", &DynamicFunctional::size)
      .def("value", &DynamicFunctional::value, py::arg("z"))
      .def("gradient", &DynamicFunctional::gradient, py::arg("z"))
      .def("value_and_gradient", &DynamicFunctional::value_and_gradient, py::arg("z"))
      .def("state", &DynamicFunctional::state, py::arg("z"))
      .def("vjp", &DynamicFunctional::vjp, py::arg("z"), py::arg("dL_dU"))
      .def("jvp", &DynamicFunctional::jvp, py::arg("z"), py::arg("dz"))
      .def_property_readonly("x0", [](const DynamicFunctional& f) { return f.design().z0; })
      .def_property_readonly("design_labels", [](const DynamicFunctional& f) { return f.design().labels; })
      .def_property_readonly("counters", &DynamicFunctional::counters)
      .def_property_readonly(
          "rest_positions",
          [](const DynamicFunctional& f) -> const Eigen::MatrixXd& {
            return f.design().scene_model.setup.mesh.rest_positions;
          },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "elements",
          [](const DynamicFunctional& f) -> const Eigen::MatrixXi& {
            return f.design().scene_model.setup.mesh.elements;
          },
          py::return_value_policy::reference_internal)
      .def("taylor_test", &DynamicFunctional::taylor_test, py::arg("z") = py::none(),
           py::arg("seed") = py::none(), py::arg("min_rate") = py::none());
}

}  // namespace tailor::python
