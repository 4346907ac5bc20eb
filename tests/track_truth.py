"""Shared helper for the track-reconstruction tests: the simulator's navigation truth fed through
rails-from-pose, once per survey folder and test session."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from insrail.geodesy.crs import EngineeringCRS
from insrail.geodesy.ellipsoid import Ellipsoid
from insrail.io.survey import TrolleyGeometry, read_manifest
from insrail.io.types import GaugeData
from insrail.nav.trajectory import Trajectory
from insrail.sim.scenario import ScenarioConfig, preset
from insrail.sim.simulate import height_anomaly, true_track
from insrail.sim.track import TrueTrack
from insrail.sim.truth import SleeperTruth, read_nav_truth, read_sleeper_truth
from insrail.track.alignment import DesignAlignment
from insrail.track.alignment_csv import read_alignment_csv
from insrail.track.chainage import RailStations, stations_on_design
from insrail.track.rails import RailPoints, rails_from_pose
from insrail.track.sleeper_table import SleeperTable, build_sleeper_table
from insrail.track.sleepers import SleeperNumbering


@dataclass(frozen=True)
class TruthReconstruction:
    folder: Path
    config: ScenarioConfig
    crs: EngineeringCRS
    track: TrueTrack
    nav: np.ndarray
    trajectory: Trajectory
    gauge: GaugeData
    trolley: TrolleyGeometry
    design: DesignAlignment
    rails: RailPoints
    stations: RailStations
    sleepers: SleeperTruth

    def to_engineering(self, lat, lon, h):
        east, north = self.crs.to_plane(lat, lon)
        return east, north, h - height_anomaly(self.config, east, north)


def trajectory_from_truth(nav: np.ndarray, ellipsoid: Ellipsoid) -> Trajectory:
    zeros = np.zeros((len(nav), 3))
    return Trajectory(
        time_s=np.ascontiguousarray(nav["time_s"]), lat_rad=np.ascontiguousarray(nav["lat_rad"]),
        lon_rad=np.ascontiguousarray(nav["lon_rad"]), height_m=np.ascontiguousarray(nav["height_m"]),
        vel_ned_mps=np.ascontiguousarray(nav["vel_ned_mps"]), rpy_rad=np.ascontiguousarray(nav["rpy_rad"]),
        sigma_pos_ned_m=zeros, sigma_vel_ned_mps=zeros, sigma_rpy_rad=zeros, gyro_bias_radps=zeros,
        accel_bias_mps2=zeros, gyro_scale=zeros, accel_scale=zeros, odometer_scale=np.zeros(len(nav)),
        smoothed=True, ellipsoid=ellipsoid,
    )


@lru_cache(maxsize=2)
def truth_reconstruction(folder: Path) -> TruthReconstruction:
    scenario = tomllib.loads((folder / "truth" / "scenario.toml").read_text())
    config = preset(scenario["scenario"]["name"], imu_profile=scenario["scenario"]["imu_profile"])
    crs = EngineeringCRS.from_settings(config.geodetic.crs)
    # The simulator's first random stream builds the track: the same seed rebuilds it exactly.
    track = true_track(config, np.random.default_rng(np.random.SeedSequence(scenario.get("track_seed", scenario["seed"])).spawn(9)[0]))
    nav = np.asarray(read_nav_truth(folder / "truth" / "nav.npy"))
    trajectory = trajectory_from_truth(nav, crs.reference_ellipsoid)
    # The error-free gauge at the trolley's reference cross-section, as the simulated sensor sees it.
    gauge = GaugeData(trajectory.time_s, track.nominal_gauge_m + track.gauge.evaluate(nav["station_m"]))
    trolley = read_manifest(folder).trolley
    design = read_alignment_csv(folder / "truth" / "design.csv")
    partial = TruthReconstruction(folder, config, crs, track, nav, trajectory, gauge, trolley, design,
                                  None, None, read_sleeper_truth(folder / "truth" / "sleepers.csv"))
    rails = rails_from_pose(trajectory, trolley, gauge, partial.to_engineering)
    stations = stations_on_design(rails, design)
    return replace(partial, rails=rails, stations=stations)


@lru_cache(maxsize=2)
def truth_sleeper_table(folder: Path) -> tuple[TruthReconstruction, SleeperTable]:
    """The sleeper table built from the truth rails at the simulator's own sleepers."""
    recon = truth_reconstruction(folder)
    truth = recon.sleepers
    at_truth = SleeperNumbering(
        number=truth["index"].astype(int), station_m=truth["station"], time_s=truth["pass_time"],
        detected=truth["detected"].astype(bool), pulse_time_s=np.empty(0), pulse_station_m=np.empty(0),
        pulse_accepted=np.empty(0, dtype=bool))
    return recon, build_sleeper_table(recon.rails, recon.stations, at_truth, recon.design)


def expected_deviations(truth, design_gauge_m=1.435, base_m=1.5):
    """Per-rail deviations implied by the injected centreline irregularities, gauge and cant
    (docs/simulator.md geometry; see insrail.track.deviations)."""
    g, c, dc = truth["gauge"], truth["cant"], truth["design_cant"]
    across = g * np.sqrt(1 - (c / base_m) ** 2) - design_gauge_m * np.sqrt(1 - (dc / base_m) ** 2)
    rise = (g * c - design_gauge_m * dc) / base_m
    lateral = np.column_stack([truth["lateral"] - across / 2, truth["lateral"] + across / 2])
    vertical = np.column_stack([truth["vertical"] + rise / 2, truth["vertical"] - rise / 2])
    return lateral, vertical
