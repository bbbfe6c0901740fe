"""The late energy exponent of the MD gas with enough seeds to tell −2/3 from −1/2.

    python benchmarks/md_late_exponent.py              # 24 seeds (about 2–5 min on one core)
    python benchmarks/md_late_exponent.py --seeds 8 --json

The runs are those of comparison 5's small preset (``energy_decay``: r = 0.5, δ = 1e-4,
N = 1000 rods at density 1, Gaussian start, t ≤ 40, recorded at its 36 geometric times) with
seeds 0, 1, …; the first three are the suite's runs.  The fit is the comparison's: slope of
ln E against ln t on t ∈ [12, 40] for each run, mean ± standard error over the runs, and the
window systematic (half the difference of the slopes on the two halves of the window, from the
seeds' mean) added in quadrature.  At the suite's 3 seeds the uncertainty is ≈ 0.1 and −2/3 and
−1/2 are 1.7σ apart; the per-run slopes scatter by ≈ 0.13, so 24 seeds bring the seeds' part to
≈ 0.027.

Checks (exit status 1 if one fails): |slope + 2/3| < 3σ (the sticky-gas exponent) and
|slope + 1/2| > 5σ (not the lattice's diffusive exponent), σ the total uncertainty.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from maxwell_kinetics import statistics as st  # noqa: E402
from maxwell_kinetics.app.comparisons import PRESETS  # noqa: E402
from maxwell_kinetics.app.comparisons.particle_runs import md_record_times, md_runs  # noqa: E402


def measure(seeds: int) -> dict:
    params = PRESETS["energy_decay"]["small"]
    start = time.perf_counter()
    runs = md_runs(params["restitution"], params["md_n"], params["delta"],
                   md_record_times(params["md_t_max"]), tuple(range(seeds)), progress=False)
    seconds = time.perf_counter() - start
    t, e = runs["times"], runs["energy"]
    lo, hi = params["md_late_window"]
    inside = (t >= lo) & (t <= hi)
    x, ys = np.log(t[inside]), np.log(e[:, inside])
    slope, seed_err, per_run = st.seed_slope(x, ys)
    h = x.size // 2
    drift = 0.5 * abs(st.seed_slope(x[h:], ys[:, h:])[0] - st.seed_slope(x[:h + 1],
                                                                       ys[:, :h + 1])[0])
    sigma = math.hypot(seed_err, drift)
    return {
        "n": params["md_n"], "restitution": params["restitution"], "delta": params["delta"],
        "t_max": params["md_t_max"], "window": [lo, hi], "seeds": seeds,
        "slope": slope, "seed_error": seed_err, "window_drift": drift, "uncertainty": sigma,
        "per_run_scatter": float(np.std(per_run, ddof=1)),
        "sigma_from_minus_two_thirds": (slope + 2.0 / 3.0) / sigma,
        "sigma_from_minus_one_half": (slope + 0.5) / sigma,
        "seconds": seconds,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=24)
    ap.add_argument("--json", action="store_true", help="one JSON object on stdout")
    args = ap.parse_args(argv)
    res = measure(args.seeds)
    ok = abs(res["sigma_from_minus_two_thirds"]) < 3 and abs(res["sigma_from_minus_one_half"]) > 5
    res["passed"] = ok
    if args.json:
        print(json.dumps(res))
    else:
        print(f"MD N={res['n']} r={res['restitution']} δ={res['delta']}, {res['seeds']} seeds, "
              f"fit on t ∈ {res['window']}: slope {res['slope']:.4f} ± {res['uncertainty']:.4f} "
              f"(seeds {res['seed_error']:.4f}, window drift {res['window_drift']:.4f}; per-run "
              f"scatter {res['per_run_scatter']:.3f})")
        print(f"  {res['sigma_from_minus_two_thirds']:+.2f}σ from −2/3, "
              f"{res['sigma_from_minus_one_half']:+.2f}σ from −1/2; {res['seconds']:.0f} s; "
              f"{'passed' if ok else 'FAILED'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
