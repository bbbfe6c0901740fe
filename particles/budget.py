"""Estimate before spending: the memory and the work of a run, checked before it starts.

Every run of the driver (and every command) first estimates

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

from .validation import InvalidArgumentError

__all__ = ["Estimate", "MAX_EVENTS", "available_memory", "estimate_run", "check_budget",
           "format_count", "format_bytes"]

#: Above this many events a run is refused unless forced (10¹³ events is months of CPU).
MAX_EVENTS = 1e13

#: Working bytes per particle of each engine (measured peak at N = 10⁶, doubled; the sticky gas:
#: 69 bytes measured at N = 3·10⁷ with 20 output times, rounded up to 96).
BYTES_PER_PARTICLE = {"ulam": 64, "lattice": 160, "md": 400, "sticky": 96}
_DEFAULT_BYTES_PER_PARTICLE = 400


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


def _md_tau(t: float, params: dict) -> float:
    """Collisions per particle by time t in the homogeneous (Haff) stage."""
    n = float(params.get("n", 2))
    length = n / float(params["density"])
    reduced = length - n * float(params.get("rod_length", 0.0))
    density = n / reduced if reduced > 0 else float("inf")
    r = float(params["restitution"])
    delta = float(params.get("delta", 0.0))
    rate0 = 2.0 / math.sqrt(math.pi) * density  # dτ/dt at t = 0, unit temperature
    if r >= 1.0:
        return rate0 * t
    from .md.observables import haff_time

    t0 = haff_time(r, density)
    tau = 2.0 / (1.0 - r * r) * math.log1p(t / t0)
    if delta > 0.0:
        # relative velocities below δ are not dissipated: once Haff's T falls to δ², collisions
        # go on at least at the rate of a gas at temperature δ² (a heuristic floor)
        t_delta = t0 * (1.0 / min(delta, 1.0) - 1.0)
        tau += rate0 * min(delta, 1.0) * max(0.0, t - t_delta)
    return tau


def estimate_run(model: str, params: dict, t_max: float, *, n_times: int = 1,
                 structure: str | None = None, snapshots: bool = False) -> Estimate:
    """Estimate the memory and the number of events of a run, in a few arithmetic operations.

    The memory is the engine's working bytes per particle (``BYTES_PER_PARTICLE``, times the
    dimension) plus the records: the energy rows, the S(k) rows (``structure``) and the velocity
    snapshots.  The events are counted as the module docstring says: pair collisions N τ/2 for
    Ulam, N τ attempted updates for the lattice (more for clocks at the relative-velocity rate),
    collisions from Haff's law for MD (a rough lower bound), N log₂N hull steps per output time
    for the sticky gas.

    Parameters
    ----------
    model : str
        The model's name (``"ulam"``, ``"lattice"``, ``"md"``, ``"sticky"``; any other name is
        counted like Ulam, with the MD bytes per particle).
    params : dict
        The model's parameter dict (the engine's ``to_dict()``); ``n`` is read, and for MD
        ``density``, ``restitution``, ``rod_length`` and ``delta``.
    t_max : float
        The last output time (τ for Ulam and the lattice, t for MD).
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
    """
    n = float(params.get("n", 0))
    d = float(params.get("dimension", 1))
    per = BYTES_PER_PARTICLE.get(model, _DEFAULT_BYTES_PER_PARTICLE) * d
    memory = n * per + 64.0 * n_times * 8
    if structure == "all":
        memory += n_times * (n / 2 + 1) * 8 + 48 * n
    elif structure == "last":
        memory += (n / 2 + 1) * 8 + 48 * n
    if snapshots:
        memory += n_times * n * 8 * d
    if model == "lattice":
        events, unit = n * t_max, "attempts"
        if params.get("rate") == "relative_velocity":  # clocks tick at the velocity range R,
            events *= 2.0 * math.sqrt(2.0 * math.log(max(n, 2.0)))  # ≈ 2√(2 ln N) at t = 0
    elif model == "md":
        events, unit = n * _md_tau(t_max, params) / 2.0, "collisions (at least)"
    elif model == "sticky":
        events, unit = n * max(1.0, math.log2(max(n, 2.0))) * n_times, "hull steps"
    else:  # ulam and its variants: pair collisions at rate N/2 per unit τ
        events, unit = n * t_max / 2.0, "collisions"
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
    """
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
