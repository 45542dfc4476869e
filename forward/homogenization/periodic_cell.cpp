#include "forward/homogenization/periodic_cell.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

namespace tailor {
namespace {

std::string format_point(const Eigen::VectorXd& x) {
  std::ostringstream s;
  s.precision(10);
  s << "(";
  for (int k = 0; k < x.size(); ++k) s << (k ? ", " : "") << x[k];
  s << ")";
  return s.str();
}

// Fractional coordinate wrapped into [0, 1); values within tol of 1 become 0.
double wrap(double f, double tol) {
  double w = f - std::floor(f);
  if (w > 1.0 - tol) w = 0.0;
  if (w < tol) w = 0.0;
  return w;
}

}  // namespace

int PeriodicCell::num_periodic_nodes() const {
  int count = 0;
  for (std::size_t v = 0; v < master.size(); ++v) count += master[v] == static_cast<int>(v);
  return count;
}

PeriodicCell make_periodic_cell(const Mesh& mesh, const Eigen::MatrixXd& lattice,
                                const Eigen::VectorXd& origin, double tolerance) {
  return make_periodic_cell(mesh, lattice, origin, tolerance, std::vector<bool>(mesh.dim(), true));
}

PeriodicCell make_periodic_cell(const Mesh& mesh, const Eigen::MatrixXd& lattice,
                                const Eigen::VectorXd& origin, double tolerance,
                                const std::vector<bool>& periodic) {
  const int dim = mesh.dim();
  if (dim != 2 && dim != 3) throw std::invalid_argument("make_periodic_cell: the mesh must be 2D or 3D");
  if (lattice.rows() != dim || lattice.cols() != dim || origin.size() != dim)
    throw std::invalid_argument("make_periodic_cell: the lattice must be " + std::to_string(dim) + " x " +
                                std::to_string(dim) + " and the origin of size " + std::to_string(dim));
  if (!(lattice.determinant() > 0.0))
    throw std::invalid_argument("make_periodic_cell: the lattice vectors must be right-handed (det A > 0)");
  if (static_cast<int>(periodic.size()) != dim || std::count(periodic.begin(), periodic.end(), true) == 0)
    throw std::invalid_argument(
        "make_periodic_cell: need one periodic flag per lattice vector, at least one set");
  if (!(tolerance > 0.0 && tolerance < 0.1))
    throw std::invalid_argument("make_periodic_cell: tolerance must lie in (0, 0.1)");
  validate_mesh(mesh, "periodic cell mesh");

  // Relative tolerance in fractional coordinates: tolerance * cell size / (shortest height).
  const Eigen::MatrixXd inverse = lattice.inverse();
  double size = 0.0;
  for (int k = 0; k < dim; ++k) size = std::max(size, lattice.col(k).norm());
  const double tol = tolerance * size * inverse.rowwise().norm().maxCoeff();

  const int n = mesh.num_vertices();
  Eigen::MatrixXd fractional(n, dim);
  std::vector<std::string> outside;
  for (int v = 0; v < n; ++v) {
    const Eigen::VectorXd X = mesh.rest_positions.row(v).transpose();
    fractional.row(v) = (inverse * (X - origin)).transpose();
    if ((fractional.row(v).array() < -tol).any() || (fractional.row(v).array() > 1.0 + tol).any())
      if (outside.size() < 10) outside.push_back("vertex " + std::to_string(v) + " at " + format_point(X));
  }
  if (!outside.empty()) {
    std::string message = "periodic cell: vertices outside the cell spanned by the lattice:";
    for (const auto& o : outside) message += "\n  " + o;
    throw PeriodicityError(message);
  }

  // Group by wrapped coordinates, quantized to a grid of spacing 4 tol; neighbouring grid
  // cells are searched so that points close to a grid line still meet.
  const double h = 4.0 * tol;
  using Key = std::vector<long long>;
  std::map<Key, std::vector<int>> grid;
  Eigen::MatrixXd wrapped(n, dim);
  std::vector<int> boundary_count(n, 0);
  for (int v = 0; v < n; ++v) {
    Key key(dim);
    for (int k = 0; k < dim; ++k) {
      const double f = fractional(v, k);
      if (periodic[k]) {
        boundary_count[v] += (std::abs(f) < tol || std::abs(f - 1.0) < tol);
        wrapped(v, k) = wrap(f, tol);
      } else {
        wrapped(v, k) = f;
      }
      key[k] = static_cast<long long>(std::floor(wrapped(v, k) / h));
    }
    grid[key].push_back(v);
  }
  PeriodicCell cell;
  cell.mesh = mesh;
  cell.lattice = lattice;
  cell.origin = origin;
  cell.periodic = periodic;
  cell.master.assign(n, -1);
  std::vector<int> group_size(n, 0);
  for (int v = 0; v < n; ++v) {
    if (cell.master[v] >= 0) continue;
    std::vector<int> group;
    Key base(dim);
    for (int k = 0; k < dim; ++k) base[k] = static_cast<long long>(std::floor(wrapped(v, k) / h));
    const int neighbours = dim == 2 ? 9 : 27;
    for (int c = 0; c < neighbours; ++c) {
      Key key = base;
      int code = c;
      for (int k = 0; k < dim; ++k, code /= 3) key[k] += code % 3 - 1;
      const auto it = grid.find(key);
      if (it == grid.end()) continue;
      for (const int u : it->second)
        if (cell.master[u] < 0 && (wrapped.row(u) - wrapped.row(v)).cwiseAbs().maxCoeff() < tol)
          group.push_back(u);
    }
    const int m = *std::min_element(group.begin(), group.end());
    for (const int u : group) {
      cell.master[u] = m;
      group_size[u] = static_cast<int>(group.size());
    }
  }
  // A vertex on b boundary faces has 2^b copies (its images across each face it lies on).
  std::vector<std::string> unmatched;
  int num_unmatched = 0;
  for (int v = 0; v < n; ++v) {
    if (group_size[v] == (1 << boundary_count[v])) continue;
    ++num_unmatched;
    if (unmatched.size() < 10)
      unmatched.push_back("vertex " + std::to_string(v) + " at " +
                          format_point(mesh.rest_positions.row(v).transpose()) + " has " +
                          std::to_string(group_size[v] - 1) + " periodic images, expected " +
                          std::to_string((1 << boundary_count[v]) - 1));
  }
  if (num_unmatched > 0) {
    std::string message = "periodic cell: the mesh is not periodic under the lattice (" +
                          std::to_string(num_unmatched) + " unmatched vertices, tolerance " +
                          std::to_string(tolerance) + " of the cell size):";
    for (const auto& u : unmatched) message += "\n  " + u;
    throw PeriodicityError(message);
  }
  const double mesh_volume = element_volumes(mesh).sum();
  if (std::abs(mesh_volume - cell.volume()) > 1e-6 * cell.volume())
    throw PeriodicityError("periodic cell: the elements' volume " + std::to_string(mesh_volume) +
                           " does not tile the cell (|det A| = " + std::to_string(cell.volume()) + ")");
  cell.anchor = cell.master[0];
  return cell;
}

PeriodicCell make_box_periodic_cell(const Mesh& mesh, double tolerance) {
  if (mesh.num_vertices() == 0) throw std::invalid_argument("make_box_periodic_cell: empty mesh");
  const Eigen::VectorXd lo = mesh.rest_positions.colwise().minCoeff().transpose();
  const Eigen::VectorXd hi = mesh.rest_positions.colwise().maxCoeff().transpose();
  return make_periodic_cell(mesh, Eigen::MatrixXd((hi - lo).asDiagonal()), lo, tolerance);
}

Vector macro_offset(const PeriodicCell& cell, const Eigen::MatrixXd& macro_gradient) {
  const int dim = cell.dim();
  if (macro_gradient.rows() != dim || macro_gradient.cols() != dim)
    throw std::invalid_argument("macro_offset: the macro displacement gradient must be dim x dim");
  Vector x0(dim * cell.mesh.num_vertices());
  for (int v = 0; v < cell.mesh.num_vertices(); ++v) {
    const Eigen::VectorXd X = cell.mesh.rest_positions.row(v).transpose();
    x0.segment(dim * v, dim) = X + macro_gradient * X;
  }
  return x0;
}

Elimination periodic_elimination(const PeriodicCell& cell, const Eigen::MatrixXd& macro_gradient) {
  const int dim = cell.dim();
  const int n = cell.mesh.num_vertices();
  std::vector<int> column(n, -1);  // per master vertex: its first free unknown
  int num_free = 0;
  for (int v = 0; v < n; ++v)
    if (cell.master[v] == v && v != cell.anchor) {
      column[v] = num_free;
      num_free += dim;
    }
  Triplets triplets;
  triplets.reserve(static_cast<std::size_t>(dim) * n);
  for (int v = 0; v < n; ++v) {
    const int m = cell.master[v];
    if (m == cell.anchor) continue;
    for (int k = 0; k < dim; ++k) triplets.emplace_back(dim * v + k, column[m] + k, 1.0);
  }
  SparseMatrix basis(dim * n, num_free);
  basis.setFromTriplets(triplets.begin(), triplets.end());
  return Elimination(macro_offset(cell, macro_gradient), std::move(basis));
}

}  // namespace tailor
