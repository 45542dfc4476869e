#include "forward/dynamics/example_damping_setup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "forward/dynamics/damping_examples.hpp"

namespace tailor {

ExampleDampingTerms add_example_damping(Model& model, const Mesh& mesh,
                                        std::shared_ptr<const MassOperator> mass, const Vector& p,
                                        const ExampleDampingSetup& setup) {
  ParameterLayout& layout = model.parameter_layout();
  for (const char* block : {"youngs_modulus", "poisson_ratio", "density"})
    if (!layout.contains(block))
      throw std::invalid_argument(std::string("add_example_damping: no '") + block + "' block");
  if (!mass) throw std::invalid_argument("add_example_damping: no mass operator");
  if (p.size() < layout.size())
    throw std::invalid_argument("add_example_damping: p has " + std::to_string(p.size()) +
                                " entries, the layout " + std::to_string(layout.size()));
  if (setup.examples.empty()) throw std::invalid_argument("add_example_damping: no examples");
  const int n = model.num_dofs();
  ExampleDampingTerms terms;
  terms.alpha_offset = layout.add("rayleigh_alpha", 1);
  terms.beta_offset = layout.add("rayleigh_beta", 1);
  int controls = 0;
  for (const auto& e : setup.examples) controls += static_cast<int>(e.curve.knots.size());
  terms.curve_offset = layout.add("example_damping", controls);

  auto base = std::make_unique<RayleighDamping>(mesh, mass, terms.alpha_offset, terms.beta_offset,
                                                layout.at("youngs_modulus").offset,
                                                layout.at("poisson_ratio").offset);
  Vector p_full = Vector::Zero(layout.size());
  const Eigen::Index known = std::min<Eigen::Index>(p.size(), layout.size());
  p_full.head(known) = p.head(known);
  const SparseMatrix K = base->rest_stiffness(p_full);
  const SparseMatrix M = mass->matrix(p_full);
  const SparseMatrix& S = model.elimination().basis();

  const auto r = static_cast<Eigen::Index>(setup.examples.size());
  Matrix raw(n, r);
  terms.eigenvalues = Vector::Constant(r, std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index i = 0; i < r; ++i) {
    const DampingExampleSpec& e = setup.examples[static_cast<std::size_t>(i)];
    const std::string what = "damping example " + std::to_string(i);
    switch (e.source) {
      case DampingExampleSpec::Source::displacement:
        if (e.field.size() != n)
          throw std::invalid_argument(what + ": the displacement has " + std::to_string(e.field.size()) +
                                      " entries, the model " + std::to_string(n) + " DOFs");
        raw.col(i) = e.field;
        break;
      case DampingExampleSpec::Source::eigenmode: {
        if (e.mode < 0 || e.mode >= S.cols() - 1)
          throw std::invalid_argument(what + ": mode index " + std::to_string(e.mode) + " is out of range");
        Vector lambda;
        raw.col(i) = eigenmode_examples(K, M, S, {e.mode}, &lambda).col(0);
        terms.eigenvalues[i] = lambda[0];
        break;
      }
      case DampingExampleSpec::Source::static_response:
        if (e.field.size() != n)
          throw std::invalid_argument(what + ": the load has " + std::to_string(e.field.size()) +
                                      " entries, the model " + std::to_string(n) + " DOFs");
        raw.col(i) = static_response_examples(K, S, Matrix(e.field)).col(0);
        break;
    }
  }
  const Matrix U = mass_orthonormalize(raw, M, setup.orthogonality_tolerance);
  Vector omega(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const double lambda = U.col(i).dot(K * U.col(i));
    if (!(lambda > 0.0))
      throw std::invalid_argument("damping example " + std::to_string(i) +
                                  " has no stiffness (a rigid motion?)");
    omega[i] = std::sqrt(lambda);
  }
  Vector rest(n);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    rest.segment(mesh.dim() * v, mesh.dim()) = mesh.rest_positions.row(v).transpose();
  std::vector<DampingCurve> curves;
  for (const auto& e : setup.examples) curves.push_back(e.curve);
  terms.damping = &model.add(std::make_unique<ExampleDamping>(
      std::move(base), M, U, omega, rest, std::move(curves), terms.curve_offset, setup.amplitude_smoothing));
  return terms;
}

}  // namespace tailor
