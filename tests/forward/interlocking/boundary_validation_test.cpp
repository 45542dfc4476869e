// Strain-space boundaries of shipped patterns against references: the square ring net's stretch
// limits (closed form of its chains), a 2 x 2 supercell against the 1 x 1 cell, the same tiling
// with other lattice vectors, and the independent clearance check at every limit state.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "adjoint/taylor_test.hpp"
#include "forward/interlocking/cell_patterns.hpp"
#include "forward/interlocking/interpenetration_check.hpp"
#include "forward/interlocking/limit_sensitivity.hpp"
#include "forward/interlocking/strain_boundary.hpp"

namespace tailor::interlocking::boundary_validation_test {
namespace {

const tori::TorusShape kRing{1.0, 0.2};
constexpr double kSpacing = 1.5;

std::vector<LoadPath> principal_paths(const std::vector<double>& degrees) {
  std::vector<LoadPath> out;
  for (double a : degrees) out.push_back(principal_path(a * M_PI / 180.0));
  return out;
}

void expect_apart(const PeriodicRigidCell& cell, const LimitPoint& p) {
  const ClearanceReport c = check_clearance(cell, cell.full_state(p.y, p.deformation), 1 << 14);
  EXPECT_TRUE(c.apart()) << "angle " << p.angle << ": certified clearance " << c.min_lower;
}

// Reference (closed form): along x the net is chains node - x link - node; each pair locks at a
// centre spacing (R_n - r_n) + (R_l - r_l) - d_hat / 2, so eps_xx = that / s0 - 1; same along y.
TEST(InterlockingBoundary, SquareRingNetStretchesToItsChainLimits) {
  const tori::TorusShape link_x{1.1, 0.2};
  const PeriodicRigidCell cell(square_ring_cell(kRing, link_x, kRing, kSpacing));
  LimitOptions options;
  const std::vector<LimitPoint> b = strain_space_boundary(cell, principal_paths({0.0, 90.0}), options);
  const double d = 0.5 * cell.activation_distance();
  const double ex = (0.8 + 0.9 - d) / kSpacing - 1.0, ey = (0.8 + 0.8 - d) / kSpacing - 1.0;
  std::printf("square net: eps_xx limit %.10f (closed form %.10f), eps_yy %.10f (%.10f); %d + %d solves\n",
              b[0].strain, ex, b[1].strain, ey, b[0].solves, b[1].solves);
  ASSERT_TRUE(b[0].locked && b[1].locked);
  EXPECT_NEAR(b[0].strain, ex, 1e-8);
  EXPECT_NEAR(b[1].strain, ey, 1e-8);
  for (const LimitPoint& p : b) expect_apart(cell, p);
}

// The 2 x 2 supercell (12 elements) tiles the plane exactly as the 1 x 1 cell: same limits.
TEST(InterlockingBoundary, SupercellHasTheSameBoundary) {
  const RigidCellSpec one = square_ring_cell(kRing, kRing, kRing, kSpacing);
  const PeriodicRigidCell small(one), big(supercell(one, 2, 2));
  LimitOptions options;
  const std::vector<LoadPath> paths = principal_paths({0.0, 45.0, 135.0});
  const std::vector<LimitPoint> a = strain_space_boundary(small, paths, options);
  const std::vector<LimitPoint> b = strain_space_boundary(big, paths, options);
  for (std::size_t k = 0; k < paths.size(); ++k) {
    std::printf("angle %5.1f: 1x1 %.10f (%s), 2x2 %.10f (%s)\n", paths[k].angle * 180 / M_PI, a[k].strain,
                a[k].status.c_str(), b[k].strain, b[k].status.c_str());
    EXPECT_EQ(a[k].locked, b[k].locked);
    EXPECT_NEAR(a[k].strain, b[k].strain, 2.0 * options.tolerance);
    expect_apart(big, b[k]);
  }
}

// Lattice vectors (t1, t1 + t2) and (t1 + t2, t2) describe the same tiling: the same limits.
TEST(InterlockingBoundary, BoundaryIsInvariantToTheChoiceOfLatticeVectors) {
  const RigidCellSpec base = square_ring_cell(kRing, kRing, kRing, kSpacing);
  Eigen::Matrix2i M;
  M << 1, 1, 0, 1;
  const PeriodicRigidCell a(base), b(relattice(base, M, 2));
  LimitOptions options;
  const std::vector<LoadPath> paths = principal_paths({0.0, 90.0, 200.0});
  const std::vector<LimitPoint> la = strain_space_boundary(a, paths, options);
  const std::vector<LimitPoint> lb = strain_space_boundary(b, paths, options);
  for (std::size_t k = 0; k < paths.size(); ++k) {
    std::printf("angle %5.1f: (t1, t2) %.10f, (t1, t1 + t2) %.10f\n", paths[k].angle * 180 / M_PI, la[k].strain,
                lb[k].strain);
    EXPECT_EQ(la[k].locked, lb[k].locked);
    EXPECT_NEAR(la[k].strain, lb[k].strain, 2.0 * options.tolerance);
  }
}

// The threefold mail locks in every direction of a coarse sweep without interpenetration, with
// the threefold symmetry of its limits in uniaxial stretch (0 and 120 degrees).
TEST(InterlockingBoundary, ThreefoldMailLocksSymmetrically) {
  const PeriodicRigidCell cell(threefold_cell(kRing, kRing, kSpacing));
  LimitOptions options;
  std::vector<LoadPath> paths = {uniaxial_path(0.0), uniaxial_path(2.0 * M_PI / 3.0), uniaxial_path(M_PI / 6.0)};
  const std::vector<LimitPoint> b = strain_space_boundary(cell, paths, options);
  for (const LimitPoint& p : b) {
    std::printf("threefold uniaxial %5.1f deg: %.10f (%s, %zu active)\n", p.angle * 180 / M_PI, p.strain,
                p.status.c_str(), p.active.size());
    EXPECT_TRUE(p.locked);
    expect_apart(cell, p);
  }
  EXPECT_NEAR(b[0].strain, b[1].strain, 2.0 * options.tolerance);
}

// Bending, reference (closed form, two interlocked rings at an angle): a flat rim ring at
// (-s, 0, 0) and (s, 0, 0) on z = kappa x^2 / 2 is tilted by alpha = atan(kappa s) about y; its
// core crosses the free link's plane (xz) at x = -(s - R cos alpha), where its tube runs along y,
// so the link (centred between the two crossings by symmetry) presses both at distance
// R - (s - R cos alpha) - 2 r. That reaches lock_fraction d_hat at
//   cos alpha* = (s - R + 2 r + d_hat / 2) / R,   kappa* = tan(alpha*) / s.
// Downward bending locks at the same |kappa|; bending across the chain (about x) never locks.
// The bisection stops at 1e-4; the augmented Newton (the rim's dx0/ds) locates the limit to
// round-off, so the closed form is met to 1e-10.
TEST(InterlockingBending, ThreeRingChainLocksAtTheClosedFormCurvature) {
  const PeriodicRigidCell cell(ring_chain_patch(kRing, kRing, kSpacing));
  LimitOptions options;
  const Vector y_rest = rest_equilibrium(cell);
  const double alpha = std::acos((kSpacing - 1.0 + 0.4 + 0.5 * cell.activation_distance()) / 1.0);
  const double expected = std::tan(alpha) / kSpacing;
  const LimitPoint up = find_limit(cell, uniaxial_path(0.0), y_rest, options);
  const LimitPoint down = find_limit(cell, principal_path(M_PI), y_rest, options);
  const LimitPoint across = find_limit(cell, uniaxial_path(0.5 * M_PI), y_rest, options);
  std::printf("three-ring chain: bending limit %.12f (down %.12f), closed form %.12f; %d solves, %zu active\n",
              up.strain, down.strain, expected, up.solves, up.active.size());
  ASSERT_TRUE(up.locked && down.locked) << up.status << " / " << down.status;
  EXPECT_TRUE(up.refined && down.refined);
  EXPECT_NEAR(up.strain, expected, 1e-10);
  EXPECT_NEAR(down.strain, expected, 1e-10);
  EXPECT_EQ(up.active.size(), 2u);  // the link against both rim rings
  EXPECT_FALSE(across.locked);
  expect_apart(cell, up);
  expect_apart(cell, down);
}

// Bending, symmetry: a disc patch of the threefold mail centred on a node (the centre node and
// its six links free, the next ring of links and nodes prescribed on the paraboloid) has the
// sixfold symmetry of the tiling, so its single-curvature limits at 0 and 120 degrees are equal
// (30 degrees' differs: there two prescribed rim links collide first); no limit state
// interpenetrates.
TEST(InterlockingBending, ThreefoldPatchBendsSymmetrically) {
  const PeriodicRigidCell cell(disc_patch(threefold_cell(kRing, kRing, kSpacing), 3.2, 0.7));
  int free = 0;
  for (const CellElement& e : cell.spec().elements) free += !e.rim;
  ASSERT_EQ(cell.num_elements(), 19);
  ASSERT_EQ(free, 7);
  LimitOptions options;
  options.initial_step = 0.05;
  options.tolerance = 1e-3;  // small: the three limits take ~150 Newton solves each
  const Vector y_rest = rest_equilibrium(cell);
  std::vector<LimitPoint> b;
  for (double degrees : {0.0, 120.0, 30.0})
    b.push_back(find_limit(cell, uniaxial_path(degrees * M_PI / 180.0), y_rest, options));
  for (const LimitPoint& p : b) {
    std::printf("threefold patch bending %5.1f deg: kappa %.8f (%s, %zu active, %d solves)\n", p.angle * 180 / M_PI,
                p.strain, p.status.c_str(), p.active.size(), p.solves);
    ASSERT_TRUE(p.locked);
    EXPECT_FALSE(p.active.empty());
    expect_apart(cell, p);
  }
  EXPECT_NEAR(b[1].strain, b[0].strain, 2.0 * options.tolerance);
  EXPECT_GT(std::abs(b[2].strain - b[0].strain), 1e-2);
}

// The rim map's derivative dx0/ds (exact, through the normal, the smallest rotation and the
// rotation vector's Jacobian) against central differences of x0 on a curved threefold patch
// whose rim holds flat nodes and upright links (rest rotations about x).
TEST(InterlockingBending, RimMapDerivativeMatchesDifferences) {
  const PeriodicRigidCell cell(disc_patch(threefold_cell(kRing, kRing, kSpacing), 3.2, 0.7));
  LoadPath path = uniaxial_path(0.4);
  path.offset << 0.05, 0.1, -0.02, 0.3;  // an unsymmetric F: the patch uses sym(F) - I
  for (double s : {0.0, 0.2}) {
    const Vector exact = cell.offset_derivative(path.deformation(s), path.direction);
    const double h = 1e-5;
    const Vector fd = (cell.offset(path.deformation(s + h)) - cell.offset(path.deformation(s - h))) / (2.0 * h);
    std::printf("rim map derivative at s = %.1f: |exact| %.6f, |exact - differences| %.3e\n", s, exact.norm(),
                (exact - fd).norm());
    EXPECT_GT(exact.tail(exact.size() - 6).norm(), 0.1);
    EXPECT_LT((exact - fd).norm(), 1e-8 * exact.norm());
  }
}

// s*(radii) of a bending limit, each evaluation continuing the last lock-up state by the
// augmented Newton; the gradient from the implicit function theorem (limit_gradient).
class BendingLimit final : public ReducedFunctional {
 public:
  BendingLimit(const RigidCellSpec& base, const LoadPath& path, double gradient_scale)
      : base_(with_parameters(base, master_radii(base), base.lattice)), path_(path), scale_(gradient_scale) {
    const PeriodicRigidCell cell(base_);
    const LimitPoint p = find_limit(cell, path_, rest_equilibrium(cell));
    EXPECT_TRUE(p.locked && p.refined) << p.status;
    y_ = p.y;
    s_ = p.strain;
    a_ = p.critical_a;
    b_ = p.critical_b;
  }
  int size() const override { return static_cast<int>(master_radii(base_).size()); }
  Vector z0() const { return master_radii(base_); }
  double value(const Vector& z) override { return evaluate(z, nullptr); }
  double value_and_gradient(const Vector& z, Vector& gradient) override { return evaluate(z, &gradient); }

