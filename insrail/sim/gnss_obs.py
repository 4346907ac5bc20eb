"""GPS observations (RINEX 2.11) for a moving rover and a static base, from real broadcast orbits.

The simulator's survey carries a finished GNSS solution; this module produces what the trolley's
receiver and a base receiver on a control point would have recorded instead, so that the PPK
stage (RTKLIB) can be tested end to end against the simulator's truth.

Model per receiver r, satellite s, receiver epoch tag T (GPS time as read by the receiver clock):

* true reception time t = T - dt_r(t), with the receiver clock dt_r = bias + drift (t - t0);
* transmission time from the light-time equation; the satellite position at transmission
  (IS-GPS-200 broadcast ephemeris, :func:`satellite_positions`) rotated by the earth's rotation
  during the signal travel (Sagnac), geometric range rho;
* satellite clock dt_s from the navigation message (polynomial plus relativistic term);
* troposphere: Saastamoinen hydrostatic zenith delay at the receiver's height times 1/sin(el),
  plus a wet part common to both receivers (short baseline); ionosphere: a thin-shell slant
  delay common to both receivers, + on code, - on phase, scaled by (f1/f2)^2 on L2;
* C1, P2 = rho + c (dt_r - dt_s) + T + I + code noise; L1, L2 = (rho + c (dt_r - dt_s) + T - I
  + phase noise) / lambda + N with integer ambiguities N per receiver, satellite and frequency;
* satellites below the elevation mask (or unhealthy, or without an ephemeris within 2 h) left out.

Not modelled (cancel in short-baseline double differences or are zero in the simulation):
antenna phase-centre offsets and variations, phase wind-up, multipath, cycle slips, TGD.
Positions are ECEF [m]; times seconds of the simulation's GPS week.
"""

from __future__ import annotations

import shutil
import tomllib
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import tomli_w

from insrail.geodesy import EngineeringCRS
from insrail.io.rinex import (
    GpsEphemerides,
    RinexObsHeader,
    read_gps_ephemerides,
    write_rinex2_obs,
)
from insrail.io.survey import read_manifest, write_manifest
from insrail.io.survey_gnss import RawGnss
from insrail.io.timescale import SECONDS_PER_WEEK
from insrail.nav import earth
from insrail.sim.scenario import ScenarioConfig
from insrail.sim.simulate import height_anomaly
from insrail.sim.truth import read_antenna_truth

SPEED_OF_LIGHT_MPS = 299_792_458.0
GM_EARTH_GPS = 3.986005e14  # m^3/s^2, IS-GPS-200
EARTH_ROTATION_RADPS = 7.2921151467e-5  # IS-GPS-200
RELATIVISTIC_F = -4.442807633e-10  # s/sqrt(m), IS-GPS-200
FREQ_L1_HZ, FREQ_L2_HZ = 1575.42e6, 1227.60e6
WAVELENGTH_L1_M, WAVELENGTH_L2_M = SPEED_OF_LIGHT_MPS / FREQ_L1_HZ, SPEED_OF_LIGHT_MPS / FREQ_L2_HZ
MAX_EPHEMERIS_AGE_S = 7200.0  # as RTKLIB: an ephemeris serves within 2 h of its toe
OBS_TYPES = ("C1", "L1", "P2", "L2")
_IONO_SHELL_M = 350e3


@dataclass(frozen=True)
class GnssObsSpec:
    """Receiver and atmosphere parameters of the observation simulator."""

    elevation_mask_deg: float = 10.0
    code_sigma_m: float = 0.3
    phase_sigma_m: float = 0.002
    rover_clock_bias_s: float = 2.5e-7
    rover_clock_drift: float = 3.0e-10  # s/s
    base_clock_bias_s: float = -4.0e-7
    base_clock_drift: float = -1.5e-10
    zenith_wet_delay_m: float = 0.12  # common to both receivers
    vertical_iono_l1_m: float = 3.0  # common to both receivers
    ambiguity_range_cycles: int = 1_000_000


