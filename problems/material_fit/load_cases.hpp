#pragma once
// Load cases of a material test on a unit cube (edges along x, y, z, from the origin): each
// prescribes the displacement of a face in steps and measures the total reaction force there
// (force units, per the energy's units; positive along the loading direction when the
// specimen resists being pulled).
//   uniaxial: z = 0 face held in z (plus two vertices against rigid motion), z = 1 face moved
//             to z = amplitude (a stretch; < 1 is compression); lateral faces free. Measured:
//             total z-reaction on the top face. Homogeneous: one stretch and two free ones.
//   biaxial:  symmetry planes x = 0, y = 0, z = 0; faces x = 1 and z = 1 moved to the stretch
//             `amplitude`. Measured: total x-reaction on x = 1 plus total z-reaction on z = 1.
//   shear:    z = 0 face clamped, z = 1 face moved by amplitude along x (simple shear, sides free).
//             Measured: total x-reaction on the top face.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/fem/materials/principal_stretch_curves.hpp"
#include "forward/mesh/mesh.hpp"
#include "objectives/target_reaction_forces.hpp"

namespace tailor {

enum class LoadCaseKind { uniaxial, biaxial, shear };
std::string to_string(LoadCaseKind kind);
LoadCaseKind parse_load_case_kind(const std::string& name);  // throws std::invalid_argument

struct LoadCase {
  std::string name;
  LoadCaseKind kind = LoadCaseKind::uniaxial;
  std::vector<double> amplitudes;  // one load step each
};

// One load step of one case as a model: the mesh, an energy term, the Dirichlet conditions of
// the step and the measured DOFs.
struct SpecimenStep {
  std::unique_ptr<Model> model;
  const EnergyTerm* term = nullptr;  // the elastic term (owned by model)
  std::vector<int> measured_dofs;    // their reactions are summed per component
  Eigen::Vector3d measured_weights;  // which components of the total reaction are measured
  Vector rest_y;                     // the rest state, reduced
};

// The unit-cube mesh the cases use (cells per edge).
Mesh load_case_mesh(int cells);
// A load step with a SplineElasticTerm whose controls are p (the whole parameter vector).
SpecimenStep spline_load_step(const Mesh& mesh, const LoadCase& c, int step,
                              const PrincipalStretchCurves& knots);
// The same step with any energy term over the mesh (e.g. ElasticTerm with a closed-form
// material, for targets); the term's parameters are p.
SpecimenStep load_step(const Mesh& mesh, const LoadCase& c, int step, std::unique_ptr<EnergyTerm> term,
                       int num_parameters);
// Measured reaction (the weighted sum of total reaction components) at state x.
double measured_force(const SpecimenStep& s, const Vector& x, const Vector& p);
// The TargetReactionForces objective of a step for the target force (scaled by 1/force_scale).
std::shared_ptr<TargetReactionForces> reaction_objective(const SpecimenStep& s, double target,
                                                         double force_scale);

}  // namespace tailor
