"""Track irregularities from per-sleeper deviations: chord versines and differential versines.

Inputs are plain arrays sampled at the sleepers: ``station_m`` (increasing, roughly 0.625 m
apart, not necessarily uniform) and a deviation ``d`` [m] of one rail in one direction
(lateral + right or vertical + up, see :mod:`insrail.track`), NaN where the sleeper is invalid.

Irregularities are computed on *deviations* from the design (or fitted) line. A chord
laid on the deviation signal therefore already has the design versine removed: on a
curve, ``versine(measured) - versine(design) = versine(measured - design)`` because the
versine is linear. :func:`versine_xy` gives the versine of absolute plane coordinates for
the case without a design line.

Methods that need equally spaced samples (the differential versines, the wavelength bands)
interpolate the deviations linearly onto a uniform grid (0.625 m by default) starting at the
first sleeper, evaluate there, and interpolate the result back to the sleepers. Grid nodes
that are farther than ``max_gap_m`` from valid sleepers on both sides are NaN, so invalid
stretches are never bridged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

SLEEPER_SPACING_M = 0.625
DEFAULT_MAX_GAP_M = 1.5  # bridges one missing sleeper, never two


def check_series(station_m: np.ndarray, values: np.ndarray, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(stations, values) as float arrays; ValueError naming ``name`` unless one value per
    finite, strictly increasing station."""
    station = np.asarray(station_m, dtype=float)
    data = np.asarray(values, dtype=float)
    if station.ndim != 1 or data.shape != station.shape:
        raise ValueError(f"{name}: expected one value per station ({station.shape}), found shape {data.shape}")
    if not np.all(np.isfinite(station)):
        raise ValueError(f"{name}: stations must be finite")
    if station.size > 1 and not np.all(np.diff(station) > 0):
        bad = int(np.argmin(np.diff(station) > 0))
        raise ValueError(f"{name}: stations must increase; sleeper {bad + 1} at {station[bad + 1]:.3f} m does not")
    return station, data


def interpolate_valid(
    station_m: np.ndarray, values: np.ndarray, query_m: np.ndarray, max_gap_m: float = DEFAULT_MAX_GAP_M
) -> np.ndarray:
    """Linear interpolation of ``values`` at ``query_m`` over the finite samples only.

    NaN outside the sampled range and inside gaps between valid samples wider than
    ``max_gap_m`` (a query that falls exactly on a valid sample is always kept).
    """
    station, data = check_series(station_m, values, "interpolate_valid")
    query = np.asarray(query_m, dtype=float)
    ok = np.isfinite(data)
    sv, dv = station[ok], data[ok]
    out = np.full(query.shape, np.nan)
    if sv.size == 0:
        return out
    right = np.clip(np.searchsorted(sv, query, side="left"), 0, sv.size - 1)
    left = np.clip(right - 1, 0, sv.size - 1)
    on_sample = np.isclose(sv[right], query, rtol=0.0, atol=1e-9) | np.isclose(sv[left], query, rtol=0.0, atol=1e-9)
    inside = (query >= sv[0] - 1e-9) & (query <= sv[-1] + 1e-9)
    bridged = (sv[right] - sv[left]) <= max_gap_m
    keep = inside & (bridged | on_sample)
    out[keep] = np.interp(query[keep], sv, dv)
    return out


