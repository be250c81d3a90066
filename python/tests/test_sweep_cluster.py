"""tsubu.sweep's engines of a cluster (tsubu.cluster): the Slurm array job's script as text and
run by bash as Slurm runs it, bad [slurm] tables; a real single-node Slurm started here (root
and Debian's slurm-wlm: a grid, then a case stopped by its time limit, resubmitted without
waiting and cancelled by Ctrl-C); an MPI pool (mpirun and mpi4py: a grid, a Ctrl-C and the
resume). Skipped parts say why. About a minute and a half in all."""
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from test_sweep import CASES, ENV, SCENARIO, TSUBU, results, same_outputs, sweep, wait_for, write_sweep
from tsubu.runs import lock_holder
from tsubu.sweep import SweepError, load_sweep

ONE = {"particles.0.solid_fraction": [0.1], "simulation.seed": [3]}  # CASES[0]


def sweep_in(env, cwd, *args):
    """`python3 -m tsubu.sweep ARGS` in the environment `env` and the folder `cwd`."""
    return subprocess.run([sys.executable, "-m", "tsubu.sweep", *map(str, args)], env=env, cwd=cwd,
                          capture_output=True, text=True)


def run_pid(case):
    """The pid of the tsubu that holds the case's folder (tsubu.runs.lock_holder), else None."""
    holder = lock_holder(case)
    return int(re.match(r"pid (\d+)", holder).group(1)) if holder else None


def slurm_table(file, **settings):
    """Appends a [slurm] table to a sweep file."""
    file.write_text(file.read_text() + "[slurm]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in settings.items()))
    return file


def array_script(file, cwd):
    """The array job's script that `--engine slurm --dry-run` prints."""
    done = sweep(file, "--engine", "slurm", "--dry-run", cwd=cwd)
    assert done.returncode == 0, done.stderr
    return done.stdout.split("):\n", 1)[1]


def test_a_case_is_a_job_of_its_own(tmp_path, monkeypatch):
    """A worker of an MPI pool carries the variables of its place in the pool's job; a case's
    command must not (tsubu would refuse to run as one of several processes)."""
    from tsubu.sweep import start_run
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "3")
    monkeypatch.setenv("PMIX_RANK", "1")
    monkeypatch.setenv("OMPI_MCA_btl", "self")
    proc, log = start_run(["env"], tmp_path / "log")
    assert proc.wait() == 0
    log.close()
    seen = (tmp_path / "log").read_text()
    assert "OMPI_COMM_WORLD_SIZE" not in seen and "PMIX_RANK" not in seen
    assert "OMPI_MCA_btl=self" in seen  # a setting of the user's stays


def test_the_array_script(tmp_path):
    """Every #SBATCH line from the sweep file, a case line per case, multi-rank cases by srun."""
    file = slurm_table(write_sweep(tmp_path / "s.toml", tmp_path / "out", jobs=2, threads=2, ranks=3),
                       partition="short", time="1:30:00", stop_before=300, sbatch=["--account=geo", "--mem=2G"])
    script = array_script(file, cwd=tmp_path)
    assert re.findall(r"^#SBATCH (.*)$", script, re.M) == [
        "--job-name=tsubu-out", "--array=0-3%2", f"--chdir={tmp_path}", f"--output={tmp_path}/out/slurm/slurm.out",
        "--open-mode=append", "--cpus-per-task=2", "--ntasks=3", "--partition=short", "--time=1:30:00",
        "--signal=B:USR1@300", "--account=geo", "--mem=2G"]
    assert script.startswith("#!/bin/bash\n") and "case $SLURM_ARRAY_TASK_ID in\n" in script
    for i, name in enumerate(CASES):
        phi, seed = re.match(r"solid_fraction=(.*),seed=(.*)", name).groups()
        assert (f"  {i}) name={name}; run=(srun -n 3 {TSUBU} run {SCENARIO} --out {tmp_path}/out/{name} --threads 2 "
                f"--set simulation.duration=0.4 --set particles.0.solid_fraction={phi} --set simulation.seed={seed}) ;;\n"
                in script)
    assert f"\nlog={tmp_path}/out/logs/$name.log\n" in script
    assert f'\necho $code > {tmp_path}/out/slurm/"$name.exit"\n' in script
    # Without jobs nor [slurm]: no throttle, no time limit, the default warning; one rank runs tsubu itself.
    script = array_script(write_sweep(tmp_path / "t.toml", tmp_path / "t", grid=ONE), cwd=tmp_path)
    assert re.findall(r"^#SBATCH (.*)$", script, re.M) == [
        "--job-name=tsubu-t", "--array=0-0", f"--chdir={tmp_path}", f"--output={tmp_path}/t/slurm/slurm.out",
        "--open-mode=append", "--cpus-per-task=1", "--signal=B:USR1@120"]
    assert f"  0) name={CASES[0]}; run=({TSUBU} run {SCENARIO} --out {tmp_path}/t/{CASES[0]} --threads 1 " in script
    # The local runner and the MPI pool start a multi-rank case with mpirun.
    done = sweep(write_sweep(tmp_path / "r.toml", tmp_path / "r", grid=ONE, ranks=2), "--dry-run")
    assert done.returncode == 0 and f"{CASES[0]}: mpirun -np 2 {TSUBU} run {SCENARIO}" in done.stdout


