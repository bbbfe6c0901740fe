"""Where an ensemble runs: a local dask cluster, an existing scheduler, or a batch cluster
(SLURM, PBS) through dask-jobqueue with a TOML configuration."""

from __future__ import annotations

import os

from ..validation import InvalidArgumentError

#: Seconds allowed to connect to an existing scheduler (``scheduler=ADDRESS``).
SCHEDULER_TIMEOUT = 10.0


_CLUSTER_KEYS = {
    "queue": str, "walltime": str, "cores": int, "memory": str, "processes": int, "jobs": int,
    "account": str, "job_extra_directives": list, "job_script_prologue": list, "interface": str,
    "local_directory": str, "log_directory": str, "python": str, "dashboard_address": str,
}


def load_cluster_config(path, cluster: str) -> dict:
    """Settings of a batch cluster from a TOML file (top-level keys, or a ``[slurm]`` /
    ``[pbs]`` table)::

        queue = "normal"          # SLURM partition / PBS queue
        walltime = "02:00:00"     # per job
        cores = 16                # cores per job (required)
        memory = "64GB"           # memory per job (required)
        processes = 16            # worker processes per job (default: cores, 1 thread each)
        jobs = 4                  # jobs started (default 1)
        account = "proj42"        # optional: account / project
        job_extra_directives = ["--constraint=cpu"]
        job_script_prologue = ["module load python"]
        interface = "ib0"         # optional network interface
        local_directory = "/tmp"  # optional worker scratch
        log_directory = "logs"    # optional job logs
        dashboard_address = ":8787"  # optional; default ":0" (a free port)

    The values go to ``dask_jobqueue.SLURMCluster`` / ``PBSCluster`` under the same names.

    Parameters
    ----------
    path : str or os.PathLike
        The TOML file.
    cluster : str
        ``"slurm"`` or ``"pbs"``.

    Returns
    -------
    dict
        The checked settings, with ``processes`` (default ``cores``) and ``jobs`` (default 1).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``cluster``) if it is not ``"slurm"`` or ``"pbs"``; (argument ``config``)
        for an unreadable or invalid TOML file, an unknown key, a value of the wrong type, or
        a missing ``cores`` or ``memory``.
    """
    if cluster not in ("slurm", "pbs"):
        raise InvalidArgumentError("cluster", cluster, "'slurm' or 'pbs'")
    if not isinstance(path, (str, os.PathLike)) or not str(path):
        raise InvalidArgumentError("config", path, "the path of a TOML file")
    try:
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except (OSError, TypeError) as exc:
        raise InvalidArgumentError("config", str(path), f"a readable TOML file ({exc})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:  # a binary file: not UTF-8
        raise InvalidArgumentError("config", str(path), f"valid TOML ({exc})") from None
    if isinstance(data.get(cluster), dict):
        data = data[cluster]
    settings = {}
    for key, value in data.items():
        if key in ("slurm", "pbs"):
            continue
        kind = _CLUSTER_KEYS.get(key)
        if kind is None:
            raise InvalidArgumentError("config", f"{path}: {key}",
                                       f"keys among {sorted(_CLUSTER_KEYS)}")
        if not isinstance(value, kind) or isinstance(value, bool) or (
            kind is int and value < 1
        ) or (kind is list and not all(isinstance(v, str) for v in value)):
            wanted = "an integer >= 1" if kind is int else f"a {kind.__name__}"
            raise InvalidArgumentError("config", f"{path}: {key} = {value!r}", f"{key}: {wanted}")
        settings[key] = value
    missing = [k for k in ("cores", "memory") if k not in settings]
    if missing:
        raise InvalidArgumentError("config", str(path), f"the keys {missing}")
    settings.setdefault("processes", settings["cores"])
    settings.setdefault("jobs", 1)
    return settings


def require_jobqueue(cluster: str) -> None:
    """Check that the optional ``dask-jobqueue`` (the extra ``cluster``) can be imported.

    Parameters
    ----------
    cluster : str
        The batch system asked for (``"slurm"`` or ``"pbs"``), named in the error.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``cluster``) if ``dask_jobqueue`` cannot be imported; the message says what
        to install.
    """
    try:
        import dask_jobqueue  # noqa: F401
    except ImportError:
        raise InvalidArgumentError(
            "cluster", cluster,
            "the optional package dask-jobqueue, which is not installed "
            "(pip install 'maxwell-kinetics[cluster]')") from None


def local_cluster(workers: int | None = None):
    """A ``dask.distributed.LocalCluster`` of ``workers`` single-threaded worker processes
    (default: one per core) with one BLAS/OpenMP thread each, and WITHOUT distributed's default
    ``MALLOC_TRIM_THRESHOLD_=65536``: with it glibc gives every large temporary array back to the
    OS, and the engines' O(N) temporaries then pay page faults on every allocation, which makes
    tasks on the workers markedly slower than the same runs in the parent process.

    Parameters
    ----------
    workers : int, optional
        Number of worker processes (default: dask's choice, one per core).

    Returns
    -------
    distributed.LocalCluster
        The started cluster (the caller closes it).
    """
    import dask
    from distributed import LocalCluster

    environ = {name: 1 for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                    "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")}
    with dask.config.set({"distributed.nanny.pre-spawn-environ": environ}):
        # ":0" and no dashboard: the scheduler's HTTP routes on a free port (the default 8787
        # may be taken by another cluster, and dask then warns)
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                            dashboard_address=":0", scheduler_kwargs={"dashboard": False})


