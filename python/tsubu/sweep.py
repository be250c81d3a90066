"""Runs the variants of a scenario, a grid and/or a list of cases, a few at a time.

    /usr/bin/python3 -m tsubu.sweep SWEEP.toml [--jobs N] [--dry-run] [--retry-failed] [--tsubu PATH]
                                    [--engine local|slurm|mpi] [--no-wait]

A sweep file names a base scenario, the `--set` overrides each case applies (a full grid of
values and/or an explicit list of cases), the output root and the number of runs at a time.
Every case runs `tsubu run` in a folder of its own named after its parameters. Re-running
the sweep skips the finished cases, resumes an interrupted or killed one from its checkpoint
(`tsubu resume`) and leaves a failed one alone (reported; --retry-failed runs it again).
After each case and at the end, the parameters, status, wall time and results of every case
are written to OUTPUT/results.csv. Ctrl-C (or SIGTERM) asks the runs to stop with a
checkpoint; re-running continues them. `--engine slurm` hands the cases to Slurm as an array
job, `--engine mpi` to an MPI pool of workers (tsubu.cluster). The format and the command:
docs/sweeps.md.

Exit codes: 0 every case finished (with --no-wait: or is in Slurm's queue), 1 a case failed
or did not finish, 2 a bad sweep file or command line, 4 interrupted, 5 a file of the sweep
could not be written (the runs were stopped with a checkpoint).
"""
import argparse
import contextlib
import csv
import fcntl
import itertools
import json
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
import tomllib
from pathlib import Path

from .runs import lock_holder

__all__ = ["SweepError", "SweepWriteError", "Case", "Sweep", "load_sweep", "run_sweep", "main"]

INTERRUPTED = 4
WRITE_FAILED = 5  # as tsubu's own exit code for an output it cannot write
SWEEP_LOCK = ".tsubu-sweep-lock"  # in the output root, held by the sweep running there


class SweepError(ValueError):
    """A bad sweep file: `file: key: what is wrong`."""


class SweepWriteError(OSError):
    """A file of the sweep (results.csv, a log, the lock) could not be written:
    `cannot write FILE: reason`. The runs under way were stopped with a checkpoint."""


@contextlib.contextmanager
def _writing(path, partial=None):
    """Turns an OSError while writing `path` into a SweepWriteError naming it; the file
    `partial` (a temporary one being written) is removed then."""
    try:
        yield
    except OSError as e:
        if partial:
            with contextlib.suppress(OSError):
                partial.unlink(missing_ok=True)
        raise SweepWriteError(f"cannot write {path}: {e.strerror or e}") from None


class Case:
    """One variant: its parameters (dotted scenario key -> TOML value) and its folder."""

    def __init__(self, params, folder):
        self.params, self.folder = params, Path(folder)
        self.status = "pending"  # pending, running, ok, failed, interrupted
        self.summary = None      # run.json, once there is one
        self.message = ""

    @property
    def name(self):
        return self.folder.name

    def refresh(self):
        """Reads the case's run.json (if any) into status, summary and message."""
        path = self.folder / "run.json"
        try:
            self.summary = json.loads(path.read_text())
        except FileNotFoundError:
            self.status, self.summary = "pending", None
            return
        except (OSError, ValueError) as e:
            self.status, self.message = "failed", f"{path}: unreadable: {e}"
            return
        self.status = self.summary.get("status", "failed")
        self.message = self.summary.get("message", "")

    def set_arguments(self, overrides):
        """The case's `--set key=value` arguments: the sweep's fixed overrides, then its own."""
        values = {**overrides, **self.params}
        return [a for key, value in values.items() for a in ("--set", f"{key}={toml_value(value)}")]

    def next_command(self, tsubu, scenario, overrides, threads, retry_failed):
        """The command that brings the case forward, or None when there is nothing to do:
        a finished case, or a failed one without retry_failed."""
        self.refresh()
        run = [str(tsubu), "run", str(scenario), "--out", str(self.folder), "--threads", str(threads),
               *self.set_arguments(overrides)]
        if self.status == "ok" or (self.status == "failed" and not retry_failed):
            return None
        if self.status == "failed":
            return run + ["--overwrite"]
        if not (self.folder / ".tsubu-run").is_file():
            return run  # a new case (tsubu refuses a folder holding anything else)
        if any((self.folder / "checkpoint").glob("step_*.tsbk")):
            return [str(tsubu), "resume", str(self.folder), "--threads", str(threads)]
        return run + ["--overwrite"]  # killed before its first checkpoint: start again


