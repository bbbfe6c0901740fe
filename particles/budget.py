"""Estimate before spending: the memory and the work of a run, checked before it starts.

Every run of the driver (and every command) first estimates, from two methods of its engine
(``memory_per_particle`` and ``expected_events`` of :class:`particles.driver.Engine`; an engine
without them is refused by name, never costed by guess):

* its **memory**: the engine's working arrays (bytes per particle measured on this project's
  machine, doubled for headroom: Ulam 31, lattice 77, MD 181 bytes per particle at N = 10⁶), the
  records of the driver (S(k) rows, snapshots) and the histogram;
* its **work**: the expected number of events (pair collisions for Ulam, N/2 per unit τ;
  attempted bond updates for the lattice, N per unit τ; MD pair collisions N τ(t)/2 with
  τ(t) = (2/(1 − r²)) ln(1 + t/t₀) from Haff's law, plus, with δ > 0, collisions at
  the rate (2/√π) n δ of a gas at temperature δ² once Haff's temperature falls below δ²
  (relative velocities below δ are not dissipated); this ignores the collision-hungry clustered
  stage (~7·10⁴ collisions per particle by t = 300 at r = 0.5, δ = 10⁻⁴), so it is a
  rough lower bound; (2/√π) n t for r = 1).

A run whose memory exceeds what the machine has available is refused (``InvalidArgumentError``
naming the argument that drives it, with the estimate).  A run of more than
:data:`MAX_EVENTS` events is refused unless ``force=True`` (``--force``).  The estimate costs a
few arithmetic operations.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from .validation import InvalidArgumentError, check_bool

__all__ = ["Estimate", "MAX_EVENTS", "available_memory", "estimate_run", "check_budget",
           "format_count", "format_bytes"]

#: Above this many events a run is refused unless forced (10¹³ events is months of CPU).
MAX_EVENTS = 1e13

@dataclass(frozen=True)
class Estimate:
    """The estimated memory and work of a run, computed before it starts.

    Attributes
    ----------
    memory : float
        Bytes the run is expected to need (working arrays, records and histogram).
    events : float
        The expected number of events (see ``unit``).
    driver : str
        The name of the argument that sets the size, named in the error when the memory does
        not fit (default ``"n"``).
    unit : str
        What an event is: ``"collisions"``, ``"attempts"``, ``"hull steps"``...
    size : float
        The value of that argument (the number of particles).
    t_max : float
        The last output time of the run (in the run's time variable).
    """

    memory: float
    events: float
    driver: str = "n"
    unit: str = "events"
    size: float = 0.0
    t_max: float = 0.0

    def describe(self) -> str:
        """The estimate in words, for messages.

        Returns
        -------
        str
            E.g. ``"~5e+06 collisions, ~6.1 MB"``.
        """
        return f"~{format_count(self.events)} {self.unit}, ~{format_bytes(self.memory)}"


def format_count(x: float) -> str:
    """Format a count: 3 significant digits from 10⁴ on, an integer below.

    Parameters
    ----------
    x : float
        The count (non-finite values are shown as they are).

    Returns
    -------
    str
        The formatted count.
    """
    if not math.isfinite(x):
        return str(x)
    return f"{x:.3g}" if x >= 1e4 else f"{x:.0f}"


def format_bytes(x: float) -> str:
    """Format a number of bytes with binary prefixes (``"512 B"``, ``"1.5 KB"``, ``"3.2 GB"``).

    Parameters
    ----------
    x : float
        The number of bytes.

    Returns
    -------
    str
        Three significant digits and the unit (B, KB, MB, GB or TB; 1 KB = 1024 B).
    """
    for unit in ("B", "KB", "MB", "GB", "TB"):
        if abs(x) < 1024 or unit == "TB":
            return f"{x:.3g} {unit}" if unit != "B" else f"{x:.0f} B"
        x /= 1024.0
    return f"{x:.3g} PB"  # pragma: no cover


def available_memory() -> float:
    """Bytes of memory available now.

    Returns
    -------
    float
        ``MemAvailable`` from ``/proc/meminfo``; where that cannot be read, the physical memory;
        ``inf`` when neither is known.
    """
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:  # pragma: no cover - not Linux
        pass
    try:  # pragma: no cover
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover
        return float("inf")


def estimate_run(engine, t_max: float, *, n_times: int = 1, structure: str | None = None,
                 snapshots: bool = False) -> Estimate:
    """Estimate the memory and the number of events of a run of ``engine``, in a few arithmetic
    operations.

    The memory is the engine's working bytes per particle (its ``memory_per_particle()``) times
    N, plus the records: the energy rows, the S(k) rows (``structure``) and the velocity
    snapshots.  The events are the engine's ``expected_events(t_max, n_times)`` (module
    docstring).  Both estimates are methods of the engine (:class:`particles.driver.Engine`);
    an engine without them is refused, naming it: a run is never costed by guess.

    Parameters
    ----------
    engine : particles.driver.Engine
        The run's engine; ``engine.to_dict()`` gives ``n`` and (d > 1) ``dimension``.
    t_max : float
        The last output time, in the engine's time (τ for Ulam and the lattice, t for MD).
    n_times : int, optional
        The number of output times (default 1).
    structure : str or None, optional
        ``"all"`` (S(k) at every output time), ``"last"`` (at the last) or None.
    snapshots : bool, optional
        Whether the velocities are kept at every output time (default False).

    Returns
    -------
    Estimate
        The estimate, with ``driver = "n"``.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``engine`` when it is not an engine object with both estimates (a model's name
        alone, or an engine that does not write them out).
    """
    from .driver.engine import engine_label

    estimates = ("memory_per_particle", "expected_events", "to_dict")
    if isinstance(engine, str) or not all(callable(getattr(engine, m, None)) for m in estimates):
        raise InvalidArgumentError(
            "engine", engine if isinstance(engine, str) else engine_label(engine),
            "an engine with its own cost estimates (memory_per_particle and expected_events): "
            "a run is never costed by guess",
        )
    params = engine.to_dict()
    n = float(params.get("n", 0))
    d = float(params.get("dimension", 1))
    memory = n * float(engine.memory_per_particle()) + 64.0 * n_times * 8
    if structure == "all":
        memory += n_times * (n / 2 + 1) * 8 + 48 * n
    elif structure == "last":
        memory += (n / 2 + 1) * 8 + 48 * n
    if snapshots:
        memory += n_times * n * 8 * d
    events, unit = engine.expected_events(float(t_max), int(n_times))
    return Estimate(memory, events, "n", unit, params.get("n", 0), t_max)


def check_budget(estimate: Estimate, *, force: bool = False, time_name: str = "tau",
                 memory_available: float | None = None) -> Estimate:
    """Refuse a run that cannot fit in memory, or whose work is absurd unless ``force``.

    Parameters
    ----------
    estimate : Estimate
        The run's estimate (:func:`estimate_run`).
    force : bool, optional
        Accept more than ``MAX_EVENTS`` = 10¹³ events (``--force``; default False).  Memory is
        checked even then.
    time_name : str, optional
        The name of the time argument, named in the error for too much work (default ``"tau"``).
    memory_available : float or None, optional
        Bytes available; None (default) asks :func:`available_memory`.

    Returns
    -------
    Estimate
        ``estimate``, unchanged.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``estimate.driver`` when the memory exceeds what is available, or ``time_name``
        when the events exceed ``MAX_EVENTS`` without ``force``; the message shows the estimate.
        Naming ``force`` when it is not a bool (``'no'`` is not True).
    """
    force = check_bool(force, "force")
    available = available_memory() if memory_available is None else memory_available
    if not estimate.memory <= available:
        raise InvalidArgumentError(
            estimate.driver, estimate.size,
            f"a size whose run fits in the {format_bytes(available)} of memory available "
            f"(estimate: {estimate.describe()})",
        )
    if not force and not estimate.events <= MAX_EVENTS:
        raise InvalidArgumentError(
            time_name, estimate.t_max,
            f"a run of at most {MAX_EVENTS:.0e} events (estimate: {estimate.describe()}); "
            "pass force=True (--force) to run it anyway",
        )
    return estimate
