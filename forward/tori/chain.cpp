// Chains of interlocked tori (see chain.hpp).
#include "forward/tori/chain.hpp"

#include <cmath>
#include <stdexcept>

#include "forward/rigid/rotation.hpp"

namespace tailor::tori {

double ChainSpec::effective_spacing() const {
  return spacing > 0.0 ? spacing : 2.0 * (shape.major_radius - shape.minor_radius) - gap;
}

Chain make_chain(const ChainSpec& spec, const std::string& where) {
  if (spec.count < 2) throw std::invalid_argument(where + ".count: a chain needs at least 2 links");
  validate_shape(spec.shape, where);
  const double R = spec.shape.major_radius, r = spec.shape.minor_radius, s = spec.effective_spacing();
  if (!(s > 0.0) || !(s < 2.0 * (R - r)) || !(s > R))
    throw std::invalid_argument(where + ".spacing: neighbours are interlocked and apart for R < spacing < 2 (R - r) = " +
                                std::to_string(2.0 * (R - r)) + ", got " + std::to_string(s));
  const Eigen::Matrix3d tilt = rigid::rotation_matrix(Eigen::Vector3d(spec.tilt, 0, 0));
  Chain chain;
  for (int k = 0; k < spec.count; ++k) {
    const Eigen::Vector3d w = (k % 2 == 0) ? Eigen::Vector3d(M_PI / 2, 0, 0) : Eigen::Vector3d(0, M_PI / 2, 0);
    const Eigen::Vector3d position = tilt * Eigen::Vector3d(0, 0, -k * s);
    const Eigen::Vector3d rotation = rigid::rotation_vector(tilt * rigid::rotation_matrix(w), w);
    chain.bodies.push_back(torus_body("link_" + std::to_string(k), spec.shape, spec.density, position, rotation,
                                      spec.fix_first && k == 0, spec.major_segments, spec.minor_segments,
                                      spec.inscribed));
    chain.shapes.push_back(spec.shape);
  }
  return chain;
}

}  // namespace tailor::tori
