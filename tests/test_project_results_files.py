"""Result files written from the cache: copies (never links into the cache), a rerun's unchanged large
file linked from the previous results, and the trajectory's fields read a chunk at a time."""

import os

import numpy as np
import pytest

from insrail.nav.trajectory import TRAJECTORY_DTYPE, load_trajectory, save_trajectory
from insrail.project.results import read_trajectory_fields, write_results


def _cached_file(tmp_path):
    cache = tmp_path / "cache.npy"
    cache.write_bytes(os.urandom(1000))
    return cache


def test_a_rerun_links_the_previous_copy_and_never_the_cache(tmp_path):
    results = tmp_path / "results"
    cache = _cached_file(tmp_path)
    first = write_results(results, "s", {"big.npy": cache, "summary.toml": "a = 1\n"}) / "big.npy"
    assert first.read_bytes() == cache.read_bytes() and first.stat().st_ino != cache.stat().st_ino
    inode = first.stat().st_ino
    second = write_results(results, "s", {"big.npy": cache, "summary.toml": "a = 2\n"}) / "big.npy"
    assert second.stat().st_ino == inode and second.stat().st_nlink == 1  # the old folder is gone
    # a result edited by hand is not carried on: copied again from the cache
    with open(second, "r+b") as handle:
        handle.write(b"edited")
    third = write_results(results, "s", {"big.npy": cache, "summary.toml": "a = 3\n"}) / "big.npy"
    assert third.stat().st_ino != inode and third.read_bytes() == cache.read_bytes()
    # editing a result never changes the cache
    third.write_bytes(b"x")
    assert cache.stat().st_size == 1000


def test_trajectory_fields_are_those_of_the_whole_file(tmp_path):
    n = 2501
    rng = np.random.default_rng(3)
    records = np.zeros(n, dtype=TRAJECTORY_DTYPE)
    for name in TRAJECTORY_DTYPE.names:
        records[name] = rng.standard_normal(records[name].shape)
    path = tmp_path / "trajectory.npy"
    np.save(path, records)
    whole = load_trajectory(path)
    fields = read_trajectory_fields(path, ("time_s", "rpy_rad", "sigma_pos_ned_m"), chunk=1000)
    for name, values in fields.items():
        np.testing.assert_array_equal(values, getattr(whole, name))
    save_trajectory(tmp_path / "other.npy", whole)
    np.testing.assert_array_equal(read_trajectory_fields(tmp_path / "other.npy", ("lat_rad",))["lat_rad"], whole.lat_rad)
    with open(path, "r+b") as handle:
        handle.truncate(path.stat().st_size - 300)
    with pytest.raises(ValueError, match="ends after"):
        read_trajectory_fields(path, ("time_s",), chunk=1000)
    np.save(tmp_path / "plain.npy", np.zeros(10))
    with pytest.raises(ValueError, match="not an insrail trajectory"):
        read_trajectory_fields(tmp_path / "plain.npy", ("time_s",))
    with pytest.raises(ValueError, match="not an insrail trajectory"):
        load_trajectory(tmp_path / "plain.npy")


def test_a_trajectory_read_for_its_pose_holds_nan_elsewhere(tmp_path):
    """``load_trajectory(..., only=POSE_FIELDS)`` (the track reconstruction's read): those fields
    as in the whole file, every other one NaN, read-only and without memory of its own."""
    from insrail.track.rails import POSE_FIELDS

    records = np.zeros(1234, dtype=TRAJECTORY_DTYPE)
    rng = np.random.default_rng(5)
    for name in TRAJECTORY_DTYPE.names:
        records[name] = rng.standard_normal(records[name].shape)
    np.save(tmp_path / "trajectory.npy", records)
    whole = load_trajectory(tmp_path / "trajectory.npy")
    pose = load_trajectory(tmp_path / "trajectory.npy", only=POSE_FIELDS)
    for name in TRAJECTORY_DTYPE.names:
        values = getattr(pose, name)
        assert values.shape == getattr(whole, name).shape
        if name in POSE_FIELDS:
            np.testing.assert_array_equal(values, getattr(whole, name))
        else:
            assert np.isnan(values).all() and not values.flags.writeable and values.strides[0] == 0
    with pytest.raises(ValueError, match="not trajectory fields: speed"):
        load_trajectory(tmp_path / "trajectory.npy", only=("time_s", "speed"))
