#include "problems/meshless/meshless_scene.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>

#include "forward/fem/loads.hpp"
#include "forward/meshless/essential_conditions.hpp"
#include "forward/meshless/meshless_elastic_term.hpp"
#include "forward/meshless/point_cloud_io.hpp"
#include "objectives/linear_observations.hpp"
#include "objectives/tikhonov.hpp"
#include "objectives/weighted_sum.hpp"
#include "problems/optimizer_section.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"
#include "problems/solver_keys.hpp"

namespace tailor {

namespace {

MeshlessBox parse_meshless_box(const SceneNode& node) {
  node.expect_keys({"lo", "hi"});
  MeshlessBox b{node.at("lo").vector(3), node.at("hi").vector(3)};
  if (!(b.lo.array() <= b.hi.array()).all()) node.fail("expected lo <= hi in every coordinate");
  return b;
}

MeshlessPointForce parse_meshless_force(const SceneNode& node) {
  node.expect_keys({"at", "force"});
  return {node.at("at").vector(3), node.at("force").vector(3)};
}

AnalyticShape parse_meshless_shape(const SceneNode& node) {
  const std::string kind = node.only_key({"box", "sphere", "cylinder"});
  const SceneNode s = node.at(kind.c_str());
  if (kind == "box") {
    const MeshlessBox b = parse_meshless_box(s);
    if (!(b.lo.array() < b.hi.array()).all()) s.fail("expected lo < hi in every coordinate");
    return box_shape(b.lo, b.hi);
  }
  if (kind == "sphere") {
    s.expect_keys({"center", "radius"});
    return sphere_shape(s.at("center").vector(3), s.at("radius").positive());
  }
  s.expect_keys({"center", "radius", "length", "axis"});
  const int axis = s.has("axis") ? s.at("axis").integer(0) : 2;
  if (axis > 2) s.at("axis").fail("expected 0, 1 or 2");
  return cylinder_shape(s.at("center").vector(3), s.at("radius").positive(), s.at("length").positive(), axis);
}

}  // namespace

MeshlessSceneSpec parse_meshless_scene(const SceneNode& root, const std::string& directory) {
  root.expect_keys({"meshless", "material", "regions", "fixed", "handles", "loads", "solver", "modes", "inverse",
                    "description", "name"});
  MeshlessSceneSpec spec;
  spec.source = root.source();
  spec.directory = directory;
  const SceneNode g = root.at("meshless");
  g.expect_keys({"points", "shape", "surface_spacing", "implicit_support_factor", "implicit_fit", "spacing", "quadrature_order",
                 "boundary_depth", "max_level", "refine_thin", "refine", "covering_condition", "basis", "support_factor"});
  if (g.has("points") == g.has("shape")) g.fail("expected exactly one of \"points\" (a file) and \"shape\"");
  if (g.has("points")) {
    const std::filesystem::path file(g.at("points").string());
    spec.points_file = file.is_absolute() ? file.string() : (std::filesystem::path(directory) / file).string();
  } else {
    spec.shape = parse_meshless_shape(g.at("shape"));
  }
  if (g.has("surface_spacing")) spec.surface_spacing = g.at("surface_spacing").positive();
  if (g.has("implicit_support_factor")) spec.implicit.support_factor = g.at("implicit_support_factor").positive();
  spec.implicit.fit = ImplicitFit::quadric;  // the scene sizes its patches (cover_points)
  if (g.has("implicit_fit"))
    spec.implicit.fit = g.at("implicit_fit").choice({"quadric", "linear"}) == "quadric" ? ImplicitFit::quadric : ImplicitFit::linear;
  spec.sampling.spacing = g.at("spacing").positive();
  spec.sampling.quadrature_order = 2;
  if (g.has("quadrature_order")) {
    spec.sampling.quadrature_order = g.at("quadrature_order").integer(1);
    if (spec.sampling.quadrature_order > 8) g.at("quadrature_order").fail("expected 1 to 8");
  }
  if (g.has("boundary_depth")) {
    spec.sampling.boundary_depth = g.at("boundary_depth").integer(0);
    if (spec.sampling.boundary_depth > 8) g.at("boundary_depth").fail("expected 0 to 8");
  }
  if (g.has("max_level")) {
    spec.sampling.max_level = g.at("max_level").integer(0);
    if (spec.sampling.max_level > 6) g.at("max_level").fail("expected 0 to 6");
  }
  if (g.has("refine_thin")) spec.sampling.refine_thin = g.at("refine_thin").boolean();
  if (const auto refine = g.find("refine"))
    for (const SceneNode& r : refine->items()) {
      r.expect_keys({"box", "level"});
      const MeshlessBox b = parse_meshless_box(r.at("box"));
      const int level = r.at("level").integer(1);
      if (level > spec.sampling.max_level) r.at("level").fail("expected at most meshless.max_level (" + std::to_string(spec.sampling.max_level) + ")");
      spec.sampling.refine_boxes.push_back({b.lo, b.hi, level});
    }
  if (g.has("covering_condition")) {
    spec.covering.target_condition = g.at("covering_condition").positive();
    if (!(spec.covering.target_condition > 1.0)) g.at("covering_condition").fail("expected a number above 1");
  }
  if (g.has("basis")) spec.mls.basis = g.at("basis").choice({"linear", "quadratic"}) == "linear" ? MlsBasis::linear : MlsBasis::quadratic;
  if (g.has("support_factor")) spec.mls.support_factor = g.at("support_factor").positive();

  if (const auto m = root.find("material")) {
    m->expect_keys({"model", "youngs_modulus", "poisson_ratio", "density"});
    if (m->has("model")) {
      try {
        spec.material = parse_material_kind(m->at("model").string());
      } catch (const std::invalid_argument& e) {
        m->at("model").fail(e.what());
      }
    }
    if (m->has("youngs_modulus")) spec.youngs_modulus = m->at("youngs_modulus").positive();
    if (m->has("poisson_ratio")) spec.poisson_ratio = m->at("poisson_ratio").open_interval(-1.0, 0.5);
    if (m->has("density")) spec.density = m->at("density").positive();
  }
  if (const auto regions = root.find("regions"))
    for (const SceneNode& r : regions->items()) {
      r.expect_keys({"name", "box", "youngs_modulus"});
      spec.region_names.push_back(r.has("name") ? r.at("name").string() : "region" + std::to_string(spec.regions.size()));
      spec.regions.push_back(parse_meshless_box(r.at("box")));
      spec.region_moduli.push_back(r.has("youngs_modulus") ? r.at("youngs_modulus").positive() : spec.youngs_modulus);
    }
  if (const auto fixed = root.find("fixed"))
    for (const SceneNode& f : fixed->items()) {
      f.expect_keys({"box"});
      spec.fixed.push_back(parse_meshless_box(f.at("box")));
    }
  if (const auto handles = root.find("handles"))
    for (const SceneNode& h : handles->items()) {
      h.expect_keys({"box", "displacement", "rotation"});
      if (!h.has("displacement") && !h.has("rotation")) h.fail("a handle needs a displacement, a rotation or both");
      spec.handles.push_back(parse_meshless_box(h.at("box")));
      spec.handle_displacements.push_back(h.has("displacement") ? Eigen::Vector3d(h.at("displacement").vector(3))
                                                                : Eigen::Vector3d::Zero());
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      std::optional<Eigen::Vector3d> center;
      if (const auto rotation = h.find("rotation")) {
        rotation->expect_keys({"axis", "degrees", "center"});
        const Eigen::Vector3d axis = rotation->at("axis").vector(3);
        if (!(axis.norm() > 0.0)) rotation->at("axis").fail("the rotation axis must not be zero");
        w = rotation->at("degrees").number() * M_PI / 180.0 * axis.normalized();
        if (rotation->has("center")) center = Eigen::Vector3d(rotation->at("center").vector(3));
      }
      spec.handle_rotations.push_back(w);
      spec.handle_centers.push_back(center);
    }
  if (const auto loads = root.find("loads")) {
    loads->expect_keys({"gravity", "forces"});
    if (loads->has("gravity")) spec.gravity = loads->at("gravity").vector(3);
    if (const auto forces = loads->find("forces"))
      for (const SceneNode& f : forces->items()) spec.forces.push_back(parse_meshless_force(f));
  }
  if (const auto solver = root.find("solver")) {
    solver->expect_keys({"max_newton_iterations", "reuse_factorization"});
    if (solver->has("max_newton_iterations")) spec.max_newton_iterations = solver->at("max_newton_iterations").integer(1);
    if (const auto v = solver->find("reuse_factorization")) spec.reuse_factorization = parse_factor_reuse(*v);
  }
  if (const auto modes = root.find("modes")) {
    modes->expect_keys({"count", "rayleigh", "time_step", "steps", "force", "frame_every", "handle_stiffness"});
    if (modes->has("count")) spec.mode_count = modes->at("count").integer(1);
    if (const auto r = modes->find("rayleigh")) {
      r->expect_keys({"alpha", "beta"});
      if (r->has("alpha")) spec.damping.alpha = r->at("alpha").non_negative();
      if (r->has("beta")) spec.damping.beta = r->at("beta").non_negative();
    }
    if (modes->has("time_step")) spec.time_step = modes->at("time_step").positive();
    if (modes->has("steps")) spec.steps = modes->at("steps").integer(0);
    if (modes->has("frame_every")) spec.frame_every = modes->at("frame_every").integer(1);
    if (const auto f = modes->find("force")) spec.modal_force = parse_meshless_force(*f);
    if (modes->has("handle_stiffness")) spec.handle_stiffness = modes->at("handle_stiffness").positive();
  }
  if (const auto inv = root.find("inverse")) {
    inv->expect_keys({"design", "per", "observations", "regularization", "optimizer", "gradcheck"});
    MeshlessSceneSpec::Inverse in;
    inv->at("design").choice({"youngs_modulus"});
    if (inv->has("per")) in.per_region = inv->at("per").choice({"region", "node"}) == "region";
    if (in.per_region && spec.regions.empty())
      inv->at("design").fail("a design per region needs a \"regions\" section (or \"per\": \"node\")");
    const SceneNode obs = inv->at("observations");
    const std::vector<SceneNode> items = obs.items();
    if (items.empty()) obs.fail("expected at least one observation");
    in.targets.resize(static_cast<Eigen::Index>(items.size()), 3);
    for (std::size_t i = 0; i < items.size(); ++i) {
      items[i].expect_keys({"at", "target", "displacement"});
      const Eigen::Vector3d at = items[i].at("at").vector(3);
      if (items[i].has("target") == items[i].has("displacement"))
        items[i].fail("expected exactly one of \"target\" (a position) and \"displacement\"");
      in.observed.push_back(at);
      in.targets.row(static_cast<Eigen::Index>(i)) =
          (items[i].has("target") ? Eigen::Vector3d(items[i].at("target").vector(3)) : Eigen::Vector3d(at + items[i].at("displacement").vector(3))).transpose();
    }
    if (inv->has("regularization")) in.regularization = inv->at("regularization").non_negative();
    // Newton-CG on the functional's Gauss-Newton products: scale-invariant, where L-BFGS's first
    // step (the gradient of a misfit relative to the size squared) is tiny.
    in.optimizer.backend = OptimizerBackend::newton_cg;
    in.optimizer.max_iterations = 50;
    in.optimizer.gradient_tolerance = 1e-14;
    if (const auto opt = inv->find("optimizer"))
      in.optimizer = parse_optimizer_section(*opt, in.optimizer, {"a meshless scene", true, false, {}});
    if (const auto gc = inv->find("gradcheck")) {
      gc->expect_keys({"seed"});
      if (gc->has("seed")) in.seed = static_cast<unsigned>(gc->at("seed").integer(0));
    }
    spec.inverse = in;
  }
  return spec;
}

Vector MeshlessScene::rest() const {
  const Eigen::MatrixXd t = sampling.nodes.transpose();
  return Eigen::Map<const Vector>(t.data(), t.size());
}

double MeshlessScene::size() const { return (sampling.nodes.colwise().maxCoeff() - sampling.nodes.colwise().minCoeff()).norm(); }

std::unique_ptr<MeshlessScene> build_meshless_scene(const MeshlessSceneSpec& spec) {
  using Clock = std::chrono::steady_clock;
  auto scene = std::make_unique<MeshlessScene>();
  MeshlessScene& S = *scene;
  S.spec = spec;
  const std::string& source = spec.source;
  try {
    auto t0 = Clock::now();
    AnalyticShape shape;
    if (!spec.points_file.empty()) {
      SurfaceSamplingOptions sampling;
      sampling.spacing = spec.surface_spacing;
      auto surface = std::make_shared<ImplicitSurface>(read_oriented_points(spec.points_file, sampling), spec.implicit);
      S.samples = surface->points().positions;
      S.surface = surface;
      shape = ImplicitSurface::shape(surface);
    } else {
      shape = *spec.shape;
    }
    auto t1 = Clock::now();
    S.sampling = sample_shape(shape, spec.sampling);
    if (S.samples.rows() == 0) S.samples = S.sampling.points;
    auto t2 = Clock::now();
    // Patches sized so that every quadrature point and every surface sample is covered.
    Eigen::MatrixXd covered(S.sampling.points.rows() + (S.surface ? S.samples.rows() : 0), 3);
    covered.topRows(S.sampling.points.rows()) = S.sampling.points;
    if (S.surface) covered.bottomRows(S.samples.rows()) = S.samples;
    S.patch_spacing = cover_points(S.sampling.nodes, S.sampling.spacing, covered, spec.mls, spec.covering, &S.covering);
    S.mls = std::make_shared<MlsShapeFunctions>(S.sampling.nodes, S.patch_spacing, spec.mls);
    S.quadrature = std::make_shared<MeshlessQuadrature>(build_meshless_quadrature(*S.mls, S.sampling.points, S.sampling.weights));
    auto t3 = Clock::now();
    S.seconds_implicit = std::chrono::duration<double>(t1 - t0).count();
    S.seconds_sampling = std::chrono::duration<double>(t2 - t1).count();
    S.seconds_quadrature = std::chrono::duration<double>(t3 - t2).count();
  } catch (const PointInputError& e) {
    throw SceneError(source + ": meshless.points: " + e.what());
  } catch (const MeshlessPointError& e) {
    throw SceneError(source + ": meshless: " + e.what());
  } catch (const std::invalid_argument& e) {
    throw SceneError(source + ": meshless: " + e.what());
  }
  const int n = S.num_nodes();
  S.model = std::make_unique<Model>(3 * n);
  S.model->parameter_layout().add("youngs_modulus", n);
  S.model->parameter_layout().add("poisson_ratio", n);
  S.model->add(std::make_unique<MeshlessElasticTerm<3>>(S.quadrature, std::shared_ptr<const Material<3>>(make_material<3>(spec.material)), 0, n));
  S.p.resize(2 * n);
  S.p.head(n).setConstant(spec.youngs_modulus);
  S.p.tail(n).setConstant(spec.poisson_ratio);
  S.region_of_node.assign(static_cast<std::size_t>(n), 0);
  for (int a = 0; a < n; ++a)
    for (std::size_t r = 0; r < spec.regions.size(); ++r)
      if (spec.regions[r].contains(S.sampling.nodes.row(a).transpose())) {
        S.region_of_node[static_cast<std::size_t>(a)] = static_cast<int>(r) + 1;
        S.p[a] = spec.region_moduli[r];
      }
  // Loads: gravity as a body force at the quadrature points, point forces at their points.
  Vector forces = Vector::Zero(3 * n);
  if (spec.gravity.norm() > 0.0) {
    const Eigen::MatrixXd densities = (spec.density * spec.gravity).transpose().replicate(S.sampling.points.rows(), 1);
    forces += meshless_point_forces(*S.mls, S.sampling.points, S.sampling.weights, densities);
  }
  for (std::size_t i = 0; i < spec.forces.size(); ++i) {
    try {
      forces += meshless_point_forces(*S.mls, spec.forces[i].at.transpose(), Eigen::VectorXd::Ones(1), spec.forces[i].force.transpose());
    } catch (const MeshlessPointError& e) {
      throw SceneError(source + ": loads.forces[" + std::to_string(i) + "].at: outside the solid (" + e.what() + ")");
    }
  }
  if (forces.norm() > 0.0) S.model->add(std::make_unique<ExternalForceTerm>(forces));
  // Clamps and handles: x(X_b) = X_b (+ d) at the nodes in their boxes, by the transformation.
  std::vector<int> constrained;
  std::vector<Eigen::Vector3d> targets;
  std::vector<int> owner(static_cast<std::size_t>(n), -1);
  // The nodes in `box` not held already go to c + R (X - c) + d (c: `center`, else their centroid).
  const auto hold = [&](const MeshlessBox& box, const Eigen::Vector3d& d, const Eigen::Vector3d& w,
                        const std::optional<Eigen::Vector3d>& center, const std::string& key) {
    const std::size_t first = constrained.size();
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int a = 0; a < n; ++a) {
      const Eigen::Vector3d X = S.sampling.nodes.row(a).transpose();
      if (!box.contains(X) || owner[static_cast<std::size_t>(a)] >= 0) continue;
      owner[static_cast<std::size_t>(a)] = 1;
      constrained.push_back(a);
      centroid += X;
    }
    const std::size_t count = constrained.size() - first;
    if (count == 0) throw SceneError(source + ": " + key + ": the box holds no node");
    const Eigen::Vector3d c = center ? *center : Eigen::Vector3d(centroid / static_cast<double>(count));
    const Eigen::Matrix3d R = rotation_matrix(w);
    MeshlessScene::Handle handle{{}, Eigen::MatrixXd(static_cast<Eigen::Index>(count), 3), w, c};
    for (std::size_t i = first; i < constrained.size(); ++i) {
      const Eigen::Vector3d X = S.sampling.nodes.row(constrained[i]).transpose();
      targets.push_back(c + R * (X - c) + d);
      handle.nodes.push_back(constrained[i]);
      handle.targets.row(static_cast<Eigen::Index>(i - first)) = targets.back().transpose();
    }
    return handle;
  };
  for (std::size_t i = 0; i < spec.fixed.size(); ++i)
    hold(spec.fixed[i], Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), std::nullopt, "fixed[" + std::to_string(i) + "].box");
  const std::size_t fixed_count = constrained.size();
  for (std::size_t i = 0; i < spec.handles.size(); ++i)
    S.handles.push_back(hold(spec.handles[i], spec.handle_displacements[i], spec.handle_rotations[i], spec.handle_centers[i],
                             "handles[" + std::to_string(i) + "].box"));
  const auto transformation = [&](std::size_t count) {
    Eigen::MatrixXd t(static_cast<Eigen::Index>(count), 3);
    for (std::size_t i = 0; i < count; ++i) t.row(static_cast<Eigen::Index>(i)) = targets[i].transpose();
    try {
      return mls_transformation(*S.mls, std::vector<int>(constrained.begin(), constrained.begin() + static_cast<std::ptrdiff_t>(count)), t)
          .elimination;
    } catch (const std::invalid_argument& e) {
      throw SceneError(source + ": fixed/handles: " + e.what());
    }
  };
  if (!constrained.empty()) S.model->set_elimination(transformation(constrained.size()));
  if (!S.handles.empty()) S.fixed_elimination = fixed_count > 0 ? transformation(fixed_count) : Elimination::identity(3 * n);
  return scene;
}

