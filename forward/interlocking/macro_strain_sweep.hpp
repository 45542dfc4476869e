#pragma once
// Native sweeps over the sphere of in-plane strain directions (docs/interlocking.md, "Macro-scale
// model"): the samples of the anisotropic admissible set (macro_anisotropic_fit.hpp), through the
// strain-space boundary search of strain_boundary.hpp. A direction is n = (u, v, w), the unit
// strain of Frobenius size 1 (u equibiaxial, v and w deviatoric; macro_anisotropic_fit.hpp).
#include <Eigen/Core>
#include <vector>

#include "forward/interlocking/strain_boundary.hpp"

namespace tailor::interlocking {

// The load path F(s) = I + s G with G the unit strain of direction n = (u, v, w) ([[g_xx, g_xy],
// [g_xy, g_yy]], |G| = 1), so s at the limit is rho (and e = s G); angle: beta, for reports.
LoadPath strain_direction_path(double u, double v, double w);
// Directions of a latitude-longitude grid about the equibiaxial pole: phi = pi i / rings (i = 0 ..
// rings; the poles once), beta = beta_max j / sectors (j = 0 .. sectors). beta in [0, pi/2] covers
// a set with both symmetries; [0, pi] with one; 2 pi (sectors excluding the end) none.
std::vector<Eigen::Vector3d> strain_sphere_directions(int rings, int sectors, double beta_max);
// The locked strains (e_xx, e_yy, e_xy) along each direction (u, v, w), each path from the cell's
// rest equilibrium (strain_space_boundary); paths that do not lock (or stall) are left out and
// counted in *skipped.
std::vector<Eigen::Vector3d> native_strain_sweep(const PeriodicRigidCell& cell,
                                                 const std::vector<Eigen::Vector3d>& directions,
                                                 const LimitOptions& options, int* skipped = nullptr);

}  // namespace tailor::interlocking
