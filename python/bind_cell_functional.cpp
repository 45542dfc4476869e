// The reduced functional of a periodic cell's density design: tailor._tailor.CellFunctional.
// J(z) and dJ/dz are those `tailor run` minimizes on the scene (problems/metamaterial/
// cell_design.hpp: per-element density z in [0, 1], filtered, projected at the first stage's
// beta, SIMP moduli, the cell problems, J(C^H) through LinearCell's self-adjoint contraction).
// The state is the cells' periodic fluctuations: for each unit macro strain eps_I (Voigt order,
// docs/homogenization.md) the displacement u~_I = x_I - (X + eps_I X) of the equilibrium x_I,
// shape (voigt_size, num_vertices, dim). With the periodic stiffness K = S^T K(E) S (S the
// periodic elimination, the same for every load case) and the material linear in E,
//   K du~_I = -S^T (dK/dE dE) (x_I - X)                    (tangent, one back-solve per case)
//   dL/dE  = -sum_I lambda_I^T (dK/dE) (x_I - X),  K lambda_I = S^T dL/du~_I   (adjoint)
// then through SIMP, the projection and the filter as CellDesignFunctional chains dJ/dE. The
// products are LinearCell's (state_tangent and its transpose), through the factor of the
// functional's last solve at the same design.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <random>

#include "bindings.hpp"
#include "problems/homogenization/cell_scene.hpp"
#include "problems/metamaterial/metamaterial_scene.hpp"
#include "problems/scene_error.hpp"

namespace py = pybind11;

namespace tailor::python {
namespace {

using Cases = py::array_t<double, py::array::c_style | py::array::forcecast>;

class CellFunctional {
  void check_size(const Vector& z, const char* name) const { check_design_size(source_, z, size(), name); }

 public:
  explicit CellFunctional(const SceneDocument& doc) : source_(doc.file.source) {
    const SceneFile& file = doc.file;
    scene_ = parse_cell_scene(file.node(), file.directory());
    scene_.name = file.name();
    if (!scene_.has_design)
      throw SceneError(source_ +
                       ": (top level): the periodic cell has no \"design\" section (functional() needs one; "
                       "see docs/homogenization.md)");
    spec_ = parse_metamaterial_design(file.node(), scene_);
    without_gil([&] {
      cell_ = std::make_shared<LinearCell>(scene_.cell, scene_.plane);
      functional_ = std::make_unique<CellDesignFunctional>(cell_, spec_.material, spec_.filter_radius,
                                                           spec_.objective);
      functional_->set_projection(spec_.projection_betas.front());
      return 0;
    });
    // The initial design as `tailor run` draws it (problems/metamaterial/metamaterial_scene.cpp).
    const int ne = size();
    z0_.resize(ne);
    std::mt19937 rng(spec_.seed);
    std::uniform_real_distribution<double> noise(-1.0, 1.0);
    for (int e = 0; e < ne; ++e)
      z0_[e] = std::clamp(spec_.initial_density[static_cast<std::size_t>(scene_.element_phase[e])] +
                              spec_.perturbation * noise(rng),
                          0.0, 1.0);
    for (int e = 0; e < ne; ++e) labels_.push_back("density[" + std::to_string(e) + "]");
  }

  int size() const { return cell_->num_elements(); }
  int dim() const { return scene_.cell.dim(); }
  int cases() const { return voigt_size(dim()); }
  int num_vertices() const { return scene_.cell.mesh.num_vertices(); }
  CellDesignFunctional& f() const { return *functional_; }

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
  // C^H at z (Voigt, voigt_size x voigt_size).
  Matrix stiffness(const Vector& z) {
    check_size(z, "z");
    return locked(mutex_, [&] {
      f().value(z);
      return Matrix(f().last().stiffness);
    });
  }
  Vector youngs_modulus(const Vector& z) {
    check_size(z, "z");
    return f().youngs_moduli(f().densities(z));
  }
  std::pair<double, Vector> volume_fraction(const Vector& z) {
    check_size(z, "z");
    Vector g;
    const double v = f().volume_fraction(z, &g);
    return {v, g};
  }

