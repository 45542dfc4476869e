#include "forward/homogenization/rod_network_cell.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/core/assembler.hpp"
#include "forward/core/timing.hpp"
#include "forward/homogenization/linear_homogenization.hpp"
#include "forward/rods/bending_term.hpp"
#include "forward/rods/rigid_joint_term.hpp"
#include "forward/rods/rod_parameters.hpp"
#include "forward/rods/stretching_term.hpp"
#include "forward/rods/twisting_term.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

void RodNetwork::validate() const {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("RodNetwork: " + what); };
  if (!(lattice.determinant() > 0.0))
    fail("the lattice vectors must be right-handed and independent (det > 0)");
  if (joints.rows() == 0) fail("no joints");
  if (bars.empty()) fail("no bars");
  if (!(youngs_modulus > 0.0) || !(shear_modulus > 0.0) || !std::isfinite(youngs_modulus) ||
      !std::isfinite(shear_modulus))
    fail("the Young's and shear moduli must be positive");
  if (!(radius > 0.0) || !std::isfinite(radius)) fail("the radius must be positive");
  if (edges_per_bar < 1) fail("edges_per_bar must be at least 1");
  std::vector<int> degree(static_cast<std::size_t>(joints.rows()), 0);
  for (std::size_t b = 0; b < bars.size(); ++b) {
    const RodNetworkBar& bar = bars[b];
    if (bar.from < 0 || bar.from >= joints.rows() || bar.to < 0 || bar.to >= joints.rows())
      fail("bar " + std::to_string(b) + " names a joint that does not exist (there are " +
           std::to_string(joints.rows()) + ")");
    const int i = static_cast<int>(b);
    if (!((bar_end(i) - bar_start(i)).norm() > 1e-12 * std::sqrt(cell_area())))
      fail("bar " + std::to_string(b) + " has zero length");
    ++degree[static_cast<std::size_t>(bar.from)];
    ++degree[static_cast<std::size_t>(bar.to)];
  }
  for (std::size_t j = 0; j < degree.size(); ++j)
    if (degree[j] == 0) fail("joint " + std::to_string(j) + " is on no bar");
}

double RodNetwork::cell_area() const { return lattice.determinant(); }

Eigen::Vector3d RodNetwork::bar_start(int bar) const {
  const RodNetworkBar& b = bars[static_cast<std::size_t>(bar)];
  return Eigen::Vector3d(joints(b.from, 0), joints(b.from, 1), 0.0);
}

Eigen::Vector3d RodNetwork::bar_end(int bar) const {
  const RodNetworkBar& b = bars[static_cast<std::size_t>(bar)];
  const Eigen::Vector2d end = joints.row(b.to).transpose() + lattice * b.shift.cast<double>();
  return Eigen::Vector3d(end[0], end[1], 0.0);
}

RodNetwork square_rod_lattice(double cell_size, double radius, double youngs_modulus, double shear_modulus,
                              int edges_per_bar) {
  RodNetwork n;
  n.lattice = cell_size * Eigen::Matrix2d::Identity();
  n.joints = Eigen::MatrixX2d::Zero(1, 2);
  n.bars = {{0, 0, Eigen::Vector2i(1, 0)}, {0, 0, Eigen::Vector2i(0, 1)}};
  n.youngs_modulus = youngs_modulus;
  n.shear_modulus = shear_modulus;
  n.radius = radius;
  n.edges_per_bar = edges_per_bar;
  return n;
}

RodNetwork honeycomb_rod_lattice(double wall_length, double radius, double youngs_modulus,
                                 double shear_modulus, int edges_per_bar) {
  const double l = wall_length, s3 = std::sqrt(3.0);
  RodNetwork n;
  n.lattice << s3 * l, 0.5 * s3 * l, 0.0, 1.5 * l;
  n.joints.resize(2, 2);
  n.joints << 0.0, 0.0, 0.0, l;
  n.bars = {{0, 1, Eigen::Vector2i(0, 0)}, {1, 0, Eigen::Vector2i(0, 1)}, {1, 0, Eigen::Vector2i(-1, 1)}};
  n.youngs_modulus = youngs_modulus;
  n.shear_modulus = shear_modulus;
  n.radius = radius;
  n.edges_per_bar = edges_per_bar;
  return n;
}

