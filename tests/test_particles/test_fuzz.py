"""Property-based tests (hypothesis) of the argument parsers and the file loaders.

The property in every case: untrusted input either gives the right answer or raises
``InvalidArgumentError`` (``FileFormatError`` for files) naming the argument; never another
exception, never a hang, never a wrong value.  Example counts are set so the file runs in a few
seconds; the number of cases each test tries is its ``max_examples``.
"""

from __future__ import annotations

import io
import json
import zipfile
from decimal import Decimal

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from particles import persistence
from particles.validation import (
    InvalidArgumentError,
    parse_float_list,
    parse_int,
    parse_name_list,
    parse_seed,
)

FAST = settings(max_examples=300, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture])


@FAST
@given(st.integers(min_value=0, max_value=2**64 - 1))
def test_every_seed_round_trips_exactly(seed):
    assert parse_seed(str(seed)) == seed
    assert parse_seed(f"{seed}.0") == seed


@FAST
@given(st.text(max_size=40))
def test_parse_int_is_exact_or_refuses(text):
    try:
        value = parse_int(text, "n")
    except InvalidArgumentError as exc:
        assert exc.name == "n" and exc.value == text
        return
    # accepted: the text is exactly this integer as a decimal number
    assert Decimal(text.strip()) == value


@FAST
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=8,
                unique_by=lambda x: x + 0.0))  # repeats (0.0 and -0.0 included) are refused
def test_float_lists_round_trip(values):
    text = ",".join(repr(v) for v in values)
    assert parse_float_list(text, "tau") == values


@FAST
@given(st.text(alphabet=st.sampled_from("0123456789.,- e"), max_size=20))
def test_float_lists_refuse_empty_elements(text):
    try:
        out = parse_float_list(text, "tau")
    except InvalidArgumentError as exc:
        assert exc.name == "tau"
        return
    parts = text.split(",")
    assert len(out) == len(parts) and all(p.strip() for p in parts)


@FAST
@given(st.lists(st.text(alphabet="abcdefgh_", min_size=0, max_size=5), max_size=5))
def test_name_lists(names):
    text = ",".join(names)
    try:
        out = parse_name_list(text, "only")
    except InvalidArgumentError:
        assert not names or any(not n.strip() for n in names) or len(set(names)) < len(names)
        return
    assert out == names


def _valid_file() -> bytes:
    path = io.BytesIO()
    arrays = {"a": np.arange(6.0).reshape(2, 3), "b": np.array([1, 2, 3], dtype=np.int64)}
    meta = {"format": persistence.FORMAT_TAG, "kind": "thing", "version": 1, "x": 1}
    meta["sha256"] = persistence.digest(meta, arrays)
    np.savez(path, meta=np.array(json.dumps(meta)), **arrays)
    return path.getvalue()


VALID = _valid_file()


def _load(data: bytes, tmp_path):
    path = tmp_path / "f.npz"
    path.write_bytes(data)
    return persistence.load(path, "thing", (1,), max_bytes=1 << 20)


def test_the_valid_file_loads(tmp_path):
    loaded = _load(VALID, tmp_path)
    assert loaded.arrays["a"].shape == (2, 3) and loaded.meta["x"] == 1


@settings(max_examples=400, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.data())
def test_a_mutated_file_is_refused_or_identical(tmp_path, data):
    # flip, insert or delete bytes anywhere in a valid file: the loader either refuses it with
    # FileFormatError or returns exactly the original content (a flip inside zip padding or
    # an unused header field can leave the content intact)
    raw = bytearray(VALID)
    for _ in range(data.draw(st.integers(1, 4))):
        i = data.draw(st.integers(0, len(raw) - 1))
        op = data.draw(st.sampled_from(["flip", "insert", "delete"]))
        if op == "flip":
            raw[i] ^= data.draw(st.integers(1, 255))
        elif op == "insert":
            raw.insert(i, data.draw(st.integers(0, 255)))
        elif len(raw) > 1:
            del raw[i]
    try:
        loaded = _load(bytes(raw), tmp_path)
    except persistence.FileFormatError as exc:
        assert "f.npz" in str(exc)
        return
    assert loaded.meta["x"] == 1
    assert np.array_equal(loaded.arrays["a"], np.arange(6.0).reshape(2, 3))
    assert np.array_equal(loaded.arrays["b"], [1, 2, 3])


@FAST
@given(st.binary(max_size=512))
def test_random_bytes_are_refused(tmp_path, blob):
    with pytest.raises(persistence.FileFormatError):
        _load(blob, tmp_path)


@FAST
@given(shape=st.lists(st.integers(0, 2**40), min_size=0, max_size=4),
       descr=st.sampled_from(["<f8", "<i8", "|O", "<U5", "|b1", "<c16", "|V8"]))
def test_any_declared_header_is_refused_or_read_within_the_cap(tmp_path, shape, descr):
    # an entry whose .npy header declares any shape and dtype, with 64 bytes of data behind it
    with zipfile.ZipFile(io.BytesIO(VALID)) as zin:
        entries = {i.filename: zin.read(i) for i in zin.infolist()}
    head = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        head, {"descr": descr, "fortran_order": False, "shape": tuple(shape)})
    entries["a.npy"] = head.getvalue() + bytes(64)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as zout:
        for name, blob in entries.items():
            zout.writestr(name, blob)
    try:
        loaded = _load(out.getvalue(), tmp_path)
    except persistence.FileFormatError:
        return
    assert loaded.arrays["a"].nbytes <= 1 << 20  # never more than the cap
