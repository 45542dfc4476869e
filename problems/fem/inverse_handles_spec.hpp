#pragma once
// The "handles" objective term of an inverse scene as typed data (heterogeneous material
// design, Xu et al. 2015; see docs/scenes.md, "Material design with handles"). Parsed with the
// inverse section; resolved against the mesh by problems/fem/inverse_handles.hpp.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "problems/fem/objective_term_registry.hpp"
#include "problems/fem/scene.hpp"

namespace tailor {

// One handle: a vertex set whose displacement is designed, with the force it should apply
// and the displacement it should have.
struct HandleSpec {
  VertexSelector vertices;
  std::optional<Eigen::VectorXd> displacement;  // ubar, the same for every vertex
  std::optional<Eigen::VectorXd> force;         // fbar: total over the vertices, or per vertex
  bool force_per_vertex = false;                // "force_per_vertex" instead of "force"
  double weight = 1.0;                          // W_h on the squared force misfit
  std::string key;                              // "inverse.objective[i].handles[h]"
};

// alpha/2 sum_h W_h |f_h - fbar_h|^2 + alpha beta/2 sum_h |u~_h - ubar_h|^2.
struct HandlesTerm : ObjectiveTermSettings {
  std::vector<HandleSpec> handles;
  double alpha = 1.0;
  double beta = 1.0;
};

}  // namespace tailor
