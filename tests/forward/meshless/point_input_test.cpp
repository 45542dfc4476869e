// Oriented point input and the implicit surface: the readers (.xyz/.pts, ASCII and binary PLY,
// OBJ/OFF/STL sampled), their errors naming file and line or point, and the partition-of-unity
// implicit function feeding the octree sampling (volumes against the exact ones).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <memory>
#include <string>

#include "forward/meshless/implicit_surface.hpp"
#include "forward/meshless/meshless_quadrature.hpp"
#include "forward/meshless/octree_sampling.hpp"
#include "forward/meshless/point_cloud_io.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::point_input_test {
namespace {

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / ("tailor_meshless_" + name)).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// n points on the unit sphere (Fibonacci spiral) with outward normals.
OrientedPoints fibonacci_sphere(int n, double radius = 1.0) {
  OrientedPoints p;
  p.source = "sphere";
  p.positions.resize(n, 3);
  p.normals.resize(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d u(r * std::cos(golden * i), r * std::sin(golden * i), z);
    p.normals.row(i) = u.transpose();
    p.positions.row(i) = radius * u.transpose();
  }
  return p;
}

std::string xyz_text(const OrientedPoints& p) {
  std::string s = "# x y z nx ny nz\n";
  for (int i = 0; i < p.size(); ++i) {
    for (int k = 0; k < 3; ++k) s += std::to_string(p.positions(i, k)) + " ";
    for (int k = 0; k < 3; ++k) s += std::to_string(p.normals(i, k)) + (k < 2 ? " " : "\n");
  }
  return s;
}

