#include "problems/fem/inverse_modes.hpp"

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "forward/reduction/material_modes.hpp"

namespace tailor {
namespace {

bool bounded(const ModalDesignOptions& o) { return o.lower.has_value(); }

void check(const ModalDesignOptions& o) {
  if (o.lower.has_value() != o.upper.has_value())
    throw std::invalid_argument("modal design: give both bounds or neither");
  if (!o.logarithmic && !bounded(o))
    throw std::invalid_argument("modal design: the identity map needs bounds (E = Phi z may turn negative)");
  if (bounded(o) && !(*o.upper > *o.lower))
    throw std::invalid_argument("modal design: the upper bound must exceed the lower one");
  if (bounded(o) && o.logarithmic && !(*o.lower > 0.0))
    throw std::invalid_argument("modal design: the log map needs a lower bound > 0");
}

// y -> E per element (see the header).
ParameterizationPtr value_map(int m, const ModalDesignOptions& o) {
  if (!bounded(o)) return exp_map(m);
  if (!o.logarithmic) return bounds_map(Vector::Constant(m, *o.lower), Vector::Constant(m, *o.upper));
  return compose(exp_map(m), bounds_map(Vector::Constant(m, std::log(*o.lower)),
                                        Vector::Constant(m, std::log(*o.upper))));
}

}  // namespace

Vector modal_preimage(const Eigen::VectorXd& youngs_modulus, const ModalDesignOptions& options) {
  check(options);
  Vector y(youngs_modulus.size());
  for (Eigen::Index e = 0; e < y.size(); ++e) {
    const double E = youngs_modulus[e];
    if (!bounded(options)) {
      if (!(E > 0.0)) throw std::invalid_argument("modal design: E = " + std::to_string(E) + " is not > 0");
      y[e] = std::log(E);
      continue;
    }
    const double a = options.logarithmic ? std::log(*options.lower) : *options.lower;
    const double b = options.logarithmic ? std::log(*options.upper) : *options.upper;
    const double v = options.logarithmic && E > 0.0 ? std::log(E) : E;
    const double s = (v - a) / (b - a);  // (1 + tanh y) / 2
    if (!(E > 0.0) || !(s > 0.0 && s < 1.0)) {
      std::ostringstream message;
      message << "modal design: the initial E = " << E << " of element " << e
              << " is not strictly inside the bounds [" << *options.lower << ", " << *options.upper
              << "] (the smooth box reaches them only as z -> infinity)";
      throw std::invalid_argument(message.str());
    }
    y[e] = 0.5 * std::log(s / (1.0 - s));  // atanh(2 s - 1)
  }
  return y;
}

ModalDesign modal_design(const Mesh& mesh, const Eigen::VectorXd& initial_youngs_modulus,
                         const ModalDesignOptions& options) {
  const int m = mesh.num_elements();
  if (initial_youngs_modulus.size() != m)
    throw std::invalid_argument("modal design: expected one initial E per element");
  ModalDesign design;
  design.offset = modal_preimage(initial_youngs_modulus, options);
  const ParameterizationPtr values = value_map(m, options);
  if (!options.modes) {
    design.element_map = values;
    design.z0 = design.offset;
    design.eigen_message = "full: no reduction";
    return design;
  }
  const auto t0 = std::chrono::steady_clock::now();
  MaterialModeOptions mode_options;
  mode_options.weighting = options.weighting;
  MaterialModes modes = material_modes(mesh, *options.modes, mode_options);
  design.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  design.modes = std::move(modes.modes);
  design.eigenvalues = modes.eigenvalues;
  design.eigen_message = modes.solve.message;
  design.element_map = compose(values, linear_basis_map(design.modes, design.offset));
  design.z0 = Vector::Zero(*options.modes);
  return design;
}

}  // namespace tailor
