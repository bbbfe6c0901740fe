"""The spectral hard-sphere solve timed on whatever JAX device this process has (a GPU when one
is there, else the CPU): the same code, unchanged.

    python benchmarks/hard_sphere_device.py                       # d = 3, α = 0.5, default grid
    python benchmarks/hard_sphere_device.py --grid fine --repeats 3 --out device.json
    JAX_PLATFORMS=cpu python benchmarks/hard_sphere_device.py     # the CPU, for the ratio

Two workloads, each run ``--repeats`` times in this process (the first call compiles; the
best of the later calls is the warm time):

* ``solve``: :func:`maxwell_kinetics.sphere_spectral.solve_spheres` from the unit Maxwellian
  to t = 0.1, 0.2, 0.4 (T and a₂ at the last time);
* ``cooling_state``: :func:`maxwell_kinetics.sphere_spectral.cooling_state` (march and
  Newton–Krylov), a₂, a₃ and the residual of the homogeneous cooling state.

Prints one JSON object (the device, JAX's version, each workload's first and warm wall
times and its numbers); ``--out`` also writes it to a file.  The compile store is off
(``MAXWELL_KINETICS_CACHE=off``), so the first call's time includes the compilation.  The
numbers of a GPU run must equal the CPU's to the solver's tolerances (float64 on both).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

os.environ.setdefault("MAXWELL_KINETICS_CACHE", "off")


def _timed(function, repeats: int):
    """(first wall time, best later wall time or None, the last result) of ``function()``."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return times[0], (min(times[1:]) if len(times) > 1 else None), result


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dimension", type=int, default=3, choices=(2, 3))
    parser.add_argument("--restitution", type=float, default=0.5)
    parser.add_argument("--grid", default="default", help="coarse, default or fine")
    parser.add_argument("--repeats", type=int, default=2, help="calls per workload (2)")
    parser.add_argument("--skip-cooling-state", action="store_true",
                        help="time the solve only")
    parser.add_argument("--out", help="also write the JSON object here")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats must be at least 1, got {args.repeats}")

    import jax

    from maxwell_kinetics import sphere_spectral as spectral
    from particles.sphere_kernels import HardSpheres

    kernel = HardSpheres(args.restitution)
    device = jax.devices()[0]
    report = {
        "device": {"platform": device.platform, "kind": getattr(device, "device_kind", ""),
                   "count": jax.device_count()},
        "jax": jax.__version__, "python": platform.python_version(),
        "dimension": args.dimension, "restitution": args.restitution, "grid": args.grid,
        "repeats": args.repeats, "workloads": {},
    }

    def solve():
        spectral.clear_operator_cache()  # each call builds its tables, as a fresh process would
        sol = spectral.solve_spheres(kernel, [0.1, 0.2, 0.4], dimension=args.dimension,
                                     grid=args.grid)
        return {"temperature": float(sol.temperature[-1]), "a2": float(sol.a2[-1])}

    first, warm, numbers = _timed(solve, args.repeats)
    report["workloads"]["solve"] = {"first_s": first, "warm_s": warm, **numbers}
    if not args.skip_cooling_state:
        def hcs():
            spectral.clear_operator_cache()
            state = spectral.cooling_state(kernel, dimension=args.dimension, grid=args.grid)
            return {"a2": state.a2, "a3": state.a3, "residual": state.residual,
                    "newton_steps": state.newton_steps}

        first, warm, numbers = _timed(hcs, args.repeats)
        report["workloads"]["cooling_state"] = {"first_s": first, "warm_s": warm, **numbers}
    text = json.dumps(report)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    return report


if __name__ == "__main__":
    main()
