#pragma once
// DOF indices and stored frames of a rod's stencils (private to forward/rods).
#include <array>

#include "forward/rods/discrete_rod.hpp"
#include "forward/rods/rod_kinematics.hpp"

namespace tailor::rod_detail {

// Edge j: x_j (0-2), x_{j+1} (3-5).
inline std::array<int, 6> edge_dofs(const DiscreteRod& rod, int edge) {
  std::array<int, 6> d{};
  for (int k = 0; k < 3; ++k) {
    d[static_cast<std::size_t>(k)] = rod.position_dof(edge, k);
    d[static_cast<std::size_t>(3 + k)] = rod.position_dof(rod.edge_end(edge), k);
  }
  return d;
}

// Interior vertex i (between edges i and next_edge(i); rod vertex i+1 mod n): see kBendTwistDofs.
inline std::array<int, kBendTwistDofs> bend_twist_dofs(const DiscreteRod& rod, int interior) {
  std::array<int, kBendTwistDofs> d{};
  const int vertices[3] = {interior, rod.edge_end(interior), rod.edge_end(rod.edge_end(interior))};
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) d[static_cast<std::size_t>(3 * v + k)] = rod.position_dof(vertices[v], k);
  d[9] = rod.twist_dof(interior);
  d[10] = rod.twist_dof(rod.next_edge(interior));
  return d;
}

inline StoredFrames stored_frames(const DiscreteRod& rod, int interior) {
  const int next = rod.next_edge(interior);
  return {rod.stored_tangent(interior), rod.stored_director(interior), rod.stored_tangent(next),
          rod.stored_director(next), rod.stored_reference_twist(interior)};
}

}  // namespace tailor::rod_detail
