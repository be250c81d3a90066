#!/usr/bin/env python3
"""LAMMPS against tsubu: grains deposited in vacuum at the same mass flux (issue #12, "Cost").

  TSUBU=build/tsubu /usr/bin/python3 bench/lammps_deposit.py [--rounds 3] [--wait-load 120]
      [--skins 0.25e-3,0.5e-3,1e-3,2e-3,4e-3] [--work DIR] [--results DIR] [--render DIR/raw.json]

tsubu runs examples/sedimentation/mono-vacuum.toml in the L = 8 d box until the deposit is
0.4 L high. LAMMPS (`lmp`, pair_style granular, fix deposit, fix wall/gran) pours the same
grains at the same mass flux from the same entry plane at the same speed onto the same floor,
with the contact law closest to tsubu's, and stops by the same deposit-height rule, checked at
the same times (bench/lammps/deposit.in). Both final states are then measured by tsubu itself
(porosity and coordination on 0.15 L < z < 0.35 L): LAMMPS's is written as a `source = "file"`
state and run for one step.

Steps: (1) single collisions in both codes (restitution and rebound, grain pairs and grains on
the floor); (2) LAMMPS neighbour skins, two runs each, the fastest kept; (3) ROUNDS rounds,
round r with seed r in both codes (round 1 is the brief's exact tsubu command): tsubu as
given, tsubu "lean" (no VTK frames, a one-point porosity at the rows: the work LAMMPS does),
LAMMPS, each alone on one thread after waiting (up to --wait-load s) for a quiet machine, then
untimed: tsubu's deposit at LAMMPS's stop time, for the solid fraction by slab. Writes
RESULTS/lammps-deposit.{csv,md} and keeps the raw numbers in WORK/raw.json (--render rewrites
the tables from it). Without `lmp` it says so and exits 0.
"""
import argparse
import csv
import datetime
import json
import math
import os
import platform
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENARIO = os.path.join(ROOT, 'examples', 'sedimentation', 'mono-vacuum.toml')
INPUTS = os.path.join(HERE, 'lammps')

# The brief's box: L = 8 d, entry plane z_c = 2 L, and the paper's protocol (the example measures
# at rest): the inflow never stops, the run stops at a deposit height of 0.4 L by the slice rule.
TSUBU_SETTINGS = ['domain.upper=[0.08, 0.08, 0.17]', 'particles.0.mass_limit=0',
                  'analyses=[{type="deposit_height", rule="slices", threshold=0.55}, {type="porosity"}, '
                  '{type="coordination", z_range=[0.012, 0.028]}, {type="kinetic_energy"}]',
                  'stop=[{when="deposit_height", at_least=0.032}]']
MEASURES = ['deposit_height', 'porosity', 'porosity_standard_error', 'porosity_exact', 'porosity_grains',
            'coordination', 'coordination_no_rattlers', 'coordination_no_rattlers_4', 'coordination_grains']
LOAD_LIMIT = 1.5  # one-minute load average above which the 2-core machine counts as busy


# ---------------------------------------------------------------------------------------------
# The physics of the tsubu scenario, and the LAMMPS coefficients that reproduce it

def apply_settings(table, settings):
    """The tsubu `--set key=value` overrides applied to the parsed scenario (lists, numbers)."""
    for s in settings:
        key, value = s.split('=', 1)
        parts = key.split('.')
        node = table
        for p in parts[:-1]:
            node = node[int(p)] if p.isdigit() else node[p]
        node[parts[-1]] = tomllib.loads('v = ' + value)['v']
    return table


def physics(scenario):
    """Everything both codes must share, from the scenario (after the brief's overrides)."""
    sim, dom = scenario['simulation'], scenario['domain']
    (material,) = scenario['materials']
    contact = scenario['contact']['default']
    (inflow,) = [p for p in scenario['particles'] if p['source'] == 'inflow']
    (floor,) = scenario['walls']
    assert contact['normal'] == 'hertz_sediment' and contact['tangential'] == 'mindlin', contact
    assert inflow['distribution']['type'] == 'single', inflow['distribution']
    assert floor['normal'] == [0, 0, 1] and floor['point'] == [0, 0, 0], floor
    assert dom['lower'] == [0, 0, 0] and dom['periodic'] == ['x', 'y'], dom
    assert dom['upper'][0] == dom['upper'][1], 'a square box'
    assert sim['gravity'][:2] == [0, 0] and sim['gravity'][2] < 0, sim['gravity']
    (height,) = [a for a in scenario['analyses'] if a['type'] == 'deposit_height']
    (stop,) = scenario['stop']
    assert stop['when'] == 'deposit_height' and 'at_least' in stop, stop
    L = dom['upper'][0]
    p = dict(d=inflow['distribution']['diameter'], rho=material['density'], E=material['youngs_modulus'],
             nu=material['poisson'], alpha=contact['alpha'], mu=contact['friction'], L=L, top=dom['upper'][2],
             u_r=inflow['fall_speed'], phi_0=inflow['solid_fraction'], z_c=inflow.get('entry_height', 2 * L),
             omega_star_rms=inflow.get('omega_star_rms', 0.0), dt=sim['dt'], g=-sim['gravity'][2],
             duration=sim['duration'], series_interval=scenario['output']['series_interval'],
             slice=height.get('slice', 0.1 * L), slices=height.get('slices', 10),
             threshold=height.get('threshold', 0.6), stop_height=stop['at_least'])
    p['mass'] = p['rho'] * math.pi / 6 * p['d'] ** 3
    p['F'] = p['rho'] * p['phi_0'] * L * L * p['u_r']  # tsubu's mass flux, kg/s (docs/scenario.md)
    return p


def lammps_coefficients(p):
    """The -var values of bench/lammps/contact.in (see its header) and the inflow of deposit.in."""
    E, nu, d, m = p['E'], p['nu'], p['d'], p['mass']
    e_star = E / (2 * (1 - nu * nu))  # two grains of one material, and grain on floor alike

    def dashpot(r_eff, m_eff, d_mean):  # tsubu's model H: alpha sqrt(K m* dbar^(1/2)), K = 4/3 E* sqrt(R*)
        return p['alpha'] * math.sqrt(4 / 3 * e_star * math.sqrt(r_eff) * m_eff * math.sqrt(d_mean))

    every = round(m / (p['F'] * p['dt']))  # steps between two grains: the same mass per second
    return {'E': E, 'nu': nu, 'eta_pair': dashpot(d / 4, m / 2, d), 'E_wall': E / (1 + nu),
            'eta_wall': dashpot(d / 2, m, d), 'kt': 2 * E / ((1 + nu) * (2 - nu)),
            'xgamma': 1 / math.sqrt(2 * (1 - nu)), 'mu': p['mu'], 'every': every,
            'F_lammps': m / (every * p['dt'])}


# ---------------------------------------------------------------------------------------------
# Running the codes

def load1():
    return float(open('/proc/loadavg').read().split()[0])


