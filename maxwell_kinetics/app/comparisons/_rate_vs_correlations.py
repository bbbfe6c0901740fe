"""Comparison 12: MD's kurtosis split into the effect of the collision rate (the hard-rod
Boltzmann equation against the Maxwell model at equal collision number) and the effect of
correlations (MD against the hard-rod Boltzmann equation), with the verdict on the paper's
attribution of the pseudo-Maxwell model's failure to correlations.  ``run`` computes, ``plot``
draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles.kernels import RelativeVelocity
from particles.observables import mean_sem

from ...exact import moment_hierarchy
from ...inelastic_boltzmann import scaling_state, solve_boltzmann
from ...model import MaxwellModel
from ...velocity_grid import VelocityGrid
from .analysis import bin_edges, rescaled
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import panels
from .particle_runs import ParticleRuns
from .verdicts import Check, judge, pair, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "verdicts", "collisions_per_particle",
           "maxwell_kurtosis", "kurtosis_split", "MODELS", "dsmc_share"]

NAME = "rate_vs_correlations"

_TIMES = ((5.0, 10.0, 25.0, 50.0, 100.0, 200.0, 300.0, 400.0),
          (2.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0))

PRESETS = {
    "small": {"restitutions": (0.99, 0.9), "times": _TIMES, "delta": 1e-4,
              "md_n": 2000, "md_seeds": 4, "dsmc_n": 5000, "dsmc_seeds": 16,
              "lattice_n": 2000, "lattice_seeds": 4, "ulam_n": 5000, "ulam_seeds": 16,
              "grid_points": 101, "dense_times": 101, "scaling_grid": (101, 6.0),
              "edges": (-3.0, 3.0, 0.25)},
    "default": {"restitutions": (0.99, 0.9), "times": _TIMES, "delta": 1e-4,
                "md_n": 50_000, "md_seeds": 4, "dsmc_n": 100_000, "dsmc_seeds": 4,
                "lattice_n": 50_000, "lattice_seeds": 4, "ulam_n": 100_000, "ulam_seeds": 4,
                "grid_points": 201, "dense_times": 401, "scaling_grid": None,
                "edges": (-3.0, 3.0, 0.1)},
    "full": {"restitutions": (0.99, 0.9), "times": _TIMES, "delta": 1e-4,
             "md_n": 200_000, "md_seeds": 4, "dsmc_n": 1_000_000, "dsmc_seeds": 4,
             "lattice_n": 200_000, "lattice_seeds": 4, "ulam_n": 1_000_000, "ulam_seeds": 4,
             "grid_points": 201, "dense_times": 401, "scaling_grid": None,
             "edges": (-3.0, 3.0, 0.05)},
}

#: The particle models of the comparison, in the order of the figure's legend: label → what it is.
MODELS = {
    "md": "MD, hard rods on a ring (density 1)",
    "dsmc": "DSMC of the hard-rod Boltzmann equation (Ulam, rate n|v − w|)",
    "lattice_rv": "lattice, rate ∝ |Δv| (with the kinematic constraint)",
    "maxwell": "Maxwell model (Ulam, constant rate) at the hard-rod collision number",
}

#: The correlation part counts as grown where it exceeds this many standard errors.
ONSET_SIGMAS = 3.0


def collisions_per_particle(solution) -> np.ndarray:
    """Collisions per particle τ(t) = ∫₀ᵗ n⟨|v − w|⟩ dt′ of a hard-rod Boltzmann solution, by the
    trapezoid rule over its saved times (which must start at t = 0 and be dense enough).

    Each particle collides at rate n⟨|v − w|⟩ (2n√(T/π) for a Gaussian of temperature T), with
    ⟨|v − w|⟩ = s Σᵢⱼ h² F_i F_j |c_i − c_j| on the solution's grid (v = u + s c).

    Parameters
    ----------
    solution : maxwell_kinetics.BoltzmannSolution
        A solution with γ = 1 whose first saved time is 0.

    Returns
    -------
    numpy.ndarray
        τ at each saved time, shape (T,), starting at 0.

    Raises
    ------
    ValueError
        If the first saved time is not 0.
    """
    if solution.t[0] != 0.0:
        raise ValueError(f"solution.t[0] = {solution.t[0]!r}: the solution must start at t = 0")
    c, h = solution.grid.c, solution.grid.h
    distance = np.abs(c[:, None] - c[None, :])
    mean_speed = h * h * np.einsum("ti,ij,tj->t", solution.F, distance, solution.F)
    rate = solution.number_density * solution.scale * mean_speed
    steps = 0.5 * (rate[1:] + rate[:-1]) * np.diff(solution.t)
    return np.concatenate([[0.0], np.cumsum(steps)])


def maxwell_kurtosis(restitution, tau) -> np.ndarray:
    """The Maxwell model's kurtosis ⟨v⁴⟩/⟨v²⟩² at collisions per particle ``tau`` from the unit
    Gaussian, exact: the closed moment hierarchy (:func:`maxwell_kinetics.exact.moment_hierarchy`).

    Parameters
    ----------
    restitution : float
        r.
    tau : array_like
        Increasing τ ≥ 0.

    Returns
    -------
    numpy.ndarray
        The kurtosis at each τ.
    """
    m = moment_hierarchy(MaxwellModel(restitution), [1.0, 0.0, 1.0, 0.0, 3.0],
                         np.asarray(tau, dtype=float))
    return m[:, 4] / m[:, 2] ** 2


def kurtosis_split(k_md, k_md_err, k_boltzmann, k_maxwell) -> dict:
    """MD's departure from the Maxwell model split into the rate part (hard-rod Boltzmann minus
    Maxwell) and the correlation part (MD minus hard-rod Boltzmann); their sum is the total.

    The errors are those of MD (the two kinetic kurtoses are deterministic).  The correlation
    share C/(R + C) has the error σ|R|/(R + C)².

    Parameters
    ----------
    k_md, k_md_err : array_like
        MD's kurtosis and its standard error, at each time.
    k_boltzmann, k_maxwell : array_like
        The hard-rod Boltzmann and the Maxwell kurtosis at the same times.

    Returns
    -------
    dict
        Arrays ``total``, ``rate``, ``correlation``, ``correlation_error``,
        ``correlation_share``, ``correlation_share_error``.
    """
    k_md, err = np.asarray(k_md, float), np.asarray(k_md_err, float)
    rate = np.asarray(k_boltzmann, float) - np.asarray(k_maxwell, float)
    corr = k_md - np.asarray(k_boltzmann, float)
    total = rate + corr
    with np.errstate(divide="ignore", invalid="ignore"):
        share = corr / total
        share_err = err * np.abs(rate) / total**2
    return {"total": total, "rate": rate, "correlation": corr, "correlation_error": err,
            "correlation_share": share, "correlation_share_error": share_err}


def _kurtosis_runs(snapshots: np.ndarray) -> np.ndarray:
    """Central kurtosis of each run and time: snapshots (R, T, N) → (R, T)."""
    return np.array([[np.mean(rescaled(row[None])[0] ** 4) for row in run] for run in snapshots])


def kurtosis_sampling_error(snapshots: np.ndarray) -> np.ndarray:
    """Standard error of the runs' mean kurtosis at each time from the particles themselves (the
    delta method for independent particles: K̂ − K ≈ mean of ψ(x) = (x⁴ − μ₄) − 2μ₄(x² − 1),
    x rescaled to unit variance), combined over the R runs: √(Σ var ψ/N)/R.  Exact for N → ∞ in
    the kinetic models (DSMC, Ulam), whose particles are independent up to O(1/N); it misses
    the correlations of MD and the lattice, whose errors come from the run scatter.

    Parameters
    ----------
    snapshots : numpy.ndarray
        Velocities, shape ``(R, T, N)``: R runs, T times, N particles.

    Returns
    -------
    numpy.ndarray
        The standard error at each of the T times.
    """
    out = np.empty(snapshots.shape[1])
    for j in range(snapshots.shape[1]):
        x = rescaled(snapshots[:, j, :])
        mu4 = np.mean(x**4, axis=1, keepdims=True)
        psi = (x**4 - mu4) - 2.0 * mu4 * (x**2 - 1.0)
        out[j] = math.sqrt(np.sum(np.var(psi, axis=1) / x.shape[1])) / x.shape[0]
    return out


def _model_record(snapshots: np.ndarray, edges) -> dict:
    """Kurtosis and energy (mean ± standard error over runs) at each time, the kurtosis's
    sampling error for independent particles, and the density of x = (v − ⟨v⟩)/√var at the
    last time (pooled runs, error from the run scatter)."""
    k = _kurtosis_runs(snapshots)
    e = np.mean(snapshots**2, axis=2)
    k_mean, k_err = mean_sem(k, axis=0)
    e_mean, e_err = mean_sem(e, axis=0)
    x = rescaled(snapshots[:, -1, :])
    width = np.diff(edges)
    dens = np.array([np.histogram(row, edges)[0] / (row.size * width) for row in x])
    return {"kurtosis": k_mean, "kurtosis_error": k_err, "per_run_kurtosis": k,
            "kurtosis_sampling_error": kurtosis_sampling_error(snapshots),
            "energy": e_mean, "energy_error": e_err, "density": dens.mean(axis=0),
            "density_error": mean_sem(dens, axis=0)[1]}


def _one_restitution(r, times, params, runner, progress) -> dict:
    """Every model at restitution ``r`` and the times ``times``."""
    times = np.asarray(times, dtype=float)
    edges = bin_edges(params["edges"])
    grid = VelocityGrid(int(params["grid_points"]), 6.0)
    dense = np.union1d(np.linspace(0.0, times[-1], int(params["dense_times"])), times)
    hr = solve_boltzmann(r, dense, grid=grid)
    tau = collisions_per_particle(hr)
    at = np.searchsorted(dense, times)
    k_max_dense = maxwell_kurtosis(r, tau)
    lam = MaxwellModel(r).lam
    sg = params["scaling_grid"]
    state = scaling_state(r, grid=None if sg is None else VelocityGrid(int(sg[0]), float(sg[1])))

    seeds = lambda k: tuple(range(int(params[k])))  # noqa: E731
    md = runner.md_runs(r, params["md_n"], params["delta"], tuple(times), seeds("md_seeds"),
                        progress=progress)
    dsmc = runner.ulam_runs({"n": int(params["dsmc_n"]), "restitution": r,
                             "rate": RelativeVelocity.name, "density": 1.0},
                            tuple(times), seeds("dsmc_seeds"), progress=progress)
    lat = runner.lattice_runs(r, params["lattice_n"], tuple(times), seeds("lattice_seeds"),
                              progress=progress, snapshots=True, rate=RelativeVelocity.name)
    n_u = int(params["ulam_n"])
    taus = [float(x) for x in tau[at]]
    ulam = runner.ulam_snapshots(r, "gaussian", n_u, taus, list(seeds("ulam_seeds")),
                                 progress=progress)
    models = {"md": _model_record(md["snapshots"], edges),
              "dsmc": _model_record(dsmc["snapshots"], edges),
              "lattice_rv": _model_record(lat["snapshots"], edges),
              "maxwell": _model_record(np.transpose(ulam, (1, 0, 2)), edges)}
    models["md"]["collisions_per_particle"] = md["tau"].mean(axis=0)
    models["dsmc"]["per_run_collisions_per_particle"] = 2.0 * dsmc["collisions"]
    models["dsmc"]["collisions_per_particle"] = 2.0 * dsmc["collisions"].mean(axis=0)

    k_hr, k_max = hr.kurtosis[at], k_max_dense[at]
    split = kurtosis_split(models["md"]["kurtosis"], models["md"]["kurtosis_error"], k_hr, k_max)
    grown = np.abs(split["correlation"]) > ONSET_SIGMAS * split["correlation_error"]
    onset = float(times[np.argmax(grown)]) if grown.any() else None
    x_fine = np.linspace(edges[0], edges[-1], 301)
    return {"restitution": r, "times": times, "dense_t": dense, "tau": tau,
            "boltzmann_kurtosis": hr.kurtosis, "boltzmann_energy": hr.energy,
            "maxwell_kurtosis": k_max_dense, "maxwell_energy": np.exp(-2.0 * lam * tau),
            "models": models, "split": split, "onset": onset,
            "boltzmann_density": hr.density(x_fine)[1], "scaling_density": state.density(x_fine),
            "x_fine": x_fine, "edges": edges, "scaling_kurtosis": state.kurtosis,
            "scaling_c6": state.moment(6), "scaling_residual": state.residual,
            "boltzmann_seconds": hr.seconds, "boltzmann_steps": hr.steps,
            "at": at}


def _z(a, ea, b, eb=0.0):
    err = math.hypot(ea, eb)
    return (a - b) / err if err > 0 else math.nan


def _summary_of(case) -> dict:
    """JSON rows of one restitution: per time, every model's kurtosis and the split."""
    m, s, at = case["models"], case["split"], case["at"]
    rows = []
    for j, t in enumerate(case["times"]):
        k_hr = float(case["boltzmann_kurtosis"][at[j]])
        k_max = float(case["maxwell_kurtosis"][at[j]])
        row = {"t": float(t), "collisions_per_particle": float(case["tau"][at[j]]),
               "md_collisions_per_particle": float(m["md"]["collisions_per_particle"][j]),
               "kurtosis": {"boltzmann": k_hr, "maxwell_exact": k_max}}
        for name, rec in m.items():
            row["kurtosis"][name] = [float(rec["kurtosis"][j]), float(rec["kurtosis_error"][j])]
        row["energy"] = {"boltzmann": float(case["boltzmann_energy"][at[j]]),
                         "maxwell_exact": float(case["maxwell_energy"][at[j]]),
                         **{name: [float(rec["energy"][j]), float(rec["energy_error"][j])]
                            for name, rec in m.items()}}
        row["split"] = {"total": [float(s["total"][j]), float(s["correlation_error"][j])],
                        "rate": float(s["rate"][j]),
                        "correlation": [float(s["correlation"][j]),
                                        float(s["correlation_error"][j])],
                        "correlation_share": [float(s["correlation_share"][j]),
                                              float(s["correlation_share_error"][j])]}
        row["dsmc_minus_boltzmann_in_sigma"] = _z(m["dsmc"]["kurtosis"][j],
                                                  m["dsmc"]["kurtosis_sampling_error"][j], k_hr)
        row["maxwell_particles_minus_exact_in_sigma"] = _z(
            m["maxwell"]["kurtosis"][j], m["maxwell"]["kurtosis_sampling_error"][j], k_max)
        rows.append(row)
    return {"restitution": case["restitution"], "rows": rows,
            "correlation_onset_t": case["onset"],
            "scaling_state": {"kurtosis": case["scaling_kurtosis"], "c6": case["scaling_c6"],
                              "residual": case["scaling_residual"]},
            "boltzmann_seconds": case["boltzmann_seconds"]}