@dataclass(frozen=True)
class ReceiverTrack:
    """A receiver's antenna (ARP = phase centre here) over time: (n,) GPS s of week, (n, 3) ECEF m.

    A static receiver has one row; a moving one is interpolated linearly (give 1 Hz or better).
    """

    time_s: np.ndarray
    ecef_m: np.ndarray

    def at(self, t: np.ndarray) -> np.ndarray:
        if len(self.time_s) == 1:
            return np.broadcast_to(self.ecef_m[0], np.shape(t) + (3,))
        return np.stack([np.interp(t, self.time_s, self.ecef_m[:, k]) for k in range(3)], axis=-1)


def _select(eph: GpsEphemerides, prn: int, t: np.ndarray, week: int) -> np.ndarray:
    """Index of the ephemeris of ``prn`` nearest in toe to each time (-1 when none within 2 h or unhealthy)."""
    rows = np.flatnonzero((eph.prn == prn) & (eph.health == 0))
    if rows.size == 0:
        return np.full(np.shape(t), -1)
    toe = (eph.toe_week[rows] - week) * SECONDS_PER_WEEK + eph.toe_s[rows]
    age = np.abs(np.asarray(t)[..., None] - toe)
    best = np.argmin(age, axis=-1)
    return np.where(np.take_along_axis(age, best[..., None], -1)[..., 0] <= MAX_EPHEMERIS_AGE_S, rows[best], -1)


def satellite_positions(eph: GpsEphemerides, rows: np.ndarray, t: np.ndarray,
                        week: int) -> tuple[np.ndarray, np.ndarray]:
    """ECEF position [m] (frame at ``t``) and clock offset [s] of ephemeris ``rows`` at GPS times ``t``.

    IS-GPS-200 Table 20-IV (user algorithm for ephemeris determination) and 20.3.3.3.3.1
    (satellite clock with the relativistic correction). ``t`` in seconds of ``week``.
    """
    t = np.asarray(t, dtype=float)
    toe = (eph.toe_week[rows] - week) * SECONDS_PER_WEEK + eph.toe_s[rows]
    toc = (eph.toc_week[rows] - week) * SECONDS_PER_WEEK + eph.toc_s[rows]
    a = eph.sqrt_a_sqrtm[rows] ** 2
    e = eph.e[rows]
    tk = t - toe
    mean_anomaly = eph.m0_rad[rows] + (np.sqrt(GM_EARTH_GPS / a**3) + eph.delta_n_radps[rows]) * tk
    eccentric = mean_anomaly.copy()
    for _ in range(10):  # Kepler's equation; e < 0.03 converges to 1e-15 in a few steps
        eccentric = mean_anomaly + e * np.sin(eccentric)
    true_anomaly = np.arctan2(np.sqrt(1.0 - e**2) * np.sin(eccentric), np.cos(eccentric) - e)
    phi = true_anomaly + eph.omega_rad[rows]
    sin2, cos2 = np.sin(2.0 * phi), np.cos(2.0 * phi)
    u = phi + eph.cus_rad[rows] * sin2 + eph.cuc_rad[rows] * cos2
    r = a * (1.0 - e * np.cos(eccentric)) + eph.crs_m[rows] * sin2 + eph.crc_m[rows] * cos2
    inclination = eph.i0_rad[rows] + eph.cis_rad[rows] * sin2 + eph.cic_rad[rows] * cos2 + eph.idot_radps[rows] * tk
    node = (eph.omega0_rad[rows] + (eph.omega_dot_radps[rows] - EARTH_ROTATION_RADPS) * tk
            - EARTH_ROTATION_RADPS * eph.toe_s[rows])
    x_orb, y_orb = r * np.cos(u), r * np.sin(u)
    position = np.stack([x_orb * np.cos(node) - y_orb * np.cos(inclination) * np.sin(node),
                         x_orb * np.sin(node) + y_orb * np.cos(inclination) * np.cos(node),
                         y_orb * np.sin(inclination)], axis=-1)
    dt = t - toc
    clock = (eph.af0_s[rows] + eph.af1[rows] * dt + eph.af2_per_s[rows] * dt**2
             + RELATIVISTIC_F * e * eph.sqrt_a_sqrtm[rows] * np.sin(eccentric))
    return position, clock


def _elevation(receiver_ecef: np.ndarray, satellite_ecef: np.ndarray) -> np.ndarray:
    lat, lon, _ = earth.ecef_to_geodetic(receiver_ecef)
    up = np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=-1)
    line = satellite_ecef - receiver_ecef
    return np.arcsin(np.sum(line * up, axis=-1) / np.linalg.norm(line, axis=-1))