def toml_value(value):
    """The TOML text of a value, as `tsubu --set key=VALUE` takes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return repr(value) if math.isfinite(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, str):
        return json.dumps(value)  # a JSON string of printable text is a TOML basic string
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"{value!r} ({type(value).__name__}) is not a value --set takes")


def _flatten(table, prefix=""):
    """{"particles": {"0": {"x": 1}}} and {"particles.0.x": 1} both give {"particles.0.x": 1}."""
    flat = {}
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict):
            flat.update(_flatten(value, path + "."))
        else:
            flat[path] = value
    return flat


def _folder_name(params, labels):
    """The folder of a case: label=value for each parameter, joined by commas."""
    def text(value):
        return re.sub(r"[^A-Za-z0-9._+-]", "_", toml_value(value).strip('"'))
    return ",".join(f"{labels[key]}={text(value)}" for key, value in params.items())


def _labels(keys):
    """Each dotted key's shortest trailing part that no other key ends with."""
    labels = {}
    for key in keys:
        parts = key.split(".")
        for n in range(1, len(parts) + 1):
            label = ".".join(parts[-n:])
            if not any(k != key and (k == label or k.endswith("." + label)) for k in keys):
                break
        labels[key] = label
    return labels


class Sweep:
    """A sweep file, checked: scenario, output root, jobs (None when not given), threads, ranks,
    fixed overrides, cases, Slurm settings."""

    KEYS = ("scenario", "output", "jobs", "threads", "ranks", "set", "grid", "cases", "slurm")

    def __init__(self, spec, file="<dict>", base=Path(".")):
        self.file = file

        def fail(key, what):
            raise SweepError(f"{file}: {key}: {what}")

        if not isinstance(spec, dict):
            fail("(top)", "a sweep is a table of keys")
        for key in spec:
            if key not in self.KEYS:
                fail(key, f"unknown key (allowed: {', '.join(self.KEYS)})")
        if not isinstance(spec.get("scenario"), str) or not spec["scenario"]:
            fail("scenario", "required: the path of the base scenario, relative to the sweep file")
        self.scenario = (base / spec["scenario"]).resolve()
        if not self.scenario.is_file():
            fail("scenario", f"no such file: {self.scenario}")
        output = spec.get("output", f"out/{Path(file).stem if file != '<dict>' else 'sweep'}")
        if not isinstance(output, str) or not output:
            fail("output", "must be a non-empty string: the folder that holds the cases' folders")
        self.output = Path(output)
        self.jobs = self._count(spec, "jobs", None, fail) if "jobs" in spec else None
        self.threads = self._count(spec, "threads", 1, fail)
        self.ranks = self._count(spec, "ranks", 1, fail)
        from .cluster import slurm_settings  # here: tsubu.cluster imports this module
        self.slurm = slurm_settings(spec.get("slurm", {}), fail)

        def table(key):
            value = spec.get(key, {})
            if not isinstance(value, dict):
                fail(key, "must be a table of scenario keys (e.g. \"simulation.dt\" = 1e-6)")
            return _flatten(value, key + ".")

        self.overrides = {k[len("set."):]: v for k, v in table("set").items()}
        grid = table("grid")
        for key, values in grid.items():
            if not isinstance(values, list) or not values:
                fail(key, "a grid parameter takes a non-empty array of values")
        cases = spec.get("cases", [])
        if not isinstance(cases, list) or not all(isinstance(c, dict) for c in cases):
            fail("cases", "must be an array of tables ([[cases]]), each a set of scenario keys and values")
        if not grid and not cases:
            fail("grid", "a sweep needs a [grid] and/or [[cases]]")
        listed = [_flatten(c) for c in cases] or [{}]
        for n, case in enumerate(listed):
            if cases and not case:
                fail(f"cases.{n}", "an empty case: give it at least one key")
            for key in case:
                if f"grid.{key}" in grid:
                    fail(f"cases.{n}.{key}", "also a grid parameter: give it in one of them")
        # Every explicit case at every point of the grid.
        points = [dict(zip((k[len("grid."):] for k in grid), values)) for values in itertools.product(*grid.values())]
        params = [{**point, **case} for case in listed for point in points]
        for p in params:
            for key, value in p.items():
                try:
                    toml_value(value)
                except TypeError as e:
                    fail(key, str(e))
        keys = list(dict.fromkeys(k for p in params for k in p))
        self.parameters = keys
        labels = _labels(keys)
        self.cases, seen = [], {}
        for p in params:
            name = _folder_name(p, labels)
            if name in seen:
                fail("cases", f"two cases give the folder {name!r}: {seen[name]} and {p}")
            seen[name] = p
            self.cases.append(Case(p, self.output / name))

    def command(self, case, tsubu, retry_failed, launcher):
        """The command that brings the case forward (Case.next_command), started by `launcher`
        with the sweep's ranks when it has more than one (e.g. ("mpirun", "-np")); or None."""
        command = case.next_command(tsubu, self.scenario, self.overrides, self.threads, retry_failed)
        return [*launcher, str(self.ranks), *command] if command and self.ranks > 1 else command

    @staticmethod
    def _count(spec, key, default, fail):
        value = spec.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            fail(key, f"must be an integer of at least 1, got {value!r}")
        return value


