"""The catalogue of particle models (``particles.models``) and what is generated from it.

The cases are generated from the catalogue, not written by hand: a model or a parameter added
there is tested here without an edit.

* parity: every parameter of every model (its declared example value, on top of the required
  parameters' examples) runs through ``simulate`` (seeds 1 and 2, saved with ``--save``) and
  through ``ensemble --serial`` (``--seeds 1,2``); the task files, loaded back, hold the same
  numbers as the simulate runs of the same seed, bit for bit;
* bad input: for every parameter, each of a few malformed or out-of-range values (by kind) that
  the model refuses gets the same message from ``simulate`` and ``ensemble``: exit 2, the
  argument and the value named, and nothing written.
"""

import inspect
from pathlib import Path

import numpy as np
import pytest
from helpers import run_error, run_json

from particles.driver import RunResult
from particles.ensemble import EnsembleSpec, load_task
from particles.models import MODELS, REQUIRED, get_model
from particles.validation import InvalidArgumentError

#: Small runs: the parity cases are 22 (model, parameter) pairs, each 2 simulate runs and an
#: ensemble of 2 tasks.
N = "24"
TIMES = "0.5,1"


def _cli_models():
    from maxwell_kinetics.app.commands.model_options import cli_models

    return cli_models()


def _cases():
    return [(m.name, p.name) for m in _cli_models() for p in m.parameters]


def _text(value) -> str:
    return str(value).lower() if isinstance(value, bool) else str(value)


def _base(model) -> dict:
    """{name: text} of the required parameters (their examples; N particles)."""
    return {p.name: (N if p.name == "n" else _text(p.example))
            for p in model.parameters if p.required}


def _argv(model, texts: dict) -> list:
    return [f"{model.parameter(name).option}={text}" for name, text in texts.items()]


def _time(model, texts: dict) -> str:
    params = {name: model.parameter(name).parse(text) for name, text in texts.items()}
    return model.time_name(model.build(params))


def test_the_catalogue_declares_exactly_the_factories_keywords_and_defaults():
    for model in MODELS.values():
        signature = inspect.signature(model.factory).parameters
        keywords = [k for k, p in signature.items() if p.kind != p.VAR_KEYWORD]
        assert keywords == [p.name for p in model.declared], model.name
        # the parameters read from the kernels (ulam's exponent) go to the factory's **
        extra = model.names[len(keywords):]
        assert not extra or any(p.kind == p.VAR_KEYWORD for p in signature.values()), model.name
        for p in model.parameters[:len(keywords)]:
            default = signature[p.name].default
            assert (p.default is REQUIRED) == (default is inspect.Parameter.empty), p.name
            if not p.required:
                assert p.default == default and type(p.default) is type(default), p.name


def test_declared_examples_and_defaults_pass_their_own_checks():
    for model in _cli_models():
        for p in model.parameters:
            assert p.example is not None and p.example != p.default, (model.name, p.name)
            assert p.parse(_text(p.example)) == p.example
            if not p.required:
                assert p.parse(_text(p.default)) == p.default


def test_the_time_name_is_the_engines():
    lattice = get_model("lattice")
    assert lattice.time_names == ("tau", "t")
    for model_name, params, expected in [
        ("ulam", {"n": 10, "restitution": 0.5}, "tau"),
        ("lattice", {"n": 10, "restitution": 0.5}, "tau"),
        ("lattice", {"n": 10, "restitution": 0.5, "rate": "relative_velocity"}, "t"),
        ("md", {"n": 10, "density": 1.0, "restitution": 0.5}, "t"),
        ("sticky", {"n": 10, "density": 1.0}, "t"),
    ]:
        engine = get_model(model_name).build(params)
        assert engine.time_name == expected
        spec = EnsembleSpec(model_name, params, "1", (1.0,))
        assert spec.time_name == expected


