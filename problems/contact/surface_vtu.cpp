// Triangle surfaces as .vtu (see surface_vtu.hpp).
#include "problems/contact/surface_vtu.hpp"

#include <iomanip>
#include <sstream>

#include "forward/core/atomic_file.hpp"

namespace tailor {

void write_surface_vtu(const std::string& path, const Eigen::MatrixX3d& positions,
                       const Eigen::MatrixX3i& faces) {
  std::ostringstream out;  // written whole by write_text_file_atomically
  out << std::setprecision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
         "byte_order=\"LittleEndian\">\n"
      << "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << positions.rows() << "\" NumberOfCells=\""
      << faces.rows() << "\">\n      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" "
      << "format=\"ascii\">\n";
  for (int i = 0; i < positions.rows(); ++i)
    out << "          " << positions(i, 0) << " " << positions(i, 1) << " " << positions(i, 2) << "\n";
  out << "        </DataArray>\n      </Points>\n      <Cells>\n"
      << "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (int f = 0; f < faces.rows(); ++f)
    out << "          " << faces(f, 0) << " " << faces(f, 1) << " " << faces(f, 2) << "\n";
  out << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
  for (int f = 0; f < faces.rows(); ++f) out << "          " << 3 * (f + 1) << "\n";
  out << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (int f = 0; f < faces.rows(); ++f) out << "          5\n";  // VTK_TRIANGLE
  out << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  write_text_file_atomically(path, out.str());
}

}  // namespace tailor
