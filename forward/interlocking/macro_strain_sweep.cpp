// Native sweeps over the sphere of strain directions (see macro_strain_sweep.hpp).
#include "forward/interlocking/macro_strain_sweep.hpp"

#include <cmath>
#include <stdexcept>

namespace tailor::interlocking {

LoadPath strain_direction_path(double u, double v, double w) {
  LoadPath path;
  const double a = (u + v) / std::sqrt(2.0), b = (u - v) / std::sqrt(2.0), c = w / std::sqrt(2.0);
  path.direction << a, c, c, b;
  path.angle = std::atan2(w, v);  // beta, for reports
  return path;
}

std::vector<Eigen::Vector3d> strain_sphere_directions(int rings, int sectors, double beta_max) {
  if (rings < 2 || sectors < 1 || !(beta_max > 0.0))
    throw std::invalid_argument("strain_sphere_directions: needs rings >= 2, sectors >= 1, beta_max > 0");
  const bool full_circle = beta_max >= 2.0 * M_PI - 1e-12;
  std::vector<Eigen::Vector3d> directions{Eigen::Vector3d(1.0, 0.0, 0.0)};
  for (int i = 1; i < rings; ++i) {
    const double phi = M_PI * i / rings;
    for (int j = 0; j <= (full_circle ? sectors - 1 : sectors); ++j) {
      const double beta = beta_max * j / sectors;
      directions.emplace_back(std::cos(phi), std::sin(phi) * std::cos(beta), std::sin(phi) * std::sin(beta));
    }
  }
  directions.emplace_back(-1.0, 0.0, 0.0);
  return directions;
}

std::vector<Eigen::Vector3d> native_strain_sweep(const PeriodicRigidCell& cell,
                                                 const std::vector<Eigen::Vector3d>& directions,
                                                 const LimitOptions& options, int* skipped) {
  std::vector<LoadPath> paths;
  for (const Eigen::Vector3d& d : directions) paths.push_back(strain_direction_path(d.x(), d.y(), d.z()));
  const std::vector<LimitPoint> limits = strain_space_boundary(cell, paths, options);
  std::vector<Eigen::Vector3d> strains;
  int left_out = 0;
  for (std::size_t k = 0; k < limits.size(); ++k) {
    if (!limits[k].locked) {
      ++left_out;
      continue;
    }
    const Eigen::Matrix2d e = limits[k].strain * paths[k].direction;
    strains.emplace_back(e(0, 0), e(1, 1), e(0, 1));
  }
  if (skipped) *skipped = left_out;
  return strains;
}

}  // namespace tailor::interlocking
