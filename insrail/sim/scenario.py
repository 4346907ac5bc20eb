"""Scenario parameters of the simulator and the built-in presets ``short``, ``long`` and ``straight``.

Every value is a parameter; the defaults are the benchmark scenario the later issues
measure against (GNSS white 10 mm horizontal / 20 mm vertical plus Gauss-Markov
5 mm / 10 mm with 300 s; a 120 s GNSS outage in ``short``; odometer, gauge and sleeper
detector as on the thesis's trolley).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from insrail.io.survey import TrolleyGeometry
from insrail.sim.irregularity import Bump

INF = math.inf


@dataclass(frozen=True)
class DesignSpec:
    """Design alignment in the engineering plane.

    horizontal: ("line", length) | ("clothoid", length, radius_start, radius_end, turn)
                | ("arc", length, radius, turn), turn "left"/"right", INF for a straight end
    pvis: (station, elevation [m, normal height], vertical-curve radius [m]; 0 at the ends)
    cant: (station, signed design cant [m]) rows, linear in between
    """

    start_east_m: float
    start_north_m: float
    start_azimuth_deg: float
    start_station_m: float
    horizontal: tuple
    pvis: tuple
    cant: tuple
    name: str = "main"


@dataclass(frozen=True)
class IrregularitySpec:
    """Injected irregularities: random band-limited parts (RMS and band) and isolated bumps."""

    lateral_rms_m: float = 1.0e-3
    vertical_rms_m: float = 1.0e-3
    band_m: tuple[float, float] = (3.0, 70.0)
    gauge_rms_m: float = 0.3e-3
    cross_level_rms_m: float = 0.3e-3
    gauge_band_m: tuple[float, float] = (3.0, 30.0)
    #: a ballasted track's settlement between two tampings: a second random part of the centreline at long
    #: wavelengths (0 leaves it out and draws nothing: the other presets keep their random numbers)
    long_wave_lateral_rms_m: float = 0.0
    long_wave_vertical_rms_m: float = 0.0
    long_wave_band_m: tuple[float, float] = (40.0, 200.0)
    lateral_bumps: tuple[Bump, ...] = ()
    vertical_bumps: tuple[Bump, ...] = ()
    gauge_bumps: tuple[Bump, ...] = ()
    cross_level_bumps: tuple[Bump, ...] = ()
    nominal_gauge_m: float = 1.435


@dataclass(frozen=True)
class MotionSpec:
    """The trolley's run from ``start_station_m`` to ``end_station_m`` (stations increasing);
    with ``reverse`` it runs the same stretch the other way, from ``end_station_m`` down to
    ``start_station_m``, facing its direction of travel (its x axis against the stationing,
    its reference rail the stationing's other rail). Stops, outages and prism fixes are
    given by station either way."""

    start_station_m: float
    end_station_m: float
    cruise_speed_mps: float = 1.2
    speed_variation: float = 0.15
    speed_change_interval_s: float = 45.0
    ramp_s: float = 6.0
    static_start_s: float = 300.0
    static_end_s: float = 60.0
    stops: tuple[tuple[float, float], ...] = ()  # (station, duration)
    reverse: bool = False


@dataclass(frozen=True)
class GnssSpec:
    rate_hz: float = 1.0
    white_horizontal_m: float = 0.010
    white_vertical_m: float = 0.020
    gm_horizontal_m: float = 0.005
    gm_vertical_m: float = 0.010
    gm_tau_s: float = 300.0
    outages: tuple[tuple[float, float], ...] = ()  # (station where it starts, duration s)
    with_velocity: bool = False
    velocity_sigma_mps: float = 0.005


@dataclass(frozen=True)
class OdometerSlip:
    """A wheel that slips over a stretch: between the two stations it counts ``fraction`` less than it
    rolls (0.05: 5 %)."""

    wheel: str = "right"  # "left" (the first odometer) or "right" (the second)
    from_station_m: float = 0.0
    to_station_m: float = 0.0
    fraction: float = 0.05


@dataclass(frozen=True)
class OdometerSpec:
    rate_hz: float = 10.0
    scale_factor_error: float = 0.0015  # reported distance = (1 + error) * true distance
    pulse_length_m: float = 0.001
    form: str = "distance"  # "distance" or "pulses"
    #: a second odometer on the other rail ([files.odometer_right]), its wheel's contact point (b frame [m];
    #: the default trolley's first wheel is at y = -0.60, the rails 1.5 m apart) and scale-factor error
    second: bool = False
    right_lever_arm_m: tuple[float, float, float] = (0.45, 0.90, 0.31)
    right_scale_factor_error: float = 0.0025
    slip: OdometerSlip | None = None


@dataclass(frozen=True)
class GaugeSpec:
    rate_hz: float = 20.0
    noise_m: float = 0.1e-3
    resolution_m: float = 0.01e-3


@dataclass(frozen=True)
class SleeperSpec:
    spacing_m: float = 0.625
    spacing_jitter_m: float = 0.002
    missed_fraction: float = 0.01
    false_fraction: float = 0.005
    timing_jitter_s: float = 0.001


@dataclass(frozen=True)
class PrismSpec:
    """Total-station fixes of the trolley's prism, taken at stops (stations listed); a station at the
    run's first or last station is taken during its static start or end."""

    stations_m: tuple[float, ...] = ()
    sigma_m: float = 0.001
    duration_s: float = 20.0


@dataclass(frozen=True)
class TrolleyPlaySpec:
    """Play of the trolley frame about the reference rail point: pitch and yaw deviations
    from the rail's tangent, band-limited random functions of station with a flat
    spectrum (``random_irregularity`` with amplitude proportional to wavelength^-1/2)
    between the two wavelengths. The rail point stays on the rail; the IMU and the other
    points of the trolley move with the frame.

    Physically: wheel and flange play, wheels rolling over rail-head roughness and gauge
    variations, the push on the handle. In the trolley frame the rail point then moves
    sideways at v*yaw and vertically at v*pitch: what the fusion's NHC noise stands for.
    Seen by 10 Hz NHC updates the process is coloured (about 1 s correlation at 1 m/s),
    but its spectrum is flat down to the longest wavelength, so at the long waves that
    set the 5 m and 150 m lag errors it acts like white noise of
    ``equivalent_nhc_sigma_mps``. The default (0.316 mrad = 0.018 deg RMS, 0.5 m to 5 km)
    is equivalent to the fusion's default NHC sigma, 0.5 mm/s at 10 Hz, at 1 m/s; zero
    RMS turns the play off (the trolley frame then follows the rail exactly).
    """

    pitch_rms_rad: float = 0.316e-3
    yaw_rms_rad: float = 0.316e-3
    shortest_wavelength_m: float = 0.5
    longest_wavelength_m: float = 5000.0
    components: int = 400

    def drift_m2_per_m(self) -> tuple[float, float]:
        """(lateral, vertical) variance per metre run of the play's integral along the track, the
        rail point's drift from the rail where the NHC holds the trolley's x axis to it: for the flat
        one-sided spatial PSD G = rms^2 / (1/shortest - 1/longest) of yaw and pitch, G / 2 per metre
        (the fusion's ``resources/trolley_play.toml``)."""
        band = 1.0 / self.shortest_wavelength_m - 1.0 / self.longest_wavelength_m
        return self.yaw_rms_rad**2 / band / 2.0, self.pitch_rms_rad**2 / band / 2.0

    def equivalent_nhc_sigma_mps(self, speed_mps: float, update_interval_s: float) -> tuple[float, float]:
        """(vertical, lateral) sigma of white NHC noise at ``update_interval_s`` with the same
        low-frequency spectrum as the play at ``speed_mps``: for a flat one-sided spatial
        PSD G = rms^2 / (1/shortest - 1/longest), the lateral velocity v*yaw has the
        two-sided PSD v G / 2 at zero frequency, and white samples sigma^2 * dt."""
        band = 1.0 / self.shortest_wavelength_m - 1.0 / self.longest_wavelength_m
        return tuple(math.sqrt(speed_mps * rms**2 / band / (2.0 * update_interval_s))
                     for rms in (self.pitch_rms_rad, self.yaw_rms_rad))


@dataclass(frozen=True)
class JointSpec:
    """Rail joints (thesis §5.3.1.2): every ``spacing_m`` of station from ``first_station_m`` the
    trolley's reference wheel drops into a joint gap and bounces. Its specific force gets a shock
    when the reference point passes the joint: a Ricker wavelet (the second derivative of a
    Gaussian: no net velocity or position change) of peak ``vertical_mps2`` up-down and
    ``lateral_mps2`` sideways, centre frequency ``frequency_hz`` (a 5 m/s^2, 40 Hz shock is a dip of
    0.16 mm). The truth (rails, trolley path) does not hold the dip: the sensor sees a shock the
    filter must not take for motion. ``spacing_m`` = 0 (the default): jointless welded rail."""

    spacing_m: float = 0.0
    first_station_m: float = 0.0
    vertical_mps2: float = 5.0
    lateral_mps2: float = 1.5
    frequency_hz: float = 40.0

    def shock_mps2(self, time_from_joint_s: np.ndarray) -> np.ndarray:
        """(n, 3) specific force of the shock in the body frame (FRD) at times from the passing."""
        a = (math.pi * self.frequency_hz * np.asarray(time_from_joint_s, dtype=float)) ** 2
        wavelet = (1.0 - 2.0 * a) * np.exp(-a)
        return np.column_stack([np.zeros_like(wavelet), self.lateral_mps2 * wavelet, self.vertical_mps2 * wavelet])


@dataclass(frozen=True)
class GeodeticSpec:
    """Engineering CRS of the line and the height-anomaly surface zeta = h - H.

    zeta(E, N) = zeta0 + gradient . (E - E0, N - N0) + curvature * |(E, N) - (E0, N0)|^2
    with (E0, N0) the design start point.
    """

    crs: dict = field(
        default_factory=lambda: {
            "ellipsoid": "CGCS2000",
            "central_meridian_deg": 114.3,
            "scale_factor": 1.0,
            "false_easting_m": 500000.0,
            "false_northing_m": 0.0,
            "projection_height_m": 30.0,
            "projection_height_convention": "scale_factor",
        }
    )
    zeta0_m: float = -12.35
    zeta_gradient: tuple[float, float] = (4.0e-6, -9.0e-6)
    zeta_curvature_per_m: float = 2.0e-11
    benchmark_spacing_m: float = 500.0
    benchmark_offset_m: tuple[float, float] = (20.0, 150.0)
    benchmark_sigma_h_m: float = 0.003
    benchmark_sigma_normal_height_m: float = 0.001


@dataclass(frozen=True)
class ScenarioConfig:
    name: str
    design: DesignSpec
    motion: MotionSpec
    irregularities: IrregularitySpec = IrregularitySpec()
    gnss: GnssSpec = GnssSpec()
    odometer: OdometerSpec = OdometerSpec()
    gauge: GaugeSpec = GaugeSpec()
    sleepers: SleeperSpec = SleeperSpec()
    prism: PrismSpec = PrismSpec()
    geodetic: GeodeticSpec = GeodeticSpec()
    play: TrolleyPlaySpec = TrolleyPlaySpec()
    joints: JointSpec = JointSpec()
    trolley: TrolleyGeometry = field(default_factory=lambda: default_trolley())
    imu_profile: str = "nav"
    #: the accelerometers' turn-on bias (x, y, z) [m/s^2] of this unit, instead of one drawn from the profile
    #: (a unit known to be that far off)
    accel_bias_turn_on_mps2: tuple[float, float, float] | None = None
    imu_rate_hz: float = 200.0
    gps_week: int = 2380
    start_time_s: float = 230400.0025  # GPS seconds of week; IMU epochs fall between GNSS seconds
    station_grid_m: float = 0.05  # spacing of the kinematic splines


def default_trolley() -> TrolleyGeometry:
    """Geometry of the simulated trolley (IMU about 0.3 m above the rails, antenna and prism on a mast)."""
    return TrolleyGeometry(
        imu_to_antenna_m=np.array([0.02, 0.18, -1.35]),
        imu_to_odometer_m=np.array([0.45, -0.60, 0.31]),
        imu_to_prism_m=np.array([0.02, 0.18, -1.52]),
        imu_to_sleeper_detector_m=np.array([0.30, -0.45, 0.22]),
        imu_to_reference_rail_m=np.array([0.10, -0.60, 0.31]),
        reference_rail="left",
        mounting_rpy_rad=np.deg2rad([0.05, -0.08, 0.12]),
        rail_centre_spacing_m=1.5,
    )


def _short_design() -> DesignSpec:
    # 1.2 km: straight, clothoid, R = 2000 m right-hand arc, clothoid, straight; a crest
    # vertical curve between +3 and -2 per mille; 120 mm cant ramped on the clothoids.
    return DesignSpec(
        start_east_m=512340.0,
        start_north_m=3374210.0,
        start_azimuth_deg=32.0,
        start_station_m=1000.0,
        horizontal=(
            ("line", 240.0),
            ("clothoid", 120.0, INF, 2000.0, "right"),
            ("arc", 420.0, 2000.0, "right"),
            ("clothoid", 120.0, 2000.0, INF, "right"),
            ("line", 400.0),
        ),
        pvis=((1000.0, 28.40, 0.0), (1620.0, 30.26, 25000.0), (2300.0, 28.90, 0.0)),
        cant=((1000.0, 0.0), (1240.0, 0.0), (1360.0, 0.120), (1780.0, 0.120), (1900.0, 0.0), (2300.0, 0.0)),
    )


def _long_design() -> DesignSpec:
    # About 10.3 km of high-speed line: two curves of opposite hand (R 5500 m and 7000 m),
    # rolling grades with vertical curves.
    return DesignSpec(
        start_east_m=508120.0,
        start_north_m=3369880.0,
        start_azimuth_deg=58.0,
        start_station_m=20000.0,
        horizontal=(
            ("line", 1400.0),
            ("clothoid", 260.0, INF, 5500.0, "right"),
            ("arc", 1500.0, 5500.0, "right"),
            ("clothoid", 260.0, 5500.0, INF, "right"),
            ("line", 2100.0),
            ("clothoid", 220.0, INF, 7000.0, "left"),
            ("arc", 1300.0, 7000.0, "left"),
            ("clothoid", 220.0, 7000.0, INF, "left"),
            ("line", 3040.0),
        ),
        pvis=(
            (20000.0, 35.20, 0.0),
            (22600.0, 43.00, 25000.0),
            (25400.0, 37.40, 30000.0),
            (28200.0, 44.40, 25000.0),
            (30300.0, 42.30, 0.0),
        ),
        cant=(
            (20000.0, 0.0), (21400.0, 0.0), (21660.0, 0.150), (23160.0, 0.150), (23420.0, 0.0),
            (25520.0, 0.0), (25740.0, -0.110), (27040.0, -0.110), (27260.0, 0.0), (30300.0, 0.0),
        ),
    )


def _bumps(rng_seed: int, first: float, last: float, count: int, amplitude_m: float) -> tuple[Bump, ...]:
    rng = np.random.default_rng(rng_seed)
    stations = np.sort(rng.uniform(first, last, count))
    return tuple(
        Bump(float(s), float(rng.uniform(4.0, 9.0)), float(amplitude_m * rng.choice([-1.0, 1.0]) * rng.uniform(0.7, 1.0)))
        for s in stations
    )


def short_scenario() -> ScenarioConfig:
    """About 1.2 km at walking speed with two stops and a 120 s GNSS outage on the curve."""
    design = _short_design()
    return ScenarioConfig(
        name="short",
        design=design,
        motion=MotionSpec(start_station_m=1050.0, end_station_m=2250.0, stops=((1450.0, 20.0), (1900.0, 20.0))),
        irregularities=IrregularitySpec(
            lateral_bumps=_bumps(11, 1100.0, 2200.0, 3, 3.0e-3),
            vertical_bumps=_bumps(12, 1100.0, 2200.0, 3, 3.0e-3),
        ),
        gnss=GnssSpec(outages=((1600.0, 120.0),)),
    )


def long_scenario(outage_700s: bool = False) -> ScenarioConfig:
    """About 10 km; optionally a 700 s GNSS outage (a tunnel) with prism fixes at its ends."""
    design = _long_design()
    outages = ((25000.0, 700.0),) if outage_700s else ()
    return ScenarioConfig(
        name="long-outage" if outage_700s else "long",
        design=design,
        motion=MotionSpec(
            start_station_m=20050.0,
            end_station_m=30250.0,
            stops=tuple((float(s), 20.0) for s in range(21000, 30000, 1000)),
        ),
        irregularities=IrregularitySpec(
            lateral_bumps=_bumps(21, 20100.0, 30200.0, 10, 3.0e-3),
            vertical_bumps=_bumps(22, 20100.0, 30200.0, 10, 3.0e-3),
        ),
        gnss=GnssSpec(outages=outages),
    )


#: The ``ballasted`` preset's fixed stretches on the `short` design's chainage (a bridge and a level
#: crossing: the tamping machine must not move the track there), written as the demo's track events.
BALLASTED_EVENTS = (("bridge", 1500.0, 1540.0, "Xiaohe bridge"), ("level_crossing", 1800.0, 1808.0, "of the service road"))


def ballasted_scenario() -> ScenarioConfig:
    """The `short` line as a ballasted track due for tamping: maintenance-level errors of the
    centreline, 8 mm RMS vertical and 5 mm RMS lateral at 40-200 m wavelengths (peaks of 10-30 mm),
    on top of the short-wave part, and local dips (a sleeper group settled 8-20 mm over 6-12 m) and
    lateral kinks of 5-10 mm; the track's fixed stretches are :data:`BALLASTED_EVENTS`."""
    short = short_scenario()
    rng = np.random.default_rng(41)
    dips = tuple(Bump(float(s), float(rng.uniform(6.0, 12.0)), -float(rng.uniform(8.0e-3, 20.0e-3)))
                 for s in (1130.0, 1290.0, 1455.0, 1620.0, 1745.0, 1960.0, 2120.0))
    kinks = tuple(Bump(float(s), float(rng.uniform(6.0, 12.0)), float(rng.choice([-1.0, 1.0]) * rng.uniform(5e-3, 10e-3)))
                  for s in (1210.0, 1590.0, 2040.0))
    return replace(short, name="ballasted", irregularities=IrregularitySpec(
        lateral_rms_m=1.5e-3, vertical_rms_m=2.0e-3, long_wave_lateral_rms_m=5.0e-3, long_wave_vertical_rms_m=8.0e-3,
        lateral_bumps=kinks, vertical_bumps=dips))


def straight_scenario() -> ScenarioConfig:
    """1 km of straight, level, north-bound track at a constant 1 m/s, no stops, no outage:
    the thesis's chapter 3-4 set-up, for Monte Carlo checks of the accuracy prediction."""
    design = DesignSpec(
        start_east_m=512340.0,
        start_north_m=3374210.0,
        start_azimuth_deg=0.0,
        start_station_m=1000.0,
        horizontal=(("line", 1100.0),),
        pvis=((1000.0, 28.40, 0.0), (2100.0, 28.40, 0.0)),
        cant=((1000.0, 0.0), (2100.0, 0.0)),
    )
    return ScenarioConfig(
        name="straight",
        design=design,
        motion=MotionSpec(start_station_m=1050.0, end_station_m=2050.0,
                          cruise_speed_mps=1.0, speed_variation=0.0),
    )


def tunnel_scenario() -> ScenarioConfig:
    """2.5 km of the `long` line with a 1.5 km tunnel: no GNSS from station 20 700 m to the far portal
    (about 22 200 m), total-station fixes of the prism (1 mm) every 60 m inside, as on CPIII pairs every
    60 m (seed 001's workflow), each at a 20 s stop."""
    design = _long_design()
    fixes = tuple(float(s) for s in np.arange(20760.0, 22200.0, 60.0))
    return ScenarioConfig(
        name="tunnel",
        design=design,
        motion=MotionSpec(start_station_m=20050.0, end_station_m=22550.0),
        irregularities=IrregularitySpec(
            lateral_bumps=_bumps(31, 20100.0, 22500.0, 4, 3.0e-3),
            vertical_bumps=_bumps(32, 20100.0, 22500.0, 4, 3.0e-3),
        ),
        gnss=GnssSpec(outages=((20700.0, 1860.0),)),
        prism=PrismSpec(stations_m=fixes, sigma_m=0.001, duration_s=20.0),
    )


def tunnel_no_gnss_scenario() -> ScenarioConfig:
    """1.5 km inside the `tunnel` preset's tunnel, with no GNSS at all: the run starts and ends at a
    prism fix (taken during the static start and at the end), 1 mm fixes every 60 m between. The
    simulator writes a GNSS file with nothing in it but its outage; drop the gnss role from
    survey.toml to process it as a survey without GNSS (``benchmarks/tunnel.py``)."""
    tunnel = tunnel_scenario()
    fixes = tuple(float(s) for s in np.arange(20720.0, 22221.0, 60.0))
    return replace(tunnel, name="tunnel-no-gnss",
                   motion=replace(tunnel.motion, start_station_m=20720.0, end_station_m=22220.0),
                   gnss=replace(tunnel.gnss, outages=((20720.0, 1.0e5),)),
                   prism=replace(tunnel.prism, stations_m=fixes))


PRESETS = {"short": short_scenario, "ballasted": ballasted_scenario, "tunnel": tunnel_scenario, "tunnel-no-gnss": tunnel_no_gnss_scenario, "straight": straight_scenario, "long": long_scenario, "long-outage": lambda: long_scenario(True)}


def preset(name: str, **overrides) -> ScenarioConfig:
    """A built-in scenario by name, with top-level fields replaced by ``overrides``."""
    try:
        config = PRESETS[name]()
    except KeyError:
        raise ValueError(f"unknown scenario preset {name!r}; choose one of {', '.join(PRESETS)}") from None
    return replace(config, **overrides) if overrides else config