@dataclass(frozen=True)
class UniformGrid:
    """Deviations resampled to ``station_m = start_m + spacing_m * k`` (NaN in gaps)."""

    start_m: float
    spacing_m: float
    values: np.ndarray

    @property
    def station_m(self) -> np.ndarray:
        return self.start_m + self.spacing_m * np.arange(self.values.size)

    @classmethod
    def resample(
        cls,
        station_m: np.ndarray,
        values: np.ndarray,
        spacing_m: float = SLEEPER_SPACING_M,
        max_gap_m: float = DEFAULT_MAX_GAP_M,
    ) -> UniformGrid:
        station, data = check_series(station_m, values, "resample")
        if spacing_m <= 0:
            raise ValueError(f"grid spacing must be positive, found {spacing_m}")
        if station.size == 0:
            return cls(0.0, spacing_m, np.empty(0))
        count = int(np.floor((station[-1] - station[0]) / spacing_m + 1e-9)) + 1
        grid = station[0] + spacing_m * np.arange(count)
        return cls(float(station[0]), float(spacing_m), interpolate_valid(station, data, grid, max_gap_m))

    def at(self, station_m: np.ndarray, grid_values: np.ndarray) -> np.ndarray:
        """Values defined on this grid, interpolated back to ``station_m`` (NaN propagates)."""
        position = (np.asarray(station_m, dtype=float) - self.start_m) / self.spacing_m
        node = np.clip(np.floor(position + 1e-9).astype(int), 0, max(grid_values.size - 1, 0))
        upper = np.clip(node + 1, 0, grid_values.size - 1)
        fraction = np.clip(position - node, 0.0, 1.0)
        fraction[fraction < 1e-9] = 0.0
        low, high = grid_values[node], grid_values[upper]
        # An exact node must not be poisoned by a NaN neighbour.
        return np.where(fraction == 0.0, low, low + fraction * (high - low))

    def steps(self, length_m: float, what: str) -> int:
        """``length_m`` as a whole number of grid steps (the chord methods need exact multiples)."""
        count = length_m / self.spacing_m
        if count < 1 or abs(count - round(count)) > 1e-6:
            raise ValueError(
                f"{what} = {length_m} m must be a positive multiple of the grid spacing {self.spacing_m} m"
            )
        return round(count)


def versine(
    station_m: np.ndarray,
    deviation_m: np.ndarray,
    chord_m: float = 10.0,
    back_m: float | None = None,
    max_gap_m: float = DEFAULT_MAX_GAP_M,
) -> np.ndarray:
    """Versine [m] at every sleeper of a chord whose ends lie ``back_m`` behind and
    ``chord_m - back_m`` ahead (symmetric when ``back_m`` is None):

        v(s) = d(s) - [b d(s - a) + a d(s + b)] / (a + b),  a = back_m, b = chord_m - back_m

    positive when the rail lies right of (or above) the chord. The chord ends are linearly
    interpolated between sleepers. NaN where the chord leaves the data or hits a gap.
    Transfer function of the symmetric chord: 1 - cos(pi chord / wavelength).
    """
    station, deviation = check_series(station_m, deviation_m, "versine")
    a = chord_m / 2.0 if back_m is None else float(back_m)
    b = chord_m - a
    if chord_m <= 0 or a <= 0 or b <= 0:
        raise ValueError(f"chord {chord_m} m with back part {a} m: both parts of the chord must be positive")
    behind = interpolate_valid(station, deviation, station - a, max_gap_m)
    ahead = interpolate_valid(station, deviation, station + b, max_gap_m)
    return deviation - (b * behind + a * ahead) / (a + b)


def versine_xy(
    station_m: np.ndarray, east_m: np.ndarray, north_m: np.ndarray, chord_m: float = 10.0, back_m: float | None = None
) -> np.ndarray:
    """Versine [m] of absolute plane coordinates: signed distance of the point at ``s`` from
    the straight chord between the points at ``s - a`` and ``s + b``, positive right of the
    chord looking along increasing station. A curve turning right bulges left of its chords,
    so its versine is negative.

    For a circle of radius R the magnitude is a*b/(2R) to first order. Use this when there is
    no design line; with a design line, take :func:`versine` of the deviations instead.
    """
    station, east = check_series(station_m, east_m, "versine_xy")
    _, north = check_series(station_m, north_m, "versine_xy")
    a = chord_m / 2.0 if back_m is None else float(back_m)
    b = chord_m - a
    if a <= 0 or b <= 0:
        raise ValueError(f"chord {chord_m} m with back part {a} m: both parts of the chord must be positive")
    e0, n0 = (interpolate_valid(station, c, station - a) for c in (east, north))
    e1, n1 = (interpolate_valid(station, c, station + b) for c in (east, north))
    de, dn = e1 - e0, n1 - n0
    length = np.hypot(de, dn)
    # Cross product of chord direction and the point's offset: + when the point is right of the chord.
    return (dn * (east - e0) - de * (north - n0)) / length


