#pragma once
// A planar periodic rod network (docs/homogenization.md, "Rod-network cells"): the lattice, the
// joints in the cell, the bars between joints and their images, one circular section and one
// material. Plain data for RodNetworkCell (rod_network_cell.hpp), which defines these functions.
// Units: lengths [length], moduli [pressure].
#include <Eigen/Core>
#include <vector>

namespace tailor {

struct RodNetworkBar {
  int from = 0, to = 0;
  Eigen::Vector2i shift = Eigen::Vector2i::Zero();  // the bar ends at joint `to` + A shift
};

struct RodNetwork {
  Eigen::Matrix2d lattice = Eigen::Matrix2d::Identity();  // columns a_1, a_2 [length]
  Eigen::MatrixX2d joints;                                // joint positions (x, y) [length]
  std::vector<RodNetworkBar> bars;
  double youngs_modulus = 1.0;  // E_s [pressure]
  double shear_modulus = 0.5;   // G_s [pressure]
  double radius = 0.01;         // circular section of radius a [length]
  int edges_per_bar = 16;

  // Throws std::invalid_argument naming what is wrong: det A <= 0, no joints or bars, a bar
  // with a bad joint index or of zero length, a joint on no bar, bad moduli, radius or edges.
  void validate() const;
  double cell_area() const;  // det A [length^2]
  // The bar's two end points (rest, z = 0).
  Eigen::Vector3d bar_start(int bar) const;
  Eigen::Vector3d bar_end(int bar) const;
};

// Square lattice of cell size l: one joint, bars along a_1 and a_2 (Gibson & Ashby's square
// grid, stretch-dominated along the bars).
RodNetwork square_rod_lattice(double cell_size, double radius, double youngs_modulus, double shear_modulus,
                              int edges_per_bar);
// Regular hexagonal honeycomb of wall length l (Gibson & Ashby's h = l, theta = 30 degrees):
// a_1 = (sqrt(3) l, 0), a_2 = (sqrt(3) l / 2, 3 l / 2), joints (0, 0) and (0, l), the wall
// between them parallel to x_2.
RodNetwork honeycomb_rod_lattice(double wall_length, double radius, double youngs_modulus,
                                 double shear_modulus, int edges_per_bar);

}  // namespace tailor