def test_the_array_script_keeps_the_code_of_a_run_that_ends_as_the_shell_is_signalled(tmp_path):
    """SIGTERM reaches the shell as its run ends (scancel, the time limit): the exit file holds
    the run's code. A wait that the signal ended early once made the script record 143 (bash
    returns that for the interrupted wait and loses the code of a run that ends then: about
    one time in four with a run that signals its shell and exits at once)."""
    fake = tmp_path / "fake-tsubu"
    fake.write_text("#!/bin/bash\nkill -TERM $PPID\nexit 4\n")
    fake.chmod(0o755)
    out = tmp_path / "out"
    (out / "logs").mkdir(parents=True)
    (out / "slurm").mkdir()
    (tmp_path / "array.sh").write_text(array_script(write_sweep(tmp_path / "s.toml", out, grid=ONE), cwd=tmp_path)
                                       .replace(str(TSUBU), str(fake)))
    codes = []
    for _ in range(20):
        subprocess.run(["bash", "array.sh"], cwd=tmp_path, env={**ENV, "SLURM_ARRAY_TASK_ID": "0"}, check=True)
        codes.append((out / "slurm" / f"{CASES[0]}.exit").read_text())
    assert codes == ["4\n"] * 20


def test_the_array_script_runs_a_case_and_passes_on_the_signals(tmp_path):
    """Run by bash as Slurm would (task 0): the case's log and exit code as the local runner
    writes them. --signal's USR1 to the shell asks the run to stop with a checkpoint (exit 4);
    SIGTERM to the shell and to the run at once (scancel, the time limit) stops the run once,
    with a checkpoint, and the shell waits for it."""
    out = tmp_path / "out"
    case, log, code = out / CASES[0], out / "logs" / f"{CASES[0]}.log", out / "slurm" / f"{CASES[0]}.exit"
    (out / "logs").mkdir(parents=True)
    (out / "slurm").mkdir()

    def task(file):
        (tmp_path / "array.sh").write_text(array_script(file, cwd=tmp_path))
        return subprocess.Popen(["bash", "array.sh"], cwd=tmp_path, env={**ENV, "SLURM_ARRAY_TASK_ID": "0"})

    assert task(write_sweep(tmp_path / "s.toml", out, grid=ONE)).wait(timeout=120) == 0
    assert code.read_text() == "0\n" and json.loads((case / "run.json").read_text())["status"] == "ok"
    assert log.read_text().startswith(f"$ {TSUBU} run {SCENARIO} --out {case} --threads 1 --set simulation.duration=0.4 ")

    shutil.rmtree(case)
    file = write_sweep(tmp_path / "s.toml", out, grid=ONE, set={"simulation.duration": 60.0})
    shell = task(file)
    wait_for(lambda: (case / "frames" / "frame_00001.vtu").exists(), "frame 1")
    shell.send_signal(signal.SIGUSR1)
    assert shell.wait(timeout=120) == 0 and code.read_text() == "4\n"
    stopped = json.loads((case / "run.json").read_text())
    assert stopped["status"] == "interrupted" and stopped["message"].startswith("stopped by SIGTERM")

    started = time.time()
    shell = task(file)  # now a resume; signalled once its loop runs (a frame written since)
    wait_for(lambda: "tsubu: resuming" in log.read_text() and run_pid(case)
             and any(f.stat().st_mtime > started for f in (case / "frames").glob("frame_*.vtu")), "the resume's frame")
    run = run_pid(case)
    shell.send_signal(signal.SIGTERM)
    os.kill(run, signal.SIGTERM)
    assert shell.wait(timeout=120) == 0 and code.read_text() == "4\n"
    again = json.loads((case / "run.json").read_text())
    assert again["status"] == "interrupted" and again["steps"] > stopped["steps"]
    assert f"$ {TSUBU} resume {case} --threads 1\n" in log.read_text()


