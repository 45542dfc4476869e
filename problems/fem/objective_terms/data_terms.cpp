// What the displacement data terms share (builtin_terms.hpp).
#include "objectives/target_positions.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"

namespace tailor {

BuiltObjectiveTerm displacement_misfit(const InverseProblem& problem, std::vector<int> vertices,
                                       const Eigen::MatrixXd& displacements) {
  const Mesh& mesh = problem.setup.mesh;
  double norm2 = displacements.squaredNorm();
  if (!(norm2 > 0.0)) {
    const double diagonal =
        (mesh.rest_positions.colwise().maxCoeff() - mesh.rest_positions.colwise().minCoeff()).norm();
    norm2 = static_cast<double>(vertices.size()) * diagonal * diagonal;
  }
  return {std::make_shared<TargetPositions>(TargetPositions::displacements(mesh, std::move(vertices), displacements)),
          norm2};
}

}  // namespace tailor