// The unit cube [0, 1]^3 as OFF, faces wound outwards; `drop_face` < 0 keeps all.
std::string cube_off(int drop_face = -1, bool flip_one = false) {
  const char* faces[] = {"4 0 3 2 1", "4 4 5 6 7", "4 0 1 5 4", "4 2 3 7 6", "4 1 2 6 5", "4 0 4 7 3"};
  std::string s = "OFF\n8 " + std::to_string(drop_face < 0 ? 6 : 5) + " 0\n";
  s += "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";
  for (int f = 0; f < 6; ++f) {
    if (f == drop_face) continue;
    std::string face = faces[f];
    if (flip_one && f == 1) face = "4 7 6 5 4";
    s += face + "\n";
  }
  return s;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const PointInputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(PointInput, XyzReadsPointsAndNamesTheLineOfABadOne) {
  const OrientedPoints sphere = fibonacci_sphere(50);
  const OrientedPoints read = read_oriented_points(temp_file("ok.xyz", xyz_text(sphere)));
  ASSERT_EQ(read.size(), 50);
  EXPECT_LT((read.positions - sphere.positions).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(read.normals.row(7).norm(), 1.0, 1e-15);
  EXPECT_EQ(read.lines[0], 2);  // after the comment line
  // A .pts file with a leading count.
  EXPECT_EQ(read_oriented_points(temp_file("ok.pts", "50\n" + xyz_text(sphere))).size(), 50);
  const std::string no_normals = error_of([] { read_xyz_points(temp_file("a.xyz", "0 0 0 0 0 1\n1 2 3\n")); });
  EXPECT_NE(no_normals.find("a.xyz: line 2"), std::string::npos) << no_normals;
  EXPECT_NE(no_normals.find("no normals"), std::string::npos) << no_normals;
  const std::string nan = error_of([] { read_xyz_points(temp_file("b.xyz", "0 0 0 0 0 1\n\n1 nan 3 0 0 1\n")); });
  EXPECT_NE(nan.find("b.xyz: point 1 (line 3): the position is not finite"), std::string::npos) << nan;
  const std::string zero = error_of([] { read_xyz_points(temp_file("c.xyz", "0 0 0 0 0 0\n")); });
  EXPECT_NE(zero.find("point 0 (line 1): the normal is zero"), std::string::npos) << zero;
  EXPECT_NE(error_of([] { read_oriented_points(temp_file("d.txt", "")); }).find("unknown point or surface format"),
            std::string::npos);
}

TEST(PointInput, AsciiAndBinaryPlyAgree) {
  const OrientedPoints sphere = fibonacci_sphere(20);
  std::string header = "ply\nformat ascii 1.0\ncomment made by the test\nelement vertex 20\nproperty float x\n"
                       "property float y\nproperty float z\nproperty uchar red\nproperty double nx\nproperty double ny\n"
                       "property double nz\nend_header\n";
  std::string ascii = header, binary = header;
  binary.replace(binary.find("ascii"), 5, "binary_little_endian");
  for (int i = 0; i < 20; ++i) {
    for (int k = 0; k < 3; ++k) ascii += std::to_string(static_cast<float>(sphere.positions(i, k))) + " ";
    ascii += "200";
    for (int k = 0; k < 3; ++k) ascii += " " + std::to_string(sphere.normals(i, k));
    ascii += "\n";
    for (int k = 0; k < 3; ++k) {
      const float v = static_cast<float>(sphere.positions(i, k));
      binary.append(reinterpret_cast<const char*>(&v), 4);
    }
    binary.push_back(static_cast<char>(200));
    for (int k = 0; k < 3; ++k) {
      const double v = sphere.normals(i, k);
      binary.append(reinterpret_cast<const char*>(&v), 8);
    }
  }
  const OrientedPoints a = read_oriented_points(temp_file("a.ply", ascii));
  const OrientedPoints b = read_oriented_points(temp_file("b.ply", binary));
  ASSERT_EQ(a.size(), 20);
  ASSERT_EQ(b.size(), 20);
  EXPECT_LT((a.positions - b.positions).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((b.normals - sphere.normals).cwiseAbs().maxCoeff(), 1e-12);
  std::string big = binary;
  big.replace(big.find("binary_little_endian"), 20, "binary_big_endian");
  EXPECT_NE(error_of([&] { read_ply_points(temp_file("big.ply", big)); }).find("big_endian PLY is not supported"),
            std::string::npos);
  std::string no_normals = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                           "end_header\n0 0 0\n";
  EXPECT_NE(error_of([&] { read_ply_points(temp_file("nn.ply", no_normals)); }).find("have no normals"), std::string::npos);
  std::string truncated = binary.substr(0, binary.size() - 10);
  EXPECT_NE(error_of([&] { read_ply_points(temp_file("cut.ply", truncated)); }).find("ends in vertex 19"), std::string::npos);
}

TEST(PointInput, MeshesAreSampledWithOutwardNormalsAndOpenOnesRefused) {
  const SurfaceMesh off = read_off_mesh(temp_file("cube.off", cube_off()));
  EXPECT_NEAR(check_closed_surface(off), 1.0, 1e-14);
  const OrientedPoints p = sample_surface(off, {0.1, 1});
  // Every sample on a face of the cube with that face's outward normal.
  for (int i = 0; i < p.size(); ++i) {
    const Eigen::Vector3d X = p.positions.row(i), n = p.normals.row(i);
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(X[axis], n[axis] > 0 ? 1.0 : 0.0, 1e-12);
  }
  EXPECT_NEAR(p.size(), 6 / (0.01 * std::sqrt(3.0) / 2.0), 12.0);
  const std::string open = error_of([] { read_oriented_points(temp_file("open.off", cube_off(2))); });
  EXPECT_NE(open.find("open.off: line"), std::string::npos) << open;
  EXPECT_NE(open.find("the surface is open"), std::string::npos) << open;
  const std::string flipped = error_of([] { read_oriented_points(temp_file("flip.off", cube_off(-1, true))); });
  EXPECT_NE(flipped.find("inconsistently oriented"), std::string::npos) << flipped;
  const std::string bad_index = error_of([] { read_obj_mesh(temp_file("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")); });
  EXPECT_NE(bad_index.find("bad.obj: line 4: vertex index 3 out of range"), std::string::npos) << bad_index;

  // The same cube as OBJ (wound inwards: turned outwards) and as binary STL.
  std::string obj;
  const SurfaceMesh& m = off;
  for (int v = 0; v < m.vertices.rows(); ++v)
    obj += "v " + std::to_string(m.vertices(v, 0)) + " " + std::to_string(m.vertices(v, 1)) + " " + std::to_string(m.vertices(v, 2)) + "\n";
  std::string stl(80, ' ');
  const std::uint32_t count = static_cast<std::uint32_t>(m.triangles.rows());
  stl.append(reinterpret_cast<const char*>(&count), 4);
  for (int t = 0; t < m.triangles.rows(); ++t) {
    obj += "f " + std::to_string(m.triangles(t, 0) + 1) + "/1/1 " + std::to_string(m.triangles(t, 2) + 1) + " " +
           std::to_string(m.triangles(t, 1) + 1) + "\n";
    stl.append(12, '\0');
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) {
        const float v = static_cast<float>(m.vertices(m.triangles(t, k), c));
        stl.append(reinterpret_cast<const char*>(&v), 4);
      }
    stl.append(2, '\0');
  }
  const SurfaceMesh inward = read_obj_mesh(temp_file("cube.obj", obj));
  EXPECT_NEAR(check_closed_surface(inward), -1.0, 1e-12);
  const OrientedPoints q = read_oriented_points(temp_file("cube.obj", obj), {0.1, 1});
  EXPECT_NEAR(q.normals.row(0).dot(p.normals.row(0)), 1.0, 1e-12);
  const SurfaceMesh stl_mesh = read_stl_mesh(temp_file("cube.stl", stl));
  EXPECT_EQ(stl_mesh.vertices.rows(), 8);  // welded
  EXPECT_NEAR(check_closed_surface(stl_mesh), 1.0, 1e-6);
}

TEST(ImplicitSurface, SphereFromPointsInsideOutsideAndVolume) {
  const ImplicitSurfaceOptions linear_fits{2.0, ImplicitFit::linear, true};
  auto surface = std::make_shared<ImplicitSurface>(fibonacci_sphere(2000), linear_fits);
  const ImplicitSurfaceReport& r = surface->report();
  EXPECT_GE(r.min_neighbours, 3);
  // Near the surface f approximates the signed distance |X| - 1.
  for (double radius : {0.9, 0.97, 1.03, 1.1}) {
    const Eigen::Vector3d X = radius * Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
    EXPECT_NEAR(surface->value(X), radius - 1.0, 0.01) << radius;
  }
  EXPECT_LT(surface->value(Eigen::Vector3d::Zero()), 0.0);
  EXPECT_GT(surface->value(Eigen::Vector3d(3, 0, 0)), 0.0);
  // The classifying distance has the sign of the side and does not exceed the true distance
  // |1 - |X|| by more than the O(rho^2) error of f near the surface; the quadrics' f is closer.
  auto quadric = std::make_shared<ImplicitSurface>(fibonacci_sphere(2000), ImplicitSurfaceOptions{2.0, ImplicitFit::quadric, true});
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d X = Eigen::Vector3d::Random() * 1.5;
    const double exact = X.norm() - 1.0;
    for (const ImplicitSurface* fit : {surface.get(), quadric.get()}) {
      const double d = fit->classifying_distance(X);
      EXPECT_LE(std::abs(d), std::abs(exact) + (fit == quadric.get() ? 1e-3 : 0.01)) << X.transpose();
      if (std::abs(exact) > 0.01) {
        EXPECT_GE(d * exact, 0.0) << X.transpose();
      }
    }
  }
  // The volume of the octree quadrature inside f = 0. The tangent planes of a convex surface
  // lie outside it, so the linear fits' zero level sits outside by O(rho^2 curvature): the
  // error falls with the sample spacing squared (4x more points: rho / 2, error / 4), towards
  // the clipped quadrature's own error (5.7e-4 on the exact sphere at this depth,
  // docs/meshless.md). The quadrics' zero level is at the quadrature's error already.
  const double exact = 4.0 / 3.0 * M_PI;
  const OctreeSampling s = sample_shape(ImplicitSurface::shape(surface), {0.25, 2, 2});
  auto finer = std::make_shared<ImplicitSurface>(fibonacci_sphere(8000), linear_fits);
  const OctreeSampling f = sample_shape(ImplicitSurface::shape(finer), {0.25, 2, 2});
  const OctreeSampling q = sample_shape(ImplicitSurface::shape(quadric), {0.25, 2, 2});
  std::printf("implicit sphere, linear fits: 2000 points, rho = %.4f: volume error %.2e; 8000 points, rho = %.4f: "
              "%.2e; quadric fits, 2000 points: %.2e\n",
              r.support_radius, s.volume() / exact - 1.0, finer->report().support_radius, f.volume() / exact - 1.0,
              q.volume() / exact - 1.0);
  EXPECT_NEAR(s.volume() / exact, 1.0, 1.2e-2);
  EXPECT_NEAR(f.volume() / exact, 1.0, 4e-3);
  EXPECT_LT(std::abs(f.volume() / exact - 1.0), 0.5 * std::abs(s.volume() / exact - 1.0));
  EXPECT_LT(std::abs(q.volume() / exact - 1.0), 1e-3);
  const MlsShapeFunctions mls(s.nodes, s.spacing);
  const MeshlessQuadrature quadrature = build_meshless_quadrature(mls, s.points, s.weights);
  EXPECT_LT(quadrature.max_condition, 1e4);
}

// The zero level's radius along `directions` rays through the centre of the unit sphere
// (bisection of f on [0.5, 1.5]); returns the largest |r - 1|.
double zero_level_radius_error(const ImplicitSurface& surface, int directions) {
  const OrientedPoints rays = fibonacci_sphere(directions);
  double worst = 0.0;
  for (int k = 0; k < directions; ++k) {
    const Eigen::Vector3d u = rays.normals.row(k).transpose();
    double inside = 0.5, outside = 1.5;
    for (int iteration = 0; iteration < 50; ++iteration) {
      const double mid = 0.5 * (inside + outside);
      (surface.value(mid * u) <= 0.0 ? inside : outside) = mid;
    }
    worst = std::max(worst, std::abs(0.5 * (inside + outside) - 1.0));
  }
  return worst;
}

// Ohtake et al.'s local quadrics remove the tangent planes' O(rho^2 curvature) offset of the
// zero level. Reference: the exact unit sphere the samples lie on. Each 4x more samples halves
// rho; the linear fits' radius error falls at rate 2 in rho (the offset of the tangent planes,
// ~ rho^2 / R), the quadrics' much faster and far lower.
TEST(ImplicitSurface, QuadricFitsRemoveTheCurvatureOffset) {
  const int counts[] = {1000, 4000, 16000};
  double linear_error[3], quadric_error[3], rho[3];
  for (int level = 0; level < 3; ++level) {
    const OrientedPoints points = fibonacci_sphere(counts[level]);
    const ImplicitSurface quadric(points, {2.0, ImplicitFit::quadric, true});
    const ImplicitSurface linear(points, {2.0, ImplicitFit::linear, false});
    EXPECT_EQ(quadric.report().quadric_fits, counts[level]);
    EXPECT_EQ(linear.report().linear_fits, counts[level]);
    rho[level] = quadric.report().support_radius;
    linear_error[level] = zero_level_radius_error(linear, 200);
    quadric_error[level] = zero_level_radius_error(quadric, 200);
    std::printf("sphere, %5d points, rho = %.4f: zero-level radius error linear %.3e, quadric %.3e\n", counts[level],
                rho[level], linear_error[level], quadric_error[level]);
  }
  for (int level = 1; level < 3; ++level) {
    const double scale = std::log(rho[level - 1] / rho[level]);
    const double linear_rate = std::log(linear_error[level - 1] / linear_error[level]) / scale;
    const double quadric_rate = std::log(quadric_error[level - 1] / quadric_error[level]) / scale;
    std::printf("rates in rho: linear %.2f, quadric %.2f\n", linear_rate, quadric_rate);
    EXPECT_NEAR(linear_rate, 2.0, 0.25);
    EXPECT_GT(quadric_rate, 3.5);
  }
  // The linear fits' offset is ~ c rho^2 / R (c ~ 0.07 for these weights); the quadrics' error is
  // over 500 times smaller at every spacing.
  for (int level = 0; level < 3; ++level) {
    EXPECT_GT(linear_error[level], 0.05 * rho[level] * rho[level]);
    EXPECT_LT(quadric_error[level], 2e-3 * linear_error[level]);
  }
}

// The shipped capsule's samples (scenes/meshless_capsule.ply): its volume from the octree
// quadrature inside the implicit surface against the same quadrature inside the exact capsule
// (a segment's distance less the radius, on the same cell lattice): the difference is the
// implicit surface's, and the quadrics shrink it.
TEST(ImplicitSurface, QuadricFitsShrinkTheCapsuleVolumeError) {
  const OrientedPoints points = read_oriented_points(std::string(::tailor::testing::source_dir()) + "/scenes/meshless_capsule.ply");
  auto quadric = std::make_shared<ImplicitSurface>(points, ImplicitSurfaceOptions{2.0, ImplicitFit::quadric, true});
  auto linear = std::make_shared<ImplicitSurface>(points, ImplicitSurfaceOptions{2.0, ImplicitFit::linear, false});
  const AnalyticShape implicit = ImplicitSurface::shape(quadric);
  // Radius 0.5 about the segment through the samples' bounding box centre along x, 5 long.
  const Eigen::Vector3d centre = 0.5 * (implicit.lo + implicit.hi);
  const double radius = 0.5, half_segment = 2.0;
  AnalyticShape capsule = implicit;
  capsule.name = "exact capsule";
  capsule.inside_value = nullptr;
  capsule.signed_distance = [=](const Eigen::Vector3d& X) {
    Eigen::Vector3d d = X - centre;
    d[0] -= std::clamp(d[0], -half_segment, half_segment);
    return d.norm() - radius;
  };
  const double exact = M_PI * radius * radius * (2.0 * half_segment) + 4.0 / 3.0 * M_PI * std::pow(radius, 3);
  const OctreeSamplingOptions options{0.25, 2, 2};
  const double reference = sample_shape(capsule, options).volume();
  const double linear_volume = sample_shape(ImplicitSurface::shape(linear), options).volume();
  const double quadric_volume = sample_shape(implicit, options).volume();
  std::printf("capsule volume (exact %.5f): quadrature in the exact capsule %.5f, implicit linear fits %.5f (%+.2e), "
              "quadric fits %.5f (%+.2e)\n",
              exact, reference, linear_volume, linear_volume / reference - 1.0, quadric_volume,
              quadric_volume / reference - 1.0);
  EXPECT_EQ(quadric->report().linear_fits, 0);
  EXPECT_GT(linear_volume / reference - 1.0, 1e-3);  // the tangent planes' outward offset
  EXPECT_LT(std::abs(quadric_volume / reference - 1.0), 0.1 * (linear_volume / reference - 1.0));
}

TEST(ImplicitSurface, RefusesInconsistentOpenAndInwardSampleSets) {
  OrientedPoints flipped = fibonacci_sphere(1000);
  flipped.normals.row(417) *= -1.0;
  const std::string inconsistent = error_of([&] { ImplicitSurface s(flipped); });
  EXPECT_NE(inconsistent.find("inconsistent normals"), std::string::npos) << inconsistent;
  EXPECT_NE(inconsistent.find("point 417"), std::string::npos) << inconsistent;

  OrientedPoints sphere = fibonacci_sphere(1000), half;
  half.source = "hemisphere";
  half.positions = sphere.positions.topRows(500);
  half.normals = sphere.normals.topRows(500);
  const std::string open = error_of([&] { ImplicitSurface s(half); });
  EXPECT_NE(open.find("hemisphere: the sample set is open"), std::string::npos) << open;

  OrientedPoints inward = fibonacci_sphere(1000);
  inward.normals *= -1.0;
  const std::string inwards = error_of([&] { ImplicitSurface s(inward); });
  EXPECT_NE(inwards.find("the normals point inwards"), std::string::npos) << inwards;

  OrientedPoints lonely = fibonacci_sphere(1000);
  lonely.positions.row(3) << 5, 5, 5;
  const std::string isolated = error_of([&] { ImplicitSurface s(lonely); });
  EXPECT_NE(isolated.find("point 3 is isolated"), std::string::npos) << isolated;
}

// Two spheres sampled whole and overlapping (centres 1 apart, radius 1: the sheets cross at 60
// degrees along a circle) form a self-intersecting sample set; the same spheres 3 apart do not.
TEST(ImplicitSurface, RefusesASelfIntersectingSampleSet) {
  auto pair_of_spheres = [](double separation) {
    const OrientedPoints one = fibonacci_sphere(1000);
    OrientedPoints two;
    two.source = "two spheres";
    two.positions.resize(2000, 3);
    two.normals.resize(2000, 3);
    two.positions << one.positions.rowwise() - Eigen::RowVector3d(0.5 * separation, 0, 0),
        one.positions.rowwise() + Eigen::RowVector3d(0.5 * separation, 0, 0);
    two.normals << one.normals, one.normals;
    return two;
  };
  const std::string crossing = error_of([&] { ImplicitSurface s(pair_of_spheres(1.0)); });
  EXPECT_NE(crossing.find("two spheres: the sample set intersects itself near point"), std::string::npos) << crossing;
  EXPECT_EQ(error_of([&] { ImplicitSurface s(pair_of_spheres(3.0)); }), "(no error)");
}

TEST(ImplicitSurface, CubeMeshThroughTheWholePipeline) {
  // OFF cube -> samples -> implicit function -> octree nodes and quadrature: its volume is the
  // cube's within the clipped leaves' error, and the MLS covering holds at every point.
  const OrientedPoints p = read_oriented_points(temp_file("pipeline.off", cube_off()), {0.04, 3});
  auto surface = std::make_shared<ImplicitSurface>(p);
  const OctreeSampling s = sample_shape(ImplicitSurface::shape(surface), {0.2, 2, 2});
  EXPECT_NEAR(s.volume(), 1.0, 2e-2);
  const MlsShapeFunctions mls(s.nodes, s.spacing);
  EXPECT_NO_THROW(build_meshless_quadrature(mls, s.points, s.weights));
}

}  // namespace
}  // namespace tailor::point_input_test
