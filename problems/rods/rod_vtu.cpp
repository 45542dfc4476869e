#include "problems/rods/rod_vtu.hpp"

#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "forward/core/atomic_file.hpp"

namespace tailor {

namespace {
void array_header(std::ostream& f, const char* name, int components) {
  f << "        <DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"" << components
    << "\" format=\"ascii\">\n";
}
}  // namespace

void write_rods_vtu(const std::string& path, const std::vector<RodOutput>& rods, const Vector& x,
                    const Vector& p) {
  std::ostringstream f;  // written whole by write_text_file_atomically
  int points = 0, cells = 0;
  for (const auto& r : rods) points += r.rod->num_vertices(), cells += r.rod->num_edges();
  f << std::setprecision(17);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
       "byte_order=\"LittleEndian\">\n"
    << "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << points << "\" NumberOfCells=\"" << cells
    << "\">\n"
    << "      <Points>\n";
  array_header(f, "positions", 3);
  for (const auto& r : rods)
    for (int v = 0; v < r.rod->num_vertices(); ++v) f << r.rod->position(x, v).transpose() << "\n";
  f << "        </DataArray>\n      </Points>\n      <Cells>\n"
    << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  int base = 0;
  for (const auto& r : rods) {
    for (int j = 0; j < r.rod->num_edges(); ++j) f << base + j << " " << base + r.rod->edge_end(j) << "\n";
    base += r.rod->num_vertices();
  }
  f << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (int c = 1; c <= cells; ++c) f << 2 * c << "\n";
  f << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (int c = 0; c < cells; ++c) f << "3\n";
  f << "        </DataArray>\n      </Cells>\n      <PointData>\n";
  array_header(f, "kappa", 2);
  for (const auto& r : rods)
    for (int v = 0; v < r.rod->num_vertices(); ++v) {
      const bool interior = r.rod->closed() || (v > 0 && v + 1 < r.rod->num_vertices());
      const int stencil = v == 0 ? r.rod->num_interior() - 1 : v - 1;  // stencil at vertex v
      const Eigen::Vector3d s =
          interior ? bend_twist_strain_values(*r.rod, x, stencil) : Eigen::Vector3d::Zero();
      f << s[0] << " " << s[1] << "\n";
    }
  f << "        </DataArray>\n";
  array_header(f, "twist", 1);
  for (const auto& r : rods)
    for (int v = 0; v < r.rod->num_vertices(); ++v) {
      const bool interior = r.rod->closed() || (v > 0 && v + 1 < r.rod->num_vertices());
      const int stencil = v == 0 ? r.rod->num_interior() - 1 : v - 1;
      f << (interior ? bend_twist_strain_values(*r.rod, x, stencil)[2] : 0.0) << "\n";
    }
  f << "        </DataArray>\n      </PointData>\n      <CellData>\n";
  for (int c = 0; c < 2; ++c) {
    array_header(f, c == 0 ? "m1" : "m2", 3);
    for (const auto& r : rods)
      for (int j = 0; j < r.rod->num_edges(); ++j)
        f << r.rod->material_frame(x, j).col(c).transpose() << "\n";
    f << "        </DataArray>\n";
  }
  array_header(f, "theta", 1);
  for (const auto& r : rods)
    for (int j = 0; j < r.rod->num_edges(); ++j) f << x[r.rod->twist_dof(j)] << "\n";
  f << "        </DataArray>\n";
  array_header(f, "axial_strain", 1);
  for (const auto& r : rods)
    for (int j = 0; j < r.rod->num_edges(); ++j)
      f << r.rod->edge_vector(x, j).norm() / p[r.blocks.rest_length + j] - 1.0 << "\n";
  f << "        </DataArray>\n      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  write_text_file_atomically(path, f.str());
}

}  // namespace tailor
