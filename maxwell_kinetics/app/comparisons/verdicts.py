"""Verdicts: each claim a comparison tests, judged from the numbers of its summary.

A :class:`Check` is one measured quantity with its standard error against an expected value
with its source (an exact result, the paper's number, another model) and a tolerance: a number
of standard errors, a stated absolute tolerance, or both (allowed deviation
``n_sigma · σ + tolerance``, with σ the measured and the expected standard errors added in
quadrature).  :func:`judge` turns a claim and its check into a :class:`Verdict`:

``agrees``
    the check holds;
``explained``
    the check fails, and a second check, the explanation (the number that shows why it fails,
    e.g. the same quantity once the known cause is removed), holds;
``disagrees``
    the check fails and no explanation holds (or the quantity could not be measured).

No status is ever written by hand: it always comes from :func:`judge`.  Every comparison module
has ``verdicts(summary) -> list[Verdict]`` reading only its own summary, and its ``run`` ends
with ``return Comparison(NAME, with_verdicts(summary, verdicts), data)``; ``reproduce`` prints
:func:`verdict_table` and exits with status 3 when :func:`disagreeing` finds a verdict that
disagrees.

This module imports nothing from the rest of the package.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass

from particles.validation import InvalidArgumentError

__all__ = [
    "STATUSES",
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
]

#: The statuses a verdict can have.
STATUSES = ("agrees", "disagrees", "explained")

_RELATIONS = ("equal", "at_most", "at_least", "below", "above", "differs")


def _number(x) -> float | None:
    """``x`` as a finite float, or None (a missing fit, NaN or infinity)."""
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
        Number of combined standard errors allowed (default 3).
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

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``relation``, ``n_sigma``, ``tolerance``, ``sigma`` or ``expected`` for a value
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

    def __post_init__(self):
        if self.relation not in _RELATIONS:
            raise InvalidArgumentError("relation", self.relation, "one of " + ", ".join(_RELATIONS))
        for name in ("n_sigma", "tolerance"):
            value = _number(getattr(self, name))
            if value is None or value < 0:
                raise InvalidArgumentError(name, getattr(self, name), "a finite number >= 0")
        for name in ("sigma", "expected_sigma"):
            value = getattr(self, name)
            if value is not None and (_number(value) is None or value < 0):
                raise InvalidArgumentError(name, value, "None or a finite number >= 0")
        if self.expected is not None and _number(self.expected) is None:
            raise InvalidArgumentError("expected", self.expected,
                                       "a finite number, or None when not measured")

    @property
    def combined_sigma(self) -> float:
        """√(σ² + σ_expected²), 0 when neither is given."""
        return math.hypot(self.sigma or 0.0, self.expected_sigma or 0.0)

    @property
    def allowed(self) -> float:
        """The largest deviation that still agrees: ``n_sigma · combined_sigma + tolerance``."""
        return self.n_sigma * self.combined_sigma + self.tolerance

    @property
    def deviation(self) -> float | None:
        """measured − expected (None when either is not measured)."""
        m = _number(self.measured)
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
        if self.combined_sigma > 0 or (self.sigma is None and _number(self.measured) is None):
            parts.append(f"{self.n_sigma:g}σ")
        if self.tolerance > 0:
            parts.append(f"{self.tolerance:.2g}")
        if not parts:
            return {"equal": "exact", "at_most": "≤", "at_least": "≥", "below": "below",
                    "above": "above", "differs": "differs"}[self.relation]
        text = " + ".join(parts)
        return {"equal": "±", "at_most": "≤ +", "at_least": "≥ −", "below": "below by ",
                "above": "above by ", "differs": "differs by "}[self.relation] + text


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
        ``"agrees"``, ``"disagrees"`` or ``"explained"`` (:data:`STATUSES`).
    explanation : Check or None
        The check that explains a failure (given to :func:`judge`; kept whatever the status).
    why : str
        The explanation in words ("" when none).
    """

    claim: str
    check: Check
    status: str
    explanation: Check | None = None
    why: str = ""

    def to_dict(self) -> dict:
        """The JSON-able record of the summary: ``claim``, ``quantity``, ``measured``,
        ``sigma``, ``expected``, ``expected_sigma``, ``source``, ``n_sigma``, ``tolerance``,
        ``relation``, ``allowed``, ``tolerance_text``, ``deviation_in_sigma`` (None without a
        standard error), ``status``, ``why`` and ``explanation`` (the same fields for the
        explaining check, with ``holds``; None when none).

        Returns
        -------
        dict
            JSON-able (non-finite measured values become None).
        """
        return {"claim": self.claim, **_check_dict(self.check), "status": self.status,
                "why": self.why,
                "explanation": (None if self.explanation is None
                                else {**_check_dict(self.explanation),
                                      "holds": self.explanation.holds()})}


