#include "problems/material_fit/load_cases.hpp"

#include <cmath>
#include <stdexcept>

#include "forward/fem/spline_elastic_term.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor {
namespace {

bool on(double coordinate, double value) { return std::abs(coordinate - value) < 1e-9; }

}  // namespace

std::string to_string(LoadCaseKind kind) {
  switch (kind) {
    case LoadCaseKind::uniaxial:
      return "uniaxial";
    case LoadCaseKind::biaxial:
      return "biaxial";
    case LoadCaseKind::shear:
      return "shear";
  }
  return "unknown";
}

LoadCaseKind parse_load_case_kind(const std::string& name) {
  for (LoadCaseKind k : {LoadCaseKind::uniaxial, LoadCaseKind::biaxial, LoadCaseKind::shear})
    if (name == to_string(k)) return k;
  throw std::invalid_argument("unknown load case '" + name + "' (expected uniaxial, biaxial or shear)");
}

Mesh load_case_mesh(int cells) {
  return box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), cells, cells, cells);
}

SpecimenStep load_step(const Mesh& mesh, const LoadCase& c, int step, std::unique_ptr<EnergyTerm> term,
                       int num_parameters) {
  if (step < 0 || step >= static_cast<int>(c.amplitudes.size()))
    throw std::invalid_argument("load case '" + c.name + "': no step " + std::to_string(step));
  const double a = c.amplitudes[step];
  SpecimenStep s;
  const int n = 3 * mesh.num_vertices();
  s.model = std::make_unique<Model>(n);
  s.model->parameter_layout().add("curve_controls", num_parameters);
  s.term = &s.model->add(std::move(term));
  Vector x0(n);
  for (int v = 0; v < mesh.num_vertices(); ++v) x0.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();
  Vector target = x0;
  std::vector<int> fixed;
  s.measured_weights.setZero();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d X = mesh.rest_positions.row(v).transpose();
    auto fix = [&](int k, double value) {
      fixed.push_back(3 * v + k);
      target[3 * v + k] = value;
    };
    switch (c.kind) {
      case LoadCaseKind::uniaxial:
        if (on(X.z(), 0.0)) fix(2, 0.0);
        if (on(X.z(), 1.0)) {
          fix(2, a);
          s.measured_dofs.push_back(3 * v + 2);
        }
        if (on(X.x(), 0.0) && on(X.y(), 0.0) && on(X.z(), 0.0)) {
          fix(0, 0.0);
          fix(1, 0.0);
        }
        if (on(X.x(), 1.0) && on(X.y(), 0.0) && on(X.z(), 0.0)) fix(1, 0.0);
        s.measured_weights << 0, 0, 1;
        break;
      case LoadCaseKind::biaxial:
        if (on(X.y(), 0.0)) fix(1, 0.0);
        if (on(X.x(), 0.0)) fix(0, 0.0);
        if (on(X.z(), 0.0)) fix(2, 0.0);
        if (on(X.x(), 1.0)) {
          fix(0, a);
          s.measured_dofs.push_back(3 * v);
        }
        if (on(X.z(), 1.0)) {
          fix(2, a);
          s.measured_dofs.push_back(3 * v + 2);
        }
        s.measured_weights << 1, 0, 1;
        break;
      case LoadCaseKind::shear:
        if (on(X.z(), 0.0)) {
          fix(0, X.x());
          fix(1, X.y());
          fix(2, 0.0);
        }
        if (on(X.z(), 1.0)) {
          fix(0, X.x() + a);
          fix(1, X.y());
          fix(2, 1.0);
          s.measured_dofs.push_back(3 * v);
        }
        s.measured_weights << 1, 0, 0;
        break;
    }
  }
  s.model->set_elimination(Elimination::dirichlet(fixed, target));
  if (s.model->elimination().num_free() == 0)
    throw std::invalid_argument("load case '" + c.name +
                                "': the specimen has no free vertex (use 2 or more cells)");
  s.rest_y = s.model->elimination().restrict_state(x0);
  return s;
}

SpecimenStep spline_load_step(const Mesh& mesh, const LoadCase& c, int step,
                              const PrincipalStretchCurves& knots) {
  return load_step(mesh, c, step, std::make_unique<SplineElasticTerm<3>>(mesh, knots, 0),
                   knots.num_controls());
}

double measured_force(const SpecimenStep& s, const Vector& x, const Vector& p) {
  Vector g = Vector::Zero(x.size());
  s.term->add_gradient(x, p, g);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int dof : s.measured_dofs) total[dof % 3] += g[dof];
  return s.measured_weights.dot(total);
}

std::shared_ptr<TargetReactionForces> reaction_objective(const SpecimenStep& s, double target,
                                                         double force_scale) {
  // Residual w^(1/2) (total - target), per measured component; biaxial measures two components
  // whose sum is the target, each taken as half of it (the test is symmetric).
  const double components = s.measured_weights.sum();
  const Vector target_totals = s.measured_weights * (target / components);
  const Vector weights = s.measured_weights / (force_scale * force_scale);
  return std::make_shared<TargetReactionForces>(*s.term, s.model->num_dofs(), 3, s.measured_dofs,
                                                TargetReactionForces::Aggregation::total, target_totals,
                                                weights);
}

}  // namespace tailor
