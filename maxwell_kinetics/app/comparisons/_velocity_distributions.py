"""Comparison 4 (paper Figs. 1a/1b): rescaled P(x) of MD, the lattice and the Ulam model at equal
energy, early and late.  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles.kernels import ConstantRate, RelativeVelocity
from particles.md import haff_energy
from particles.observables import mean_sem, mean_sem_json

from ...exact import f_density
from ...model import MaxwellModel
from .analysis import bin_edges, rescaled
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import panels
from .particle_runs import ParticleRuns
from .verdicts import Check, judge, pair, student_sigmas, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "ABS_MEAN_F", "ABS_MEAN_GAUSSIAN", "verdicts"]

NAME = "velocity_distributions"

PRESETS = {
    "small": {"restitution": 0.99, "delta": 1e-4, "md_n": 2000, "md_seeds": 4,
              "md_t_early": 400.0, "md_t_late": 3000.0, "lattice_n": 2000, "lattice_seeds": 4,
              "lattice_late_restitution": 0.5, "ulam_n": 2000, "ulam_seeds": 4,
              "edges": (-4.0, 4.0, 0.25)},
    "default": {"restitution": 0.99, "delta": 1e-4, "md_n": 20_000, "md_seeds": 4,
                "md_t_early": 400.0, "md_t_late": 3000.0, "lattice_n": 20_000,
                "lattice_seeds": 4, "lattice_late_restitution": 0.5, "ulam_n": 20_000,
                "ulam_seeds": 4, "edges": (-4.0, 4.0, 0.2)},
    "full": {"restitution": 0.99, "delta": 1e-4, "md_n": 100_000, "md_seeds": 4,
             "md_t_early": 400.0, "md_t_late": 3000.0, "lattice_n": 1_000_000,
             "lattice_seeds": 2, "lattice_late_restitution": 0.5, "ulam_n": 1_000_000,
             "ulam_seeds": 2, "edges": (-4.0, 4.0, 0.1)},
}


#: ⟨|x|⟩ for x = v/v0 under f(x) = 2/(π(1+x²)²) (= 2/π; its ⟨x⁴⟩ diverges), a Gaussian
#: (√(2/π)) and two symmetric δ peaks (1): a bounded measure of the shape.
ABS_MEAN_F = 2.0 / math.pi
ABS_MEAN_GAUSSIAN = math.sqrt(2.0 / math.pi)


def _shape_numbers(v: np.ndarray, edges) -> dict:
    """Per run (rows of ``v``): x = (v − ⟨v⟩)/√var, kurtosis ⟨x⁴⟩ and ⟨|x|⟩; mean ± standard
    error over runs; pooled histogram density with its error from the run scatter."""
    x = rescaled(np.atleast_2d(v))
    kurt = np.mean(x**4, axis=1)
    absm = np.mean(np.abs(x), axis=1)
    width = np.diff(edges)
    dens = np.array([np.histogram(row, edges)[0] / (row.size * width) for row in x])
    r = x.shape[0]

    return {"kurtosis": mean_sem_json(kurt), "abs_mean": mean_sem_json(absm),
            "per_run_kurtosis": kurt.tolist(), "per_run_abs_mean": absm.tolist(),
            "_density": dens.mean(axis=0),
            "_density_error": (mean_sem(dens, axis=0)[1] if r > 1 else np.zeros(dens.shape[1]))}


def run(size=None, progress: bool | None = None, checkpoint_dir=None,
        runner=None, **overrides) -> Comparison:
    """Comparison 4 (paper Figs. 1a/1b): rescaled P(x), x = (v − ⟨v⟩)/v0, of MD, the lattice and
    the Ulam model at equal energy, early (MD homogeneous) and late (MD inhomogeneous).

    Energy is the common clock: MD (r = ``restitution``, density 1, δ = ``delta``) is recorded
    at ``md_t_early`` and ``md_t_late``; the lattice is stopped, run by run, where its energy
    equals the MD mean energy at that time (:func:`lattice_at_energy`), at the same r and, late,
    also at ``lattice_late_restitution`` (the paper's r = 0.5 for the lattice in the
    inhomogeneous regime), and the lattice whose bonds collide at a rate ∝ |v_i − v_{i+1}| as MD
    pairs do (``lattice_rv_r<r>``, :class:`particles.lattice.Lattice` with
    ``rate="relative_velocity"``; its time is MD's t); the Ulam model at the same r is taken at
    the τ where its exact mean
    energy e^{−2λτ N/(N−1)} equals the target, and f(x) = 2/(π(1+x²)²) is its τ → ∞ law.

    Choice of the MD times (r = 0.99): Haff's time t₀ = √π/((1 − r²) n) ≈ 89.  At t = 400 the
    gas is still close to Haff's homogeneous cooling (E/E_Haff is reported) and the kurtosis of
    P(x) is near its minimum along the run: the two-hump precursor of the homogeneous stage.
    At t = 3000 the gas is clustered and P(x) is back near a Gaussian.  The constant-rate
    lattice misses MD's two humps early because in MD a pair collides at a rate ∝ |Δ|; with
    that rate the lattice reproduces MD's P(x) at equal energy (the page "Measured results" of
    the documentation).

    Numbers per model and stage (mean ± standard error over seeds): kurtosis ⟨x⁴⟩ (Gaussian 3,
    two δ peaks 1, ∞ for f) and the bounded ⟨|x|⟩ (Gaussian 0.798, f 2/π = 0.637, two δ peaks 1).

    ``checkpoint_dir``: an existing folder where each MD run checkpoints and from which it
    resumes (:func:`.particle_runs.md_runs`); None (default): no checkpoints.

    Parameters
    ----------
    size : str, optional
        ``"small"``, ``"default"`` or ``"full"`` (the presets of ``PRESETS``); None (default):
        :func:`maxwell_kinetics.app.comparisons.base.default_size`.
    progress : bool or None, optional
        Show progress of the runs and solves (None, the default: a bar on a terminal or in a
        notebook, nothing otherwise).
    checkpoint_dir : str or os.PathLike, optional
        Existing folder for the MD runs' checkpoints (see above); default none.
    runner : maxwell_kinetics.app.comparisons.particle_runs.ParticleRuns, optional
        Where the particle runs execute and are kept; default a new serial one.
    **overrides
        Replace single parameters of the size's preset (e.g. ``n=20000``).

    Returns
    -------
    maxwell_kinetics.app.comparisons.base.Comparison
        ``summary``: the numbers above with their uncertainties, the parameters used and the
        wall-clock ``seconds``; ``data``: the arrays its figure is drawn from.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From :func:`maxwell_kinetics.app.comparisons.base.preset`: an unknown ``size`` or an
        override that is not a parameter of the preset.
    """
    runner = ParticleRuns() if runner is None else runner
    start = time.perf_counter()
    params = preset(PRESETS, size, overrides)
    edges = bin_edges(params["edges"])
    r = params["restitution"]
    md = runner.md_runs(params["restitution"], params["md_n"], params["delta"],
                        (params["md_t_early"], params["md_t_late"]),
                        tuple(range(params["md_seeds"])),
                        progress=progress,
                        checkpoint_dir=checkpoint_dir)
    stages = {}
    for j, stage in enumerate(("early", "late")):
        t = float(md["times"][j])
        e_md = md["energy"][:, j]
        target = float(np.mean(e_md))
        models = {"md": _shape_numbers(md["snapshots"][:, j], edges)}
        info = {"md_time": t, "energy": target,
                "energy_md_per_run": e_md.tolist(),
                "energy_over_haff": target / float(haff_energy(t, r, 1.0)),
                "md_collisions_per_particle": md["tau"][:, j].tolist()}
        lat_rs = [r] if stage == "early" else [r, params["lattice_late_restitution"]]
        lattices = ([(rl, ConstantRate.name) for rl in lat_rs]
                    + [(r, RelativeVelocity.name)])
        for rl, rate in lattices:
            lat = runner.lattice_at_energy(rl, params["lattice_n"], target,
                                           tuple(range(params["lattice_seeds"])), progress=progress,
                                           rate=rate)
            lab = (f"lattice_r{rl:g}" if rate == ConstantRate.name
                   else f"lattice_rv_r{rl:g}")
            models[lab] = _shape_numbers(lat["snapshots"], edges)
            info[lab + ("_tau" if rate == ConstantRate.name else "_t")] = lat["tau"].tolist()
            info[lab + "_energy"] = lat["energy"].tolist()
        lam = MaxwellModel(r).lam
        n_u = int(params["ulam_n"])
        tau_u = -math.log(target) / (2.0 * lam) * (n_u - 1) / n_u
        snaps = runner.ulam_snapshots(r, "gaussian", n_u, [tau_u],
                                      list(range(params["ulam_seeds"])), progress=progress)
        models["ulam"] = _shape_numbers(snaps[0], edges)
        info["ulam_tau"] = tau_u
        stages[stage] = {"info": info, "models": models}
    # Distances between the models' shape numbers in units of their combined standard error.
    for st_ in stages.values():
        m = st_["models"]
        comp = {}
        names = list(m)
        for a_i, a in enumerate(names):
            for b in names[a_i + 1:]:
                for q in ("kurtosis", "abs_mean"):
                    (va, ea), (vb, eb) = m[a][q], m[b][q]
                    err = math.hypot(ea or 0.0, eb or 0.0)
                    comp[f"{q}:{a}-{b}"] = (va - vb) / err if err > 0 else None
        st_["differences_in_sigma"] = comp
    summary = {
        "parameters": jsonable(params),
        "reference_values": {"abs_mean_f": ABS_MEAN_F, "abs_mean_gaussian": ABS_MEAN_GAUSSIAN,
                             "kurtosis_gaussian": 3.0, "kurtosis_f": None},
        "stages": {s: {"info": v["info"],
                       "models": {k: {q: w for q, w in mm.items() if not q.startswith("_")}
                                  for k, mm in v["models"].items()},
                       "differences_in_sigma": v["differences_in_sigma"]}
                   for s, v in stages.items()},
        "md_seconds": md["seconds"],
        "seconds": time.perf_counter() - start,
    }
    data = {"edges": edges, "stages": stages}
    return Comparison(NAME, with_verdicts(summary, verdicts), data)


def _dof(seeds: int) -> int | None:
    """Degrees of freedom of a standard error over ``seeds`` runs (None for fewer than 2, or
    0: not recorded)."""
    return seeds - 1 if seeds > 1 else None


def verdicts(s: dict) -> list:
    """The verdicts of comparison 4 (Figs. 1a/1b) from its summary ``s``: early, MD against
    the lattice at equal energy (refuted when the lattice with MD's collision rate agrees: the
    paper's constant-rate lattice does not equal MD, and its one collision rate is the cause)
    and against the Ulam model; late, MD against the lattice at r = 0.5 and against a
    Gaussian bulk.  Models are compared by their kurtosis or ⟨|x|⟩ with the seeds' standard
    errors added in quadrature (the quantile of Student's t with their Welch–Satterthwaite
    degrees of freedom at the coverage of 3σ).  The Gaussian bulk has no stated tolerance:
    MD's ⟨|x|⟩ against √(2/π) within :func:`.verdicts.student_sigmas` of its standard error
    (its σ comes from ``md_seeds`` runs only: Student's t with ``md_seeds − 1`` degrees of
    freedom at the coverage of 3σ, 9.2σ for 4 seeds)."""
    def model(stage, name, q):
        return pair(s["stages"][stage]["models"][name][q])

    par = s["parameters"]

    def seeds_of(name):
        return int(par.get("md_seeds" if name == "md" else
                           "ulam_seeds" if name == "ulam" else "lattice_seeds", 0))

    def versus(stage, a, b, q, relation="equal"):
        (va, ea), (vb, eb) = model(stage, a, q), model(stage, b, q)
        label = {"kurtosis": "kurtosis ⟨x⁴⟩", "abs_mean": "⟨|x|⟩"}[q]
        na, nb = seeds_of(a), seeds_of(b)
        return Check(f"{label} of {a}, {stage}", va, ea, vb, f"model: {b} at equal energy",
                     expected_sigma=eb, relation=relation, dof=_dof(na), expected_dof=_dof(nb),
                     sigma_source=f"seeds: standard errors over {na} ({a}) and {nb} ({b}) "
                                  f"runs, in quadrature", t_law=True)

    r = s["parameters"]["restitution"]
    r_late = s["parameters"]["lattice_late_restitution"]
    out = [judge(f"Fig. 1a: early (homogeneous) P(x) of the lattice equals MD's at equal energy, "
                 f"r = {r:g}",
                 versus("early", f"lattice_r{r:g}", "md", "kurtosis"),
                 refutation=versus("early", f"lattice_rv_r{r:g}", "md", "kurtosis"),
                 why="the lattice's bonds collide at one rate; with MD's rate ∝ |v_i − v_j| "
                     "the lattice matches MD",
                 short="1a: constant-rate lattice = MD, early"),
           judge("Fig. 1a: the Ulam (mean-field) P(x) does not resemble MD's",
                 versus("early", "ulam", "md", "kurtosis", relation="differs"),
                 short="1a: Ulam P(x) differs from MD's")]
    late = s["stages"]["late"]["models"]
    if f"lattice_r{r_late:g}" in late:
        out.append(judge(
            f"Fig. 1b: late (inhomogeneous) P(x) of the lattice at r = {r_late:g} equals MD's "
            f"at equal energy",
            versus("late", f"lattice_r{r_late:g}", "md", "abs_mean"),
            short=f"1b: lattice r = {r_late:g} = MD, late"))
    md, md_err = model("late", "md", "abs_mean")
    seeds = int(s["parameters"]["md_seeds"])
    out.append(judge(
        "Fig. 1b: the late MD bulk does not deviate appreciably from a Gaussian",
        Check("⟨|x|⟩ of MD, late", md, md_err, ABS_MEAN_GAUSSIAN,
              f"exact: Gaussian √(2/π); Student's t, {seeds - 1} degrees of freedom",
              n_sigma=student_sigmas(seeds), dof=_dof(seeds),
              sigma_source=f"seeds: standard error over {seeds} MD runs"),
        short="1b: late MD bulk is Gaussian"))
    return out


def plot(c, ax=None):
    """Two panels (new, or the two axes ``ax``), early and late: P(x) of each model (seed mean
    ± standard error) with f(x) and the Gaussian."""
    d = c.data
    edges = d["edges"]
    centres = 0.5 * (edges[1:] + edges[:-1])
    own = ax is None
    fig, axes = panels(2, ax, width=5.0)
    xf = np.linspace(edges[0], edges[-1], 400)
    for ax, stage in zip(axes, ("early", "late"), strict=True):
        st = d["stages"][stage]
        for i, (name, m) in enumerate(st["models"].items()):
            k, ke = m["kurtosis"]
            ax.errorbar(centres, m["_density"], yerr=m["_density_error"], fmt=".-", ms=3, lw=0.8,
                        color=f"C{i}", label=f"{name}: ⟨x⁴⟩={k:.2f}±{ke or 0:.2f}")
        ax.plot(xf, f_density(xf), "k--", lw=1, label="Ulam τ→∞: f(x)")
        ax.plot(xf, np.exp(-xf**2 / 2) / np.sqrt(2 * np.pi), "k:", lw=1, label="Gaussian")
        info = st["info"]
        ax.set(xlabel="x = (v − ⟨v⟩)/v0", ylabel="P(x)",
               title=f"{stage}: MD t={info['md_time']:g}, equal energy E={info['energy']:.3g}")
        ax.legend(fontsize=6)
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=4))
