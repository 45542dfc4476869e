// The reduced functional of a rod scene's inverse problem: tailor._tailor.RodFunctional. J(z),
// dJ/dz, Hessian-vector and Gauss-Newton products, and the Taylor test are those `tailor run`
// and `tailor gradcheck` use on the scene (problems/rods/rod_inverse.hpp: the static adjoint
// with the exact Hessian). The state is the rods' vertex positions: state(z) gives their
// displacements from the drawn positions, one row per vertex in the scene's rod order, and vjp
// and jvp act on those rows; the edges' twist angles are state too but are not among them (a
// dL/du acts on positions only, and jvp leaves the twists out).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>

#include "bindings.hpp"
#include "problems/rods/rod_inverse.hpp"
#include "problems/scene_error.hpp"

namespace py = pybind11;

namespace tailor::python {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

class RodFunctional {
  void check_size(const Vector& z, const char* name) const {
    check_design_size(problem_->source, z, size(), name);
  }
  Eigen::MatrixXd vertex_rows(const Vector& x) const {
    RowMajor rows(num_vertices(), 3);
    for (std::size_t i = 0; i < position_dofs_.size(); ++i) rows.data()[i] = x[position_dofs_[i]];
    return rows;
  }

 public:
  explicit RodFunctional(const SceneDocument& doc) {
    const SceneFile& file = doc.file;
    if (!file.document.is_object() || !file.document.contains("inverse"))
      throw SceneError(file.source +
                       ": (top level): the scene has no \"inverse\" section (a reduced functional needs one; "
                       "see docs/rods.md)");
    problem_ = without_gil([&] { return build_rod_inverse(file.node(), file.name()); });
    for (const auto& rod : problem_->model.rods)
      for (int v = 0; v < rod->num_vertices(); ++v)
        for (int k = 0; k < 3; ++k) position_dofs_.push_back(rod->position_dof(v, k));
    rest_positions_ = vertex_rows(problem_->model.rest);
  }

  StaticFunctional& f() const { return *problem_->functional; }
  const RodInverseProblem& problem() const { return *problem_; }
  int size() const { return f().size(); }
  int num_vertices() const { return static_cast<int>(position_dofs_.size() / 3); }

  double value(const Vector& z) {
    check_size(z, "z");
    return locked(mutex_, [&] { return f().value(z); });
  }
  Vector gradient(const Vector& z) { return value_and_gradient(z).second; }
  std::pair<double, Vector> value_and_gradient(const Vector& z) {
    check_size(z, "z");
    return locked(mutex_, [&] {
      Vector g;
      const double v = f().value_and_gradient(z, g);
      return std::make_pair(v, g);
    });
  }
  bool has_hessian_vector() const { return f().has_hessian_vector(); }
  Vector hessian_vector_product(const Vector& z, const Vector& v) {
    check_size(z, "z");
    check_size(v, "v");
    return locked(mutex_, [&] { return f().hessian_vector(z, v); });
  }
  bool has_gauss_newton_vector() const { return f().has_gauss_newton_vector(); }
  Vector gauss_newton_vector_product(const Vector& z, const Vector& v) {
    check_size(z, "z");
    check_size(v, "v");
    if (!has_gauss_newton_vector())
      throw std::invalid_argument(problem_->source +
                                  ": this objective is not least squares (no Gauss-Newton products)");
    return locked(mutex_, [&] { return f().gauss_newton_vector(z, v); });
  }

  // The equilibrium at z: the vertices' displacements from the drawn positions (num_vertices x 3).
  Eigen::MatrixXd state(const Vector& z) {
    check_size(z, "z");
    return locked(mutex_, [&] {
      f().value(z);
      return vertex_rows(f().state() - problem_->model.rest);
    });
  }
  // (du/dz)^T dL_du by one adjoint solve, dL_du one row per vertex (num_vertices x 3).
  Vector vjp(const Vector& z, const Eigen::MatrixXd& dL_du) {
    check_size(z, "z");
    if (dL_du.rows() != num_vertices() || dL_du.cols() != 3)
      throw std::invalid_argument(problem_->source + ": dL_du has shape (" + std::to_string(dL_du.rows()) +
                                  ", " + std::to_string(dL_du.cols()) + "), the state (" +
                                  std::to_string(num_vertices()) + ", 3)");
    if (!dL_du.allFinite()) throw std::invalid_argument(problem_->source + ": dL_du has non-finite entries");
    const RowMajor rows = dL_du;
    return locked(mutex_, [&] {
      Vector w = Vector::Zero(problem_->model.model->num_dofs());
      for (std::size_t i = 0; i < position_dofs_.size(); ++i) w[position_dofs_[i]] = rows.data()[i];
      return f().state_vjp(z, w);
    });
  }
  // (du/dz) dz by one tangent solve, one row per vertex.
  Eigen::MatrixXd jvp(const Vector& z, const Vector& dz) {
    check_size(z, "z");
    check_size(dz, "dz");
    if (!dz.allFinite()) throw std::invalid_argument(problem_->source + ": dz has non-finite entries");
    return locked(mutex_, [&] { return vertex_rows(f().state_jvp(z, dz)); });
  }