std::unique_ptr<MeshlessInverse> build_meshless_inverse(const MeshlessScene& S) {
  const MeshlessSceneSpec::Inverse& in = *S.spec.inverse;
  auto out = std::make_unique<MeshlessInverse>();
  const int n = S.num_nodes();
  const Vector E0 = S.p.head(n);
  ParameterizationPtr map = compose(scale_map(E0), exp_map(n));
  if (in.per_region) {
    const int regions = static_cast<int>(S.spec.regions.size()) + 1;
    map = compose(map, region_scatter_map(S.region_of_node, regions));
    out->z0 = Vector::Zero(regions);
    out->labels.push_back("log_youngs_modulus[outside the regions]");
    for (const std::string& name : S.spec.region_names) out->labels.push_back("log_youngs_modulus[" + name + "]");
  } else {
    out->z0 = Vector::Zero(n);
    for (int a = 0; a < n; ++a) out->labels.push_back("log_youngs_modulus[" + std::to_string(a) + "]");
  }
  out->parameterization = embed_blocks(S.p, {{0, map}});
  // 1/2 sum |x(X_i) - t_i|^2 / (m L^2): the misfit of the MLS field relative to the size L.
  const int m = static_cast<int>(in.observed.size());
  Triplets t;
  for (int i = 0; i < m; ++i) {
    MlsValues v;
    try {
      v = S.mls->evaluate(in.observed[static_cast<std::size_t>(i)]);
    } catch (const MeshlessPointError& e) {
      throw SceneError(S.spec.source + ": inverse.observations[" + std::to_string(i) + "].at: " + e.what());
    }
    for (std::size_t k = 0; k < v.nodes.size(); ++k)
      for (int c = 0; c < 3; ++c) t.emplace_back(3 * i + c, 3 * v.nodes[k] + c, v.values[static_cast<Eigen::Index>(k)]);
  }
  SparseMatrix B(3 * m, 3 * n);
  B.setFromTriplets(t.begin(), t.end());
  const Eigen::MatrixXd tt = in.targets.transpose();
  const Vector targets = Eigen::Map<const Vector>(tt.data(), tt.size());
  const double L = S.size();
  ObjectivePtr misfit = std::make_shared<LinearObservations>(B, targets, Vector::Constant(3 * m, 1.0 / (m * L * L)));
  if (in.regularization > 0.0) {
    auto tikhonov = std::make_shared<Tikhonov>(0, n, in.regularization, E0, Vector(E0.cwiseInverse()));
    out->objective = std::make_shared<WeightedSum>(std::vector<ObjectivePtr>{misfit, tikhonov}, std::vector<double>{1.0, 1.0});
  } else {
    out->objective = misfit;
  }
  StaticFunctionalOptions options;
  options.newton.max_iterations = S.spec.max_newton_iterations;
  options.newton.reuse_factorization = S.spec.reuse_factorization;
  out->functional = std::make_unique<StaticFunctional>(*S.model, out->parameterization, out->objective,
                                                       S.model->elimination().restrict_state(S.rest()), options);
  return out;
}

}  // namespace tailor
