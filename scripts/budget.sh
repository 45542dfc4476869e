#!/usr/bin/env bash
# Usage: bash scripts/budget.sh NAME SECONDS
# Compares a measured time with its budget in scripts/build-budgets.txt: prints one line and
# exits 1 when the time passes the budget (2 for an unknown name).
set -euo pipefail
name=$1 seconds=$2
budget=$(awk -v n="${name}" '$1 == n { print $2 }' "$(dirname "${BASH_SOURCE[0]}")/build-budgets.txt")
if [[ -z ${budget} ]]; then
  echo "budget: no budget named '${name}' in scripts/build-budgets.txt" >&2
  exit 2
fi
if ((seconds > budget)); then
  echo "budget: ${name} took ${seconds} s, over its budget of ${budget} s (scripts/build-budgets.txt)"
  exit 1
fi
echo "budget: ${name} ${seconds} s, within ${budget} s"