@pytest.mark.parametrize("table, message", [
    ('partition = ["a"]', r"slurm.partition: must be the name of a partition"),
    ('time = "2 hours"', r"slurm.time: the time limit of each case: minutes .* got '2 hours'"),
    ("time = 0", r"slurm.time: the time limit of each case"),
    ("stop_before = 0", r"slurm.stop_before: .* an integer from 1 to 65535, got 0"),
    ('sbatch = "--mem=2G"', r"slurm.sbatch: more #SBATCH lines: an array of sbatch options"),
    ('sbatch = ["mem=2G"]', r"slurm.sbatch: more #SBATCH lines"),
    ("nodes = 2", r"slurm.nodes: unknown key \(allowed: partition, time, stop_before, sbatch\)"),
])
def test_bad_slurm_tables(tmp_path, table, message):
    file = write_sweep(tmp_path / "s.toml", tmp_path / "out", grid=ONE)
    file.write_text(file.read_text() + f"[slurm]\n{table}\n")
    with pytest.raises(SweepError, match=rf"^{re.escape(str(file))}: {message}"):
        load_sweep(file)


def test_engine_mistakes_exit_2(tmp_path):
    file = write_sweep(tmp_path / "s.toml", tmp_path / "out", grid=ONE)
    file.write_text("ranks = 0\n" + file.read_text())
    done = sweep(file, "--dry-run")
    assert done.returncode == 2 and done.stderr == f"error: {file}: ranks: must be an integer of at least 1, got 0\n"
    file = write_sweep(tmp_path / "s.toml", tmp_path / "out", grid=ONE)
    done = sweep(file, "--no-wait")
    assert done.returncode == 2 and done.stderr == (
        "error: --no-wait: only with --engine slurm (the local engine waits for its cases)\n")
    done = sweep(file, "--engine", "mpi")
    assert done.returncode == 2 and done.stderr.startswith("error: --engine mpi: not in an MPI pool: run mpirun -np K")
    done = sweep_in({**ENV, "PATH": "/nowhere"}, tmp_path, file, "--engine", "slurm")
    assert done.returncode == 2 and done.stderr.startswith("error: --engine slurm: sbatch: not found on the PATH")
    assert not (tmp_path / "out").exists()


# A single-node Slurm of this machine, started for these tests.