def timed(cmd, cwd, log=None):
    """Run a command alone, one thread: wall seconds, CPU seconds (user + system of the child)."""
    env = dict(os.environ, OMP_NUM_THREADS='1')
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    with open(log or os.devnull, 'w') as out:
        done = subprocess.run(cmd, cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        tail = open(log).read()[-3000:] if log else ''
        sys.exit(f"lammps_deposit.py: {' '.join(cmd)} failed (exit {done.returncode})\n{tail}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def lammps_vars(values):
    args = []
    for k, v in values.items():
        args += ['-var', k, repr(v) if isinstance(v, float) else str(v)]
    return args


def lammps_log(path):
    """Loop time, steps, atoms, neighbour builds and warnings from LAMMPS's screen output."""
    text = open(path).read()
    loops = re.findall(r'^Loop time of (\S+) on \d+ procs for (\d+) steps with (\d+) atoms', text, re.M)
    loop, steps, atoms = loops[0]
    use = re.search(r'^([\d.]+)% CPU use with', text, re.M)
    return {'loop_s': float(loop), 'loop_cpu_s': float(loop) * float(use.group(1)) / 100,
            'steps': int(steps), 'atoms': int(atoms),
            'builds': int(re.search(r'^Neighbor list builds = (\d+)', text, re.M).group(1)),
            'dangerous': int(re.search(r'^Dangerous builds = (\d+)', text, re.M).group(1)),
            'warnings': re.findall(r'^WARNING: (.*)$', text, re.M),
            'version': re.search(r'^LAMMPS \((.*)\)', text, re.M).group(1)}


def read_dump(path):
    """A LAMMPS custom dump as {column: array}, rows sorted by atom id."""
    lines = open(path).read().splitlines()
    at = next(i for i, l in enumerate(lines) if l.startswith('ITEM: ATOMS'))
    names = lines[at].split()[2:]
    data = np.array([[float(v) for v in l.split()] for l in lines[at + 1:] if l.strip()]).reshape(-1, len(names))
    data = data[np.argsort(data[:, names.index('id')])]
    return {n: data[:, i] for i, n in enumerate(names)}


def write_state(dump, path):
    """A LAMMPS dump as tsubu's particle state (`source = "file"`, docs/scenario.md)."""
    with open(path, 'w') as f:
        f.write('id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz\n')
        for i in range(len(dump['id'])):
            row = [dump[k][i] for k in ('radius', 'x', 'y', 'z', 'vx', 'vy', 'vz', 'omegax', 'omegay', 'omegaz')]
            f.write(f'{i},0,' + ','.join(repr(float(v)) for v in row) + '\n')


def toml_value(v):
    if isinstance(v, bool):
        return 'true' if v else 'false'
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v + '"'
    if isinstance(v, list):
        return '[' + ', '.join(toml_value(x) for x in v) + ']'
    if isinstance(v, dict):
        return '{ ' + ', '.join(f'{k} = {toml_value(x)}' for k, x in v.items()) + ' }'
    raise TypeError(v)


def toml_table(header, table):
    return f'{header}\n' + ''.join(f'{k} = {toml_value(v)}\n' for k, v in table.items()) + '\n'


def measure_scenario(scenario, p, particles, duration, gravity, upper, extra='', seed=1):
    """A tsubu scenario with the deposit run's box, material, contact law and floor, the
    given particle sources and the deposit measures of the brief."""
    z_lo, z_hi = 0.15 * p['L'], 0.35 * p['L']
    text = toml_table('[simulation]', {'name': 'measure', 'duration': duration, 'dt': p['dt'],
                                       'integrator': 'velocity_verlet', 'gravity': gravity, 'seed': seed})
    text += toml_table('[domain]', {'lower': [0.0, 0.0, 0.0], 'upper': upper,
                                    'periodic': scenario['domain']['periodic']})
    for mat in scenario['materials']:
        text += toml_table('[[materials]]', mat)
    text += toml_table('[contact.default]', scenario['contact']['default'])
    for wall in scenario['walls']:
        text += toml_table('[[walls]]', wall)
    text += particles + extra
    text += toml_table('[[analyses]]', {'type': 'deposit_height', 'threshold': p['threshold']})
    text += toml_table('[[analyses]]', {'type': 'porosity', 'z_range': [z_lo, z_hi]})
    text += toml_table('[[analyses]]', {'type': 'coordination', 'z_range': [z_lo, z_hi]})
    return text


def tsubu_measure(tsubu, scenario, p, state_csv, work, name, seed):
    """tsubu's porosity and coordination of a particle state: one step from it, no inflow; the
    seed (of the porosity's Monte Carlo points) is the deposit run's."""
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    shutil.copy(state_csv, os.path.join(folder, 'state.csv'))
    text = measure_scenario(scenario, p, toml_table('[[particles]]', {'source': 'file', 'file': 'state.csv'}),
                            p['dt'], [0.0, 0.0, -p['g']], [p['L'], p['L'], p['top']],
                            toml_table('[output]', {'vtk_interval': 0.0, 'series_interval': 0.0,
                                                    'checkpoint_every_steps': 0, 'checkpoint_every_seconds': 0}),
                            seed)
    path = os.path.join(folder, 'measure.toml')
    open(path, 'w').write(text)
    timed([tsubu, 'run', path, '--out', os.path.join(folder, 'out')], folder, os.path.join(folder, 'tsubu.log'))
    return json_load(os.path.join(folder, 'out', 'run.json'))['results']


def json_load(path):
    return json.load(open(path))


def geometric_contacts(x, y, z, radius, L, z_range):
    """An independent count: touching grain pairs (centre distance < sum of radii, x and y
    periodic) of the grains with their centre in z_range: mean contacts, with and without
    rattlers (fewer than 2 or 4 contacts), the number of overlapping pairs, the largest overlap."""
    pos = np.stack([x, y, z], axis=1)
    gap = pos[:, None, :] - pos[None, :, :]
    gap[:, :, :2] -= L * np.round(gap[:, :, :2] / L)
    dist = np.sqrt((gap ** 2).sum(axis=2))
    overlap = radius[:, None] + radius[None, :] - dist
    np.fill_diagonal(overlap, -1.0)
    touching = overlap > 0
    count = touching.sum(axis=1)
    inside = (z > z_range[0]) & (z < z_range[1])
    c = count[inside]
    mean = lambda v: float(v.mean()) if len(v) else 0.0
    return {'Z': mean(c), 'Z_no_rattlers': mean(c[c >= 2]), 'Z_no_rattlers_4': mean(c[c >= 4]),
            'grains': int(inside.sum()), 'pairs': int(touching.sum() // 2),
            'max_overlap_ratio': float(overlap.max() / (2 * radius.max())) if len(x) > 1 else 0.0}


def read_state(path):
    """z and radius of a particle state CSV (tsubu's export, header with units, or write_state's)."""
    rows = list(csv.DictReader(open(path)))
    plain = lambda row: {k.split('[')[0]: v for k, v in row.items()}
    rows = [plain(r) for r in rows]
    return np.array([float(r['z']) for r in rows]), np.array([float(r['radius']) for r in rows])


def solid_fractions(z, radius, L, slice, slices):
    """Solid fraction of each slab k slice < z < (k+1) slice and of 0 < z < k slice (k = 1 ...),
    from exact sphere-slab volumes (x and y periodic: the full cross-section)."""
    def below(t):  # the volume of every grain below the plane z = t
        h = np.clip(t - (z - radius), 0.0, 2 * radius)
        return (math.pi * h * h * (3 * radius - h) / 3).sum()
    area = L * L
    layer = [(below((k + 1) * slice) - below(k * slice)) / (area * slice) for k in range(slices)]
    cumulative = [(below(k * slice) - below(0.0)) / (area * k * slice) for k in range(1, slices + 1)]
    return layer, cumulative


# ---------------------------------------------------------------------------------------------
# (1) The contact check: single collisions, no gravity

SPEEDS = (0.33, 1.0, 1.8)  # m/s: the entry speed, and up to the speed of a grain reaching the floor


def collision_cases(p):
    """Grains in one box far apart: (kind, speed, [(x, y, z, vx, vy, vz), ...])."""
    d, gap, spacing = p['d'], 0.05e-3, 5 * p['d']
    cases = []
    for kind in ('pair', 'floor', 'floor45', 'floor80'):
        for v in SPEEDS:
            cx = spacing * (len(cases) + 1)
            if kind == 'pair':
                cz, h = 5 * d, d / 2 + gap / 2
                grains = [(cx - h, 2 * d, cz, v / 2, 0.0, 0.0), (cx + h, 2 * d, cz, -v / 2, 0.0, 0.0)]
            else:
                angle = {'floor': 0, 'floor45': 45, 'floor80': 80}[kind]  # from the normal, degrees
                s, c = math.sin(math.radians(angle)), math.cos(math.radians(angle))
                grains = [(cx, 2 * d, d / 2 + gap, v * s, 0.0, -v * c)]
            cases.append((kind, v, grains))
    return cases


def collision_check(tsubu, scenario, p, coeffs, work):
    """Every case of collision_cases in both codes: the grains' final velocities and spins."""
    folder = os.path.join(work, 'collisions')
    os.makedirs(folder, exist_ok=True)
    cases = collision_cases(p)
    grains = [g for _, _, gs in cases for g in gs]
    upper = [5 * p['d'] * (len(cases) + 2), 4 * p['d'], 10 * p['d']]
    steps = 2500  # 10 ms: every collision is over (first touch within 1 ms, contacts of 0.2-0.4 ms)
    # tsubu
    with open(os.path.join(folder, 'grains.csv'), 'w') as f:
        f.write('x,y,z,d,vx,vy,vz\n')
        for g in grains:
            f.write(','.join(repr(v) for v in (g[0], g[1], g[2], p['d'], g[3], g[4], g[5])) + '\n')
    scen = dict(scenario, domain=dict(scenario['domain'], periodic=[]))
    text = measure_scenario(scen, p, toml_table('[[particles]]', {'source': 'csv', 'file': 'grains.csv',
                                                                 'material': scenario['materials'][0]['name']}),
                            steps * p['dt'], [0.0, 0.0, 0.0], upper,
                            toml_table('[output]', {'vtk_interval': 0.0, 'series_interval': 1.0,
                                                    'track': list(range(len(grains))),
                                                    'checkpoint_every_steps': 0, 'checkpoint_every_seconds': 0}))
    open(os.path.join(folder, 'collisions.toml'), 'w').write(text)
    timed([tsubu, 'run', 'collisions.toml', '--out', 'out'], folder, os.path.join(folder, 'tsubu.log'))
    last = {}
    for row in csv.DictReader(open(os.path.join(folder, 'out', 'track.csv'))):
        last[int(row['id'])] = row
    ts = [tuple(float(last[i][k]) for k in ('vx', 'vz', 'wy')) for i in range(len(grains))]
    # LAMMPS
    with open(os.path.join(folder, 'grains.data'), 'w') as f:
        f.write(f'grains of the contact check\n\n{len(grains)} atoms\n1 atom types\n\n0 {upper[0]!r} xlo xhi\n'
                f'0 {upper[1]!r} ylo yhi\n0 {upper[2]!r} zlo zhi\n\nAtoms # sphere\n\n')
        for i, g in enumerate(grains):
            f.write(f'{i + 1} 1 {p["d"]!r} {p["rho"]!r} {g[0]!r} {g[1]!r} {g[2]!r}\n')
        f.write('\nVelocities\n\n')
        for i, g in enumerate(grains):
            f.write(f'{i + 1} {g[3]!r} {g[4]!r} {g[5]!r} 0 0 0\n')
    values = {k: coeffs[k] for k in ('E', 'nu', 'eta_pair', 'E_wall', 'eta_wall', 'kt', 'xgamma', 'mu')}
    values.update(data='grains.data', skin=0.1 * p['d'], dt=p['dt'], steps=steps, state='final.dump',
                  contacts=os.path.join(INPUTS, 'contact.in'))
    timed(['lmp', '-nocite', '-log', 'none', '-in', os.path.join(INPUTS, 'collisions.in')] + lammps_vars(values),
          folder, os.path.join(folder, 'lammps.out'))
    dump = read_dump(os.path.join(folder, 'final.dump'))
    lm = [(dump['vx'][i], dump['vz'][i], dump['omegay'][i]) for i in range(len(grains))]
    # restitution: normal rebound over normal approach; for 45 degrees also the tangential
    # velocity kept (vx out / vx in) and the spin (R omega_y / vx in)
    rows, n = [], 0
    for kind, v, gs in cases:
        row = {'kind': kind, 'speed': v}
        for code, res in (('tsubu', ts), ('lammps', lm)):
            if kind == 'pair':
                row[f'e_{code}'] = (res[n + 1][0] - res[n][0]) / v
            else:
                vz_in, vx_in = gs[0][5], gs[0][3]
                row[f'e_{code}'] = -res[n][1] / vz_in
                if kind != 'floor':
                    row[f'vt_{code}'] = res[n][0] / vx_in
                    row[f'spin_{code}'] = res[n][2] * p['d'] / 2 / vx_in
        rows.append(row)
        n += len(gs)
    return rows


# ---------------------------------------------------------------------------------------------
# The deposit runs

# tsubu's "lean" variant: what LAMMPS's run does at the rows (the deposit height that stops it)
# and not the scenario's other output: no VTK frames, the porosity of 1 Monte Carlo point instead
# of 65536 at every row (the final state is measured afterwards, as LAMMPS's is).
LEAN_SETTINGS = ['output.vtk_interval=0', 'analyses.1.points=1']


def particle_steps_from_series(path, dt):
    """Grains in the box summed over the steps, from series.csv's rows (trapezoids between rows).
    run.json's particle_force_evaluations counts the final grains over every step, an upper
    bound for an inflow (about twice the true sum for a box filling at a constant rate)."""
    rows = [(float(r['time']), float(r['particles'])) for r in csv.DictReader(open(path))]
    return sum((n0 + n1) / 2 * round((t1 - t0) / dt) for (t0, n0), (t1, n1) in zip(rows, rows[1:]))


def run_tsubu(tsubu, seed, lean, work, name):
    out = os.path.join(work, name)
    cmd = [tsubu, 'run', SCENARIO, '--out', out]
    for s in TSUBU_SETTINGS + ([f'simulation.seed={seed}'] if seed != 1 else []) + (LEAN_SETTINGS if lean else []):
        cmd += ['--set', s]
    load = load1()
    wall, cpu = timed(cmd, work, os.path.join(work, name + '.log'))
    run = json_load(os.path.join(out, 'run.json'))
    timed([tsubu, 'export', out, '--to', os.path.join(out, 'export')], work)
    (state,) = [f for f in os.listdir(os.path.join(out, 'export')) if f.startswith('particles_')]
    return {'code': 'tsubu-lean' if lean else 'tsubu', 'version': f"tsubu {run['version']}", 'seed': seed,
            'load_before': load, 'wall_s': wall, 'cpu_s': cpu, 'own_wall_s': run['wall_time_s'],
            'loop_s': run['loop_time_s'], 'steps': run['steps'], 'simulated_s': run['steps'] * run['dt'],
            'dt': run['dt'], 'grains_end': run['particles'],
            'particle_steps': particle_steps_from_series(os.path.join(out, 'series.csv'), run['dt']),
            'particle_steps_run_json': run['particle_force_evaluations'],
            'list_builds': run['list_builds'], 'stop_reason': run['stop_reason'],
            'mass_flux': run['results']['inflow_F'], 'mass_flux_measured': run['results']['inflow_F_measured'],
            'own_results': {k: run['results'][k] for k in MEASURES},
            'state_csv': os.path.join(out, 'export', state), 'out': out}


def tsubu_state_at(tsubu, seed, t, work, name):
    """tsubu's deposit (lean, untimed) at time t, its stop rule off: the state CSV."""
    out = os.path.join(work, name)
    cmd = [tsubu, 'run', SCENARIO, '--out', out]
    for s in TSUBU_SETTINGS + LEAN_SETTINGS + [f'simulation.seed={seed}', f'simulation.duration={t!r}',
                                               'stop.0.after=1e9']:
        cmd += ['--set', s]
    timed(cmd, work, os.path.join(work, name + '.log'))
    timed([tsubu, 'export', out, '--to', os.path.join(out, 'export')], work)
    (state,) = [f for f in os.listdir(os.path.join(out, 'export')) if f.startswith('particles_')]
    return os.path.join(out, 'export', state)


def run_lammps(p, coeffs, seed, skin, work, name):
    """The LAMMPS deposit (bench/lammps/deposit.in): until the deposit-height rule holds at a
    row (every series_interval) or the scenario's duration, state dumped at the end."""
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, 'grain.mol'), 'w') as f:
        f.write(f'# one grain\n\n1 atoms\n\nCoords\n\n1 0 0 0\n\nTypes\n\n1 1\n\n'
                f'Diameters\n\n1 {p["d"]!r}\n\nMasses\n\n1 {p["mass"]!r}\n')
    row = round(p['series_interval'] / p['dt'])
    values = {k: coeffs[k] for k in ('E', 'nu', 'eta_pair', 'E_wall', 'eta_wall', 'kt', 'xgamma', 'mu', 'every')}
    values.update(L=p['L'], top=p['top'], dt=p['dt'], steps=round(p['duration'] / p['dt']), zc=p['z_c'],
                  vz=-p['u_r'], near=p['d'], seed=1000 + seed, skin=skin, check=1, g=p['g'], row=row,
                  slice=p['slice'], r=p['d'] / 2, first=round(p['stop_height'] / p['slice']), last=p['slices'],
                  threshold=p['threshold'], grain='grain.mol', contacts=os.path.join(INPUTS, 'contact.in'),
                  state='final.dump')
    load = load1()
    log = os.path.join(folder, 'lammps.out')
    wall, cpu = timed(['lmp', '-nocite', '-log', 'none', '-in', os.path.join(INPUTS, 'deposit.in')]
                      + lammps_vars(values), folder, log)
    info = lammps_log(log)
    steps, every = info['steps'], coeffs['every']
    # grain k enters at the end of step 1 + k every and moves from the next step on
    entries = np.arange(1, steps + 1, every)
    if info['atoms'] != len(entries):
        print(f"lammps_deposit.py: warning: {info['atoms']} grains in the box, {len(entries)} scheduled", file=sys.stderr)
    dump = read_dump(os.path.join(folder, 'final.dump'))
    write_state(dump, os.path.join(folder, 'state.csv'))
    return {'code': 'lammps', 'version': f"LAMMPS {info['version']}", 'seed': seed, 'load_before': load,
            'wall_s': wall, 'cpu_s': cpu, 'loop_s': info['loop_s'], 'loop_cpu_s': info['loop_cpu_s'], 'steps': steps,
            'simulated_s': steps * p['dt'], 'dt': p['dt'], 'grains_end': info['atoms'],
            'particle_steps': int((steps - entries).sum()), 'list_builds': info['builds'],
            'dangerous_builds': info['dangerous'], 'warnings': info['warnings'], 'skin': skin,
            'stop_reason': 'height rule' if steps < values['steps'] else 'duration',
            'mass_flux': coeffs['F_lammps'], 'mass_flux_measured': info['atoms'] * p['mass'] / (steps * p['dt']),
            'dump': dump, 'state_csv': os.path.join(folder, 'state.csv')}


# ---------------------------------------------------------------------------------------------
# Output

CODES = {'tsubu': 'tsubu, scenario as given', 'tsubu-lean': 'tsubu, lean output', 'lammps': 'LAMMPS'}
CSV_COLUMNS = ['code', 'variant', 'version', 'dt', 'wall_s', 'cpu_s', 'loop_s', 'wall_s_median', 'cpu_s_median',
               'loop_s_median', 'simulated_s', 'steps', 'grains_end', 'particle_steps_per_s',
               'particle_steps_per_s_median', 'mass_flux_kg_s', 'deposit_height', 'porosity',
               'porosity_exact', 'coordination', 'coordination_no_rattlers', 'coordination_no_rattlers_4',
               'slab_grains', 'runs']
VARIANTS = {'tsubu': 'scenario as given (VTK frames, porosity of 65536 points at every 0.01 s row)',
            'tsubu-lean': 'no VTK frames, porosity of 1 point at the rows; final state measured afterwards',
            'lammps': 'fix deposit, neighbor bin, skin {skin:g} m, height rule at the rows'}
AVERAGED = ['deposit_height', 'porosity', 'porosity_exact', 'coordination', 'coordination_no_rattlers',
            'coordination_no_rattlers_4']


def summary(runs, best_skin):
    """One row per code: the fastest round's times (the one least disturbed by other jobs) and the
    medians, medians of the counts, means of the deposit measures over the rounds."""
    med = lambda k: statistics.median(r[k] for r in runs)
    rate = [r['particle_steps'] / r['loop_s'] for r in runs]
    first = runs[0]
    row = {'code': first['code'].split('-')[0], 'variant': VARIANTS[first['code']].format(skin=best_skin),
           'version': first['version'], 'dt': first['dt'], 'simulated_s': med('simulated_s'), 'steps': med('steps'),
           'grains_end': med('grains_end'), 'particle_steps_per_s': max(rate),
           'particle_steps_per_s_median': statistics.median(rate), 'mass_flux_kg_s': first['mass_flux'],
           'slab_grains': statistics.fmean(r['measured']['porosity_grains'] for r in runs), 'runs': len(runs)}
    for k in ('wall_s', 'cpu_s', 'loop_s'):
        row[k] = min(r[k] for r in runs)
        row[k + '_median'] = med(k)
    for k in AVERAGED:
        row[k] = statistics.fmean(r['measured'][k] for r in runs)
    return row


def spread(runs, key, digits):
    values = [r['measured'][key] for r in runs]
    return f"{statistics.fmean(values):.{digits}f} ({min(values):.{digits}f}-{max(values):.{digits}f})"


WRITE_ARGS = ['p', 'coeffs', 'collisions', 'skins', 'best_skin', 'rounds', 'startup', 'tsubu_binary', 'remeasure']


def write_results(results, p, coeffs, collisions, skins, best_skin, rounds, startup, tsubu_binary, remeasure):
    os.makedirs(results, exist_ok=True)
    by_code = {c: [r for r in rounds if r['code'] == c] for c in CODES}
    rows = {c: summary(runs, best_skin) for c, runs in by_code.items()}
    with open(os.path.join(results, 'lammps-deposit.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
        w.writeheader()
        for r in rows.values():
            w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in r.items()})
    ts, lean, lm = rows['tsubu'], rows['tsubu-lean'], rows['lammps']
    cpu = next((l.split(':', 1)[1].strip() for l in open('/proc/cpuinfo') if l.startswith('model name')),
               platform.machine())
    loads = [r['load_before'] for r in rounds]
    n_rounds = len(by_code['lammps'])
    md = []
    add = md.append
    add('# LAMMPS against tsubu: a deposit in vacuum at the same mass flux\n')
    add(f'Issue #12 ("Cost"). Measured {datetime.date.today()} by `bench/lammps_deposit.py` on {cpu}, '
        f'{os.cpu_count()} cores, one thread each (`OMP_NUM_THREADS=1`), each run alone, {n_rounds} rounds; '
        f'round r uses seed r in both codes (round 1 is the brief\'s exact tsubu command) and runs tsubu, '
        f'tsubu lean, then LAMMPS. tsubu: {tsubu_binary}. Re-run: '
        '`TSUBU=build/tsubu /usr/bin/python3 bench/lammps_deposit.py` (about 2 minutes on an idle machine).\n')
    busy = [l for l in loads if l > LOAD_LIMIT]
    if not busy:
        add(f'Load before the timed runs: {min(loads):.2f}-{max(loads):.2f} (one-minute average, below '
            f'{LOAD_LIMIT} each time).\n')
    elif len(busy) * 2 < len(loads):
        add(f'Load: the one-minute load average before the timed runs was {min(loads):.2f}-{max(loads):.2f}, '
            f'above {LOAD_LIMIT} before {len(busy)} of {len(loads)} runs (each run\'s load is in "Every run"): '
            'another job kept one of the 2 cores busy, the runs had the other. The medians over the rounds '
            'damp the slow runs; the CPU times (user + system of each process) are the steadier measure.\n')
    else:
        add(f'**The machine was busy**: other jobs shared the 2 cores, and the one-minute load average '
            f'before the timed runs was {min(loads):.2f}-{max(loads):.2f} (above {LOAD_LIMIT} before '
            f'{len(busy)} of {len(loads)} runs). Wall and loop times are inflated and noisy; the CPU '
            f'times (user + system of each process) are the steadier measure.\n')
    add('## Result\n')
    add('| run | wall s | CPU s | loop s | simulated s | steps | grains at end | particle-steps/s (loop) | '
        'deposit height (m) | porosity | porosity (exact) | Z | Z no rattlers (≥2) | Z no rattlers (≥4) | '
        'grains in slab |')
    add('|' + '---|' * 15)
    for c, r in rows.items():
        add(f"| {CODES[c]} | {r['wall_s']:.2f} ({r['wall_s_median']:.2f}) | {r['cpu_s']:.2f} ({r['cpu_s_median']:.2f}) | "
            f"{r['loop_s']:.2f} ({r['loop_s_median']:.2f}) | {r['simulated_s']:.3f} | {r['steps']:.0f} | "
            f"{r['grains_end']:.0f} | {r['particle_steps_per_s']:.3g} ({r['particle_steps_per_s_median']:.3g}) | "
            f"{r['deposit_height']:.4g} | {r['porosity']:.3f} | {r['porosity_exact']:.3f} | "
            f"{r['coordination']:.2f} | {r['coordination_no_rattlers']:.2f} | "
            f"{r['coordination_no_rattlers_4']:.2f} | {r['slab_grains']:.0f} |")
    add('')
    add(f"Times and rates: the fastest of the {n_rounds} rounds (the least disturbed by other jobs), the "
        "median in brackets; steps and grains: medians; deposit measures: means (`lammps-deposit.csv`: the "
        f"same rows, `_median` columns for the medians). Ratios below from the fastest rounds. Versions: {ts['version']}, {lm['version']}; dt = "
        f"{p['dt']:g} s for both.\n")
    add('| LAMMPS / tsubu | wall | CPU | loop | particle-steps/s |')
    add('|---|---|---|---|---|')
    for name, t in (('scenario as given', ts), ('lean output', lean)):
        add(f"| tsubu {name} | {lm['wall_s'] / t['wall_s']:.2f} | {lm['cpu_s'] / t['cpu_s']:.2f} | "
            f"{lm['loop_s'] / t['loop_s']:.2f} | {lm['particle_steps_per_s'] / t['particle_steps_per_s']:.2f} |")
    add('')
    add('- *wall s*: the process from start to exit, timed by the script; *CPU s*: user + system time of '
        'that process; *loop s*: each code\'s own timer of its time loop (LAMMPS "Loop time", tsubu '
        f"`loop_time_s`). LAMMPS's wall time includes its start-up: an empty input takes "
        f"{statistics.median(startup):.2f} s of wall time here (MPI initialisation), most of the gap "
        'between its wall and loop times.')
    add('- *particle-steps/s*: grains in the box summed over the steps, over the loop time (tsubu: from '
        '`series.csv`\'s grain counts every 0.01 s; LAMMPS: from its insertion schedule, checked against '
        'its final count). tsubu\'s own `run.json` `particle_steps_per_second` counts the final grains '
        f"over every step, an upper bound for an inflow: {statistics.median(r['particle_steps_run_json'] / r['loop_s'] for r in by_code['tsubu']):.3g} "
        'for the run as given.')
    add('- *tsubu, scenario as given* does at every 0.01 s row what its scenario asks: the deposit height '
        '(which stops it), the porosity of 65536 Monte Carlo points, the coordination, and a VTK frame '
        'with the contact network every 0.05 s. *tsubu, lean output* (`' + "`, `".join(f"--set {x}" for x in LEAN_SETTINGS)
        + '`) does what the LAMMPS run does: the deposit height at the rows, no frames; its deposit is '
        + ('the same, bit for bit (identical final state in every round)' if all(r['same_state'] for r in by_code['tsubu-lean'])
           else '**not** always bit-identical to the full run\'s') + ', measured afterwards like LAMMPS\'s.')
    add('- Porosity and Z: tsubu\'s own analyses on the final states, on 0.15 L < z < 0.35 L '
        f"({0.15 * p['L']:g}-{0.35 * p['L']:g} m); Z counts grain-grain contacts (floor excluded), the no-rattler "
        'variants leave out grains with fewer than 2 or 4 contacts. Mean (range) over the rounds:\n')
    add('| run | porosity | porosity (exact) | Z | Z ≥2 | Z ≥4 | stop time (s) |')
    add('|---|---|---|---|---|---|---|')
    for c in ('tsubu', 'lammps'):
        runs = by_code[c]
        times = [r['simulated_s'] for r in runs]
        add(f"| {CODES[c]} | {spread(runs, 'porosity', 3)} | {spread(runs, 'porosity_exact', 3)} | "
            f"{spread(runs, 'coordination', 2)} | {spread(runs, 'coordination_no_rattlers', 2)} | "
            f"{spread(runs, 'coordination_no_rattlers_4', 2)} | {statistics.fmean(times):.3f} "
            f"({min(times):.2f}-{max(times):.2f}) |")
    add('')
    add('Why LAMMPS reaches the height sooner: solid fraction of the slabs of 0.1 L from the floor up '
        '(exact sphere-slab volumes), and of 0 < z < 0.4 L, which decides the stop (mean of the rounds):\n')
    add('| state | ' + ' | '.join(f"{k / 10:g}-{(k + 1) / 10:g} L" for k in range(6)) + ' | 0-0.4 L |')
    add('|---|' + '---|' * 7)
    mean_profile = lambda key, runs: [statistics.fmean(r[key][0][k] for r in runs) for k in range(6)] + \
        [statistics.fmean(r[key][1][3] for r in runs)]
    t_lm = statistics.fmean(r['simulated_s'] for r in by_code['lammps'])
    t_ts = statistics.fmean(r['simulated_s'] for r in by_code['tsubu'])
    for label, values in ((f'LAMMPS at its stop (t = {t_lm:.2f} s)', mean_profile('profile', by_code['lammps'])),
                          (f'tsubu at the same time', mean_profile('profile_at_lammps_stop', by_code['tsubu'])),
                          (f'tsubu at its stop (t = {t_ts:.3f} s)', mean_profile('profile', by_code['tsubu']))):
        add(f'| {label} | ' + ' | '.join(f'{v:.3f}' for v in values) + ' |')
    add('')
    add('### Every run\n')
    add('| round (seed) | run | load before | wall s | CPU s | loop s | steps | grains | height (m) | '
        'porosity | Z | Z ≥2 | Z ≥4 | slab grains |')
    add('|' + '---|' * 14)
    for i, r in enumerate(rounds):
        m = r['measured']
        add(f"| {r['seed']} | {CODES[r['code']]} | {r['load_before']:.2f} | {r['wall_s']:.2f} | "
            f"{r['cpu_s']:.2f} | {r['loop_s']:.2f} | {r['steps']} | {r['grains_end']} | "
            f"{m['deposit_height']:.3g} | {m['porosity']:.3f} | {m['coordination']:.2f} | "
            f"{m['coordination_no_rattlers']:.2f} | {m['coordination_no_rattlers_4']:.2f} | "
            f"{m['porosity_grains']} |")
    add('')
    add('Checks of the measurement. (a) The procedure used for LAMMPS (`tsubu export` of the final '
        'checkpoint, one step as `source = "file"`, no inflow) applied to tsubu\'s own final state '
        'against the run\'s own `run.json` results:\n')
    add('| round | porosity run / re-measured | porosity (exact) | Z | Z ≥2 | Z ≥4 |')
    add('|---|---|---|---|---|---|')
    for i, (own, again) in enumerate(remeasure):
        add(f"| {i + 1} | {own['porosity']:.4f} / {again['porosity']:.4f} | {own['porosity_exact']:.4f} / "
            f"{again['porosity_exact']:.4f} | {own['coordination']:.3f} / {again['coordination']:.3f} | "
            f"{own['coordination_no_rattlers']:.3f} / {again['coordination_no_rattlers']:.3f} | "
            f"{own['coordination_no_rattlers_4']:.3f} / {again['coordination_no_rattlers_4']:.3f} |")
    add('')
    add('(b) Contact detection on the LAMMPS states (a loaded deposit must show overlaps): an independent '
        'count by the script of touching grain pairs (centre distance below the sum of radii, x and y '
        'periodic) on the dumped state, against tsubu\'s coordination after its one step:\n')
    add('| round | overlapping pairs | largest overlap / d | Z script / tsubu | Z ≥2 script / tsubu | '
        'Z ≥4 script / tsubu |')
    add('|---|---|---|---|---|---|')
    for r in by_code['lammps']:
        c, m = r['geometric'], r['measured']
        add(f"| {r['seed']} | {c['pairs']} | {c['max_overlap_ratio']:.2e} | {c['Z']:.3f} / {m['coordination']:.3f} | "
            f"{c['Z_no_rattlers']:.3f} / {m['coordination_no_rattlers']:.3f} | "
            f"{c['Z_no_rattlers_4']:.3f} / {m['coordination_no_rattlers_4']:.3f} |")
    add('')
    add('## Settings\n')
    add(f"Grains: d = {p['d']:g} m, rho = {p['rho']:g} kg/m3 (m = {p['mass']:.6g} kg), E = {p['E']:g} Pa, "
        f"nu = {p['nu']:g}; box {p['L']:g} x {p['L']:g} x {p['top']:g} m (L = {p['L'] / p['d']:g} d), periodic "
        f"in x and y, a floor at z = 0 of the same material, gravity {p['g']:g} m/s2, vacuum. Entry plane "
        f"z_c = {p['z_c']:g} m (2 L), fall speed {p['u_r']:g} m/s. Both stop by tsubu's rule, checked every "
        f"{p['series_interval']:g} s: the deposit height, the largest k <= {p['slices']} for which the solid "
        f"fraction of 0 < z < k {p['slice']:g} m exceeds {p['threshold']:g}, times {p['slice']:g} m, has reached "
        f"{p['stop_height']:g} m (0.4 L). In LAMMPS: `fix halt` every {round(p['series_interval'] / p['dt'])} "
        'steps on an equal-style variable built from per-atom sphere-cap volumes (exact sphere-slab volumes, '
        'as tsubu\'s), see `deposit.in`. Time step '
        f"{p['dt']:g} s, velocity Verlet in both (LAMMPS `fix nve/sphere`; tsubu evaluates velocity-dependent "
        'forces with the half-step velocity as LAMMPS does): the scenario\'s step, about 1/50 of a Hertz '
        'contact time at 0.7 m/s, not LAMMPS\'s largest stable one, so that both integrate the same contacts '
        'alike.\n')
    add("**tsubu**: `OMP_NUM_THREADS=1 build/tsubu run examples/sedimentation/mono-vacuum.toml --out OUT "
        + ' '.join(f"--set '{x}'" for x in TSUBU_SETTINGS) + "` (rounds 2+ add `--set simulation.seed=r`); "
        'linked-cell search with its default skin d/10.\n')
    add("**LAMMPS**: `bench/lammps/deposit.in` with `bench/lammps/contact.in`: `atom_style sphere`, "
        "`pair_style granular`, `fix wall/gran granular` at z = 0, `fix deposit`, `fix nve/sphere`, "
        "`fix gravity`, `newton off`, `comm_modify vel yes`; thermo only at the end, one `write_dump` after "
        "the run. Neighbour list `neighbor SKIN bin`, `neigh_modify delay 0 every 1 check yes`; skins tried "
        "(seed 1, the faster of two runs each; loop time, and loop CPU time = loop time x LAMMPS's CPU use, "
        "which ranks them): " + ', '.join(f"{sk * 1e3:g} mm: {t:.2f} s / {c:.2f} s" for sk, t, c in skins)
        + f"; kept {best_skin * 1e3:g} mm. `bin` is the style for one grain size (`multi` helps only with "
        'size ratios); `newton on` gave no gain in a trial.\n')
    add('### How the mass flux was matched\n')
    flux = lambda c: statistics.fmean(r['mass_flux_measured'] for r in by_code[c])
    add(f"tsubu's inflow lets a random column of solid fraction phi_0 = {p['phi_0']:g}, falling at u_r, "
        f"through the entry plane: F = rho phi_0 L^2 u_r = {p['F']:.5g} kg/s "
        f"({p['F'] / p['mass']:.1f} grains/s), each grain entering at z_c with velocity -u_r. LAMMPS's "
        f"`fix deposit` inserts one grain (a one-atom molecule template carrying d and m) every "
        f"N = round(m / (F dt)) = {coeffs['every']} steps at a random x, y on the plane z = z_c with velocity "
        f"-u_r, at least d from every grain already in the box (so grains enter without overlap, as "
        f"tsubu's column guarantees): F = m / (N dt) = {coeffs['F_lammps']:.5g} kg/s "
        f"({(coeffs['F_lammps'] / p['F'] - 1) * 100:+.2f} %). Mass in the box at the stop over the stop "
        f"time, mean of the rounds: tsubu {flux('tsubu'):.4g}, LAMMPS {flux('lammps'):.4g} kg/s (tsubu's "
        "arrivals are random, LAMMPS's regular). `fix pour` was not used: it inserts batches at intervals "
        "set by the fall time through its region, a pulsed flux, where tsubu's is steady. tsubu also gives "
        f"each grain a small random spin (Omega*_rms = {p['omega_star_rms']:g}, about "
        f"{2 * p['u_r'] * p['omega_star_rms'] / p['d']:.2g} rad/s); LAMMPS none.\n")
    add('### How the contact models were matched\n')
    add('tsubu: `hertz_sediment` (model H) F_n = K delta^1.5 - eta_n v_n, K = 4/3 E* sqrt(R*), '
        f"eta_n = alpha sqrt(K m* dbar^0.5) (alpha = {p['alpha']:g}), a constant dashpot; `mindlin` "
        'tangential: the spring xi is capped at xi_max = mu (2-nu)/(2(1-nu)) delta and '
        'F_t = -mu chi |F_n| xi/|xi| - eta_t v_t with chi = 1 - (1 - |xi|/xi_max)^1.5, '
        'eta_t = eta_n / sqrt(2(1-nu)).\n')
    add('LAMMPS (`pair_style granular`, and the same in `fix wall/gran granular`):\n')
    add(f"- normal `hertz/material E nu` with **`damping velocity`**, whose dashpot is the constant "
        f"given: tsubu's eta_n goes in directly, {coeffs['eta_pair']:.5g} kg/s for a grain pair (R* = d/4, "
        f"m* = m/2, dbar = d) and {coeffs['eta_wall']:.5g} kg/s on the floor (R* = d/2, m* = m, dbar = d). "
        'The other damping models scale with the overlap (`viscoelastic`, `tsuji`) or the mass '
        '(`mass_velocity`) and cannot give model H\'s constant dashpot (`tsuji` is tsubu\'s `hertz_tsuji`). '
        'The normal force is then the same function of overlap and approach speed in both codes, '
        'attraction at the end of a contact included (neither clamps F_n at 0).')
    add(f"- the floor: this LAMMPS version's `fix wall/gran` takes 4/3 E/(2(1-nu)) as its 4/3 E*, not "
        f"E/(2(1-nu^2)) as for two grains of one material (the quirk noted in "
        f"../shared/bench/lammps/bench_lmp.in), so the wall is given E/(1+nu) = {coeffs['E_wall']:.5g} Pa, "
        "which makes its grain-floor stiffness tsubu's (the floor collisions below confirm it).")
    add(f"- tangential `mindlin kt xgamma mu` with kt = 8 G* = 2E/((1+nu)(2-nu)) = {coeffs['kt']:.5g} Pa "
        f"(LAMMPS multiplies it by the contact radius a = sqrt(R* delta)): the initial slope of tsubu's chi "
        f"law, 3/2 mu |F_n| / xi_max, is the same 8 G* a. xgamma = 1/sqrt(2(1-nu)) = {coeffs['xgamma']:.5g} "
        'makes the tangential dashpot tsubu\'s (kt is given explicitly, the same for grain pairs and the '
        'floor, not left to `NULL`). What differs: LAMMPS\'s spring stays linear up to '
        'mu |F_n| (it slips at 2/3 of tsubu\'s xi_max; tsubu\'s force bends over before), and LAMMPS caps '
        'spring plus dashpot at mu |F_n| where tsubu caps the spring and adds the dashpot. Neither has '
        'rolling or twisting resistance.\n')
    add('Single collisions, no gravity, run by the script in both codes (e = normal speed out / in; for '
        'oblique impacts also the tangential speed kept and the spin R omega, over the tangential speed '
        'in; angles from the normal):\n')
    add('| collision | speed (m/s) | e tsubu | e LAMMPS | tangential kept, tsubu / LAMMPS | '
        'R omega / tangential in, tsubu / LAMMPS |')
    add('|---|---|---|---|---|---|')
    names = {'pair': 'grain pair, head-on', 'floor': 'grain on floor, normal', 'floor45': 'grain on floor, 45°',
             'floor80': 'grain on floor, 80° (glancing)'}
    for c in collisions:
        tang = (f"{c['vt_tsubu']:.4f} / {c['vt_lammps']:.4f}", f"{c['spin_tsubu']:.4f} / {c['spin_lammps']:.4f}") \
            if 'vt_tsubu' in c else ('', '')
        add(f"| {names[c['kind']]} | {c['speed']:g} | {c['e_tsubu']:.5f} | {c['e_lammps']:.5f} | {tang[0]} | {tang[1]} |")
    add('')
    worst = max(abs(c['e_tsubu'] - c['e_lammps']) for c in collisions)
    add(f"The normal restitutions agree to {worst:.1e}: the normal law is the same. With a constant "
        'dashpot, restitution is not a parameter: it rises with the impact speed (the Hertz spring '
        'stiffens with the overlap, the dashpot does not), and alpha = 0.2 makes these grains very '
        f"inelastic: e from {min(c['e_tsubu'] for c in collisions):.2g} (the glancing 0.33 m/s impact, a "
        f"normal approach of {0.33 * math.cos(math.radians(80)):.2f} m/s, does not rebound) to "
        f"{max(c['e_tsubu'] for c in collisions):.2f}. It also depends by a few per cent on where the touch "
        'falls within a step (the dashpot acts at full strength from the first overlap); both codes '
        'start the same collision alike. At 45° both grains end rolling (tangential speed kept '
        'about 5/7, R omega equal to it), within a few per cent. At 80° they part ways: a grain sliding '
        'on LAMMPS\'s floor keeps most of its tangential speed and hardly spins, as Coulomb friction '
        'allows (tangential impulse at most mu times the normal one), while tsubu\'s ends rolling as at '
        '45°: its tangential dashpot acts on top of mu |F_n|, and eta_t v_t (about 13 N at 1 m/s on the '
        'floor) exceeds the Coulomb force of such a glancing contact several times.\n')
    add('## What differs\n')
    add('- Insertion: tsubu\'s grains come from a random column (irregular arrival times, a little spin); '
        'LAMMPS\'s arrive one every N steps at random positions on the entry plane, without spin. Same '
        'flux, entry height and speed.')
    lm_profile = mean_profile('profile', by_code['lammps'])
    ts_profile = mean_profile('profile_at_lammps_stop', by_code['tsubu'])
    grains_later = statistics.fmean(r['grains_end'] for r in by_code['tsubu']) - \
        statistics.fmean(r['grains_end'] for r in by_code['lammps'])
    add('- The tangential law (above); the normal law and both dashpots are the same. Grains landing on '
        'the deposit meet it at every angle, and in tsubu a glancing impact cannot slide (its dashpot '
        'acts beyond the Coulomb cap). This is the likely cause of the profiles above: at the same time '
        f"LAMMPS's lowest layer packs denser ({lm_profile[0]:.3f} against {ts_profile[0]:.3f} in the first "
        f"0.1 L) and its surface is flatter ({lm_profile[4]:.3f} against {ts_profile[4]:.3f} in 0.4-0.5 L), "
        f"so 0 < z < 0.4 L passes {p['threshold']:g} with fewer grains: LAMMPS stops "
        f"{t_ts - t_lm:.3f} s sooner, with {grains_later:.0f} grains fewer in the box. The measured slab "
        '(0.15-0.35 L) has the same porosity in both, and Z is higher in LAMMPS. Likely, not proven: the '
        'insertion differs too.')
    add('- The deposits are small (about 120 grains in the measured slab) and still dynamic at the stop '
        '(grains keep landing at about 1.8 m/s): porosity and Z change from row to row and from seed to '
        'seed. Compare the ranges over the rounds, not single digits.')
    add('- Both codes are deterministic for a seed (a repeated run gives the same bits), but LAMMPS\'s '
        'deposit also changes with the neighbour skin (the contact forces are summed in another order and '
        'the difference grows): the skins tried are within a few per cent of each other, so which one is '
        'kept, and with it the LAMMPS deposits, can change from one invocation of the script to the next.')
    add('- The timed work: tsubu as given measures porosity and coordination at every row and writes VTK '
        'frames, which LAMMPS does not do; the lean tsubu run removes that difference.')
    warnings = sorted({w for r in by_code['lammps'] for w in r.get('warnings', [])})
    if warnings:
        add('- LAMMPS warnings: ' + '; '.join(warnings))
    dangerous = sum(r['dangerous_builds'] for r in by_code['lammps'])
    add(f"- LAMMPS neighbour lists: {statistics.median(r['list_builds'] for r in by_code['lammps']):.0f} builds "
        f"(median), {dangerous} dangerous; tsubu: {statistics.median(r['list_builds'] for r in by_code['tsubu']):.0f}.")
    add('')
    open(os.path.join(results, 'lammps-deposit.md'), 'w').write('\n'.join(md))


# ---------------------------------------------------------------------------------------------

def wait_for_quiet(seconds):
    """Wait up to this long for the one-minute load average to drop below LOAD_LIMIT."""
    end = time.time() + seconds
    while load1() > LOAD_LIMIT and time.time() < end:
        time.sleep(10)
    return load1()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--rounds', type=int, default=3)
    ap.add_argument('--skins', default='0.25e-3,0.5e-3,1e-3,2e-3,4e-3', help='LAMMPS neighbour skins to try, m')
    ap.add_argument('--wait-load', type=float, default=120,
                    help='before each timed run, seconds to wait at most for a quiet machine')
    ap.add_argument('--tsubu', default=os.environ.get('TSUBU', os.path.join(ROOT, 'build', 'tsubu')))
    ap.add_argument('--results', default=os.path.join(HERE, 'results'))
    ap.add_argument('--work', help='keep the runs in this folder (default: a temporary one)')
    ap.add_argument('--render', metavar='RAW_JSON', help='only write the tables again from a kept raw.json')
    args = ap.parse_args()
    args.tsubu = os.path.abspath(args.tsubu)  # the runs start in folders of their own
    if args.render:
        raw = json.load(open(args.render))
        write_results(args.results, **{k: raw[k] for k in WRITE_ARGS})
        return 0
    if shutil.which('lmp') is None:
        print('lammps_deposit.py: LAMMPS (`lmp`) is not installed; nothing to compare (apt-get install lammps)')
        return 0
    work = args.work or tempfile.mkdtemp(prefix='lammps-deposit-')
    os.makedirs(work, exist_ok=True)
    scenario = apply_settings(tomllib.load(open(SCENARIO, 'rb')), TSUBU_SETTINGS)
    p = physics(scenario)
    coeffs = lammps_coefficients(p)
    source = os.path.dirname(os.path.dirname(os.path.abspath(args.tsubu)))  # the binary's checkout
    head = subprocess.run(['git', '-C', source, 'rev-parse', '--short=10', 'HEAD'], capture_output=True,
                          text=True).stdout.strip() or 'unknown'
    built = datetime.datetime.fromtimestamp(os.path.getmtime(args.tsubu), datetime.timezone.utc)
    tsubu_binary = (f"`{os.path.relpath(args.tsubu, source)}` built {built:%Y-%m-%d %H:%M} UTC "
                    f"(its checkout at {head} when measured)")

    print('contact check: single collisions in both codes', flush=True)
    collisions = collision_check(args.tsubu, scenario, p, coeffs, work)
    for c in collisions:
        print(f"  {c['kind']:8s} {c['speed']:5.2f} m/s  e tsubu {c['e_tsubu']:.5f}  LAMMPS {c['e_lammps']:.5f}")

    skins = []
    for skin in (float(s) for s in args.skins.split(',')):
        tries = []
        for n in range(2):
            wait_for_quiet(args.wait_load)
            tries.append(run_lammps(p, coeffs, 1, skin, work, f'skin-{skin:g}-{n}'))
        r = min(tries, key=lambda t: t['loop_cpu_s'])
        skins.append((skin, r['loop_s'], r['loop_cpu_s']))
        print(f"LAMMPS skin {skin:g} m: loop {r['loop_s']:.2f} s (CPU {r['loop_cpu_s']:.2f} s), "
              f"{r['list_builds']} builds ({r['dangerous_builds']} dangerous)", flush=True)
    best_skin = min(skins, key=lambda s: s[2])[0]

    startup = []  # LAMMPS's process start-up and exit alone (MPI initialisation): an empty input
    open(os.path.join(work, 'empty.in'), 'w').write('')
    for _ in range(3):
        startup.append(timed(['lmp', '-nocite', '-log', 'none', '-in', 'empty.in'], work)[0])

    rounds, remeasure = [], []
    for seed in range(1, args.rounds + 1):
        wait_for_quiet(args.wait_load)
        ts = run_tsubu(args.tsubu, seed, False, work, f'tsubu-{seed}')
        ts['measured'] = ts['own_results']
        remeasure.append((ts['own_results'], tsubu_measure(args.tsubu, scenario, p, ts['state_csv'], work,
                                                           f'remeasure-{seed}', seed)))
        wait_for_quiet(args.wait_load)
        lean = run_tsubu(args.tsubu, seed, True, work, f'tsubu-lean-{seed}')
        lean['same_state'] = open(lean['state_csv']).read() == open(ts['state_csv']).read()
        lean['measured'] = tsubu_measure(args.tsubu, scenario, p, lean['state_csv'], work, f'measure-lean-{seed}',
                                         seed)
        wait_for_quiet(args.wait_load)
        lm = run_lammps(p, coeffs, seed, best_skin, work, f'lammps-{seed}')
        lm['measured'] = tsubu_measure(args.tsubu, scenario, p, lm['state_csv'], work, f'measure-{seed}', seed)
        dump = lm.pop('dump')
        lm['geometric'] = geometric_contacts(dump['x'], dump['y'], dump['z'], dump['radius'], p['L'],
                                             (0.15 * p['L'], 0.35 * p['L']))
        # where the two deposits differ: solid fraction by slab at LAMMPS's stop time, and tsubu's
        # at its own stop
        at_lammps_stop = tsubu_state_at(args.tsubu, seed, lm['simulated_s'], work, f'tsubu-at-lammps-stop-{seed}')
        for run, state in ((lm, lm['state_csv']), (ts, ts['state_csv'])):
            run['profile'] = solid_fractions(*read_state(state), p['L'], p['slice'], 6)
        ts['profile_at_lammps_stop'] = solid_fractions(*read_state(at_lammps_stop), p['L'], p['slice'], 6)
        rounds += [ts, lean, lm]
        for r in (ts, lean, lm):
            m = r['measured']
            print(f"round {seed} {r['code']:10s}: load {r['load_before']:.2f}, wall {r['wall_s']:.2f} s, CPU "
                  f"{r['cpu_s']:.2f} s, loop {r['loop_s']:.2f} s, t = {r['simulated_s']:.2f} s, {r['grains_end']} "
                  f"grains, height {m['deposit_height']:.3g}, porosity {m['porosity']:.3f}, Z "
                  f"{m['coordination']:.2f} / {m['coordination_no_rattlers']:.2f} / "
                  f"{m['coordination_no_rattlers_4']:.2f}", flush=True)
    raw = dict(p=p, coeffs=coeffs, collisions=collisions, skins=skins, best_skin=best_skin, rounds=rounds,
               startup=startup, tsubu_binary=tsubu_binary, remeasure=remeasure)
    with open(os.path.join(work, 'raw.json'), 'w') as f:  # for --render
        json.dump(raw, f, default=float)
    write_results(args.results, **{k: raw[k] for k in WRITE_ARGS})
    print(f"wrote {os.path.join(args.results, 'lammps-deposit.csv')} and .md; runs in {work}")
    if not args.work:
        shutil.rmtree(work)
    return 0


if __name__ == '__main__':
    sys.exit(main())