def _cores():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def load_sweep(sweep):
    """A Sweep from a file path or a dict (paths in a dict are relative to the working folder)."""
    if isinstance(sweep, dict):
        return Sweep(sweep)
    path = Path(sweep)
    try:
        with open(path, "rb") as f:
            spec = tomllib.load(f)
    except OSError as e:
        raise SweepError(f"{path}: cannot read: {e.strerror}") from None
    except tomllib.TOMLDecodeError as e:
        raise SweepError(f"{path}: not valid TOML: {e}") from None
    return Sweep(spec, str(path), path.parent)


def find_tsubu(tsubu=None):
    """The tsubu executable: the argument, else $TSUBU_BINARY (either must name an executable:
    SweepError otherwise), else `tsubu` on the PATH, else the build's tsubu: beside build/python
    when the package is imported from the build (as the set-up installs it), or the
    repository's build/tsubu when imported from python/."""
    for given, source in ((tsubu, "--tsubu"), (os.environ.get("TSUBU_BINARY"), "TSUBU_BINARY")):
        if given:
            found = shutil.which(given)
            if not found:
                raise SweepError(f"{source} {given}: names no executable file (nor a command on the PATH); "
                                 "give the path of tsubu, e.g. build/tsubu")
            return Path(found).resolve()
    here = Path(__file__).resolve().parents[2]
    candidates = [shutil.which("tsubu"), here / "tsubu", here / "build" / "tsubu"]
    for c in candidates:
        if c and Path(c).is_file() and os.access(c, os.X_OK):
            return Path(c).resolve()
    raise SweepError(f"tsubu: no executable found (tried {', '.join(str(c) for c in candidates if c)}); "
                     "give --tsubu PATH or set TSUBU_BINARY")


def _duration(seconds):
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    return f"{h}h{rest // 60:02d}m" if h else (f"{rest // 60}m{rest % 60:02d}s" if rest >= 60 else f"{rest}s")