def dsmc_share(row: dict) -> tuple[float | None, float | None]:
    """The correlation share measured with the DSMC in place of the deterministic hard-rod
    Boltzmann equation, (K_MD − K_DSMC)/(K_MD − K_Maxwell), and its standard error from MD's and
    the DSMC's seed errors: an estimate of the split that shares no number with
    ``split["correlation_share"]`` but MD's kurtosis (independent particles with the same
    rate, no correlations).

    Parameters
    ----------
    row : dict
        One time's row of the summary (``kurtosis`` with ``md``, ``dsmc``, ``maxwell_exact``).

    Returns
    -------
    (float or None, float or None)
        None where a kurtosis is missing or the departure MD − Maxwell is 0.
    """
    k = row["kurtosis"]
    (md, md_err), (ds, ds_err) = pair(k["md"]), pair(k["dsmc"])
    mx = k.get("maxwell_exact")
    if md is None or ds is None or mx is None or md == mx:
        return None, None
    total = md - mx
    err = math.hypot((md_err or 0.0) * (ds - mx) / total**2, (ds_err or 0.0) / total)
    return (md - ds) / total, err


def _energy_ratio(row: dict, name: str, exact: str = "boltzmann") -> tuple[float | None,
                                                                         float | None]:
    """E of model ``name`` over the deterministic E ``exact`` (the hard-rod Boltzmann
    equation's, or ``maxwell_exact``) at one time's row, with its standard error (the
    seeds')."""
    e, sigma = pair(row["energy"][name])
    b = row["energy"][exact]
    if e is None or not b:
        return None, None
    return e / b, None if sigma is None else sigma / b


