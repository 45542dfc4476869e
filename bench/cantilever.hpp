#pragma once
// The cantilever scene and timing helpers shared by the dynamics benchmarks (dynamics_bench,
// reduced_dynamics_bench, reduction_error_bench): a length x 1 x 1 bar of along x across x
// across cells of 6 tets, clamped at x = 0, with one elastic term of a chosen material and
// parameter blocks "youngs_modulus" and "poisson_ratio" (one entry per element) first.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <memory>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/core/statistics.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::bench {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
// Process CPU seconds (all threads): with OMP_NUM_THREADS=1 it measures the work done without
// the waiting a loaded machine adds to wall-clock time.
inline double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

using tailor::median;  // forward/core/statistics.hpp

struct CantileverCells {
  int along = 1, across = 1;
};
// n x n cells across (n = floor(cbrt(target / (6 length)))), as many along the length as bring
// the tet count nearest the target (57,798 tets for 58000 and length 4).
inline CantileverCells cantilever_cells(int target_tets, double length) {
  const int n = std::max(1, static_cast<int>(std::floor(std::cbrt(target_tets / (6.0 * length)))));
  return {std::max(1, static_cast<int>(std::lround(target_tets / (6.0 * n * n)))), n};
}

struct Cantilever {
  Mesh mesh;
  std::unique_ptr<Model> model;
  Vector rest;                    // rest positions as a state vector
  std::vector<int> fixed_dofs;    // the DOFs of the clamped face x = 0
  std::vector<int> tip_vertices;  // vertices of the free end x = length
};

// The bar with its elastic term; `add_terms` (optional) adds further terms (e.g. dynamics) to
// the model before the clamp is set as its elimination. Parameters: p[0, m) Young's moduli,
// p[m, 2m) Poisson's ratios, then whatever add_terms appended.
inline Cantilever make_cantilever(double length, CantileverCells cells, MaterialKind material,
                                  const std::function<void(Model&, const Mesh&)>& add_terms = {}) {
  Cantilever c;
  c.mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(length, 1, 1), cells.along, cells.across,
                        cells.across);
  const int m = c.mesh.num_elements();
  c.model = std::make_unique<Model>(3 * c.mesh.num_vertices());
  const int youngs = c.model->parameter_layout().add("youngs_modulus", m);
  const int poisson = c.model->parameter_layout().add("poisson_ratio", m);
  c.model->add(std::make_unique<ElasticTerm<3>>(c.mesh, make_material<3>(material), youngs, poisson));
  if (add_terms) add_terms(*c.model, c.mesh);
  c.rest.resize(3 * c.mesh.num_vertices());
  for (int v = 0; v < c.mesh.num_vertices(); ++v) {
    c.rest.segment<3>(3 * v) = c.mesh.rest_positions.row(v).transpose();
    if (c.mesh.rest_positions(v, 0) < 1e-9)
      for (int k = 0; k < 3; ++k) c.fixed_dofs.push_back(3 * v + k);
    if (c.mesh.rest_positions(v, 0) > length - 1e-9) c.tip_vertices.push_back(v);
  }
  c.model->set_elimination(Elimination::dirichlet(c.fixed_dofs, c.rest));
  return c;
}

// p of the model with every Young's modulus and Poisson's ratio set (other entries zero).
inline Vector cantilever_parameters(const Cantilever& c, double youngs_modulus, double poisson_ratio) {
  const int m = c.mesh.num_elements();
  Vector p = Vector::Zero(c.model->parameter_layout().size());
  p.head(m).setConstant(youngs_modulus);
  p.segment(m, m).setConstant(poisson_ratio);
  return p;
}

}  // namespace tailor::bench