class _Progress:
    """Progress lines on a stream: at every change, and every `interval` seconds otherwise."""

    def __init__(self, stream, total, interval=30.0):
        self.stream, self.total, self.interval = stream, total, interval
        self.start = self.last = time.monotonic()
        self.finished_here = 0  # cases this session ran to an end, for the rate

    def report(self, done, running, failed, force=True):
        now = time.monotonic()
        if not self.stream or (not force and now - self.last < self.interval):
            return
        self.last = now
        elapsed = now - self.start
        left = self.total - done - failed - running
        eta = "ETA ?"
        if self.finished_here:
            eta = f"ETA {_duration(elapsed / self.finished_here * (left + running))}"
        print(f"sweep: {done} done, {running} running, {left} left, {failed} failed; "
              f"elapsed {_duration(elapsed)}, {eta}", file=self.stream, flush=True)


def _holder_text():
    """Who holds a lock, as tsubu writes it: "pid 123 on host, since 2026-12-01T10:00:00Z"."""
    return f"pid {os.getpid()} on {socket.gethostname()}, since {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}"


def _lock_output(output):
    """Holds OUTPUT/.tsubu-sweep-lock (flock, released however the sweep ends) and returns its
    file; a folder another sweep holds raises SweepError naming the holder."""
    with _writing(output / SWEEP_LOCK):
        lock = open(output / SWEEP_LOCK, "a+")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        lock.seek(0)
        holder = lock.readline().strip() or "holder unknown"
        lock.close()
        raise SweepError(f"{output}: in use by another sweep ({holder}); wait for it to end or choose another "
                         "output folder") from None
    with _writing(output / SWEEP_LOCK):
        lock.seek(0)
        lock.truncate()
        lock.write(_holder_text() + "\n")
        lock.flush()
    return lock


