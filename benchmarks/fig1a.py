"""Fig. 1a: does a lattice whose bonds collide at rate ∝ |Δ| recover MD's two
humps of P(x), x = v/√E, at equal energy in the homogeneous stage?

Measurement only.  r = 0.99, unit Gaussian start, N = 2·10⁴ (the comparison's default size).

* MD (density 1, δ = 1e-4 as in the Fig. 1a comparison) recorded every 25 in t up to 600; the
  target energy E* is the mean over seeds of E(t = 400) (the comparison's early stage).
* Lattice models, each run stopped where its own energy equals E*: the paper's constant-rate
  lattice (τ), and the rate-|Δ| variant (``rate="relative_velocity"``, time t) with and without
  the kinematic constraint.  Stopping as the comparison does: advance on a geometric grid
  (ratio 1.25) until E ≤ E*, interpolate the time in (ln t, ln E), continue from the earlier
  state to it (exact: the state is Markov).
* Per run x = (v − ⟨v⟩)/√var; kurtosis ⟨x⁴⟩ and ⟨|x|⟩; histogram density on [−4, 4] (bins of
  0.2), symmetrised in x; two humps: P(|x| ∈ [0.8, 1]) − P(|x| < 0.2) > 0 (per run, then over
  seeds), and where the largest symmetrised bin lies.
  Mean ± standard error over seeds.  The traces of ⟨x⁴⟩ against E (every recorded point)
  are kept too, with the smallest ⟨x⁴⟩ met on the way down to E* (points with E ≥ 0.8 E*).

Run: ``PYTHONPATH=$PWD python benchmarks/fig1a.py [--n 20000] [--seeds 6]``; writes
``benchmarks/fig1a.json`` and prints a table.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

from particles.driver import simulate
from particles.lattice import Lattice
from particles.md import MDEngine, MDParams

R = 0.99
DELTA = 1e-4
T_TARGET = 400.0
MD_TIMES = np.arange(25.0, 601.0, 25.0)
EDGES = np.arange(-4.0, 4.0 + 1e-9, 0.2)
#: The symmetrised bin |x| ∈ [0.8, 1.0], where MD's P(x) peaks at this energy (measured).
HUMP_BIN = 4


def rescaled(v):
    v = np.asarray(v, dtype=float)
    v = v - v.mean()
    return v / math.sqrt(float(np.mean(v * v)))


def shape(v) -> dict:
    x = rescaled(v)
    dens = np.histogram(x, EDGES)[0] / (x.size * np.diff(EDGES))
    mid = len(dens) // 2  # bins [-0.2, 0) and [0, 0.2)
    sym = 0.5 * (dens[mid:] + dens[:mid][::-1])  # P(|x|)/2 on the bins 0-0.2, 0.2-0.4, ...
    peak = int(np.argmax(sym))
    return {"kurtosis": float(np.mean(x**4)), "abs_mean": float(np.mean(np.abs(x))),
            "p0": float(sym[0]), "p_hump": float(sym[HUMP_BIN]),
            "hump_minus_p0": float(sym[HUMP_BIN] - sym[0]), "pmax": float(sym[peak]),
            "x_peak": float(0.5 * (EDGES[mid + peak] + EDGES[mid + peak + 1])),
            "density": dens.tolist(), "symmetrised": sym.tolist()}


def energy(v) -> float:
    return float(np.mean(np.asarray(v) ** 2))


def md_runs(n, seeds):
    out = []
    for seed in seeds:
        start = time.perf_counter()
        res = simulate(MDEngine(MDParams(n, 1.0, R, delta=DELTA)), MD_TIMES, seed,
                       progress=False, snapshots=True)
        trace = [(float(t), float(e), shape(s)["kurtosis"], 2.0 * c / n)
                 for t, e, s, c in zip(res.times, res.energy, res.snapshots, res.collisions,
                                       strict=True)]
        j = int(np.flatnonzero(res.times == T_TARGET)[0])
        out.append({"seed": seed, "time": T_TARGET, "energy": float(res.energy[j]),
                    "tau": 2.0 * float(res.collisions[j]) / n, "snapshot": res.snapshots[j],
                    "trace": trace, "seconds": time.perf_counter() - start})
    return out


def lattice_at_energy(engine, target, seed):
    """The run of ``engine`` stopped where E = ``target`` (see the module docstring)."""
    start = time.perf_counter()
    n = engine.n
    rng = np.random.default_rng(seed)
    state = engine.initial_state(rng)
    trace = [(0.0, 1.0, shape(state.velocities)["kurtosis"], 0.0)]
    prev, t = state, 1.0
    while True:
        new = engine.advance(prev, t, rng)
        e = energy(new.velocities)
        trace.append((t, e, shape(new.velocities)["kurtosis"], 2.0 * new.collisions / n))
        if e <= target:
            break
        prev, t = new, t * 1.25
    (ta, ea), (tb, eb) = trace[-2][:2], trace[-1][:2]
    if ta <= 0.0 or ea <= eb:
        final = new
    else:
        w = (math.log(ea) - math.log(target)) / (math.log(ea) - math.log(eb))
        t_star = math.exp(math.log(ta) + w * (math.log(tb) - math.log(ta)))
        final = engine.advance(prev, max(t_star, prev.time), rng)
    return {"seed": seed, "time": final.time, "energy": energy(final.velocities),
            "tau": 2.0 * final.collisions / n, "attempts_per_site": final.attempts / n,
            "snapshot": final.velocities, "trace": trace,
            "seconds": time.perf_counter() - start}


def summarise(runs, target) -> dict:
    shapes = [shape(r["snapshot"]) for r in runs]
    out = {}
    for key in ("kurtosis", "abs_mean", "p0", "p_hump", "hump_minus_p0", "pmax", "x_peak",
                "energy", "time", "tau", "seconds"):
        vals = np.array([s[key] for s in shapes] if key in shapes[0] else [r[key] for r in runs])
        out[key] = [float(vals.mean()),
                    float(vals.std(ddof=1) / math.sqrt(len(vals))) if len(vals) > 1 else None]
    for key in ("density", "symmetrised"):
        out[key] = np.array([s[key] for s in shapes]).mean(axis=0).tolist()
    out["per_run_kurtosis"] = [s["kurtosis"] for s in shapes]
    # smallest ⟨x⁴⟩ on the way down to E* (recorded points with E ≥ 0.8 E*, t > 0)
    out["min_kurtosis_along_trace"] = [
        float(min(k for t, e, k, _ in r["trace"] if t > 0 and e >= 0.8 * target)) for r in runs
    ]
    out["traces"] = [r["trace"] for r in runs]
    return out


#: Energies at which the ⟨x⁴⟩ traces are compared (interpolated linearly in ln E between
#: recorded points: every 25 in t for MD, a ratio 1.25 in time for the lattices).
TRACE_ENERGIES = (0.5, 0.3, 0.2, 0.1, 0.06, 0.045)


def kurtosis_at_energies(traces, energies=TRACE_ENERGIES):
    """Mean ± standard error over runs of ⟨x⁴⟩ at each energy (interpolated in ln E)."""
    rows = []
    for tr in traces:
        tr = np.asarray(tr)
        order = np.argsort(tr[:, 1])
        rows.append(np.interp(np.log(energies), np.log(tr[order, 1]), tr[order, 2]))
    rows = np.array(rows)
    return rows.mean(axis=0), rows.std(axis=0, ddof=1) / math.sqrt(len(rows))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20_000)
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--out", default=str(Path(__file__).with_name("fig1a.json")))
    args = ap.parse_args(argv)
    seeds = list(range(args.seeds))
    md = md_runs(args.n, seeds)
    target = float(np.mean([m["energy"] for m in md]))
    models = {"md": summarise(md, target)}
    engines = {
        "lattice_constant": Lattice(args.n, R),
        "lattice_rel_velocity": Lattice(args.n, R, rate="relative_velocity"),
        "lattice_rel_velocity_no_constraint": Lattice(args.n, R, constraint=False,
                                                      rate="relative_velocity"),
    }
    for name, engine in engines.items():
        models[name] = summarise([lattice_at_energy(engine, target, s) for s in seeds], target)
    result = {"restitution": R, "delta": DELTA, "n": args.n, "seeds": seeds,
              "md_time": T_TARGET, "target_energy": target, "edges": EDGES.tolist(),
              "models": models}
    for m in models.values():
        mean, se = kurtosis_at_energies(m["traces"])
        m["kurtosis_at_energies"] = {"energies": list(TRACE_ENERGIES), "mean": mean.tolist(),
                                     "se": se.tolist()}
    Path(args.out).write_text(json.dumps(result, indent=1))

    def pm(v, fmt="{:.3f}"):
        return fmt.format(v[0]) + " ± " + (fmt.format(v[1]) if v[1] is not None else "-")

    print(f"r = {R}, N = {args.n}, {len(seeds)} seeds, E* = {target:.5f} (MD mean at t = 400)")
    print(f"{'model':36s} {'<x^4>':>15s} {'<|x|>':>15s} {'P(0)':>15s} {'P(0.9)-P(0)':>16s} "
          f"{'x_max':>6s} {'time':>14s} {'tau':>14s} {'min <x^4>':>9s} {'s/run':>6s}")
    for name, m in models.items():
        print(f"{name:36s} {pm(m['kurtosis']):>15s} {pm(m['abs_mean']):>15s} "
              f"{pm(m['p0']):>15s} {pm(m['hump_minus_p0']):>16s} {m['x_peak'][0]:6.2f} "
              f"{pm(m['time'], '{:.1f}'):>14s} {pm(m['tau'], '{:.1f}'):>14s} "
              f"{np.mean(m['min_kurtosis_along_trace']):9.3f} {m['seconds'][0]:6.1f}")
    print("<x^4> along the cooling, at E =", " ".join(f"{e:g}" for e in TRACE_ENERGIES))
    for name, m in models.items():
        k = m["kurtosis_at_energies"]
        print(f"  {name:36s}", " ".join(f"{a:.3f}±{b:.3f}" for a, b in zip(k["mean"], k["se"],
                                                                           strict=True)))
    print("symmetrised P(|x|) on bins of 0.2 from 0:")
    for name, m in models.items():
        print(f"  {name:36s}", " ".join(f"{p:.3f}" for p in m["symmetrised"][:13]))


if __name__ == "__main__":
    main()
