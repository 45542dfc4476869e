#!/usr/bin/env bash
# Builds part of the test suite with AddressSanitizer and UndefinedBehaviorSanitizer (clang,
# build-asan/, see scripts/configure-asan.sh) and runs it; any sanitizer report ends its test
# with an error, so the script fails on any report as on any failing test. See docs/testing.md.
#
# The subset (the whole suite under ASan does not fit CI's time): every parser -- the mesh
# readers, the scene files of every kind with their data files -- and every energy term's
# derivative checks. The test executables and the ctest name filter below say exactly which.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Test executables (one per tests/ folder) and, for each, a ctest regular expression over
# "<executable>.<Suite>.<Test>" ("" = all of its tests).
subset=(
  # Parsers.
  "forward_mesh_tests|"                     # Gmsh 2/4, Medit, TetGen readers; generators
  "problems_tests|Scene|SceneValidation|InverseScene|SplineScene|HandlesScene|StaticScene|DynamicScene|DescentScene|ParserRegression"
  "problems_rods_tests|"
  "problems_contact_tests|"
  "problems_homogenization_tests|"
  "forward_homogenization_tests|RodNetworkCell"  # periodic rod networks: their terms' derivative checks
  "problems_material_fit_tests|MaterialFitScene"
  "problems_damping_design_tests|DampingDesignScene"
  "study_tests|"                            # C++-built scenes, registered scene term types
  # Energy terms: their derivative checks (check_energy_term) and the terms' own tests.
  "forward_fem_tests|"
  "forward_fem_materials_tests|"
  "forward_spline_material_tests|"
  "forward_rods_tests|"
  "forward_contact_tests|"
  "forward_tori_tests|"                     # implicit torus distance, contact term, CCD, chains
  "forward_rigid_tests|"
  "forward_meshless_tests|MlsShapeFunctions|OctreeSampling|GaussLegendre|MeshlessElasticTerm|EveryMaterial/MeshlessElasticTermTest|MeshlessMass|MlsTransformation|MeshlessAdjoint|PointInput|ModalWarping|ImplicitSurface|CoveringPatches"  # shape functions, quadrature, the term's derivative checks, point-file readers, warping
  "problems_meshless_tests|"                # meshless scenes and their point files
  "forward_interlocking_tests|"             # periodic rigid cells, the boundary search
  "problems_interlocking_tests|"           # interlocking scenes, the limit's derivative checks
  "forward_reduction_tests|KrylovRecurrence|DomainPartition|DomainDecomposition|OverlappingDomains|LocalReducedStvk|DomainRotations|RotatingSubspaceDynamics"  # local reduced models
  "forward_rig_tests|RigDerivatives|RigInput|PoseSpaceBasis|ConstrainedModes|MovingRestShape|RigInverse"  # rigs, their derivatives, per-pose bases
  "problems_rig_tests|"                     # rig_dynamics scenes and rig files
  "studio_tests|"                           # the studio server's messages, token, Host/Origin and path checks
  "forward_dynamics_tests|"                 # includes DescentKernels (the host side of the device rule)
  "reduced_design_tests|ReducedDynamicScene"  # dynamics.reduction scenes
  "adjoint_tests|TransientFunctional"        # the transient adjoint and its tangent (forward-mode) pass
  "forward_damping_tests|"
  "forward_solve_tests|HessianShare"        # assembly by parts: the shares and Newton through them
  "forward_core_tests|ReducedAssembler"      # reduction through long rows of S by sparse products
  "optimizers_tests|NewtonCg"                # newton_cg's trust region, CG stops and Hessian products
)

# Left out of the subset: long validation runs (whole trajectories, optimizations, chains of a
# hundred links; 20 to 140 s each under the sanitizers, about two thirds of the subset's time).
# They run the same energy terms, parsers and solvers as the tests above, on more steps, and
# they stay in the Release suite (scripts/test.sh).
excluded=(
  "problems_rods_tests\\.(RodDynamics|RodInverseScene\\.ShippedDesignsReachTheirTargets)"
  "problems_contact_tests\\.(FemContactScene\\.(ShippedSoftBlockSceneCarriesItsLoad|HertzContact)|TorusScene\\.GradcheckOfAnEllipticChain|RigidScene\\.KinematicPlateAndTorqueScene)"
  "forward_dynamics_tests\\.Integrators\\.NewmarkConservesEnergy"
  "forward_dynamics_tests\\.DescentSolver\\.(AcceptedIterates|ChebyshevAcceleration)"  # thousands of descent passes
  "forward_interlocking_tests\\.InterlockingBending\\.ThreefoldPatchBendsSymmetrically"  # 21-26 Newton solves per direction, 2.4 s in Release
  "problems_interlocking_tests\\.InterlockingDesign\\.RecoversAKnownPatchFromItsBendingLimits"  # an MMA design, 5 s in Release
  "forward_interlocking_tests\\.PeriodicMeshCell\\.(SquareNetMatchesTheImplicitTori|ChainOfMeshedRingsLocksAtTheClosedFormSpacing)"  # boundary searches through triangle-mesh contact, 0.6-3.7 s in Release
  "problems_interlocking_tests\\.InterlockingMacroScene\\.ShippedSheetMatchesTheNativeCellInFiveStates"  # native sweeps and macro solves, 3 s in Release
  "reduced_design_tests\\.ReducedDynamicScene\\.TurningDomainsFollowTheFullTrajectory"  # full-space and rotating-subspace trajectories
  "forward_reduction_tests\\.RotatingSubspaceDynamics\\.DomainBasisStaysBoundedWhereTheGlobalBasisGainsEnergy"  # four 40-step trajectories, 5.4 s in Release
  "forward_rods_tests\\.(RodValidation|ClosedRodValidation)\\."
  "forward_rigid_tests\\.FrictionValidation\\."
  "forward_tori_tests\\.TorusChain\\.HundredAndOneLinks"
  "study_tests\\.Study\\.EveryBackendRecoversTheBar"
  "problems_damping_design_tests\\.DampingDesignScene\\.RunWritesReportAndPlots"
)

[[ -f build-asan/CMakeCache.txt ]] || bash scripts/configure-asan.sh
executables=()
patterns=()
for entry in "${subset[@]}"; do
  executable=${entry%%|*}
  suites=${entry#*|}
  executables+=("${executable}")
  if [[ -z ${suites} ]]; then
    patterns+=("^${executable}\\.")
  else
    # One alternative per suite: CMake's regular expressions allow only a few parenthesized groups.
    IFS='|' read -ra names <<<"${suites}"
    for name in "${names[@]}"; do patterns+=("^${executable}\\.${name}\\."); done
  fi
done
# problems_tests runs bin/tailor in some of the selected tests.
cmake --build build-asan -j"$(nproc)" --target tailor_cli "${executables[@]}"

# Leaks count as reports. OpenMP: see docs/testing.md for why the tests run with the default
# threads under ASan.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=${PWD}/scripts/lsan.supp:print_suppressions=0}"
regex=$(IFS='|'; echo "${patterns[*]}")
exclude=$(IFS='|'; echo "${excluded[*]}")
ctest --test-dir build-asan --output-on-failure --no-tests=error -j"$(nproc)" -R "${regex}" -E "${exclude}" --timeout 600
