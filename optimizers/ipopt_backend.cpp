// Ipopt back-end (3.11, MUMPS): interior point with bounds and general constraints.
//
// Constraints are few in tailor's problems, so their Jacobian is dense. Second derivatives:
// limited-memory BFGS, or, with options.exact_hessian on a small unconstrained-or-bounded
// problem (n <= kMaxExactHessianSize) whose functional has Hessian-vector products, the dense
// Hessian assembled from n products. Constraint Hessians are not available, so constraints
// force limited-memory (the message says so).
//
// Ipopt 3.11 cannot report its current iterate from the intermediate callback, so the TNLP
// remembers the last point whose gradient Ipopt asked for: Ipopt evaluates the gradient at
// each accepted iterate before its iteration output, which is where the callback comes.
#include <IpIpoptApplication.hpp>
#include <IpJournalist.hpp>
#include <IpTNLP.hpp>
#include <cmath>
#include <ostream>
#include <sstream>
#include <string>

#include "optimizers/backend_detail.hpp"
#include "optimizers/backend_registry.hpp"

namespace tailor::detail {

namespace {

constexpr int kMaxExactHessianSize = 500;
constexpr double kIpoptInfinity = 1e19;  // nlp_lower_bound_inf / nlp_upper_bound_inf

using Ipopt::Index;
using Ipopt::Number;

std::string status_name(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded:
      return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level:
      return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected:
      return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small:
      return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates:
      return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop:
      return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found:
      return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded:
      return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed:
      return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation:
      return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded:
      return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom:
      return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition:
      return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option:
      return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected:
      return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception:
      return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown:
      return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory:
      return "Insufficient_Memory";
    case Ipopt::Internal_Error:
      return "Internal_Error";
  }
  return "Ipopt status " + std::to_string(static_cast<int>(status));
}

OptimizerStatus map_status(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded:
    case Ipopt::Solved_To_Acceptable_Level:
    case Ipopt::Feasible_Point_Found:
      return OptimizerStatus::converged;
    case Ipopt::Maximum_Iterations_Exceeded:
      return OptimizerStatus::max_iterations;
    case Ipopt::Maximum_CpuTime_Exceeded:
      return OptimizerStatus::time_limit;
    default:
      return OptimizerStatus::failed;
  }
}

class IpoptProblem : public Ipopt::TNLP {
 public:
  IpoptProblem(Tracker& tracker, const Vector& z0, bool exact_hessian)
      : tracker_(tracker), z0_(z0), exact_hessian_(exact_hessian) {}

