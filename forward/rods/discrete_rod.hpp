#pragma once
// DiscreteRod: the DOF layout and the reference frames of one open or closed discrete elastic
// rod (Bergou et al. 2008, "Discrete Elastic Rods"; Bergou et al. 2010, "Discrete Viscous
// Threads").
//
// DOFs (inside a Model's state vector x, next to other bodies):
//   vertex positions  x[position_offset + 3 v + k], v = 0..num_vertices-1, k = 0..2 [length]
//   twist angles      x[twist_offset + j], j = 0..num_edges-1 [rad], edge j = (v_j, v_{j+1}).
// An open rod has n - 1 edges and n - 2 interior vertices (bend-twist stencils) for n vertices.
// A closed rod (a ring) has n edges, the last one closing from v_{n-1} to v_0, and every vertex
// is interior: stencil i sits between edges i and (i + 1) mod n, at vertex (i + 1) mod n.
//
// Reference frames (docs/rods.md, "Reference frames"): each edge stores a unit tangent t^j_*
// and a unit director a1^j_* normal to it, taken from the last converged state. At a state x
// the edge's reference frame is their parallel transport to the current tangent,
//   a1^j(x) = P(t^j_* -> t^j(x)) a1^j_*,   a2^j = t^j x a1^j,
// (time-parallel transport, Bergou 2010 section 4.2), a smooth function of x as long as
// t^j(x) . t^j_* > -1. The material frame is the reference frame rotated by the twist angle
// theta^j about t^j. update_reference_frames(x) replaces the stored frames by a1^j(x) and
// t^j(x): a driver calls it between solves (load or time steps), never inside Newton, so that
// within one solve the energy is one fixed function of x whose exact derivatives the terms
// deliver. It also records each interior vertex's reference twist, which later evaluations
// unwrap against (so twists of many full turns are tracked, see reference_twist_turns()).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

enum class RodTopology { open, closed };

class DiscreteRod {
 public:
  // rest_positions: num_vertices x 3 (num_vertices >= 2, no zero-length edge). The first
  // edge's director a1 is `first_director` made normal to the first tangent (when zero, or
  // parallel to the tangent, the coordinate axis most normal to it); the others follow by
  // space-parallel transport along the rest centreline, so the rest reference twist is zero.
  // Throws std::invalid_argument on bad input.
  // Closed (topology = closed, num_vertices >= 3): the directors follow by space-parallel
  // transport from edge 0 to edge n-1; transporting once more, around the closing vertex, gives
  // the loop's holonomy, which becomes the closing stencil's stored reference twist (so the rest
  // twist of every stencil is still the rest state's strain, and no frame has a jump).
  DiscreteRod(Eigen::MatrixX3d rest_positions, int position_offset, int twist_offset,
              const Eigen::Vector3d& first_director = Eigen::Vector3d::Zero(),
              RodTopology topology = RodTopology::open);

  bool closed() const { return closed_; }
  int num_vertices() const { return static_cast<int>(rest_positions_.rows()); }
  int num_edges() const { return closed_ ? num_vertices() : num_vertices() - 1; }
  // Bending / twisting stencils.
  int num_interior() const { return closed_ ? num_vertices() : num_vertices() - 2; }
  // Second vertex of an edge, (edge + 1) mod num_vertices.
  int edge_end(int edge) const { return edge + 1 == num_vertices() ? 0 : edge + 1; }
  // The edge after `edge` around a closed rod ((edge + 1) mod num_edges; edge + 1 when open).
  int next_edge(int edge) const { return closed_ && edge + 1 == num_edges() ? 0 : edge + 1; }
  // The vertex of stencil i (between edges i and next_edge(i)).
  int interior_vertex(int interior) const { return edge_end(interior); }
  int position_offset() const { return position_offset_; }
  int twist_offset() const { return twist_offset_; }
  int position_dof(int vertex, int k) const { return position_offset_ + 3 * vertex + k; }
  int twist_dof(int edge) const { return twist_offset_ + edge; }
  // One past the last DOF this rod uses.
  int dof_end() const;
  const Eigen::MatrixX3d& rest_positions() const { return rest_positions_; }
  Eigen::Vector3d position(const Vector& x, int vertex) const;
  Eigen::Vector3d edge_vector(const Vector& x, int edge) const;

  // Writes the rest positions and zero twists into the rod's slice of x.
  void write_rest_state(Vector& x) const;
  // Rest edge lengths (num_edges).
  Eigen::VectorXd rest_lengths() const;

  // Stored (last converged) tangent and director of an edge; stored reference twist of an
  // interior vertex i (between edges i and next_edge(i)) [rad], possibly many turns.
  const Eigen::Vector3d& stored_tangent(int edge) const { return tangents_[static_cast<std::size_t>(edge)]; }
  const Eigen::Vector3d& stored_director(int edge) const {
    return directors_[static_cast<std::size_t>(edge)];
  }
  double stored_reference_twist(int interior) const {
    return reference_twist_[static_cast<std::size_t>(interior)];
  }

  // The reference director a1^j(x) (parallel transport of the stored one), and the material
  // frame (m1, m2) of edge j at x (columns of the returned 3x2 matrix).
  Eigen::Vector3d reference_director(const Vector& x, int edge) const;
  Eigen::Matrix<double, 3, 2> material_frame(const Vector& x, int edge) const;
  // Reference twist of interior vertex i at x, unwrapped to the 2 pi branch nearest the
  // stored value [rad].
  double reference_twist(const Vector& x, int interior) const;

  // Moves the stored frames to the state x (see the header comment). Throws
  // std::runtime_error when an edge's tangent has turned by pi since the last update.
  void update_reference_frames(const Vector& x);

 private:
  Eigen::MatrixX3d rest_positions_;
  int position_offset_, twist_offset_;
  bool closed_ = false;
  std::vector<Eigen::Vector3d> tangents_, directors_;
  std::vector<double> reference_twist_;
};

// Parallel transport of w from unit vector u to unit vector v: the rotation about u x v that
// takes u to v (Bergou 2008, section 4.2). Requires u . v > -1.
Eigen::Vector3d parallel_transport(const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                                   const Eigen::Vector3d& w);

}  // namespace tailor
