"""maxwell_kinetics: the pseudo-Maxwell (Ulam) Boltzmann equation solved in Fourier space.

JAX runs in float64 everywhere in this package, whatever the import order:

* if JAX is already imported when this package is, ``jax.config.update("jax_enable_x64",
  True)`` is called at once (the environment variable would come too late);
* otherwise ``JAX_ENABLE_X64=1`` is set in ``os.environ``, which JAX reads when it is first
  imported.  JAX itself is *not* imported here, so ``import particles.initial`` (used by
  :mod:`particles`) stays free of JAX.

Decision: an explicit ``JAX_ENABLE_X64=0`` in the environment is overridden.  The solver's error
floors (down to ~1e-12) and its tests need float64, and the JAX modules (``solver``,
``stationary``) switch x64 on anyway when they run, so honouring 0 would only make arrays created
before the first solve float32.  Code that needs float32 JAX should not import this package.
The NumPy-only modules (``initial``, ``validation``) import no JAX.

Public names are loaded lazily so that ``import particles.initial`` stays light.
"""

from __future__ import annotations

import importlib
import os
import sys


def _enable_x64() -> None:
    """Float64 for JAX: now if JAX is imported, else when it is (see the module docstring)."""
    jax = sys.modules.get("jax")
    if jax is not None and hasattr(jax, "config"):
        jax.config.update("jax_enable_x64", True)
    else:
        os.environ["JAX_ENABLE_X64"] = "1"


_enable_x64()

__version__ = "0.1.0"

_LAZY = {
    "MaxwellModel": "model",
    "Resolution": "grid",
    "RESOLUTIONS": "grid",
    "solve": "solver",
    "Solution": "solver",
    "fixed_point": "stationary",
    "FixedPoint": "stationary",
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


def __getattr__(name):
    if name in _LAZY:
        where = _LAZY[name]
        module = importlib.import_module(where if "." in where else f".{where}", __name__)
        return getattr(module, name)
    raise AttributeError(f"module 'maxwell_kinetics' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
