// "tikhonov": a regularization pulling every element's E towards a prior, relative to it:
// J = 1/2 sum_e ((E_e - prior) / prior)^2 (objectives/tikhonov.hpp).
#include "objectives/tikhonov.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"

namespace tailor {

ObjectiveTermType tikhonov_objective_term() {
  ObjectiveTermType t;
  t.type = "tikhonov";
  t.keys = t.required = {"prior"};
  t.parse = [](const SceneNode& node, const std::string&) {
    auto s = std::make_shared<TikhonovTerm>();
    s->prior = node.at("prior").positive();
    return s;
  };
  t.build = [](const ObjectiveTermContext& c) {
    const double prior = c.settings<TikhonovTerm>().prior;
    const int ne = c.problem.setup.mesh.num_elements();
    // Weights 1 / prior make each entry's misfit a ratio.
    return std::make_shared<Tikhonov>(c.problem.youngs_offset, ne, 1.0, Vector::Constant(ne, prior),
                                      Vector::Constant(ne, 1.0 / prior));
  };
  t.example = {{"type", "tikhonov"}, {"prior", 2e5}};
  return t;
}

}  // namespace tailor