  // Rod designs are unbounded (rod_inverse.cpp minimizes without bounds).
  py::object bounds() const { return py::none(); }
  py::dict taylor_test(std::optional<Vector> z, std::optional<unsigned> seed, std::optional<double> min_rate,
                       bool hessian) {
    if (z) check_size(*z, "z");
    if (hessian && !has_hessian_vector())
      throw std::invalid_argument(problem_->source +
                                  ": this objective has no Hessian-vector products to test");
    TaylorTestOptions options;
    options.seed = seed.value_or(problem_->spec.seed);
    if (min_rate) options.min_rate = *min_rate;
    const TaylorTestResult r = locked(mutex_, [&] {
      const Vector& at = z ? *z : problem_->z0;
      return hessian ? taylor_test_hessian(f(), at, options) : tailor::taylor_test(f(), at, options);
    });
    if (r.status == TaylorStatus::evaluation_failed && r.rows.empty()) throw EvaluationError(r.message);
    return taylor_result_dict(r);
  }
  py::dict counters() const { return counters_dict(f().counters()); }
  // The drawn vertex positions, one row per vertex (the rows of state, vjp and jvp).
  const Eigen::MatrixXd& rest_positions() const { return rest_positions_; }

 private:
  std::unique_ptr<RodInverseProblem> problem_;
  std::vector<int> position_dofs_;  // vertex v, coordinate k at 3 v + k
  Eigen::MatrixXd rest_positions_;
  std::mutex mutex_;
};

}  // namespace

void bind_rod_functional(py::module_& m) {
  py::class_<RodFunctional>(m, "RodFunctional",
                            "The reduced functional J(z) of a rod scene's inverse problem (docs/python.md).")
      .def(py::init<const SceneDocument&>(), py::arg("scene"))
      .def_property_readonly("size", &RodFunctional::size)
      .def("value", &RodFunctional::value, py::arg("z"))
      .def("gradient", &RodFunctional::gradient, py::arg("z"))
      .def("value_and_gradient", &RodFunctional::value_and_gradient, py::arg("z"))
      .def_property_readonly("has_hessian_vector", &RodFunctional::has_hessian_vector)
      .def("hessian_vector_product", &RodFunctional::hessian_vector_product, py::arg("z"), py::arg("v"))
      .def_property_readonly("has_gauss_newton_vector", &RodFunctional::has_gauss_newton_vector)
      .def("gauss_newton_vector_product", &RodFunctional::gauss_newton_vector_product, py::arg("z"),
           py::arg("v"))
      .def("state", &RodFunctional::state, py::arg("z"))
      .def("vjp", &RodFunctional::vjp, py::arg("z"), py::arg("dL_du"))
      .def("jvp", &RodFunctional::jvp, py::arg("z"), py::arg("dz"))
      .def_property_readonly("bounds", &RodFunctional::bounds)
      .def_property_readonly(
          "optimizer", [](const RodFunctional& f) { return optimizer_dict(f.problem().spec.optimizer); })
      .def_property_readonly("x0", [](const RodFunctional& f) { return f.problem().z0; })
      .def_property_readonly("design_labels", [](const RodFunctional& f) { return f.problem().labels; })
      .def_property_readonly("counters", &RodFunctional::counters)
      .def_property_readonly("rest_positions", &RodFunctional::rest_positions,
                             py::return_value_policy::reference_internal)
      .def("taylor_test", &RodFunctional::taylor_test, py::arg("z") = py::none(),
           py::arg("seed") = py::none(), py::arg("min_rate") = py::none(), py::arg("hessian") = false);
}

}  // namespace tailor::python
