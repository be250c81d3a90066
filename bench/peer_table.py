#!/usr/bin/env python3
"""Tables of the peer benchmark (bench/compare_peers.sh, bench/run_all.sh).

  peer_table.py case SAMPLES OUT CASE N STEPS_OVERRIDE
      SAMPLES: code,threads,round,steps,particle_steps_per_second,peak_rss_bytes, one line a
      run. STEPS_OVERRIDE: the STEPS the runs were given, or "" for the cases' own counts.
      Writes OUT.csv and OUT.md: medians over the rounds for each (code, threads).
  peer_table.py all RESULTS ROUNDS STEPS_OVERRIDE CASE...
      Joins RESULTS/<case>.csv into RESULTS/peers.csv and RESULTS/peers.md.

Throughput ratios are to the faster LAMMPS variant on one core (bin or multi neighbour
style), memory ratios to the leaner one (multi keeps more per grain). Memory is the peak
resident set (ru_maxrss) of the process, fixed costs (binary, libraries, MPI) included,
over N grains.
"""
import csv
import datetime
import os
import platform
import statistics
import sys

COLUMNS = ['code', 'threads', 'median_particle_steps_per_second', 'runs', 'ratio_to_best_lammps_1core',
           'median_peak_rss_bytes', 'bytes_per_particle', 'memory_ratio_to_lammps', 'steps', 'particles']


def session(rounds, steps_override):
    """The lines that say where and how a table was measured."""
    cpu = next((l.split(':', 1)[1].strip() for l in open('/proc/cpuinfo') if l.startswith('model name')),
               platform.machine())
    text = f"{datetime.date.today()}, {cpu}, {os.cpu_count()} cores; median of {rounds} alternating runs.\n"
    if steps_override:
        text += (f"\n**STEPS={steps_override} overrides the cases' step counts** (smoke test: start-up "
                 "weighs more, not comparable with full runs).\n")
    return text + "\n"


def summarise(samples, particles):
    """One row per (code, threads) from the per-run samples, with the ratios to LAMMPS; the
    LAMMPS rows that the throughput and memory ratios refer to."""
    runs = {}
    for r in samples:
        runs.setdefault((r['code'], int(r['threads'])), []).append(r)
    rows = []
    for (code, t), rs in sorted(runs.items()):
        rss = [float(r['peak_rss_bytes']) for r in rs if r['peak_rss_bytes']]
        rows.append({'code': code, 'threads': t, 'runs': len(rs), 'steps': rs[0]['steps'], 'particles': particles,
                     'median_particle_steps_per_second': statistics.median(float(r['particle_steps_per_second']) for r in rs),
                     'median_peak_rss_bytes': statistics.median(rss) if rss else float('nan')})
    lammps = [r for r in rows if r['code'].startswith('lammps') and r['threads'] == 1]
    fast = max(lammps, key=lambda r: r['median_particle_steps_per_second']) if lammps else None
    lean = min(lammps, key=lambda r: r['median_peak_rss_bytes']) if lammps else None
    for r in rows:
        r['bytes_per_particle'] = r['median_peak_rss_bytes'] / particles
        r['ratio_to_best_lammps_1core'] = (r['median_particle_steps_per_second'] / fast['median_particle_steps_per_second']
                                           if lammps else float('nan'))
        r['memory_ratio_to_lammps'] = r['median_peak_rss_bytes'] / lean['median_peak_rss_bytes'] if lammps else float('nan')
    return rows, fast, lean


def write_csv(path, rows, first=()):
    with open(path, 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(list(first) + COLUMNS)
        for r in rows:
            w.writerow([r[k] for k in first] + [f'{r[k]:.4g}' if isinstance(r[k], float) else r[k] for k in COLUMNS])


def ratio(x):
    return 'n/a' if x != x else f'{x:.2f}'  # NaN: no LAMMPS in this session


def md_table(rows, with_case):
    head = (['case', 'steps'] if with_case else []) + ['code', 'threads', 'particle-steps/s', 'per thread',
                                                         'vs best LAMMPS (1 core)', 'bytes/particle', 'memory vs LAMMPS']
    out = '| ' + ' | '.join(head) + ' |\n' + '|---' * len(head) + '|\n'
    for r in rows:
        cells = ([r['case'], r['steps']] if with_case else []) + [
            r['code'], r['threads'], f"{float(r['median_particle_steps_per_second']):.3g}",
            f"{float(r['median_particle_steps_per_second']) / int(r['threads']):.3g}",
            ratio(float(r['ratio_to_best_lammps_1core'])), f"{float(r['bytes_per_particle']):.0f}",
            ratio(float(r['memory_ratio_to_lammps']))]
        out += '| ' + ' | '.join(str(c) for c in cells) + ' |\n'
    return out


def one_case(samples_path, out, case, particles, steps_override):
    samples = list(csv.DictReader(open(samples_path)))
    rows, fast, lean = summarise(samples, int(particles))
    write_csv(out + '.csv', rows)
    rounds = max(r['runs'] for r in rows)
    with open(out + '.md', 'w') as f:
        f.write(f"# {case}: particle-steps per second and memory\n\n")
        f.write(session(rounds, steps_override))
        f.write(f"{particles} grains, {rows[0]['steps']} steps. Bytes/particle: peak resident memory (ru_maxrss) "
                "over the grain count.")
        f.write(f" Ratios to {fast['code']} (the faster LAMMPS variant) for speed, to {lean['code']} (the leaner) "
                "for memory.\n\n" if fast else " No LAMMPS run.\n\n")
        f.write(md_table(rows, with_case=False))
    print(open(out + '.md').read())


def all_cases(results, rounds, steps_override, *cases):
    rows = []
    for case in cases:
        for r in csv.DictReader(open(os.path.join(results, case + '.csv'))):
            rows.append(dict(r, case=case))
    write_csv(os.path.join(results, 'peers.csv'), rows, first=['case'])
    with open(os.path.join(results, 'peers.md'), 'w') as f:
        f.write("# Peer benchmark: all shared beds\n\n")
        f.write(session(rounds, steps_override))
        f.write("`bench/run_all.sh` (`bench/compare_peers.sh` on each case). Throughput: grains x steps / loop "
                "time. Bytes/particle: peak resident memory (ru_maxrss, fixed costs included) over the grain "
                "count. Ratios: to the case's faster LAMMPS variant (bin or multi, one core) for speed, to the "
                "leaner one for memory.\n\n")
        f.write(md_table(rows, with_case=True))
    print(open(os.path.join(results, 'peers.md')).read())


if __name__ == '__main__':
    modes = {'case': one_case, 'all': all_cases}
    if len(sys.argv) < 2 or sys.argv[1] not in modes:
        sys.exit(__doc__)
    modes[sys.argv[1]](*sys.argv[2:])
