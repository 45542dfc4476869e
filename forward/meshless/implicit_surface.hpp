#pragma once
// An inside/outside function from oriented points (docs/meshless.md, "Implicit surface"): a
// partition of unity of local fits Q_i centred at the samples,
//   f(X) = sum_i w_i(X) Q_i(X) / sum_i w_i(X),   w_i = W(|X - p_i| / rho),
// W the C2 Wendland function (1 - r)^4 (4 r + 1) on [0, 1]: the multi-level partition of unity
// of Ohtake et al. (2003) at one level, with the samples as centres. Local fits:
//   quadric (the meshless scene's default): in the frame (t1, t2, n_i) at p_i, (u, v, w) = the coordinates of X - p_i,
//     Q_i(X) = w - h_i(u, v),  h_i = a u^2 + b u v + c v^2 + d u + e v + g,
//     Ohtake et al.'s local bivariate quadric: weighted least squares (weights w_j(p_i)) to the
//     heights of the neighbours within rho and to the slopes their normals give
//     (dh/du = -m_u / m_w, dh/dv = -m_v / m_w: the normals' constraint). A sample falls back to
//     the linear fit where a neighbour's normal is over 45 degrees from its own (a sharp edge,
//     where no height function exists; neighbours of an opposite sheet, n_i . m_j < 0, are left
//     out of the fit), where fewer than 6 neighbours take part, where the normal equations'
//     condition number exceeds 1e8, or where the fit bends by more than rho over rho (|a|, |b|,
//     |c| > 1 / rho);
//   linear (this struct's default, for callers that size no MLS patches: the quadrics' zero
//     level can pass just inside a node lattice's planes, where uncovered points then appear;
//     covering_patches.hpp repairs them): Q_i(X) = (X - p_i) . n_i, the tangent plane (the implicit moving-least-squares
//     surface of Shen, O'Brien & Shewchuk 2004 and Kolluri 2005). The tangent planes of a convex
//     surface lie outside it, so its zero set sits outside by O(rho^2 curvature); the quadrics
//     remove that term.
// Where no sample lies within rho, f is the distance to the nearest sample's tangent plane
// (Hoppe et al. 1992). f < 0 inside.
//
// rho = support_factor * s, s the median over the samples of the distance to their 6th nearest
// neighbour. Before use the samples are checked, each failure a PointInputError naming the file
// and point (with its line):
//   - an isolated point (fewer than 3 neighbours within rho);
//   - inconsistent normals: two samples within rho on the same sheet (each within 0.3 |p_j - p_i|
//     of the other's tangent plane) whose normals point in opposite directions (n_i . n_j < -0.5);
//   - an open sample set: a sample whose neighbours (those of an opposite sheet excepted),
//     projected onto its tangent plane, leave an angular gap above 150 degrees (a boundary of
//     the sampled surface; at an edge of a closed one the other face closes the fan). Samples
//     with neighbours whose normals differ by 45 to 120 degrees (sharp edges and corners, where
//     the fan is legitimately incomplete) are not judged, so an open boundary along a sharp
//     edge escapes this check (meshes are checked for closure exactly before sampling);
//   - a self-intersecting sample set: two neighbours of a sample, one on each side of its tangent
//     plane (each at least 0.3 of its distance off it), that lie on one sheet crossing it (normals
//     within 25 degrees of each other and over 25 degrees from the sample's, their difference
//     within 0.3 of its length of their tangent plane). At an edge of a closed solid, and at a
//     thin wall, the other sheet lies on one side only. Crossings at under 25 degrees escape it;
//   - normals pointing inwards: f > 0 required at the corners of the enlarged bounding box.
//
// As an AnalyticShape (for octree_sampling.hpp) the inside test is f <= 0, and the distance
// that classifies octree cells is f itself within rho of a sample (where f approximates the
// signed distance up to O(rho^2 curvature)) and sign(f) * max(0, d_s - s) beyond (d_s the
// distance to the nearest sample: no larger than the distance to the surface as long as every
// surface point lies within s of a sample). A cell is thus refined only in a band about its
// half-diagonal wide around the surface; the classification is approximate where the surface
// curves on the scale of rho.
#include <memory>
#include <vector>

#include "forward/meshless/analytic_shape.hpp"
#include "forward/meshless/point_cloud_io.hpp"

namespace tailor {

enum class ImplicitFit { linear, quadric };

struct ImplicitSurfaceOptions {
  double support_factor = 2.0;  // rho = support_factor * the median 6th-neighbour distance
  ImplicitFit fit = ImplicitFit::linear;  // the local fits Q_i (see above)
  bool check_samples = true;    // the checks above (isolated, inconsistent, open, inward)
};

struct ImplicitSurfaceReport {
  int samples = 0;
  double neighbour_distance = 0.0;  // s
  double support_radius = 0.0;      // rho
  int min_neighbours = 0;           // fewest samples within rho of a sample (itself excluded)
  double max_boundary_gap = 0.0;    // largest angular gap met by the open-set check [rad]
  int quadric_fits = 0;             // samples with a quadric fit
  int linear_fits = 0;              // samples with the tangent plane (by choice or fallback)
};

class ImplicitSurface {
 public:
  // PointInputError (see above) on a bad sample set; std::invalid_argument on a bad option.
  ImplicitSurface(OrientedPoints points, ImplicitSurfaceOptions options = {});
  ~ImplicitSurface();
  ImplicitSurface(const ImplicitSurface&) = delete;
  ImplicitSurface& operator=(const ImplicitSurface&) = delete;

  double value(const Eigen::Vector3d& X) const;             // f(X)
  double nearest_distance(const Eigen::Vector3d& X, int* nearest = nullptr) const;  // d_s(X)
  double classifying_distance(const Eigen::Vector3d& X) const;  // see above
  const ImplicitSurfaceReport& report() const { return report_; }
  const OrientedPoints& points() const { return points_; }
  // The samples' indices within `radius` of X.
  std::vector<int> neighbours(const Eigen::Vector3d& X, double radius) const;

  // The shape for sample_shape(): bounding box of the samples; keeps this object alive.
  static AnalyticShape shape(std::shared_ptr<const ImplicitSurface> surface);

 private:
  struct Grid;
  // The local fit at a sample: Q(X) = w - h(u, v) in the frame (t1, t2, n) (see above); all
  // coefficients zero for the tangent plane.
  struct LocalFit {
    Eigen::Vector3d t1 = Eigen::Vector3d::Zero(), t2 = Eigen::Vector3d::Zero();
    double a = 0.0, b = 0.0, c = 0.0, d = 0.0, e = 0.0, g = 0.0;
  };
  void check_samples();
  void fit_quadrics();
  double local_value(int i, const Eigen::Vector3d& X) const;  // Q_i(X)
  OrientedPoints points_;
  std::vector<LocalFit> fits_;  // empty for linear fits
  ImplicitSurfaceOptions options_;
  ImplicitSurfaceReport report_;
  std::unique_ptr<Grid> grid_;
};

}  // namespace tailor
