#include "problems/fem/reduced_design_cubature.hpp"

#include <Eigen/Cholesky>
#include <chrono>
#include <random>
#include <stdexcept>
#include <vector>

#include "forward/reduction/cubature.hpp"

namespace tailor {
namespace {

// Every element evaluates (no inverted element of a barrier material).
bool evaluates(const SubspaceElements& elements, const Vector& q) {
  double e = 0.0;
  for (int k = 0; k < elements.size(); ++k)
    if (!elements.add(k, q, 1.0, &e, nullptr, nullptr)) return false;
  return true;
}

std::vector<Vector> training_poses(const SubspaceElements& elements, const Matrix& basis,
                                   const Matrix& material_modes, const Vector& load, int count) {
  const int r = elements.reduced_size(), m = static_cast<int>(material_modes.cols());
  // Reduced stiffness at rest of the base material and of each mode: K(w) = K_0 + sum_j w_j K_j.
  std::vector<Matrix> k(static_cast<std::size_t>(m + 1), Matrix::Zero(r, r));
  const Vector rest = Vector::Zero(r);
  Matrix ke(r, r);
  for (int e = 0; e < elements.size(); ++e) {
    ke.setZero();
    if (!elements.add(e, rest, 1.0, nullptr, nullptr, &ke))
      throw std::invalid_argument("the material cannot be evaluated at rest");
    k[0] += ke;
    for (int j = 0; j < m; ++j)
      k[static_cast<std::size_t>(j + 1)] += material_modes(elements.mesh_element(e), j) * ke;
  }
  std::vector<Vector> poses;
  const auto response = [&](const Matrix& stiffness, Vector& q) {
    Eigen::LLT<Matrix> llt(0.5 * (stiffness + stiffness.transpose()));
    if (llt.info() != Eigen::Success) return false;
    q = llt.solve(load);
    return q.allFinite() && q.norm() > 0.0;
  };
  Vector q0;
  if (!response(k[0], q0))
    throw std::invalid_argument("the reduced stiffness at rest is not positive definite or the load is zero");
  for (double t : {1.0, 1.5, 0.5}) poses.push_back(t * q0);
  for (int j = 0; j < m; ++j)
    for (double s : {-0.5, 0.5}) {
      Vector q;
      if (response(k[0] + s * k[static_cast<std::size_t>(j + 1)], q)) poses.push_back(q);
    }
  const double amplitude = (basis * q0).cwiseAbs().maxCoeff();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  while (static_cast<int>(poses.size()) < count) {
    Vector d(r);
    for (int a = 0; a < r; ++a) d[a] = normal(random);
    d *= 0.5 * amplitude * unit(random) / std::max((basis * d).cwiseAbs().maxCoeff(), 1e-300);
    poses.push_back(1.5 * unit(random) * q0 + d);
  }
  poses.resize(static_cast<std::size_t>(count));
  for (Vector& q : poses)
    for (int halving = 0; halving < 30 && !evaluates(elements, q); ++halving) q *= 0.5;
  return poses;
}

}  // namespace

std::shared_ptr<const CubatureDesignModel> fit_reduced_design_cubature(
    const Model& model, const Vector& p, const Matrix& basis, const Matrix& material_modes,
    const Vector& load, const CubatureSpec& spec, const std::string& key, ReducedDesignCubature& summary) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string where = key + ".cubature: ";
  if (spec.elements < 1)
    throw std::invalid_argument(where + "elements must be at least 1, got " + std::to_string(spec.elements));
  if (spec.training_poses < 1)
    throw std::invalid_argument(where + "training_poses must be at least 1, got " +
                                std::to_string(spec.training_poses));
  if (!(spec.tolerance > 0.0)) throw std::invalid_argument(where + "the tolerance must be positive");
  summary = ReducedDesignCubature{};
  try {
    SubspaceElements all(model, p, basis);
    summary.mesh_elements = all.size();
    std::shared_ptr<const CubatureDesignModel> out;
    if (spec.elements >= all.size()) {
      // The rule every quadrature would reach: each element at weight 1 (the projected model).
      summary.exact = true;
      summary.elements = all.size();
      out = std::make_shared<CubatureDesignModel>(std::move(all), Vector::Ones(summary.elements),
                                                  material_modes);
    } else {
      const std::vector<Vector> poses = training_poses(all, basis, material_modes, load, spec.training_poses);
      Matrix weights(material_modes.rows(), material_modes.cols() + 1);
      weights.col(0).setOnes();
      weights.rightCols(material_modes.cols()) = material_modes;
      const CubatureTraining training = cubature_training(all, poses, weights);
      CubatureOptions options;
      options.max_elements = spec.elements;
      options.tolerance = spec.tolerance;
      options.candidates = spec.candidates;
      const CubatureRule rule = fit_cubature(training.a, training.b, options);
      if (rule.elements.empty()) throw std::invalid_argument("the greedy fit selected no element");
      summary.training_poses = training.poses;
      summary.training_error = rule.training_error;
      summary.elements = static_cast<int>(rule.elements.size());
      out = std::make_shared<CubatureDesignModel>(SubspaceElements(model, p, basis, rule.elements),
                                                  rule.weights, material_modes);
    }
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + e.what());
  }
}

}  // namespace tailor
