#pragma once
// Colour-mapped pictures of per-element fields (e.g. Young's modulus): 2D meshes are drawn
// triangle by triangle; 3D meshes as their cut by the mid-plane of the bounding box normal to
// its shortest side (ties: the last axis), each tet's cut polygon in the tet's colour, so
// interior features (inclusions) show. Several panels (e.g. designed and true field) share
// one colour scale and one colour bar labelled with its range. Orthographic, no shading.
#include <string>
#include <vector>

#include "forward/mesh/mesh.hpp"
#include "problems/plot/png_writer.hpp"

namespace tailor {

struct FieldPanel {
  std::string title;       // drawn above the panel
  Eigen::VectorXd values;  // one per mesh element
};

struct FieldImageOptions {
  std::string title;      // above everything
  std::string bar_label;  // next to the colour bar, e.g. "E [Pa]"
  int panel_width = 480;  // pixels per panel
  int panel_height = 320;
};

// Where a 3D mesh was cut: axis (0, 1, 2) and the coordinate of the plane.
struct FieldSlice {
  int axis = 2;
  double value = 0.0;
};
// The plane render_field_image cuts a 3D mesh with.
FieldSlice mid_plane(const Mesh& mesh);

// A colour for t in [0, 1] (clamped) on a perceptually ordered dark-blue-to-yellow scale.
Rgb field_colour(double t);

// Throws std::invalid_argument when there is no panel, a panel has the wrong number of values
// or a non-finite one, or the sizes are below 80 x 60.
RgbImage render_field_image(const Mesh& mesh, const std::vector<FieldPanel>& panels,
                            const FieldImageOptions& options = {});
// render_field_image + write_png; throws std::runtime_error naming the path when it cannot write.
void write_field_png(const std::string& path, const Mesh& mesh, const std::vector<FieldPanel>& panels,
                     const FieldImageOptions& options = {});

}  // namespace tailor
