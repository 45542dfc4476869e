#pragma once
// A triangle surface as a VTK XML unstructured grid (.vtu, ASCII) for ParaView.
#include <Eigen/Core>
#include <string>

namespace tailor {

// `positions` n x 3 [length], `faces` m x 3 vertex indices. Throws std::runtime_error when the
// file cannot be written.
void write_surface_vtu(const std::string& path, const Eigen::MatrixX3d& positions,
                       const Eigen::MatrixX3i& faces);

}  // namespace tailor
