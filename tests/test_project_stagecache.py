"""Stage caches: nested dataclasses of arrays and text round-trip through .npz, no pickle."""

from dataclasses import dataclass

import numpy as np
import pytest

from insrail.io.errors import InputError
from insrail.project.stagecache import load_dataclass, save_dataclass
from insrail.track.adjustment import Adjustment


@dataclass(frozen=True)
class Inner:
    values_m: np.ndarray
    rail: str
    from_design: bool


@dataclass(frozen=True)
class Outer:
    inner: Inner
    label: tuple[str, ...]
    count: int


def test_nested_dataclass_round_trip(tmp_path):
    value = Outer(Inner(np.array([[1.0, np.nan], [3.0, 4.0]]), "left", True), ("DK1+000.000", "DK1+000.625"), 7)
    save_dataclass(tmp_path / "c.npz", value)
    back = load_dataclass(tmp_path / "c.npz", Outer)
    np.testing.assert_array_equal(back.inner.values_m, value.inner.values_m)
    assert (back.inner.rail, back.inner.from_design, back.label, back.count) == ("left", True, value.label, 7)
    assert type(back.count) is int and type(back.inner.from_design) is bool


def test_adjustment_round_trip_and_damaged_file(tmp_path):
    flags = np.zeros((3, 2), bool)
    adjustment = Adjustment(np.full((3, 2), 1e-3), np.zeros((3, 2)), flags, flags | True, "wj8",
                            flags.astype(np.uint8), flags.astype(np.uint8) | 2)
    save_dataclass(tmp_path / "a.npz", adjustment)
    back = load_dataclass(tmp_path / "a.npz", Adjustment)
    assert back.fastener == "wj8" and back.unresolved_vertical.all() and back.total_movement_m == pytest.approx(6e-3)
    (tmp_path / "a.npz").write_bytes(b"not a zip")
    with pytest.raises(InputError, match="damaged cache file"):
        load_dataclass(tmp_path / "a.npz", Adjustment)
