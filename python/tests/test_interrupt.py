"""Ctrl-C (SIGINT) during a long advance_to stops it between two steps with KeyboardInterrupt
and leaves a consistent state: stepping on gives the bits of an uninterrupted run."""

import os
import signal
import subprocess
import sys
import textwrap

CHILD = textwrap.dedent(
    """\
    import sys
    import numpy as np
    import tsubu
    from conftest import bed_text

    sim = tsubu.Simulation(bed_text())
    print("stepping", flush=True)
    try:
        sim.advance_to(1000.0)  # hours of stepping
        sys.exit("advance_to returned")
    except KeyboardInterrupt:
        pass
    steps = sim.step_count
    assert 0 < steps < 200000, steps
    assert sim.time == steps * sim.dt
    sim.step(10)
    again = tsubu.Simulation(bed_text())
    again.step(steps + 10)
    for name in ("positions", "velocities", "spins", "forces"):
        a, b = (getattr(s, name)[np.argsort(s.ids)] for s in (sim, again))
        assert a.tobytes() == b.tobytes(), name
    print("interrupted at step", steps, flush=True)
    """
)


def test_sigint_stops_between_steps_with_a_consistent_state():
    here = os.path.dirname(__file__)
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD],
        cwd=here,
        env=dict(os.environ, PYTHONPATH=os.pathsep.join([os.environ.get("PYTHONPATH", ""), here])),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout.readline() == "stepping\n"
        import time

        time.sleep(1.0)  # well inside advance_to, with the GIL released
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=120)
    finally:
        child.kill()
    assert child.returncode == 0, err
    assert out.startswith("interrupted at step"), (out, err)


def test_the_gil_is_released_while_stepping_and_the_state_is_guarded(bed):
    import threading

    import tsubu

    sim = tsubu.Simulation(bed)
    worker = threading.Thread(target=sim.advance_to, args=(0.02,))  # 4000 steps
    worker.start()
    refused = 0
    while worker.is_alive():  # this thread runs meanwhile: the GIL is free
        try:
            sim.positions
        except RuntimeError as e:
            assert "stepping in another thread" in str(e)
            refused += 1
    worker.join()
    assert refused > 0
    assert sim.step_count == 4000 and sim.positions.shape[0] == sim.particle_count
