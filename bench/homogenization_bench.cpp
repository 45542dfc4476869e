// Homogenization time against cell size, split into assembly, factorization and the solves
// of all unit macro strains, with the error of C^H against the finest cell of the same
// geometry (a disc or sphere inclusion of radius 0.3, E ratio 10, elements by centroid).
//   homogenization_bench [--max2d N] [--max3d N] [--n2d a,b,...] [--n3d a,b,...] [--out FILE]
// (--max: doubling from 32 (2D) / 8 (3D); --n: explicit grid sizes instead)
// writes FILE (default bench_homogenization.json) and prints a table.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/timing.hpp"
#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/linear_homogenization.hpp"

namespace tailor::bench::homogenization_bench {

namespace {

using namespace tailor;

struct Row {
  int dim, n, elements, unknowns;
  double setup, assembly, factorization, solves, total;
  Matrix C;
};

Row run(int dim, int n) {
  const auto t0 = Clock::now();
  const Mesh mesh = dim == 2
                        ? lattice_triangle_mesh(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), n, n)
                        : lattice_tet_mesh(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), n, n, n);
  LinearCell cell(make_box_periodic_cell(mesh));
  const double setup = seconds_since(t0);
  const int ne = mesh.num_elements();
  Vector E(ne);
  for (int e = 0; e < ne; ++e) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(dim);
    for (int a = 0; a <= dim; ++a) c += mesh.rest_positions.row(mesh.elements(e, a)).transpose() / (dim + 1);
    E[e] = (c.array() - 0.5).matrix().norm() < 0.3 ? 10.0 : 1.0;
  }
  const auto t1 = Clock::now();
  const LinearHomogenization h = cell.solve(E, Vector::Constant(ne, 0.3));
  const double total = seconds_since(t1);
  return {dim,
          n,
          ne,
          dim * (cell.cell().num_periodic_nodes() - 1),
          setup,
          h.assembly_seconds,
          h.factorization_seconds,
          h.solve_seconds,
          total,
          h.stiffness};
}

}  // namespace

int run(int argc, char** argv) {
  int max2d = 512, max3d = 32;
  std::string out = "bench_homogenization.json";
  std::vector<int> n2d, n3d;
  bench::Cli cli("homogenization_bench", "Homogenization time against cell size, and the error of C^H.");
  cli.integer("--max2d", max2d, "largest 2D grid, doubling from 32 (0: no 2D cells)", 0);
  cli.integer("--max3d", max3d, "largest 3D grid, doubling from 8 (0: no 3D cells)", 0);
  cli.integers("--n2d", n2d, "2D grid sizes instead of the doubling", 1);
  cli.integers("--n3d", n3d, "3D grid sizes instead of the doubling", 1);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::vector<Row> rows;
  if (n2d.empty())
    for (int n = 32; n <= max2d; n *= 2) n2d.push_back(n);
  if (n3d.empty())
    for (int n = 8; n <= max3d; n *= 2) n3d.push_back(n);
  for (const int n : n2d) rows.push_back(run(2, n));
  for (const int n : n3d) rows.push_back(run(3, n));
  std::printf("%3s %5s %9s %9s %8s %9s %8s %8s %10s\n", "dim", "n", "elements", "unknowns", "setup_s",
              "assembly_s", "factor_s", "solves_s", "rel_error");
  bench::Json json = bench::report("homogenization");
  bench::Json results = bench::Json::array();
  for (const Row& r : rows) {
    // Error against the finest cell of the same dimension.
    const Row* finest = &r;
    for (const Row& s : rows)
      if (s.dim == r.dim && s.n > finest->n) finest = &s;
    const double error = (r.C - finest->C).norm() / finest->C.norm();
    std::printf("%3d %5d %9d %9d %8.3f %9.3f %8.3f %8.3f %10.2e\n", r.dim, r.n, r.elements, r.unknowns,
                r.setup, r.assembly, r.factorization, r.solves, error);
    results.push_back({{"dim", r.dim},
                       {"n", r.n},
                       {"elements", r.elements},
                       {"unknowns", r.unknowns},
                       {"setup_seconds", r.setup},
                       {"assembly_seconds", r.assembly},
                       {"factorization_seconds", r.factorization},
                       {"solve_seconds", r.solves},
                       {"relative_error_vs_finest", error}});
  }
  json["rows"] = results;
  return bench::write_report(out, json, "homogenization_bench") ? 0 : 1;
}

}  // namespace tailor::bench::homogenization_bench
