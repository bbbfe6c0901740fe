"""The resolving power of the comparisons' verdicts: plant a relative error ε in one engine
parameter, in this process only (monkeypatching; the checkout is never edited), run the
comparisons it touches at a size with one shared runner (as ``reproduce`` does), and print each
verdict's claim, status, z and allowance, with and without the error.

    python benchmarks/power.py --size small                              # no error: the baseline
    python benchmarks/power.py --size small --plant ulam_rate --epsilon 0.01
    python benchmarks/power.py --size small --plant md_p --epsilon 0.05 --only energy_decay
    python benchmarks/power.py --size small --plant driven_noise --epsilon 0.05 \\
        --json docs/figures/power_small.json                             # merged into the file

The planted errors (:data:`PLANTS`; ε > 0 throughout):

``md_p``, ``lattice_p``, ``ulam_p``
    The engine's collision parameter p = (1 + r)/2 of MD, the lattice or the Ulam particles, as
    a relative error ε in the inelasticity 1 − p = (1 − r)/2, made ε too small: the engine is
    built with r' = r + ε(1 − r), which stays a restitution in [0, 1] at every r (a relative
    error in p itself makes r = 0.99 superelastic).
``ulam_rate``, ``dsmc_rate``
    The constant pair rate of the Ulam model (the Poisson mean of events per window) or the
    candidate rate of its DSMC (the Poisson mean of candidates per window, thinned rate), × (1 + ε).
``driven_noise``
    The white-noise strength D of the driven Ulam particles × (1 + ε) (the exact steady state
    stays at the nominal D).
``sticky_density``
    The sticky gas's density × (1 + ε) (it has no restitution; its time scale is set by the
    density).
``solver_restitution``
    The restitution handed to the kinetic solver and to the exact tail exponents, r' = r + ε(1 − r)
    (the particles keep r): the deterministic comparisons' key parameter.
``dsmc_alpha``
    The hard-sphere DSMC's restitution α, α' = α + ε(1 − α), in the early runs and in the
    cooling state's tail sampler.

``--json FILE`` merges the run into FILE: ``comparisons[name]["plants"][plant][str(ε)]`` holds
every verdict (claim, status, relation, z, allowance in σ, ratio: how much of its allowance it
uses, :func:`closeness`), the claims that turn ``disagrees`` (not so at ε = 0), the other status
changes and the agreeing verdict of largest ratio; the baseline is stored under every plant as
``"0"``.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

#: plant → (what it changes, the comparisons it touches)
PLANTS = {
    "md_p": ("MD's p: the inelasticity (1 − r)/2 made ε too small",
             ("energy_decay", "rate_vs_correlations", "velocity_distributions",
              "structure_factors", "sticky_vs_md", "velocity_profiles")),
    "lattice_p": ("the lattice's p: the inelasticity (1 − r)/2 made ε too small",
                  ("energy_decay", "structure_factors", "velocity_distributions",
                   "velocity_profiles")),
    "ulam_rate": ("the Ulam model's constant pair rate × (1 + ε)",
                  ("kinetic_vs_ulam", "ulam_collapse", "velocity_distributions",
                   "rate_vs_correlations")),
    "dsmc_rate": ("the DSMC's candidate rate × (1 + ε)",
                  ("rate_vs_correlations", "velocity_distributions")),
    "driven_noise": ("the driven noise D × (1 + ε)", ("driven_steady",)),
    "sticky_density": ("the sticky gas's density × (1 + ε)", ("late_stage", "sticky_vs_md")),
    "solver_restitution": ("the kinetic solver's restitution: (1 − r) made ε too small",
                           ("kinetic_theory", "tail_exponents", "kinetic_vs_ulam",
                            "ulam_collapse")),
    "dsmc_alpha": ("the hard-sphere DSMC's α: (1 − α) made ε too small", ("hard_spheres",)),
    "ulam_p": ("the Ulam particles' p: the inelasticity (1 − r)/2 made ε too small",
               ("kinetic_vs_ulam", "ulam_collapse", "tail_exponents", "driven_steady")),
}


def less_inelastic(r: float, eps: float) -> float:
    """The restitution whose inelasticity 1 − r is ε too small: r + ε(1 − r)."""
    return float(r) + eps * (1.0 - float(r))


class ScaledPoisson:
    """A generator whose Poisson means are × ``factor``; every other draw is ``rng``'s."""

    def __init__(self, rng, factor: float):
        self._rng, self._factor = rng, factor

    def poisson(self, lam, *args, **kwargs):
        return self._rng.poisson(lam * self._factor, *args, **kwargs)

    def __getattr__(self, name):
        return getattr(self._rng, name)