@pytest.mark.parametrize("model_name, name", _cases())
def test_simulate_and_ensemble_give_the_same_numbers(capsys, tmp_path, model_name, name):
    model = get_model(model_name)
    p = model.parameter(name)
    texts = _base(model)
    texts[name] = N if name == "n" else _text(p.example)
    if p.needs:  # e.g. ulam's --angular needs --dimension 2 or 3
        other, values, _ = p.needs
        example = model.parameter(other).example
        texts.setdefault(other, _text(example if example in values else values[0]))
    time = _time(model, texts)
    argv = _argv(model, texts) + [f"--{time}", TIMES]
    runs = {}
    for seed in (1, 2):
        saved = tmp_path / f"seed{seed}.npz"
        payload = run_json(capsys, ["simulate", model_name, *argv, "--seed", str(seed), "--json",
                                    "--save", str(saved)])
        assert payload[time] == [0.5, 1.0]
        runs[seed] = RunResult.load(saved)
        assert runs[seed].params == payload["params"]
        assert runs[seed].energy.tolist() == payload["energy"]
    out = tmp_path / "e"
    report = run_json(capsys, ["ensemble", model_name, *argv, "--seeds", "1,2", "--serial",
                               "--out", str(out), "--json"])
    assert report["ok"] and report["ran"] == 2
    assert report["aggregate"][time] == [0.5, 1.0]
    tasks = [load_task(path) for path in sorted(out.glob("task-*.npz"))]
    assert sorted(t.seed for t in tasks) == [1, 2]
    for task in tasks:
        run = runs[task.seed]
        assert task.params == run.params
        assert task.params.get(name, p.example) == p.example or name == "n"
        for field in ("energy", "momentum", "collisions", "velocities"):
            np.testing.assert_array_equal(getattr(task, field), getattr(run, field))
        assert task.extras.keys() == run.extras.keys()
        for key in task.extras:
            np.testing.assert_array_equal(task.extras[key], run.extras[key])


#: Candidate bad values by kind; those the model refuses (parsed, or when the engine is built)
#: are tested.  Every parameter must be refused for at least one of them.
_CANDIDATES = {
    "int": ["x", "1.5", "-1", "0", "4e9"],
    "float": ["x", "nan", "inf", "-1", "0", "2", "1e-310", "1e308"],
    "choice": ["nosuch", "Gaussian"],
    "flag": ["maybe", "2"],
}


def _bad_values(model, name) -> list[str]:
    base = {k: model.parameter(k).parse(v) for k, v in _base(model).items()}
    bad = []
    for text in _CANDIDATES[model.parameter(name).kind]:
        try:
            model.build({**base, name: model.parameter(name).parse(text)})
        except InvalidArgumentError:
            bad.append(text)
    return bad


def _parsed(model, name, text) -> str:
    """The value as the engine shows it (for values refused by the engine, not the parser)."""
    try:
        return repr(model.parameter(name).parse(text))
    except InvalidArgumentError:
        return text


def _message(err: str, command: str) -> str:
    prefix = f"maxwell-kinetics {command}: error: "
    assert err.startswith(prefix) and err.count("\n") == 1 and "Traceback" not in err, err
    return err[len(prefix):]


@pytest.mark.parametrize("model_name, name", _cases())
def test_a_bad_value_gets_one_message_from_both_commands(capsys, tmp_path, model_name, name):
    model = get_model(model_name)
    bad = _bad_values(model, name)
    assert bad, f"no candidate value is refused for {model_name} {name}"
    for text in bad:
        texts = {**_base(model), name: text}
        time = _time(model, _base(model))  # the base's engine: the bad value has none
        argv = _argv(model, texts) + [f"--{time}", TIMES]
        ckpt, saved, out = tmp_path / "c.ckpt", tmp_path / "s.npz", tmp_path / "e"
        err_sim = run_error(capsys, ["simulate", model_name, *argv, "--checkpoint", str(ckpt),
                                     "--save", str(saved)])
        err_ens = run_error(capsys, ["ensemble", model_name, *argv, "--seeds", "1", "--serial",
                                     "--out", str(out)])
        message = _message(err_sim, "simulate")
        assert message == _message(err_ens, "ensemble")
        label = model.parameter(name).option.lstrip("-")  # the option as typed: rod-length
        assert message.startswith(f"argument {label}="), message
        assert text in message or _parsed(model, name, text) in message, message
        assert list(tmp_path.iterdir()) == [], (model_name, name, text)


@pytest.mark.parametrize("argv, named", [
    (["--angular", "hard"], "angular='hard'"),  # default dimension 1: no collision direction
    (["--angular", "uniform", "--dimension", "1"], "angular='uniform'"),
    (["--driving", "0", "--dimension", "2"], "driving=0.0"),  # driving is one-dimensional
])
def test_an_option_that_needs_another_is_refused_without_it(capsys, tmp_path, argv, named):
    base = ["ulam", "--n", N, "--restitution", "0.5", "--tau", TIMES, *argv]
    err = run_error(capsys, ["simulate", *base, "--save", str(tmp_path / "s.npz")])
    assert named in err and "--dimension" in err
    err = run_error(capsys, ["ensemble", *base, "--seeds", "1", "--serial",
                             "--out", str(tmp_path / "e")])
    assert named in err and "--dimension" in err
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(InvalidArgumentError, match="--dimension 2 or 3"):
        get_model("ulam").build({"n": 10, "restitution": 0.5, "angular": "hard"})
    # with the setting it needs, the option is taken
    engine = get_model("ulam").build({"n": 10, "restitution": 0.5, "angular": "hard",
                                      "dimension": 2})
    assert engine.angular == "hard"


