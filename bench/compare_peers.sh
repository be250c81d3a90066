#!/usr/bin/env bash
# Particle-steps per second of tsubu (1 and 2 threads) and, when installed, LAMMPS (`lmp`,
# bin and multi neighbour styles) and LIGGGHTS (`liggghts`), 1 rank, 1 thread, on a shared
# benchmark bed (bench/<case>.toml for tsubu, the input scripts beside the bed for the
# peers), runs alternating, median of ROUNDS. Writes bench/results/<case>.{csv,md}.
#   usage: bench/compare_peers.sh [CASE=mono-settled] [ROUNDS=3]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
case=${1:-mono-settled}
rounds=${2:-3}
shared=$(cd "$root/../shared/bench" && pwd)
tsubu=${TSUBU:-$root/build/tsubu}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$here/results"
dt=$(/usr/bin/python3 -c "import json; print(json.load(open('$shared/$case.json'))['dt'])")
case "$case" in mono*) skin=0.4e-3 ;; *) skin=0.1e-3 ;; esac  # the peers' skins (../shared/bench/README.md)

have_lmp=0; have_lig=0
command -v lmp >/dev/null && have_lmp=1
command -v liggghts >/dev/null && have_lig=1
if [ $have_lmp = 1 ] || [ $have_lig = 1 ]; then
  /usr/bin/python3 "$shared/tools/csv2lammps.py" "$shared/$case.csv" "$work/$case.data" >/dev/null
fi
# "Loop time of T on 1 procs for N steps with M atoms"
loop_rate() { awk '/^Loop time of/ {print $12 * $9 / $4}' "$1"; }

samples="$work/samples.csv"
echo "code,threads,round,particle_steps_per_second" > "$samples"
for r in $(seq 1 "$rounds"); do
  for t in 1 2; do
    "$tsubu" run "$here/$case.toml" --threads "$t" --out "$work/tsubu$t" >/dev/null
    ps=$(/usr/bin/python3 -c "import json; print(json.load(open('$work/tsubu$t/run.json'))['particle_steps_per_second'])")
    echo "tsubu,$t,$r,$ps" >> "$samples"
  done
  steps=$(/usr/bin/python3 -c "import json; print(json.load(open('$work/tsubu1/run.json'))['steps'])")
  if [ $have_lmp = 1 ]; then
    for nmul in 0 1; do
      (cd "$work" && OMP_NUM_THREADS=1 lmp -in "$shared/lammps/bench_lmp.in" -var data "$case.data" -var dt "$dt" \
         -var nsteps "$steps" -var skin "$skin" -var nmul "$nmul" -log none -screen lmp.out >/dev/null)
      echo "lammps-$([ $nmul = 0 ] && echo bin || echo multi),1,$r,$(loop_rate "$work/lmp.out")" >> "$samples"
    done
  fi
  if [ $have_lig = 1 ]; then
    (cd "$work" && OMP_NUM_THREADS=1 liggghts -in "$shared/liggghts/bench_lig.in" -var data "$case.data" -var dt "$dt" \
       -var nsteps "$steps" -var skin "$skin" -log none -screen lig.out >/dev/null)
    echo "liggghts,1,$r,$(loop_rate "$work/lig.out")" >> "$samples"
  fi
done

/usr/bin/python3 - "$samples" "$here/results/$case" "$case" <<'PY'
import csv, statistics, sys, platform, os, datetime
rows = list(csv.DictReader(open(sys.argv[1])))
runs = {}
for r in rows:
    runs.setdefault((r['code'], int(r['threads'])), []).append(float(r['particle_steps_per_second']))
med = {k: statistics.median(v) for k, v in runs.items()}
lammps = [m for (code, t), m in med.items() if code.startswith('lammps')]
ref = max(lammps) if lammps else None  # the better of LAMMPS' bin and multi
cpu = next((l.split(':', 1)[1].strip() for l in open('/proc/cpuinfo') if l.startswith('model name')), platform.machine())
with open(sys.argv[2] + '.csv', 'w') as f:
    f.write('code,threads,median_particle_steps_per_second,runs,ratio_to_best_lammps_1core\n')
    for (code, t), m in sorted(med.items()):
        f.write(f"{code},{t},{m:.4g},{len(runs[(code, t)])},{(m / ref) if ref else float('nan'):.3f}\n")
with open(sys.argv[2] + '.md', 'w') as f:
    f.write(f"# {sys.argv[3]}: particle-steps per second\n\n")
    f.write(f"{datetime.date.today()}, {cpu}, {os.cpu_count()} cores; median of {max(len(v) for v in runs.values())} alternating runs.\n\n")
    f.write('| code | threads | particle-steps/s | per thread | vs best LAMMPS (1 core) |\n|---|---|---|---|---|\n')
    for (code, t), m in sorted(med.items()):
        f.write(f"| {code} | {t} | {m:.3g} | {m / t:.3g} | {(f'{m / ref:.2f}') if ref else 'n/a'} |\n")
print(open(sys.argv[2] + '.md').read())
PY
