"""The run driver shared by every particle model: initial velocities, the run loop, progress bar,
checkpoint / resume, Ctrl-C, and saving / loading results.

Engine contract
---------------
:class:`Engine` lists every member of an engine that the driver calls (it calls nothing else):
``name``, ``time_name``, ``to_dict()``, ``initial_state(rng)``, ``advance(state, until, rng)``,
``next_stop(time)``, ``state_from_arrays(arrays)`` (raising ``InvalidArgumentError`` naming
``checkpoint`` for bad arrays), the hooks ``observe(state)``, ``snapshot_fields`` and
``snapshot_arrays(state)``, and the cost estimates ``memory_per_particle()`` and
``expected_events(t_max, n_times)``.  :class:`EngineBase` is the base class of the four engines
(``particles.Ulam``, ``particles.Lattice``, ``particles.MDEngine``, ``particles.StickyGas``): it
writes the stop grid, the checks of a checkpointed state and the neutral hooks once (see
:mod:`particles.driver.engine`, which says how to add an engine).  An object without every
member is refused by :func:`simulate`, naming it; an engine without its estimates likewise.

A state is a frozen dataclass with at least ``time: float``, ``velocities: ndarray``,
``collisions: int`` and ``to_arrays() -> dict[str, ndarray]``.

All randomness comes from one ``np.random.default_rng(seed)``.
"""

from __future__ import annotations

from .checkpoint import read_checkpoint
from .engine import Engine, EngineBase, next_grid_point
from .result import FORMAT_VERSION, CheckpointError, RunResult
from .run import initial_velocities, simulate

__all__ = [
    "FORMAT_VERSION",
    "CheckpointError",
    "read_checkpoint",
    "Engine",
    "EngineBase",
    "RunResult",
    "initial_velocities",
    "simulate",
    "next_grid_point",
]