@contextlib.contextmanager
def planted(plant: str | None, eps: float):
    """Plant the error ``plant`` of relative size ``eps`` for the ``with`` block (None or
    ε = 0: nothing)."""
    if plant is None or eps == 0.0:
        yield
        return
    if plant not in PLANTS:
        raise SystemExit(f"unknown plant {plant!r}: one of {', '.join(PLANTS)}")
    undo = []

    def patch(owner, name, value):
        undo.append((owner, name, getattr(owner, name)))
        setattr(owner, name, value)

    f = 1.0 + eps
    if plant in ("md_p", "lattice_p", "ulam_p", "driven_noise", "sticky_density"):
        from particles.models import Model

        build = Model.build
        model, key = {"md_p": ("md", "restitution"), "lattice_p": ("lattice", "restitution"),
                      "ulam_p": ("ulam", "restitution"), "driven_noise": ("ulam", "driving"),
                      "sticky_density": ("sticky", "density")}[plant]

        def planted_build(self, params):
            params = dict(params)
            if self.name == model and key in params:
                if key == "restitution":
                    params[key] = less_inelastic(params[key], eps)
                else:
                    params[key] = float(params[key]) * f
            return build(self, params)

        patch(Model, "build", planted_build)
    elif plant in ("ulam_rate", "dsmc_rate"):
        from particles.ulam import Ulam

        if plant == "ulam_rate":
            advance = Ulam._advance

            def planted_advance(self, state, until, rng):
                if self.relative_velocity_rate:
                    return advance(self, state, until, rng)
                return advance(self, state, until, ScaledPoisson(rng, f))

            patch(Ulam, "_advance", planted_advance)
        else:
            thinned = Ulam._advance_thinned

            def planted_thinned(self, state, until, rng, sequential=False):
                return thinned(self, state, until, ScaledPoisson(rng, f), sequential)

            patch(Ulam, "_advance_thinned", planted_thinned)
    elif plant == "solver_restitution":
        from maxwell_kinetics.app.comparisons import (
            _kinetic_theory,
            _kinetic_vs_ulam,
            _tail_exponents,
            _ulam_collapse,
            kinetic_predictions,
        )

        solution = kinetic_predictions.kinetic_solution

        def planted_solution(restitution, *args, **kwargs):
            return solution(less_inelastic(restitution, eps), *args, **kwargs)

        for module in (kinetic_predictions, _kinetic_theory, _kinetic_vs_ulam, _ulam_collapse):
            patch(module, "kinetic_solution", planted_solution)
        exponent = _tail_exponents.tail_exponent
        patch(_tail_exponents, "tail_exponent",
              lambda d, r, *a, **k: exponent(d, less_inelastic(r, eps), *a, **k))
    elif plant == "dsmc_alpha":
        from particles import cooling_state_sample, hard_sphere_dsmc

        dsmc = hard_sphere_dsmc.SphereDSMC
        planted_dsmc = lambda n, alpha, *a, **k: dsmc(n, less_inelastic(alpha, eps), *a, **k)  # noqa: E731
        # the early runs and the cooling state's tail sampler (which holds its own name)
        patch(hard_sphere_dsmc, "SphereDSMC", planted_dsmc)
        patch(cooling_state_sample, "SphereDSMC", planted_dsmc)
    try:
        yield
    finally:
        for owner, name, value in reversed(undo):
            setattr(owner, name, value)


def closeness(v: dict) -> float | None:
    """How much of its allowance a verdict uses: |deviation|/allowed for a two-sided check,
    the deviation towards the bound over allowed for ``at_most``/``at_least``, allowed/|deviation|
    for a resolved difference (``below``, ``above``, ``differs``); 1 is the edge."""
    m, e, allowed = v.get("measured"), v.get("expected"), v.get("allowed")
    if not all(isinstance(x, (int, float)) and math.isfinite(x) for x in (m, e, allowed)):
        z, sigmas = v.get("deviation_in_sigma"), v.get("sigmas")
        ok = isinstance(z, (int, float)) and math.isfinite(z) and sigmas
        return abs(z) / sigmas if ok and v.get("relation", "equal") == "equal" else None
    d, relation = m - e, v.get("relation", "equal")
    if relation in ("below", "above", "differs"):  # the wrong side: not close, failed
        right = {"below": d < 0, "above": d > 0}.get(relation, d != 0)
        return allowed / abs(d) if right else math.inf
    if not allowed:
        return None
    return {"at_most": max(d, 0.0), "at_least": max(-d, 0.0)}.get(relation, abs(d)) / allowed


