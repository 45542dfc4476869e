// Mesh bodies in periodic cells (forward/interlocking/periodic_mesh_*.hpp): a chain of meshed rings
// against the closed-form lock-up spacing, the square ring net against the implicit tori, zero
// force at F = I, no intersection in any reported state (exact triangle-triangle test), and the
// derivative check of the cell energy with mesh contact in the master DOFs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "adjoint/derivative_check.hpp"
#include "forward/interlocking/cell_patterns.hpp"
#include "forward/interlocking/periodic_mesh_contact.hpp"
#include "forward/interlocking/strain_boundary.hpp"

namespace tailor::interlocking::periodic_mesh_test {
namespace {

const tori::TorusShape kRing{1.0, 0.2};
constexpr double kSpacing = 1.5, kActivation = 1e-3;

RigidCellSpec meshed_chain(int major, int minor) {
  RigidCellSpec spec = with_torus_meshes(chain_cell(kRing, kRing, kSpacing, 10.0 * kSpacing), major, minor);
  spec.activation_distance = kActivation;
  return spec;
}

LimitOptions fine_options() {
  LimitOptions o;
  o.tolerance = 1e-6;
  o.max_strain = 0.3;
  return o;
}

void expect_no_intersection(const PeriodicRigidCell& cell, const LimitPoint& p) {
  const MeshIntersectionReport r = check_mesh_intersections(cell, cell.full_state(p.y, p.deformation));
  EXPECT_TRUE(r.apart()) << "angle " << p.angle << ": " << r.intersecting << " of " << r.triangle_pairs
                         << " triangle pairs meet";
  EXPECT_GT(r.triangle_pairs, 0);  // the check looked at the touching triangles
}

// Reference (closed form, Tang et al. 2023): two interlocked rings pulled apart stop at a centre
// spacing 2 (R - r), here 2 (R - r) - d_hat / 2 by the lock-up criterion; the chain's stretch
// limit is that over s0, minus 1. The mesh moves each surface by at most its chordal bound
// delta, so the meshed limit lies within 2 delta / s0 of it, and delta ~ 1 / segments^2 (the
// table over resolutions, converging to the closed form, is interlocking_bench --mesh-chain).
TEST(PeriodicMeshCell, ChainOfMeshedRingsLocksAtTheClosedFormSpacing) {
  const double closed_form = (2.0 * (kRing.major_radius - kRing.minor_radius) - 0.5 * kActivation) / kSpacing - 1.0;
  for (const auto& [major, minor] : {std::pair{12, 6}}) {
    const PeriodicRigidCell cell(meshed_chain(major, minor));
    const std::vector<LimitPoint> b = strain_space_boundary(cell, {uniaxial_path(0.0)}, fine_options());
    ASSERT_TRUE(b[0].locked) << b[0].status;
    const double bound = 2.0 * torus_chordal_bound(kRing, major, minor) / kSpacing;
    const double error = std::abs(b[0].strain - closed_form);
    std::printf("meshed chain %d x %d: limit %.7f, closed form %.7f, error %.2e, bound %.2e, %d solves\n", major,
                minor, b[0].strain, closed_form, error, bound, b[0].solves);
    EXPECT_LE(error, bound);
    EXPECT_LT(error, 1e-3 * closed_form);  // far inside the bound: the limit is the torus's
    expect_no_intersection(cell, b[0]);
  }
}

// F = I: the rest placement is an equilibrium with no pair within d_hat: zero energy and force.
TEST(PeriodicMeshCell, IdentityGivesZeroForce) {
  RigidCellSpec spec = with_torus_meshes(square_ring_cell(kRing, kRing, kRing, kSpacing), 16, 8);
  spec.activation_distance = kActivation;
  const PeriodicRigidCell cell(spec);
  const Vector y = rest_equilibrium(cell);
  const Vector x = cell.full_state(y, Eigen::Matrix2d::Identity());
  const ReducedContact c = reduced_contact(cell, x, true);
  EXPECT_EQ(c.energy, 0.0);
  EXPECT_EQ(c.gradient.lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_TRUE(contact_pair_forces(cell, x).empty());
  EXPECT_GT(smallest_distance(cell, x, 1.0), kActivation);
}

// Reference: the implicit tori's limits of the same net (their own closed form is checked in
// boundary_validation_test); meshed rings agree within the two rings' chordal bounds over s0.
TEST(PeriodicMeshCell, SquareNetMatchesTheImplicitTori) {
  RigidCellSpec tori_spec = square_ring_cell(kRing, kRing, kRing, kSpacing);
  tori_spec.activation_distance = kActivation;
  const PeriodicRigidCell tori_cell(tori_spec);
  const int major = 12, minor = 6;
  const PeriodicRigidCell mesh_cell(with_torus_meshes(tori_spec, major, minor));
  const std::vector<LoadPath> paths = {principal_path(0.5 * M_PI)};
  LimitOptions options = fine_options();
  options.tolerance = 1e-5;
  const std::vector<LimitPoint> t = strain_space_boundary(tori_cell, paths, options);
  const std::vector<LimitPoint> m = strain_space_boundary(mesh_cell, paths, options);
  const double bound = 2.0 * torus_chordal_bound(kRing, major, minor) / kSpacing + 2e-5;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    ASSERT_TRUE(t[k].locked && m[k].locked) << m[k].status;
    std::printf("square net %.0f deg: tori %.6f, meshed %.6f (diff %.2e, bound %.2e), %zu active pairs\n",
                paths[k].angle * 180.0 / M_PI, t[k].strain, m[k].strain, m[k].strain - t[k].strain, bound,
                m[k].active.size());
    EXPECT_LE(std::abs(m[k].strain - t[k].strain), bound);
    EXPECT_FALSE(m[k].active.empty());
    expect_no_intersection(mesh_cell, m[k]);
  }
}

// The reduced cell energy E(y) = B(x0(F) + S y) as an EnergyTerm over the master DOFs y, for
// check_energy_term; `gradient_scale` != 1 makes a deliberately wrong gradient.
class ReducedCellEnergy final : public EnergyTerm {
 public:
  ReducedCellEnergy(const PeriodicRigidCell& cell, const Eigen::Matrix2d& F, double gradient_scale = 1.0)
      : cell_(cell), F_(F), scale_(gradient_scale) {}
  std::string name() const override { return "mesh_cell_contact"; }
  void evaluate(const Vector& y, const Vector& p, const EnergyRequest& request) const override {
    (void)p;
    const ReducedContact c =
        reduced_contact(cell_, cell_.full_state(y, F_), request.hessian_values != nullptr, request.hessian_mode);
    if (request.value) *request.value += c.energy;
    if (request.gradient) *request.gradient += scale_ * c.gradient;
    if (request.hessian_values)
      for (Eigen::Index j = 0, k = 0; j < c.hessian.cols(); ++j)
        for (Eigen::Index i = 0; i < c.hessian.rows(); ++i) request.hessian_values[k++] = c.hessian(i, j);
  }
  void hessian_pattern(HessianPattern& pattern) const override {
    for (int j = 0; j < cell_.num_free(); ++j)
      for (int i = 0; i < cell_.num_free(); ++i) pattern.push_back({i, j});
  }

