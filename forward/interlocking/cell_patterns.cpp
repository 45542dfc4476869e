// Cells of common interlocking patterns (see cell_patterns.hpp).
#include "forward/interlocking/cell_patterns.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tailor::interlocking {

CellElement upright_ring(const tori::TorusShape& shape, const Eigen::Vector3d& position, double angle) {
  // A quarter turn about the in-plane direction e takes the body axis z to e x z: horizontal
  // and perpendicular to e, so the ring's plane is the vertical plane through e.
  const Eigen::Vector3d e(std::cos(angle), std::sin(angle), 0.0);
  return {shape, position, 0.5 * M_PI * e};
}

CellElement flat_ring(const tori::TorusShape& shape, const Eigen::Vector3d& position) {
  return {shape, position, Eigen::Vector3d::Zero()};
}

RigidCellSpec chain_cell(const tori::TorusShape& node, const tori::TorusShape& link, double spacing, double lateral) {
  RigidCellSpec c;
  c.elements = {flat_ring(node, Eigen::Vector3d::Zero()), upright_ring(link, Eigen::Vector3d(spacing, 0, 0), 0.0)};
  c.lattice << 2.0 * spacing, 0.0, 0.0, lateral;
  return c;
}

RigidCellSpec square_ring_cell(const tori::TorusShape& node, const tori::TorusShape& link_x,
                               const tori::TorusShape& link_y, double spacing) {
  RigidCellSpec c;
  c.elements = {flat_ring(node, Eigen::Vector3d::Zero()), upright_ring(link_x, Eigen::Vector3d(spacing, 0, 0), 0.0),
                upright_ring(link_y, Eigen::Vector3d(0, spacing, 0), 0.5 * M_PI)};
  c.lattice << 2.0 * spacing, 0.0, 0.0, 2.0 * spacing;
  return c;
}

RigidCellSpec threefold_cell(const tori::TorusShape& node, const tori::TorusShape& link, double spacing) {
  RigidCellSpec c;
  c.elements.push_back(flat_ring(node, Eigen::Vector3d::Zero()));
  for (int k = 0; k < 3; ++k) {
    const double angle = k * M_PI / 3.0;
    c.elements.push_back(
        upright_ring(link, Eigen::Vector3d(spacing * std::cos(angle), spacing * std::sin(angle), 0.0), angle));
  }
  c.lattice << 2.0 * spacing, spacing, 0.0, std::sqrt(3.0) * spacing;
  c.image_rings = 2;  // the links reach cells two shifts away along the short diagonal
  return c;
}

RigidCellSpec ring_chain_patch(const tori::TorusShape& node, const tori::TorusShape& link, double spacing) {
  RigidCellSpec c;
  c.bending_patch = true;
  c.elements = {flat_ring(node, Eigen::Vector3d(-spacing, 0, 0)), upright_ring(link, Eigen::Vector3d::Zero(), 0.0),
                flat_ring(node, Eigen::Vector3d(spacing, 0, 0))};
  c.elements[0].rim = c.elements[2].rim = true;
  return c;
}

RigidCellSpec disc_patch(const RigidCellSpec& cell, double radius, double rim_width) {
  if (!(radius > 0.0) || !(rim_width > 0.0) || !(rim_width < radius))
    throw std::invalid_argument("disc_patch: need 0 < rim_width < radius");
  RigidCellSpec out = cell;
  out.bending_patch = true;
  out.elements.clear();
  // Lattice shifts covering the disc: |L k| <= radius + the cell's extent.
  double extent = 0.0;
  for (const CellElement& e : cell.elements) extent = std::max(extent, e.position.head<2>().norm());
  const Eigen::Matrix2d inverse = cell.lattice.inverse();
  const int K = static_cast<int>(std::ceil((radius + extent) * inverse.norm())) + 1;
  for (int b = -K; b <= K; ++b)
    for (int a = -K; a <= K; ++a)
      for (std::size_t i = 0; i < cell.elements.size(); ++i) {
        CellElement copy = cell.elements[i];
        copy.origin = static_cast<int>(i);
        const Eigen::Vector2d t = cell.lattice * Eigen::Vector2d(a, b);
        copy.position += Eigen::Vector3d(t.x(), t.y(), 0.0);
        const double rho = copy.position.head<2>().norm();
        if (rho > radius) continue;
        copy.rim = rho > radius - rim_width;
        out.elements.push_back(copy);
      }
  return out;
}

RigidCellSpec supercell(const RigidCellSpec& cell, int nx, int ny) {
  if (nx < 1 || ny < 1) throw std::invalid_argument("supercell: nx and ny must be >= 1");
  RigidCellSpec out = cell;
  out.elements.clear();
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      for (const CellElement& e : cell.elements) {
        CellElement copy = e;
        const Eigen::Vector2d t = cell.lattice * Eigen::Vector2d(i, j);
        copy.position += Eigen::Vector3d(t.x(), t.y(), 0.0);
        out.elements.push_back(copy);
      }
  out.lattice = cell.lattice * Eigen::Vector2d(nx, ny).asDiagonal();
  return out;
}

RigidCellSpec relattice(const RigidCellSpec& cell, const Eigen::Matrix2i& M, int image_rings) {
  const int det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
  if (det != 1 && det != -1) throw std::invalid_argument("relattice: M must have determinant +-1");
  RigidCellSpec out = cell;
  out.lattice = cell.lattice * M.cast<double>();
  out.image_rings = image_rings;
  return out;
}

}  // namespace tailor::interlocking