def _hydrostatic_zenith_delay_m(receiver_ecef: np.ndarray) -> np.ndarray:
    """Saastamoinen hydrostatic zenith delay with the standard atmosphere (as RTKLIB's tropmodel)."""
    lat, _, h = earth.ecef_to_geodetic(receiver_ecef)
    h = np.clip(h, 0.0, 1e4)
    pressure_hpa = 1013.25 * (1.0 - 2.2557e-5 * h) ** 5.2568
    return 0.0022768 * pressure_hpa / (1.0 - 0.00266 * np.cos(2.0 * lat) - 0.00028 * h / 1e3)


def _iono_mapping(elevation_rad: np.ndarray) -> np.ndarray:
    radius = earth.WGS84.a
    return 1.0 / np.sqrt(1.0 - (radius * np.cos(elevation_rad) / (radius + _IONO_SHELL_M)) ** 2)


@dataclass(frozen=True)
class _Geometry:
    rho_m: np.ndarray  # (n, k) geometric range, NaN where not tracked
    sat_clock_s: np.ndarray
    elevation_rad: np.ndarray
    hydrostatic_m: np.ndarray  # (n,) zenith delay at the receiver


def _geometry(eph: GpsEphemerides, prns: np.ndarray, track: ReceiverTrack, tags_s: np.ndarray, week: int,
              clock_bias_s: float, clock_drift: float, mask_rad: float) -> _Geometry:
    t_rx = tags_s - (clock_bias_s + clock_drift * (tags_s - tags_s[0]))
    receiver = track.at(t_rx)
    n, k = len(tags_s), len(prns)
    rho = np.full((n, k), np.nan)
    sat_clock = np.full((n, k), np.nan)
    elevation = np.full((n, k), np.nan)
    for j, prn in enumerate(prns):  # a loop over satellites (about 30), vectorised over epochs
        rows = _select(eph, int(prn), t_rx, week)
        ok = rows >= 0
        if not ok.any():
            continue
        tau = np.full(ok.sum(), 0.075)
        for _ in range(4):  # light time: converges to picoseconds
            sat, clock = satellite_positions(eph, rows[ok], t_rx[ok] - tau, week)
            angle = EARTH_ROTATION_RADPS * tau  # the earth turns under the signal (Sagnac)
            rotated = np.stack([sat[:, 0] * np.cos(angle) + sat[:, 1] * np.sin(angle),
                                -sat[:, 0] * np.sin(angle) + sat[:, 1] * np.cos(angle), sat[:, 2]], axis=-1)
            distance = np.linalg.norm(rotated - receiver[ok], axis=-1)
            tau = distance / SPEED_OF_LIGHT_MPS
        el = _elevation(receiver[ok], rotated)
        visible = el >= mask_rad
        index = np.flatnonzero(ok)[visible]
        rho[index, j], sat_clock[index, j], elevation[index, j] = distance[visible], clock[visible], el[visible]
    return _Geometry(rho, sat_clock, elevation, _hydrostatic_zenith_delay_m(receiver))


def _observations(geometry: _Geometry, common_slant_m: np.ndarray, iono_l1_m: np.ndarray, tags_s: np.ndarray,
                  clock_bias_s: float, clock_drift: float, spec: GnssObsSpec,
                  rng: np.random.Generator) -> np.ndarray:
    """(n, k, 4) C1, L1, P2, L2 of one receiver."""
    shape = geometry.rho_m.shape
    receiver_clock = (clock_bias_s + clock_drift * (tags_s - tags_s[0]))[:, None]
    troposphere = geometry.hydrostatic_m[:, None] / np.sin(geometry.elevation_rad) + common_slant_m
    base = geometry.rho_m + SPEED_OF_LIGHT_MPS * (receiver_clock - geometry.sat_clock_s) + troposphere
    iono_l2 = iono_l1_m * (FREQ_L1_HZ / FREQ_L2_HZ) ** 2
    ambiguity = rng.integers(-spec.ambiguity_range_cycles, spec.ambiguity_range_cycles, (2, shape[1]))
    columns = []
    for iono, wavelength, cycles in ((iono_l1_m, WAVELENGTH_L1_M, ambiguity[0]), (iono_l2, WAVELENGTH_L2_M, ambiguity[1])):
        columns.append(base + iono + rng.normal(0.0, spec.code_sigma_m, shape))  # C1 / P2: delayed
        columns.append((base - iono + rng.normal(0.0, spec.phase_sigma_m, shape)) / wavelength + cycles)  # advanced
    return np.stack(columns, axis=-1)