RodNetworkCell::RodNetworkCell(RodNetwork network) : network_(std::move(network)) {
  network_.validate();
  const int m = network_.edges_per_bar;
  const int num_bars = static_cast<int>(network_.bars.size());
  const int num_joints = static_cast<int>(network_.joints.rows());
  const int per_bar = 3 * (m + 1) + m;
  const int joint_offset = num_bars * per_bar;
  const int num_dofs = joint_offset + 3 * num_joints;
  model_ = std::make_unique<Model>(num_dofs);

  // Rods: bar b owns DOFs [b per_bar, (b + 1) per_bar): positions, then twists.
  for (int b = 0; b < num_bars; ++b) {
    Eigen::MatrixX3d points(m + 1, 3);
    const Eigen::Vector3d start = network_.bar_start(b), end = network_.bar_end(b);
    for (int v = 0; v <= m; ++v)
      points.row(v) = (start + (end - start) * (static_cast<double>(v) / m)).transpose();
    // First director along z: m1 out of the plane for every bar, so in-plane bending is about m1.
    rods_.push_back(std::make_shared<DiscreteRod>(points, b * per_bar, b * per_bar + 3 * (m + 1),
                                                  Eigen::Vector3d::UnitZ()));
    blocks_.push_back(
        add_rod_parameters(model_->parameter_layout(), *rods_.back(), "bar" + std::to_string(b)));
  }
  RodMaterial material;
  material.youngs_modulus = network_.youngs_modulus;
  material.shear_modulus = network_.shear_modulus;
  material.radius = network_.radius;
  parameters_ = Vector::Zero(model_->parameter_layout().size());
  rest_ = Vector::Zero(num_dofs);
  for (int b = 0; b < num_bars; ++b) {
    write_rod_parameters(*rods_[b], blocks_[b], material, parameters_);
    rods_[b]->write_rest_state(rest_);
    model_->add(std::make_unique<RodStretchingTerm>(rods_[b], material.section, blocks_[b]));
    model_->add(std::make_unique<RodBendingTerm>(rods_[b], material.section, blocks_[b]));
    model_->add(std::make_unique<RodTwistingTerm>(rods_[b], material.section, blocks_[b]));
  }
  // Rigid joints: each bar's first edge joins joint `from`, its last edge joint `to` (the image
  // joint shares the master's rotation DOFs). Stress-free at rest.
  for (int j = 0; j < num_joints; ++j) {
    auto joint = std::make_unique<RodRigidJointTerm>(joint_offset + 3 * j);
    for (int b = 0; b < num_bars; ++b) {
      const double edge_length = rods_[b]->rest_lengths()[0];
      const Eigen::Vector3d stiffness = rigid_joint_stiffness(
          material.section, material.youngs_modulus, material.shear_modulus, material.radius, edge_length);
      if (network_.bars[b].from == j) joint->add_member(rods_[b], 0, stiffness, rest_);
      if (network_.bars[b].to == j) joint->add_member(rods_[b], m - 1, stiffness, rest_);
    }
    model_->add(std::move(joint));
  }

  // The periodic elimination (header): joint j > 0 has three fluctuation unknowns, joint 0 is the
  // anchor; interior vertices, twists and joint rotations are free.
  std::vector<Triplet> basis;
  int free = 0;
  std::vector<int> joint_column(static_cast<std::size_t>(num_joints), -1);
  for (int j = 1; j < num_joints; ++j) {
    joint_column[static_cast<std::size_t>(j)] = free;
    free += 3;
  }
  const auto tie = [&basis](int first_dof, int column) {
    if (column < 0) return;  // the anchor
    for (int k = 0; k < 3; ++k) basis.emplace_back(first_dof + k, column + k, 1.0);
  };
  for (int b = 0; b < num_bars; ++b) {
    const DiscreteRod& rod = *rods_[b];
    for (int v = 0; v <= m; ++v) {
      position_dofs_.push_back(rod.position_dof(v, 0));
      rest_positions_.push_back(rod.rest_positions().row(v).transpose());
      if (v == 0) {
        tie(rod.position_dof(v, 0), joint_column[static_cast<std::size_t>(network_.bars[b].from)]);
      } else if (v == m) {
        tie(rod.position_dof(v, 0), joint_column[static_cast<std::size_t>(network_.bars[b].to)]);
      } else {
        tie(rod.position_dof(v, 0), free);
        free += 3;
      }
    }
    for (int e = 0; e < m; ++e) basis.emplace_back(rod.twist_dof(e), free++, 1.0);
  }
  for (int k = 0; k < 3 * num_joints; ++k) basis.emplace_back(joint_offset + k, free++, 1.0);
  SparseMatrix S(num_dofs, free);
  S.setFromTriplets(basis.begin(), basis.end());
  model_->set_elimination(Elimination(macro_offset(Matrix::Zero(2, 2)), S));
  assembler_ = std::make_unique<ReducedAssembler>(*model_);
  hessian_ = assembler_->hessian_pattern_matrix();
  factor_ = std::make_unique<SparseCholesky>();
  factor_->analyze(hessian_);
}

