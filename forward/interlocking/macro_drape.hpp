#pragma once
// Simulations with the macro-scale interlocking sheet (docs/interlocking.md, "Macro-scale model"):
// a square sheet draped under gravity over a sphere, and a strip pulled to its lock in uniaxial
// strain (the state compared with the native cell). Static equilibria by Newton with the terms'
// max_step (the sheet never leaves its admissible set, the vertices never enter the sphere).
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
  double sagitta_bound = 0.0;         // largest deformed edge^2 / (8 R): how far a face can dip [length]
};

// The sheet starts flat, its centre vertex d_hat / 2 above the sphere's top; the centre's x, y and
// the y of its neighbour along +x are held (the sphere and gravity leave the sheet free to slide
// and to spin about the vertical), everything else is free.
DrapeResult drape_over_sphere(const BoundaryFit& fit, const DrapeSpec& spec);

struct PullResult {
  double strain = 0.0;      // mean e_xx of the strip [strain]
  double min_margin = 0.0;  // smallest element margin g
  NewtonResult newton;
};

// A flat strip [0, length] x [0, width] (nx x ny squares) in uniaxial strain: every vertex's y and z
// held, the left edge's x held, the right edge pulled along +x by `traction` [force / length of
// edge]. The macro model's answer to the native uniaxial path at 0 degrees (F = diag(1 + s, 1)).
PullResult pull_strip(const BoundaryFit& fit, const MacroSheetMaterial& material, double traction,
                      double length = 1.0, double width = 0.5, int nx = 6, int ny = 3);

// The fitted limit of the homogeneous uniaxial path F = I + s d d^T (s > 0): principal strains
// (s, 0), so s = r(1/sqrt(2)) for every direction d (the fitted set is isotropic).
double macro_uniaxial_limit(const BoundaryFit& fit);

}  // namespace tailor::interlocking
