#pragma once
// Simulations with the macro-scale interlocking sheet (docs/interlocking.md, "Macro-scale model"):
// a square sheet draped under gravity over a sphere, and a strip pulled to its lock in uniaxial
// strain (the state compared with the native cell). Static equilibria by Newton with the terms'
// max_step (the sheet never leaves its admissible set, the vertices never enter the sphere).
#include "forward/interlocking/macro_bending_limit.hpp"
#include "forward/interlocking/macro_sheet_term.hpp"
#include "forward/mesh/mesh.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::interlocking {

struct DrapeSpec {
  double width = 1.4;         // side of the square sheet [length], centred above the sphere
  int divisions = 14;         // squares per side (even: a vertex sits at the centre)
  double areal_weight = 1.0;  // weight per rest area [force / area], along -z
  MacroSheetMaterial material;
  double bending_stiffness = 1e-3;   // D [energy] (QuadraticBendingTerm)
  bool bending_limits = false;       // add the curvature barrier (BendingLimitTerm) on bending_fit
  BendingLimitFit bending_fit;
  CurvatureBarrier curvature_barrier;
  double sphere_radius = 1.0;        // [length], centred at the origin
  double contact_activation = 0.01;  // d_hat [length]
  double contact_stiffness = 1.0;    // kappa [energy]
  NewtonOptions newton;              // max_iterations defaults to 500 here
  DrapeSpec() { newton.max_iterations = 500; }
};

struct DrapeResult {
  Mesh flat;         // the rest sheet (2D)
  Vector positions;  // deformed positions, 3 per vertex [length]
  NewtonResult newton;
  Eigen::MatrixXd principal_strains;  // per element (e_1, e_2)
  Eigen::VectorXd margins;            // per element g
  Eigen::VectorXd gaps;               // per vertex distance to the sphere [length]
  int barrier_elements = 0;           // elements with g < g_hat (the barrier acts)
  int contact_vertices = 0;           // vertices with gap < d_hat
  Eigen::VectorXd hinge_curvatures;   // bending limits: per hinge |kappa_e| [1 / length]
  Eigen::VectorXd hinge_margins;      // bending limits: per hinge g_e
  double sagitta_bound = 0.0;         // largest deformed edge^2 / (8 R): how far a face can dip [length]
};

// The sheet starts flat, its centre vertex d_hat / 2 above the sphere's top; the centre's x, y and
// the y of its neighbour along +x are held (the sphere and gravity leave the sheet free to slide
// and to spin about the vertical), everything else is free.
DrapeResult drape_over_sphere(const MacroStrainSet& set, const DrapeSpec& spec);

struct PullResult {
  double strain = 0.0;      // mean stretch strain along the pull of the strip [strain]
  double lateral_strain = 0.0;  // biaxial pulls: mean strain across the pull [strain]
  double min_margin = 0.0;  // smallest element margin g
  NewtonResult newton;
};

// A flat strip [0, length] x [0, width] (nx x ny squares, in the strip's frame) whose material axes
// are turned by -angle against the strip, so the pull along the strip's x stretches the material
// along d = (cos angle, sin angle). Every vertex's z held, the left edge's x and the bottom edge's y
// held, the right edge pulled along +x by `traction` [force / length of edge]; lateral_traction 0:
// every y held too (uniaxial strain, the macro model's answer to the native uniaxial path F = I + s d
// d^T); > 0: the top edge pulled along +y (a biaxial state).
struct PullSpec {
  double traction = 200.0;
  double lateral_traction = 0.0;
  double angle = 0.0;  // [rad]
  double length = 1.0, width = 0.5;
  int nx = 6, ny = 3;
};
PullResult pull_strip(const MacroStrainSet& set, const MacroSheetMaterial& material, const PullSpec& spec);
PullResult pull_strip(const MacroStrainSet& set, const MacroSheetMaterial& material, double traction);

// A strip as pull_strip's (material turned by -angle against it, nx x ny squares) bent by a couple
// at its free end: the first two vertex columns clamped, +P and -P along z on the last two columns
// (no net force, so the moment M = P h, h = length / nx, is the same along the strip) with P =
// moment * width / h [force]; the membrane, the quadratic bending (D) and the curvature barrier.
// The macro model's answer to the native single-curvature path across the strip (the curvature
// direction d = (cos angle, sin angle) in the material).
struct BendSpec {
  double moment = 1.0;  // per width [energy / length]
  double angle = 0.0;   // [rad]
  double length = 1.0, width = 0.25;
  int nx = 16, ny = 2;
  double bending_stiffness = 1e-3;  // D [energy]
  CurvatureBarrier barrier;
};
struct BendResult {
  double curvature = 0.0;      // mean |kappa_e| over the hinges across the strip (the moment is M at each)
  double max_curvature = 0.0;  // largest |kappa_e| of the hinges across the strip
  double min_margin = 0.0;     // smallest hinge margin g_e
  NewtonResult newton;
};
BendResult bend_strip(const MacroStrainSet& set, const MacroSheetMaterial& material, const BendingLimitFit& fit,
                      const BendSpec& spec);

// The fitted limit of the homogeneous uniaxial path F = I + s d d^T, d = (cos angle, sin angle)
// (s > 0): the radius along the strain d d^T. The isotropic set gives r(1/sqrt(2)) for every d.
double macro_uniaxial_limit(const MacroStrainSet& set, double angle = 0.0);

}  // namespace tailor::interlocking