def _check_dict(c: Check) -> dict:
    d = asdict(c)
    d["measured"] = _number(c.measured)
    sigma = c.combined_sigma
    dev = c.deviation
    d["allowed"] = c.allowed
    d["tolerance_text"] = c.tolerance_text()
    d["deviation_in_sigma"] = None if dev is None or sigma == 0 else dev / sigma
    return d


def judge(claim: str, check: Check, explanation: Check | None = None, why: str = "") -> Verdict:
    """The verdict on ``claim``: ``agrees`` when ``check`` holds; else ``explained`` when an
    ``explanation`` is given and holds; else ``disagrees``.

    Parameters
    ----------
    claim : str
        The claim in one line, with the paper's figure or equation (non-empty).
    check : Check
        The measured quantity the claim stands on.
    explanation : Check, optional
        Why the claim may fail: a check that holds when the known cause is what makes ``check``
        fail (e.g. the same quantity once the cause is removed, or the number that shows the
        regime is not reached).
    why : str, optional
        The explanation in words, shown with an ``explained`` status.

    Returns
    -------
    Verdict

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``claim`` if it is empty, ``check`` or ``explanation`` if not a :class:`Check`.
    """
    if not isinstance(claim, str) or not claim.strip():
        raise InvalidArgumentError("claim", claim, "a non-empty line of text")
    if not isinstance(check, Check):
        raise InvalidArgumentError("check", check, "a Check")
    if explanation is not None and not isinstance(explanation, Check):
        raise InvalidArgumentError("explanation", explanation, "a Check or None")
    if check.holds():
        status = "agrees"
    elif explanation is not None and explanation.holds():
        status = "explained"
    else:
        status = "disagrees"
    return Verdict(claim, check, status, explanation, why)


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
    """The verdicts with status ``disagrees`` in ``{name: summary}``, as ``(name, record)``.

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
            for v in s.get("verdicts", []) if v.get("status") == "disagrees"]


def _fmt(x) -> str:
    x = _number(x)
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


def verdict_table(summaries: dict) -> str:
    """The verdict table, one line per claim: comparison, status, claim, measured ± σ,
    expected and its source, tolerance; an ``explained`` line is followed by its explanation.

    Parameters
    ----------
    summaries : dict
        ``{comparison name: summary}``; the verdicts are read from each ``summary["verdicts"]``.

    Returns
    -------
    str
        The table (no trailing newline), ending with the count of each status.
    """
    rows = []
    counts = dict.fromkeys(STATUSES, 0)
    for name, s in summaries.items():
        for v in s.get("verdicts", []):
            counts[v["status"]] = counts.get(v["status"], 0) + 1
            rows.append((name, v["status"], v["claim"],
                         f"{measured_text(v)} vs {expected_text(v)} ({v['source']}), "
                         f"{v['tolerance_text']}"))
            e = v.get("explanation")
            if v["status"] == "explained" and e is not None:
                rows.append(("", "", f"  why: {v['why']}",
                             f"{e['quantity']}: {measured_text(e)} vs {expected_text(e)}, "
                             f"{e['tolerance_text']}"))
    if not rows:
        return "no verdicts"
    w0 = max(len(r[0]) for r in rows)
    w1 = max(len(r[1]) for r in rows)
    w2 = max(len(r[2]) for r in rows)
    lines = [f"{r[0]:<{w0}}  {r[1]:<{w1}}  {r[2]:<{w2}}  {r[3]}" for r in rows]
    lines.append(", ".join(f"{n} {k}" for k, n in counts.items()))
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
        phi, phi_err = _number(phi), _number(phi_err)
        if phi is None or phi <= 0 or _number(row.get("chi2_dof")) is None:
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
        return _number(entry[0]), _number(entry[1])
    return _number(entry), None
