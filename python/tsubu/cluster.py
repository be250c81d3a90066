"""The engines of a cluster for tsubu.sweep (`--engine slurm`, `--engine mpi`; docs/sweeps.md).

The sweep chooses the cases and their commands as it does locally (tsubu.sweep.run_sweep);
an engine here runs them elsewhere and collects how they ended into OUTPUT/results.csv:

- Slurm: the cases to run become one array job (OUTPUT/slurm/array.sh, one task a case, at
  most `jobs` at a time), submitted with sbatch and followed with squeue until it has ended.
  Each task runs its case's command as the local runner would, its output appended to the
  case's log, and writes its exit code to OUTPUT/slurm/CASE.exit. `#SBATCH --signal` asks each
  run to stop with a checkpoint before the time limit; the next run of the sweep resumes it.
- MPI: `mpirun -np K python3 -m mpi4py.futures -m tsubu.sweep SWEEP.toml --engine mpi`: rank 0
  is the sweep, the K - 1 others are the pool's workers, each running one case at a time.
"""
import json
import re
import shutil
import signal
import subprocess
import sys
import threading
from collections import namedtuple
from concurrent.futures import FIRST_COMPLETED, wait
from pathlib import Path

from .sweep import (SweepError, _Progress, _quote, _writing, record_end, start_results, start_run,
                    write_results)

__all__ = ["SlurmSettings", "slurm_settings", "engine", "Slurm", "MpiPool", "run_case"]

SlurmSettings = namedtuple("SlurmSettings", "partition time stop_before sbatch")
SLURM_KEYS = SlurmSettings._fields
# Slurm's time formats: minutes, minutes:seconds, hours:minutes:seconds, days-hours,
# days-hours:minutes, days-hours:minutes:seconds.
SLURM_TIME = re.compile(r"\d+(:\d+){0,2}|\d+-\d+(:\d+){0,2}")


def slurm_settings(table, fail):
    """The [slurm] table of a sweep file, checked (`fail(key, what)` for a bad value)."""
    if not isinstance(table, dict):
        fail("slurm", f"must be a table ([slurm]) of {', '.join(SLURM_KEYS)}")
    for key in table:
        if key not in SLURM_KEYS:
            fail(f"slurm.{key}", f"unknown key (allowed: {', '.join(SLURM_KEYS)})")
    partition = table.get("partition")
    if partition is not None and not (isinstance(partition, str) and re.fullmatch(r"[\w.-]+(,[\w.-]+)*", partition)):
        fail("slurm.partition", f"must be the name of a partition (or names joined by commas), got {partition!r}")
    time = table.get("time")
    if isinstance(time, int) and not isinstance(time, bool) and time >= 1:
        time = str(time)
    if time is not None and not (isinstance(time, str) and SLURM_TIME.fullmatch(time)):
        fail("slurm.time", "the time limit of each case: minutes (an integer of at least 1) or a string as Slurm "
             f'writes it ("MM:SS", "HH:MM:SS", "D-HH", "D-HH:MM:SS"), got {time!r}')
    stop_before = table.get("stop_before", 120)
    if isinstance(stop_before, bool) or not isinstance(stop_before, int) or not 1 <= stop_before <= 65535:
        fail("slurm.stop_before", "the seconds before the time limit at which each run is asked to stop with a "
             f"checkpoint: an integer from 1 to 65535, got {stop_before!r}")
    sbatch = table.get("sbatch", [])
    if not isinstance(sbatch, list) or not all(isinstance(o, str) and re.fullmatch(r"-[^\n]+", o) for o in sbatch):
        fail("slurm.sbatch", "more #SBATCH lines: an array of sbatch options, each on one line, e.g. "
             f'["--account=geo", "--mem-per-cpu=2G"], got {sbatch!r}')
    return SlurmSettings(partition, time, stop_before, sbatch)


