#!/usr/bin/env bash
# Measures the build times that docs/testing.md ("Build time") records, on a fresh clone of the
# committed HEAD in a scratch folder, without the compiler cache (CCACHE_DISABLE), as a new user's
# first build. Dependencies must be installed (scripts/install-deps.sh); that step is not timed.
#
#   bash scripts/build-times.sh [--check] [--out FILE] [--keep]
#
# - quickstart:  configure + build the libraries and `tailor` + the default job's first line
# - clean_build: configure + build everything (the quick start's build, then the rest)
# - incremental: touch forward/fem/elastic_term.cpp, rebuild and run forward_fem_tests
# and, from Ninja's log, the compile and link seconds (CPU) per group of targets. Writes JSON
# (default out/build-times.json), prints a table; --check fails when a time passes its budget
# (scripts/build-budgets.txt). --keep leaves the scratch clone in place.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
repo=${PWD}
check=0 keep=0 out=out/build-times.json
while (($#)); do
  case $1 in
    --check) check=1 ;;
    --keep) keep=1 ;;
    --out) out=$2; shift ;;
    *) echo "build-times: unknown argument '$1'" >&2; exit 2 ;;
  esac
  shift
done
command -v ninja >/dev/null || { echo "build-times: needs ninja (scripts/install-deps.sh)" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/tailor-build-times.XXXXXX")
((keep)) || trap 'rm -rf "${work}"' EXIT
git clone -q --no-local "${repo}" "${work}/tailor"
cd "${work}/tailor"
echo "build-times: clean clone of $(git rev-parse --short HEAD) in ${work}/tailor, $(nproc) cores, no compiler cache"
export CCACHE_DISABLE=1
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.0f", b - a }'; }

start=$(now)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DTAILOR_WERROR=ON -DTAILOR_UNITY_BUILD=ON >configure.log
configured=$(now)
cmake --build build -j"$(nproc)" --target tailor_cli >build-cli.log
cli_built=$(now)
first_line=""
while IFS= read -r line; do
  [[ -n ${first_line} ]] && continue
  first_line=$(now)
  echo "build-times: the default job's first line: ${line}"
done < <(build/bin/tailor run scenes/cantilever_handle.json --out "${work}/quickstart" 2>&1 || true)
rest_start=$(now)
cmake --build build -j"$(nproc)" >build-rest.log
rest_built=$(now)

touch forward/fem/elastic_term.cpp
incremental_start=$(now)
cmake --build build -j"$(nproc)" --target forward_fem_tests >build-incremental.log
build/tests/forward/fem/forward_fem_tests >run-incremental.log
incremental_done=$(now)

quickstart=$(elapsed "${start}" "${first_line}")
clean_build=$(($(elapsed "${start}" "${cli_built}") + $(elapsed "${rest_start}" "${rest_built}")))
incremental=$(elapsed "${incremental_start}" "${incremental_done}")
configure=$(elapsed "${start}" "${configured}")

mkdir -p "$(dirname "${repo}/${out}")"
python3 - "${repo}/${out}" "${quickstart}" "${clean_build}" "${incremental}" "${configure}" \
  "$(git rev-parse HEAD)" "$(nproc)" <<'PYTHON'
import json, sys
path, quickstart, clean_build, incremental, configure, commit, cores = sys.argv[1:]
groups = {}
def group(output):
    if output.startswith("tests/"): return "tests"
    if output.startswith("bench/") or output.endswith("_bench"): return "benches"
    if output.startswith("python/"): return "python"
    if "tailor_cli" in output or output == "bin/tailor": return "cli"
    if output.startswith(("forward/", "adjoint/", "objectives/", "optimizers/", "problems/")): return "libraries"
    return "other"
with open("build/.ninja_log") as log:
    for line in log:
        if line.startswith("#"): continue
        start, end, _, output, _ = line.rstrip("\n").split("\t")
        g = groups.setdefault(group(output), {"compile_s": 0.0, "units": 0, "link_s": 0.0})
        seconds = (int(end) - int(start)) / 1000
        if output.endswith(".o"):
            g["compile_s"] += seconds; g["units"] += 1
        else:
            g["link_s"] += seconds
report = {"commit": commit, "cores": int(cores), "compiler_cache": False,
          "seconds": {"quickstart": int(quickstart), "clean_build": int(clean_build),
                      "incremental": int(incremental), "configure": int(configure)},
          "cpu_seconds_by_group": {k: {"compile_s": round(v["compile_s"], 1), "units": v["units"],
                                       "link_s": round(v["link_s"], 1)} for k, v in sorted(groups.items())}}
with open(path, "w") as f:
    json.dump(report, f, indent=2)
print(f"{'measure':<14}{'seconds':>9}")
for k, v in report["seconds"].items(): print(f"{k:<14}{v:>9}")
print(f"\n{'group (CPU)':<14}{'compile s':>10}{'units':>7}{'link s':>8}")
for k, v in report["cpu_seconds_by_group"].items():
    print(f"{k:<14}{v['compile_s']:>10.0f}{v['units']:>7}{v['link_s']:>8.0f}")
print(f"\nbuild-times: wrote {path}")
PYTHON

if ((check)); then
  status=0
  for name in quickstart clean_build incremental; do
    bash "${repo}/scripts/budget.sh" "${name}" "${!name}" || status=1
  done
  exit "${status}"
fi
