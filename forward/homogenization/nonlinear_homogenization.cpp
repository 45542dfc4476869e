#include "forward/homogenization/nonlinear_homogenization.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "forward/fem/elastic_term.hpp"

namespace tailor {
namespace {

template <int Dim>
Matrix average_stress(const EnergyTerm* term, const Vector& x, const Vector& p, const Mesh& mesh,
                      double volume) {
  const auto* elastic = static_cast<const ElasticTerm<Dim>*>(term);
  const Eigen::MatrixXd P = elastic->stresses(x, p);  // row-major per element
  const Eigen::VectorXd volumes = element_volumes(mesh);
  Matrix out = Matrix::Zero(Dim, Dim);
  for (int e = 0; e < P.rows(); ++e)
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) out(i, j) += volumes[e] * P(e, Dim * i + j);
  return out / volume;
}

}  // namespace

NonlinearCell::NonlinearCell(PeriodicCell cell, MaterialKind material, const Vector& youngs_modulus,
                             const Vector& poisson_ratio, NewtonOptions options)
    : cell_(std::move(cell)) {
  const int dim = cell_.dim();
  const int ne = cell_.mesh.num_elements();
  if (youngs_modulus.size() != ne || poisson_ratio.size() != ne)
    throw std::invalid_argument("NonlinearCell: need one Young's modulus and Poisson's ratio per element (" +
                                std::to_string(ne) + ")");
  for (int e = 0; e < ne; ++e) lame_from_young_poisson(youngs_modulus[e], poisson_ratio[e]);  // validates
  model_ = std::make_unique<Model>(dim * cell_.mesh.num_vertices());
  model_->parameter_layout().add("youngs_modulus", ne);
  model_->parameter_layout().add("poisson_ratio", ne);
  if (dim == 2) {
    elastic_ = &model_->add(std::make_unique<ElasticTerm<2>>(
        cell_.mesh, std::shared_ptr<const Material<2>>(make_material<2>(material)), 0, ne));
  } else {
    elastic_ = &model_->add(std::make_unique<ElasticTerm<3>>(
        cell_.mesh, std::shared_ptr<const Material<3>>(make_material<3>(material)), 0, ne));
  }
  model_->set_elimination(periodic_elimination(cell_, Matrix::Zero(dim, dim)));
  parameters_.resize(2 * ne);
  parameters_ << youngs_modulus, poisson_ratio;
  user_reference_residual_ = options.reference_residual;
  newton_ = std::make_unique<NewtonSolver>(*model_, options);
  fluctuation_ = Vector::Zero(model_->elimination().num_free());
  state_ = model_->elimination().expand(fluctuation_);
}

NonlinearCell::~NonlinearCell() = default;

MacroResponse NonlinearCell::solve(const Matrix& F) {
  const int dim = cell_.dim();
  if (F.rows() != dim || F.cols() != dim)
    throw std::invalid_argument("NonlinearCell::solve: F must be dim x dim");
  model_->elimination().set_offset(macro_offset(cell_, F - Matrix::Identity(dim, dim)));
  MacroResponse response;
  response.deformation_gradient = F;
  // A start already in equilibrium up to round-off (a homogeneous cell, a repeated F) has a
  // tiny initial residual, so the relative tolerance refers to the force scale of the load:
  // E_max h^(dim-1) sqrt(#unknowns) |F - I| (h the mean element size), unless the caller set one.
  NewtonOptions& options = newton_->options();
  if (user_reference_residual_ <= 0.0) {
    const int ne = cell_.mesh.num_elements();
    const double h = std::pow(cell_.volume() / ne, 1.0 / dim);
    options.reference_residual = parameters_.head(ne).maxCoeff() * std::pow(h, dim - 1) *
                                 std::sqrt(static_cast<double>(fluctuation_.size())) *
                                 std::max((F - Matrix::Identity(dim, dim)).norm(), 1e-3);
  }
  Vector y = fluctuation_;
  response.newton = newton_->solve(parameters_, y);
  if (response.newton.converged()) fluctuation_ = y;
  state_ = model_->elimination().expand(y);
  response.energy_density = model_->energy(state_, parameters_) / cell_.volume();
  response.stress = dim == 2 ? average_stress<2>(elastic_, state_, parameters_, cell_.mesh, cell_.volume())
                             : average_stress<3>(elastic_, state_, parameters_, cell_.mesh, cell_.volume());
  return response;
}

std::vector<MacroResponse> macro_strain_path(NonlinearCell& cell, const Matrix& direction, double t_max,
                                             int steps) {
  if (steps < 1) throw std::invalid_argument("macro_strain_path: need at least one step");
  const int dim = cell.cell().dim();
  std::vector<MacroResponse> out;
  for (int k = 0; k <= steps; ++k) {
    MacroResponse r = cell.solve(Matrix::Identity(dim, dim) + (t_max * k / steps) * direction);
    const bool ok = r.newton.converged();
    out.push_back(std::move(r));
    if (!ok) break;
  }
  return out;
}

}  // namespace tailor
