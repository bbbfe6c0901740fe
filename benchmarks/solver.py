"""Benchmarks of the kinetic solver (run on demand; results go to benchmarks/README.md).

    python benchmarks/solver.py timing     # compile time, wall time for τ ∈ [0, 1000]
    python benchmarks/solver.py stability  # r ∈ {0,.5,.9,.99} × laws × resolutions, τ ≤ 1e4
    python benchmarks/solver.py floor      # error floor: long runs (r = 0, .5), fixed point (all r)
    python benchmarks/solver.py scale      # the floor as a rescaling of f̂: what it depends on
    python benchmarks/solver.py sweep      # 10 values of r in one process: compiles and wall time
    python benchmarks/solver.py isotropic  # d = 1, 2, 3 at the default resolution, τ ≤ 1000

Each mode prints a Markdown table and writes JSON next to this file (benchmarks/solver_<mode>.json).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

from maxwell_kinetics.grid import RESOLUTIONS, get_resolution
from maxwell_kinetics.model import MaxwellModel
from maxwell_kinetics.solver import SolverOptions, Stepper, solve
from particles.initial import LAWS, get_law, law_from_characteristic

HERE = Path(__file__).resolve().parent


def timing(restitutions=(0.5, 0.0), resolutions=("default", "finest"), tau_end=1000.0):
    rows = []
    for r in restitutions:
        for name in resolutions:
            grid = get_resolution(name)
            t0 = time.perf_counter()
            st = Stepper(MaxwellModel(r), get_law("gaussian"), grid, SolverOptions())
            t1 = time.perf_counter()
            y = st.advance(st.y0, 0, 1).block_until_ready()
            st.output(y, 1, 1.5 * st.dtau).block_until_ready()
            t2 = time.perf_counter()
            windows = int(math.floor(tau_end / st.dtau + 1e-12))
            best = math.inf
            for _ in range(3):
                t3 = time.perf_counter()
                y = st.advance(st.y0, 0, windows)
                np.asarray(st.output(y, windows, tau_end))
                best = min(best, time.perf_counter() - t3)
            rows.append({"restitution": r, "resolution": name, "points": grid.n,
                         "setup_s": t1 - t0, "compile_s": t2 - t1, "run_s": best,
                         "windows": windows})
    print("| r | resolution | points | compile (s) | τ ∈ [0, 1000] after JIT (s, best of 3) |")
    print("|---|---|---|---|---|")
    for row in rows:
        print(f"| {row['restitution']:g} | {row['resolution']} | {row['points']} | "
              f"{row['compile_s']:.2f} | {row['run_s']:.2f} |")
    return rows


def _stable(taus, err):
    """Finite everywhere, and over τ ∈ [1000, τ_max] never above 1.5 × its value at τ ≈ 1000.

    (A running-minimum criterion is wrong here: while the physical error crosses the
    discretisation floor the two can cancel, and the sup error dips below the floor.)
    """
    err = np.asarray(err)
    if err.size == 0 or not np.all(np.isfinite(err)):
        return False
    late = np.asarray(taus) >= 1000.0 - 1e-9
    return bool(np.all(err[late] <= 1.5 * err[late][0] + 1e-15))


def stability(restitutions=(0.0, 0.5, 0.9, 0.99), laws=None,
              resolutions=tuple(RESOLUTIONS), tau_max=1e4):
    laws = tuple(sorted(LAWS)) if laws is None else laws
    taus = np.unique(np.round(np.geomspace(1.0, tau_max, 25), 6))
    rows = []
    for r in restitutions:
        for law in laws:
            for name in resolutions:
                t0 = time.perf_counter()
                try:
                    sol = solve(r, law, taus, name)
                    err = sol.sup_error()
                    ok = _stable(taus, err)
                    final = float(err[-1])
                except Exception as exc:  # report, do not hide, a failure
                    err, ok, final = [], False, repr(exc)
                rows.append({"restitution": r, "initial": law, "resolution": name,
                             "stable": ok, "final_sup_error": final,
                             "min_sup_error": float(np.min(err)) if len(err) else None,
                             "seconds": time.perf_counter() - t0,
                             "tau": taus.tolist(), "sup_error": np.asarray(err).tolist()})
                print(json.dumps({k: rows[-1][k] for k in
                                  ("restitution", "initial", "resolution", "stable",
                                   "final_sup_error", "seconds")}), flush=True)
    return rows


def floor(long_restitutions=(0.0, 0.5), fp_restitutions=(0.0, 0.5, 0.9, 0.99),
          resolutions=tuple(RESOLUTIONS), tau_max=1e4, fp_tau=(10.0, 100.0, 1000.0)):
    from maxwell_kinetics.stationary import fixed_point

    rows = []
    taus = np.unique(np.round(np.geomspace(100.0, tau_max, 11), 6))
    for r in long_restitutions:
        for name in resolutions:
            sol = solve(r, "gaussian", taus, name)
            err = sol.sup_error()
            rows.append({"method": "long run from gaussian", "restitution": r,
                         "resolution": name, "h": get_resolution(name).h,
                         "floor": float(np.median(err[-4:])), "tau": taus.tolist(),
                         "sup_error": err.tolist()})
            print(json.dumps({k: rows[-1][k] for k in ("method", "restitution", "resolution",
                                                        "floor")}), flush=True)
    for r in fp_restitutions:
        fp = fixed_point(r)
        law = law_from_characteristic(lambda k, fp=fp: fp.evaluate(np.asarray(k)), 1.0,
                                      name=f"fixed-point r={r:g}")
        for name in resolutions:
            sol = solve(r, law, list(fp_tau), name)
            err = sol.sup_error()
            rows.append({"method": "from the fixed point", "restitution": r,
                         "resolution": name, "h": get_resolution(name).h,
                         "fixed_point_error": fp.max_error,
                         "floor": float(err.max()), "tau": list(fp_tau),
                         "sup_error": err.tolist()})
            print(json.dumps({k: rows[-1][k] for k in ("method", "restitution", "resolution",
                                                        "floor")}), flush=True)
    return rows


def scale(taus=(100.0, 1000.0, 3000.0)):
    """The scale offset of the late state, G → f̂((1 + ε) q) (before ``bce2bde`` it was the
    whole ~4e-12 floor of the fine grids, ε ≈ 0.21 q_min): ε by least squares on the scale mode
    ε q f̂'(q) = −ε q² e^{−q}, and what is left after removing it, from the Newton fixed point
    (as in ``floor``) at r = 0 and 0.5, varying one thing at a time: resolution, interpolation
    order, window length, q_min, and r itself by 1e-14 … 2e-13 (f̂ does not depend on r, but
    every rounding in the run changes)."""
    from maxwell_kinetics.exact import f_hat
    from maxwell_kinetics.grid import Resolution
    from maxwell_kinetics.stationary import fixed_point

    variants = [("fine", {}), ("finest", {}), ("fine, order 10", {"order": 10}),
                ("fine, order 6", {"order": 6})]
    variants += [(f"fine, window {w:g}", {"window": w}) for w in (0.25, 1.0, 4.0, 16.0)]
    variants += [(f"fine, s_min {m:g}", {"s_min": m}) for m in (-12.0, -18.0, -30.0)]
    variants += [(f"fine, r + {d:g}", {"dr": d}) for d in (1e-14, 3e-14, 2e-13)]
    rows = []
    for r in (0.0, 0.5):
        fp = fixed_point(r)
        law = law_from_characteristic(lambda k, fp=fp: fp.evaluate(np.asarray(k)), 1.0,
                                      name=f"fixed-point r={r:g}")
        for label, v in variants:
            base = get_resolution("finest" if label == "finest" else "fine")
            grid = Resolution(base.name, h=base.h, order=v.get("order", base.order),
                              s_min=v.get("s_min", base.s_min))
            opts = SolverOptions(window=v.get("window", 2.0))
            sol = solve(r + v.get("dr", 0.0), law, list(taus), grid, options=opts)
            q = sol.q
            mode = -q * q * np.exp(-q)
            exact = f_hat(q)
            eps, sup, rest = [], [], []
            for k in range(len(taus)):
                diff = sol.G[k] - exact
                d = diff.real
                e = float(d @ mode / (mode @ mode))
                eps.append(e)
                sup.append(float(np.abs(diff).max()))
                rest.append(float(np.abs(d - e * mode).max()))
            rows.append({"restitution": r, "variant": label, "tau": list(taus), "epsilon": eps,
                         "sup_error": sup, "after_removing_the_mode": rest})
            print(f"| {r:g} | {label} | " + " | ".join(f"{e:.2e}" for e in eps)
                  + f" | {sup[-1]:.1e} | {rest[-1]:.1e} |", flush=True)
    return rows


def sweep(restitutions=(0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9), resolution="default",
          tau_end=1000.0):
    """Ten solves over r at one resolution in one process (one compile per resolution
    and law family).  Compilations are counted as traces of the jitted functions
    (``maxwell_kinetics._kinetic_scheme.TRACES``, a Python side effect that runs only while JAX
    traces).  The sweep runs twice: the first pass pays the compilation, the second gives each
    solve after JIT; the compile time is the first solve's wall time minus its second-pass time.
    Target: total wall of the first pass ≤ (compile + Σ second-pass solves) × 1.2.  Wall and CPU
    time (process_time) are both recorded: the machine may be shared.
    """
    from maxwell_kinetics import _kinetic_scheme

    def one_pass():
        rows = []
        for r in restitutions:
            before = sum(_kinetic_scheme.TRACES.values())
            w0, c0 = time.perf_counter(), time.process_time()
            sol = solve(float(r), "gaussian", [tau_end], resolution)
            rows.append({"restitution": float(r), "wall_s": time.perf_counter() - w0,
                         "cpu_s": time.process_time() - c0,
                         "traces": sum(_kinetic_scheme.TRACES.values()) - before,
                         "sup_error": float(sol.sup_error(0))})
        return rows

    w0, c0 = time.perf_counter(), time.process_time()
    first = one_pass()
    total_wall, total_cpu = time.perf_counter() - w0, time.process_time() - c0
    second = one_pass()
    compile_wall = first[0]["wall_s"] - second[0]["wall_s"]
    compile_cpu = first[0]["cpu_s"] - second[0]["cpu_s"]
    solves_wall = sum(row["wall_s"] for row in second)
    solves_cpu = sum(row["cpu_s"] for row in second)
    summary = {
        "resolution": resolution, "tau_end": tau_end,
        "traces_first_pass": sum(row["traces"] for row in first),
        "traces_second_pass": sum(row["traces"] for row in second),
        "total_wall_s": total_wall, "total_cpu_s": total_cpu,
        "compile_wall_s": compile_wall, "compile_cpu_s": compile_cpu,
        "solves_after_jit_wall_s": solves_wall, "solves_after_jit_cpu_s": solves_cpu,
        "target_wall_s": 1.2 * (compile_wall + solves_wall),
        "target_cpu_s": 1.2 * (compile_cpu + solves_cpu),
        "first_pass": first, "second_pass": second,
    }
    print("| r | first pass wall (s) | traces | after JIT wall (s) | CPU (s) | sup|G − f̂| |")
    print("|---|---|---|---|---|---|")
    for a, b in zip(first, second, strict=True):
        print(f"| {a['restitution']:g} | {a['wall_s']:.2f} | {a['traces']} | {b['wall_s']:.2f} | "
              f"{b['cpu_s']:.2f} | {b['sup_error']:.2e} |")
    print(f"compiles (traces of advance + output) in the sweep: {summary['traces_first_pass']}, "
          f"then {summary['traces_second_pass']}; total wall {total_wall:.2f} s (CPU "
          f"{total_cpu:.2f} s) against compile {compile_wall:.2f} s + 10 solves "
          f"{solves_wall:.2f} s, x 1.2 = {summary['target_wall_s']:.2f} s (CPU: compile "
          f"{compile_cpu:.2f} + {solves_cpu:.2f}, x 1.2 = {summary['target_cpu_s']:.2f})")
    return summary


def isotropic(restitution=0.5, resolution="default", tau_end=1000.0):
    """solve(..., dimension=d) for d = 1, 2, 3 (uniform angular model, 16 η nodes) with both η
    rules ("fast", the default, and "accurate"): wall and CPU time of τ ∈ [0, 1000] after JIT
    (the second call), against d = 1 (target: within 5x).  CPU time includes XLA's
    helper threads; run under ``taskset -c 0`` for one core (then CPU = wall)."""
    import os

    rows = []
    for d, rule in ((1, "fast"), (2, "fast"), (3, "fast"), (2, "accurate"), (3, "accurate")):
        kw = {"dimension": d, "angular_rule": rule}
        w0 = time.perf_counter()
        solve(restitution, "gaussian", [tau_end], resolution, **kw)
        first = time.perf_counter() - w0
        w0, c0 = time.perf_counter(), time.process_time()
        sol = solve(restitution, "gaussian", [tau_end], resolution, **kw)
        rows.append({"dimension": d, "rule": sol.angular_rule, "first_call_s": first,
                     "wall_s": time.perf_counter() - w0, "cpu_s": time.process_time() - c0,
                     "G_at_1": float(sol.evaluate([1.0])[0].real),
                     "load_average": os.getloadavg()[0]})
    print("| d | η rule | first call, with compile (s) | after JIT wall (s) | CPU (s) "
          "| wall / wall(d = 1) | CPU / CPU(d = 1) |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        print(f"| {row['dimension']} | {row['rule']} | {row['first_call_s']:.2f} | "
              f"{row['wall_s']:.2f} | {row['cpu_s']:.2f} | {row['wall_s'] / rows[0]['wall_s']:.1f} "
              f"| {row['cpu_s'] / rows[0]['cpu_s']:.1f} |")
    return rows


def scaling_tails(resolution="coarse", angular_nodes=16, taus=(200.0, 500.0, 1000.0)):
    """Tail root s* measured from the solver's G (the |q|^{2s*} term near q = 0,
    :func:`maxwell_kinetics.scaling_tails.tail_root_from_solution`) and the density tail slope
    against the root of λ(s) = s λ(1), for d = 2, 3, both angular models, r = 0 and 0.5."""
    from maxwell_kinetics.scaling_tails import tail_exponent_from_solution, tail_root_from_solution
    from maxwell_kinetics.tails import tail_exponent
    from particles.validation import InvalidArgumentError

    fits = {"q in [1e-4, 0.1], 3 analytic": ((1e-4, 0.1), 3),
            "q in [1e-2, 0.5], 5 analytic": ((1e-2, 0.5), 5)}
    rows = []
    for d in (2, 3):
        for angular in ("uniform", "hard"):
            for r in (0.0, 0.5):
                sol = solve(r, "gaussian", list(taus), resolution, dimension=d, angular=angular,
                            angular_nodes=angular_nodes, angular_rule="accurate")
                exact = tail_exponent(d, r, angular)
                for k, tau in enumerate(taus):
                    row = {"d": d, "angular": angular, "r": r, "tau": tau, "s_star": exact.s,
                           "component_exponent": exact.exponents["component"]}
                    for name, (window, terms) in fits.items():
                        row[name] = tail_root_from_solution(sol, window, k, terms,
                                                            beta_range=(0.02, 8.0))
                    try:
                        row["density slope x in [10, 30]"] = tail_exponent_from_solution(
                            sol, (10.0, 30.0), k)
                    except InvalidArgumentError:  # P <= 0 in the window: tail not resolved
                        row["density slope x in [10, 30]"] = None
                    rows.append(row)
    print("| d | angular | r | τ | s* (equation) | " + " | ".join(fits) +
          " | 1 + 2s* | density slope x ∈ [10, 30] |")
    print("|---|---|---|---|---|" + "---|" * len(fits) + "---|---|")
    for row in rows:
        cells = [f"{row[n][0]:.5f} ± {row[n][1]:.1e}" for n in fits]
        dens = row["density slope x in [10, 30]"]
        dens = "P ≤ 0 in window" if dens is None else f"{dens[0]:.4f} ± {dens[1]:.4f}"
        print(f"| {row['d']} | {row['angular']} | {row['r']:g} | {row['tau']:g} | "
              f"{row['s_star']:.5f} | " + " | ".join(cells) +
              f" | {row['component_exponent']:.4f} | {dens} |")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=["timing", "stability", "floor", "scale", "sweep",
                                         "isotropic", "scaling_tails"])
    args = parser.parse_args()
    rows = {"timing": timing, "stability": stability, "floor": floor, "scale": scale,
            "sweep": sweep, "isotropic": isotropic, "scaling_tails": scaling_tails}[args.mode]()
    (HERE / f"solver_{args.mode}.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