  py::array_t<double> state(const Vector& z) {
    check_size(z, "z");
    const std::vector<Vector> u = locked(mutex_, [&] {
      solve(z);
      std::vector<Vector> out(static_cast<std::size_t>(cases()));
      for (int I = 0; I < cases(); ++I) out[I] = fluctuation(I);
      return out;
    });
    return to_cases(u);
  }

  // (du~/dz) dz, shape (voigt_size, num_vertices, dim).
  py::array_t<double> jvp(const Vector& z, const Vector& dz) {
    check_size(z, "z");
    check_size(dz, "dz");
    if (!dz.allFinite()) throw std::invalid_argument(source_ + ": dz has non-finite entries");
    const std::vector<Vector> du = locked(mutex_, [&] {
      solve(z);
      const Vector dE = modulus_slope(z).cwiseProduct(f().filter().apply(dz));
      std::vector<Vector> out(static_cast<std::size_t>(cases()));
      for (int I = 0; I < cases(); ++I) out[I] = cell_->state_tangent(I, dE);
      return out;
    });
    return to_cases(du);
  }

  // (du~/dz)^T dL_du, dL_du of the shape of state(z).
  Vector vjp(const Vector& z, const Cases& dL_du) {
    check_size(z, "z");
    const int m = cases(), nv = num_vertices(), d = dim();
    if (dL_du.ndim() != 3 || dL_du.shape(0) != m || dL_du.shape(1) != nv || dL_du.shape(2) != d)
      throw std::invalid_argument(source_ + ": dL_du has shape " + shape_text(dL_du) + ", the state (" +
                                  std::to_string(m) + ", " + std::to_string(nv) + ", " + std::to_string(d) + ")");
    const Eigen::Index n = static_cast<Eigen::Index>(nv) * d;
    std::vector<Vector> w(static_cast<std::size_t>(m));
    for (int I = 0; I < m; ++I) w[I] = Eigen::Map<const Vector>(dL_du.data() + I * n, n);
    for (const Vector& wi : w)
      if (!wi.allFinite()) throw std::invalid_argument(source_ + ": dL_du has non-finite entries");
    return locked(mutex_, [&] {
      solve(z);
      Vector dL_dE = Vector::Zero(size());
      for (int I = 0; I < m; ++I) dL_dE += cell_->state_tangent_transpose(I, w[I]);
      return Vector(f().filter().apply_transpose(modulus_slope(z).cwiseProduct(dL_dE)));
    });
  }

  py::dict taylor_test(std::optional<Vector> z, std::optional<unsigned> seed, std::optional<double> min_rate) {
    if (z) check_size(*z, "z");
    TaylorTestOptions options;
    options.seed = seed.value_or(spec_.seed);
    if (min_rate) options.min_rate = *min_rate;
    const TaylorTestResult r = locked(mutex_, [&] { return tailor::taylor_test(f(), z ? *z : z0_, options); });
    if (r.status == TaylorStatus::evaluation_failed && r.rows.empty()) throw EvaluationError(r.message);
    return taylor_result_dict(r);
  }
  py::dict counters() const { return counters_dict(f().counters()); }

  const Vector& z0() const { return z0_; }
  const std::vector<std::string>& labels() const { return labels_; }
  const MetamaterialDesignSpec& spec() const { return spec_; }
  const Mesh& mesh() const { return scene_.cell.mesh; }

 private:
  // The cell problems solved at z: the shared LinearCell keeps the states and the factor of its
  // last solve, which another call (a Taylor test, a value at another design) may have moved.
  void solve(const Vector& z) {
    const Vector& solved = cell_->solved_youngs_modulus();
    const Vector E = f().youngs_moduli(f().densities(z));
    if (solved.size() == E.size() && solved == E) return;
    f().value(z);
  }
  Vector fluctuation(int I) const { return f().last().states[I] - macro_offset(scene_.cell, unit_macro_strain(dim(), I)); }