def verdict_row(v: dict) -> dict:
    """Claim, status, relation, z, allowance (σ) and closeness (``ratio``) of a verdict."""
    z, allowance = v.get("deviation_in_sigma"), v.get("sigmas")
    ratio = closeness(v)
    finite = isinstance(z, (int, float)) and math.isfinite(z)
    return {"claim": v.get("short") or v["claim"], "status": v["status"],
            "relation": v.get("relation", "equal"), "z": float(z) if finite else None,
            "allowance": float(allowance) if isinstance(allowance, (int, float)) else None,
            "ratio": None if ratio is None or not math.isfinite(ratio) else float(ratio)}


def run(size: str, names, plant: str | None, eps: float) -> dict:
    """name → (seconds, verdict rows) of the comparisons ``names`` at ``size``, with the error
    planted, sharing one runner."""
    from maxwell_kinetics.app import comparisons

    out = {}
    with planted(plant, eps):
        runner = comparisons.ParticleRuns()
        for name in names:
            start = time.perf_counter()
            result = comparisons.COMPARISONS[name](size, progress=False, runner=runner)
            rows = [verdict_row(v) for v in result.summary.get("verdicts", [])]
            out[name] = (time.perf_counter() - start, rows)
    return out


def outcome(rows: list[dict], baseline: list[dict] | None) -> dict:
    """The claims that turn ``disagrees`` (not so in ``baseline``), those whose status changes
    otherwise (e.g. to ``refuted``) and, of those that agree, the one closest to its allowance
    (largest ``ratio``)."""
    before = {r["claim"]: r["status"] for r in baseline or []}
    turned = [r for r in rows
              if r["status"] == "disagrees" and before.get(r["claim"]) != "disagrees"]
    changed = [r for r in rows if r not in turned and r["claim"] in before
               and r["status"] != before[r["claim"]]]
    rest = [r for r in rows if r["status"] == "agrees" and r["ratio"] is not None]
    largest = max(rest, key=lambda r: r["ratio"], default=None)
    return {"disagrees": turned, "changed": changed, "largest": largest}


def merge(path: Path, size: str, plant: str, eps: float, done: dict, load: str) -> None:
    """Merge this run's results into the JSON at ``path``."""
    data = json.loads(path.read_text()) if path.exists() else {}
    data.setdefault("size", size)
    if data["size"] != size:
        raise SystemExit(f"{path} holds size {data['size']!r}, not {size!r}")
    data.setdefault("plants", {k: v[0] for k, v in PLANTS.items()})
    comps = data.setdefault("comparisons", {})
    for name, (seconds, rows) in done.items():
        entry = comps.setdefault(name, {}).setdefault("plants", {})
        if plant is None:  # the baseline: under every plant that touches the comparison
            targets = [p for p, (_, names) in PLANTS.items() if name in names]
            comps[name]["baseline"] = {"seconds": round(seconds, 1), "load": load,
                                       "verdicts": rows}
            for p in targets:
                entry.setdefault(p, {})["0"] = {**outcome(rows, None), "verdicts": rows}
            continue
        base = comps[name].get("baseline", {}).get("verdicts")
        entry.setdefault(plant, {})[repr(eps)] = {
            **outcome(rows, base), "verdicts": rows, "seconds": round(seconds, 1), "load": load}
    path.write_text(json.dumps(data, indent=1, ensure_ascii=False) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", choices=("small", "default"), default="small")
    parser.add_argument("--only", help="comma-separated comparisons (default: those the plant "
                        "touches; all without a plant)")
    parser.add_argument("--plant", choices=tuple(PLANTS))
    parser.add_argument("--epsilon", type=float, default=0.0)
    parser.add_argument("--json", type=Path, help="merge the results into this JSON file")
    args = parser.parse_args(argv)
    from maxwell_kinetics.app.comparisons import COMPARISONS

    if args.only:
        names = [n.strip() for n in args.only.split(",") if n.strip()]
    elif args.plant and args.epsilon:
        names = [n for n in COMPARISONS if n in PLANTS[args.plant][1]]
    else:
        names = list(COMPARISONS)
    unknown = [n for n in names if n not in COMPARISONS]
    if unknown:
        raise SystemExit(f"unknown comparisons: {', '.join(unknown)}")
    plant = args.plant if args.epsilon else None
    load = " / ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"size {args.size}, plant {plant or 'none'} ε = {args.epsilon:g}, load {load}")
    done = run(args.size, names, plant, args.epsilon)
    for name, (seconds, rows) in done.items():
        print(f"\n{name} ({seconds:.1f} s)")
        for r in rows:
            z = "—" if r["z"] is None else f"{r['z']:+.2f}"
            allowance = "—" if r["allowance"] is None else f"{r['allowance']:.3g}σ"
            print(f"  {r['status']:13s} z = {z:>8s} / {allowance:>7s}  {r['claim'][:90]}")
    if args.json:
        merge(args.json, args.size, plant, args.epsilon, done, load)
        print(f"\nmerged into {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
