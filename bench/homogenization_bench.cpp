// Homogenization time against cell size, split into assembly, factorization and the solves
// of all unit macro strains, with the error of C^H against the finest cell of the same
// geometry (a disc or sphere inclusion of radius 0.3, E ratio 10, elements by centroid).
//   homogenization_bench [--max2d N] [--max3d N] [--n2d a,b,...] [--n3d a,b,...] [--out FILE]
// (--max: doubling from 32 (2D) / 8 (3D); --n: explicit grid sizes instead)
// writes FILE (default homogenization_bench.json) and prints a table.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "forward/core/timing.hpp"
#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/linear_homogenization.hpp"

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

int main(int argc, char** argv) {
  int max2d = 512, max3d = 32;
  std::string out = "homogenization_bench.json";
  std::vector<int> n2d, n3d;
  const auto parse_list = [](const std::string& text) {
    std::vector<int> values;
    std::size_t start = 0;
    while (start < text.size()) {
      const std::size_t end = text.find(',', start);
      values.push_back(std::atoi(text.substr(start, end - start).c_str()));
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return values;
  };
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--max2d")
      max2d = std::atoi(argv[i + 1]);
    else if (a == "--max3d")
      max3d = std::atoi(argv[i + 1]);
    else if (a == "--out")
      out = argv[i + 1];
    else if (a == "--n2d")
      n2d = parse_list(argv[i + 1]);
    else if (a == "--n3d")
      n3d = parse_list(argv[i + 1]);
  }
  std::vector<Row> rows;
  if (n2d.empty())
    for (int n = 32; n <= max2d; n *= 2) n2d.push_back(n);
  if (n3d.empty())
    for (int n = 8; n <= max3d; n *= 2) n3d.push_back(n);
  for (const int n : n2d)
    if (n > 0) rows.push_back(run(2, n));
  for (const int n : n3d)
    if (n > 0) rows.push_back(run(3, n));
  std::ofstream json(out);
  json << "{\"rows\": [\n";
  std::printf("%3s %5s %9s %9s %8s %9s %8s %8s %10s\n", "dim", "n", "elements", "unknowns", "setup_s",
              "assembly_s", "factor_s", "solves_s", "rel_error");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    // Error against the finest cell of the same dimension.
    const Row* finest = &r;
    for (const Row& s : rows)
      if (s.dim == r.dim && s.n > finest->n) finest = &s;
    const double error = (r.C - finest->C).norm() / finest->C.norm();
    std::printf("%3d %5d %9d %9d %8.3f %9.3f %8.3f %8.3f %10.2e\n", r.dim, r.n, r.elements, r.unknowns,
                r.setup, r.assembly, r.factorization, r.solves, error);
    json << "  {\"dim\": " << r.dim << ", \"n\": " << r.n << ", \"elements\": " << r.elements
         << ", \"unknowns\": " << r.unknowns << ", \"setup_seconds\": " << r.setup
         << ", \"assembly_seconds\": " << r.assembly << ", \"factorization_seconds\": " << r.factorization
         << ", \"solve_seconds\": " << r.solves << ", \"relative_error_vs_finest\": " << error << "}"
         << (i + 1 < rows.size() ? ",\n" : "\n");
  }
  json << "]}\n";
  return 0;
}