def write_results(sweep, path):
    """results.csv: one row per case, parameters, status, timing and run.json's results;
    written to a temporary file renamed over it (removed when the write fails)."""
    result_keys = sorted({k for c in sweep.cases if c.summary for k in c.summary.get("results", {})})
    header = ["case", "status", "stop_reason", "wall_time_s", "steps", "particles", "particle_force_evaluations",
              *sweep.parameters, *result_keys, "message"]
    tmp = path.with_suffix(".csv.tmp")
    with _writing(path, partial=tmp), open(tmp, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(header)
        for c in sweep.cases:
            s = c.summary or {}
            results = s.get("results", {})
            row = [c.name, c.status, s.get("stop_reason", ""), s.get("wall_time_s", ""), s.get("steps", ""),
                   s.get("particles", ""), s.get("particle_force_evaluations", ""),
                   *(toml_value(c.params[k]).strip('"') if k in c.params else "" for k in sweep.parameters),
                   *(results.get(k, "") for k in result_keys), c.message]
            out.writerow(row)
        f.flush()
        os.fsync(f.fileno())
        os.replace(tmp, path)


def select_cases(cases, only):
    """The cases whose parameters match every "KEY=VALUE" of `only` (VALUE in TOML, as the
    sweep file writes it: particles.0.solid_fraction=0.1; a bare word that is not TOML is the
    string it spells, as typed at a shell: contact.default.friction_bound=spring); SweepError
    when none does, listing the values each key takes."""
    wanted = {}
    for item in only or ():
        key, sep, text = item.partition("=")
        try:
            wanted[key.strip()] = tomllib.loads(f"v = {text}")["v"] if sep else None
        except tomllib.TOMLDecodeError:
            wanted[key.strip()] = text.strip()  # matches a string value, or no case (an error below)
        if not sep:
            raise SweepError(f"--only {item}: expected KEY=VALUE, e.g. particles.0.solid_fraction=0.1")
    known = list(dict.fromkeys(k for c in cases for k in c.params))
    for key in wanted:
        if key not in known:
            raise SweepError(f"--only {key}: not a parameter of this sweep (its parameters: {', '.join(known)})")
    chosen = [c for c in cases if all(key in c.params and c.params[key] == v for key, v in wanted.items())]
    if wanted and not chosen:
        def values(key):
            return ", ".join(dict.fromkeys(toml_value(c.params[key]) for c in cases if key in c.params))
        raise SweepError(f"--only {' '.join(only)}: no case matches; "
                         + "; ".join(f"{key} takes {values(key)}" for key in wanted))
    return chosen


def run_sweep(sweep, jobs=None, dry_run=False, tsubu=None, retry_failed=False, progress=sys.stderr, only=None,
              engine="local", wait=True):
    """Runs the cases of `sweep` (a sweep file's path or a dict with its keys) that are not
    finished, of those `only` selects (see select_cases; all by default); returns the list of
    every Case (status "ok", "failed", "interrupted", or "pending" for a case not run; with
    wait=False "queued" or "running" for a case in Slurm's queue). A dry run prints each
    selected case's command and checks the scenario of each case to be run with `tsubu check`
    (a case it refuses is "failed"). engine: "local" (here, `jobs` at a time), "slurm" or
    "mpi" (tsubu.cluster; wait=False: Slurm's array job is submitted, not waited for). Raises
    SweepError for a bad sweep; KeyboardInterrupt after Ctrl-C or SIGTERM, and SweepWriteError
    when a file of the sweep cannot be written (a full disk), once the runs under way have
    stopped with a checkpoint."""
    sweep = load_sweep(sweep)
    chosen = select_cases(sweep.cases, only)
    if jobs is not None and (isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1):
        raise SweepError(f"--jobs: must be an integer of at least 1, got {jobs!r}")
    jobs = jobs or sweep.jobs
    if engine == "local" and wait:
        engine = _Local(jobs or _cores())
    else:
        from . import cluster
        engine = cluster.engine(engine, sweep, jobs, wait)
    tsubu = find_tsubu(tsubu)
    for c in sweep.cases:
        c.refresh()  # the cases --only leaves out keep their status in results.csv
    commands = [(c, sweep.command(c, tsubu, retry_failed, engine.launcher)) for c in chosen]
    work = [(case, command) for case, command in commands if command]
    if dry_run:
        for case, command in commands:
            print(f"{case.name}: {' '.join(map(_quote, command)) if command else f'skip ({case.status})'}")
            if command and command[command.index(str(tsubu)) + 1] == "run":
                _check(case, [str(tsubu), "check", str(sweep.scenario), *case.set_arguments(sweep.overrides)])
        print(f"{len(sweep.cases)} cases, {len(chosen)} selected, {len(work)} to run, {engine.at_a_time},"
              f" into {sweep.output}" if only else
              f"{len(sweep.cases)} cases, {len(work)} to run, {engine.at_a_time}, into {sweep.output}")
        engine.dry_run(sweep, work)
        return sweep.cases
    engine.check()
    with _writing(sweep.output):
        sweep.output.mkdir(parents=True, exist_ok=True)
    lock = _lock_output(sweep.output)
    try:
        return engine.run(sweep, chosen, work, tsubu, retry_failed, progress)
    finally:
        lock.close()


class _Local:
    """The local engine: `jobs` runs at a time, started here (_run_cases)."""

    launcher = ("mpirun", "-np")  # a case of several ranks (an MPI build of tsubu)

    def __init__(self, jobs):
        self.jobs, self.at_a_time = jobs, f"{jobs} at a time"

    def check(self):
        pass

    def dry_run(self, sweep, work):
        pass

    def run(self, sweep, chosen, work, tsubu, retry_failed, progress):
        return _run_cases(sweep, chosen, work, self.jobs, tsubu, retry_failed, progress)


def start_results(sweep):
    """Makes OUTPUT/logs and writes results.csv as the cases stand; returns both paths."""
    logs = sweep.output / "logs"
    with _writing(logs):
        logs.mkdir(exist_ok=True)
    results = sweep.output / "results.csv"
    write_results(sweep, results)
    return logs, results


def start_run(command, log_path):
    """Starts a case's command: "$ COMMAND" and then its output appended to its log, no input,
    in a session of its own (a Ctrl-C at the terminal reaches only the sweep, which then asks
    each run once to stop: a second signal would stop a run at once). Returns the process and
    the open log."""
    with _writing(log_path):
        log = open(log_path, "a")
        print(f"$ {' '.join(map(_quote, command))}", file=log, flush=True)
    proc = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                            start_new_session=True, env=_own_job_environment())
    return proc, log