@dataclass(frozen=True)
class SimulatedObservations:
    rover_obs: Path
    base_obs: Path
    epochs: int
    satellites_per_epoch_min: int
    satellites_per_epoch_median: float


def simulate_gnss_observations(nav_file: str | Path, rover: ReceiverTrack, rover_tags_s: np.ndarray,
                               base_mark_ecef_m: np.ndarray, base_antenna_height_m: float, gps_week: int,
                               out_dir: str | Path, seed: int, spec: GnssObsSpec = GnssObsSpec(),
                               names: tuple[str, str] = ("rover.obs", "base.obs"),
                               header_error_m: float = 2.0) -> SimulatedObservations:
    """Write rover and base RINEX 2.11 observation files into ``out_dir``.

    rover_tags_s     : rover epoch tags (receiver time, s of ``gps_week``); the base observes
                       every whole interval from the first to the last tag
    base_mark_ecef_m : the control point under the base; its antenna reference point is
                       ``base_antenna_height_m`` above it along the ellipsoid normal
    header_error_m   : error of the APPROX POSITION XYZ the receivers write (metre level, as real ones)
    """
    eph = read_gps_ephemerides(nav_file)
    out_dir = Path(out_dir)
    rng = np.random.default_rng(seed)
    rover_tags_s = np.asarray(rover_tags_s, dtype=float)
    interval = float(np.median(np.diff(rover_tags_s)))
    base_tags = np.arange(rover_tags_s[0], rover_tags_s[-1] + 0.5 * interval, interval)
    lat, lon, h = earth.ecef_to_geodetic(np.asarray(base_mark_ecef_m, dtype=float))
    base_arp = earth.geodetic_to_ecef(lat, lon, h + base_antenna_height_m)
    base = ReceiverTrack(np.array([base_tags[0]]), np.asarray(base_arp, dtype=float)[None, :])
    prns = np.unique(eph.prn)
    mask = np.radians(spec.elevation_mask_deg)
    base_geometry = _geometry(eph, prns, base, base_tags, gps_week, spec.base_clock_bias_s, spec.base_clock_drift,
                              mask)
    rover_geometry = _geometry(eph, prns, rover, rover_tags_s, gps_week, spec.rover_clock_bias_s,
                               spec.rover_clock_drift, mask)
    # The atmosphere common to both receivers, per satellite and epoch, taken at the base.
    at_rover = np.clip(np.searchsorted(base_tags, rover_tags_s - 0.5 * interval), 0, len(base_tags) - 1)
    common_el = base_geometry.elevation_rad
    wet = spec.zenith_wet_delay_m / np.sin(common_el)
    iono = spec.vertical_iono_l1_m * _iono_mapping(common_el)
    observed = {}
    receivers = ((names[1], base_geometry, base_tags, slice(None), spec.base_clock_bias_s, spec.base_clock_drift,
                  np.asarray(base_mark_ecef_m, dtype=float), base_antenna_height_m),
                 (names[0], rover_geometry, rover_tags_s, at_rover, spec.rover_clock_bias_s, spec.rover_clock_drift,
                  rover.at(rover_tags_s[:1])[0], 0.0))
    for name, geometry, tags, rows, bias, drift, marker, antenna_height in receivers:
        values = _observations(geometry, wet[rows], iono[rows], tags, bias, drift, spec, rng)
        tracked = np.isfinite(values).all(axis=-1)
        header = RinexObsHeader(
            marker_name=Path(name).stem.upper(),
            approx_position_ecef_m=tuple(marker + rng.normal(0.0, header_error_m / np.sqrt(3.0), 3)),
            antenna_delta_hen_m=(antenna_height, 0.0, 0.0), obs_types=OBS_TYPES, interval_s=interval)
        write_rinex2_obs(out_dir / name, header, gps_week, tags, np.where(tracked, prns[None, :], 0), values)
        observed[name] = tracked.sum(axis=1)
    rover_count = observed[names[0]]
    if rover_count.min() < 5:
        raise ValueError(f"{Path(nav_file).name}: only {rover_count.min()} satellites above the mask at some rover "
                         "epoch; the survey's time must lie inside the navigation file's day")
    return SimulatedObservations(out_dir / names[0], out_dir / names[1], len(rover_tags_s), int(rover_count.min()),
                                 float(np.median(rover_count)))