def verdicts(s: dict) -> list:
    """The verdicts of comparison 12 from its summary ``s``.  Every tolerance built from the
    seeds' σ is the quantile of Student's t with seeds − 1 degrees of freedom at the coverage
    of 3 normal σ ("3σ" below: 9.22σ for MD's 4 seeds, 3.59σ for the DSMC's and the Ulam
    model's 16 at the small size); the rest (the largest |z|, the refutation) are 3σ.

    * The paper's attribution of MD's departure from the pseudo-Maxwell model to correlations,
      at the first restitution's last time: the correlation share (MD − hard-rod Boltzmann)/(MD
      − Maxwell) of the kurtosis departure must be at least 1/2 (3σ slack).  When it fails, it
      is ``refuted`` (the claim is false, and the collision rate is its cause) only when an
      independent estimate of the same share, with the DSMC particles in place of the
      deterministic Boltzmann equation (:func:`dsmc_share`), equals it within 3σ of their
      combined errors; otherwise (a share outside what the particles show, e.g. −5) it
      disagrees.  There is no explanation: the rate share 1 − share is the check's complement.
    * Molecular chaos at the first time: MD's kurtosis equals the hard-rod Boltzmann equation's
      within 3σ (σ from the MD seeds), and, for each restitution, MD's E over the Boltzmann
      equation's E equals 1 within 3σ at the first time (a broken engine shows there).
    * The DSMC equals its deterministic solution, and the constant-rate Ulam particles equal the
      exact moment hierarchy, in the kurtosis at every time: the largest |z| over the times is
      at most 3 (z in units of the sampling error of the kurtosis for independent particles);
      and the DSMC's E over the deterministic E, and the Ulam particles' E over the exact
      e^(−2λτ), equal 1 at the last time (where an error of the collision rate has accumulated
      most), 3σ of the seeds.
    """
    cases = s["cases"]
    par = s.get("parameters", {})

    def seeds(name):
        """(dof, sigma_source) of a standard error over the runs of ``name``."""
        n = int(par.get(f"{name}_seeds", 0))  # 0: not recorded (dof unknown)
        return {"dof": n - 1 if n > 1 else None, "t_law": True,
                "sigma_source": f"seeds: standard error over {n or 'the'} runs of "
                                f"{ {'md': 'MD', 'dsmc': 'the DSMC'}.get(name, 'the Ulam model')}"}

    quasi = cases[0]
    r0 = quasi["restitution"]
    last, first = quasi["rows"][-1], quasi["rows"][0]
    share, share_err = last["split"]["correlation_share"]
    independent, independent_err = dsmc_share(last)
    out = [judge(
        f"MD's departure from the pseudo-Maxwell model in the homogeneous stage is due to "
        f"correlations (the paper's conclusion), r = {r0:g}, t = {last['t']:g}",
        Check("correlation share (MD − hard-rod Boltzmann)/(MD − Maxwell) of the kurtosis "
              "departure", share, share_err, 0.5,
              "paper: the failure of the pseudo-Maxwell model attributed to correlations",
              relation="at_least", dof=seeds("md")["dof"], t_law=True,
              sigma_source="seeds: MD's standard error of the kurtosis over its runs, "
                           "propagated to the share (the Boltzmann and Maxwell values exact)"),
        refutation=Check("correlation share measured with the DSMC particles, (MD − DSMC)/(MD "
                         "− Maxwell)", independent, independent_err,
                         None if share is None or not math.isfinite(share) else share,
                         "model: the split's share (hard-rod Boltzmann equation)",
                         expected_sigma=share_err,
                         sigma_source="seeds: MD's and the DSMC's standard errors of the "
                                      "kurtosis, propagated to the share"),
        why="the DSMC (no correlations, rate n|v − w|) measures the same small share: the "
            "collision rate, not correlations, makes the departure",
        short="MD departure due to correlations")]
    c0, e0 = first["split"]["correlation"]
    out.append(judge(
        f"MD follows the hard-rod Boltzmann equation at first (molecular chaos), r = {r0:g}, "
        f"t = {first['t']:g}",
        Check("MD − hard-rod Boltzmann kurtosis", c0, e0, 0.0,
              "exact: molecular chaos for independent initial velocities and positions",
              **seeds("md")),
        short=f"MD K = Boltzmann K at t = {first['t']:g}"))
    for case in cases:
        r = case["restitution"]
        row = case["rows"][0]
        ratio, sigma = _energy_ratio(row, "md")
        out.append(judge(
            f"MD's E equals the hard-rod Boltzmann equation's at the first time (molecular "
            f"chaos), r = {r:g}, t = {row['t']:g}",
            Check(f"E of MD over E of the hard-rod Boltzmann equation at t = {row['t']:g}",
                  ratio, sigma, 1.0, "exact: molecular chaos at the start", **seeds("md")),
            short=f"MD E = Boltzmann E at t = {row['t']:g}, r = {r:g}"))
    for case in cases:
        r = case["restitution"]
        for key, name, target, short in (
                ("dsmc_minus_boltzmann_in_sigma", "the DSMC", "its deterministic solution",
                 "DSMC K = Boltzmann K"),
                ("maxwell_particles_minus_exact_in_sigma", "the constant-rate Ulam model",
                 "the exact moment hierarchy", "Ulam K = moment hierarchy")):
            z = [row[key] for row in case["rows"]]
            measured = (None if any(v is None or not math.isfinite(v) for v in z)
                        else max(abs(v) for v in z))  # a z not measured fails the check
            out.append(judge(
                f"{name} agrees with {target} in the kurtosis at every time, r = {r:g}",
                Check("largest |z| over the times, z in units of the kurtosis's sampling error",
                      measured, None, 3.0, "exact: the same kinetic equation (N → ∞)",
                      relation="at_most"), short=f"{short}, all t, r = {r:g}"))
        row = case["rows"][-1]
        ratio, sigma = _energy_ratio(row, "dsmc")
        out.append(judge(
            f"the DSMC's energy equals its deterministic solution's, r = {r:g}, "
            f"t = {row['t']:g}",
            Check(f"E of the DSMC over E of the hard-rod Boltzmann equation at t = "
                  f"{row['t']:g} (the last time)", ratio, sigma, 1.0,
                  "exact: the same kinetic equation (N → ∞)", **seeds("dsmc")),
            short=f"DSMC E = Boltzmann E, t = {row['t']:g}, r = {r:g}"))
        ratio, sigma = _energy_ratio(row, "maxwell", "maxwell_exact")
        out.append(judge(
            f"the constant-rate Ulam particles' energy equals the exact e^(−2λτ), r = {r:g}, "
            f"τ = {row['collisions_per_particle']:.4g}",
            Check(f"E of the Ulam particles over e^(−2λτ) at τ = "
                  f"{row['collisions_per_particle']:.4g} (the last time)", ratio, sigma, 1.0,
                  "exact: the Maxwell model's energy", **seeds("ulam")),
            short=f"Ulam E = e^(−2λτ), last τ, r = {r:g}"))
    return out