def engine(name, sweep, jobs, wait):
    """The engine `name` of run_sweep: "slurm" or "mpi" (wait=False for Slurm only)."""
    if not wait and name != "slurm":
        raise SweepError(f"--no-wait: only with --engine slurm (the {name} engine waits for its cases)")
    if name == "slurm":
        return Slurm(sweep.slurm, sweep.output / "slurm", jobs, wait)
    if name == "mpi":
        return MpiPool()
    raise SweepError(f"--engine {name}: unknown (allowed: local, slurm, mpi)")


def _ended(sweep, case, code, progress, report):
    """A case's run ended elsewhere with exit code `code`: its status (record_end), results.csv."""
    holder = record_end(case, code, sweep.output / "logs" / f"{case.name}.log", progress)
    if holder:  # another tsubu held the folder: the case is not the engine's
        case.status, case.message = "running", f"running in another tsubu ({holder})"
    report.finished_here += 1
    write_results(sweep, sweep.output / "results.csv")


def _counts(chosen):
    return tuple(sum(c.status == s for c in chosen) for s in ("ok", "running", "failed"))


class Slurm:
    """The cases to run as one Slurm array job (see the module's text). OUTPUT/slurm/array.json
    names the job and its cases from its submission until the sweep has collected it."""

    launcher = ("srun", "-n")  # a case of several ranks (an MPI build of tsubu)

    def __init__(self, settings, folder, jobs, wait):
        self.settings, self.folder, self.jobs, self.wait = settings, folder, jobs, wait
        self.at_a_time = f"{jobs} at a time" if jobs else "as many at a time as Slurm gives"

    def script(self, sweep, work):
        """The array job's script: task i runs the i-th command of `work` in the sweep's working
        folder, as the local runner does."""
        s = self.settings
        options = [f"--job-name=tsubu-{sweep.output.name}",
                   f"--array=0-{len(work) - 1}" + (f"%{self.jobs}" if self.jobs else ""),
                   f"--chdir={Path.cwd()}", f"--output={self.folder}/slurm.out", "--open-mode=append",
                   f"--cpus-per-task={sweep.threads}", *([f"--ntasks={sweep.ranks}"] if sweep.ranks > 1 else []),
                   *([f"--partition={s.partition}"] if s.partition else []), *([f"--time={s.time}"] if s.time else []),
                   f"--signal=B:USR1@{s.stop_before}", *s.sbatch]
        cases = [f"  {i}) name={_quote(case.name)}; run=({' '.join(map(_quote, command))}) ;;"
                 for i, (case, command) in enumerate(work)]
        return "\n".join([
            "#!/bin/bash",
            f"# The cases of {sweep.file} to run, as a Slurm array job: written by python3 -m tsubu.sweep",
            "# --engine slurm, which collects the outcome (docs/sweeps.md). Task i runs case i as the local",
            "# runner does, its output appended to the case's log, and writes the exit code to slurm/CASE.exit.",
            *(f"#SBATCH {option}" for option in options),
            "",
            "case $SLURM_ARRAY_TASK_ID in", *cases, "esac",
            f"log={_quote(str(sweep.output / 'logs'))}/$name.log",
            "printf '$ %s\\n' \"${run[*]}\" >> \"$log\"",
            "trap : TERM                  # scancel and the time limit send SIGTERM to the run too: wait for it",
            "\"${run[@]}\" >> \"$log\" 2>&1 < /dev/null &",
            "pid=$!",
            "trap '' TERM                 # ignored from here (the run started with the default): a caught one",
            "                             # would end the wait below, and bash loses the code of a run that ends then",
            "trap 'kill -TERM $pid' USR1  # --signal: the time limit is near: the run stops with a checkpoint",
            "while wait $pid; kill -0 $pid 2> /dev/null; do :; done  # USR1's trap ends a wait early",
            "wait $pid; code=$?           # the run's own exit code: bash keeps it once the run has ended",
            f"echo $code > {_quote(str(self.folder))}/\"$name.exit\"", ""])

    def dry_run(self, sweep, work):
        if work:
            print(f"the array job ({self.folder / 'array.sh'}):\n{self.script(sweep, work)}", end="")

    def check(self):
        for command in ("sbatch", "squeue", "scancel"):
            if not shutil.which(command):
                raise SweepError(f"--engine slurm: {command}: not found on the PATH (Slurm's commands are needed "
                                 "where the sweep runs)")

    def run(self, sweep, chosen, work, tsubu, retry_failed, progress):
        """Collects the array job submitted before when there is one, else submits one for `work`;
        waits for it to end unless wait is False."""
        start_results(sweep)
        state = self.folder / "array.json"
        if state.is_file():
            try:
                array = json.loads(state.read_text())
            except (OSError, ValueError) as e:
                raise SweepError(f"{state}: unreadable ({e}); remove it once its array job has left Slurm's queue")
            if progress:
                print(f"sweep: collecting array job {array['job']}, submitted before", file=progress, flush=True)
        elif work:
            array = self._submit(sweep, work, state)
            if progress:
                print(f"sweep: submitted array job {array['job']}: {len(work)} cases, {self.at_a_time}",
                      file=progress, flush=True)
        else:
            return sweep.cases
        self._follow(sweep, chosen, array, state, progress)
        return sweep.cases

    def _submit(self, sweep, work, state):
        with _writing(self.folder):
            self.folder.mkdir(exist_ok=True)
            for old in self.folder.glob("*.exit"):
                old.unlink()
        script = self.folder / "array.sh"
        with _writing(script):
            script.write_text(self.script(sweep, work))
        done = subprocess.run(["sbatch", "--parsable", str(script)], capture_output=True, text=True)
        if done.returncode != 0:
            lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
            raise SweepError(f"{script}: sbatch refused the array job: {lines[-1]}")
        array = {"job": done.stdout.strip().split(";")[0], "cases": [case.name for case, _ in work]}
        with _writing(state):
            state.write_text(json.dumps(array) + "\n")
        return array

    def _follow(self, sweep, chosen, array, state, progress):
        """Follows the array job until it has ended (once when not waiting): the statuses of its
        cases, results.csv and progress lines. Ctrl-C or SIGTERM cancels the job (its runs stop
        with a checkpoint), waits for it to end and raises KeyboardInterrupt."""
        cases = {c.name: c for c in sweep.cases}
        array_cases = [cases.get(name) for name in array["cases"]]  # None: no longer a case of the sweep
        report, ended, interval = _Progress(progress, len(chosen)), set(), 1.0
        stop, handlers, cancelled = threading.Event(), {}, False
        if self.wait and threading.current_thread() is threading.main_thread():
            handlers = {sig: signal.signal(sig, lambda signum, frame: stop.set()) for sig in (signal.SIGINT, signal.SIGTERM)}
        try:
            while True:
                queue = _queue(array["job"])  # before the exit codes: a task that leaves it has written its own
                for i, case in enumerate(array_cases):
                    if case is None or case.name in ended:
                        continue
                    code = _exit_code(self.folder / f"{case.name}.exit")
                    if code is not None:
                        ended.add(case.name)
                        _ended(sweep, case, code, progress, report)
                    elif i not in queue:  # out of the queue without an exit code: killed, or cancelled before it began
                        ended.add(case.name)
                        case.refresh()
                    else:
                        case.status = "queued" if queue[i] == "PENDING" else "running"
                write_results(sweep, sweep.output / "results.csv")
                report.report(*_counts(chosen), force=False)
                if not queue or not self.wait:
                    break
                if stop.wait(interval) and not cancelled:
                    cancelled = True
                    if progress:
                        print(f"sweep: interrupted: cancelling array job {array['job']}; its runs stop with a checkpoint",
                              file=progress, flush=True)
                    for sig, handler in handlers.items():  # a second Ctrl-C stops the sweep at once
                        signal.signal(sig, handler)
                    subprocess.run(["scancel", array["job"]], check=False)
                    stop.clear()
                    interval = 0.0
                interval = min(interval + 1.0, 30.0)  # 1 s, 2 s, ... between squeue calls, then every 30 s
        finally:
            for sig, handler in handlers.items():
                signal.signal(sig, handler)
        report.report(*_counts(chosen))
        if not queue:  # collected: the next run of the sweep submits what is left
            with _writing(state):
                for name in ended:
                    (self.folder / f"{name}.exit").unlink(missing_ok=True)
                state.unlink()
        if cancelled:
            raise KeyboardInterrupt


