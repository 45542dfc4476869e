// The derivative checks used in this folder must be able to fail: objectives with slightly
// wrong derivatives are rejected, and not reported as vanishing.
#include <gtest/gtest.h>

#include "../support/fem_fixtures.hpp"
#include "objective_checks.hpp"
#include "objectives/handle_objective.hpp"
#include "objectives/material_smoothness.hpp"
#include "objectives/target_positions.hpp"

namespace tailor::failing_check_test {
namespace {

using testing::random_vector;

// Forwards to an objective but scales every derivative by (1 + error): value stays exact.
class Skewed final : public Objective {
 public:
  Skewed(ObjectivePtr inner, double gradient_error, double hessian_error, double jacobian_error)
      : inner_(std::move(inner)), g_(gradient_error), h_(hessian_error), j_(jacobian_error) {}
  std::string name() const override { return "skewed(" + inner_->name() + ")"; }
  double value(const Vector& x, const Vector& p) const override { return inner_->value(x, p); }
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override {
    Vector g = Vector::Zero(gx.size());
    inner_->add_gradient_x(x, p, g);
    gx += (1 + g_) * g;
  }
  void add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const override {
    Vector g = Vector::Zero(gp.size());
    inner_->add_gradient_p(x, p, g);
    gp += (1 + g_) * g;
  }
  bool has_second_derivatives() const override { return inner_->has_second_derivatives(); }
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override {
    Vector hx = Vector::Zero(out_x.size()), hp = Vector::Zero(out_p.size());
    inner_->add_hessian_times(x, p, dx, dp, hx, hp);
    out_x += (1 + h_) * hx;
    out_p += (1 + h_) * hp;
  }
  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return inner_->num_residuals(); }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                 SparseMatrix* dr_dp) const override {
    inner_->residuals(x, p, r, dr_dx, dr_dp);
    if (dr_dx) *dr_dx *= 1 + j_;
    if (dr_dp) *dr_dp *= 1 + j_;
  }

 private:
  ObjectivePtr inner_;
  double g_, h_, j_;
};

TEST(FailingChecks, SlightlyWrongDerivativesAreRejected) {
  const Mesh mesh = testing::small_mesh(3);
  const Vector x = testing::rest_state(mesh) + random_vector(3 * mesh.num_vertices(), 71, 0.05);
  const Vector p = testing::heterogeneous_parameters(mesh, 10.0, 0.3);
  const auto positions = std::make_shared<TargetPositions>(3, std::vector<int>{1, 3}, Matrix::Ones(2, 3));
  const auto smoothness = std::make_shared<MaterialSmoothness>(
      mesh, 0, 1.0, MaterialSmoothnessOptions{AdjacencyWeighting::unit, true});
  const Vector dx = random_vector(x.size(), 73);
  const Vector dp = testing::relative_direction(p, 79);
  const Vector no_dx = Vector::Zero(x.size()), no_dp = Vector::Zero(p.size());

  // Sanity: the unperturbed objectives pass.
  ASSERT_TRUE(testing::check_gradient_x(*positions, x, p, dx).passed);
  ASSERT_TRUE(testing::check_gradient_p(*smoothness, x, p, dp).passed);

  auto expect_failure = [](const DerivativeCheck& c) {
    EXPECT_FALSE(c.passed) << c.quantity << ": " << c.message;
    EXPECT_FALSE(c.vanishing) << c.quantity;
    EXPECT_GT(c.best_error, 1e-5) << c.quantity;
  };
  const Skewed bad_gradient_x(positions, 1e-4, 0, 0), bad_gradient_p(smoothness, 1e-4, 0, 0);
  expect_failure(testing::check_gradient_x(bad_gradient_x, x, p, dx));
  expect_failure(testing::check_gradient_p(bad_gradient_p, x, p, dp));
  // A Hessian product off by 1e-4 relative, against exact gradients.
  const Skewed bad_hessian_x(positions, 0, 1e-4, 0), bad_hessian_p(smoothness, 0, 1e-4, 0);
  expect_failure(testing::check_hessian(bad_hessian_x, x, p, dx, no_dp));
  expect_failure(testing::check_hessian(bad_hessian_p, x, p, no_dx, dp));
  const Skewed bad_jacobian(smoothness, 0, 0, 1e-4);
  expect_failure(testing::check_residual_jacobians(bad_jacobian, x, p, no_dx, dp));
}

// The handle objective's checks fail too when its derivatives are off by 1e-4 relative.
TEST(FailingChecks, SlightlyWrongHandleDerivativesAreRejected) {
  const Mesh mesh = testing::small_mesh(3);
  const Vector x = testing::rest_state(mesh) + random_vector(3 * mesh.num_vertices(), 83, 0.05);
  Vector p = testing::heterogeneous_parameters(mesh, 10.0, 0.3);
  const int offset = static_cast<int>(p.size());
  Handle handle;
  handle.vertices = {1, 3};
  handle.target_force = Eigen::Vector3d(0.5, -1.0, 2.0);
  handle.target_displacement = Eigen::RowVector3d(0.1, 0.0, -0.2);
  std::vector<std::shared_ptr<const EnergyTerm>> terms{
      std::shared_ptr<const EnergyTerm>(testing::elastic_term<3>(mesh, MaterialKind::neo_hookean))};
  const auto handles = std::make_shared<HandleObjective>(terms, static_cast<int>(x.size()), 3,
                                                         std::vector<Handle>{handle}, offset);
  p.conservativeResize(offset + handles->displacement_size());
  p.tail(handles->displacement_size()) = random_vector(handles->displacement_size(), 89, 0.1);
  const Vector dx = random_vector(x.size(), 97);
  const Vector dp = testing::relative_direction(p, 101);
  ASSERT_TRUE(testing::check_gradient_x(*handles, x, p, dx).passed);
  ASSERT_TRUE(testing::check_gradient_p(*handles, x, p, dp).passed);
  const Skewed bad(handles, 1e-4, 0, 1e-4);
  for (const DerivativeCheck& c :
       {testing::check_gradient_x(bad, x, p, dx), testing::check_gradient_p(bad, x, p, dp),
        testing::check_residual_jacobians(bad, x, p, dx, dp)}) {
    EXPECT_FALSE(c.passed) << c.quantity << ": " << c.message;
    EXPECT_FALSE(c.vanishing) << c.quantity;
  }
}

}  // namespace
}  // namespace tailor::failing_check_test
