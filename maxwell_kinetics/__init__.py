"""maxwell_kinetics: the pseudo-Maxwell (Ulam) Boltzmann equation solved in Fourier space.

JAX runs in float64 everywhere in this package.  Importing the package sets
``JAX_ENABLE_X64`` before JAX is first imported, and every module that imports JAX also calls
``jax.config.update("jax_enable_x64", True)``.  The NumPy-only modules (``initial``,
``validation``) import no JAX, so :mod:`particles` can use them without it.

Public names are loaded lazily so that ``import maxwell_kinetics.initial`` stays light.
"""

from __future__ import annotations

import importlib
import os

os.environ.setdefault("JAX_ENABLE_X64", "1")

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
    "get_law": "initial",
    "law_from_characteristic": "initial",
    "InitialLaw": "initial",
    "InvalidArgumentError": "validation",
}


def __getattr__(name):
    if name in _LAZY:
        module = importlib.import_module(f".{_LAZY[name]}", __name__)
        return getattr(module, name)
    raise AttributeError(f"module 'maxwell_kinetics' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
