// The CPU backends of the descent solver (forward/dynamics/descent_backend.hpp) and the power
// method for the automatic step length.
#include "forward/dynamics/descent_backend.hpp"

#include <cmath>
#include <cstdint>

#include "forward/dynamics/descent_block_jacobi.hpp"
#include "forward/dynamics/descent_vertex_blocks.hpp"

namespace tailor {

double power_largest_eigenvalue(const Model& model, const Vector& p, const Vector& y, int iterations,
                                const std::function<void(const Vector&, Vector&)>& apply_inverse) {
  const Vector x = model.state(y, p);
  const int m = static_cast<int>(y.size());
  Vector v(m), Hv, DinvHv;
  std::uint64_t seed = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < m; ++i) {  // a fixed xorshift sequence in [-1, 1]
    seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
    v[i] = static_cast<double>(seed >> 11) / 4503599627370496.0 - 1.0;
  }
  double lambda = 0.0;
  for (int k = 0; k < iterations; ++k) {
    Hv = model.elimination().reduce(model.hessian_times(x, p, model.elimination().expand_direction(v)));
    apply_inverse(Hv, DinvHv);
    const double norm = DinvHv.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) break;
    lambda = norm / v.norm();
    v = DinvHv / norm;
  }
  return lambda;
}

namespace {

// The loop's vectors on the host, shared by both CPU rules; Pass supplies evaluate/apply_inverse
// and its evaluation type (energy, energy_roundoff, gradient, block inverses).
template <class Pass, class Evaluation>
class HostBackend : public DescentBackend {
 public:
  template <class... Args>
  explicit HostBackend(const Model& model, Args&&... args) : model_(model), pass_(std::forward<Args>(args)...) {}

  Point start(const Vector& p, const Vector& y) override {
    p_ = p;
    prepare(p, y);
    y_ = y;
    previous_ = y;
    pass_.evaluate(y_, current_);
    return point(current_);
  }
  Point try_step(double alpha, double omega, bool& admissible) override {
    pass_.apply_inverse(current_, current_.gradient, direction_);
    trial_y_ = omega * (y_ - alpha * direction_ - previous_) + previous_;
    // Terms that bound a step (CCD) reject a trial point they would clip.
    admissible = model_.max_step(model_.state(y_, p_), model_.elimination().expand_direction(trial_y_ - y_)) >= 1.0;
    pass_.evaluate(trial_y_, trial_);
    return point(trial_);
  }
  double trapezoid_change() override { return 0.5 * (current_.gradient + trial_.gradient).dot(trial_y_ - y_); }
  void accept() override {
    previous_.swap(y_);
    y_.swap(trial_y_);
    std::swap(current_, trial_);
  }
  void restart() override { previous_ = y_; }
  void read(Vector& y) const override { y = y_; }
  double largest_eigenvalue(int iterations) override {
    return power_largest_eigenvalue(model_, p_, y_, iterations,
                                    [&](const Vector& g, Vector& d) { pass_.apply_inverse(current_, g, d); });
  }
  std::string device() const override { return "cpu"; }

 protected:
  virtual void prepare(const Vector& p, const Vector& y) { (void)p, (void)y; }
  static Point point(const Evaluation& e) { return {e.energy, e.energy_roundoff, e.gradient.norm()}; }
  const Model& model_;
  Pass pass_;
  Vector p_, y_, previous_, trial_y_, direction_;
  Evaluation current_, trial_;
};

// BlockJacobiPass with the p of the solve.
struct ProjectedPass {
  ProjectedPass(const Model& model, int block_size) : pass(model, block_size) {}
  void evaluate(const Vector& y, DescentEvaluation& out) { pass.evaluate(y, *p, out, true); }
  void apply_inverse(const DescentEvaluation& at, const Vector& g, Vector& d) const { pass.apply_inverse(at, g, d); }
  BlockJacobiPass pass;
  const Vector* p = nullptr;
};

class ProjectedBackend final : public HostBackend<ProjectedPass, DescentEvaluation> {
 public:
  ProjectedBackend(const Model& model, int block_size) : HostBackend(model, model, block_size) {}
  BlockJacobiPass* projected_pass() override { return &pass_.pass; }

 private:
  void prepare(const Vector& /*p*/, const Vector& /*y*/) override { pass_.p = &p_; }
};

struct VertexBlockPass {
  explicit VertexBlockPass(const Model& model) : rule(model), pass(rule) {}
  void evaluate(const Vector& y, VertexBlockHostPass::Result& out) { pass.evaluate(y, out, true); }
  void apply_inverse(const VertexBlockHostPass::Result& at, const Vector& g, Vector& d) const {
    pass.apply_inverse(at, g, d);
  }
  VertexBlockModel rule;
  VertexBlockHostPass pass;
};

class VertexBlockBackend final : public HostBackend<VertexBlockPass, VertexBlockHostPass::Result> {
 public:
  explicit VertexBlockBackend(const Model& model) : HostBackend(model, model) {}

 private:
  void prepare(const Vector& p, const Vector& y) override { pass_.rule.prepare(p, y); }
};

}  // namespace

std::unique_ptr<DescentBackend> projected_hessian_backend(const Model& model, int block_size) {
  return std::make_unique<ProjectedBackend>(model, block_size);
}

std::unique_ptr<DescentBackend> vertex_block_host_backend(const Model& model) {
  return std::make_unique<VertexBlockBackend>(model);
}

}  // namespace tailor
