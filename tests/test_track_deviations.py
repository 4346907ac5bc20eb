"""The sleeper table on the simulator truth: resampled rails, gauge, cant and deviations."""

from dataclasses import fields, replace

import numpy as np
import pytest
from track_truth import expected_deviations, truth_reconstruction, truth_sleeper_table

from insrail.io.track_sensors import read_sleeper_times
from insrail.track.alignment import Arc, DesignAlignment, HorizontalAlignment, Line
from insrail.track.deviations import design_cant_m, design_rail_offsets, rail_deviations
from insrail.track.profile import PVI, CantTable, VerticalProfile
from insrail.track.sleeper_table import (
    build_sleeper_table,
    finished_reconstruction,
    reconstruct_track,
    regular_sleepers,
)

MM = 1e-3


@pytest.fixture(scope="module")
def table(short_perfect_survey):
    return truth_sleeper_table(short_perfect_survey)


def test_table_is_complete_and_labelled(table):
    recon, tab = table
    assert tab.valid.all() and len(tab) == len(recon.sleepers)
    assert tab.label[0].startswith(("DK", "K")) and "+" in tab.label[0]


def test_rails_resampled_at_the_sleepers(table):
    recon, tab = table
    truth = recon.sleepers
    for name, column in (("left", tab.left_rail_enh_m), ("right", tab.right_rail_enh_m), ("centre", tab.centre_enh_m)):
        expected = np.column_stack([truth[f"{name}_e"], truth[f"{name}_n"], truth[f"{name}_h"]])
        # 0.625 m quadratic window: the shortest (3 m) irregularity waves leave ~0.03 mm.
        assert np.abs(column - expected).max() < 0.1 * MM, name


def test_station_of_the_resampled_centre_within_a_millimetre(table):
    recon, tab = table
    station, _ = recon.design.horizontal.station_offset(tab.centre_enh_m[:, 0], tab.centre_enh_m[:, 1])
    assert np.abs(station - recon.sleepers["station"]).max() < 1 * MM


def test_gauge_and_cant_to_five_hundredths_of_a_millimetre(table):
    recon, tab = table
    assert np.abs(tab.gauge_m - recon.sleepers["gauge"]).max() < 0.05 * MM
    assert np.abs(tab.cant_m - recon.sleepers["cant"]).max() < 0.05 * MM
    assert np.allclose(tab.design_cant_m, recon.sleepers["design_cant"], atol=1e-9)
    assert np.abs(recon.sleepers["design_cant"]).max() > 0.05  # the curve is canted


def test_deviations_equal_the_injected_irregularities(table):
    recon, tab = table
    lateral, vertical = expected_deviations(recon.sleepers)
    assert np.abs(tab.lateral_deviation_m - lateral).max() < 0.1 * MM
    assert np.abs(tab.vertical_deviation_m - vertical).max() < 0.1 * MM
    assert np.abs(lateral).max() > 2 * MM  # the comparison is not trivially small


def test_regular_grid_table_without_design(table):
    recon, _ = table
    sleepers = regular_sleepers(recon.rails, recon.stations, spacing_m=0.625)
    assert np.allclose(np.diff(sleepers.station_m), 0.625)
    tab = build_sleeper_table(recon.rails, recon.stations, sleepers)
    assert np.isnan(tab.lateral_deviation_m).all() and tab.label[0] == ""
    assert tab.valid[1:-1].all()
    truth = recon.track.sections(sleepers.station_m[tab.valid])
    assert np.abs(tab.left_rail_enh_m[tab.valid] - truth.left_rail_enh_m).max() < 0.1 * MM


# ------------------------------------------------------------- sign conventions
def _canted_straight():
    horizontal = HorizontalAlignment(start_east_m=1000.0, start_north_m=2000.0, start_azimuth_rad=np.pi / 2,
                                     elements=(Line(100.0), Arc(50.0, 500.0, "right"), Line(100.0)), start_station_m=0.0)
    vertical = VerticalProfile((PVI(0.0, 50.0), PVI(250.0, 52.5)))
    cant = CantTable(np.array([0.0, 250.0]), np.array([0.1, 0.1]))
    return DesignAlignment(horizontal, vertical, cant)


