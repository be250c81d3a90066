"""tsubu: a discrete element method engine for spherical grains, driven from Python.

``tsubu.Simulation`` is a run of a scenario (docs/scenario.md) held in memory: step it,
read and write its particles as NumPy arrays, look at its contacts, measure it and write or
resume checkpoints. The engine's errors arrive as ``ScenarioError`` (a ``ValueError``
carrying the ``file:line: key: message`` of the command line), ``NumericalError``,
``WriteError`` and ``CheckpointError``. See docs/python.md.
"""

from ._core import (
    CheckpointError,
    NumericalError,
    ScenarioError,
    Simulation,
    WriteError,
    __version__,
)

for _name in ("CheckpointError", "NumericalError", "ScenarioError", "Simulation", "WriteError"):
    globals()[_name].__module__ = __name__  # tsubu.ScenarioError, not tsubu._core.ScenarioError
del _name

# Reading run folders (docs/sweeps.md). Sweeps are `import tsubu.sweep` or
# `python3 -m tsubu.sweep` (not imported here: runpy would then find the module loaded).
from .runs import read_run

__all__ = [
    "CheckpointError",
    "NumericalError",
    "ScenarioError",
    "Simulation",
    "WriteError",
    "__version__",
    "read_run",
]