def make_cluster(cluster: str, settings: dict):
    """A ``dask_jobqueue.SLURMCluster`` or ``PBSCluster`` (no job submitted yet; scale it with
    ``cluster.scale(jobs=settings["jobs"])``).

    Parameters
    ----------
    cluster : str
        ``"slurm"`` or ``"pbs"``.
    settings : dict
        Settings of :func:`load_cluster_config`; ``jobs`` is not passed on and
        ``dashboard_address`` goes to the scheduler (default ``":0"``).

    Returns
    -------
    dask_jobqueue.SLURMCluster or dask_jobqueue.PBSCluster
        The cluster object.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``cluster``) if dask-jobqueue is not installed
        (:func:`particles.ensemble.cluster.require_jobqueue`).
    """
    require_jobqueue(cluster)
    import dask_jobqueue

    kwargs = {k: v for k, v in settings.items() if k not in ("jobs", "dashboard_address")}
    kwargs["scheduler_options"] = {"dashboard_address": settings.get("dashboard_address", ":0")}
    cls = {"slurm": dask_jobqueue.SLURMCluster, "pbs": dask_jobqueue.PBSCluster}[cluster]
    return cls(**kwargs)


def cluster_job_script(cluster: str, config) -> str:
    """The batch script the cluster would submit per job (needs no batch system).

    Parameters
    ----------
    cluster : str
        ``"slurm"`` or ``"pbs"``.
    config : str or os.PathLike
        The TOML file of :func:`load_cluster_config`.

    Returns
    -------
    str
        The job script.
    """
    settings = load_cluster_config(config, cluster)
    c = make_cluster(cluster, settings)
    try:
        return c.job_script()
    finally:
        c.close()


def check_scheduler(scheduler) -> str:
    """Check the form of a scheduler address (a non-empty string, such as
    ``tcp://host:8786``); whether it answers is seen on connecting.

    Parameters
    ----------
    scheduler : str
        The address.

    Returns
    -------
    str
        The address.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``scheduler``) for anything but a non-empty string without blanks.
    """
    if not isinstance(scheduler, str) or not scheduler.strip() or any(
            c.isspace() for c in scheduler):
        raise InvalidArgumentError("scheduler", scheduler,
                                   "the address of a dask scheduler, such as tcp://host:8786")
    return scheduler


def connect(executor, workers, scheduler, cluster, config):
    """(client, closer) for the dask executors; errors name the argument."""
    from distributed import Client

    if scheduler is not None:
        check_scheduler(scheduler)
        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except ValueError as exc:  # not an address (raised at once, not after the timeout)
            raise InvalidArgumentError(
                "scheduler", scheduler,
                f"the address of a dask scheduler, such as tcp://host:8786 ({exc})"[:300],
            ) from None
        except (OSError, TimeoutError) as exc:
            raise InvalidArgumentError(
                "scheduler", scheduler,
                f"the address of a reachable dask scheduler (no connection within "
                f"{SCHEDULER_TIMEOUT:g} s: {type(exc).__name__})",
            ) from None
        return client, [client.close]
    if cluster is not None:
        settings = load_cluster_config(config, cluster)
        c = make_cluster(cluster, settings)
        c.scale(jobs=settings["jobs"])
        client = Client(c)
        return client, [client.close, c.close]
    c = local_cluster(workers)
    client = Client(c)
    return client, [client.close, c.close]
