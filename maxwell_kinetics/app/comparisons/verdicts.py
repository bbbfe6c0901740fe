"""Verdicts: each claim a comparison tests, judged from the numbers of its summary.

A :class:`Check` is one measured quantity with its standard error against an expected value
with its source (an exact result, the paper's number, another model) and a tolerance: a number
of standard errors, a stated absolute tolerance, or both (allowed deviation
``n_sigma · σ + tolerance``, with σ the measured and the expected standard errors added in
quadrature).  :func:`judge` turns a claim and its check into a :class:`Verdict` with one of five
statuses, in this order:

``not measured``
    the run is too small to resolve the claim: its ``resolution`` check (a number of the run
    itself, e.g. its coarsest scale or its first time against what the claim needs) fails.
    The verdict names the size that measures the claim (``measured_at``).  It never counts as
    passing, and never fails the exit status;
``agrees``
    the check holds;
``explained``
    the check fails, and the claim holds once a named measurement artefact is removed: every
    check of its ``explanation`` holds.  An explanation is an INDEPENDENT measurement (the same
    quantity with the artefact removed, or a precondition such as molecular chaos at the
    window's start), never the complement or a restatement of the check;
``refuted``
    the check fails, the claim (as the paper states it) is false, and the run shows its cause:
    every check of its ``refutation`` holds (e.g. the model with the cause removed agrees).
    A documented finding about the paper, not a failure of the code;
``disagrees``
    the check fails and neither an explanation nor a refutation holds (or the quantity could
    not be measured).

No status is ever written by hand: it always comes from :func:`judge`.  Every comparison module
has ``verdicts(summary) -> list[Verdict]`` reading only its own summary, and its ``run`` ends
with ``return Comparison(NAME, with_verdicts(summary, verdicts), data)``; ``reproduce`` prints
:func:`verdict_table` and exits with status 3 when :func:`disagreeing` finds a verdict that
disagrees: a claim failed that this size resolves (``not measured`` and ``refuted`` do not
fail it).

Every check records its standard error's degrees of freedom (``dof``: seeds − 1, None where σ
is not a scatter of a few seeds) and where σ comes from (``sigma_source``); :mod:`.calibration`
judges the z of the agreeing checks each under its own law.  The tolerance of a statistical
check has the coverage of 3 normal σ, two-sided 99.73 % (a bound or a resolved difference:
one-sided 99.865 %, the same quantile), under the law of its own z, by the kind of its σ:

σ from a law or known exactly (χ² null, binomial counts, a fit with known errors, many runs)
    z is normal: 3σ (``dof`` None);
σ the scatter of R seeds, or a jackknife over them
    z is Student's t with R − 1 degrees of freedom: the check sets ``t_law`` and allows
    :attr:`Check.sigmas` = :func:`.tolerances.t_sigmas` of its dof (9.22σ for 4 seeds,
    4.53σ for 8, 3.59σ for 16);
both sides measured
    the same with the Welch–Satterthwaite dof of the combined σ (:attr:`Check.combined_dof`);
the largest |z| of k values (a scan over times, ``trials`` k)
    the quantile whose maximum over k values keeps the coverage (Šidák).

A stated absolute ``tolerance`` (a measured systematic, a numerical floor) adds to that
allowance and never stands in for it.  A check whose σ is a seed scatter without ``t_law``
allows 3σ: about 94 % coverage at 3 dof.

This module imports nothing from the rest of the package but :mod:`.tolerances`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass

from particles.validation import InvalidArgumentError

from .tolerances import student_sigmas, t_sigmas

__all__ = [
    "CHI2_SIGMA_SOURCE",
    "finite_number",
    "STATUSES",
    "FAILING",
    "Check",
    "Verdict",
    "judge",
    "with_verdicts",
    "disagreeing",
    "verdict_table",
    "measured_text",
    "expected_text",
    "pooled_ratio",
    "pair",
    "student_sigmas",
    "status_counts",
    "welch_dof",
]

#: Where the σ of a pooled χ²/(dof·φ) comes from (the comparisons that judge one say so).
CHI2_SIGMA_SOURCE = ("χ² law: √(2/Σ dof) of the pooled bins under the null, and the "
                     "overdispersion φ's own error (seed scatter)")

#: The statuses a verdict can have.
STATUSES = ("agrees", "disagrees", "explained", "refuted", "not measured")
#: The statuses that fail ``reproduce`` (exit status 3): a claim this size resolves failed.
FAILING = ("disagrees",)

_RELATIONS = ("equal", "at_most", "at_least", "below", "above", "differs")


def finite_number(x) -> float | None:
    """``x`` as a finite float, or None (a missing fit, NaN or infinity).

    Parameters
    ----------
    x : object
        A number, or anything else.

    Returns
    -------
    float or None
    """
    if x is None or isinstance(x, bool):
        return None
    try:
        x = float(x)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


@dataclass(frozen=True)
class Check:
    """One measured quantity against its expected value, with a tolerance.

    Attributes
    ----------
    quantity : str
        What is measured, in words or symbols (e.g. ``"Haff exponent of E(t), t in [0.3, 2]"``).
    measured : float or None
        The measured value; None (or NaN) when it could not be measured: the check fails.
    sigma : float or None
        One standard error of ``measured`` (from the run's seeds or fit); None or 0 for an
        exact or deterministic number.
    expected : float or None
        The expected value; None when it is another model's number that could not be measured
        (never replaced by a stand-in such as 0): the check fails.
    source : str
        Where ``expected`` comes from: ``"exact: ..."``, ``"paper: ..."``, ``"model: ..."``.
    n_sigma : float
        Number of combined standard errors allowed (default 3); with ``t_law``, the normal
        standard errors whose coverage is kept (:attr:`sigmas` is what is allowed).
    tolerance : float
        A stated absolute tolerance added to ``n_sigma`` standard errors (default 0): a
        numerical floor, a systematic error stated by the comparison.
    relation : str
        ``"equal"`` (|measured − expected| ≤ allowed); a bound with its slack: ``"at_most"``
        (measured ≤ expected + allowed) or ``"at_least"`` (measured ≥ expected − allowed); a
        resolved difference: ``"below"`` (measured ≤ expected − allowed), ``"above"``
        (measured ≥ expected + allowed) or ``"differs"`` (|measured − expected| ≥ allowed,
        either side); a resolved difference is never zero, so equal values with nothing
        allowed (no standard error, no tolerance) are not below, above nor different.
    expected_sigma : float or None
        One standard error of ``expected`` when it is itself measured (another model's number).
    dof, expected_dof : float or None
        Degrees of freedom of ``sigma`` and of ``expected_sigma``: R − 1 for a standard error
        from the scatter of R seeds (or a jackknife over them); None (infinite) for one from a
        law (χ² null, binomial counts), a solver's error estimate, or many runs.
    sigma_source : str
        Where ``sigma`` comes from, in words (seeds, jackknife, fit, χ² law, solver's
        estimate, a measured systematic); "" when there is none.
    trials : int
        The number of values ``measured`` is the largest |z| of (a scan over times; default
        1): its p-value is that of a maximum (:func:`.calibration.p_value`).
    t_law : bool
        Allow the quantile of the check's own law at the coverage of ``n_sigma`` normal σ
        (:func:`.tolerances.t_sigmas` of :attr:`combined_dof` and ``trials``) instead of
        ``n_sigma`` itself (default False).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``relation``, ``n_sigma``, ``tolerance``, ``sigma``, ``expected``, ``dof``,
        ``expected_dof``, ``trials`` or ``t_law`` for a value
        outside its domain (a negative or non-finite tolerance, an unknown relation, a
        non-finite expected value; None is not measured, not refused).
    """

    quantity: str
    measured: float | None
    sigma: float | None
    expected: float
    source: str
    n_sigma: float = 3.0
    tolerance: float = 0.0
    relation: str = "equal"
    expected_sigma: float | None = None
    dof: float | None = None
    expected_dof: float | None = None
    sigma_source: str = ""
    trials: int = 1
    t_law: bool = False

    def __post_init__(self):
        if self.relation not in _RELATIONS:
            raise InvalidArgumentError("relation", self.relation, "one of " + ", ".join(_RELATIONS))
        for name in ("n_sigma", "tolerance"):
            value = finite_number(getattr(self, name))
            if value is None or value < 0:
                raise InvalidArgumentError(name, getattr(self, name), "a finite number >= 0")
        for name in ("sigma", "expected_sigma"):
            value = getattr(self, name)
            if value is not None and (finite_number(value) is None or value < 0):
                raise InvalidArgumentError(name, value, "None or a finite number >= 0")
        if self.expected is not None and finite_number(self.expected) is None:
            raise InvalidArgumentError("expected", self.expected,
                                       "a finite number, or None when not measured")
        for name in ("dof", "expected_dof"):
            value = getattr(self, name)
            if value is not None and (finite_number(value) is None or value <= 0):
                raise InvalidArgumentError(name, value, "None (infinite) or a finite number > 0")
        if isinstance(self.trials, bool) or not isinstance(self.trials, int) or self.trials < 1:
            raise InvalidArgumentError("trials", self.trials, "an integer >= 1")
        if not isinstance(self.t_law, bool):
            raise InvalidArgumentError("t_law", self.t_law, "True or False")

    @property
    def combined_dof(self) -> float | None:
        """Degrees of freedom of :attr:`combined_sigma`: :func:`welch_dof` of σ and the
        expected σ with their own (None: infinite)."""
        return welch_dof((self.sigma or 0.0, self.dof),
                         (self.expected_sigma or 0.0, self.expected_dof))

    @property
    def combined_sigma(self) -> float:
        """√(σ² + σ_expected²), 0 when neither is given."""
        return math.hypot(self.sigma or 0.0, self.expected_sigma or 0.0)

    @property
    def sigmas(self) -> float:
        """The number of combined standard errors allowed: ``n_sigma``, or with ``t_law`` the
        quantile of Student's t with :attr:`combined_dof` (the largest of ``trials``) at the
        two-sided coverage of ``n_sigma`` normal σ."""
        if not self.t_law:
            return float(self.n_sigma)
        return t_sigmas(self.combined_dof, self.n_sigma, self.trials)

    @property
    def allowed(self) -> float:
        """The largest deviation that still agrees: ``sigmas · combined_sigma + tolerance``."""
        return self.sigmas * self.combined_sigma + self.tolerance

    @property
    def deviation(self) -> float | None:
        """measured − expected (None when either is not measured)."""
        m = finite_number(self.measured)
        return None if m is None or self.expected is None else m - float(self.expected)

    def holds(self) -> bool:
        """Whether the measured value stands to the expected one as ``relation`` says, within
        ``allowed``; a quantity (or an expected value) not measured does not hold, and a
        resolved difference (``below``, ``above``, ``differs``) needs a non-zero deviation.

        Returns
        -------
        bool
        """
        d = self.deviation
        if d is None:
            return False
        if self.relation == "at_most":
            return d <= self.allowed
        if self.relation == "at_least":
            return d >= -self.allowed
        # a resolved difference is not zero, even when nothing is allowed
        if self.relation == "below":
            return d < 0 and d <= -self.allowed
        if self.relation == "above":
            return d > 0 and d >= self.allowed
        if self.relation == "differs":
            return d != 0 and abs(d) >= self.allowed
        return abs(d) <= self.allowed

    def tolerance_text(self) -> str:
        """The tolerance in words: ``"±3σ"``, ``"±0.05"``, ``"±3σ + 0.05"``; a bound ``"≤ +3σ"``,
        ``"≥ −3σ"``; a resolved difference ``"below by 3σ"``, ``"above by 3σ"``, ``"differs by
        3σ"``; without standard error or tolerance ``"exact"``, ``"≤"``, ``"below"``, ....

        Returns
        -------
        str
        """
        parts = []
        # a quantity not measured has no standard error: its tolerance is still nσ
        if self.combined_sigma > 0 or (self.sigma is None and finite_number(self.measured) is None):
            parts.append(f"{self.sigmas:.3g}σ")
        if self.tolerance > 0:
            parts.append(f"{self.tolerance:.2g}")
        if not parts:
            return {"equal": "exact", "at_most": "≤", "at_least": "≥", "below": "below",
                    "above": "above", "differs": "differs"}[self.relation]
        text = " + ".join(parts)
        return {"equal": "±", "at_most": "≤ +", "at_least": "≥ −", "below": "below by ",
                "above": "above by ", "differs": "differs by "}[self.relation] + text


def _checks(x) -> tuple:
    """``x`` (None, a Check or a sequence of Checks) as a tuple of Checks."""
    if x is None:
        return ()
    return (x,) if isinstance(x, Check) else tuple(x)


def _all_hold(checks) -> bool:
    """Whether there is at least one check and every one holds."""
    checks = _checks(checks)
    return bool(checks) and all(c.holds() for c in checks)


@dataclass(frozen=True)
class Verdict:
    """The judgement of one claim (made by :func:`judge`; :meth:`to_dict` is what the summary
    holds).

    Attributes
    ----------
    claim : str
        The claim in one line, with the paper's figure or equation.
    check : Check
        The measured quantity against its expected value.
    status : str
        One of :data:`STATUSES`.
    explanation : Check, tuple of Check or None
        The checks that explain a failure (given to :func:`judge`; kept whatever the status).
    why : str
        The explanation, refutation or reason it is not measured, in words ("" when none).
    refutation : Check, tuple of Check or None
        The checks that show the claim false and its cause.
    resolution : Check or None
        The check that the run resolves the claim (fails: ``not measured``).
    measured_at : str
        The size that measures the claim when this one does not ("" when not needed).
    short : str
        The claim in a few words, for the table ("" when none: the claim is shortened).
    """

    claim: str
    check: Check
    status: str
    explanation: Check | tuple | None = None
    why: str = ""
    refutation: Check | tuple | None = None
    resolution: Check | None = None
    measured_at: str = ""
    short: str = ""

    def to_dict(self) -> dict:
        """The JSON-able record of the summary: ``claim``, ``short``, ``quantity``,
        ``measured``, ``sigma``, ``expected``, ``expected_sigma``, ``source``, ``n_sigma``,
        ``tolerance``, ``relation``, ``dof``, ``expected_dof``, ``combined_dof``,
        ``sigma_source``, ``trials``, ``t_law``, ``sigmas`` (the standard errors allowed),
        ``allowed``, ``tolerance_text``, ``deviation_in_sigma`` (None without a standard
        error), ``status``, ``why``, ``measured_at``,
        ``explanation`` (the same fields for the explaining check, with ``holds``, and
        ``requires``: the records of the checks before it that must hold too; None when none),
        ``refutation`` (the same for the refuting checks) and ``resolution`` (the record of the
        check that the run resolves the claim, with ``holds``; None when none).

        Returns
        -------
        dict
            JSON-able (non-finite measured values become None).
        """
        return {"claim": self.claim, "short": self.short, **_check_dict(self.check),
                "status": self.status, "why": self.why, "measured_at": self.measured_at,
                "explanation": _chain_dict(self.explanation),
                "refutation": _chain_dict(self.refutation),
                "resolution": (None if self.resolution is None
                               else {**_check_dict(self.resolution),
                                     "holds": self.resolution.holds()})}


def _chain_dict(checks) -> dict | None:
    """The record of a chain of checks: the last one's fields with ``holds``, and ``requires``
    the records of the others (each with ``holds``)."""
    checks = _checks(checks)
    if not checks:
        return None
    *first, last = checks
    return {**_check_dict(last), "holds": last.holds(),
            "requires": [{**_check_dict(c), "holds": c.holds()} for c in first]}


def _check_dict(c: Check) -> dict:
    d = asdict(c)
    d["measured"] = finite_number(c.measured)
    sigma = c.combined_sigma
    dev = c.deviation
    d["allowed"] = c.allowed
    d["sigmas"] = c.sigmas
    d["tolerance_text"] = c.tolerance_text()
    d["deviation_in_sigma"] = None if dev is None or sigma == 0 else dev / sigma
    d["combined_dof"] = c.combined_dof
    return d


def _check_list(value, name: str) -> tuple:
    """``value`` as a tuple of Checks, refused naming ``name`` when it is not None, a Check or
    a non-empty sequence of Checks."""
    if value is None:
        return ()
    if isinstance(value, Check):
        return (value,)
    if isinstance(value, (list, tuple)) and value and all(isinstance(c, Check) for c in value):
        return tuple(value)
    raise InvalidArgumentError(name, value, "a Check, a non-empty sequence of Check, or None")


def judge(claim: str, check: Check, explanation=None, why: str = "", *, refutation=None,
          resolution: Check | None = None, measured_at: str = "", short: str = "") -> Verdict:
    """The verdict on ``claim``: ``not measured`` when a ``resolution`` is given and fails;
    else ``agrees`` when ``check`` holds; else ``explained`` when an ``explanation`` is given
    and all its checks hold; else ``refuted`` when a ``refutation`` is given and all its checks
    hold; else ``disagrees``.

    Parameters
    ----------
    claim : str
        The claim in one line, with the paper's figure or equation (non-empty).
    check : Check
        The measured quantity the claim stands on.
    explanation : Check or sequence of Check, optional
        The claim holds once a named measurement artefact is removed: independent checks that
        all hold when the artefact is what makes ``check`` fail (the same quantity once the
        artefact is removed; a precondition first, e.g. molecular chaos at the window's start).
        Never the check's complement or a restatement of it (the judge cannot tell: each
        comparison's tests feed it a failure that no artefact explains).
    why : str, optional
        The explanation, refutation or reason for ``not measured``, in words.
    refutation : Check or sequence of Check, optional
        The claim is false and the run shows its cause: independent checks that all hold when
        the cause is what makes ``check`` fail (e.g. the model with the cause removed agrees).
    resolution : Check, optional
        Holds when the run resolves the claim (its size, times, scales); when it fails the
        status is ``not measured`` whatever ``check`` says.
    measured_at : str, optional
        The size that measures the claim (required with ``resolution``), e.g. ``"default"``.
    short : str, optional
        The claim in a few words for the table (default: the claim, shortened).

    Returns
    -------
    Verdict

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``claim`` if it is empty, ``check``, ``explanation``, ``refutation`` or
        ``resolution`` if not a :class:`Check` (or a sequence of them), and ``measured_at``
        when a ``resolution`` comes without it.
    """
    if not isinstance(claim, str) or not claim.strip():
        raise InvalidArgumentError("claim", claim, "a non-empty line of text")
    if not isinstance(check, Check):
        raise InvalidArgumentError("check", check, "a Check")
    explained_by = _check_list(explanation, "explanation")
    refuted_by = _check_list(refutation, "refutation")
    if resolution is not None and not isinstance(resolution, Check):
        raise InvalidArgumentError("resolution", resolution, "a Check or None")
    if resolution is not None and not (isinstance(measured_at, str) and measured_at.strip()):
        raise InvalidArgumentError("measured_at", measured_at,
                                   "the size that measures the claim, with a resolution")
    if resolution is not None and not resolution.holds():
        status = "not measured"
    elif check.holds():
        status = "agrees"
    elif _all_hold(explained_by):
        status = "explained"
    elif _all_hold(refuted_by):
        status = "refuted"
    else:
        status = "disagrees"
    return Verdict(claim, check, status,
                   explained_by[0] if len(explained_by) == 1 else (explained_by or None), why,
                   refuted_by[0] if len(refuted_by) == 1 else (refuted_by or None), resolution,
                   measured_at, short)


def welch_dof(*parts) -> float | None:
    """The Welch–Satterthwaite degrees of freedom of a sum in quadrature of standard errors:
    (Σ σᵢ²)² / Σ σᵢ⁴/νᵢ over the parts ``(σᵢ, νᵢ)`` with σᵢ > 0 (νᵢ None: infinite, it adds
    nothing to the denominator).

    Parameters
    ----------
    *parts : (float, float or None)
        Each standard error with its degrees of freedom.

    Returns
    -------
    float or None
        None (infinite) when every part with σ > 0 has infinite degrees of freedom, or none
        has σ > 0.
    """
    parts = [(float(s), nu) for s, nu in parts if finite_number(s) is not None and s > 0]
    finite = [(s, nu) for s, nu in parts if nu is not None]
    if not finite:
        return None
    if len(parts) == 1:
        return float(parts[0][1])  # one part: its own degrees of freedom, exactly
    total = sum(s * s for s, _ in parts)
    return total * total / sum(s**4 / nu for s, nu in finite)


def with_verdicts(summary: dict, verdicts: Callable[[dict], Iterable[Verdict]]) -> dict:
    """``summary`` with ``summary["verdicts"]`` set to the records of ``verdicts(summary)``.

    The one line every comparison's ``run`` ends with:
    ``return Comparison(NAME, with_verdicts(summary, verdicts), data)``.

    Parameters
    ----------
    summary : dict
        The comparison's summary (modified in place and returned).
    verdicts : callable
        ``verdicts(summary) -> iterable of Verdict``, reading only the summary.

    Returns
    -------
    dict
        ``summary``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``verdicts`` when it returns nothing or something that is not a Verdict.
    """
    made = list(verdicts(summary))
    if not made or not all(isinstance(v, Verdict) for v in made):
        raise InvalidArgumentError("verdicts", made, "a non-empty list of Verdict")
    summary["verdicts"] = [v.to_dict() for v in made]
    return summary


def disagreeing(summaries: dict) -> list[tuple[str, dict]]:
    """The verdicts that fail the run (status in :data:`FAILING`: ``disagrees``, a claim this
    size resolves failed) in ``{name: summary}``, as ``(name, record)``; ``not measured`` and
    ``refuted`` are not among them.

    Parameters
    ----------
    summaries : dict
        ``{comparison name: summary}`` (as in ``summary.json``'s ``comparisons``); a summary
        without ``verdicts`` contributes none.

    Returns
    -------
    list of (str, dict)
    """
    return [(name, v) for name, s in summaries.items()
            for v in s.get("verdicts", []) if v.get("status") in FAILING]


def status_counts(summaries: dict) -> dict:
    """The number of verdicts of each status in ``{name: summary}``, every status of
    :data:`STATUSES` present (0 when none), in that order.

    Parameters
    ----------
    summaries : dict
        ``{comparison name: summary}``.

    Returns
    -------
    dict
        ``{status: count}``.
    """
    counts = dict.fromkeys(STATUSES, 0)
    for s in summaries.values():
        for v in s.get("verdicts", []):
            counts[v["status"]] = counts.get(v["status"], 0) + 1
    return counts


def _fmt(x) -> str:
    x = finite_number(x)
    return "—" if x is None else f"{x:.4g}"


def _value_text(value, sigma) -> str:
    """``"value ± σ"`` (``"value"`` without a standard error), 4 significant digits."""
    return _fmt(value) + (f" ± {_fmt(sigma)}" if sigma else "")


def measured_text(record: dict) -> str:
    """``"measured ± σ"`` of a verdict record, 4 significant digits.

    Parameters
    ----------
    record : dict
        A verdict record (:meth:`Verdict.to_dict`) or its ``explanation``.

    Returns
    -------
    str
        ``"—"`` when nothing was measured.
    """
    return _value_text(record.get("measured"), record.get("sigma"))


def expected_text(record: dict) -> str:
    """``"expected"`` of a verdict record, with ``"± σ"`` when the expected value is itself
    measured, 4 significant digits.

    Parameters
    ----------
    record : dict
        A verdict record (:meth:`Verdict.to_dict`) or its ``explanation``.

    Returns
    -------
    str
    """
    return _value_text(record.get("expected"), record.get("expected_sigma"))


#: The width of the verdict table's columns: claim, measured ± σ, expected, z, dof, status.
_WIDTHS = (31, 19, 17, 6, 5, 17)
#: The widest line of the table.
TABLE_WIDTH = 100


def _cut(text: str, width: int) -> str:
    """``text`` in at most ``width`` characters (cut with "…")."""
    text = " ".join(str(text).split())
    return text if len(text) <= width else text[: width - 1] + "…"


def _short_claim(v: dict) -> str:
    return v.get("short") or v["claim"]


def _z_text(v: dict) -> str:
    z = finite_number(v.get("deviation_in_sigma"))
    if z is None:
        return "—"
    return f"{z:+.1f}" if abs(z) < 999.5 else ("> +999" if z > 0 else "< −999")


def _dof_text(v: dict) -> str:
    """The degrees of freedom of a record's z (its ``combined_dof``): ``"3"``, ``"3.6"``, ``"∞"``
    for a normal law, ``"—"`` without a z or in a record without them; ``"2×11"`` for the
    largest |z| of 11 values (``trials``)."""
    if finite_number(v.get("deviation_in_sigma")) is None or "combined_dof" not in v:
        return "—"
    dof = finite_number(v.get("combined_dof"))
    text = "∞" if dof is None else f"{dof:.0f}" if abs(dof - round(dof)) < 0.05 or dof >= 99.5 \
        else f"{dof:.1f}"
    trials = v.get("trials", 1)
    return text + (f"×{trials}" if isinstance(trials, int) and trials > 1 else "")


def _where_measured(measured_at: str) -> str:
    """Where a claim not measured at a size is measured, in words: "measured at --full" for a
    size of ``reproduce`` (one word), else "measured on <measured_at>" (a description, e.g. a
    grid that no size uses yet).

    Parameters
    ----------
    measured_at : str
        A verdict's ``measured_at``.

    Returns
    -------
    str
    """
    if " " not in measured_at.strip():
        return f"measured at --{measured_at.strip()}"
    return f"measured on {measured_at}"


def verdict_table(summaries: dict) -> str:
    """The verdict table for a terminal, no line wider than :data:`TABLE_WIDTH` (100): a
    header, then per comparison its name and one row per claim (the claim in a few words,
    measured ± σ, expected (± σ when measured), z = deviation / combined σ, the degrees of
    freedom of z's Student's t law (``combined_dof``; ∞: a normal law; ``×k``: the largest |z|
    of k values), status); a status
    other than ``agrees`` carries a note number, and the notes below the table say why
    (explanation, refutation, the size that measures a claim not measured here).  Every
    detail stays in ``summary.json``.

    Parameters
    ----------
    summaries : dict
        ``{comparison name: summary}``; the verdicts are read from each ``summary["verdicts"]``.

    Returns
    -------
    str
        The table (no trailing newline), ending with the count of each status and what exit
        status 3 means; ``"no verdicts"`` when there are none.
    """
    wc, wm, we, wz, wd, _ = _WIDTHS  # the status: up to "not measured [99]"
    head = (f"{'claim':<{wc}} {'measured ± σ':>{wm}} {'expected':>{we}} {'z':>{wz}} "
            f"{'dof':>{wd}}  status")
    lines, notes = [head, "─" * len(head)], []
    for name, s in summaries.items():
        records = s.get("verdicts", [])
        if not records:
            continue
        lines.append(f"{name}:")
        for v in records:
            status = v["status"]
            if status != "agrees":
                notes.append((len(notes) + 1, v))
                status = f"{status} [{len(notes)}]"
            if v["status"] == "not measured":
                measured, z, dof = "—", "—", "—"
            else:
                measured, z, dof = _cut(measured_text(v), wm), _z_text(v), _dof_text(v)
            lines.append(f"  {_cut(_short_claim(v), wc - 2):<{wc - 2}} {measured:>{wm}} "
                         f"{_cut(expected_text(v), we):>{we}} {z:>{wz}} {_cut(dof, wd):>{wd}}  "
                         f"{status}")
    if len(lines) == 2:
        return "no verdicts"
    lines.append("─" * len(head))
    for number, v in notes:
        if v["status"] == "not measured":
            text = f"{_where_measured(v['measured_at'])}, not at this size: {v['why']}"
        elif v["status"] == "disagrees":
            text = f"{measured_text(v)} vs {expected_text(v)} ({v['source']}), " \
                   f"{v['tolerance_text']}: {v['quantity']}"
        else:
            text = v["why"] or v["quantity"]
        lines.append(_cut(f"[{number}] {v['status']}: {text}", TABLE_WIDTH))
    counts = status_counts(summaries)
    lines.append(", ".join(f"{n} {k}" for k, n in counts.items()))
    lines.append("dof: of z's Student's t law (∞: normal; ×k: the largest |z| of k values)")
    lines.append("exit 3 when a claim this size resolves disagrees; not measured and refuted "
                 "do not fail")
    return "\n".join(lines)


def pooled_ratio(rows: Iterable[dict]) -> tuple[float | None, float | None]:
    """χ²/(dof·φ) pooled over histogram comparisons (records with ``chi2_dof``, ``dof`` and
    ``overdispersion`` [φ, error]): Σ χ²ᵢ/φᵢ over Σ dofᵢ, and its standard error under the null,
    √(2/Σ dof + mean((δφ/φ)²)) (χ² scatter of the pooled dof, and φ's own relative error).

    Parameters
    ----------
    rows : iterable of dict
        Histogram comparison summaries.

    Returns
    -------
    (float, float) or (None, None)
        The pooled ratio and its standard error; (None, None) when no row has a finite φ > 0.
    """
    chi, dof, rel = 0.0, 0, []
    for row in rows:
        phi, phi_err = row["overdispersion"]
        phi, phi_err = finite_number(phi), finite_number(phi_err)
        if phi is None or phi <= 0 or finite_number(row.get("chi2_dof")) is None:
            continue
        chi += row["chi2_dof"] * row["dof"] / phi
        dof += row["dof"]
        rel.append((phi_err or 0.0) / phi)
    if dof == 0:
        return None, None
    return chi / dof, math.sqrt(2.0 / dof + sum(r * r for r in rel) / len(rel))


def pair(entry) -> tuple[float | None, float | None]:
    """``(value, standard error)`` of a summary entry ``[value, error]`` (or a bare number,
    error None); ``(None, None)`` for a missing entry.  Non-finite numbers become None.

    Parameters
    ----------
    entry : list, tuple, float or None
        A summary entry.

    Returns
    -------
    (float or None, float or None)
    """
    if isinstance(entry, (list, tuple)) and len(entry) == 2:
        return finite_number(entry[0]), finite_number(entry[1])
    return finite_number(entry), None