 private:
  const PeriodicRigidCell& cell_;
  Eigen::Matrix2d F_;
  double scale_;
};

// At a locked state of the meshed chain (point-triangle and edge-edge pairs within d_hat), the
// energy's gradient and Hessian in the masters' free DOFs match central differences; a gradient
// 0.1 % off fails the same check.
TEST(PeriodicMeshCell, CellEnergyPassesTheDerivativeCheck) {
  const PeriodicRigidCell cell(meshed_chain(12, 6));
  LimitOptions options = fine_options();
  options.tolerance = 1e-4;
  const LimitPoint p = strain_space_boundary(cell, {uniaxial_path(0.0)}, options)[0];
  ASSERT_TRUE(p.locked);
  // Off the equilibrium (where the gradient vanishes), every pair still within d_hat.
  Vector y = p.y;
  for (Eigen::Index i = 0; i < y.size(); ++i) y[i] += 2e-5 * std::sin(1.0 + 3.0 * static_cast<double>(i));
  const PeriodicMeshContact& mesh = *cell.mesh_contact();
  const Vector x = cell.full_state(y, p.deformation);
  ASSERT_GT(smallest_distance(cell, x, kActivation), 0.0);
  int point_triangle = 0, edge_edge = 0;
  mesh.term().potential().for_each_active(
      mesh.term().bodies().positions(mesh.contact_state(x)), false, [&](const contact::ActivePair& a) {
        (a.kind == contact::PairKind::point_triangle ? point_triangle : edge_edge) += 1;
      });
  std::printf("derivative check state: %d point-triangle and %d edge-edge pairs within d_hat\n", point_triangle,
              edge_edge);
  EXPECT_GT(point_triangle + edge_edge, 0);
  DerivativeCheckOptions check;
  check.state_scale = 1e-4;  // steps of 1e-7 .. 1e-9 keep every pair apart and within d_hat
  check.initial_step = 1e-3;
  const EnergyTermCheck good = check_energy_term(ReducedCellEnergy(cell, p.deformation), y, Vector(), check);
  EXPECT_TRUE(good.passed()) << good.table();
  const EnergyTermCheck wrong =
      check_energy_term(ReducedCellEnergy(cell, p.deformation, 1.001), y, Vector(), check);
  EXPECT_FALSE(wrong.passed()) << wrong.table();
}

// The intersection check sees a crossing: the chain's upright ring pushed through the flat one
// (its core through the flat ring's), and exact orientation signs on coplanar points.
TEST(PeriodicMeshCell, IntersectionCheckSeesCrossings) {
  const PeriodicRigidCell cell(meshed_chain(12, 6));
  Vector x = cell.full_state(cell.rest_free_state(), Eigen::Matrix2d::Identity());
  EXPECT_TRUE(check_mesh_intersections(cell, x).apart());
  x[6] = 0.0;  // master 1 (the upright ring) centred on the flat one: both cores pass (+-1, 0, 0)
  const MeshIntersectionReport crossing = check_mesh_intersections(cell, x);
  EXPECT_GT(crossing.intersecting, 0);
  long fallbacks = 0;
  const Eigen::Vector3d a(0.1, 0.2, 0.0), b(0.7, 0.3, 0.0), c(0.3, 0.9, 0.0);
  EXPECT_EQ(exact_orientation(a, b, c, Eigen::Vector3d(0.5, 0.5, 0.0), &fallbacks), 0);
  EXPECT_EQ(fallbacks, 1);
  // A point 1e-300 off the plane of three points: the orientation is decided, and its sign flips.
  EXPECT_EQ(exact_orientation(a, b, c, Eigen::Vector3d(0.5, 0.5, 1e-300)),
            -exact_orientation(a, b, c, Eigen::Vector3d(0.5, 0.5, -1e-300)));
  EXPECT_NE(exact_orientation(a, b, c, Eigen::Vector3d(0.5, 0.5, 1e-300)), 0);
}

// Meshes from files: an OFF tetrahedron is read, a quad face and a bad index are refused with the
// file and line.
TEST(PeriodicMeshCell, ReadsOffAndObjAndRefusesBadFiles) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tailor_periodic_mesh_test";
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const auto tet = read_element_mesh(write("tet.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n"
                                                      "3 0 3 2\n3 1 2 3\n"));
  EXPECT_EQ(tet->faces.rows(), 4);
  const auto obj = read_element_mesh(write("tet.obj", "# t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\n"
                                                      "f 1/1 2/2 4/4\nf 1 4 3\nf 2 3 4\n"));
  EXPECT_EQ(obj->vertices.rows(), 4);
  EXPECT_THROW(read_element_mesh(write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")),
               std::runtime_error);
  try {
    read_element_mesh(write("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n"));
    FAIL() << "accepted an index beyond the vertices";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj:3"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tailor::interlocking::periodic_mesh_test