SLURM_CONF = """\
ClusterName=tsubutest
SlurmctldHost={host}(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={d_port}
AuthType=auth/none
CredType=cred/none
SlurmUser=root
SlurmdUser=root
StateSaveLocation={dir}/state
SlurmdSpoolDir={dir}/spool
SlurmctldPidFile={dir}/slurmctld.pid
SlurmdPidFile={dir}/slurmd.pid
SlurmctldLogFile={dir}/slurmctld.log
SlurmdLogFile={dir}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
KillWait=30
NodeName={host} NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
"""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    """The environment of the sweeps (SLURM_CONF) of a slurmctld and a slurmd started here,
    in the foreground, with a configuration of their own (auth/none, ports of their own); both
    are stopped at the end, whatever happens."""
    missing = [c for c in ("slurmctld", "slurmd", "sbatch", "squeue", "scancel", "sinfo") if not shutil.which(c)]
    if missing or os.geteuid() != 0:
        pytest.skip(f"a Slurm of our own needs root and Debian's slurm-wlm (missing: {', '.join(missing) or 'root'})")
    folder = tmp_path_factory.mktemp("slurm")
    (folder / "state").mkdir()
    (folder / "spool").mkdir()
    conf = folder / "slurm.conf"
    conf.write_text(SLURM_CONF.format(host=socket.gethostname(), ctld_port=free_port(), d_port=free_port(), dir=folder))
    env = {**ENV, "SLURM_CONF": str(conf)}
    daemons = [subprocess.Popen([daemon, "-D", *options], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
               for daemon, options in (("slurmctld", ["-i"]), ("slurmd", []))]
    try:
        end = time.monotonic() + 60
        while subprocess.run(["sinfo", "-h", "-o", "%T"], env=env, capture_output=True, text=True).stdout.split() != ["idle"]:
            if time.monotonic() > end or any(d.poll() is not None for d in daemons):
                logs = "".join(p.read_text()[-2000:] for p in folder.glob("*.log"))
                pytest.skip(f"Slurm did not start (its logs in {folder}):\n{logs}")
            time.sleep(0.5)
        yield env
    finally:
        jobs = subprocess.run(["squeue", "-h", "-o", "%A"], env=env, capture_output=True, text=True).stdout.split()
        if jobs:
            subprocess.run(["scancel", *jobs], env=env)
            end = time.monotonic() + 60
            while time.monotonic() < end and subprocess.run(["squeue", "-h"], env=env, capture_output=True,
                                                             text=True).stdout.strip():
                time.sleep(0.5)
        for daemon in daemons:
            daemon.terminate()
        for daemon in daemons:
            try:
                daemon.wait(timeout=30)
            except subprocess.TimeoutExpired:
                daemon.kill()
                daemon.wait()


def test_slurm_runs_the_grid(slurm, tmp_path):
    """The 2 x 2 grid as one array job, 2 at a time: the results and outputs of the local
    runner; re-running submits nothing."""
    out = tmp_path / "out"
    file = write_sweep(tmp_path / "grid.toml", out, jobs=2)
    done = sweep_in(slurm, tmp_path, file, "--engine", "slurm")
    assert done.returncode == 0, done.stderr + (out / "slurm" / "slurm.out").read_text()
    assert re.search(r"sweep: submitted array job \d+: 4 cases, 2 at a time", done.stderr)
    assert "sweep: 4 of 4 cases finished" in done.stderr
    table = results(out)
    assert sorted(table) == sorted(CASES) and {row["status"] for row in table.values()} == {"ok"}
    assert {row["steps"] for row in table.values()} == {"20000"}
    assert sorted(p.name for p in (out / "slurm").iterdir()) == ["array.sh", "slurm.out"]  # collected
    for name in CASES:
        assert (out / "logs" / f"{name}.log").read_text().startswith(f"$ {TSUBU} run {SCENARIO} --out {out / name} ")
    local = write_sweep(tmp_path / "local.toml", tmp_path / "local", grid=ONE)
    assert sweep(local).returncode == 0
    same_outputs(out / CASES[0], tmp_path / "local" / CASES[0])

    done = sweep_in(slurm, tmp_path, file, "--engine", "slurm")
    assert done.returncode == 0 and "submitted" not in done.stderr and "sweep: 4 of 4 cases finished" in done.stderr


def test_slurm_time_limit_no_wait_and_ctrl_c(slurm, tmp_path):
    """A case longer than its time limit (1 minute; asked to stop 50 s before it, give or take
    Slurm's minute) ends interrupted with a checkpoint. Re-run with --no-wait: its resume is
    submitted, and a run of the sweep collects the job; Ctrl-C there cancels it and the run
    stops again with a checkpoint, further on."""
    out = tmp_path / "out"
    case, log = out / CASES[0], out / "logs" / f"{CASES[0]}.log"
    file = slurm_table(write_sweep(tmp_path / "one.toml", out, grid=ONE, set={"simulation.duration": 60.0}),
                       time=1, stop_before=50)
    done = sweep_in(slurm, tmp_path, file, "--engine", "slurm")
    assert done.returncode == 1, done.stderr
    row = results(out)[CASES[0]]
    assert row["status"] == "interrupted" and row["message"].startswith("stopped by SIGTERM after step")
    assert f"sweep: 0 of 1 cases finished; not finished: {CASES[0]}" in done.stderr

    file.write_text(file.read_text().replace("time = 1\n", "time = 10\n"))  # a longer limit for the resume
    done = sweep_in(slurm, tmp_path, file, "--engine", "slurm", "--no-wait")
    assert done.returncode == 0, done.stderr
    assert "1 in Slurm's queue: run the same command again to collect them" in done.stderr
    assert results(out)[CASES[0]]["status"] in ("queued", "running")
    assert (out / "slurm" / "array.json").exists()
    wait_for(lambda: "tsubu: resuming" in log.read_text(), "the resume to start")
    follow = subprocess.Popen([sys.executable, "-m", "tsubu.sweep", str(file), "--engine", "slurm"], env=slurm,
                              cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    first = follow.stderr.readline()  # then it follows the job, its Ctrl-C handler in place
    assert re.match(r"sweep: collecting array job \d+, submitted before", first), first
    time.sleep(2)
    follow.send_signal(signal.SIGINT)
    _, err = follow.communicate(timeout=120)
    assert follow.returncode == 4, first + err
    assert re.search(r"sweep: interrupted: cancelling array job \d+; its runs stop with a checkpoint", err)
    again = results(out)[CASES[0]]
    assert again["status"] == "interrupted" and again["message"].startswith("stopped by SIGTERM after step")
    assert int(again["steps"]) > int(row["steps"])
    assert not (out / "slurm" / "array.json").exists()
    assert log.read_text().count(f"$ {TSUBU} resume {case} --threads 1") == 1


def test_a_run_split_among_the_tasks_of_a_slurm_job(slurm, tmp_path):
    """examples/cluster/split_run.sbatch (docs/parallel.md, "On a cluster") on 2 tasks: the
    script's USR1 (the time limit is near) stops the run with a checkpoint; submitted again,
    the job resumes it to the end; the files are one process's."""
    env = {**slurm, "TSUBU": TSUBU, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1", "ASAN_OPTIONS": "detect_leaks=0"}
    script = Path(__file__).resolve().parents[2] / "examples" / "cluster" / "split_run.sbatch"
    out, sets = tmp_path / "split", ["--set", "simulation.duration=1.0", "--set", "output.checkpoint_every_steps=2000"]
    submit = ["sbatch", "--parsable", "--ntasks=2", "--cpus-per-task=1", "--time=10", f"--chdir={tmp_path}",
              f"--output={tmp_path}/job.out", "--open-mode=append", str(script), str(SCENARIO), str(out), *sets]
    done = subprocess.run(submit, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    job = done.stdout.strip().split(";")[0]
    wait_for(lambda: any((out / "checkpoint").glob("step_*.tsbk")), "the first checkpoint")
    subprocess.run(["scancel", "--signal=USR1", "--batch", job], env=env, check=True)
    wait_for(lambda: not subprocess.run(["squeue", "-h", "-j", job], env=env, capture_output=True, text=True).stdout.strip(),
             "the job to end")
    stopped = json.loads((out / "run.json").read_text())
    assert stopped["status"] == "interrupted", (tmp_path / "job.out").read_text()
    done = subprocess.run(["sbatch", "--wait", *submit[2:]], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr + (tmp_path / "job.out").read_text()
    assert json.loads((out / "run.json").read_text())["status"] == "ok"
    assert "tsubu: resuming" in (tmp_path / "job.out").read_text()
    alone = tmp_path / "alone"
    subprocess.run([TSUBU, "run", str(SCENARIO), "--out", str(alone), *sets], env=ENV, check=True, capture_output=True)
    same_outputs(alone, out)


# An MPI pool: rank 0 the sweep, the others its workers.

def mpi_sweep(file, *args, ranks=3):
    return [shutil.which("mpirun") or "mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
            sys.executable, "-m", "mpi4py.futures", "-m", "tsubu.sweep", str(file), "--engine", "mpi", *args]


@pytest.fixture
def mpi():
    if not shutil.which("mpirun"):
        pytest.skip("no mpirun (Debian's openmpi-bin)")
    pytest.importorskip("mpi4py", reason="no mpi4py (Debian's python3-mpi4py)")


def test_mpi_pool_runs_the_grid_and_resumes_after_ctrl_c(mpi, tmp_path):
    """The grid on 2 workers: the local runner's results; Ctrl-C to mpirun: each worker asks its
    run to stop with a checkpoint, and the next run of the pool resumes it to the outputs of
    an uninterrupted run."""
    out = tmp_path / "out"
    done = subprocess.run(mpi_sweep(write_sweep(tmp_path / "grid.toml", out)), env=ENV, capture_output=True,
                          text=True, timeout=240)
    assert done.returncode == 0, done.stderr
    table = results(out)
    assert sorted(table) == sorted(CASES) and {row["status"] for row in table.values()} == {"ok"}
    assert "sweep: 4 of 4 cases finished" in done.stderr

    file = write_sweep(tmp_path / "long.toml", tmp_path / "long", grid=ONE, set={"simulation.duration": 3.0})
    case = tmp_path / "long" / CASES[0]
    pool = subprocess.Popen(mpi_sweep(file, ranks=2), env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wait_for(lambda: (case / "frames" / "frame_00001.vtu").exists(), "frame 1")
    pool.send_signal(signal.SIGINT)
    pool.wait(timeout=60)
    wait_for(lambda: not lock_holder(case), "the run to stop")
    assert json.loads((case / "run.json").read_text())["status"] == "interrupted", "the run ended before the Ctrl-C"
    done = subprocess.run(mpi_sweep(file, ranks=2), env=ENV, capture_output=True, text=True, timeout=240)
    assert done.returncode == 0, done.stderr
    assert f"$ {TSUBU} resume {case} --threads 1" in (tmp_path / "long" / "logs" / f"{CASES[0]}.log").read_text()
    reference = write_sweep(tmp_path / "ref.toml", tmp_path / "ref", grid=ONE, set={"simulation.duration": 3.0})
    assert sweep(reference).returncode == 0
    same_outputs(case, tmp_path / "ref" / CASES[0])


@pytest.mark.skipif(not shutil.which("mpirun"), reason="no mpirun (Debian's openmpi-bin)")
def test_a_case_of_two_ranks_runs_split_with_the_files_of_one(tmp_path):
    """ranks = 2: the local runner starts the case as `mpirun -np 2 tsubu run ...`, which splits
    it among two processes (docs/parallel.md): the same outputs and results as one rank."""
    env = {**ENV, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1",  # root on a machine of two cores
           "ASAN_OPTIONS": "detect_leaks=0"}  # a sanitizer build: Open MPI's allocations past MPI_Finalize
    for name, ranks in (("one", 1), ("two", 2)):
        file = write_sweep(tmp_path / f"{name}.toml", tmp_path / name, grid=ONE, ranks=ranks,
                           set={"parallel.counts": [2, 1, 1]})  # cut across the deposit (one process: not read)
        done = sweep_in(env, tmp_path, file)
        assert done.returncode == 0, done.stdout + done.stderr
    same_outputs(tmp_path / "one" / CASES[0], tmp_path / "two" / CASES[0])
    # Split: run.json counts the contacts process 0 evaluated, its part of the run's.
    work = [json.loads((tmp_path / name / CASES[0] / "run.json").read_text())["contact_evaluations"] for name in ("one", "two")]
    assert 0 < work[1] < work[0]