  const Vector& final_point() const { return final_; }
  bool has_final_point() const { return final_.size() == tracker_.size(); }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = tracker_.size();
    m = static_cast<Index>(tracker_.constraints().size());
    nnz_jac_g = n * m;
    nnz_h_lag = exact_hessian_ ? n * (n + 1) / 2 : 0;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = std::isfinite(tracker_.lower()[i]) ? tracker_.lower()[i] : -kIpoptInfinity;
      x_u[i] = std::isfinite(tracker_.upper()[i]) ? tracker_.upper()[i] : kIpoptInfinity;
    }
    for (Index j = 0; j < m; ++j) {  // equality: g = 0; inequality: g <= 0
      g_l[j] = tracker_.constraints()[j].equality ? 0.0 : -kIpoptInfinity;
      g_u[j] = 0.0;
    }
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index,
                          bool init_lambda, Number*) override {
    if (init_x) Eigen::Map<Vector>(x, n) = z0_;
    return !init_z && !init_lambda;  // no warm start: only x is known
  }

  // Returning false tells Ipopt the point cannot be evaluated; it then shortens its step.
  bool eval_f(Index n, const Number* x, bool, Number& obj_value) override {
    obj_value = tracker_.value(Eigen::Map<const Vector>(x, n));
    return std::isfinite(obj_value);
  }

  bool eval_grad_f(Index n, const Number* x, bool, Number* grad_f) override {
    const Vector z = Eigen::Map<const Vector>(x, n);
    Vector g;
    if (!std::isfinite(tracker_.value_and_gradient(z, g))) return false;
    Eigen::Map<Vector>(grad_f, n) = g;
    current_ = z;
    return true;
  }

  bool eval_g(Index n, const Number* x, bool, Index m, Number* g) override {
    const Vector z = Eigen::Map<const Vector>(x, n);
    for (Index j = 0; j < m; ++j) {
      g[j] = tracker_.constraint(j, z, nullptr);
      if (std::isnan(g[j])) return false;
    }
    return true;
  }

  bool eval_jac_g(Index n, const Number* x, bool, Index m, Index, Index* iRow, Index* jCol,
                  Number* values) override {
    if (!values) {  // structure: dense, row-major
      for (Index j = 0, k = 0; j < m; ++j)
        for (Index i = 0; i < n; ++i, ++k) iRow[k] = j, jCol[k] = i;
      return true;
    }
    const Vector z = Eigen::Map<const Vector>(x, n);
    Vector gradient;
    for (Index j = 0; j < m; ++j) {
      if (std::isnan(tracker_.constraint(j, z, &gradient))) return false;
      Eigen::Map<Vector>(values + j * n, n) = gradient;
    }
    return true;
  }

  // Only used with exact_hessian, which implies no constraints: the Lagrangian's Hessian is
  // obj_factor times the objective's.
  bool eval_h(Index n, const Number* x, bool, Number obj_factor, Index, const Number*, bool, Index,
              Index* iRow, Index* jCol, Number* values) override {
    if (!values) {  // lower triangle, row by row
      for (Index i = 0, k = 0; i < n; ++i)
        for (Index j = 0; j <= i; ++j, ++k) iRow[k] = i, jCol[k] = j;
      return true;
    }
    const Vector z = Eigen::Map<const Vector>(x, n);
    if (hessian_z_.size() != n || hessian_z_ != z) {
      if (!assemble_hessian(z)) return false;
    }
    for (Index i = 0, k = 0; i < n; ++i)
      for (Index j = 0; j <= i; ++j, ++k) values[k] = obj_factor * hessian_(i, j);
    return true;
  }

  bool intermediate_callback(Ipopt::AlgorithmMode mode, Index, Number obj_value, Number, Number inf_du,
                             Number, Number, Number, Number, Number, Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities*) override {
    // Restoration-phase iterates minimize infeasibility, not the objective: no row for them.
    if (mode == Ipopt::RegularMode && current_.size() == tracker_.size()) {
      tracker_.record_iteration(current_, obj_value, inf_du);
      // Ipopt has no objective-change or step test; ours are only valid without constraints
      // (a small interior-point step says nothing about feasibility).
      if (tracker_.constraints().empty()) tracker_.apply_change_tests();
    }
    return !tracker_.stop_requested();  // false: Ipopt stops with User_Requested_Stop
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*, const Number*, Index,
                         const Number*, const Number*, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    if (x) final_ = Eigen::Map<const Vector>(x, n);
  }

 private:
  // Dense Hessian from n Hessian-vector products with the unit vectors, symmetrized.
  bool assemble_hessian(const Vector& z) {
    const int n = tracker_.size();
    Matrix H(n, n);
    try {
      for (int i = 0; i < n; ++i) H.col(i) = tracker_.functional().hessian_vector(z, Vector::Unit(n, i));
    } catch (const EvaluationError&) {
      return false;
    } catch (const std::exception& e) {
      tracker_.request_stop(OptimizerStatus::failed,
                            std::string("Hessian-vector product failed: ") + e.what());
      return false;
    }
    if (!H.allFinite()) return false;
    hessian_ = 0.5 * (H + H.transpose());
    hessian_z_ = z;
    return true;
  }

  Tracker& tracker_;
  Vector z0_;
  bool exact_hessian_;
  Vector current_;  // last point where the gradient was evaluated: the current iterate
  Vector final_;
  Vector hessian_z_;
  Matrix hessian_;
};

}  // namespace

std::function<void()>& ipopt_prelude() {
  static std::function<void()> prelude;
  return prelude;
}