RodNetworkCell::~RodNetworkCell() = default;

int RodNetworkCell::num_free() const { return model_->elimination().num_free(); }

Vector RodNetworkCell::macro_offset(const Matrix& macro_gradient) const {
  if (macro_gradient.rows() != 2 || macro_gradient.cols() != 2)
    throw std::invalid_argument("RodNetworkCell::macro_offset: H must be 2 x 2 (in-plane)");
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F.topLeftCorner<2, 2>() += macro_gradient;
  Vector x0 = Vector::Zero(model_->num_dofs());
  for (std::size_t v = 0; v < position_dofs_.size(); ++v)
    x0.segment<3>(position_dofs_[v]) = F * rest_positions_[v];
  return x0;
}

RodNetworkHomogenization RodNetworkCell::solve() {
  RodNetworkHomogenization result;
  Elimination& elimination = model_->elimination();
  const Vector y0 = Vector::Zero(num_free());
  auto t0 = Clock::now();
  // The cell problems are linear about the stress-free rest state: K is the exact Hessian there.
  elimination.set_offset(rest_);
  assembler_->evaluate(y0, parameters_, nullptr, nullptr, &hessian_);
  result.assembly_seconds = seconds_since(t0);
  t0 = Clock::now();
  const FactorizationResult factorization = factor_->factorize(hessian_);
  if (!factorization.success || !factorization.positive_definite)
    throw std::runtime_error(
        "RodNetworkCell: the periodic stiffness matrix is not positive definite (a mechanism?) (" +
        factorization.message + ")");
  result.factorization_seconds = seconds_since(t0);

  t0 = Clock::now();
  // The full K at rest, once (the terms' pattern slots, as Model::hessian_times reads them), so
  // that the six products K u below are sparse products and not six Hessian evaluations.
  std::vector<Triplet> entries;
  for (const auto& term : model_->terms()) {
    HessianPattern pattern;
    term->hessian_pattern(pattern);
    std::vector<double> values(pattern.size(), 0.0);
    EnergyRequest request;
    request.hessian_values = values.data();
    term->evaluate(rest_, parameters_, request);
    for (std::size_t k = 0; k < pattern.size(); ++k)
      entries.emplace_back(pattern[k].row, pattern[k].col, values[k]);
  }
  SparseMatrix K(model_->num_dofs(), model_->num_dofs());
  K.setFromTriplets(entries.begin(), entries.end());
  const int cases = voigt_size(2);
  Matrix rhs(num_free(), cases);
  std::vector<Vector> affine(static_cast<std::size_t>(cases));
  for (int I = 0; I < cases; ++I) {
    affine[I] = macro_offset(unit_macro_strain(2, I)) - rest_;
    rhs.col(I) = -elimination.reduce(K * affine[I]);
  }
  const Matrix fluctuations = factor_->solve_columns(rhs);
  std::vector<Vector> displacement(static_cast<std::size_t>(cases)), force(static_cast<std::size_t>(cases));
  for (int I = 0; I < cases; ++I) {
    displacement[I] = affine[I] + elimination.expand_direction(fluctuations.col(I));
    force[I] = K * displacement[I];
    result.states.push_back(rest_ + displacement[I]);
  }
  result.stiffness.resize(cases, cases);
  for (int I = 0; I < cases; ++I)
    for (int J = 0; J < cases; ++J)
      result.stiffness(I, J) = displacement[I].dot(force[J]) / network_.cell_area();
  result.solve_seconds = seconds_since(t0);
  result.symmetry_error = (result.stiffness - result.stiffness.transpose()).cwiseAbs().maxCoeff() /
                          result.stiffness.cwiseAbs().maxCoeff();
  return result;
}

}  // namespace tailor
