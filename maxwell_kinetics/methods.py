"""The numerical methods of :func:`maxwell_kinetics.solve`, as values.

A method is a frozen configuration object, in the spirit of diffrax's solvers: it holds the
numerical choices of one way of solving the kinetic equation, and says which collision kernels
(:mod:`particles.kernels`) it can carry.  :func:`maxwell_kinetics.solve` takes a kernel (the
physics), an initial law, the output times and a method (the numerics):

* :class:`FourierScheme`: the semi-Lagrangian scheme in Fourier space of
  :mod:`maxwell_kinetics.solver`, for kernels whose Fourier-space equation closes
  (:attr:`particles.kernels.Kernel.fourier_closed`: every pair collides at one rate); time τ,
  collisions per particle; d = 1, 2, 3.  Result: :class:`maxwell_kinetics.solution.Solution`.
* :class:`VelocitySpace`: the collocation scheme on a velocity grid of
  :mod:`maxwell_kinetics.inelastic_boltzmann`, for kernels of physical time t whose rate is
  homogeneous in |v − w| (:func:`maxwell_kinetics.inelastic_boltzmann.carries`); d = 1.  Its
  ``grid`` is a uniform :class:`maxwell_kinetics.velocity_grid.VelocityGrid` or, for γ = 0, a
  :class:`maxwell_kinetics.velocity_grid.MappedGrid` (the mapped grid, wide tails).  Result:
  :class:`maxwell_kinetics.boltzmann_solution.BoltzmannSolution`.
* :class:`SphereSpectral`: the Fourier–Galerkin (spectral) scheme of
  :mod:`maxwell_kinetics.sphere_spectral`, for the kernels of smooth hard spheres and variable
  hard spheres (:mod:`particles.sphere_kernels`) in d = 2, 3, physical time t.  Result:
  :class:`maxwell_kinetics.sphere_solution.SphereSolution`.

The results share one contract (:mod:`maxwell_kinetics.kinetic_result`).  A method refuses a
kernel it cannot carry, by name and with the reason, before any work (:meth:`refusal`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

__all__ = ["FourierScheme", "VelocitySpace", "SphereSpectral", "METHODS", "method_for",
           "carrying_methods"]


@dataclass(frozen=True)
class FourierScheme:
    """The Fourier-space scheme (:func:`maxwell_kinetics.solver.solve_fourier`; its accuracy
    and cost: :doc:`/guide/kinetic` and :doc:`/performance`).

    Attributes
    ----------
    resolution : str or maxwell_kinetics.grid.Resolution, default "default"
        A name in :data:`maxwell_kinetics.grid.RESOLUTIONS` or a grid.
    options : maxwell_kinetics.solution.SolverOptions, optional
        Tolerances and window length; None for the defaults.
    dimension : int, default 1
        Space dimension d ∈ {1, 2, 3}.
    angular : str, default "uniform"
        Angular model in d ≥ 2 ("uniform" or "hard").
    angular_nodes : int, default 16
        Scale of the η quadrature's node counts in d ≥ 2.
    angular_rule : str, default "fast"
        The η rule in d ≥ 2 ("fast" or "accurate").

    The values are checked when a solve starts, before any work
    (:func:`maxwell_kinetics.solver.check_solve_arguments`).
    """

    name: ClassVar[str] = "fourier"

    resolution: Any = "default"
    options: Any = None
    dimension: int = 1
    angular: str = "uniform"
    angular_nodes: int = 16
    angular_rule: str = "fast"

    @staticmethod
    def refusal(kernel) -> str | None:
        """Why this method cannot carry ``kernel`` (None when it can).

        Parameters
        ----------
        kernel : particles.kernels.Kernel
            The kernel.

        Returns
        -------
        str or None
        """
        if not kernel.fourier_closed:
            return (f"the Fourier scheme carries kernels whose Fourier-space equation closes "
                    f"(a rate independent of the velocities); {kernel.name!r} does not")
        return None


@dataclass(frozen=True)
class VelocitySpace:
    """The velocity-grid scheme (:func:`maxwell_kinetics.inelastic_boltzmann.solve_boltzmann`).

    Attributes
    ----------
    grid : VelocityGrid or MappedGrid, optional
        The grid of the rescaled velocity (:mod:`maxwell_kinetics.velocity_grid`); default
        :func:`maxwell_kinetics.velocity_grid.default_grid` of the kernel's degree γ.  A
        MappedGrid for γ = 0 only.
    rtol, atol : float
        Tolerances of the step-size controller (defaults 1e-10 and 1e-13).
    max_steps : int
        Most time steps (default 10⁶).

    Checked when a solve starts, before any work.
    """

    name: ClassVar[str] = "velocity_grid"

    grid: Any = None
    rtol: float = 1e-10
    atol: float = 1e-13
    max_steps: int = 1_000_000

    @staticmethod
    def refusal(kernel) -> str | None:
        """Why this method cannot carry ``kernel`` (None when it can).

        Parameters
        ----------
        kernel : particles.kernels.Kernel
            The kernel.

        Returns
        -------
        str or None
        """
        from .inelastic_boltzmann import carries

        if not carries(kernel):
            return (f"the velocity-space scheme carries kernels of physical time t in d = 1 "
                    f"whose rate is a power of |v - w| (a declared homogeneity); "
                    f"{kernel.name!r} is not one")
        return None


@dataclass(frozen=True)
class SphereSpectral:
    """The spectral scheme of hard spheres and disks
    (:func:`maxwell_kinetics.sphere_spectral.solve_spheres`; its method and order are in
    :mod:`maxwell_kinetics.sphere_spectral`).

    Attributes
    ----------
    dimension : int, default 3
        d, 2 or 3 (the kernels of :mod:`particles.sphere_kernels` hold no dimension).
    grid : str or maxwell_kinetics.sphere_grid.SphereGrid, optional
        A name of :data:`maxwell_kinetics.sphere_grid.GRIDS` ("coarse", "default", "fine") or
        a grid; default "default".
    rtol, atol : float
        Tolerances of the step-size controller (defaults 1e-9 and 1e-12).
    max_steps : int
        Most time steps (default 10⁵).

    Checked when a solve starts, before any work.
    """

    name: ClassVar[str] = "sphere_spectral"

    dimension: int = 3
    grid: Any = None
    rtol: float = 1e-9
    atol: float = 1e-12
    max_steps: int = 100_000

    @staticmethod
    def refusal(kernel) -> str | None:
        """Why this method cannot carry ``kernel`` (None when it can).

        Parameters
        ----------
        kernel : particles.kernels.Kernel
            The kernel.

        Returns
        -------
        str or None
        """
        from .sphere_spectral import carries

        if not carries(kernel):
            return (f"the spectral hard-sphere scheme carries the kernels of "
                    f"particles.sphere_kernels (hard_spheres, variable_hard_spheres) in "
                    f"d = 2, 3; {kernel.name!r} is not one")
        return None


#: The methods by name (the ``kernels`` listing's ``methods``).
METHODS: dict[str, type] = {FourierScheme.name: FourierScheme,
                            VelocitySpace.name: VelocitySpace,
                            SphereSpectral.name: SphereSpectral}


def carrying_methods(kernel) -> list[str]:
    """The names of the methods that carry a kernel (a class or an instance).

    Parameters
    ----------
    kernel : type or particles.kernels.Kernel
        The kernel.

    Returns
    -------
    list of str
        In the order of :data:`METHODS`.
    """
    return [name for name, method in METHODS.items() if method.refusal(kernel) is None]


def method_for(kernel):
    """The default method of a kernel: the first of :data:`METHODS` that carries it (the
    Fourier scheme, the velocity grid, the spectral hard-sphere scheme in d = 3).

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        The kernel.

    Returns
    -------
    FourierScheme or VelocitySpace or SphereSpectral

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``kernel`` when no method carries it, with each method's reason.
    """
    from particles.validation import InvalidArgumentError

    reasons = []
    for method in METHODS.values():
        reason = method.refusal(kernel)
        if reason is None:
            return method()
        reasons.append(reason)
    raise InvalidArgumentError("kernel", kernel, "a kernel some method carries: "
                               + "; ".join(reasons))
