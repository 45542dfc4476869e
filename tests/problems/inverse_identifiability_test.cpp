// Identifiability of the inclusion recovery scene (scenes/inclusion_recovery_small.json: a
// gradient plus a 5x stiffer sphere, Neo-Hookean, 3456 tets, 20 material modes): observing
// every vertex instead of the surface only must recover the field better. Noise-free, so the
// difference is the information in the data, not the noise realization. The gain is modest
// (about 0.58 -> 0.577 with 10 modes): most of the error is the sharp sphere, which 10 smooth
// modes cannot represent whatever is observed.
#include <gtest/gtest.h>

#include "../support/temp_folder.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"

namespace tailor::inverse_identifiability_test {
namespace {

double recovery_error(bool all_vertices) {
  Scene scene = read_scene(std::string(tailor::testing::kScenesDir) + "/inclusion_recovery_small.json");
  auto spec = std::make_shared<InverseSpec>(*scene.inverse);
  spec->design.modes = 10;
  spec->optimizer.max_iterations = 20;
  auto& observations = *spec->objective.at(0).settings_as<SyntheticObservationsTerm>();
  observations.noise = 0.0;
  if (all_vertices) {
    observations.vertices.kind = VertexSelector::Kind::box;
    observations.vertices.min = Eigen::Vector3d(0, 0, 0);
    observations.vertices.max = Eigen::Vector3d(2, 1, 1);
  }
  scene.inverse = spec;
  const auto problem = build_inverse_problem(scene);
  const OptimizerResult result =
      minimize(*problem->functional, problem->z0, problem->bounds, {}, spec->optimizer);
  EXPECT_LT(result.objective, 0.1 * result.history.front().objective) << result.report();
  return field_error(problem->setup.mesh, problem->youngs_modulus(result.z), problem->truth).relative_l2;
}

TEST(InverseIdentifiability, MoreObservationsRecoverTheFieldBetter) {
  const double surface = recovery_error(false);
  const double everywhere = recovery_error(true);
  EXPECT_LT(everywhere, surface) << "surface only " << surface << ", all vertices " << everywhere;
  // The initial uniform 1e5 has error 0.663 and the recovery about 0.58: a run that barely
  // improves on the start must fail, so the bound asks for at least half of that gain.
  EXPECT_LT(surface, 0.62);
  std::printf("relative L2 error of E: surface only %.4f, all vertices %.4f\n", surface, everywhere);
}

}  // namespace
}  // namespace tailor::inverse_identifiability_test
