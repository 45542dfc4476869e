#include "problems/meshless/meshless_vtu.hpp"

#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "forward/core/atomic_file.hpp"

namespace tailor {

void write_points_vtu(const std::string& path, const Eigen::MatrixXd& points, const std::vector<PointArray>& arrays) {
  const Eigen::Index m = points.rows();
  std::ostringstream f;  // written whole by write_text_file_atomically
  f << std::setprecision(10);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
    << "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << m << "\" NumberOfCells=\"" << m << "\">\n"
    << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Eigen::Index i = 0; i < m; ++i) f << points(i, 0) << " " << points(i, 1) << " " << points(i, 2) << "\n";
  f << "        </DataArray>\n      </Points>\n      <Cells>\n"
    << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (Eigen::Index i = 0; i < m; ++i) f << i << "\n";
  f << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (Eigen::Index i = 1; i <= m; ++i) f << i << "\n";
  f << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (Eigen::Index i = 0; i < m; ++i) f << "1\n";  // VTK_VERTEX
  f << "        </DataArray>\n      </Cells>\n      <PointData>\n";
  for (const PointArray& a : arrays) {
    if (a.values.size() != m * a.components)
      throw std::runtime_error("write_points_vtu: array " + a.name + " has " + std::to_string(a.values.size()) +
                               " values for " + std::to_string(m) + " points");
    f << "        <DataArray type=\"Float64\" Name=\"" << a.name << "\" NumberOfComponents=\"" << a.components
      << "\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < m; ++i) {
      for (int c = 0; c < a.components; ++c) f << (c ? " " : "") << a.values[i * a.components + c];
      f << "\n";
    }
    f << "        </DataArray>\n";
  }
  f << "      </PointData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  write_text_file_atomically(path, f.str());
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames) {
  std::ostringstream f;
  f << std::setprecision(10) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& [time, file] : frames) f << "    <DataSet timestep=\"" << time << "\" file=\"" << file << "\"/>\n";
  f << "  </Collection>\n</VTKFile>\n";
  write_text_file_atomically(path, f.str());
}

}  // namespace tailor