  // dE/drho_e dH/drho~_e per element at z: SIMP (E_min + rho^p (E_0 - E_min), rho clamped to
  // [0, 1]) after the Heaviside projection of Wang, Lazarov & Sigmund 2011 (eq. 9), as
  // CellDesignFunctional chains them.
  Vector modulus_slope(const Vector& z) const {
    const Vector filtered = f().filter().apply(z), rho = f().densities(z);
    const SimpMaterial& mat = spec_.material;
    const double beta = f().projection();
    Vector slope(size());
    for (int e = 0; e < size(); ++e) {
      const double r = std::clamp(rho[e], 0.0, 1.0);
      double projection = 1.0;
      if (beta != 0.0) {
        const double th = std::tanh(beta * (filtered[e] - 0.5));
        projection = beta * (1.0 - th * th) / (2.0 * std::tanh(0.5 * beta));
      }
      slope[e] = mat.penalty * std::pow(r, mat.penalty - 1.0) * (mat.youngs_modulus - mat.min_youngs_modulus) *
                 projection;
    }
    return slope;
  }
  py::array_t<double> to_cases(const std::vector<Vector>& u) const {
    const int m = cases(), nv = num_vertices(), d = dim();
    py::array_t<double> out({m, nv, d});
    double* data = out.mutable_data();
    for (int I = 0; I < m; ++I) std::copy(u[I].data(), u[I].data() + u[I].size(), data + I * nv * d);
    return out;
  }
  static std::string shape_text(const py::array& a) {
    std::string text = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) text += (k ? ", " : "") + std::to_string(a.shape(k));
    return text + (a.ndim() == 1 ? ",)" : ")");
  }

  std::string source_;
  CellScene scene_;
  MetamaterialDesignSpec spec_;
  std::shared_ptr<LinearCell> cell_;
  std::unique_ptr<CellDesignFunctional> functional_;
  Vector z0_;
  std::vector<std::string> labels_;
  // The products' model and the evaluation they were made at.
  std::mutex mutex_;
};

}  // namespace

void bind_cell_functional(py::module_& m) {
  py::class_<CellFunctional>(m, "CellFunctional",
                             "The reduced functional J(z) of a periodic cell's density design (docs/python.md).")
      .def(py::init<const SceneDocument&>(), py::arg("scene"))
      .def_property_readonly("size", &CellFunctional::size)
      .def("value", &CellFunctional::value, py::arg("z"))
      .def("gradient", &CellFunctional::gradient, py::arg("z"))
      .def("value_and_gradient", &CellFunctional::value_and_gradient, py::arg("z"))
      .def("state", &CellFunctional::state, py::arg("z"))
      .def("vjp", &CellFunctional::vjp, py::arg("z"), py::arg("dL_du"))
      .def("jvp", &CellFunctional::jvp, py::arg("z"), py::arg("dz"))
      .def("stiffness", &CellFunctional::stiffness, py::arg("z"))
      .def("youngs_modulus", &CellFunctional::youngs_modulus, py::arg("z"))
      .def("volume_fraction", &CellFunctional::volume_fraction, py::arg("z"))
      .def_property_readonly("max_volume_fraction",
                             [](const CellFunctional& f) { return f.spec().max_volume_fraction; })
      .def_property_readonly("bounds",
                             [](const CellFunctional& f) {
                               return std::make_pair(Vector(Vector::Zero(f.size())), Vector(Vector::Ones(f.size())));
                             })
      .def_property_readonly("optimizer", [](const CellFunctional& f) { return optimizer_dict(f.spec().optimizer); })
      .def_property_readonly("x0", &CellFunctional::z0)
      .def_property_readonly("design_labels", &CellFunctional::labels)
      .def_property_readonly("counters", &CellFunctional::counters)
      .def_property_readonly(
          "rest_positions", [](const CellFunctional& f) -> const Eigen::MatrixXd& { return f.mesh().rest_positions; },
          py::return_value_policy::reference_internal)
      .def_property_readonly(
          "elements", [](const CellFunctional& f) -> const Eigen::MatrixXi& { return f.mesh().elements; },
          py::return_value_policy::reference_internal)
      .def("taylor_test", &CellFunctional::taylor_test, py::arg("z") = py::none(), py::arg("seed") = py::none(),
           py::arg("min_rate") = py::none());
}

}  // namespace tailor::python
