"""Fusion passes until consistent (insrail.nav.self_calibration): the NHC dropped where it does not
hold without an odometer, the GNSS sigmas scaled by what their innovations show; a consistent survey
fused once. A stand-in for the filter (its innovation record as a pass would leave it), and the real
hand-held walk through `insrail fuse`."""

from __future__ import annotations

import itertools
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
from real_data import real_path

from insrail.nav.fusion import FusionOptions
from insrail.nav.integrity import InnovationRecord
from insrail.nav.self_calibration import MAX_GNSS_SCALE, MAX_STEP, fuse_consistent


@dataclass
class FakeIntegrity:
    inconsistent: str = ""


@dataclass
class FakeResult:
    innovations: InnovationRecord
    info: dict = field(default_factory=dict)
    integrity: FakeIntegrity = field(default_factory=FakeIntegrity)
    statistics: dict = field(default_factory=dict)  # no NHC statistics: the play is not estimated
    forward: object = None


@dataclass
class FakeAiding:
    odometer: object
    gnss: object = None


class FakeStore:
    def __init__(self):
        self.closed = False

    def close(self):
        self.closed = True


def record(gnss_noise_factor: float, nhc_rejected_share: float, n: int = 400, seed: int = 1) -> InnovationRecord:
    """GNSS positions whose true noise is ``gnss_noise_factor`` x the sigma used (NIS chi-square(3)
    scaled by its square, gated at the filter's 0.9999 threshold) and NHC rows of which the given share
    was rejected."""
    rng = np.random.default_rng(seed)
    nis_gnss = gnss_noise_factor**2 * rng.chisquare(3, n)
    nis_nhc = rng.chisquare(2, n)
    nhc_ok = rng.random(n) >= nhc_rejected_share
    nis = np.concatenate([nis_gnss, nis_nhc])
    accepted = np.concatenate([nis_gnss < 21.1, nhc_ok])
    return InnovationRecord(("gnss_position", "odometer_nhc"), np.arange(2 * n, dtype=float),
                            np.repeat([0, 1], n), nis, np.repeat([3, 2], n), accepted, np.ones(2 * n, dtype=bool))


def run(true_gnss_factor: float, nhc_rejected_share: float, odometer=None, options: FusionOptions | None = None):
    """fuse_consistent over a stand-in filter whose innovations follow the options of each pass:
    the NHC is rejected as given while it is used, the GNSS NIS shrinks with the sigma scale."""
    passes, stores = [], []

    def fake_fuse(imu, aiding, profile, opts, ellipsoid, covariance_store=None, **kwargs):
        passes.append(opts)
        share = nhc_rejected_share if opts.use_nhc else 0.0
        # while the filter fights the NHC its GNSS innovations are bad too
        factor = true_gnss_factor / opts.gnss_sigma_scale * (3.0 if share > 0.5 else 1.0)
        return FakeResult(record(factor, share, seed=len(passes)))

    def new_store():
        stores.append(FakeStore())
        return stores[-1]

    result, used, store, calibration = fuse_consistent(None, lambda o: FakeAiding(odometer), None,
                                                       options or FusionOptions(), None,
                                                       new_store=new_store, fuse=fake_fuse)
    return result, used, store, calibration, passes, stores


def test_a_consistent_survey_is_fused_once_and_nothing_said():
    result, used, store, calibration, passes, stores = run(1.0, 0.0)
    assert len(passes) == 1 and used == FusionOptions() and calibration.notices == ()
    assert result.info["calibration"] == {"passes": 1, "nhc_dropped": False, "gnss_sigma_scale": 1.0,
                                          "play_estimated": False, "play_drift_mm2_per_m": [0.025, 0.025],
                                          "profile_play_drift_mm2_per_m": [0.025, 0.025], "nhc_sigma_mm_per_s": 0.45,
                                          "noise": {}}
    assert store is stores[0] and not store.closed


def test_without_an_odometer_a_failing_nhc_is_dropped_and_the_gnss_sigmas_calibrated():
    result, used, store, calibration, passes, stores = run(2.0, 0.9)
    assert not used.use_nhc and calibration.nhc_dropped
    assert passes[0].use_nhc and not passes[1].use_nhc
    # damped: at most MAX_STEP per pass, and it ends where the innovations fit the sigmas
    scales = [p.gnss_sigma_scale for p in passes]
    assert all(b / a <= MAX_STEP + 1e-9 for a, b in itertools.pairwise(scales))
    assert 1.6 <= used.gnss_sigma_scale <= 3.0
    messages = [n.message for n in calibration.notices]
    assert "non-holonomic constraint does not hold" in messages[0]
    assert any(f"sigmas x {used.gnss_sigma_scale:.2f}" in m for m in messages)
    assert result.info["warnings"][-len(messages):] == messages
    assert [s.closed for s in stores] == [True] * (len(stores) - 1) + [False] and store is stores[-1]


def test_with_an_odometer_the_nhc_stays_and_the_verdict_is_the_integritys():
    _, used, _, calibration, passes, _ = run(1.0, 0.9, odometer=object())
    assert used.use_nhc and all(p.use_nhc for p in passes) and not calibration.nhc_dropped


