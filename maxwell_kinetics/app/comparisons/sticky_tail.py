"""The sticky gas's velocity tail against its exact law, for the late-stage comparison: the
deep-tail runs (many gases, their survival P(|w| > w) and its local exponent β per time, in
worker processes when asked) and the exact β(w) curve with its crossings of 2 and 2.5."""

from __future__ import annotations

import numpy as np

from particles.progress import progress_bar
from particles.sticky_comparison import exact_law_runs
from particles.sticky_exact import exact_velocity_survival, exact_velocity_tail_exponent

from .analysis import tail_grid

__all__ = ["deep_tail_runs", "exact_tail", "BETA_AT"]


def deep_tail_runs(params, progress) -> dict:
    """The deep tail: ``deep_seeds`` gases of ``deep_n`` particles, their survival P(|w| > w)
    and its chords β per time of ``deep_times``, against the exact law.

    Parameters
    ----------
    params : dict
        The late-stage comparison's parameters (a preset, with overrides): ``deep_n``,
        ``deep_seeds``, ``deep_times``, ``deep_tail_w``, ``deep_block``, ``deep_workers``,
        ``min_clusters``.
    progress : bool
        Show progress on stderr.

    Returns
    -------
    dict
        ``summary`` (``{"deep_tail": …}``, empty when ``deep_seeds`` is 0) and ``data``.
    """
    count = int(params["deep_seeds"])
    if count == 0:
        return {"summary": {}, "data": {}}
    n, times = int(params["deep_n"]), [float(t) for t in params["deep_times"]]
    grid = tail_grid(*params["deep_tail_w"])
    mc = int(params["min_clusters"])
    block = int(params["deep_block"])
    seeds = list(range(2000, 2000 + count))
    tasks = [seeds[i:i + block] for i in range(0, count, block)]
    workers = min(int(params["deep_workers"]), len(tasks))
    total = None
    with progress_bar(len(tasks), f"sticky deep tail N={n} × {count}", "block",
                      enabled=progress) as bar:
        def join(parts):
            nonlocal total
            if total is None:
                total = parts
            else:
                for a, b in zip(total, parts, strict=True):
                    a.merge(b)
            bar.update(1)

        if workers <= 1:
            for task in tasks:
                join(exact_law_runs(n, task, times, tail_w=grid, min_clusters=mc))
        else:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            # spawn: no fork of a process that holds JAX; the workers import particles only
            ctx = multiprocessing.get_context("spawn")
            with ProcessPoolExecutor(workers, mp_context=ctx) as pool:
                futures = [pool.submit(exact_law_runs, n, task, times, tail_w=grid,
                                       min_clusters=mc) for task in tasks]
                for future in futures:  # joined in seed order
                    join(future.result())
    per_time, data = [], []
    for c in total:
        tail = c.tail()
        z = (tail["beta"] - tail["beta_exact"]) / tail["beta_error"]
        per_time.append({
            "t": c.t, "particles": int(c.particles),
            "beta_w": tail["beta_w"].tolist(), "beta": tail["beta"].tolist(),
            "beta_error": tail["beta_error"].tolist(), "beta_exact": tail["beta_exact"].tolist(),
            "z": z.tolist(), "deepest": tail["deepest"],
        })
        data.append({key: tail[key] for key in ("w", "survival", "survival_error",
                                                  "exact_survival", "resolved")})
    summary = {"deep_tail": {"n": n, "seeds": count, "particles": int(total[0].particles),
                             "times": times, "grid": grid.tolist(), "min_clusters": mc,
                             "per_time": per_time}}
    return {"summary": summary, "data": {"deep_tail": data}}


#: Values of w at which the exact β is always reported (up to ``beta_curve``'s last point).
BETA_AT = (1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 30.0)


def exact_tail(curve) -> dict:
    """The exact β(w) on the points ``curve`` = (w_lo, w_hi, count) (geometric, with the
    :data:`BETA_AT` values inside), its crossings of 2 and 2.5 (cubic spline of β in ln w; β
    increases with w) and the exact P(|w| > w) there.

    Parameters
    ----------
    curve : sequence
        ``(w_lo, w_hi, count)``: the late-stage preset's ``beta_curve``.

    Returns
    -------
    dict
        ``w``, ``beta`` (arrays) and ``summary`` (JSON-ready: ``w``, ``beta``, ``crossings``,
        ``beta_at``, ``limit`` = 3).
    """
    from scipy.interpolate import CubicSpline

    lo, hi, count = float(curve[0]), float(curve[1]), int(curve[2])
    w = np.unique(np.concatenate([np.geomspace(lo, hi, count),
                                  [x for x in BETA_AT if lo <= x <= hi]]))
    beta = exact_velocity_tail_exponent(w)
    spline = CubicSpline(np.log(w), beta)
    crossings = {}
    for level in (2.0, 2.5):
        roots = [r for r in spline.solve(level, extrapolate=False) if np.isfinite(r)]
        if roots:
            wc = float(np.exp(roots[0]))
            crossings[f"{level:g}"] = {"w": wc,
                                       "survival": float(2.0 * exact_velocity_survival(wc))}
        else:
            crossings[f"{level:g}"] = None
    at = {f"{x:g}": float(beta[np.flatnonzero(w == x)[0]]) for x in BETA_AT if lo <= x <= hi}
    return {"w": w, "beta": beta,
            "summary": {"w": w.tolist(), "beta": beta.tolist(), "crossings": crossings,
                        "beta_at": at, "limit": 3.0}}
