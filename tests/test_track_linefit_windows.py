"""Windowed line-type fitting (thesis eq. 5.24) against a design with known irregularities and long waves."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shared_build import computed_once

from insrail.track.alignment import Arc, Clothoid, HorizontalAlignment, Line
from insrail.track.alignment_csv import read_alignment_csv, write_alignment_csv
from insrail.track.landxml import read_landxml, write_landxml
from insrail.track.linefit import LineFitError, fit_alignment
from insrail.track.linefit_windows import blend_weights, fit_windows, window_ranges
from insrail.track.profile import PVI, CantTable, VerticalProfile

INF = math.inf
PLAN = HorizontalAlignment(
    1000.0, 2000.0, 0.4, 0.0,
    (Line(1200.0), Clothoid(100.0, INF, 2500.0, "right"), Arc(400.0, 2500.0, "right"),
     Clothoid(100.0, 2500.0, INF, "right"), Line(1200.0)),
)
PROFILE = VerticalProfile(
    (PVI(0.0, 50.0), PVI(1000.0, 54.0, "circular", curve_radius_m=20000.0), PVI(PLAN.end_station_m, 50.0))
)
STATIONS = np.arange(0.0, PLAN.end_station_m, 0.625)
# short-wave irregularities (13-67 m), what the deviations must show
IRREGULARITY_LATERAL = (1e-3 * np.sin(2 * np.pi * STATIONS / 13.0 + 1) + 0.8e-3 * np.sin(2 * np.pi * STATIONS / 31.0)
                        + 0.6e-3 * np.sin(2 * np.pi * STATIONS / 67.0 + 2))
IRREGULARITY_VERTICAL = 0.9e-3 * np.sin(2 * np.pi * STATIONS / 17.0) + 0.7e-3 * np.sin(2 * np.pi * STATIONS / 43.0 + 1)
# GNSS-like long-wave errors: 5 mm at 2 km wavelength and a slow drift (8 mm, 6 mm over the 3 km)
RELATIVE = STATIONS / PLAN.end_station_m
LONG_WAVE_LATERAL = 5e-3 * np.sin(2 * np.pi * STATIONS / 2000.0 + 0.5) + 8e-3 * RELATIVE**2
LONG_WAVE_VERTICAL = 5e-3 * np.sin(2 * np.pi * STATIONS / 2000.0 + 1.5) + 6e-3 * RELATIVE**2


def centreline(lateral, vertical):
    east, north = PLAN.point_at(STATIONS)
    azimuth = PLAN.azimuth_at(STATIONS)
    return (STATIONS, east + lateral * np.cos(azimuth), north - lateral * np.sin(azimuth),
            PROFILE.elevation_at(STATIONS) + vertical)


def rms(values):
    return float(np.sqrt(np.mean(values**2)))


def _fitted_with_long_waves():
    points = centreline(IRREGULARITY_LATERAL + LONG_WAVE_LATERAL, IRREGULARITY_VERTICAL + LONG_WAVE_VERTICAL)
    fit = fit_alignment(*points)
    return points, fit, fit_windows(fit, *points)


def long_waves_once():
    """The global and the windowed fit of the 3 km line with long waves (some 14 s of CPU): computed once per test
    run, not once per xdist worker that runs one of this module's tests (shared_build); with -n, while the
    workers wait for the numba warm-up (tests/numba_warmup.py's PREBUILT)."""
    return computed_once("linefit-windows-long-waves", _fitted_with_long_waves)


@pytest.fixture(scope="module")
def with_long_waves():
    return long_waves_once()


def test_windows_recover_the_irregularities_the_global_fit_buries_in_long_waves(with_long_waves):
    _, fit, windowed = with_long_waves
    lateral_error = windowed.lateral_m - IRREGULARITY_LATERAL
    vertical_error = windowed.vertical_m - IRREGULARITY_VERTICAL
    # measured: global 1.57 / 2.68 mm RMS (max 3.9 / 4.7 mm); windowed 0.22 / 0.23 mm RMS (max 0.9 mm)
    assert rms(fit.horizontal.offset_m - IRREGULARITY_LATERAL) > 1.2e-3
    assert rms(fit.vertical.residual_m - IRREGULARITY_VERTICAL) > 2.0e-3
    assert rms(lateral_error) < 0.3e-3 and np.abs(lateral_error).max() < 1.2e-3
    assert rms(vertical_error) < 0.3e-3 and np.abs(vertical_error).max() < 1.2e-3
    # the reference point is the measured point moved back by the deviations
    points = with_long_waves[0]
    measured = np.column_stack(points[1:])
    assert np.allclose(np.hypot(*(measured - windowed.reference_enh_m)[:, :2].T), np.abs(windowed.lateral_m), atol=1e-9)
    assert np.allclose(measured[:, 2] - windowed.reference_enh_m[:, 2], windowed.vertical_m, atol=1e-12)


def test_blending_leaves_no_step_where_windows_join(with_long_waves):
    _, _, windowed = with_long_waves
    assert len(windowed.windows) == 8
    # neighbouring windows disagree in their overlap (a hard switch would show it as a step) ...
    disagreement = []
    for before, after in zip(windowed.windows[:-1], windowed.windows[1:]):
        common = np.arange(after.first, before.last + 1)
        disagreement.append(np.abs(before.lateral_m[common - before.first] - after.lateral_m[common - after.first]).max())
    assert max(disagreement) > 0.1e-3
    # ... but the blended deviations change smoothly: the largest step from one point to the next is
    # that of the irregularities themselves (2 pi A / lambda * 0.625 m = 0.3 mm), not more
    for deviation, truth in ((windowed.lateral_m, IRREGULARITY_LATERAL), (windowed.vertical_m, IRREGULARITY_VERTICAL)):
        assert np.abs(np.diff(deviation - truth)).max() < 0.02e-3


def test_without_long_waves_global_and_windowed_both_equal_the_truth():
    points = centreline(IRREGULARITY_LATERAL, IRREGULARITY_VERTICAL)
    fit = fit_alignment(*points)
    windowed = fit_windows(fit, *points)
    for deviation, truth in ((fit.horizontal.offset_m, IRREGULARITY_LATERAL), (fit.vertical.residual_m, IRREGULARITY_VERTICAL),
                             (windowed.lateral_m, IRREGULARITY_LATERAL), (windowed.vertical_m, IRREGULARITY_VERTICAL)):
        assert np.abs(deviation - truth).max() < 0.1e-3


def test_window_layout_and_weights():
    ranges = window_ranges(0.0, 3000.0, 500.0, 150.0)
    assert np.all(ranges[:, 1] - ranges[:, 0] >= 500.0)
    assert np.allclose(ranges[:-1, 1] - ranges[1:, 0], 150.0)
    assert ranges[0, 0] == 0.0 and ranges[-1, 1] == 3000.0
    stations = np.linspace(0.0, 3000.0, 4801)
    weights = blend_weights(stations, ranges)
    assert np.allclose(weights.sum(axis=0), 1.0)
    # eq. 5.24 inside the first overlap
    start, end = ranges[1, 0], ranges[0, 1]
    inside = (stations > start) & (stations < end)
    assert np.allclose(weights[1, inside], (stations[inside] - start) / (end - start))
    assert window_ranges(0.0, 400.0, 500.0, 150.0).tolist() == [[0.0, 400.0]]


@pytest.mark.parametrize("window, overlap, message", [(200.0, 50.0, "at least 300"), (500.0, 300.0, "half the window")])
def test_bad_window_options_are_refused(with_long_waves, window, overlap, message):
    points, fit, _ = with_long_waves
    with pytest.raises(LineFitError, match=message):
        fit_windows(fit, *points, window_m=window, overlap_m=overlap)


@settings(max_examples=25, deadline=None)
@given(
    first=st.floats(-5000.0, 5000.0),
    span=st.floats(301.0, 20000.0),
    window=st.floats(300.0, 2000.0),
    overlap_fraction=st.floats(0.01, 0.5),
)
def test_windows_tile_the_data_and_weights_blend_continuously(first, span, window, overlap_fraction):
    overlap = overlap_fraction * window
    ranges = window_ranges(first, first + span, window, overlap)
    assert ranges[0, 0] == first and ranges[-1, 1] == first + span
    if len(ranges) > 1:
        assert np.all(ranges[:, 1] - ranges[:, 0] >= window - 1e-6)
        assert np.allclose(ranges[:-1, 1] - ranges[1:, 0], overlap)
    stations = np.linspace(first, first + span, 20001)
    weights = blend_weights(stations, ranges)
    assert np.allclose(weights.sum(axis=0), 1.0) and weights.min() >= 0.0
    # linear ramps: no weight changes faster than 1 / overlap per metre
    step = stations[1] - stations[0]
    assert np.abs(np.diff(weights, axis=1)).max() <= step / overlap + 1e-9


def test_fitted_cant_and_its_export(tmp_path):
    """Cant is fitted per arc and ramped along the clothoids, and travels with the fitted alignment."""
    design_cant = CantTable(np.array([0.0, 1200.0, 1300.0, 1700.0, 1800.0, PLAN.end_station_m]),
                            np.array([0.0, 0.0, 0.08, 0.08, 0.0, 0.0]))
    rng = np.random.default_rng(9)
    measured_cant = design_cant.cant_at(STATIONS) + rng.normal(0.0, 0.3e-3, STATIONS.size)
    points = centreline(IRREGULARITY_LATERAL, IRREGULARITY_VERTICAL)
    fit = fit_alignment(*points, cant_m=measured_cant)
    cant = fit.alignment.cant
    assert np.abs(cant.cant_at(np.clip(STATIONS, cant.stations_m[0], cant.stations_m[-1]))
                  - design_cant.cant_at(STATIONS)).max() < 0.2e-3
    assert 0.2e-3 < np.sqrt(np.mean(fit.cant_residual_m**2)) < 0.4e-3 and "cant residuals" in fit.report()
    write_alignment_csv(tmp_path / "fitted.csv", fit.alignment)
    write_landxml(tmp_path / "fitted.xml", fit.alignment)
    for back in (read_alignment_csv(tmp_path / "fitted.csv"), read_landxml(tmp_path / "fitted.xml")):
        assert np.allclose(back.cant.cant_at(STATIONS[100:-100]), cant.cant_at(STATIONS[100:-100]), atol=1e-6)
