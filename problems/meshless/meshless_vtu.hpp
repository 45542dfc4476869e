#pragma once
// Point output of the meshless scene kind (docs/meshless.md, "Scenes"): an UnstructuredGrid of
// VTK_VERTEX cells, one per point, that ParaView shows as points ("Point Gaussian" or "Points"
// representation) and can warp by any of its vector arrays.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

namespace tailor {

struct PointArray {
  std::string name;
  int components = 1;
  Eigen::VectorXd values;  // points * components, interleaved
};

// points: m x 3. std::runtime_error when the file cannot be written or an array's size differs.
void write_points_vtu(const std::string& path, const Eigen::MatrixXd& points, const std::vector<PointArray>& arrays);

// A ParaView collection of (time, file) entries, files relative to the .pvd.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames);

}  // namespace tailor
