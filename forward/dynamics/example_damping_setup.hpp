#pragma once
// Adds example-based damping (ExampleDamping) to a dynamic model in place of plain Rayleigh
// damping: the examples are built (arrays, eigenmodes or static responses), M-orthonormalized
// in the given order, and the parameter blocks "rayleigh_alpha" (1), "rayleigh_beta" (1) and
// "example_damping" (the curves' control values, example by example) are appended.
// The model must already hold the "youngs_modulus", "poisson_ratio" and "density" blocks
// (add_dynamics_terms with rayleigh = false) and its elimination.
#include <vector>

#include "forward/core/model.hpp"
#include "forward/dynamics/example_damping.hpp"
#include "forward/dynamics/mass_operator.hpp"

namespace tailor {

struct DampingExampleSpec {
  enum class Source { displacement, eigenmode, static_response };
  Source source = Source::eigenmode;
  Vector field;  // displacement: the field [length]; static_response: nodal loads [force] (full DOFs)
  int mode = 0;  // eigenmode: index among the free DOFs' modes, 0 = lowest frequency
  DampingCurve curve;
};

struct ExampleDampingSetup {
  std::vector<DampingExampleSpec> examples;
  double amplitude_smoothing = 1e-8;  // eps of the amplitude chi [length]
  double orthogonality_tolerance = 1e-8;
};

struct ExampleDampingTerms {
  ExampleDamping* damping = nullptr;
  int alpha_offset = -1, beta_offset = -1, curve_offset = -1;
  Vector eigenvalues;  // K u = lambda M u for eigenmode examples (NaN for the others)
};

// p: values of the blocks already in the layout (moduli and density used to build the
// examples; entries beyond them are ignored). Throws std::invalid_argument on bad specs
// (wrong sizes, dependent examples) and std::runtime_error when the eigensolver fails.
ExampleDampingTerms add_example_damping(Model& model, const Mesh& mesh,
                                        std::shared_ptr<const MassOperator> mass, const Vector& p,
                                        const ExampleDampingSetup& setup);

}  // namespace tailor
