#pragma once
// Cells of common interlocking patterns (docs/interlocking.md, "Patterns"). Lengths in the units
// of the radii; every ring's rest placement leaves its neighbours apart.
//  chain:        a straight chain along x: a flat ring (axis z) at 0 and an upright ring (in the
//                xz plane) at (s, 0, 0); lattice (2 s, 0), (0, lateral) with `lateral` large
//                enough that rows never meet.
//  square rings: a square net: a flat node ring at 0, an upright link ring on the x edge at
//                (s, 0, 0) (in the xz plane) and one on the y edge at (0, s, 0) (in the yz plane);
//                lattice 2 s e_x, 2 s e_y. Each node holds four links, each link two nodes.
//  threefold:    a threefold-symmetric mail: a flat node ring and upright link rings on the edges
//                of a triangular lattice at 0, 60 and 120 degrees (each in the vertical plane of
//                its edge); lattice 2 s (1, 0), 2 s (1/2, sqrt(3)/2). Six links per node.
#include "forward/interlocking/periodic_cell.hpp"

namespace tailor::interlocking {

// An upright ring whose plane is vertical and contains the in-plane direction at `angle`.
CellElement upright_ring(const tori::TorusShape& shape, const Eigen::Vector3d& position, double angle);
CellElement flat_ring(const tori::TorusShape& shape, const Eigen::Vector3d& position);

RigidCellSpec chain_cell(const tori::TorusShape& node, const tori::TorusShape& link, double spacing,
                         double lateral);
RigidCellSpec square_ring_cell(const tori::TorusShape& node, const tori::TorusShape& link_x,
                               const tori::TorusShape& link_y, double spacing);
RigidCellSpec threefold_cell(const tori::TorusShape& node, const tori::TorusShape& link, double spacing);

// Bending patches (periodic_cell.hpp, bending_patch):
//  three-ring chain: flat rim rings at (-s, 0, 0) and (s, 0, 0) and a free upright link (in the
//                xz plane) at 0 between them.
//  disc patch:   every element of the tiling of `cell` whose centre lies within `radius` of the
//                origin (in xy); those beyond radius - rim_width are the rim. Each copy's `origin`
//                is its element's index in `cell`.
RigidCellSpec ring_chain_patch(const tori::TorusShape& node, const tori::TorusShape& link, double spacing);
RigidCellSpec disc_patch(const RigidCellSpec& cell, double radius, double rim_width);

// The nx x ny supercell of the same tiling (elements repeated, lattice L diag(nx, ny)).
RigidCellSpec supercell(const RigidCellSpec& cell, int nx, int ny);
// The same tiling with lattice L M for an integer matrix M of determinant +-1 (throws
// std::invalid_argument otherwise).
RigidCellSpec relattice(const RigidCellSpec& cell, const Eigen::Matrix2i& M, int image_rings);

}  // namespace tailor::interlocking