def _own_job_environment():
    """The environment of a case's command: the sweep's, without the variables that place a
    process in an MPI job (a worker of an MPI pool has them), since each case is a job of its
    own: tsubu would take itself for one of the pool's processes, an mpirun for a nested one."""
    mpi_job = ("OMPI_COMM_WORLD_", "OMPI_UNIVERSE_SIZE", "PMI_", "PMIX_")
    return {k: v for k, v in os.environ.items() if not k.startswith(mpi_job)}


def record_end(case, returncode, log_path, progress):
    """Sets the status and message of a case whose run ended with `returncode`, from its run.json
    and log, and names it on `progress` unless it is ok. Returns who holds the case's folder when
    another tsubu did (the run did nothing then), else None."""
    if returncode == 2 and "is in use by another tsubu" in _last_line(log_path):
        return lock_holder(case.folder) or "holder unknown"
    case.refresh()
    # tsubu records its own failures (exit 3, 5) in run.json; others (bad input, a resume
    # without a valid checkpoint) leave none, or the one of the session before.
    if case.summary is None or (returncode not in (0, INTERRUPTED) and case.status != "failed"):
        case.status = "failed"
        case.message = f"tsubu exited with code {returncode}: {_last_line(log_path)}"
    if case.status != "ok" and progress:
        print(f"sweep: {case.name}: {case.status}: {case.message} (log: {log_path})", file=progress, flush=True)
    return None


def _run_cases(sweep, chosen, work, jobs, tsubu, retry_failed, progress):
    """The local engine's work, with the output folder locked."""
    logs, results = start_results(sweep)
    report = _Progress(progress, len(chosen))
    running = {}  # Popen -> (case, log path, log file)
    waiting = []  # cases whose folder another tsubu holds: brought forward once it ends
    asked = set()  # runs asked to stop: a second SIGINT would end one without its checkpoint

    def ask_runs_to_stop():
        for proc in running:
            if proc not in asked:
                proc.send_signal(signal.SIGINT)
                asked.add(proc)

    def wait_for_holder(case, holder):
        case.status, case.message = "running", f"running in another tsubu ({holder}); waiting for it to end"
        waiting.append(case)
        if progress:
            print(f"sweep: {case.name}: {case.message}", file=progress, flush=True)

    def counts():
        return (sum(c.status == "ok" for c in chosen), len(running), sum(c.status == "failed" for c in chosen))

    def finish(proc):
        case, log_path, log = running.pop(proc)
        log.close()
        holder = record_end(case, proc.returncode, log_path, progress)
        if holder:
            wait_for_holder(case, holder)  # it started just before
            return
        report.finished_here += 1
        write_results(sweep, results)
        report.report(*counts())

    stop = []  # set by SIGINT or SIGTERM: the loop then stops the runs and returns
    handlers = {}
    if threading.current_thread() is threading.main_thread():
        handlers = {sig: signal.signal(sig, lambda signum, frame: stop.append(signum))
                    for sig in (signal.SIGINT, signal.SIGTERM)}
    queue = list(reversed(work))
    started = False
    try:
        while (queue or running or waiting) and not stop:
            for case in [c for c in waiting if not lock_holder(c.folder)]:
                waiting.remove(case)
                command = sweep.command(case, tsubu, retry_failed, _Local.launcher)
                if command:
                    queue.append((case, command))
                else:  # the other tsubu finished it (or it failed there)
                    write_results(sweep, results)
                    report.report(*counts())
            while queue and len(running) < jobs and not stop:
                case, command = queue.pop()
                holder = lock_holder(case.folder)
                if holder:
                    wait_for_holder(case, holder)
                    continue
                log_path = logs / f"{case.name}.log"
                proc, log = start_run(command, log_path)
                case.status = "running"
                running[proc] = (case, log_path, log)
            if not started:
                started = True
                report.report(*counts())
            time.sleep(0.1)
            for proc in [p for p in running if p.poll() is not None]:
                finish(proc)
            report.report(*counts(), force=False)
        if stop:
            if progress:
                print(f"sweep: interrupted: asking {len(running)} runs to stop with a checkpoint", file=progress,
                      flush=True)
            ask_runs_to_stop()
            for sig, handler in handlers.items():  # a second Ctrl-C stops the sweep at once
                signal.signal(sig, handler)
            for proc in list(running):
                proc.wait()
                finish(proc)
            raise KeyboardInterrupt
    except SweepWriteError as e:
        # Nothing more can be recorded: the runs stop with a checkpoint, to be resumed by the
        # same command once the disk has room.
        stopped = len(running)
        ask_runs_to_stop()
        for proc, (_, _, log) in list(running.items()):
            proc.wait()
            with contextlib.suppress(OSError):
                log.close()
        running.clear()
        raise SweepWriteError(f"{e}" + (f"; {stopped} run{'s' if stopped > 1 else ''} under way stopped, keeping "
                                        "the newest checkpoint" if stopped else "")) from None
    finally:
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
    return sweep.cases