BackendOutcome run_ipopt(Tracker& tracker, const Vector& z0) {
  if (auto& prelude = ipopt_prelude()) {
    prelude();
    prelude = nullptr;
  }
  const OptimizerOptions& options = tracker.options();
  std::string note;
  bool exact = false;
  if (options.exact_hessian) {
    if (!tracker.functional().has_hessian_vector())
      note = "; exact_hessian ignored: the functional has no Hessian-vector products";
    else if (tracker.size() > kMaxExactHessianSize)
      note = "; exact_hessian ignored: n > " + std::to_string(kMaxExactHessianSize);
    else if (!tracker.constraints().empty())
      note = "; exact_hessian ignored: constraint Hessians are not available, used limited-memory";
    else
      exact = true;
  }

  // No console journal: Ipopt prints nothing unless progress is set. Then its summary
  // (J_SUMMARY: problem size, final KKT errors, evaluation counts, EXIT line) is collected and
  // written after our per-iteration table, which replaces Ipopt's own.
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication(false);
  std::ostringstream ipopt_summary;
  if (options.progress) {
    Ipopt::SmartPtr<Ipopt::StreamJournal> journal =
        new Ipopt::StreamJournal("tailor-progress", Ipopt::J_SUMMARY);
    journal->SetOutputStream(&ipopt_summary);
    app->Jnlst()->AddJournal(Ipopt::GetRawPtr(journal));
  }
  auto ipopt_options = app->Options();
  bool ok = true;
  ok &= ipopt_options->SetStringValue("sb", "yes");  // no banner
  ok &= ipopt_options->SetIntegerValue("print_level", 0);
  ok &= ipopt_options->SetStringValue("linear_solver", "mumps");  // the only one in 3.11 here
  ok &= ipopt_options->SetStringValue("hessian_approximation", exact ? "exact" : "limited-memory");
  // Resuming, the iterations before the checkpoint count.
  ok &=
      ipopt_options->SetIntegerValue("max_iter", std::max(options.max_iterations - tracker.iterations(), 0));
  // tol bounds Ipopt's scaled KKT error; dual_inf_tol the unscaled gradient of the Lagrangian.
  const double tol = std::max(options.gradient_tolerance, 1e-14);
  ok &= ipopt_options->SetNumericValue("tol", tol);
  ok &= ipopt_options->SetNumericValue("dual_inf_tol", tol);
  ok &= ipopt_options->SetNumericValue("constr_viol_tol", 0.01 * kFeasibilityTolerance);
  // Ipopt relaxes bounds by 1e-8 by default and may then evaluate just outside the box;
  // functionals may be undefined there (a stiffness at its lower bound 0), the other
  // back-ends never leave the box, and the returned point must lie in it.
  ok &= ipopt_options->SetNumericValue("bound_relax_factor", 0.0);
  ok &= ipopt_options->SetNumericValue("nlp_lower_bound_inf", -kIpoptInfinity);
  ok &= ipopt_options->SetNumericValue("nlp_upper_bound_inf", kIpoptInfinity);
  if (!ok) return {OptimizerStatus::failed, "Ipopt rejected an option", std::nullopt};

  std::istringstream no_options_file;  // Initialize() would otherwise read ./ipopt.opt
  Ipopt::ApplicationReturnStatus status = app->Initialize(no_options_file);
  if (status != Ipopt::Solve_Succeeded)
    return {OptimizerStatus::failed, "Ipopt initialization failed: " + status_name(status), std::nullopt};

  Ipopt::SmartPtr<IpoptProblem> problem = new IpoptProblem(tracker, z0, exact);
  status = app->OptimizeTNLP(Ipopt::GetRawPtr(problem));
  if (options.progress) *options.progress << ipopt_summary.str() << std::flush;

  BackendOutcome outcome;
  outcome.status = map_status(status);
  outcome.message = "Ipopt " + status_name(status) + (exact ? " (exact Hessian)" : " (L-BFGS)") + note;
  if (problem->has_final_point()) outcome.final_point = problem->final_point();
  return outcome;
}

}  // namespace tailor::detail

namespace tailor {

void set_ipopt_prelude(std::function<void()> prelude) { detail::ipopt_prelude() = std::move(prelude); }

// The registry's entries (optimizers/backend_registry.hpp).
BackendEntry ipopt_backend_entry() {
  return {
      "ipopt",
      "interior point (Ipopt): bounds and general constraints; L-BFGS or the exact Hessian",
      {.bounds = true, .inequality_constraints = true, .equality_constraints = true, .exact_hessian = true},
      &detail::run_ipopt};
}

}  // namespace tailor