@pytest.mark.parametrize("option, values, shown", [
    ("--restitution", "0.5,0.50", "0.5"), ("--restitution", "0,-0", "0.0"),
    ("--n", "1000,1e3", "1000"), ("--driving", "0,0.0", "0.0"),
])
def test_a_sweep_that_gives_one_value_twice_is_refused(capsys, tmp_path, option, values, shown):
    base = {"--n": N, "--restitution": "0.5", option: values}
    argv = [a for k, v in base.items() for a in (k, v)]
    err = run_error(capsys, ["ensemble", "ulam", *argv, "--tau", TIMES, "--seeds", "1",
                             "--serial", "--out", str(tmp_path / "e")])
    assert f"{shown} is given twice" in err and values in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("model_name", ["md", "sticky"])
def test_a_density_whose_ring_length_overflows_is_refused(capsys, tmp_path, model_name):
    argv = ["simulate", model_name, "--n", "10", "--density", "1e-310", "--t", "1",
            "--save", str(tmp_path / "s.npz")]
    if model_name == "md":
        argv += ["--restitution", "0.5"]
    err = run_error(capsys, argv)
    assert "density=1e-310" in err and "finite" in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_the_time_option_must_be_the_engines(capsys, tmp_path):
    base = ["lattice", "--n", N, "--restitution", "0.5", "--rate", "relative_velocity"]
    err = run_error(capsys, ["simulate", *base, "--tau", "1"])
    assert "tau='1'" in err and "--t" in err
    err = run_error(capsys, ["ensemble", *base, "--tau", "1", "--seeds", "1", "--serial",
                             "--out", str(tmp_path / "e")])
    assert "tau='1'" in err and not (tmp_path / "e").exists()
    # a sweep over engines of two different times is refused
    err = run_error(capsys, ["ensemble", "lattice", "--n", N, "--restitution", "0.5", "--rate",
                             "constant,relative_velocity", "--tau", "1", "--seeds", "1",
                             "--serial", "--out", str(tmp_path / "e")])
    assert "one time" in err and not (tmp_path / "e").exists()


def test_the_switch_of_a_flag_equals_its_option_and_a_flag_can_be_swept(capsys, tmp_path):
    base = ["lattice", "--n", N, "--restitution", "0.5", "--tau", TIMES, "--json"]
    a = run_json(capsys, ["simulate", *base, "--no-constraint"])
    b = run_json(capsys, ["simulate", *base, "--constraint", "false"])
    c = run_json(capsys, ["simulate", *base])
    assert a == {**b, "seconds": a["seconds"]} and a["params"]["constraint"] is False
    assert c["params"]["constraint"] is True
    report = run_json(capsys, ["ensemble", *base, "--constraint", "true,false", "--seeds", "0",
                               "--serial", "--out", str(tmp_path / "e")])
    sets = report["aggregate"]["sets"]
    assert [s["params"]["constraint"] for s in sets] == [True, False]
    assert sets[1]["observables"]["energy"]["mean"] == a["energy"]
    assert sets[0]["observables"]["energy"]["mean"] == c["energy"]


def test_register_model_adds_to_the_catalogue():
    from particles.ensemble import register_model, registered_models

    def factory(n, restitution, initial="gaussian"):
        from particles.ulam import Ulam

        return Ulam(n, restitution, initial)

    try:
        model = register_model("ulam-plain", factory)
        assert registered_models()["ulam-plain"] == ("n", "restitution", "initial")
        assert model.required == ("n", "restitution") and model.time_names == ("tau",)
        assert "ulam-plain" not in [m.name for m in _cli_models()]  # undeclared: Python only
        spec = EnsembleSpec("ulam-plain", {"n": 10, "restitution": 0.5}, "1", (1.0,))
        assert spec.time_name == "tau"
    finally:
        MODELS.pop("ulam-plain", None)


def test_ensemble_task_keys_do_not_depend_on_how_a_value_is_written(capsys, tmp_path):
    keys = []
    for n in ("24", "2.4e1"):
        out = tmp_path / n
        run_json(capsys, ["ensemble", "ulam", "--n", n, "--restitution", "0.5", "--tau", "1",
                          "--seeds", "1", "--serial", "--out", str(out), "--json"])
        keys.append(sorted(p.name for p in Path(out).glob("task-*.npz")))
    assert keys[0] == keys[1] and len(keys[0]) == 1
