"""The deterministic hard-rod Boltzmann solver against its DSMC (the Ulam engine with the rate
|v − w|), and the cost of each for the same error in the kurtosis; results in
benchmarks/README.md and benchmarks/hard_rods_dsmc.json.

The equation (density n, p = (1 + r)/2, any test function φ):

    d/dt ∫φ f dv = (n/2) ∫∫ |v − w| f(v) f(w) [φ(v′) + φ(w′) − φ(v) − φ(w)] dv dw.

    python benchmarks/hard_rods_dsmc.py agreement  # r = 0.99, 0.9; t = 10, 100, 400
    python benchmarks/hard_rods_dsmc.py scaling    # r = 0.5, 0.9: DSMC at t = 1e6
    python benchmarks/hard_rods_dsmc.py cost       # deterministic error vs grid; DSMC cost
    python benchmarks/hard_rods_dsmc.py all --n 1000000 --seeds 4
    python benchmarks/hard_rods_dsmc.py agreement --n 10000000 --seeds 4 --first-seed 4
    python benchmarks/hard_rods_dsmc.py combined   # the kurtosis over every recorded run

Checks (printed as ``agrees`` / ``disagrees``):

* kurtosis: |K_DSMC − K_det| ≤ 3 σ, σ the standard error of the DSMC mean over the seeds;
* histogram of x = (v − ⟨v⟩)/√var pooled over the seeds (binomial errors) against the
  deterministic bin probabilities (``BoltzmannSolution.histogram``): χ²/dof within
  1 ± 5 √(2/dof) (:meth:`particles.observables.Histogram.distance`);
* the scaling state (``scaling_state``) against DSMC at t = 10⁶ (33 collisions per particle at
  r = 0.5): the kurtosis within 3 σ, the histogram's χ²/dof; the deterministic solution at the
  same t is reported, its distance from the state says how much of the start is left.  (The
  DSMC stops every 4/n of t whatever the cooling, so its cost grows like t, not like the
  collisions: t = 10⁸ is out of reach.)

Cost: the DSMC error of the kurtosis falls as 1/√(N·runs), so the seconds a DSMC needs for an
error ε are (seconds per run) · (σ_run/ε)², σ_run the scatter of one run's kurtosis over the
seeds.  The deterministic error is |K(grid) − K(finest grid)|.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from maxwell_kinetics.inelastic_boltzmann import scaling_state, solve_boltzmann
from maxwell_kinetics.velocity_grid import VelocityGrid
from particles.driver import simulate
from particles.models import get_model
from particles.observables import Histogram, rescaled_histogram

EDGES = np.round(np.arange(-4.0, 4.0 + 1e-9, 0.2), 12)
OUT = Path(__file__).with_suffix(".json")


def dsmc(restitution, n, times, seeds):
    """Central kurtosis per run and time (R, T), pooled histograms per time, seconds per run and
    pair collisions per particle (R, T)."""
    engine = get_model("ulam").build({"n": int(n), "restitution": restitution,
                                      "rate": "relative_velocity", "density": 1.0})
    kurt, hists, seconds, coll = [], [], [], []
    snaps = []
    for seed in seeds:
        # force: the event budget assumes the initial collision rate, which cooling lowers
        res = simulate(engine, list(times), int(seed), progress=False, snapshots=True,
                       force=True)
        x = res.snapshots - res.snapshots.mean(axis=1, keepdims=True)
        m2 = np.mean(x**2, axis=1)
        kurt.append(np.mean(x**4, axis=1) / m2**2)
        snaps.append(x)
        seconds.append(res.seconds)
        coll.append(res.collisions / n)
        print(f"  r={restitution} seed {seed}: {res.seconds:.1f} s, K = {kurt[-1]}", flush=True)
    snaps = np.array(snaps)  # (R, T, N)
    for j in range(len(times)):
        hists.append(rescaled_histogram(snaps[:, j, :], EDGES))
    return np.array(kurt), hists, np.array(seconds), np.array(coll)


def _check_kurtosis(k_runs, expected):
    mean = float(np.mean(k_runs))
    sem = float(np.std(k_runs, ddof=1) / math.sqrt(len(k_runs)))
    z = (mean - expected) / sem
    return {"dsmc": mean, "sigma": sem, "expected": float(expected), "z": z,
            "status": "agrees" if abs(z) <= 3 else "disagrees"}


def _check_histogram(hist: Histogram, predicted: Histogram):
    d = hist.distance(predicted)
    spread = math.sqrt(2.0 / d.dof)
    return {"chi2_dof": d.chi2_dof, "dof": d.dof, "band": [1 - 5 * spread, 1 + 5 * spread],
            "ks": d.ks,
            "status": "agrees" if abs(d.chi2_dof - 1) <= 5 * spread else "disagrees"}


def agreement(n, seeds, restitutions=(0.99, 0.9), times=(10.0, 100.0, 400.0)):
    rows = []
    for r in restitutions:
        det = solve_boltzmann(r, [0.0, *times])
        k, hists, secs, coll = dsmc(r, n, times, seeds)
        for j, t in enumerate(times):
            row = {"restitution": r, "t": t, "n": n, "seeds": len(seeds),
                   "seed_list": [int(x) for x in seeds],
                   "kurtosis_runs": [float(x) for x in k[:, j]],
                   "kurtosis": _check_kurtosis(k[:, j], det.kurtosis[j + 1]),
                   "histogram": _check_histogram(hists[j], det.histogram(EDGES, t=t)),
                   "collisions_per_particle": float(2 * coll[:, j].mean()),
                   "dsmc_seconds_per_run": float(secs.mean())}
            rows.append(row)
            print(json.dumps(row), flush=True)
    return rows


def combined(results):
    """The kurtosis check over every run recorded for each (r, N, t): rows of the same check
    run with other seeds (``--first-seed``) pooled; the histogram checks stay per row."""
    pooled = {}
    for row in results.get("agreement", []):
        if "kurtosis_runs" in row:
            key = (row["restitution"], row["n"], row["t"])
            entry = pooled.setdefault(key, {"runs": [], "seeds": [],
                                            "expected": row["kurtosis"]["expected"]})
            entry["runs"] += row["kurtosis_runs"]
            entry["seeds"] += row["seed_list"]
    out = []
    for (r, n, t), entry in sorted(pooled.items()):
        if len(set(entry["seeds"])) != len(entry["seeds"]):
            raise ValueError(f"r={r}, N={n}, t={t}: a seed is recorded twice")
        row = {"restitution": r, "n": n, "t": t, "seeds": len(entry["seeds"]),
               "kurtosis": _check_kurtosis(np.array(entry["runs"]), entry["expected"])}
        out.append(row)
        print(json.dumps(row), flush=True)
    return out


def scaling(n, seeds, cases=((0.5, 1e6), (0.9, 1e6))):
    rows = []
    for r, t in cases:
        state = scaling_state(r)
        det = solve_boltzmann(r, [0.0, t])
        k, hists, secs, coll = dsmc(r, n, [t], seeds)
        x = 0.5 * (EDGES[1:] + EDGES[:-1])
        # the state's bin probabilities by Simpson's rule on 16 sub-intervals per bin
        sub = np.linspace(0.0, 1.0, 17)
        w = np.ones(17)
        w[1:-1:2], w[2:-1:2] = 4.0, 2.0
        prob = np.array([np.dot(w, state.density(a + (b - a) * sub)) * (b - a) / 48.0
                         for a, b in zip(EDGES[:-1], EDGES[1:], strict=True)])
        width = np.diff(EDGES)
        predicted = Histogram(EDGES, x, prob / width, np.zeros(width.size),
                              np.zeros(width.size, dtype=np.int64), 0, 1.0)
        row = {"restitution": r, "t": t, "n": n, "seeds": len(seeds),
               "deterministic_kurtosis_at_t": float(det.kurtosis[-1]),
               "scaling_state_kurtosis": state.kurtosis,
               "scaling_state_c6": state.moment(6),
               "kurtosis": _check_kurtosis(k[:, 0], state.kurtosis),
               "histogram": _check_histogram(hists[0], predicted),
               "collisions_per_particle": float(2 * coll[:, 0].mean()),
               "dsmc_seconds_per_run": float(secs.mean())}
        rows.append(row)
        print(json.dumps(row), flush=True)
    return rows


def cost(n, seeds, restitution=0.99, t=400.0, points=(61, 81, 101, 151, 201, 301),
         finest=401):
    """Deterministic error of K(t) against grid size and its seconds after compile; the DSMC
    seconds for the same error from its measured per-run scatter."""
    ref = solve_boltzmann(restitution, [0.0, t], grid=VelocityGrid(finest, 6.0))
    k_ref = float(ref.kurtosis[-1])
    det_rows = []
    for m in points:
        grid = VelocityGrid(m, 6.0)
        try:
            solve_boltzmann(restitution, [0.0, t], grid=grid)  # compile for this grid
        except RuntimeError as exc:  # a grid too coarse for the time integration
            det_rows.append({"points": m, "failed": str(exc)})
            print(json.dumps(det_rows[-1]), flush=True)
            continue
        start = time.perf_counter()
        sol = solve_boltzmann(restitution, [0.0, t], grid=grid)
        det_rows.append({"points": m, "seconds": time.perf_counter() - start,
                         "kurtosis": float(sol.kurtosis[-1]),
                         "error": abs(float(sol.kurtosis[-1]) - k_ref)})
        print(json.dumps(det_rows[-1]), flush=True)
    k, _, secs, _ = dsmc(restitution, n, [t], seeds)
    sigma_run = float(np.std(k[:, 0], ddof=1))
    sec_run = float(secs.mean())
    rows = [d for d in det_rows if "failed" in d]
    for d in (d for d in det_rows if "failed" not in d):
        eps = max(d["error"], 1e-12)
        dsmc_seconds = sec_run * (sigma_run / eps) ** 2
        rows.append({**d, "dsmc_seconds_same_error": dsmc_seconds,
                     "ratio": dsmc_seconds / d["seconds"]})
    out = {"restitution": restitution, "t": t, "finest_points": finest,
           "kurtosis_finest": k_ref, "dsmc_n": n, "dsmc_runs": len(seeds),
           "dsmc_seconds_per_run": sec_run, "dsmc_sigma_per_run": sigma_run,
           "dsmc_kurtosis": float(np.mean(k[:, 0])), "rows": rows}
    print(json.dumps(out), flush=True)
    return out


#: What identifies a recorded row: rows of other checks are kept when a check is rerun.
MERGE_KEYS = {
    "scaling": lambda row: row["restitution"],
    "agreement": lambda row: (row["restitution"], row["n"], row.get("seed_list", [0])[0]),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("what", choices=("agreement", "scaling", "cost", "all", "combined"))
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--first-seed", type=int, default=0,
                    help="seeds FIRST, FIRST + 1, ... (more runs of the same check)")
    ap.add_argument("--restitutions", default="0.99,0.9",
                    help="r of the agreement check (rows of other r or N are kept)")
    ap.add_argument("--scaling-cases", default="0.5:1e6,0.9:1e6",
                    help="r:t pairs of the scaling check (rows of other r are kept)")
    args = ap.parse_args(argv)
    seeds = tuple(range(args.first_seed, args.first_seed + args.seeds))
    cases = tuple((float(a), float(b)) for a, b in
                  (c.split(":") for c in args.scaling_cases.split(",")))
    if args.what == "combined":
        results = json.loads(OUT.read_text())
        results["combined"] = combined(results)
        OUT.write_text(json.dumps(results, indent=1) + "\n")
        return 0
    for what in (("agreement", "scaling", "cost") if args.what == "all" else (args.what,)):
        start = time.perf_counter()
        if what == "scaling":
            out = scaling(args.n, seeds, cases)
        elif what == "agreement":
            out = agreement(args.n, seeds,
                            tuple(float(r) for r in args.restitutions.split(",")))
        else:
            out = cost(args.n, seeds)
        results = json.loads(OUT.read_text()) if OUT.exists() else {}  # others may have written
        if what in MERGE_KEYS:  # keep the recorded rows of other checks
            key = MERGE_KEYS[what]
            done = {key(row) for row in out}
            out = [row for row in results.get(what, []) if key(row) not in done] + out
        results[what] = out
        results[what + "_seconds"] = time.perf_counter() - start
        OUT.write_text(json.dumps(results, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
