// Pictures of per-element fields: a 2D field split in two halves and the mid-plane cut of a 3D
// block with a stiff core show the right colours in the right places, panels share one colour
// scale, and bad input is refused.
#include "problems/plot/field_image.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../support/temp_folder.hpp"
#include "forward/mesh/generate.hpp"
#include "problems/fem/inverse_commands.hpp"

namespace tailor::field_image_test {
namespace {

Eigen::Vector3d centroid(const Mesh& mesh, int e) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < mesh.elements.cols(); ++k)
    c.head(mesh.dim()) +=
        mesh.rest_positions.row(mesh.elements(e, k)).transpose() / double(mesh.elements.cols());
  return c;
}

// Panel k spans x in [12 + k (w + 6), 12 + k (w + 6) + w); with no title the panel title takes
// one text line (14 px) + 6 px, so the panel area starts at y = 32.
constexpr int kLeft = 12, kTop = 32, kWidth = 400, kHeight = 200;

TEST(FieldImage, TwoDimensionalHalvesAndSharedScale) {
  const Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 8, 4);
  Eigen::VectorXd left_soft(mesh.num_elements()), uniform(mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    left_soft[e] = centroid(mesh, e).x() < 1.0 ? 1.0 : 3.0;
    uniform[e] = 2.0;
  }
  FieldImageOptions options;
  options.panel_width = kWidth;
  options.panel_height = kHeight;
  const RgbImage image = render_field_image(mesh, {{"a", left_soft}, {"b", uniform}}, options);
  // The 2 x 1 rectangle fills the panel's width: 388 px wide, 194 px high, centred.
  const int y_mid = kTop + kHeight / 2;
  EXPECT_EQ(image.at(kLeft + kWidth / 4, y_mid), field_colour(0.0));
  EXPECT_EQ(image.at(kLeft + 3 * kWidth / 4, y_mid), field_colour(1.0));
  // The second panel's uniform 2 sits in the middle of the shared range [1, 3].
  EXPECT_EQ(image.at(kLeft + kWidth + 6 + kWidth / 2, y_mid), field_colour(0.5));
  // Outside the mesh (above the centred rectangle) stays white.
  EXPECT_EQ(image.at(kLeft + kWidth / 2, kTop + 1), (Rgb{255, 255, 255}));
  EXPECT_EQ(encode_png(image).size() > 8, true);
}

TEST(FieldImage, ThreeDimensionalMidPlaneShowsTheCore) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 8, 4, 4);
  const FieldSlice slice = mid_plane(mesh);
  EXPECT_EQ(slice.axis, 2);  // y and z tie; the last axis wins
  EXPECT_DOUBLE_EQ(slice.value, 0.5);
  Eigen::VectorXd field(mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e)
    field[e] = (centroid(mesh, e) - Eigen::Vector3d(1, 0.5, 0.5)).cwiseAbs().maxCoeff() < 0.3 ? 5.0 : 1.0;
  FieldImageOptions options;
  options.panel_width = kWidth;
  options.panel_height = kHeight;
  const RgbImage image = render_field_image(mesh, {{"E", field}}, options);
  EXPECT_EQ(image.at(kLeft + kWidth / 2, kTop + kHeight / 2), field_colour(1.0));  // the core
  EXPECT_EQ(image.at(kLeft + 20, kTop + kHeight / 2), field_colour(0.0));          // near x = 0
}

TEST(FieldImage, RefusesBadInput) {
  const Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 2, 2);
  EXPECT_THROW(render_field_image(mesh, {}), std::invalid_argument);
  EXPECT_THROW(render_field_image(mesh, {{"short", Eigen::VectorXd::Ones(3)}}), std::invalid_argument);
  Eigen::VectorXd bad = Eigen::VectorXd::Ones(mesh.num_elements());
  bad[0] = std::nan("");
  EXPECT_THROW(render_field_image(mesh, {{"nan", bad}}), std::invalid_argument);
  FieldImageOptions tiny;
  tiny.panel_width = 10;
  EXPECT_THROW(render_field_image(mesh, {{"ok", Eigen::VectorXd::Ones(mesh.num_elements())}}, tiny),
               std::invalid_argument);
}

// tailor run writes the designed and the true field side by side.
TEST(FieldImage, TailorRunWritesYoungsModulusPng) {
  tailor::testing::TempFolder folder("field_image_run");
  const InverseRun run = run_inverse_scene(
      read_scene(tailor::testing::kScenesDir + "/two_material_bar_inverse.json"), folder / "out");
  const std::string path = folder / "out/youngs_modulus.png";
  ASSERT_TRUE(std::filesystem::exists(path));
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const RgbImage expected = render_field_image(
      run.problem->setup.mesh, {{"designed E", run.youngs_modulus}, {"true E", run.problem->truth}},
      {run.problem->scene_name, "E"});
  const std::vector<std::uint8_t> encoded = encode_png(expected);
  ASSERT_EQ(bytes.size(), encoded.size());
  EXPECT_TRUE(std::equal(encoded.begin(), encoded.end(), bytes.begin(),
                         [](std::uint8_t a, char b) { return a == static_cast<std::uint8_t>(b); }));
}

}  // namespace
}  // namespace tailor::field_image_test