def test_a_few_rejected_fixes_are_not_absorbed_into_the_sigmas():
    # a GNSS fault (a false fix for a while): its fixes far off and rejected, the rest as stated
    def fake_fuse(imu, aiding, profile, opts, ellipsoid, **kwargs):
        rec = record(1.0, 0.0)
        nis, accepted = rec.nis.copy(), rec.accepted.copy()
        nis[:60], accepted[:60] = 500.0, False  # 15 % rejected: more than the limit, but only they
        return FakeResult(InnovationRecord(rec.names, rec.time_s, rec.source, nis, rec.dof, accepted, rec.trusted))

    _, used, _, calibration = fuse_consistent(None, lambda o: FakeAiding(None), None, FusionOptions(), None,
                                              fuse=fake_fuse)
    assert calibration.passes == 1 and used.gnss_sigma_scale == 1.0


def test_the_scale_is_bounded_and_a_survey_still_inconsistent_after_the_last_pass_is_said_to_be():
    result, used, _, calibration, passes, _ = run(1000.0, 0.0)
    assert used.gnss_sigma_scale <= MAX_GNSS_SCALE and len(passes) == calibration.passes <= 4
    assert "after 4 passes" in result.integrity.inconsistent and "still rejected" in result.integrity.inconsistent
    # no notice claims a pass that was not run
    said = [float(x) for w in result.info["warnings"] for x in re.findall(r"sigmas x ([0-9.]+) \(calibrated", w)]
    assert len(said) == calibration.passes - 1 and max(said) == pytest.approx(used.gnss_sigma_scale, abs=0.01)
    assert run(1.0, 0.0)[0].integrity.inconsistent == ""


# --------------------------------------------------------------------------- the real hand-held walk

def walk_folder(folder: Path, profile: str) -> Path:
    """The real walk as benchmarks/imu_integrity.py builds it (insrail.sim.recordings), with ``profile``."""
    from insrail.sim.recordings import walk_survey

    return walk_survey(folder, profile, real_path("walk_0827"))


def test_the_real_handheld_walk_fuses_consistently_as_a_user_runs_it(tmp_path, capsys):
    """insrail fuse on walk_0827 with the hand-held MEMS profile and no option: >= 90 % of the fixes
    used, no reset, the smoothed antenna within 3 sigma (as used) of >= 99 % of the fixes on every axis."""
    from insrail.cli.main import main
    from insrail.io import read_rtklib_pos
    from insrail.nav.earth import WGS84, radii
    from insrail.nav.rotation import euler_to_dcm
    from insrail.nav.trajectory import load_trajectory

    folder, out = walk_folder(tmp_path / "walk", "mems_handheld"), tmp_path / "out"
    assert main(["fuse", str(folder), "--out", str(out), "--ellipsoid", "WGS84"]) == 0
    printed = capsys.readouterr().out
    assert "non-holonomic constraint does not hold" in printed and "GNSS positions disagree" in printed
    log = tomllib.loads((out / "fusion_log.toml").read_text())
    assert log["calibration"]["nhc_dropped"] and not log["resets"]
    gnss = read_rtklib_pos(folder / "gnss_1730_sf.pos")
    traj = load_trajectory(out / "trajectory.npy")
    inside = (gnss.time_s >= traj.time_s[0]) & (gnss.time_s <= traj.time_s[-1])
    assert log["measurements"]["gnss_position"]["used"] >= 0.9 * inside.sum()
    t = gnss.time_s[inside]
    k = np.clip(np.searchsorted(traj.time_s, t), 0, len(traj) - 1)
    antenna = np.einsum("nij,j->ni", euler_to_dcm(*traj.rpy_rad[k].T), np.array([0.0, 0.05, 0.0]))
    r_m, r_n = radii(gnss.lat_rad[inside], WGS84)
    d = np.column_stack([(np.interp(t, traj.time_s, traj.lat_rad) - gnss.lat_rad[inside]) * r_m + antenna[:, 0],
                         (np.interp(t, traj.time_s, traj.lon_rad) - gnss.lon_rad[inside]) * r_n
                         * np.cos(gnss.lat_rad[inside]) + antenna[:, 1],
                         -(np.interp(t, traj.time_s, traj.height_m) - gnss.height_m[inside]) + antenna[:, 2]])
    policy = dict(FusionOptions().gnss_quality_policy)
    factor = np.array([policy[int(q)] for q in gnss.quality[inside]]) * log["calibration"]["gnss_sigma_scale"]
    sigma = np.maximum(gnss.sigma_ned_m[inside] * factor[:, None], log["options"]["gnss_sigma_floor_m"])
    within = (np.abs(d) / sigma < 3.0).mean(axis=0)
    assert np.all(within >= 0.99), within


def test_the_data_sheet_profile_on_the_walk_is_refused_loudly_naming_the_handheld_profile(tmp_path, capsys):
    from insrail.cli.main import main

    folder = walk_folder(tmp_path / "walk", "mems")
    assert main(["fuse", str(folder), "--out", str(tmp_path / "out"), "--ellipsoid", "WGS84"]) == 1
    assert "mems_handheld" in capsys.readouterr().err
    assert not (tmp_path / "out" / "trajectory.npy").exists()
