"""The data of the hard-rod gas: its parameters (:class:`MDParams`), a state that can be saved
and continued bit for bit (:class:`MDState`), and the failure of the physics,
:class:`InelasticCollapseError`.  The dynamics is in :mod:`.lightcone` and :mod:`.reference`, the
driver interface in :mod:`particles.md.engine`."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..collision import transfer_fraction
from ..initial import get_law
from ..validation import (
    InvalidArgumentError,
    check_count,
    check_nonnegative,
    check_positive,
    check_restitution,
)

__all__ = ["InelasticCollapseError", "MDParams", "MDState"]


class InelasticCollapseError(RuntimeError):
    """Collisions piled up in finite time (δ = 0): the run cannot go on.

    With δ > 0 collapse is impossible in exact arithmetic, but a very small δ can still let the
    time between one particle's collisions fall below the resolution of double precision, so that
    the clock stands still; that stall is reported with this error too, and its message then says
    to increase δ instead of to set it (and, for r = 1, that δ changes nothing).  The arguments are
    kept as attributes of the same names (``particles`` as the sorted unique labels).

    Parameters
    ----------
    time : float
        The physical time of the runaway.
    particles : array_like of int
        Labels of the particles involved (at most ten are shown in the message).
    collisions : int
        Total number of pair collisions processed so far.
    detail : str, optional
        A further explanation appended to the message.
    delta : float, optional
        The run's regularisation δ (default 0).
    restitution : float or None, optional
        The run's restitution coefficient r, when known.
    """

    def __init__(
        self,
        time: float,
        particles,
        collisions: int,
        detail: str = "",
        delta: float = 0.0,
        restitution: float | None = None,
    ):
        self.time = float(time)
        self.particles = np.unique(np.asarray(particles, dtype=np.int64))
        self.collisions = int(collisions)
        self.delta = float(delta)
        self.restitution = restitution
        shown = self.particles[:10].tolist()
        more = "" if self.particles.size <= 10 else f" (+{self.particles.size - 10} more)"
        if self.restitution == 1.0:
            hint = (
                "the collisions are elastic (r = 1), so delta changes nothing: the time steps "
                "fell below the resolution of double precision; check the initial state"
            )
        elif self.delta > 0.0:
            hint = (
                f"with delta = {self.delta:g} the collisions are regularised, but their time "
                "steps fell below the resolution of double precision (the time stands still); "
                "increase delta (measured at N = 1000, r = 0.5: delta <= 1e-7 stalls, 1e-6 runs)"
            )
        else:
            hint = (
                "set delta > 0 (e.g. --delta 1e-4) to regularise collisions with small relative "
                "velocity"
            )
        super().__init__(
            f"inelastic collapse at t={self.time!r} after {self.collisions} collisions, "
            f"particles {shown}{more}{': ' + detail if detail else ''}; {hint}"
        )


@dataclass(frozen=True)
class MDParams:
    """Parameters of the hard-rod gas on a ring, checked at construction.

    Attributes
    ----------
    n : int
        Number of rods N ≥ 2.
    density : float
        Number density n = N/L > 0 (L the ring length).
    restitution : float
        Restitution coefficient r ∈ [0, 1].
    delta : float
        Regularisation δ ≥ 0: a collision with relative velocity below δ is elastic (0: none).
    rod_length : float
        Rod length σ ≥ 0, with N σ < L.
    initial : str
        Name of the initial velocity law (:func:`particles.initial.get_law`; one with a
        sampler), stored as the law's name.

    Raises
    ------
    particles.InvalidArgumentError
        Naming the field that is out of its domain: ``n``, ``density``, ``restitution``,
        ``delta``, ``rod_length`` (also when the rods do not fit on the ring), or ``initial``
        (an unknown law, or one without a sampler).
    """

    n: int
    density: float
    restitution: float
    delta: float = 0.0
    rod_length: float = 0.0
    initial: str = "gaussian"

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 2))
        object.__setattr__(self, "density", check_positive(self.density, "density"))
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        object.__setattr__(self, "delta", check_nonnegative(self.delta, "delta"))
        object.__setattr__(self, "rod_length", check_nonnegative(self.rod_length, "rod_length"))
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", self.initial, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)
        if not math.isfinite(self.length):  # n/density overflows: density underflows
            raise InvalidArgumentError(
                "density", self.density,
                f"a density whose ring length n/density is finite (n = {self.n})",
            )
        if not self.reduced_length > 0.0:
            raise InvalidArgumentError(
                "rod_length",
                self.rod_length,
                f"rods that fit: n*rod_length < L = n/density = {self.length!r}",
            )
        if not math.isfinite(self.reduced_density):  # L - n*rod_length is subnormal
            raise InvalidArgumentError(
                "rod_length", self.rod_length,
                f"rods that leave a free length L - n*rod_length that n can be divided by "
                f"(L = {self.length!r})",
            )

    @property
    def length(self) -> float:
        """Ring length L = N / n."""
        return self.n / self.density

    @property
    def reduced_length(self) -> float:
        """Length L − Nσ of the ring of point particles."""
        return self.length - self.n * self.rod_length

    @property
    def reduced_density(self) -> float:
        """Density N / (L − Nσ) of the equivalent point particles."""
        return self.n / self.reduced_length

    @property
    def p(self) -> float:
        """Momentum-transfer fraction p = (1 + r)/2 of an inelastic collision."""
        return transfer_fraction(self.restitution)

    def to_dict(self) -> dict:
        """The parameters as a plain dict (the engine protocol's parameter dict).

        Returns
        -------
        dict
            Field name → value.
        """
        return asdict(self)


@dataclass(frozen=True, eq=False)
class MDState:
    """A snapshot of the gas at ``time``: everything needed to continue bit for bit.

    Positions are stored lazily: each rod's point coordinate on the reduced ring (length L − Nσ,
    unwrapped) at its own last-update time.

    Attributes
    ----------
    time : float
        The physical time t of the snapshot.
    positions : numpy.ndarray
        Float array of shape ``(N,)``: ``positions[i]`` is the point coordinate of rod i at
        time ``t_last[i]``.
    t_last : numpy.ndarray
        Float array of shape ``(N,)``: the last-update time of each rod (≤ ``time``).
    velocities : numpy.ndarray
        Float array of shape ``(N,)``: each rod's velocity since ``t_last[i]``.
    collisions : int
        Total number of pair collisions since t = 0.
    """

    time: float
    positions: np.ndarray
    t_last: np.ndarray
    velocities: np.ndarray
    collisions: int

    def positions_at(self, t: float | None = None) -> np.ndarray:
        """Point coordinates (reduced ring, unwrapped) at time ``t``.

        Parameters
        ----------
        t : float or None, optional
            The physical time; None (default) means ``self.time``.

        Returns
        -------
        numpy.ndarray
            ``positions + velocities * (t - t_last)``, shape ``(N,)``.
        """
        t = self.time if t is None else float(t)
        return self.positions + self.velocities * (t - self.t_last)

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The state as a dict of NumPy arrays (what the driver's checkpoints store).

        Returns
        -------
        dict of str to numpy.ndarray
            ``time``, ``positions``, ``t_last``, ``velocities`` (floats) and ``collisions``
            (int64).
        """
        return {
            "time": np.array(self.time, dtype=float),
            "positions": np.array(self.positions, dtype=float),
            "t_last": np.array(self.t_last, dtype=float),
            "velocities": np.array(self.velocities, dtype=float),
            "collisions": np.array(self.collisions, dtype=np.int64),
        }

    @classmethod
    def from_arrays(cls, data, params: MDParams | None = None) -> MDState:
        """Rebuild a state from :meth:`to_arrays`'s dict, with consistency checks.

        Parameters
        ----------
        data : mapping
            The arrays, as :meth:`to_arrays` writes them.
        params : particles.MDParams or None, optional
            When given, N must match and the rods must be in order on the ring at ``time``.

        Returns
        -------
        particles.MDState
            The state.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``, for a corrupt state: not a mapping, missing or non-numeric
            entries, inconsistent shapes or N < 2, an N other than ``params.n``, non-finite values,
            a negative count, a ``t_last`` after ``time``, or rods out of order.  It is a
            ``ValueError``, which the driver turns into its ``CheckpointError`` naming the file.
        """
        keys = ("time", "positions", "t_last", "velocities", "collisions")
        try:
            missing = [k for k in keys if k not in data]
        except TypeError:
            raise InvalidArgumentError("checkpoint", type(data).__name__, "a mapping") from None
        if missing:
            raise InvalidArgumentError("checkpoint", f"missing {missing}", "an MD state")
        try:
            t = float(np.asarray(data["time"]))
            x = np.array(data["positions"], dtype=float)
            tl = np.array(data["t_last"], dtype=float)
            v = np.array(data["velocities"], dtype=float)
            count = int(np.asarray(data["collisions"]))
        except (TypeError, ValueError) as exc:
            raise InvalidArgumentError("checkpoint", str(exc), "an MD state") from None
        n = x.shape[0] if x.ndim == 1 else -1
        if x.ndim != 1 or tl.shape != x.shape or v.shape != x.shape or n < 2:
            shapes = (x.shape, tl.shape, v.shape)
            raise InvalidArgumentError("checkpoint", f"shapes {shapes}", "three arrays of length N")
        if params is not None and n != params.n:
            raise InvalidArgumentError("checkpoint", f"N={n}", f"N={params.n} as in the parameters")
        finite = all(np.all(np.isfinite(a)) for a in (x, tl, v)) and math.isfinite(t)
        if not finite or count < 0 or np.any(tl > t):
            raise InvalidArgumentError(
                "checkpoint", "non-finite values, negative count or t_last > time", "an MD state"
            )
        if params is not None:
            xt = x + v * (t - tl)
            gaps = np.diff(np.append(xt, xt[0] + params.reduced_length))
            if np.any(gaps < -1e-9 * (params.reduced_length + np.max(np.abs(xt)))):
                raise InvalidArgumentError("checkpoint", "particles out of order", "an MD state")
        return cls(t, x, tl, v, count)