 private:
  double evaluate(const Vector& z, Vector* gradient) {
    const PeriodicRigidCell cell(with_parameters(base_, z, base_.lattice));
    const RefineResult r =
        refine_limit(cell, path_, LimitOptions{}.lock_fraction * cell.activation_distance(), a_, b_, y_, s_);
    if (!r.converged) throw EvaluationError(r.message);
    if (gradient) *gradient = scale_ * limit_gradient(cell, path_, a_, b_, r.y, r.strain).radii;
    return r.strain;
  }
  RigidCellSpec base_;
  LoadPath path_;
  double scale_;
  Vector y_;
  double s_ = 0.0;
  int a_ = -1, b_ = -1;
};

// Taylor test of a bending limit in every radius: a chain patch with unequal rings (rim rings
// R = 1, r = 0.2; link R = 1.05, r = 0.18) bent along the chain, where the tilted rim rings'
// pose derivative enters f_s and c_s; the gradient scaled by 1.001 fails.
TEST(InterlockingBending, BendingLimitDerivativePassesTheTaylorTest) {
  const RigidCellSpec chain = ring_chain_patch(kRing, {1.05, 0.18}, kSpacing);
  TaylorTestOptions options;
  options.initial_step = 1e-4;
  options.seed = 5;
  BendingLimit limit(chain, uniaxial_path(0.0), 1.0);
  const TaylorTestResult r = taylor_test(limit, limit.z0(), options);
  std::printf("%s", r.table().c_str());
  EXPECT_TRUE(r.passed()) << r.message;
  EXPECT_GE(r.rate1, 1.9);
  EXPECT_NEAR(r.rate0, 1.0, 0.1);
  BendingLimit wrong(chain, uniaxial_path(0.0), 1.001);
  EXPECT_FALSE(taylor_test(wrong, wrong.z0(), options).passed());
}

}  // namespace
}  // namespace tailor::interlocking::boundary_validation_test