def run(size=None, progress: bool | None = None, runner=None, **overrides) -> Comparison:
    """Comparison 12: how much of MD's kurtosis departure from the Maxwell model is the collision
    rate and how much the correlations, at r = 0.99 (the paper's homogeneous stage to t = 400,
    then the onset of clustering) and r = 0.9 (clustering from t ≈ 20).

    Every model starts from the unit Gaussian (zero mean), at density 1, and is taken at the same
    physical times t:

    * MD: hard rods on a ring (point rods, regularisation δ = ``delta``: collisions slower than
      δ are elastic), through :meth:`ParticleRuns.md_runs`;
    * the hard-rod Boltzmann equation (rate n|v − w|), deterministic
      (:func:`maxwell_kinetics.inelastic_boltzmann.solve_boltzmann` on ``grid_points`` nodes of
      [−6, 6], saved at ``dense_times`` times; the scaling state on ``scaling_grid``, (points,
      half-width), None for the solver's default) and its DSMC (the Ulam engine with
      ``rate="relative_velocity"``);
    * the Maxwell model at equal collision number: τ(t) = ∫n⟨|v − w|⟩dt of the hard-rod
      solution (:func:`collisions_per_particle`), the kurtosis exact
      (:func:`maxwell_kurtosis`), and constant-rate Ulam particles at τ(t) for P(x);
    * the lattice with bond rate ∝ |Δv| (its time is MD's t at density 1).

    The split at each t (:func:`kurtosis_split`): total = K_MD − K_Maxwell, rate part =
    K_Boltzmann − K_Maxwell, correlation part = K_MD − K_Boltzmann (error: MD's standard error
    over seeds).  ``correlation_onset_t`` is the first t where the correlation part exceeds
    :data:`ONSET_SIGMAS` standard errors.  ``verdicts`` judges the paper's attribution to
    correlations (the share of the correlation part at the last time of r = 0.99), molecular
    chaos at the first time, and DSMC and the Ulam particles against their exact kinetics (σ:
    the kurtosis's sampling error for independent particles, by the delta method).
    The hard-rod scaling state (:func:`maxwell_kinetics.inelastic_boltzmann.scaling_state`) is
    drawn with P(x).

    Parameters
    ----------
    size : str, optional
        ``"small"``, ``"default"`` or ``"full"`` (the presets of ``PRESETS``); None (default):
        :func:`maxwell_kinetics.app.comparisons.base.default_size`.
    progress : bool or None, optional
        Show progress of the runs (None, the default: a bar on a terminal or in a notebook).
    runner : maxwell_kinetics.app.comparisons.particle_runs.ParticleRuns, optional
        Where the particle runs execute and are kept; default a new serial one.
    **overrides
        Replace single parameters of the size's preset (e.g. ``md_n=20000``).

    Returns
    -------
    maxwell_kinetics.app.comparisons.base.Comparison
        ``summary``: ``split_at_last_time`` and ``correlation_onset_t`` per restitution; in
        ``cases``, per restitution and time, every model's kurtosis and ⟨v²⟩ (mean ± standard
        error over seeds) and the split, and the scaling state; ``verdicts``; the parameters
        and the wall-clock ``seconds``; ``data``: the arrays of the figure.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From :func:`maxwell_kinetics.app.comparisons.base.preset`: an unknown ``size`` or an
        override that is not a parameter of the preset; ``restitutions`` and ``times`` of
        different lengths.
    """
    from particles.validation import InvalidArgumentError

    runner = ParticleRuns() if runner is None else runner
    start = time.perf_counter()
    params = preset(PRESETS, size, overrides)
    if len(params["restitutions"]) != len(params["times"]):
        raise InvalidArgumentError("times", params["times"],
                                   "one list of times per restitution")
    cases = [_one_restitution(float(r), ts, params, runner, progress)
             for r, ts in zip(params["restitutions"], params["times"], strict=True)]
    last = {}
    for c in cases:
        j, s = len(c["times"]) - 1, c["split"]
        err = float(s["correlation_error"][j])
        last[f"r{c['restitution']:g}_t{float(c['times'][j]):g}"] = {
            "total": {"value": float(s["total"][j]), "uncertainty": err},
            "rate": float(s["rate"][j]),
            "correlation": {"value": float(s["correlation"][j]), "uncertainty": err},
            "correlation_share": {"value": float(s["correlation_share"][j]),
                                  "uncertainty": float(s["correlation_share_error"][j])}}
    summary = {"parameters": jsonable(params),
               "split_at_last_time": last,
               "correlation_onset_t": {f"r{c['restitution']:g}": c["onset"] for c in cases},
               "cases": [_summary_of(c) for c in cases],
               "seconds": time.perf_counter() - start}
    return Comparison(NAME, with_verdicts(summary, verdicts), {"cases": cases})


