#include "problems/fem/full_space_design.hpp"

#include <vector>

#include "objectives/linear_observations.hpp"

namespace tailor {

FullSpaceDesignFunctional::FullSpaceDesignFunctional(const ReducedDesign& design) : design_(design) {
  const StaticSetup& setup = design.setup;
  const Model& model = *design.model;
  const int dim = setup.dim();
  // E = E0 (1 + Y w): a linear basis diag(E0) Y with offset E0, embedded in p.
  const Matrix basis = setup.youngs_modulus.asDiagonal() * design.material_modes;
  ParameterizationPtr map =
      embed_blocks(setup.parameters(), {ParameterBlock{model.parameter_layout().at("youngs_modulus").offset,
                                                       linear_basis_map(basis, setup.youngs_modulus)}});
  // Observations: each handle's mean position, aimed at its mean rest position plus ubar, with
  // the weight W_h / |ubar_h|^2 per component (the reduced loop's rows, in full space).
  const Vector rest = setup.rest_state();
  std::vector<Eigen::Triplet<double>> entries;
  const Eigen::Index rows = dim * static_cast<Eigen::Index>(design.handles.size());
  Vector targets(rows), weights(rows);
  for (std::size_t h = 0; h < design.handles.size(); ++h) {
    const ReducedDesignHandle& handle = design.handles[h];
    const double share = 1.0 / static_cast<double>(handle.vertices.size());
    for (int k = 0; k < dim; ++k) {
      const Eigen::Index row = dim * static_cast<Eigen::Index>(h) + k;
      double mean_rest = 0.0;
      for (int v : handle.vertices) {
        entries.emplace_back(static_cast<int>(row), dim * v + k, share);
        mean_rest += share * rest[dim * v + k];
      }
      targets[row] = mean_rest + handle.target[k];
      weights[row] = handle.weight / handle.target.squaredNorm();
    }
  }
  SparseMatrix observations(rows, setup.num_dofs());
  observations.setFromTriplets(entries.begin(), entries.end());
  auto objective = std::make_shared<LinearObservations>(std::move(observations), targets, weights);

  const ReducedEquilibriumData& reduced = design.functional->data();
  terms_.regularization = reduced.regularization;
  terms_.element_modes = reduced.element_modes;
  terms_.element_weights = reduced.element_weights;
  terms_.positivity_floor = reduced.positivity_floor;
  terms_.positivity_weight = reduced.positivity_weight;

  StaticFunctionalOptions options;  // its tighter Newton tolerance: gradients need it
  options.newton.max_iterations = setup.solver.newton.max_iterations;
  options.newton.hessian = setup.solver.newton.hessian;
  const Vector rest_y = model.elimination().restrict_state(rest);
  equilibrium_ =
      std::make_unique<StaticFunctional>(model, std::move(map), std::move(objective), rest_y, options);
}

double FullSpaceDesignFunctional::value(const Vector& w) {
  const double design = design_terms(terms_, w, nullptr);  // throws where E <= 0 somewhere
  return equilibrium_->value(w) + design;
}

double FullSpaceDesignFunctional::value_and_gradient(const Vector& w, Vector& gradient) {
  Vector design_gradient = Vector::Zero(size());
  const double design = design_terms(terms_, w, &design_gradient);
  const double misfit = equilibrium_->value_and_gradient(w, gradient);
  gradient += design_gradient;
  return misfit + design;
}

std::vector<double> FullSpaceDesignFunctional::handle_errors() const {
  return design_.handle_errors(equilibrium_->state() - design_.setup.rest_state());
}

}  // namespace tailor