def test_deviation_signs():
    design = _canted_straight()
    s = np.array([20.0, 50.0, 80.0])
    offsets, rises = design_rail_offsets(design, s)
    height = design.vertical.elevation_at(s)
    left = np.column_stack([*design.horizontal.point_at(s, offsets[:, 0]), height + rises[:, 0]])
    right = np.column_stack([*design.horizontal.point_at(s, offsets[:, 1]), height + rises[:, 1]])
    lateral, vertical = rail_deviations(design, left, right)
    assert np.abs(lateral).max() < 1e-9 and np.abs(vertical).max() < 1e-9
    # Heading east, right = south: move the right rail 1 mm south, lift the left rail 1 mm.
    lateral, vertical = rail_deviations(design, left + [0, 0, 1e-3], right - [0, 1e-3, 0])
    assert lateral[:, 1] == pytest.approx(1e-3, abs=1e-9) and lateral[:, 0] == pytest.approx(0, abs=1e-9)
    assert vertical[:, 0] == pytest.approx(1e-3, abs=1e-9) and vertical[:, 1] == pytest.approx(0, abs=1e-9)
    # Positive cant: the left design rail is the higher one, both sit 0.7175 cos(phi) off the centre.
    assert rises[0, 0] == pytest.approx(0.7175 * 0.1 / 1.5) and rises[0, 1] == pytest.approx(-rises[0, 0])
    assert offsets[0, 1] == pytest.approx(0.7175 * np.sqrt(1 - (0.1 / 1.5) ** 2))


def test_plan_only_design_gives_no_vertical_deviation():
    design = _canted_straight()
    plan_only = DesignAlignment(design.horizontal)
    points = np.array([[1020.0, 2000.7, 50.0], [1030.0, 1999.3, 50.0]])
    lateral, vertical = rail_deviations(plan_only, points, points)
    assert np.isfinite(lateral).all() and np.isnan(vertical).all()


def test_points_past_the_profile_or_cant_table_are_not_assessed():
    """A survey running past the end of the design's profile or cant table (a fitted alignment used
    as the design of a longer repeat run) gets NaN there, like points beyond the plan's ends."""
    design = _canted_straight()  # plan 0..250 m
    short_profile = DesignAlignment(design.horizontal, VerticalProfile((PVI(0.0, 50.0), PVI(200.0, 52.0))),
                                    CantTable(np.array([0.0, 150.0]), np.array([0.1, 0.1])))
    s = np.array([20.0, 120.0, 180.0, 240.0])
    points = np.column_stack([*design.horizontal.point_at(s), np.full(4, 51.0)])
    lateral, vertical = rail_deviations(short_profile, points, points)
    # cant defined up to 150 m: the design rail offsets (and so the lateral deviations) stop there
    assert np.isfinite(lateral[:2]).all() and np.isnan(lateral[2:]).all()
    assert np.isfinite(vertical[:2]).all() and np.isnan(vertical[2:]).all()
    assert np.isnan(design_cant_m(short_profile, s)[2:]).all()


def test_reconstruct_track_end_to_end(short_perfect_survey):
    recon = truth_reconstruction(short_perfect_survey)
    pulses = read_sleeper_times(short_perfect_survey / "sleepers.txt")
    result = reconstruct_track(recon.trajectory, recon.trolley, recon.gauge, recon.to_engineering,
                               design=recon.design, pulses=pulses, first_number=0)
    truth, tab = recon.sleepers, result.table
    first = int(truth["index"][np.argmin(np.abs(truth["station"] - tab.station_m[0]))])
    rows = tab.number + first
    assert tab.valid.all() and np.array_equal(tab.detected, truth["detected"][rows].astype(bool))
    lateral, vertical = expected_deviations(truth)
    # Pulse stations carry the detector's timing jitter (mm along the track): no visible effect.
    assert np.abs(tab.lateral_deviation_m - lateral[rows]).max() < 0.1 * MM
    assert np.abs(tab.vertical_deviation_m - vertical[rows]).max() < 0.1 * MM
    assert np.abs(tab.gauge_m - truth["gauge"][rows]).max() < 0.05 * MM
    assert np.abs(tab.cant_m - truth["cant"][rows]).max() < 0.05 * MM


def test_reconstruct_track_without_design_needs_a_start_station(short_perfect_survey):
    recon = truth_reconstruction(short_perfect_survey)
    with pytest.raises(ValueError, match="start station"):
        reconstruct_track(recon.trajectory, recon.trolley, recon.gauge, recon.to_engineering)
    start = float(recon.nav["station_m"][0])
    result = reconstruct_track(recon.trajectory, recon.trolley, recon.gauge, recon.to_engineering,
                               start_station_m=start, fit_line=False)
    tab = result.table
    assert np.isnan(tab.lateral_deviation_m).all() and tab.valid[1:-1].all()
    assert result.fitted is None and result.reference is None
    # Along-path stations: the sections found there are the true ones within a few millimetres.
    truth = recon.track.sections(tab.station_m[tab.valid])
    assert np.abs(tab.centre_enh_m[tab.valid] - truth.centre_enh_m).max() < 5 * MM
    assert np.abs(tab.gauge_m[tab.valid] - truth.gauge_m).max() < 0.05 * MM


