#pragma once
// An interpenetration check of a cell's state that shares no code with the contact model
// (docs/interlocking.md): for circular tori, the distance between the core circles is bounded
// below by sampling circle a at `samples` angles and taking the exact closed-form distance from
// each sample point p to circle b (centre c, unit normal n, radius R_b):
//   dist(p, b)^2 = z^2 + (rho - R_b)^2,   z = (p - c) . n,   rho = |(p - c) - z n|.
// dist(c_a(t), b) is Lipschitz in t with constant R_a (the core point's speed; the distance to a
// set is 1-Lipschitz), so with spacing h = 2 pi / samples the true minimum D satisfies
//   min_k dist(c_a(t_k), b) - R_a h / 2 <= D <= min_k dist(c_a(t_k), b),
// and the tori are certified apart when that lower bound exceeds r_a + r_b.
#include <Eigen/Core>
#include <vector>

#include "forward/interlocking/periodic_cell.hpp"

namespace tailor::interlocking {

struct PairClearance {
  int body_a = 0, body_b = 0;
  double upper = 0.0;  // sampled surface distance (an upper bound) [length]
  double lower = 0.0;  // certified lower bound [length]
};

struct ClearanceReport {
  std::vector<PairClearance> pairs;  // every candidate pair whose bounding spheres meet
  double min_lower = 0.0;            // smallest certified lower bound (infinity without pairs)
  bool elliptic_skipped = false;     // pairs with an elliptic torus are not checked here
  bool apart() const { return min_lower > 0.0; }
};

// Core-circle distance bounds for two circular tori given by centre T, rotation vector w and
// major radius R (the tube radii are subtracted by the caller).
void core_distance_bounds(const Eigen::Vector3d& Ta, const Eigen::Vector3d& wa, double Ra, const Eigen::Vector3d& Tb,
                          const Eigen::Vector3d& wb, double Rb, int samples, double& lower, double& upper);

// Every pair of the cell's bodies that the contact term considers (masters with masters and
// images) at full state x whose bounding spheres come within 0.1 x the smallest R (the others
// are certified apart by the spheres' gap).
ClearanceReport check_clearance(const PeriodicRigidCell& cell, const Vector& x, int samples = 1 << 15);

}  // namespace tailor::interlocking
