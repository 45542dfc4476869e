#include "forward/homogenization/compliance_fit.hpp"

#include <stdexcept>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/homogenization/engineering_constants.hpp"

namespace tailor {

Matrix fit_compliance(const std::vector<StressStrainSample>& samples) {
  if (samples.empty()) throw std::invalid_argument("fit_compliance: no samples");
  const int m = static_cast<int>(samples[0].stress.size());
  if (m != 3 && m != 6) throw std::invalid_argument("fit_compliance: Voigt vectors have 3 or 6 entries");
  const int unknowns = m * (m + 1) / 2;
  Matrix A = Matrix::Zero(m * static_cast<int>(samples.size()), unknowns);
  Vector b(A.rows());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const StressStrainSample& s = samples[i];
    if (s.stress.size() != m || s.strain.size() != m)
      throw std::invalid_argument("fit_compliance: sample " + std::to_string(i) + " has the wrong size");
    const double scale = s.strain.norm();
    if (!(scale > 0.0))
      throw std::invalid_argument("fit_compliance: sample " + std::to_string(i) + " has zero strain");
    // Row r of S sigma: sum_c S(r, c) sigma_c, with S(r, c) = S(c, r) the unknown of the pair.
    int k = 0;
    for (int r = 0; r < m; ++r)
      for (int c = r; c < m; ++c, ++k) {
        A(m * i + r, k) += s.stress[c] / scale;
        if (c != r) A(m * i + c, k) += s.stress[r] / scale;
      }
    b.segment(m * i, m) = s.strain / scale;
  }
  const PivotedQrSolution qr = pivoted_qr_solve(A, b);
  if (qr.rank < unknowns)
    throw std::invalid_argument("fit_compliance: the samples determine only " + std::to_string(qr.rank) +
                                " of the " + std::to_string(unknowns) +
                                " compliance entries; add load directions");
  const Vector x = qr.x.col(0);
  Matrix S(m, m);
  int k = 0;
  for (int r = 0; r < m; ++r)
    for (int c = r; c < m; ++c, ++k) S(r, c) = S(c, r) = x[k];
  return S;
}

StressStrainSample macro_sample(const MacroResponse& response) {
  const Matrix& F = response.deformation_gradient;
  const Matrix strain = 0.5 * (F + F.transpose()) - Matrix::Identity(F.rows(), F.cols());
  const Vector stress = voigt_stress(0.5 * (response.stress + response.stress.transpose()));
  Vector engineering = voigt_stress(strain);
  engineering.tail(engineering.size() - F.rows()) *= 2.0;  // gamma_ij = 2 eps_ij
  return {stress, engineering};
}

}  // namespace tailor
