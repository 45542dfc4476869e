#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ (docs/testing.md) on seed corpora made from the shipped
# scenes and meshes. Builds them in build-asan/ (scripts/configure-asan.sh) first.
#
#   scripts/fuzz.sh                  # CI: a fixed number of executions per target, seed 1
#   scripts/fuzz.sh --runs 20000     # more executions
#   scripts/fuzz.sh --seconds 600    # a long local run: 10 minutes per target, random seed
#   scripts/fuzz.sh --seconds 60 scene gmsh   # only some targets
#
# Prints one line per target (executions, time, corpus size, result) and exits non-zero when
# any target found a crash, a sanitizer report, an unexpected exception, a timeout or a memory
# blow-up; the input that did it is saved as build-asan/fuzz/findings/<target>-crash-* (or
# -timeout-*, -oom-*), to be replayed with build-asan/fuzz/fuzz_<target> FILE.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

runs=5000
seconds=0
targets=()
while (($#)); do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --seconds) seconds=$2; runs=0; shift 2 ;;
    -h | --help) sed -n '2,14p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
all_targets=(scene gmsh medit tetgen data_file curve_file)
((${#targets[@]})) || targets=("${all_targets[@]}")

[[ -f build-asan/CMakeCache.txt ]] || bash scripts/configure-asan.sh
cmake --build build-asan -j"$(nproc)" --target "${targets[@]/#/fuzz_}"

work=build-asan/fuzz
mkdir -p "${work}/findings"

# The seeds of each target, fresh each run: shipped inputs plus fuzz/corpus/<target>.
seeds_for() {
  local target=$1 dir="${work}/seeds/$1"
  rm -rf "${dir}"
  mkdir -p "${dir}"
  case ${target} in
    scene) find scenes problems -name '*.json' -exec cp -t "${dir}" --backup=numbered {} + ;;
    gmsh) cp tests/data/meshes/*.msh "${dir}" ;;
    medit) cp tests/data/meshes/*.mesh "${dir}" ;;
    tetgen)
      # One input holds both files (fuzz/tetgen_fuzzer.cpp): .node, a line "%ele", .ele.
      for node in tests/data/meshes/*.node; do
        { cat "${node}"; printf '%%ele\n'; cat "${node%.node}.ele"; } >"${dir}/$(basename "${node%.node}")"
      done ;;
    curve_file) cp scenes/materials/*.json "${dir}" ;;
  esac
  [[ -d fuzz/corpus/${target} ]] && cp fuzz/corpus/"${target}"/* "${dir}"
  echo "${dir}"
}

# The scene target's dictionary: every key of the shipped scenes, so mutations spell keys.
dictionary_for() {
  local target=$1
  if [[ ${target} == scene ]]; then
    find scenes problems -name '*.json' -exec grep -ohE '"[a-z_0-9]+"' {} + | sort -u >"${work}/scene.dict"
    echo "-dict=${work}/scene.dict"
  elif [[ -f fuzz/${target}.dict ]]; then
    echo "-dict=fuzz/${target}.dict"
  fi
}

if ((runs > 0)); then budget=(-runs="${runs}" -seed=1); else budget=(-max_total_time="${seconds}"); fi
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=${PWD}/scripts/lsan.supp:print_suppressions=0}"
failed=()
printf '%-11s %12s %9s %8s  %s\n' target executions seconds corpus result
for target in "${targets[@]}"; do
  seeds=$(seeds_for "${target}")
  corpus="${work}/corpus/${target}"  # grows across local runs; new inputs land here
  mkdir -p "${corpus}"
  log="${work}/${target}.log"
  # -timeout: an input that takes 10 s is a hang; -rss_limit_mb / -malloc_limit_mb: an input
  # that needs gigabytes is a memory blow-up (what an absurd size in a file would cause).
  status=0
  start=${SECONDS}
  "${work}/fuzz_${target}" "${budget[@]}" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -max_len=16384 -print_final_stats=1 -artifact_prefix="${work}/findings/${target}-" \
    $(dictionary_for "${target}") "${corpus}" "${seeds}" >"${log}" 2>&1 || status=$?
  executions=$(grep -oE 'stat::number_of_executed_units: [0-9]+' "${log}" | grep -oE '[0-9]+$' || echo '?')
  result=ok
  if ((status != 0)); then
    result="FAILED (exit ${status}; see ${log})"
    failed+=("${target}")
  fi
  printf '%-11s %12s %9s %8s  %s\n' "${target}" "${executions}" "$((SECONDS - start))" \
    "$(find "${corpus}" -type f | wc -l)" "${result}"
done

if ((${#failed[@]})); then
  for target in "${failed[@]}"; do
    echo "---- ${target}: the end of ${work}/${target}.log"
    tail -n 40 "${work}/${target}.log"
  done
  exit 1
fi
