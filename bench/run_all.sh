#!/usr/bin/env bash
# The peer benchmark over every shared bed: bench/compare_peers.sh on each case (tsubu 1 and
# 2 threads; LAMMPS bin and multi and LIGGGHTS on one core when installed), then one table
# of throughput and memory per particle over all cases: $RESULTS/peers.{csv,md}.
#   usage: bench/run_all.sh [ROUNDS=3]
#   environment: as compare_peers.sh (TSUBU, RESULTS=bench/results, STEPS for smoke tests:
#   STEPS=50 RESULTS=/tmp/smoke bench/run_all.sh 1)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
rounds=${1:-3}
results=${RESULTS:-$here/results}
export RESULTS=$results
cases="mono-settled mono-settled-large poly10-settled poly10-gas poly10-gas-vrand"
for c in $cases; do
  echo "== $c" >&2
  bash "$here/compare_peers.sh" "$c" "$rounds" >/dev/null
done
/usr/bin/python3 "$here/peer_table.py" all "$results" "$rounds" "${STEPS:-}" $cases