def _check(case, check):
    """Runs `tsubu check` for a case; a refusal fails the case with tsubu's message."""
    done = subprocess.run(check, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines()
        case.status, case.message = "failed", lines[-1] if lines else f"tsubu check exited with code {done.returncode}"
        print(f"  refused by tsubu check: {case.message}")


def _last_line(path):
    lines = [line for line in Path(path).read_text(errors="replace").splitlines() if line.strip()]
    return lines[-1].strip() if lines else "(no output)"


def _quote(arg):
    return arg if re.fullmatch(r"[A-Za-z0-9_./=+:,-]+", arg) else "'" + arg.replace("'", "'\\''") + "'"


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m tsubu.sweep", description=__doc__.split("\n\n")[0])
    parser.add_argument("sweep", help="the sweep file (TOML, docs/sweeps.md)")
    parser.add_argument("--jobs", type=int, help="runs at a time (default: the file's jobs, else the cores)")
    parser.add_argument("--dry-run", action="store_true", help="print what each case would run, run nothing")
    parser.add_argument("--retry-failed", action="store_true", help="run failed cases again from the start")
    parser.add_argument("--tsubu", help="the tsubu executable (default: $TSUBU_BINARY, tsubu on the PATH, build/tsubu)")
    parser.add_argument("--only", action="append", metavar="KEY=VALUE",
                        help="run only the cases with this parameter value (repeatable; VALUE in TOML)")
    parser.add_argument("--engine", choices=("local", "slurm", "mpi"), default="local",
                        help="who runs the cases: this process (default), a Slurm array job, or the workers of an "
                             "MPI pool (mpirun -np K python3 -m mpi4py.futures -m tsubu.sweep ... --engine mpi)")
    parser.add_argument("--no-wait", action="store_true",
                        help="with --engine slurm: submit the array job and return; re-running collects")
    args = parser.parse_args(argv)
    try:
        cases = run_sweep(args.sweep, jobs=args.jobs, dry_run=args.dry_run, tsubu=args.tsubu,
                          retry_failed=args.retry_failed, only=args.only, engine=args.engine, wait=not args.no_wait)
    except SweepError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("sweep: stopped; run the same command again to continue", file=sys.stderr)
        return INTERRUPTED
    except SweepWriteError as e:
        print(f"error: {e}; make room, then run the same command again to continue", file=sys.stderr)
        return WRITE_FAILED
    cases = select_cases(cases, args.only)
    queued = [c.name for c in cases if args.no_wait and c.status in ("queued", "running")]
    failed = [c.name for c in cases if c.status != "ok" and c.name not in queued]
    if args.dry_run:
        failed = [c.name for c in cases if c.status == "failed"]
        return 1 if failed else 0
    print(f"sweep: {len(cases) - len(failed) - len(queued)} of {len(cases)} cases finished"
          + (f"; {len(queued)} in Slurm's queue: run the same command again to collect them" if queued else "")
          + (f"; not finished: {', '.join(failed)}" if failed else ""), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    # As the module tsubu.sweep, not this copy run as __main__: tsubu.cluster raises that
    # module's SweepError, which main must catch.
    from tsubu.sweep import main as _main
    sys.exit(_main())