def test_reconstruct_track_without_design_measures_against_the_fitted_line(short_perfect_survey):
    """No design: deviations are "measured - best" from the windowed line-type fit. On the error-free
    trajectory they equal the deviations from the true design (measured: 0.03 mm RMS, max 0.24 mm
    lateral, 0.57 mm vertical, against 1 mm RMS irregularities), and the fitted cant the design cant."""
    recon = truth_reconstruction(short_perfect_survey)
    result = reconstruct_track(recon.trajectory, recon.trolley, recon.gauge, recon.to_engineering,
                               start_station_m=float(recon.nav["station_m"][0]))
    tab, truth = result.table, recon.sleepers
    assert result.line_fit_error == "" and result.fitted is not None and tab.valid.all()
    assert [row.element.describe().split()[0] for row in result.fitted.alignment.horizontal.placed_elements] == [
        "Line", "Clothoid", "Arc", "Clothoid", "Line"]
    lateral, vertical = expected_deviations(truth)
    at = [np.column_stack([np.interp(tab.station_m, truth["station"], d[:, i]) for i in range(2)])
          for d in (lateral, vertical)]
    for got, want in ((tab.lateral_deviation_m, at[0]), (tab.vertical_deviation_m, at[1])):
        error = got - want
        assert np.sqrt(np.mean(error**2)) < 0.1 * MM and np.abs(error).max() < 1 * MM
        assert np.sqrt(np.mean(want**2)) > 0.8 * MM
    assert np.abs(tab.design_cant_m - np.interp(tab.station_m, truth["station"], truth["design_cant"])).max() < 0.1 * MM
    assert len(result.reference.windows) >= 2


def reconstruction_between(survey, first_m, last_m):
    """The reconstruction (without a design) of the error-free trajectory between two stations."""
    recon = truth_reconstruction(survey)
    trajectory = recon.trajectory
    keep = (recon.nav["station_m"] > first_m) & (recon.nav["station_m"] < last_m)
    sliced = {f.name: getattr(trajectory, f.name)[keep] for f in fields(trajectory)
              if isinstance(getattr(trajectory, f.name), np.ndarray) and len(getattr(trajectory, f.name)) == len(keep)}
    return reconstruct_track(replace(trajectory, **sliced), recon.trolley, recon.gauge, recon.to_engineering,
                             start_station_m=first_m)


def test_reconstruct_track_reports_a_line_fit_it_cannot_make(short_perfect_survey):
    """A survey too short to be line-fitted: the reconstruction still completes, says why, and
    leaves the deviations empty."""
    result = reconstruction_between(short_perfect_survey, 1400.0, 1450.0)
    assert "at least" in result.line_fit_error and result.fitted is None
    assert np.isnan(result.table.lateral_deviation_m).all() and len(result.table) > 60


def test_a_survey_inside_the_curve_is_fitted_as_its_arc(short_perfect_survey):
    """A run that starts and ends inside the curve (the `short` arc, R 2000 m right) is fitted, not
    refused: one arc of the design's radius."""
    result = reconstruction_between(short_perfect_survey, 1400.0, 1750.0)
    assert result.line_fit_error == "" and result.fitted is not None
    (arc,) = result.fitted.alignment.horizontal.elements
    assert isinstance(arc, Arc) and arc.turn == "right" and abs(arc.radius_m / 2000.0 - 1.0) < 0.002


def test_the_line_fit_leaves_out_the_rows_it_is_told_to(short_perfect_survey):
    """Sleepers where the fusion is not valid are no measurements of the line: a 30 mm excursion
    there does not bend the fit (fitted through, it makes the plan leave the line: refused), and
    their deviations stay empty."""
    recon = truth_reconstruction(short_perfect_survey)
    result = reconstruct_track(recon.trajectory, recon.trolley, recon.gauge, recon.to_engineering,
                               start_station_m=float(recon.nav["station_m"][0]), fit_line=False)
    table = result.table
    bad = np.zeros(len(table), dtype=bool)
    bad[700:760] = True
    shifted = np.where(bad[:, None], [0.03, 0.0, 0.0], 0.0)
    table = replace(table, centre_enh_m=table.centre_enh_m + shifted, left_rail_enh_m=table.left_rail_enh_m + shifted,
                    right_rail_enh_m=table.right_rail_enh_m + shifted)
    dense = {"epochs": result.epochs}
    blind = finished_reconstruction(result.sleepers, table, dense, True)
    told = finished_reconstruction(result.sleepers, table, dense, True, fit_rows=~bad)
    # fitted through them, the plan leaves the line around them: refused, naming where
    assert blind.fitted is None and "does not follow the centreline between" in blind.line_fit_error
    assert told.fitted.horizontal.rms_m < 1.5 * MM
    assert np.isnan(told.table.lateral_deviation_m[bad]).all()
    assert np.isfinite(told.table.lateral_deviation_m[table.valid & ~bad]).all()
