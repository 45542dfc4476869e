// Homogenization time against cell size, split into assembly, factorization and the solves
// of all unit macro strains, with the error of C^H against the finest cell of the same
// geometry (a disc or sphere inclusion of radius 0.3, E ratio 10, elements by centroid).
// Rod-network cells: time per effective tensor (assembly, factorization, 3 solves; median of
// --repeats) of the square and honeycomb rod lattices (a/l = 0.01) for each --rod-edges (edges
// per bar), with the relative error of E_1 = 1 / S_11 against Gibson & Ashby's closed form.
//   homogenization_bench [--max2d N] [--max3d N] [--n2d a,b,...] [--n3d a,b,...]
//                        [--rod-edges a,b,...] [--repeats N] [--out FILE]
// (--max: doubling from 32 (2D) / 8 (3D); --n: explicit grid sizes instead)
// writes FILE (default bench_homogenization.json) and prints two tables.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/timing.hpp"
#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/linear_homogenization.hpp"
#include "forward/homogenization/rod_network_cell.hpp"

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

struct RodRow {
  std::string lattice;
  int edges_per_bar, unknowns;
  double setup, median_tensor, assembly, factorization, solves, error;
};

// a/l = 0.01, E = 1, nu = 0.3. Reference E_1 (membrane, uniaxial stress): the square grid E pi a^2 / l (stretching), the
// regular honeycomb 12 E I cos(theta) / ((h + l sin(theta)) l^2 sin^2(theta)) with I = pi a^4 / 4
// (Gibson & Ashby, Cellular Solids, eq. 4.4, per unit depth).
RodRow run_rods(bool honeycomb, int edges, int repeats) {
  const double l = 1.0, a = 0.01, E = 1.0, G = E / 2.6;
  const auto t0 = Clock::now();
  RodNetworkCell cell(honeycomb ? honeycomb_rod_lattice(l, a, E, G, edges) : square_rod_lattice(l, a, E, G, edges));
  const double setup = seconds_since(t0);
  std::vector<double> times;
  RodNetworkHomogenization h;
  for (int k = 0; k < repeats; ++k) {
    const auto t1 = Clock::now();
    h = cell.solve();
    times.push_back(seconds_since(t1));
  }
  std::sort(times.begin(), times.end());
  const double I = M_PI * std::pow(a, 4) / 4.0;
  const double reference = honeycomb ? 12.0 * E * I * std::cos(M_PI / 6) / (1.5 * l * l * l * 0.25)
                                     : E * M_PI * a * a / l;
  const double E1 = 1.0 / compliance(h.stiffness)(0, 0);  // uniaxial stress along x
  return {honeycomb ? "honeycomb" : "square", edges, cell.num_free(), setup, times[times.size() / 2],
          h.assembly_seconds, h.factorization_seconds, h.solve_seconds, std::abs(E1 / reference - 1.0)};
}

}  // namespace

int run(int argc, char** argv) {
  int max2d = 512, max3d = 32;
  std::string out = "bench_homogenization.json";
  std::vector<int> n2d, n3d, rod_edges{4, 16, 64, 256};
  int repeats = 5;
  bench::Cli cli("homogenization_bench", "Homogenization time against cell size, and the error of C^H.");
  cli.integer("--max2d", max2d, "largest 2D grid, doubling from 32 (0: no 2D cells)", 0);
  cli.integer("--max3d", max3d, "largest 3D grid, doubling from 8 (0: no 3D cells)", 0);
  cli.integers("--n2d", n2d, "2D grid sizes instead of the doubling", 1);
  cli.integers("--n3d", n3d, "3D grid sizes instead of the doubling", 1);
  cli.integers("--rod-edges", rod_edges, "edges per bar of the rod-network cells", 1);
  cli.repeats(repeats);
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
  std::printf("\n%-10s %6s %9s %8s %12s %10s %8s %8s %10s\n", "rod_cell", "edges", "unknowns", "setup_s",
              "tensor_s(med)", "assembly_s", "factor_s", "solves_s", "GA_error");
  bench::Json rod_results = bench::Json::array();
  for (const bool honeycomb : {false, true})
    for (const int edges : rod_edges) {
      const RodRow r = run_rods(honeycomb, edges, repeats);
      std::printf("%-10s %6d %9d %8.4f %12.5f %10.5f %8.5f %8.5f %10.2e\n", r.lattice.c_str(), r.edges_per_bar,
                  r.unknowns, r.setup, r.median_tensor, r.assembly, r.factorization, r.solves, r.error);
      rod_results.push_back({{"lattice", r.lattice},
                             {"edges_per_bar", r.edges_per_bar},
                             {"unknowns", r.unknowns},
                             {"setup_seconds", r.setup},
                             {"median_seconds_per_tensor", r.median_tensor},
                             {"assembly_seconds", r.assembly},
                             {"factorization_seconds", r.factorization},
                             {"solve_seconds", r.solves},
                             {"relative_error_vs_gibson_ashby", r.error}});
    }
  json["rod_network_rows"] = rod_results;
  return bench::write_report(out, json, "homogenization_bench") ? 0 : 1;
}

}  // namespace tailor::bench::homogenization_bench
