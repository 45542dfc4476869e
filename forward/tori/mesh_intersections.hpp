#pragma once
// Intersection check of rigid bodies' meshes (validation of the torus contact's intersection-
// free guarantee on the tori's inscribed triangulations, torus.hpp): for every pair of bodies
// whose bounding spheres overlap, every edge of one against every face of the other
// (contact::segment_intersects_triangle, with a box rejection), both ways.
#include "forward/core/types.hpp"
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::tori {

// The number of crossing (edge, face) pairs between different bodies at state q.
int count_body_intersections(const rigid::RigidBodySystem& system, const Vector& q);

}  // namespace tailor::tori