def _trailing_extreme(values: np.ndarray, width: int, pick) -> np.ndarray:
    """``pick`` (np.max or np.min) over values[k - width + 1 .. k] for every k; +-inf mark excluded entries."""
    fill = -np.inf if pick is np.max else np.inf
    padded = np.concatenate([np.full(width - 1, fill), values])
    return pick(sliding_window_view(padded, width), axis=1)


def differential_versine_grid(deviation_m: np.ndarray, chord_steps: int, pair_steps: int) -> np.ndarray:
    """Worst signed differential versine per grid node (uniform samples; see
    :func:`differential_versine`). Entry k holds the worst value of the point pair (k, k + p)
    over every chord placement that contains it; NaN when no placement is fully valid.

    For a chord starting at node i the residual is r(j) = d(j) - d(i) - (j - i)/m [d(i+m) - d(i)],
    so r(k) - r(k+p) = D(k) + S(i) with D(k) = d(k) - d(k+p), S(i) = p/m [d(i+m) - d(i)].
    The chords containing the pair start at i = k - (m - p) .. k; the worst |D + S| over them is
    reached at the window's largest or smallest S, which makes the slide O(n * (m - p)) in
    numpy rather than O(n * m * m) in loops.
    """
    d = np.asarray(deviation_m, dtype=float)
    m, p = int(chord_steps), int(pair_steps)
    if not 0 < p < m:
        raise ValueError(f"point-pair distance ({p} steps) must be positive and shorter than the chord ({m} steps)")
    n = d.size
    out = np.full(n, np.nan)
    if n <= m:
        return out
    slope_term = np.full(n, np.nan)
    slope_term[: n - m] = p / m * (d[m:] - d[: n - m])
    pair_difference = np.full(n, np.nan)
    pair_difference[: n - p] = d[: n - p] - d[p:]
    valid_chord = np.isfinite(slope_term)
    width = m - p + 1
    highest = _trailing_extreme(np.where(valid_chord, slope_term, -np.inf), width, np.max)
    lowest = _trailing_extreme(np.where(valid_chord, slope_term, np.inf), width, np.min)
    with np.errstate(invalid="ignore"):
        upper = pair_difference + highest
        lower = pair_difference + lowest
    usable = np.isfinite(upper) & np.isfinite(lower)
    out[usable] = np.where(np.abs(upper[usable]) >= np.abs(lower[usable]), upper[usable], lower[usable])
    return out


def differential_versine(
    station_m: np.ndarray,
    deviation_m: np.ndarray,
    chord_m: float = 30.0,
    pair_m: float = 5.0,
    spacing_m: float = SLEEPER_SPACING_M,
    max_gap_m: float = DEFAULT_MAX_GAP_M,
) -> np.ndarray:
    """Chinese differential-versine check (矢距差法; 30 m / 5 m and 300 m / 150 m) per sleeper [m].

    For every placement of a chord of length ``chord_m`` (slid by one grid step, i.e. one
    sleeper, along the whole line) the residual r(s) = d(s) - (straight line through d at the
    chord's ends) is formed, and every point pair p = ``pair_m`` apart inside the chord gives
    r(s) - r(s + p). Thesis eq. (2.2) evaluates one pair per chord (the chord through P1 and
    P49, value at P25); sliding every chord over every pair is the stricter reading that the
    digest's literature cross-check calls for. The value of a pair belongs to its first point
    s (the thesis's P25); each sleeper gets the signed value of largest magnitude over all
    placements. Deviations are resampled to ``spacing_m`` (chord and pair must be multiples).
    Worst-case gains per unit amplitude: 30/5: 2.0 at 10 m, 0 at 5 m; 300/150: 2.0 at 100 m.
    """
    station, deviation = check_series(station_m, deviation_m, "differential_versine")
    grid = UniformGrid.resample(station, deviation, spacing_m, max_gap_m)
    chord_steps = grid.steps(chord_m, "chord length")
    pair_steps = grid.steps(pair_m, "point-pair distance")
    return grid.at(station, differential_versine_grid(grid.values, chord_steps, pair_steps))


# EN 13848-1 wavelength bands [m] (digest tags them [U]; check against the standard text).
BANDS_M = {
    "D1": (3.0, 25.0),
    "D2": (25.0, 70.0),
    "D3_level": (70.0, 150.0),
    "D3_alignment": (70.0, 200.0),
}
MIN_SEGMENT_WAVELENGTHS = 1.0  # a valid stretch shorter than the band's longest wave stays NaN