def _exit_code(path):
    """The exit code a task wrote, or None (none yet)."""
    try:
        return int(path.read_text())
    except (FileNotFoundError, ValueError):
        return None


def _queue(job):
    """The tasks of array job `job` still in Slurm's queue: {task index: state}."""
    done = subprocess.run(["squeue", "--noheader", "--array", "--jobs", job, "--format", "%K %T"],
                          capture_output=True, text=True)
    if done.returncode != 0:
        if "Invalid job id" in done.stderr:  # ended long ago: Slurm no longer knows it
            return {}
        raise SweepError(f"squeue: {done.stderr.strip() or f'exit code {done.returncode}'}")
    return {int(index): state for index, state in (line.split() for line in done.stdout.splitlines() if line.strip())}


class MpiPool:
    """The workers of an MPI pool (mpi4py.futures), each running one case at a time."""

    launcher = ("mpirun", "-np")
    at_a_time = "one on each worker of the MPI pool"

    def check(self):
        if "mpi4py.futures" not in sys.modules:  # imported by python3 -m mpi4py.futures
            raise SweepError("--engine mpi: not in an MPI pool: run mpirun -np K python3 -m mpi4py.futures -m "
                             "tsubu.sweep SWEEP.toml --engine mpi (K - 1 workers; mpi4py: Debian's python3-mpi4py)")
        from mpi4py import MPI
        if MPI.COMM_WORLD.Get_size() < 2:
            raise SweepError("--engine mpi: an MPI pool without workers: give mpirun -np 2 or more")

    def dry_run(self, sweep, work):
        pass

    def run(self, sweep, chosen, work, tsubu, retry_failed, progress):
        from mpi4py.futures import MPIPoolExecutor
        logs, _ = start_results(sweep)
        report = _Progress(progress, len(chosen))
        with MPIPoolExecutor() as pool:
            futures = {pool.submit(run_case, command, str(logs / f"{case.name}.log")): case for case, command in work}
            pending = set(futures)
            while pending:
                done, pending = wait(pending, timeout=1.0, return_when=FIRST_COMPLETED)
                for future in pending:
                    if future.running():
                        futures[future].status = "running"
                for future in done:
                    _ended(sweep, futures[future], future.result(), progress, report)
                report.report(*_counts(chosen), force=bool(done))
        return sweep.cases


def run_case(command, log_path):
    """The task of an MPI pool's worker: runs a case's command as the local runner does and
    returns its exit code. SIGINT or SIGTERM to the worker (mpirun passes a Ctrl-C on to every
    rank as SIGTERM) asks the run once to stop with a checkpoint, which it writes on its own
    should mpirun end the worker first."""
    handlers, run = {}, {"proc": None, "asked": False}

    def ask_to_stop(signum, frame):
        for sig in handlers:  # once: a second signal would stop the run at once
            signal.signal(sig, signal.SIG_IGN)
        if run["proc"] is None:
            run["asked"] = True
        else:
            run["proc"].send_signal(signal.SIGINT)

    # The handlers first: a signal that arrives while the run starts is passed on once it has
    # (a Python handler runs between two bytecodes: before the run is recorded, or after).
    for sig in (signal.SIGINT, signal.SIGTERM):
        handlers[sig] = signal.signal(sig, ask_to_stop)
    proc, log = start_run(command, Path(log_path))
    run["proc"] = proc
    if run["asked"]:
        proc.send_signal(signal.SIGINT)
    try:
        return proc.wait()
    finally:
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
        log.close()
