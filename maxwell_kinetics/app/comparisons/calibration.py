"""Calibration of the verdicts' standard errors: is z = (measured − expected)/σ of the agreeing
checks distributed as their σ says?

Each check's z has its own law.  A σ that is the standard error of a mean over R seeds, with
the scatter of those seeds, makes z a Student's t with R − 1 degrees of freedom (the check's
``combined_dof``; with a measured expected value, the Welch–Satterthwaite degrees of freedom
of both); a σ from a law (a χ² null expectation, binomial counts, a solver's error floor) or
from many runs makes z normal (degrees of freedom None: infinite).  A check that is the
largest |z| of ``trials`` values (a scan over times) has the p-value of a maximum,
1 − (1 − p)^trials (Šidák: the values taken as independent).  :func:`p_value` turns a z into
its two-sided p-value under that law and :func:`normal_z` into the normal z of the same
p-value; :func:`z_calibration` counts the normal-equivalent z beyond 1, 2 and 3, and measures
how far the p-values are from uniform (Kolmogorov–Smirnov distance and its p-value; the
binomial tail of the count beyond 2σ).

Reads verdict records (:meth:`.verdicts.Verdict.to_dict`); imports nothing from the rest of
the package.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from particles.validation import InvalidArgumentError

from .verdicts import finite_number

__all__ = ["Z_THRESHOLDS", "p_value", "normal_z", "z_calibration"]

#: The |z| thresholds of :func:`z_calibration`, in normal standard errors.
Z_THRESHOLDS = (1, 2, 3)


def p_value(z: float, dof: float | None = None, trials: int = 1) -> float:
    """The two-sided p-value of a deviation of ``z`` standard errors: P(|T| ≥ |z|) for T a
    Student's t with ``dof`` degrees of freedom (normal when ``dof`` is None), and for the
    largest of ``trials`` such values 1 − (1 − p)^trials.

    Parameters
    ----------
    z : float
        Deviation over standard error.
    dof : float or None, optional
        Degrees of freedom of the standard error (None: known exactly, a normal law).
    trials : int, optional
        The number of values ``z`` is the largest |z| of (default 1).

    Returns
    -------
    float
        In [0, 1].

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``z`` (not finite), ``dof`` (not None nor a number > 0) or ``trials`` (not an
        integer ≥ 1).
    """
    from scipy import stats

    if finite_number(z) is None:
        raise InvalidArgumentError("z", z, "a finite number")
    if dof is not None and (finite_number(dof) is None or dof <= 0):
        raise InvalidArgumentError("dof", dof, "None (infinite) or a finite number > 0")
    if isinstance(trials, bool) or not isinstance(trials, int) or trials < 1:
        raise InvalidArgumentError("trials", trials, "an integer >= 1")
    law = stats.norm if dof is None else stats.t(dof)
    p = float(2.0 * law.sf(abs(z)))
    # 1 − (1 − p)^k without the cancellation of small p
    return p if trials == 1 else float(-math.expm1(trials * math.log1p(-min(p, 1.0))))


def normal_z(z: float, dof: float | None = None, trials: int = 1) -> float:
    """The normal z of the same two-sided p-value as ``z`` under its own law (:func:`p_value`),
    with the sign of ``z``: ``z`` itself for a normal law and one trial, smaller in size for
    few degrees of freedom or many trials.

    Parameters
    ----------
    z, dof, trials
        As for :func:`p_value`.

    Returns
    -------
    float
        Finite (capped at ±38, the normal quantile of the smallest double).
    """
    from scipy import stats

    p = p_value(z, dof, trials)
    if dof is None and trials == 1:
        return float(z)
    return math.copysign(min(float(stats.norm.isf(max(p, 5e-324) / 2.0)), 38.0), z)


def _short_claim(v: dict) -> str:
    return v.get("short") or v["claim"]


def _comparison_summaries(summary: dict) -> dict:
    """``{name: comparison summary}`` of a ``reproduce`` summary (with ``comparisons``), or of
    a mapping that already is one."""
    comparisons = summary.get("comparisons")
    return comparisons if isinstance(comparisons, dict) else summary


def _law(v: dict, student: bool) -> tuple[float | None, int]:
    """(degrees of freedom, trials) of a record's z: its ``combined_dof`` (a record of before
    the degrees of freedom: None, normal) and ``trials``; (None, 1) when not ``student``."""
    if not student:
        return None, 1
    dof = finite_number(v.get("combined_dof"))
    trials = v.get("trials", 1)
    return (dof if dof is not None and dof > 0 else None,
            trials if isinstance(trials, int) and trials >= 1 else 1)


def z_calibration(summary: dict, *, statuses: Iterable[str] | None = None,
                  relations: Iterable[str] | None = None, student: bool = True) -> dict:
    """Whether the standard errors of the verdicts are calibrated: how many of the statistical
    checks (the verdict records with a finite ``deviation_in_sigma`` z) lie beyond 1, 2 and 3
    normal σ once each z is converted to the normal z of its own p-value (:func:`normal_z`,
    with the record's ``combined_dof`` and ``trials``), against the counts a calibrated set
    gives (fractions 0.3173, 0.0455, 0.0027), and how far the p-values are from uniform.

    Only the top-level check of each verdict counts (not its explanation, refutation or
    resolution).  A check whose claim is a resolved difference (relation ``below``, ``above``,
    ``differs``), or a verdict that is explained or refuted, is expected to lie far from its
    value: ``statuses`` and ``relations`` select a subset.

    Parameters
    ----------
    summary : dict
        The summary of ``reproduce`` (``{"comparisons": {name: summary}}``) or
        ``{name: summary}``; each comparison's ``verdicts`` is a list of records
        (:meth:`.verdicts.Verdict.to_dict`).
    statuses : iterable of str, optional
        Count only the verdicts with one of these statuses (all when None).
    relations : iterable of str, optional
        Count only the checks with one of these relations (all when None).
    student : bool, optional
        Each z under its own law (default); False: every z under a normal law, one trial (the
        calibration as if every σ were exact).

    Returns
    -------
    dict
        ``n`` (the number of checks with a finite z); ``observed`` and ``expected``
        (``{k: count}`` of normal z beyond ±k for k = 1, 2, 3; expected ``n`` times the normal
        two-sided fraction); ``fractions`` (those fractions); ``p_value`` (two-sided binomial
        p-value of the count beyond 2σ, :func:`scipy.stats.binomtest`) and ``tail_p`` (its
        upper tail, P(count ≥ observed)); ``ks`` and ``ks_p`` (Kolmogorov–Smirnov distance of
        the checks' p-values from the uniform law, and its p-value); ``rms_z`` (rms of the
        normal z; 1 when calibrated) (all None when ``n`` is 0); ``beyond_2sigma`` (a list of
        ``{"comparison", "claim", "z", "z_normal", "p", "dof", "trials", "status",
        "relation"}`` for normal z beyond ±2, largest first; ``claim`` is the short claim).

    Raises
    ------
    InvalidArgumentError
        If ``summary`` is not a dict, or a comparison's ``verdicts`` is not a list.
    """
    if not isinstance(summary, dict):
        raise InvalidArgumentError("summary", summary, "a dict (the summary of reproduce)")
    statuses = None if statuses is None else set(statuses)
    relations = None if relations is None else set(relations)
    zs, ps, beyond = [], [], []
    for name, entry in _comparison_summaries(summary).items():
        records = entry.get("verdicts", []) if isinstance(entry, dict) else []
        if not isinstance(records, list):
            raise InvalidArgumentError(f"{name}.verdicts", records, "a list of verdict records")
        for v in records:
            z = finite_number(v.get("deviation_in_sigma"))
            if z is None:
                continue
            if statuses is not None and v.get("status") not in statuses:
                continue
            if relations is not None and v.get("relation") not in relations:
                continue
            dof, trials = _law(v, student)
            zn, p = normal_z(z, dof, trials), p_value(z, dof, trials)
            zs.append(zn)
            ps.append(p)
            if abs(zn) > 2:
                beyond.append({"comparison": name, "claim": _short_claim(v), "z": z,
                               "z_normal": zn, "p": p, "dof": dof, "trials": trials,
                               "status": v.get("status"), "relation": v.get("relation")})
    n = len(zs)
    fractions = {k: math.erfc(k / math.sqrt(2.0)) for k in Z_THRESHOLDS}
    observed = {k: sum(abs(z) > k for z in zs) for k in Z_THRESHOLDS}
    out = {"n": n, "observed": observed, "expected": {k: n * f for k, f in fractions.items()},
           "fractions": fractions, "p_value": None, "tail_p": None, "ks": None, "ks_p": None,
           "rms_z": None}
    if n:
        from scipy.stats import binomtest, kstest

        test = binomtest(observed[2], n, fractions[2])
        ks = kstest(ps, "uniform")
        out.update(p_value=float(test.pvalue),
                   tail_p=float(binomtest(observed[2], n, fractions[2],
                                          alternative="greater").pvalue),
                   ks=float(ks.statistic), ks_p=float(ks.pvalue),
                   rms_z=math.sqrt(sum(z * z for z in zs) / n))
    beyond.sort(key=lambda r: -abs(r["z_normal"]))
    out["beyond_2sigma"] = beyond
    return out
