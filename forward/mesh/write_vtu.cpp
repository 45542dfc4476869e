// VTK XML unstructured grid writer (ASCII .vtu), the format ParaView reads natively.
//
// Numbers are formatted with std::to_chars, whose shortest round-trip form keeps full double
// precision, into a buffer that is flushed in large pieces: stream formatting would dominate
// the time for meshes with hundreds of thousands of elements.
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "forward/core/atomic_file.hpp"
#include "forward/mesh/mesh_io.hpp"

namespace tailor {
namespace {

constexpr int kVtkTriangle = 5;
constexpr int kVtkTetrahedron = 10;

std::string xml_escaped(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&apos;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

// How a field's columns map onto VTK components.
enum class FieldKind { scalar, vector, tensor };

FieldKind field_kind(const std::string& where, const std::string& name, const Eigen::MatrixXd& values,
                     Eigen::Index rows, int dim) {
  if (values.rows() != rows) {
    throw std::invalid_argument("write_vtu: " + where + " field '" + name + "' has " +
                                std::to_string(values.rows()) + " rows, expected " + std::to_string(rows));
  }
  if (values.cols() == 1) return FieldKind::scalar;
  if (values.cols() == dim) return FieldKind::vector;
  if (values.cols() == dim * dim) return FieldKind::tensor;
  throw std::invalid_argument("write_vtu: " + where + " field '" + name + "' has " +
                              std::to_string(values.cols()) + " columns; expected 1 (scalar), " +
                              std::to_string(dim) + " (vector) or " + std::to_string(dim * dim) +
                              " (tensor)");
}

class VtuOutput {
 public:
  // Written to a temporary and renamed into place by finish() (forward/core/atomic_file.hpp): a
  // run killed while writing never leaves a truncated file.
  explicit VtuOutput(const std::string& path) : out_(open(path)) { buffer_.reserve(kFlushSize + 256); }

  void text(std::string_view s) {
    buffer_ += s;
    if (buffer_.size() >= kFlushSize) flush();
  }
  void number(double value) { append_chars(value); }
  void number(int value) { append_chars(value); }

  void finish() {
    flush();
    try {
      out_.commit();
    } catch (const std::runtime_error& e) {
      throw MeshError(e.what());
    }
  }

 private:
  static constexpr std::size_t kFlushSize = 1 << 20;

  template <class T>
  void append_chars(T value) {
    char chars[32];
    const auto result = std::to_chars(chars, chars + sizeof chars, value);
    text(std::string_view(chars, static_cast<std::size_t>(result.ptr - chars)));
  }

  static AtomicFile open(const std::string& path) {
    try {
      return AtomicFile(path);
    } catch (const std::runtime_error& e) {
      throw MeshError(e.what());
    }
  }

  void flush() {
    out_.write(buffer_);
    buffer_.clear();
  }

  AtomicFile out_;
  std::string buffer_;
};

void write_field(VtuOutput& out, const std::string& name, const Eigen::MatrixXd& values, FieldKind kind,
                 int dim) {
  const int components = kind == FieldKind::scalar ? 1 : kind == FieldKind::vector ? 3 : 9;
  out.text("        <DataArray type=\"Float64\" Name=\"" + xml_escaped(name) + "\" NumberOfComponents=\"" +
           std::to_string(components) + "\" format=\"ascii\">\n");
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    out.text("          ");
    for (int c = 0; c < components; ++c) {
      // Pad 2D vectors with z = 0, and 2D tensors (row-major 2x2) to a 3x3 with zeros.
      double value = 0.0;
      if (kind != FieldKind::tensor) {
        if (c < values.cols()) value = values(r, c);
      } else if (c / 3 < dim && c % 3 < dim) {
        value = values(r, (c / 3) * dim + c % 3);
      }
      if (c > 0) out.text(" ");
      out.number(value);
    }
    out.text("\n");
  }
  out.text("        </DataArray>\n");
}

}  // namespace

void write_vtu(const std::string& path, const Mesh& mesh, const VtkFields& fields,
               const Eigen::MatrixXd* positions) {
  const int dim = mesh.dim();
  const Eigen::Index num_vertices = mesh.num_vertices();
  const Eigen::Index num_elements = mesh.num_elements();
  if ((dim != 2 && dim != 3) || mesh.elements.cols() != dim + 1) {
    throw std::invalid_argument("write_vtu: " + path +
                                ": the mesh needs dim 2 or 3 and dim + 1 vertices per element");
  }
  if (num_elements > 0 && (mesh.elements.minCoeff() < 0 || mesh.elements.maxCoeff() >= num_vertices)) {
    throw std::invalid_argument("write_vtu: " + path + ": an element references a vertex out of range");
  }
  if (mesh.element_regions.size() != 0 && mesh.element_regions.size() != num_elements) {
    throw std::invalid_argument("write_vtu: " + path + ": element_regions has the wrong size");
  }
  const Eigen::MatrixXd& points = positions != nullptr ? *positions : mesh.rest_positions;
  if (points.rows() != num_vertices || points.cols() != dim) {
    throw std::invalid_argument("write_vtu: " + path + ": positions must be num_vertices x dim");
  }
  // Check every field before creating the file, so a mistake leaves no half-written output.
  std::map<std::string, FieldKind> point_kinds;
  std::map<std::string, FieldKind> cell_kinds;
  for (const auto& [name, values] : fields.point)
    point_kinds[name] = field_kind("point", name, values, num_vertices, dim);
  for (const auto& [name, values] : fields.cell)
    cell_kinds[name] = field_kind("cell", name, values, num_elements, dim);
  if (fields.cell.count("region") != 0) {
    throw std::invalid_argument("write_vtu: cell field name 'region' is reserved for the element regions");
  }

  VtuOutput out(path);
  out.text("<?xml version=\"1.0\"?>\n");
  out.text("<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
  out.text("  <UnstructuredGrid>\n");
  out.text("    <Piece NumberOfPoints=\"" + std::to_string(num_vertices) + "\" NumberOfCells=\"" +
           std::to_string(num_elements) + "\">\n");

  out.text("      <PointData>\n");
  for (const auto& [name, values] : fields.point) write_field(out, name, values, point_kinds[name], dim);
  out.text("      </PointData>\n");

  out.text("      <CellData>\n");
  for (const auto& [name, values] : fields.cell) write_field(out, name, values, cell_kinds[name], dim);
  out.text("        <DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n");
  for (Eigen::Index e = 0; e < num_elements; ++e) {
    out.text("          ");
    out.number(mesh.element_regions.size() != 0 ? mesh.element_regions[e] : 0);
    out.text("\n");
  }
  out.text("        </DataArray>\n");
  out.text("      </CellData>\n");

  out.text("      <Points>\n");
  out.text("        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (Eigen::Index v = 0; v < num_vertices; ++v) {
    out.text("          ");
    for (int k = 0; k < 3; ++k) {
      if (k > 0) out.text(" ");
      out.number(k < dim ? points(v, k) : 0.0);
    }
    out.text("\n");
  }
  out.text("        </DataArray>\n");
  out.text("      </Points>\n");

  out.text("      <Cells>\n");
  out.text("        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
  for (Eigen::Index e = 0; e < num_elements; ++e) {
    out.text("          ");
    for (int k = 0; k <= dim; ++k) {
      if (k > 0) out.text(" ");
      out.number(mesh.elements(e, k));
    }
    out.text("\n");
  }
  out.text("        </DataArray>\n");
  // Offsets of one past each cell's last vertex in the connectivity array.
  out.text("        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (Eigen::Index e = 0; e < num_elements; ++e) {
    out.text("          ");
    out.text(std::to_string((e + 1) * (dim + 1)));
    out.text("\n");
  }
  out.text("        </DataArray>\n");
  out.text("        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  const std::string type_line =
      "          " + std::to_string(dim == 3 ? kVtkTetrahedron : kVtkTriangle) + "\n";
  for (Eigen::Index e = 0; e < num_elements; ++e) out.text(type_line);
  out.text("        </DataArray>\n");
  out.text("      </Cells>\n");
  out.text("    </Piece>\n");
  out.text("  </UnstructuredGrid>\n");
  out.text("</VTKFile>\n");
  out.finish();
}

}  // namespace tailor
