#pragma once
// DOF indices and stored frames of a rod's stencils (private to forward/rods).
#include <array>
#include <vector>

#include "forward/rods/discrete_rod.hpp"
#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_stencil_term.hpp"

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

// Every edge's frame in its own 3 coordinates at state x (T3 = Dual2<3> or Dual1<3>), for the
// bend-twist stencils to share (rod_kinematics.hpp, edge_frame_in_own_coordinates). The edge
// vectors are the same doubles as the stencils' (x_end - x_start).
template <class T3>
void edge_frames_of_rod(const DiscreteRod& rod, const Vector& x, std::vector<EdgeFrameOf<T3>>& out) {
  const int ne = rod.num_edges();
  out.resize(static_cast<std::size_t>(ne));
#pragma omp parallel for schedule(static) if (ne > 512)
  for (int j = 0; j < ne; ++j) {
    Eigen::Vector3d e;
    for (int k = 0; k < 3; ++k) e[k] = x[rod.position_dof(rod.edge_end(j), k)] - x[rod.position_dof(j, k)];
    out[static_cast<std::size_t>(j)] =
        edge_frame_in_own_coordinates<T3>(e, rod.stored_tangent(j), rod.stored_director(j));
  }
}

// The first-order part of frames on Dual2<3>: the frames edge_frames_of_rod computes on Dual1<3>,
// bit for bit (Dual1 computes values and gradients with Dual2's expressions,
// low_order_duals.hpp), without computing them again.
inline void first_order_parts(const std::vector<EdgeFrameOf<Dual2<3>>>& frames2,
                              std::vector<EdgeFrameOf<Dual1<3>>>& out) {
  out.resize(frames2.size());
  auto truncate = [](const Dual2<3>& a) {
    Dual1<3> r(a.v);
    r.g = a.g;
    return r;
  };
  for (std::size_t j = 0; j < frames2.size(); ++j)
    for (int k = 0; k < 3; ++k) {
      out[j].t[k] = truncate(frames2[j].t[k]);
      out[j].a1[k] = truncate(frames2[j].a1[k]);
    }
}

// The edge frames a bend-twist term's prepare() computes for a request of `order`
// (RodStencilTerm): 2, the Dual2 frames; kProductHessians, the Dual2 frames and their first-order
// parts, and true is returned (the term then forms its frame vectors from `frames2`); otherwise
// the Dual1 frames.
inline bool prepare_edge_frames(const DiscreteRod& rod, const Vector& x, int order,
                                std::vector<EdgeFrameOf<Dual1<3>>>& frames1,
                                std::vector<EdgeFrameOf<Dual2<3>>>& frames2) {
  if (order == 2 || order == kProductHessians) {
    edge_frames_of_rod(rod, x, frames2);
    if (order == 2) return false;
    first_order_parts(frames2, frames1);
    return true;
  }
  edge_frames_of_rod(rod, x, frames1);
  return false;
}

}  // namespace tailor::rod_detail
