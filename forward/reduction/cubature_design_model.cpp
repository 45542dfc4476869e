#include "forward/reduction/cubature_design_model.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace tailor {

CubatureDesignModel::CubatureDesignModel(SubspaceElements elements, Vector weights, const Matrix& material_modes)
    : elements_(std::move(elements)), weights_(std::move(weights)) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("CubatureDesignModel: " + what); };
  if (weights_.size() != elements_.size())
    fail(std::to_string(weights_.size()) + " weights for " + std::to_string(elements_.size()) + " elements");
  if (elements_.size() < 1) fail("no element");
  if ((weights_.array() < 0.0).any() || !weights_.allFinite()) fail("a weight is negative or not finite");
  if (material_modes.cols() < 1) fail("no material mode");
  design_rows_.resize(elements_.size(), material_modes.cols());
  for (int k = 0; k < elements_.size(); ++k) {
    const int e = elements_.mesh_element(k);
    if (e >= material_modes.rows())
      fail("the material modes have " + std::to_string(material_modes.rows()) + " rows, the rule uses element " +
           std::to_string(e));
    design_rows_.row(k) = material_modes.row(e);
  }
}

void CubatureDesignModel::evaluate(const Vector& q, const Vector& w, double* energy, Vector* force,
                                   Matrix* stiffness) const {
  const int r = size();
  if (q.size() != r || w.size() != design_size())
    throw std::invalid_argument("CubatureDesignModel: q has " + std::to_string(q.size()) + " entries, w " +
                                std::to_string(w.size()) + " (expected " + std::to_string(r) + " and " +
                                std::to_string(design_size()) + ")");
  double e = 0.0;
  if (force) *force = Vector::Zero(r);
  if (stiffness) *stiffness = Matrix::Zero(r, r);
  const Vector relative = Vector::Ones(elements_.size()) + design_rows_ * w;  // E_e / E0_e
  for (int k = 0; k < elements_.size(); ++k) {
    if (elements_.add(k, q, weights_[k] * relative[k], energy ? &e : nullptr, force, stiffness)) continue;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    e = std::numeric_limits<double>::infinity();
    if (force) force->setConstant(nan);
    if (stiffness) stiffness->setConstant(nan);
    break;
  }
  if (energy) *energy = e;
  if (stiffness) *stiffness = 0.5 * (*stiffness + stiffness->transpose()).eval();
}

Matrix CubatureDesignModel::force_design_derivative(const Vector& q) const {
  // d force / dw_j = sum_e omega_e y_ej f_e(q), f_e the element's reduced force at E0.
  Matrix d = Matrix::Zero(size(), design_size());
  Vector f(size());
  for (int k = 0; k < elements_.size(); ++k) {
    f.setZero();
    if (!elements_.add(k, q, weights_[k], nullptr, &f, nullptr))
      return Matrix::Constant(size(), design_size(), std::numeric_limits<double>::quiet_NaN());
    d.noalias() += f * design_rows_.row(k);
  }
  return d;
}

Vector CubatureDesignModel::force_design_derivative_transpose(const Vector& q, const Vector& lambda) const {
  Vector out = Vector::Zero(design_size());
  Vector f(size());
  for (int k = 0; k < elements_.size(); ++k) {
    f.setZero();
    if (!elements_.add(k, q, weights_[k], nullptr, &f, nullptr))
      return Vector::Constant(design_size(), std::numeric_limits<double>::quiet_NaN());
    out.noalias() += lambda.dot(f) * design_rows_.row(k).transpose();
  }
  return out;
}

}  // namespace tailor
