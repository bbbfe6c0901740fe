"""The η quadrature of the gain in d ≥ 2, by range of q: the rules (:data:`ANGULAR_RULES`),
their tiers on a q grid (:func:`tier_counts`, whose quadratures
:func:`maxwell_kinetics._kinetic_scheme.angular_tiers` builds) and the mean η nodes per state
node that the cost of a solve scales with (:func:`angular_nodes_per_state_node`)."""

from __future__ import annotations

import math

__all__ = ["ANGULAR_RULES", "tier_counts", "angular_nodes_per_state_node"]

#: The η rule is :meth:`maxwell_kinetics.angular.AngularLaw.quadrature` (Gauss–Jacobi).  Measured
#: convergence (r = 0.5, coarse grid, G at τ = 30 and 300 against 32 nodes): 4, 6, 8, 12, 16
#: nodes differ by 1.4e-5, 3.5e-7, 2.0e-8, 4.5e-9, 3.1e-9 (d = 2) and 2.6e-6, 4.5e-8, 1.1e-8,
#: 6.6e-9, 2.7e-9 (d = 3).  Gauss–Jacobi in u = √η was worse at these node counts, and so was
#: Gauss in u = η^{1/m} (m = 2, 3, 4): the error at few nodes comes from the scale ~1/q² in η on
#: which G(p √η q) varies at q ≳ 1, hence a node count that grows with q.
#: Per angular rule: (q from which the tier applies, its Gauss–Jacobi nodes at
#: ``angular_nodes`` = 16; None: all ``angular_nodes``), by increasing q; see
#: :func:`maxwell_kinetics._kinetic_scheme.angular_tiers`.  "fast" (the default of
#: :func:`maxwell_kinetics.solver.solve`):
#: 4.76 nodes per state node on average, G within 1.0e-8 of 32 nodes at every q; "accurate":
#: 10.7 nodes per state node, also exact enough at small q for the fits of the non-analytic
#: |q|^{2s*} term in :mod:`maxwell_kinetics.scaling_tails`, which refuse "fast".
ANGULAR_RULES: dict[str, tuple[tuple[float, int | None], ...]] = {
    "fast": ((0.0, 2), (1e-3, 3), (1e-2, 4), (0.05, 6), (0.15, 8), (0.35, 12), (0.6, None),
             (10.0, 12)),
    "accurate": ((0.0, 2), (1e-6, None), (10.0, 12)),
}


def tier_counts(nodes: int, grid, rule: str) -> tuple[tuple[int, int], ...]:
    """The tiers of :func:`maxwell_kinetics._kinetic_scheme.angular_tiers` in d ≥ 2 without
    their quadratures: (first state node, η nodes) by increasing q (the cost estimate reads
    them before a solve).

    Parameters
    ----------
    nodes : int
        ``angular_nodes``: the η nodes of the widest tier.
    grid : maxwell_kinetics.grid.Resolution
        The q grid.
    rule : str
        A key of :data:`ANGULAR_RULES`.

    Returns
    -------
    tuple of (int, int)
        (first state node, η nodes) per tier.
    """
    tiers: list[tuple[int, int]] = []
    for q_from, tier_nodes in ANGULAR_RULES[rule]:
        count = nodes if tier_nodes is None else min(max(math.ceil(tier_nodes * nodes / 16), 2),
                                                     nodes)
        first = 0 if q_from == 0.0 else max(0, math.ceil((math.log(q_from) - grid.s_min)
                                                         / grid.h - 1e-9))
        if first >= grid.n:
            break
        if tiers and tiers[-1][1] == count:
            continue  # the same rule as the tier below: extend that one
        if tiers and tiers[-1][0] == first:
            tiers.pop()
        tiers.append((first, count))
    return tuple(tiers)


def angular_nodes_per_state_node(grid, angular_rule: str,
                                 angular_nodes: int) -> float:
    """The mean number of η nodes of the gain per state node in d ≥ 2: the tiers of
    :func:`maxwell_kinetics._kinetic_scheme.angular_tiers` weighted by the state nodes they
    cover (at 16 nodes on the coarse and default grids: 4.63 for "fast", 10.65 for
    "accurate").

    Parameters
    ----------
    grid : maxwell_kinetics.grid.Resolution
        The q grid.
    angular_rule : str
        "fast" or "accurate".
    angular_nodes : int
        The η nodes of the widest tier.

    Returns
    -------
    float
        Σ over tiers of (state nodes of the tier × its η nodes) / ``grid.n``.
    """
    tiers = tier_counts(int(angular_nodes), grid, angular_rule)
    ends = [first for first, _ in tiers[1:]] + [grid.n]
    pairs = zip(tiers, ends, strict=True)
    return sum((end - first) * count for (first, count), end in pairs) / grid.n
