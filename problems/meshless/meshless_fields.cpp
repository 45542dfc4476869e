#include "problems/meshless/meshless_fields.hpp"

#include <string>

#include "problems/scene_error.hpp"

namespace tailor {

SparseMatrix meshless_node_values(const MeshlessScene& S) {
  const int n = S.num_nodes();
  Triplets t;
  for (int b = 0; b < n; ++b) {
    MlsValues v;
    try {
      v = S.mls->evaluate(S.sampling.nodes.row(b).transpose());
    } catch (const MeshlessPointError& e) {
      throw SceneError(S.spec.source + ": meshless: node " + std::to_string(b) + ": " + e.what());
    }
    for (std::size_t i = 0; i < v.nodes.size(); ++i)
      for (int k = 0; k < 3; ++k) t.emplace_back(3 * b + k, 3 * v.nodes[i] + k, v.values[static_cast<Eigen::Index>(i)]);
  }
  SparseMatrix N(3 * n, 3 * n);
  N.setFromTriplets(t.begin(), t.end());
  return N;
}

Eigen::VectorXd meshless_sample_displacements(const MeshlessScene& S, const Vector& x) {
  const Vector u = x - S.rest();
  Eigen::VectorXd out(3 * S.samples.rows());
  for (Eigen::Index i = 0; i < S.samples.rows(); ++i)
    out.segment<3>(3 * i) = S.mls->interpolate(u, S.samples.row(i).transpose());
  return out;
}

Eigen::MatrixXd as_point_rows(const Vector& interleaved) {
  const Eigen::Index m = interleaved.size() / 3;
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(interleaved.data(), m, 3);
}

Vector as_interleaved(const Eigen::MatrixXd& rows) {
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> r = rows;
  return Eigen::Map<const Vector>(r.data(), r.size());
}

MeshlessFields meshless_fields(const MeshlessScene& S, const SparseMatrix& node_values, const Vector& x,
                               const Vector& p) {
  MeshlessFields f;
  const Vector u = x - S.rest();
  f.rest_positions = S.sampling.nodes;
  f.coefficient_displacement = as_point_rows(u);
  f.displacement = as_point_rows(node_values * u);
  f.positions = f.rest_positions + f.displacement;
  f.samples = S.samples;
  f.sample_displacement = as_point_rows(meshless_sample_displacements(S, x));
  f.youngs_modulus = p.head(S.num_nodes());
  return f;
}

}  // namespace tailor