def band_pass(
    station_m: np.ndarray,
    deviation_m: np.ndarray,
    band: str | tuple[float, float],
    spacing_m: float = SLEEPER_SPACING_M,
    order: int = 4,
    max_gap_m: float = DEFAULT_MAX_GAP_M,
) -> np.ndarray:
    """Zero-phase band-pass of deviations to a wavelength band [m] (EN 13848 D1/D2/D3).

    ``band`` is a key of :data:`BANDS_M` or (shortest, longest) wavelength. Butterworth of
    ``order`` applied forward and backward (effective order doubled, no phase shift) on the
    uniform grid, separately on every valid stretch; stretches shorter than the longest
    wavelength are NaN (the filter has nothing to settle on).
    """
    station, deviation = check_series(station_m, deviation_m, "band_pass")
    shortest, longest = BANDS_M[band] if isinstance(band, str) else band
    if not 0 < shortest < longest:
        raise ValueError(f"wavelength band {band}: expected 0 < shortest < longest")
    if shortest <= 2 * spacing_m:
        raise ValueError(f"shortest wavelength {shortest} m is not resolved by a {spacing_m} m grid")
    # imported here: its filter loop is a numba kernel, which the reports (BANDS_M) do not load
    from insrail.track.butterworth import band_pass_sos, zero_phase

    grid = UniformGrid.resample(station, deviation, spacing_m, max_gap_m)
    sos = band_pass_sos(order, 1.0 / longest, 1.0 / shortest, 1.0 / spacing_m)
    filtered = np.full(grid.values.size, np.nan)
    finite = np.isfinite(grid.values)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], finite.astype(int), [0]])))
    minimum = int(np.ceil(MIN_SEGMENT_WAVELENGTHS * longest / spacing_m))
    for start, stop in zip(edges[::2], edges[1::2]):  # one call per valid stretch, not per sample
        if stop - start >= minimum:
            filtered[start:stop] = zero_phase(sos, grid.values[start:stop])
    return grid.at(station, filtered)


@dataclass(frozen=True)
class SectionStatistics:
    """Standard deviations per fixed-length section [m]; sections start at ``start_m``."""

    start_m: np.ndarray
    end_m: np.ndarray
    standard_deviation_m: np.ndarray  # (sections, channels)
    channels: tuple[str, ...]

    @property
    def track_quality_index_m(self) -> np.ndarray:
        """TQI per section: the sum of the channel standard deviations (NaN if any is missing)."""
        return self.standard_deviation_m.sum(axis=1)


def section_statistics(
    station_m: np.ndarray,
    channels: dict[str, np.ndarray],
    section_m: float = 200.0,
    min_fraction_valid: float = 0.8,
) -> SectionStatistics:
    """Standard deviation of every channel per ``section_m`` section of station.

    A section's value is NaN when fewer than ``min_fraction_valid`` of its sleepers are
    valid. For the Chinese TQI pass the 7 channels left/right level, left/right alignment
    (band-passed, e.g. D1), gauge, cross-level and twist.
    """
    station = np.asarray(station_m, dtype=float)
    names = tuple(channels)
    data = np.column_stack([check_series(station, channels[c], c)[1] for c in names])
    section = np.floor((station - station[0]) / section_m).astype(int)
    count = section[-1] + 1
    finite = np.isfinite(data)
    filled = np.where(finite, data, 0.0)
    n_valid = np.zeros((count, len(names)))
    total = np.zeros_like(n_valid)
    square = np.zeros_like(n_valid)
    np.add.at(n_valid, section, finite)
    np.add.at(total, section, filled)
    np.add.at(square, section, filled**2)
    per_section = np.bincount(section, minlength=count)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = total / n_valid
        variance = np.maximum(square / n_valid - mean**2, 0.0) * n_valid / (n_valid - 1)
    sd = np.sqrt(variance)
    sd[(n_valid < min_fraction_valid * per_section) | (n_valid < 2)] = np.nan
    start = station[0] + section_m * np.arange(count)
    return SectionStatistics(start, start + section_m, sd, names)
