// A constrained design with Ipopt: the stiffest cantilever (least compliance f . u, an objective
// of the user's own) for a given material budget, a volume-weighted mean Young's modulus of at
// most 1e5, with E between 1e4 and 1e6 in each of its 30 tets.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "problems/fem/study.hpp"

using namespace tailor;

// C(x) = f . (x - X) / C0: the work of the loads, relative to its value C0 at the start.
class Compliance final : public Objective {
 public:
  Compliance(Vector forces, Vector rest, double c0) : f_(std::move(forces) / c0), rest_(std::move(rest)) {}
  std::string name() const override { return "compliance"; }
  double value(const Vector& x, const Vector&) const override { return f_.dot(x - rest_); }
  void add_gradient_x(const Vector&, const Vector&, Vector& gx) const override { gx += f_; }
  // Linear in x, independent of p: the second derivatives vanish (the default adds nothing).

 private:
  Vector f_, rest_;
};

int main() {
  const double budget = 1e5;
  Study study;
  study.mesh_box({0, 0, 0}, {5, 1, 1}, {5, 1, 1})
      .material(select::all(), "linear", budget, 0.3)
      .fix(select::plane("x", 0))
      .traction(select::plane("x", 5), {0, 0, -1e2})
      .design({{"parameter", "youngs_modulus"}, {"granularity", "per_element"}, {"min", 1e4}, {"max", 1e6}})
      .objective("compliance",
                 [](const InverseProblem& p) {
                   const StaticSolution start = solve_static(p.setup);  // at the initial design
                   const double c0 = p.setup.nodal_forces.dot(start.positions - p.setup.rest_state());
                   return std::make_shared<Compliance>(p.setup.nodal_forces, p.setup.rest_state(), c0);
                 })
      .constraint([budget](const InverseProblem& p) {
        return at_most(mean_youngs_modulus(p), budget, "mean Young's modulus");
      })
      .optimizer({{"backend", "ipopt"}, {"max_iterations", 200}, {"gradient_tolerance", 1e-6}});

  const TaylorTestResult taylor = study.taylor_test();  // J(z), z = log E per element
  std::printf("%s", taylor.table().c_str());
  if (!taylor.passed()) return 1;

  const InverseRun run = study.run("out/constrained_design", &std::cout);
  const double mean = mean_youngs_modulus(*run.problem)->value(run.result.z);
  std::printf("compliance %.4f of the uniform design's, mean E %.6g (budget %g)\n", run.result.objective,
              mean, budget);
  return run.result.objective < 0.9 && mean <= budget * (1 + 1e-6) ? 0 : 1;
}
