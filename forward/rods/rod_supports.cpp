#include "forward/rods/rod_supports.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace tailor {

namespace {
void check_vertex(const DiscreteRod& rod, int vertex) {
  if (vertex < 0 || vertex >= rod.num_vertices())
    throw std::out_of_range("rod vertex " + std::to_string(vertex) + " out of range [0, " +
                            std::to_string(rod.num_vertices()) + ")");
}
}  // namespace

std::vector<int> clamped_end_dofs(const DiscreteRod& rod, RodEnd end) {
  if (rod.closed()) throw std::invalid_argument("clamped_end_dofs: a closed rod has no ends");
  const int v0 = end == RodEnd::first ? 0 : rod.num_vertices() - 2;
  const int edge = end == RodEnd::first ? 0 : rod.num_edges() - 1;
  std::vector<int> dofs;
  for (int v = v0; v < v0 + 2; ++v)
    for (int k = 0; k < 3; ++k) dofs.push_back(rod.position_dof(v, k));
  dofs.push_back(rod.twist_dof(edge));
  return dofs;
}

std::vector<int> pinned_vertex_dofs(const DiscreteRod& rod, int vertex) {
  check_vertex(rod, vertex);
  return {rod.position_dof(vertex, 0), rod.position_dof(vertex, 1), rod.position_dof(vertex, 2)};
}

Eigen::VectorXd lumped_vertex_masses(const DiscreteRod& rod, const CrossSection& section, double density,
                                     const Eigen::VectorXd& radius, const Eigen::VectorXd& rest_length) {
  if (radius.size() != rod.num_edges() || rest_length.size() != rod.num_edges())
    throw std::invalid_argument("lumped_vertex_masses: radius and rest_length need one value per edge");
  Eigen::VectorXd m = Eigen::VectorXd::Zero(rod.num_vertices());
  for (int j = 0; j < rod.num_edges(); ++j) {
    const double edge_mass = density * section.area_coefficient() * radius[j] * radius[j] * rest_length[j];
    m[j] += 0.5 * edge_mass;
    m[rod.edge_end(j)] += 0.5 * edge_mass;
  }
  return m;
}

Eigen::VectorXd lumped_twist_inertias(const DiscreteRod& rod, const CrossSection& section, double density,
                                      const Eigen::VectorXd& radius, const Eigen::VectorXd& rest_length) {
  if (radius.size() != rod.num_edges() || rest_length.size() != rod.num_edges())
    throw std::invalid_argument("lumped_twist_inertias: radius and rest_length need one value per edge");
  const double polar = section.bending_coefficient1() + section.bending_coefficient2();
  Eigen::VectorXd inertia(rod.num_edges());
  for (int j = 0; j < rod.num_edges(); ++j) {
    const double r2 = radius[j] * radius[j];
    inertia[j] = density * polar * r2 * r2 * rest_length[j];
  }
  return inertia;
}

void add_rod_mass_diagonal(const DiscreteRod& rod, const CrossSection& section, double density,
                           const Eigen::VectorXd& radius, const Eigen::VectorXd& rest_length, Vector& diagonal) {
  if (diagonal.size() < rod.dof_end()) throw std::invalid_argument("add_rod_mass_diagonal: diagonal too short");
  const Eigen::VectorXd m = lumped_vertex_masses(rod, section, density, radius, rest_length);
  const Eigen::VectorXd J = lumped_twist_inertias(rod, section, density, radius, rest_length);
  for (int v = 0; v < rod.num_vertices(); ++v) diagonal.segment<3>(rod.position_dof(v, 0)).setConstant(m[v]);
  for (int j = 0; j < rod.num_edges(); ++j) diagonal[rod.twist_dof(j)] = J[j];
}

void add_gravity_forces(const DiscreteRod& rod, const Eigen::VectorXd& vertex_masses,
                        const Eigen::Vector3d& g, Vector& forces) {
  for (int v = 0; v < rod.num_vertices(); ++v)
    forces.segment<3>(rod.position_dof(v, 0)) += vertex_masses[v] * g;
}

void add_point_load(const DiscreteRod& rod, int vertex, const Eigen::Vector3d& force, Vector& forces) {
  check_vertex(rod, vertex);
  forces.segment<3>(rod.position_dof(vertex, 0)) += force;
}

void add_twisting_moment(const DiscreteRod& rod, int edge, double moment, Vector& forces) {
  if (edge < 0 || edge >= rod.num_edges())
    throw std::out_of_range("rod edge " + std::to_string(edge) + " out of range");
  forces[rod.twist_dof(edge)] += moment;
}

std::vector<rigid::FreeMotion> free_rod_motions(const std::vector<const DiscreteRod*>& rods, const Vector& x,
                                                const std::vector<int>& held, Eigen::Vector3d& centre) {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const DiscreteRod* rod : rods)
    for (int v = 0; v < rod->num_vertices(); ++v) {
      low = low.cwiseMin(rod->position(x, v));
      high = high.cwiseMax(rod->position(x, v));
    }
  centre = 0.5 * (low + high);
  Matrix motions = Matrix::Zero(x.size(), 6);
  for (const DiscreteRod* rod : rods) {
    for (int v = 0; v < rod->num_vertices(); ++v)
      for (int k = 0; k < 3; ++k) {
        motions.block<3, 1>(rod->position_dof(v, 0), k) = Eigen::Vector3d::Unit(k);
        motions.block<3, 1>(rod->position_dof(v, 0), 3 + k) =
            Eigen::Vector3d::Unit(k).cross(rod->position(x, v) - centre);
      }
    // Turning with the body, the material frame spins about t^j by a . t^j relative to the
    // time-parallel reference frame (which does not spin about the tangent).
    for (int j = 0; j < rod->num_edges(); ++j)
      motions.block<1, 3>(rod->twist_dof(j), 3) = rod->edge_vector(x, j).normalized().transpose();
  }
  return rigid::free_motions(motions, held, (high - low).norm());
}

}  // namespace tailor
