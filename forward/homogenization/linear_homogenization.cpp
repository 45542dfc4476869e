#include "forward/homogenization/linear_homogenization.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

#include "forward/core/assembler.hpp"
#include "forward/core/timing.hpp"
#include "forward/fem/elastic_term.hpp"

namespace tailor {

int voigt_size(int dim) { return dim == 2 ? 3 : 6; }

Matrix unit_macro_strain(int dim, int voigt_index) {
  static constexpr int kPairs2[3][2] = {{0, 0}, {1, 1}, {0, 1}};
  static constexpr int kPairs3[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
  if ((dim != 2 && dim != 3) || voigt_index < 0 || voigt_index >= voigt_size(dim))
    throw std::invalid_argument("unit_macro_strain: bad dimension or Voigt index");
  const int i = dim == 2 ? kPairs2[voigt_index][0] : kPairs3[voigt_index][0];
  const int j = dim == 2 ? kPairs2[voigt_index][1] : kPairs3[voigt_index][1];
  Matrix H = Matrix::Zero(dim, dim);
  // Engineering shear: gamma_ij = 1 means eps_ij = eps_ji = 1/2.
  if (i == j) {
    H(i, i) = 1.0;
  } else {
    H(i, j) = H(j, i) = 0.5;
  }
  return H;
}

LinearCell::LinearCell(PeriodicCell cell, PlaneMode mode) : cell_(std::move(cell)), mode_(mode) {
  const int dim = cell_.dim();
  if (mode_ == PlaneMode::plane_stress && dim != 2)
    throw std::invalid_argument("LinearCell: plane stress applies to 2D cells only");
  const int ne = num_elements();
  model_ = std::make_unique<Model>(dim * cell_.mesh.num_vertices());
  model_->parameter_layout().add("youngs_modulus", ne);
  model_->parameter_layout().add("poisson_ratio", ne);
  if (dim == 2) {
    elastic_ = &model_->add(std::make_unique<ElasticTerm<2>>(
        cell_.mesh, std::shared_ptr<const Material<2>>(make_material<2>(MaterialKind::linear)), 0, ne));
  } else {
    elastic_ = &model_->add(std::make_unique<ElasticTerm<3>>(
        cell_.mesh, std::shared_ptr<const Material<3>>(make_material<3>(MaterialKind::linear)), 0, ne));
  }
  model_->set_elimination(periodic_elimination(cell_, Matrix::Zero(dim, dim)));
  assembler_ = std::make_unique<ReducedAssembler>(*model_);
  hessian_ = assembler_->hessian_pattern_matrix();
  factor_.analyze(hessian_);
  rest_ = macro_offset(cell_, Matrix::Zero(dim, dim));
}

LinearCell::~LinearCell() = default;

LinearHomogenization LinearCell::solve(const Vector& youngs_modulus, const Vector& poisson_ratio) {
  const int ne = num_elements();
  const int dim = cell_.dim();
  if (youngs_modulus.size() != ne || poisson_ratio.size() != ne)
    throw std::invalid_argument(
        "LinearCell::solve: need one Young's modulus and Poisson's ratio per element (" + std::to_string(ne) +
        ")");
  youngs_modulus_.resize(0);  // invalid until this solve succeeds
  parameters_.resize(2 * ne);
  modulus_scale_.resize(ne);
  for (int e = 0; e < ne; ++e) {
    const double E = youngs_modulus[e], nu = poisson_ratio[e];
    if (!(E > 0.0) || !std::isfinite(E) || !(nu > -1.0 && nu < 0.5))
      throw std::invalid_argument("LinearCell::solve: element " + std::to_string(e) +
                                  " needs E > 0 and -1 < nu < 0.5, got E = " + std::to_string(E) +
                                  ", nu = " + std::to_string(nu));
    if (mode_ == PlaneMode::plane_stress) {
      modulus_scale_[e] = (1.0 + 2.0 * nu) / ((1.0 + nu) * (1.0 + nu));
      parameters_[e] = E * modulus_scale_[e];
      parameters_[ne + e] = nu / (1.0 + nu);
    } else {
      modulus_scale_[e] = 1.0;
      parameters_[e] = E;
      parameters_[ne + e] = nu;
    }
  }
  LinearHomogenization result;
  const int m = voigt_size(dim);
  const Vector y0 = Vector::Zero(assembler_->num_free());

  auto t0 = Clock::now();
  // The material is linear, so the Hessian is the same at every state: assemble it at rest.
  model_->elimination().set_offset(rest_);
  assembler_->evaluate(y0, parameters_, nullptr, nullptr, &hessian_);
  result.assembly_seconds = seconds_since(t0);
  t0 = Clock::now();
  const FactorizationResult factorization = factor_.factorize(hessian_);
  if (!factorization.success || !factorization.positive_definite)
    throw std::runtime_error("LinearCell: the periodic stiffness matrix is not positive definite (" +
                             factorization.message + ")");
  result.factorization_seconds = seconds_since(t0);

  t0 = Clock::now();
  Matrix rhs(assembler_->num_free(), m);
  std::vector<Vector> offsets(m);
  for (int I = 0; I < m; ++I) {
    offsets[I] = macro_offset(cell_, unit_macro_strain(dim, I));
    model_->elimination().set_offset(offsets[I]);
    Vector g;
    assembler_->evaluate(y0, parameters_, nullptr, &g, nullptr);
    rhs.col(I) = -g;
  }
  const Matrix fluctuations = factor_.solve_columns(rhs);
  states_.assign(m, Vector());
  std::vector<Vector> forces(m);
  for (int I = 0; I < m; ++I) {
    model_->elimination().set_offset(offsets[I]);
    states_[I] = model_->elimination().expand(fluctuations.col(I));
    forces[I] = model_->gradient(states_[I], parameters_);  // K u_I
  }
  model_->elimination().set_offset(rest_);
  result.stiffness.resize(m, m);
  for (int I = 0; I < m; ++I)
    for (int J = 0; J < m; ++J) result.stiffness(I, J) = (states_[I] - rest_).dot(forces[J]) / cell_.volume();
  result.solve_seconds = seconds_since(t0);
  result.symmetry_error = (result.stiffness - result.stiffness.transpose()).cwiseAbs().maxCoeff() /
                          result.stiffness.cwiseAbs().maxCoeff();
  result.states = states_;
  youngs_modulus_ = youngs_modulus;
  return result;
}

Vector LinearCell::youngs_modulus_gradient(const Matrix& dJ_dC) const {
  const int m = voigt_size(cell_.dim());
  const int ne = num_elements();
  if (states_.size() != static_cast<std::size_t>(m))
    throw std::logic_error("LinearCell::youngs_modulus_gradient: call solve() first");
  if (dJ_dC.rows() != m || dJ_dC.cols() != m)
    throw std::invalid_argument("LinearCell::youngs_modulus_gradient: dJ/dC must be " + std::to_string(m) +
                                " x " + std::to_string(m));
  Vector dp = Vector::Zero(2 * ne);
  for (int J = 0; J < m; ++J) {
    // w_J = sum_I W_IJ u_I; (d2E/dx dp)^T w at x_J is w^T (dK/dp) u_J for the linear material.
    Vector w = Vector::Zero(rest_.size());
    for (int I = 0; I < m; ++I)
      if (dJ_dC(I, J) != 0.0) w += dJ_dC(I, J) * (states_[I] - rest_);
    elastic_->add_mixed_transpose_times(states_[J], parameters_, w, dp);
  }
  return dp.head(ne).cwiseProduct(modulus_scale_) / cell_.volume();
}

namespace {
void check_cell_load_case(const char* what, int load_case, std::size_t cases, Eigen::Index vector_size,
                     Eigen::Index expected) {
  if (load_case < 0 || static_cast<std::size_t>(load_case) >= cases)
    throw std::out_of_range(std::string("LinearCell::") + what + ": no such load case (call solve() first)");
  if (vector_size != expected)
    throw std::invalid_argument(std::string("LinearCell::") + what + ": expected a vector of size " +
                                std::to_string(expected) + ", got " + std::to_string(vector_size));
}
}  // namespace

Vector LinearCell::state_tangent(int load_case, const Vector& youngs_modulus_change) const {
  const int ne = num_elements();
  check_cell_load_case("state_tangent", load_case, states_.size(), youngs_modulus_change.size(), ne);
  const Vector& x = states_[static_cast<std::size_t>(load_case)];
  Triplets triplets;
  elastic_->add_mixed(x, parameters_, triplets);
  SparseMatrix mixed(x.size(), parameters_.size());
  mixed.setFromTriplets(triplets.begin(), triplets.end());
  Vector dp = Vector::Zero(parameters_.size());
  dp.head(ne) = modulus_scale_.cwiseProduct(youngs_modulus_change);  // Poisson's ratios fixed
  const Elimination& elimination = model_->elimination();
  return elimination.expand_direction(factor_.solve(elimination.reduce(-(mixed * dp))));
}

Vector LinearCell::state_tangent_transpose(int load_case, const Vector& w) const {
  const int ne = num_elements();
  check_cell_load_case("state_tangent_transpose", load_case, states_.size(), w.size(), rest_.size());
  const Elimination& elimination = model_->elimination();
  const Vector adjoint = elimination.expand_direction(factor_.solve(elimination.reduce(w)));
  Vector dp = Vector::Zero(parameters_.size());
  elastic_->add_mixed_transpose_times(states_[static_cast<std::size_t>(load_case)], parameters_, adjoint, dp);
  return -dp.head(ne).cwiseProduct(modulus_scale_);
}

Matrix LinearCell::element_stresses(int load_case) const {
  if (load_case < 0 || load_case >= static_cast<int>(states_.size()))
    throw std::out_of_range("LinearCell::element_stresses: no such load case (call solve() first)");
  if (cell_.dim() == 2)
    return static_cast<const ElasticTerm<2>*>(elastic_)->stresses(states_[load_case], parameters_);
  return static_cast<const ElasticTerm<3>*>(elastic_)->stresses(states_[load_case], parameters_);
}

}  // namespace tailor
