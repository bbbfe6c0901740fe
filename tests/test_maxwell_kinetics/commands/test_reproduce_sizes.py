"""``reproduce`` never loses another run's results: a folder that holds results of another size
is refused unless ``--force`` (``reproduce --small --out results`` replaced the default-size
results of ``make demo``, 19 minutes of work), a run of another size writing the same folder
meanwhile is refused at the next write, and a PNG of a comparison's name is replaced only when
this program wrote it (a photo passed the old 8-byte check)."""

from __future__ import annotations

import json

import matplotlib.figure
import pytest
from helpers import run_error, run_json

from maxwell_kinetics.app import comparisons
from maxwell_kinetics.app.reproduce import FIGURE_SOURCE, is_our_figure, run_all
from particles.validation import InvalidArgumentError

SMALL = ["reproduce", "--small", "--only", "tail_exponents", "--json", "--no-progress"]


def _write_summary(folder, size, names):
    text = json.dumps({"size": size, "comparisons": {n: {"x": 1.5} for n in names}})
    (folder / "summary.json").write_text(text)
    return text


def _no_work(monkeypatch):
    def reached(*args, **kwargs):
        raise AssertionError("the work started before the outputs were checked")

    for name in comparisons.COMPARISONS:
        monkeypatch.setitem(comparisons.COMPARISONS, name, reached)


def test_a_small_run_over_default_results_is_refused_even_when_it_would_replace_them_all(
        capsys, tmp_path, monkeypatch):
    _no_work(monkeypatch)
    text = _write_summary(tmp_path, "default", list(comparisons.COMPARISONS))
    err = run_error(capsys, ["reproduce", "--small", "--json", "--no-progress", "--out",
                             str(tmp_path)])
    assert f"argument out='{tmp_path / 'summary.json'}'" in err
    assert "size 'default'" in err and "--force" in err, err
    assert (tmp_path / "summary.json").read_text() == text


def test_force_replaces_the_results_of_another_size(capsys, tmp_path):
    _write_summary(tmp_path, "default", ["tail_exponents"])
    run_json(capsys, SMALL + ["--force", "--out", str(tmp_path)])
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["size"] == "small" and list(summary["comparisons"]) == ["tail_exponents"]
    # its figure carries the mark, so a second run may replace it
    assert is_our_figure(tmp_path / "tail_exponents.png") is None
    run_json(capsys, SMALL + ["--out", str(tmp_path)])


def test_a_run_of_another_size_writing_meanwhile_is_refused_not_overwritten(tmp_path,
                                                                            monkeypatch):
    real = comparisons.COMPARISONS["tail_exponents"]

    def meanwhile(*args, **kwargs):  # another run, at the default size, finishes first
        _write_summary(tmp_path, "default", ["driven_steady"])
        return real(*args, **kwargs)

    monkeypatch.setitem(comparisons.COMPARISONS, "tail_exponents", meanwhile)
    with pytest.raises(InvalidArgumentError, match="a run at size 'default' wrote"):
        run_all(tmp_path, "small", only=["tail_exponents"], progress=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["size"] == "default" and list(summary["comparisons"]) == ["driven_steady"]


def _png(path, source=None):
    figure = matplotlib.figure.Figure(figsize=(1, 1))
    figure.add_subplot().plot([0, 1])
    figure.savefig(path, format="png", metadata=None if source is None else {"Source": source})


def test_a_png_this_program_did_not_write_is_never_replaced(capsys, tmp_path, monkeypatch):
    _no_work(monkeypatch)
    photo = tmp_path / "tail_exponents.png"
    _png(photo)  # a valid PNG (Matplotlib's, even), but no comparison file beside it
    before = photo.read_bytes()
    err = run_error(capsys, SMALL + ["--out", str(tmp_path)])
    assert f"argument out='{photo}'" in err and "did not write" in err, err
    assert photo.read_bytes() == before
    assert is_our_figure(photo) == "it is a PNG image this program did not write"
    _png(photo, "another program")
    assert is_our_figure(photo) is not None
    _png(photo, FIGURE_SOURCE)
    assert is_our_figure(photo) is None


def test_a_figure_of_an_earlier_version_beside_its_comparison_file_is_ours(capsys, tmp_path):
    run_json(capsys, SMALL + ["--out", str(tmp_path)])
    figure = tmp_path / "tail_exponents.png"
    _png(figure)  # as written before the mark: Matplotlib's, beside tail_exponents.npz
    assert is_our_figure(figure) is None
    (tmp_path / "tail_exponents.npz").unlink()
    assert is_our_figure(figure) is not None
