// The reduced functional of a meshless scene's inverse problem: tailor._tailor.MeshlessFunctional.
// J(z), dJ/dz, Hessian-vector and Gauss-Newton products and the Taylor test are those of
// `tailor run` and `tailor gradcheck` on the scene (load_meshless_design,
// problems/meshless/meshless_runs.hpp: the static adjoint on the MLS node coefficients). The
// state is the MLS field's displacement at the nodes, u(X_b) = sum_a phi_a(X_b) (x_a - X_a), one
// row per node: a linear map N of the coefficients (meshless_node_values), so vjp applies N^T
// before the adjoint solve and jvp applies N after the tangent solve.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <mutex>
#include <optional>

#include "bindings.hpp"
#include "problems/meshless/meshless_runs.hpp"
#include "problems/scene_node.hpp"

namespace py = pybind11;

namespace tailor::python {
namespace {

class MeshlessFunctional {
  void check_size(const Vector& z, const char* name) const { check_design_size(source_, z, size(), name); }
  void check_finite(const Eigen::MatrixXd& a, const char* name) const {
    if (!a.allFinite()) throw std::invalid_argument(source_ + ": " + name + " has non-finite entries");
  }
 public:
  explicit MeshlessFunctional(const SceneDocument& doc) : source_(doc.file.source) {
    MeshlessVerbOptions options;
    options.name = doc.file.name();
    options.directory = doc.file.directory();
    design_ = without_gil([&] { return load_meshless_design(doc.file.node(), options, "functional()", nullptr); });
    node_values_ = meshless_node_values(scene());
  }

  const MeshlessScene& scene() const { return *design_.scene; }
  StaticFunctional& f() const { return *design_.inverse->functional; }
  const MeshlessInverse& inverse() const { return *design_.inverse; }
  const std::string& source() const { return source_; }
  int size() const { return f().size(); }
  int num_nodes() const { return scene().num_nodes(); }

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
  Vector hessian_vector_product(const Vector& z, const Vector& v) {
    check_size(z, "z");
    check_size(v, "v");
    return locked(mutex_, [&] { return f().hessian_vector(z, v); });
  }
  Vector gauss_newton_vector_product(const Vector& z, const Vector& v) {
    check_size(z, "z");
    check_size(v, "v");
    return locked(mutex_, [&] { return f().gauss_newton_vector(z, v); });
  }
  // The displacement u(X_b) at the nodes at the equilibrium of z (num_nodes x 3).
  Eigen::MatrixXd state(const Vector& z) {
    check_size(z, "z");
    return locked(mutex_, [&] {
      f().value(z);
      return as_point_rows(node_values_ * (f().state() - scene().rest()));
    });
  }
  Vector vjp(const Vector& z, const Eigen::MatrixXd& dL_du) {
    check_size(z, "z");
    if (dL_du.rows() != num_nodes() || dL_du.cols() != 3)
      throw std::invalid_argument(source_ + ": dL_du has shape (" + std::to_string(dL_du.rows()) + ", " +
                                  std::to_string(dL_du.cols()) + "), the state (" + std::to_string(num_nodes()) + ", 3)");
    check_finite(dL_du, "dL_du");
    const Vector w = node_values_.transpose() * as_interleaved(dL_du);
    return locked(mutex_, [&] { return f().state_vjp(z, w); });
  }
  Eigen::MatrixXd jvp(const Vector& z, const Vector& dz) {
    check_size(z, "z");
    check_size(dz, "dz");
    check_finite(dz, "dz");
    return locked(mutex_, [&] { return as_point_rows(node_values_ * f().state_jvp(z, dz)); });
  }
  // The fields at the equilibrium of z (MeshlessFields), copied into NumPy arrays.
  py::dict fields(const Vector& z) {
    check_size(z, "z");
    const MeshlessFields m = locked(mutex_, [&] {
      f().value(z);
      return meshless_fields(scene(), node_values_, f().state(), f().parameters());
    });
    py::dict d;
    d["rest_positions"] = m.rest_positions;
    d["displacement"] = m.displacement;
    d["positions"] = m.positions;
    d["coefficient_displacement"] = m.coefficient_displacement;
    d["youngs_modulus"] = m.youngs_modulus;
    d["samples"] = m.samples;
    d["sample_displacement"] = m.sample_displacement;
    return d;
  }
  py::dict taylor_test(std::optional<Vector> z, std::optional<unsigned> seed, std::optional<double> min_rate,
                       bool hessian) {
    if (z) check_size(*z, "z");
    TaylorTestOptions options;
    options.seed = seed.value_or(scene().spec.inverse->seed);
    if (min_rate) options.min_rate = *min_rate;
    const TaylorTestResult r = locked(mutex_, [&] {
      const Vector& at = z ? *z : inverse().z0;
      return hessian ? taylor_test_hessian(f(), at, options) : tailor::taylor_test(f(), at, options);
    });
    if (r.status == TaylorStatus::evaluation_failed && r.rows.empty()) throw EvaluationError(r.message);
    return taylor_result_dict(r);
  }

 private:
  std::string source_;
  MeshlessDesign design_;
  SparseMatrix node_values_;  // 3n x 3n: coefficients -> the field's values at the nodes
  std::mutex mutex_;
};

}  // namespace

void bind_meshless_functional(py::module_& m) {
  using F = MeshlessFunctional;
  py::class_<F>(m, "MeshlessFunctional",
                "The reduced functional J(z) of a meshless scene's inverse problem (docs/python.md).")
      .def(py::init<const SceneDocument&>(), py::arg("scene"))
      .def_property_readonly("size", &F::size)
      .def("value", &F::value, py::arg("z"))
      .def("gradient", [](F& f, const Vector& z) { return f.value_and_gradient(z).second; }, py::arg("z"))
      .def("value_and_gradient", &F::value_and_gradient, py::arg("z"))
      .def_property_readonly("has_hessian_vector", [](const F& f) { return f.f().has_hessian_vector(); })
      .def("hessian_vector_product", &F::hessian_vector_product, py::arg("z"), py::arg("v"))
      .def_property_readonly("has_gauss_newton_vector", [](const F& f) { return f.f().has_gauss_newton_vector(); })
      .def("gauss_newton_vector_product", &F::gauss_newton_vector_product, py::arg("z"), py::arg("v"))
      .def("state", &F::state, py::arg("z"))
      .def("vjp", &F::vjp, py::arg("z"), py::arg("dL_du"))
      .def("jvp", &F::jvp, py::arg("z"), py::arg("dz"))
      .def("fields", &F::fields, py::arg("z"))
      .def_property_readonly("optimizer", [](const F& f) { return optimizer_dict(f.scene().spec.inverse->optimizer); })
      .def_property_readonly("x0", [](const F& f) { return f.inverse().z0; })
      .def_property_readonly("design_labels", [](const F& f) { return f.inverse().labels; })
      .def_property_readonly("rest_positions", [](const F& f) { return f.scene().sampling.nodes; })
      .def_property_readonly("counters", [](const F& f) { return counters_dict(f.f().counters()); })
      .def("taylor_test", &F::taylor_test, py::arg("z") = py::none(), py::arg("seed") = py::none(),
           py::arg("min_rate") = py::none(), py::arg("hessian") = false);
}

}  // namespace tailor::python
