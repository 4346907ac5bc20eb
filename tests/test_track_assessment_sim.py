"""Issue 6 on the simulator: irregularities from the reconstructed truth coordinates equal those
from the injected offsets, and the adjustment computed on them clears every check it can."""

import numpy as np
import pytest

from insrail.track.adjustment import load_fastener_type, optimise_adjustment
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.tolerance import load_tolerance_profile
from track_truth import expected_deviations, truth_sleeper_table

MM = 1e-3


@pytest.fixture(scope="module")
def geometries(short_perfect_survey):
    recon, table = truth_sleeper_table(short_perfect_survey)
    truth = recon.sleepers
    from_coordinates = SleeperGeometry.from_arrays(
        table.station_m, table.lateral_deviation_m, table.vertical_deviation_m, table.gauge_m, table.cant_m,
        table.design_cant_m, sleeper_number=table.number)
    lateral, vertical = expected_deviations(truth)
    from_offsets = SleeperGeometry.from_arrays(
        truth["station"], lateral, vertical, truth["gauge"], truth["cant"], truth["design_cant"],
        sleeper_number=truth["index"].astype(int))
    return from_coordinates, from_offsets


def test_irregularities_from_coordinates_equal_those_from_injected_offsets(geometries):
    profile = load_tolerance_profile()
    a, b = (assess(g, profile) for g in geometries)
    compared = 0
    for ca, cb in zip(a.channels, b.channels):
        assert (ca.check, ca.rail, ca.direction) == (cb.check, cb.rail, cb.direction)
        both = np.isfinite(ca.values) & np.isfinite(cb.values)
        assert both.sum() > 0.5 * len(ca.values)
        scale = 1.0 if ca.kind.endswith("rate") else MM  # rates are ratios, the rest lengths
        # A sleeper's value is its worst signed check; where the worst positive and negative pairs
        # are equally large (1.720 vs -1.718 mm) the sign may flip, so compare magnitudes.
        assert np.abs(np.abs(ca.values[both]) - np.abs(cb.values[both])).max() < 0.05 * scale, ca.check
        compared += 1
    assert compared >= 10
    # Same exceedances, at the same sleepers.
    assert [(e.check, e.rail, e.direction, e.first_sleeper) for e in a.exceedances] == \
           [(e.check, e.rail, e.direction, e.first_sleeper) for e in b.exceedances]


def test_adjustment_clears_every_chord_check_except_flagged_sleepers(geometries):
    geometry, _ = geometries
    profile = load_tolerance_profile()
    adjustment = optimise_adjustment(geometry, profile, load_fastener_type("wj8"))
    after = assess(adjustment.apply(geometry), profile)
    chord_checks = {c.name for c in profile.checks if c.kind in ("differential_versine", "versine")}
    remaining = [e for e in after.exceedances if e.check in chord_checks]
    flagged = set(np.flatnonzero(np.any(adjustment.unresolved_lateral | adjustment.unresolved_vertical, axis=1)))
    for e in remaining:
        assert set(range(e.first_index, e.last_index + 1)) & flagged, e


def test_injected_bumps_above_the_limit_are_reported_at_their_chainage(short_perfect_survey, geometries):
    from insrail.sim.scenario import preset

    geometry, _ = geometries
    result = assess(geometry, load_tolerance_profile())
    spec = preset("short").irregularities
    station = geometry.station_m
    checked = 0
    for direction, bumps in (("lateral", spec.lateral_bumps), ("vertical", spec.vertical_bumps)):
        for bump in bumps:
            if abs(bump.amplitude_m) <= 2.2e-3:  # clear of the 2 mm limit, so the 1 mm background cannot decide
                continue
            peak = int(np.argmin(np.abs(station - (bump.start_station_m + bump.length_m / 2))))
            # The 30 m/5 m value goes to the pair's first point (thesis eq. 2.2), so a bump shows at
            # its own sleeper (as check point) and 8 sleepers before it (as the 5 m reckoning point).
            hits = [e for e in result.exceedances
                    if e.check == "short_wave_30m_5m" and e.direction == direction
                    and any(e.first_index - 1 <= k <= e.last_index + 1 for k in (peak, peak - 8))]
            assert {e.rail for e in hits} == {"left", "right"}, (direction, bump)
            checked += 1
    assert checked >= 3
