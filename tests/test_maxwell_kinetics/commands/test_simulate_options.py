"""``simulate``: an option that means something only with another one is refused without it,
every option given is checked (and named as the user typed it) even where it would be ignored,
and a long bad value is cut in the message.  Nothing is written on bad input."""

from __future__ import annotations

import pytest
from helpers import run_error, run_json

ULAM = ["simulate", "ulam", "--n", "50", "--restitution", "0.5", "--tau", "1"]
STICKY = ["simulate", "sticky", "--n", "50", "--density", "1", "--t", "1"]
MD = ["simulate", "md", "--n", "20", "--density", "1", "--restitution", "0.5", "--t", "1"]


@pytest.mark.parametrize("argv, shown, words", [
    (STICKY + ["--workers", "2"], "workers='2'", "without --chunks"),
    (STICKY + ["--scheduler", "tcp://127.0.0.1:9"], "scheduler=", "without --chunks"),
    (ULAM + ["--checkpoint-interval", "5", "--save", "OUT"], "checkpoint-interval='5'",
     "without --checkpoint"),
    (ULAM + ["--checkpoint-interval", "nan", "--checkpoint", "OUT"],
     "checkpoint-interval='nan'", "finite"),
    (ULAM + ["--checkpoint-interval", "-1", "--checkpoint", "OUT"],
     "checkpoint-interval='-1'", ">= 0"),
    (STICKY + ["--chunks", "2", "--checkpoint-interval", "5"], "checkpoint-interval='5'",
     "with --chunks"),
    (ULAM[:-1] + ["0,-0", "--save", "OUT"], "tau='0,-0'", "repeated"),
    (ULAM[:-1] + ["1,1e400", "--save", "OUT"], "tau='1,1e400'", "finite"),
    # the option as typed, not the keyword rod_length / stop_step
    (MD + ["--rod-length", "1e400", "--save", "OUT"], "rod-length='1e400'", "finite"),
    (MD + ["--rod-length", "1", "--save", "OUT"], "rod-length=1.0", "fit"),  # engine's check
    (MD + ["--stop-step", "0", "--save", "OUT"], "stop-step='0'", "> 0"),
])
def test_an_option_is_checked_and_needs_its_partner(capsys, tmp_path, argv, shown, words):
    argv = [str(tmp_path / "out") if a == "OUT" else a for a in argv]
    err = run_error(capsys, argv)
    assert shown in err and words in err and "Traceback" not in err
    for internal in ("checkpoint_interval", "rod_length", "stop_step"):
        assert f"argument {internal}=" not in err  # the option as typed, not the keyword
    assert list(tmp_path.iterdir()) == []


def test_a_long_bad_value_is_cut_in_the_message(capsys):
    err = run_error(capsys, ULAM[:-1] + [",".join(["1"] * 3000)])
    assert "tau='1,1,1" in err and "6001 characters" in err and len(err) < 400


def test_the_interval_is_taken_with_a_checkpoint(capsys, tmp_path):
    out = run_json(capsys, ULAM + ["--checkpoint", str(tmp_path / "c.ckpt"),
                                   "--checkpoint-interval", "0", "--json"])
    assert out["tau"] == [1.0]


@pytest.mark.parametrize("json", [True, False])
def test_an_energy_that_overflows_is_a_failure_not_a_result(capsys, tmp_path, json):
    # --driving 1e307 at r = 1: the energy ~ 2 D tau is beyond float64 at tau = 1.  The JSON
    # output crashed with a traceback after printing half an object; the table printed inf
    # with exit status 0.
    argv = ["simulate", "ulam", "--n", "50", "--restitution", "1", "--driving", "1e307",
            "--tau", "1,100", "--save", str(tmp_path / "s.npz")] + (["--json"] if json else [])
    err = run_error(capsys, argv, status=3)
    assert "overflowed" in err and "tau = 1" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []
