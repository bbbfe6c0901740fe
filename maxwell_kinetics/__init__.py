"""maxwell_kinetics: kinetic theory of inelastic Maxwell models in Fourier space (JAX in float64,
diffrax, pyfftw), and the application built on it and on :mod:`particles`: the command line
(:mod:`.cli`, one module per subcommand in :mod:`.commands`), the comparisons with the paper
(:mod:`.comparisons`) and ``reproduce``.

Importing this package changes no global configuration.  The JAX computations (:mod:`.solver`,
:mod:`.stationary`) run in float64 inside ``jax.enable_x64(True)``, a thread-local context that
restores the caller's setting, so a user's own float32 JAX code is not affected.

Public names are loaded lazily so that ``import maxwell_kinetics`` stays light (no JAX until a
solver runs).
"""

from __future__ import annotations

import importlib

__version__ = "0.2.0"

_LAZY = {
    "MaxwellModel": "model",
    "Resolution": "grid",
    "RESOLUTIONS": "grid",
    "solve": "solver",
    "Solution": "solution",
    "SolverOptions": "solution",
    "Moments": "moments",
    "fixed_point": "stationary",
    "FixedPoint": "stationary",
    "linear_decay_rates": "linear_rates",
    "LinearRates": "linear_rates",
    "f_hat": "exact",
    "f_density": "exact",
    "get_law": "particles.initial",
    "law_from_characteristic": "particles.initial",
    "InitialLaw": "particles.initial",
    "InvalidArgumentError": "particles.validation",
    "tail_exponent": "tails",
    "TailExponent": "tails",
    "decay_rate": "tails",
    "moment_rates": "tails",
    "steady_state": "driven",
    "DrivenSteadyState": "driven",
    "Comparison": "comparisons",
    "COMPARISONS": "comparisons",
}

#: The public names: each is loaded on first access.
__all__ = list(_LAZY)


def __getattr__(name):
    if name in _LAZY:
        where = _LAZY[name]
        module = importlib.import_module(where if "." in where else f".{where}", __name__)
        return getattr(module, name)
    raise AttributeError(f"module 'maxwell_kinetics' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