# --------------------------------------------------------------------------- a survey with raw GNSS

@dataclass(frozen=True)
class RawGnssSurvey:
    """What :func:`convert_survey_to_raw_gnss` did: the files, the base control point (engineering
    coordinates: east, north, normal height [m]) and its true ellipsoidal position."""

    observations: SimulatedObservations
    navigation: Path
    base_point: str
    base_enh_m: tuple[float, float, float]
    base_mark_ecef_m: tuple[float, float, float]
    base_antenna_height_m: float


def convert_survey_to_raw_gnss(survey_folder: str | Path, config: ScenarioConfig, nav_file: str | Path, seed: int,
                               base_point: str = "CPII-BASE", base_offset_en_m: tuple[float, float] = (-150.0, 90.0),
                               base_antenna_height_m: float = 1.55,
                               spec: GnssObsSpec = GnssObsSpec()) -> RawGnssSurvey:
    """Replace the GNSS solution of a simulated survey by the rover and base observations behind it.

    The rover observes at the antenna truth's epochs outside the scenario's GNSS outages; the
    base stands on a control point ``base_offset_en_m`` from the survey's first antenna position,
    2 m below it. survey.toml gets a ``[gnss_raw]`` table naming the files and the base point
    (whose coordinates belong in the project); truth/base_point.toml records the mark.
    ``config`` is the scenario the survey was simulated with; its time must lie inside the
    navigation file's day (e.g. ``preset("short", gps_week=1316, start_time_s=558000.0025)`` for
    the 2005-04-02 file of the rinex_0759_3040 data).
    """
    folder = Path(survey_folder)
    antenna = read_antenna_truth(folder / "truth" / "antenna.npy")
    outages = tomllib.loads((folder / "truth" / "errors.toml").read_text(encoding="utf-8"))["gnss_outages_s"]
    tags = antenna["time_s"]
    keep = np.ones(len(tags), dtype=bool)
    for start, end in outages:
        keep &= ~((tags >= start) & (tags <= end))
    crs = EngineeringCRS.from_settings(config.geodetic.crs)
    ellipsoid = crs.reference_ellipsoid
    lat, lon, h = earth.ecef_to_geodetic(antenna["ecef_m"][0], ellipsoid)
    east, north = crs.to_plane(lat, lon)
    east, north = float(east) + base_offset_en_m[0], float(north) + base_offset_en_m[1]
    mark_lat, mark_lon = crs.to_geodetic(east, north)
    mark_h = float(h) - 2.0
    normal_height = mark_h - float(height_anomaly(config, east, north))
    mark = earth.geodetic_to_ecef(float(mark_lat), float(mark_lon), mark_h, ellipsoid)
    observations = simulate_gnss_observations(nav_file, ReceiverTrack(tags, antenna["ecef_m"]), tags[keep], mark,
                                              base_antenna_height_m, config.gps_week, folder, seed, spec)
    navigation = folder / Path(nav_file).name
    shutil.copyfile(nav_file, navigation)
    manifest = read_manifest(folder)
    (folder / manifest.files["gnss"].path).unlink()
    raw = RawGnss(base=observations.base_obs.name, navigation=(navigation.name,), base_point=base_point,
                  rover=observations.rover_obs.name, base_antenna_height_m=base_antenna_height_m)
    files = {role: entry for role, entry in manifest.files.items() if role != "gnss"}
    write_manifest(folder, replace(manifest, files=files, raw_gnss=raw))
    truth = {"base_point": base_point, "east_m": east, "north_m": north, "normal_height_m": normal_height,
             "lat_deg": float(np.degrees(mark_lat)), "lon_deg": float(np.degrees(mark_lon)),
             "ellipsoidal_height_m": mark_h, "antenna_height_m": base_antenna_height_m}
    (folder / "truth" / "base_point.toml").write_text(tomli_w.dumps(truth), encoding="utf-8")
    return RawGnssSurvey(observations, navigation, base_point, (east, north, normal_height),
                         tuple(float(v) for v in mark), base_antenna_height_m)
