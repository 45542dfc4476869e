#!/usr/bin/env bash
# The descent solver's GPU check (docs/dynamics.md, "The GPU path"), for a machine with nvcc and a
# CUDA device: configures build-cuda/ with the CUDA path required (TAILOR_WITH_CUDA=ON, sm_80 and
# sm_90 unless CUDA_ARCHITECTURES says otherwise), builds the dynamics tests and descent_bench,
# runs the descent tests (the device ones fail here rather than skip when no device is usable)
# and the bench's device rows at the published table's sizes.
#
# usage: scripts/gpu-descent-check.sh [OUTPUT_DIR]   (default: build-cuda/gpu-check)
#   writes OUTPUT_DIR/tests.txt, OUTPUT_DIR/bench_descent_device.json and .txt
# Environment: STEPS (default 3) and BUDGETS (default 50,100,200) for the bench; BUILD_DIR.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${BUILD_DIR:-build-cuda}
out=${1:-$build/gpu-check}
mkdir -p "$out"
export PATH="/usr/local/cuda/bin:$PATH"
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv | tee "$out/device.txt"

generator=()
if [[ ! -f $build/CMakeCache.txt ]] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DTAILOR_UNITY_BUILD=ON -DTAILOR_WITH_CUDA=ON \
  -DTAILOR_BUILD_TESTS=ON -DTAILOR_BUILD_BENCH=ON ${CUDA_ARCHITECTURES:+-DCMAKE_CUDA_ARCHITECTURES=$CUDA_ARCHITECTURES}
cmake --build "$build" -j"$(nproc)" --target forward_dynamics_tests tailor_bench

# The device tests must run, not skip: a skip here means the device was not usable.
"$build"/tests/forward/dynamics/forward_dynamics_tests --gtest_filter='DescentKernels.*:DescentSolver.*' \
  2>&1 | tee "$out/tests.txt"
if grep -q "SKIPPED" "$out/tests.txt"; then
  echo "gpu-descent-check: device tests were skipped: no usable CUDA device" >&2
  exit 1
fi

bench="$build/bin/descent_bench"
"$bench" --device-table --steps "${STEPS:-3}" --device-budgets "${BUDGETS:-50,100,200}" \
  --out "$out/bench_descent_device.json" | tee "$out/bench_descent_device.txt"
echo "gpu-descent-check: results in $out"
