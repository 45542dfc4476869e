// Cost of the principal-stretch spline material against the closed-form stable Neo-Hookean:
// energy + gradient + Hessian values of the elastic term (exact and projected) on a block of
// ~50k tets in a deformed state, and the material evaluation alone (energy, stress, tangent per
// element). The spline material uses the Neo-Hookean preset (same small-strain response); its
// per-element work is one 3x3 SVD, 7 spline lookups and the tangent assembled in the SVD basis.
// Median of repeats. Writes JSON (--out, default bench_spline_material.json), prints a table.
//
// usage: spline_material_bench [--tets 50000] [--repeats 7] [--out FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/statistics.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/materials/spline_material.hpp"
#include "forward/fem/spline_elastic_term.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::bench::spline_material_bench {

using namespace tailor;

namespace {

using Clock = std::chrono::steady_clock;

template <class F>
double median_seconds(int repeats, F&& work) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    work();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return median(t);
}

struct Row {
  std::string what;
  double neo_hookean = 0, spline = 0;
};

}  // namespace

int run(int argc, char** argv) {
  int target_tets = 50000, repeats = 7;
  std::string out = "bench_spline_material.json";
  bench::Cli cli("spline_material_bench",
                 "Cost of the principal-stretch spline material vs stable Neo-Hookean.");
  cli.tets(target_tets);
  cli.repeats(repeats);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;

  const int n = std::max(1, static_cast<int>(std::lround(std::cbrt(target_tets / 6.0))));
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), n, n, n);
  const int m = mesh.num_elements();
  const double E = 1e3, nu = 0.35;
  const LameParameters lame = lame_from_young_poisson(E, nu);

  // Deformed state: stretch, shear and a random perturbation (some elements strongly compressed).
  Vector x(3 * mesh.num_vertices());
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  Eigen::Matrix3d A;
  A << 1.3, 0.2, 0.0, 0.0, 0.9, 0.1, -0.1, 0.0, 0.8;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    x.segment<3>(3 * v) =
        A * mesh.rest_positions.row(v).transpose() + Eigen::Vector3d(u(rng), u(rng), u(rng)) / n;

  Vector pe(2 * m);
  pe.head(m).setConstant(E);
  pe.tail(m).setConstant(nu);
  const ElasticTerm<3> nh(mesh, make_material<3>(MaterialKind::neo_hookean), 0, m);
  const PrincipalStretchCurves curves = principal_stretch_preset(SplinePreset::neo_hookean, lame);
  const SplineElasticTerm<3> spline(mesh, curves, 0);
  const Vector pc = curves.controls();

  constexpr int kSlots = 144;
  std::vector<double> hessian(static_cast<std::size_t>(m) * kSlots);
  Vector gradient = Vector::Zero(x.size());
  double value = 0.0;
  auto term_work = [&](const EnergyTerm& term, const Vector& p, HessianMode mode) {
    return [&, mode] {
      gradient.setZero();
      value = 0.0;
      EnergyRequest r;
      r.value = &value;
      r.gradient = &gradient;
      r.hessian_values = hessian.data();
      r.hessian_mode = mode;
      term.evaluate(x, p, r);
    };
  };
  std::vector<Eigen::Matrix3d> Fs(m);
  for (int k = 0; k < m; ++k) Fs[k] = nh.deformation_gradient(x, k);
  const auto nh_material = make_material<3>(MaterialKind::neo_hookean);
  const SplineMaterial<3> spline_material(curves);
  auto material_work = [&](const Material<3>& material, HessianMode mode) {
    return [&, mode] {
      double sum = 0.0;
      for (int k = 0; k < m; ++k) {
        MaterialEvaluation<3> e;
        material.evaluate(Fs[k], lame, true, true, mode, e);
        sum += e.energy_density + e.tangent(0, 0);
      }
      value = sum;
    };
  };

  std::vector<Row> rows;
  for (HessianMode mode : {HessianMode::exact, HessianMode::projected}) {
    const std::string tag = mode == HessianMode::exact ? "exact" : "projected";
    Row term{"term energy+gradient+Hessian (" + tag + ")"};
    term.neo_hookean = median_seconds(repeats, term_work(nh, pe, mode));
    term.spline = median_seconds(repeats, term_work(spline, pc, mode));
    rows.push_back(term);
    Row material{"material evaluate, serial (" + tag + ")"};
    material.neo_hookean = median_seconds(repeats, material_work(*nh_material, mode));
    material.spline = median_seconds(repeats, material_work(spline_material, mode));
    rows.push_back(material);
  }

  std::printf("spline material vs stable Neo-Hookean, %d tets, median of %d\n", m, repeats);
  std::printf("%-46s %14s %14s %8s\n", "", "neo_hookean [s]", "spline [s]", "ratio");
  for (const Row& r : rows)
    std::printf("%-46s %14.4f %14.4f %8.2f\n", r.what.c_str(), r.neo_hookean, r.spline,
                r.spline / r.neo_hookean);
  bench::Json json = bench::report("spline_material");
  json["tets"] = m;
  json["repeats"] = repeats;
  bench::Json results = bench::Json::array();
  for (const Row& r : rows)
    results.push_back({{"what", r.what},
                       {"neo_hookean_seconds", r.neo_hookean},
                       {"spline_seconds", r.spline},
                       {"ratio", r.spline / r.neo_hookean}});
  json["rows"] = results;
  return bench::write_report(out, json, "spline_material_bench") ? 0 : 1;
}

}  // namespace tailor::bench::spline_material_bench