_STYLE = {"md": ("C0", "o"), "dsmc": ("C1", "s"), "lattice_rv": ("C2", "^"),
          "maxwell": ("C3", "v")}


def plot(c, ax=None):
    """Four panels (new, or the four axes ``ax``): P(x) of every model at the last time of each
    restitution with the hard-rod Boltzmann solution and its scaling state; the kurtosis and
    ⟨v²⟩ against t (lines: hard-rod Boltzmann and the exact Maxwell model; points: particles)."""
    cases = c.data["cases"]
    own = ax is None
    fig, axes = panels(2 + 2, ax, width=4.6)
    for axis, case in zip(axes[:2], cases, strict=False):
        edges = case["edges"]
        centres = 0.5 * (edges[1:] + edges[:-1])
        t_last = float(case["times"][-1])
        for name, rec in case["models"].items():
            color, marker = _STYLE[name]
            axis.errorbar(centres, rec["density"], yerr=rec["density_error"], fmt=marker,
                          ms=2.5, lw=0.6, color=color, label=name)
        axis.plot(case["x_fine"], case["boltzmann_density"], "k-", lw=1.2,
                  label="hard-rod Boltzmann")
        axis.plot(case["x_fine"], case["scaling_density"], "k:", lw=1.2,
                  label=f"scaling state (K={case['scaling_kurtosis']:.3f})")
        axis.set(xlabel="x = (v − ⟨v⟩)/v0", ylabel="P(x)",
                 title=f"r = {case['restitution']:g}, t = {t_last:g}")
        axis.legend(fontsize=6)
    k_ax, e_ax = axes[2], axes[3]
    for i, case in enumerate(cases):
        ls = "-" if i == 0 else "--"
        lab = f"r={case['restitution']:g}"
        t = case["dense_t"][1:]
        k_ax.plot(t, case["boltzmann_kurtosis"][1:], "k" + ls, lw=1, label=f"Boltzmann {lab}")
        k_ax.plot(t, case["maxwell_kurtosis"][1:], "C3" + ls, lw=1, label=f"Maxwell {lab}")
        e_ax.plot(t, case["boltzmann_energy"][1:], "k" + ls, lw=1, label=f"Boltzmann {lab}")
        e_ax.plot(t, case["maxwell_energy"][1:], "C3" + ls, lw=1, label=f"Maxwell {lab}")
        for name, rec in case["models"].items():
            color, marker = _STYLE[name]
            mfc = color if i == 0 else "none"
            k_ax.errorbar(case["times"], rec["kurtosis"], yerr=rec["kurtosis_error"],
                          fmt=marker, ms=3, color=color, mfc=mfc,
                          label=name if i == 0 else None)
            e_ax.plot(case["times"], rec["energy"], marker, ms=3, color=color, mfc=mfc,
                      label=name if i == 0 else None)
    rs = [f"r={case['restitution']:g}" for case in cases]
    k_ax.set(xscale="log", xlabel="t", ylabel="kurtosis ⟨x⁴⟩",
             title="kurtosis (filled: " + ", open: ".join(rs) + ")")
    e_ax.set(xscale="log", yscale="log", xlabel="t", ylabel="⟨v²⟩", title="energy")
    k_ax.legend(fontsize=6)
    e_ax.legend(fontsize=6)
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=12))
