#!/usr/bin/env bash
# Particle-steps per second and peak memory of tsubu (1 and 2 threads) and, when installed,
# LAMMPS (`lmp`, bin and multi neighbour styles) and LIGGGHTS (`liggghts`), 1 rank, 1 thread,
# on a shared benchmark bed (bench/<case>.toml for tsubu, the input scripts beside the bed for
# the peers), runs alternating, median of ROUNDS. Memory is each run's peak resident set
# (ru_maxrss, from GNU time), reported as bytes per particle. Writes $RESULTS/<case>.{csv,md}.
#   usage: bench/compare_peers.sh [CASE=mono-settled] [ROUNDS=3]
#   environment: TSUBU (binary, default build/tsubu), RESULTS (folder, default bench/results),
#                STEPS (override the case's step count, for smoke tests)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
case=${1:-mono-settled}
rounds=${2:-3}
shared=$(cd "$root/../shared/bench" && pwd)
tsubu=${TSUBU:-$root/build/tsubu}
results=${RESULTS:-$here/results}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$results"
[ -x /usr/bin/time ] || { echo "compare_peers.sh: needs GNU time (/usr/bin/time; apt-get install time)" >&2; exit 1; }
json() { /usr/bin/python3 -c "import json, sys; print(json.load(open(sys.argv[1]))$2)" "$1"; }
dt=$(json "$shared/$case.json" "['dt']")
particles=$(json "$shared/$case.json" "['N']")
case "$case" in mono*) skin=0.4e-3 ;; *) skin=0.1e-3 ;; esac  # the peers' skins (../shared/bench/README.md)
tsubu_set=()
[ -n "${STEPS:-}" ] && tsubu_set=(--set "simulation.duration=$(/usr/bin/python3 -c "print(repr($STEPS * $dt))")")

have_lmp=0; have_lig=0
command -v lmp >/dev/null && have_lmp=1
command -v liggghts >/dev/null && have_lig=1
if [ $have_lmp = 1 ] || [ $have_lig = 1 ]; then
  /usr/bin/python3 "$shared/tools/csv2lammps.py" "$shared/$case.csv" "$work/$case.data" >/dev/null
fi
# "Loop time of T on 1 procs for N steps with M atoms"
loop_rate() { awk '/^Loop time of/ {print $12 * $9 / $4}' "$1"; }
# run a command, its peak resident set in KiB (ru_maxrss) to $work/rss
measured() { /usr/bin/time -f %M -o "$work/rss" "$@"; }
rss_bytes() { echo $(( $(tail -n 1 "$work/rss") * 1024 )); }

samples="$work/samples.csv"
echo "code,threads,round,steps,particle_steps_per_second,peak_rss_bytes" > "$samples"
for r in $(seq 1 "$rounds"); do
  for t in 1 2; do
    measured "$tsubu" run "$here/$case.toml" --threads "$t" --out "$work/tsubu$t" --overwrite "${tsubu_set[@]}" >/dev/null
    steps=$(json "$work/tsubu$t/run.json" "['steps']")
    echo "tsubu,$t,$r,$steps,$(json "$work/tsubu$t/run.json" "['particle_steps_per_second']"),$(rss_bytes)" >> "$samples"
  done
  if [ $have_lmp = 1 ]; then
    for nmul in 0 1; do
      (cd "$work" && OMP_NUM_THREADS=1 measured lmp -in "$shared/lammps/bench_lmp.in" -var data "$case.data" -var dt "$dt" \
         -var nsteps "$steps" -var skin "$skin" -var nmul "$nmul" -log none -screen lmp.out >/dev/null)
      echo "lammps-$([ $nmul = 0 ] && echo bin || echo multi),1,$r,$steps,$(loop_rate "$work/lmp.out"),$(rss_bytes)" >> "$samples"
    done
  fi
  if [ $have_lig = 1 ]; then
    (cd "$work" && OMP_NUM_THREADS=1 measured liggghts -in "$shared/liggghts/bench_lig.in" -var data "$case.data" -var dt "$dt" \
       -var nsteps "$steps" -var skin "$skin" -log none -screen lig.out >/dev/null)
    echo "liggghts,1,$r,$steps,$(loop_rate "$work/lig.out"),$(rss_bytes)" >> "$samples"
  fi
done

/usr/bin/python3 "$here/peer_table.py" case "$samples" "$results/$case" "$case" "$particles" "${STEPS:-}"
