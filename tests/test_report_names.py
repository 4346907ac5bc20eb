"""Display names (insrail.names): every id of every shipped tolerance profile and every sleepers.csv
column has a human name; unknown ids are refused, never shown raw."""

from dataclasses import replace

import numpy as np
import pytest
from report_support import shared_project, stored

from insrail.names import (
    COLUMN_NAMES,
    QUANTITY_NAMES,
    UnknownName,
    channel_name,
    check_name,
    column_name,
    quantity_name,
)
from insrail.project.results import QUALITY_HEADER, check_column
from insrail.track.exceedance import SleeperGeometry, assess, track_quality
from insrail.track.tolerance import load_tolerance_profile, shipped_tolerance_profiles


def _geometry(n: int = 700) -> SleeperGeometry:
    station = 0.625 * np.arange(n)
    zeros = np.zeros((n, 2))
    return SleeperGeometry.from_arrays(station, zeros, zeros, np.full(n, 1.435), np.zeros(n), np.zeros(n))


def _looks_human(text: str) -> bool:
    return bool(text) and "_" not in text and (text[0].isupper() or text[0].isdigit())


@pytest.mark.parametrize("profile_name", shipped_tolerance_profiles())
def test_every_check_and_channel_column_of_every_shipped_profile_has_a_name(profile_name):
    profile = load_tolerance_profile(profile_name)
    names = [check_name(check) for check in profile.checks]
    assert all(_looks_human(name) for name in names), names
    assert len(set(names)) == len(names), f"two checks of {profile_name} share a name: {names}"
    channels = assess(_geometry(), profile).channels
    assert channels
    full = []
    for channel in channels:
        name = column_name(check_column(channel.check, channel.kind, channel.rail, channel.direction), profile.checks)
        assert _looks_human(name.name) and name.unit in ("mm", "‰"), name
        full.append(name.name)
    assert len(set(full)) == len(full), f"two channels of {profile_name} share a name: {full}"


def test_shipped_ids_read_as_a_surveyor_says_them():
    checks = {c.name: c for c in load_tolerance_profile("cn_hsr_ballastless").checks}
    assert check_name(checks["short_wave_30m_5m"]) == "30 m / 5 m short wave"
    assert check_name(checks["long_wave_300m_150m"]) == "300 m / 150 m long wave"
    assert check_name(checks["gauge_change_rate"]) == "Gauge change rate 2.5 m"
    assert channel_name(checks["short_wave_30m_5m"], "left", "lateral") == "30 m / 5 m short wave, left rail, lateral"
    assert channel_name(checks["cross_level"], "track", "") == "Cross level"
    fra = {c.name: c for c in load_tolerance_profile("fra_class_1").checks}
    assert check_name(fra["alignment_62ft"]) == "Alignment 62 ft chord"
    assert check_name(fra["twist_62ft"]) == "Twist 62 ft"
    assert column_name("gauge_mm").with_unit == "Gauge (mm)"
    assert column_name("gauge_change_rate_2_5m_ratio").unit == "‰"


def test_a_user_check_is_named_from_its_definition_not_its_id():
    short = next(c for c in load_tolerance_profile().checks if c.name == "short_wave_30m_5m")
    # a copied profile whose 30 m / 5 m check now has a 40 m chord, and a check with an id of the user's own
    assert check_name(replace(short, chord_m=40.0)) == "40 m / 5 m short wave"
    mine = replace(short, name="my_check_7", chord_m=20.0, pair_m=4.0)
    assert check_name(mine) == "20 m / 4 m differential versine"
    # an id of a shipped check reused for another kind takes the kind's wording
    assert check_name(replace(short, name="gauge")) == "30 m / 5 m differential versine"
    assert column_name("check_my_check_7_right_vertical_mm", [mine]).name == (
        "20 m / 4 m differential versine, right rail, vertical")


def test_every_sleepers_csv_column_has_a_name(tmp_path_factory):
    project = shared_project(tmp_path_factory)
    profile = load_tolerance_profile(project.tolerance_profile)
    columns = stored(project).columns
    for key in ["number", "label", *columns]:
        assert _looks_human(column_name(key, profile.checks).name), key


def test_tqi_channels_and_quality_figures_have_names():
    n = 800
    station = 0.625 * np.arange(n)
    zeros = np.zeros((n, 2))
    geometry = SleeperGeometry.from_arrays(station, zeros, zeros, np.full(n, 1.435), np.zeros(n), np.zeros(n))
    for channel in track_quality(geometry).channels:
        assert _looks_human(quantity_name(channel).name)
    for figure in QUALITY_HEADER[2:]:
        assert _looks_human(quantity_name(figure).name)
    assert all(_looks_human(n.name) for n in (*COLUMN_NAMES.values(), *QUANTITY_NAMES.values()))


def test_unknown_ids_are_refused_not_shown_raw():
    with pytest.raises(UnknownName, match="new_column_mm"):
        column_name("new_column_mm")
    with pytest.raises(UnknownName, match="check_gone_mm"):
        column_name("check_gone_mm", load_tolerance_profile().checks)
    with pytest.raises(UnknownName):
        quantity_name("gauge_mm_typo")


@pytest.mark.parametrize("profile_id", shipped_tolerance_profiles())
def test_every_shipped_profile_has_a_name(profile_id):
    from insrail.names import profile_name

    assert _looks_human(profile_name(load_tolerance_profile(profile_id)))


def test_fasteners_are_named_for_people(tmp_path):
    from insrail.names import fastener_name
    from insrail.track.adjustment import load_fastener_type

    assert [fastener_name(load_fastener_type(name)) for name in ("wj7", "wj8")] == ["WJ-7", "WJ-8"]
    assert fastener_name(None, "wj8") == "WJ-8"  # the id the results recorded, the file no longer readable
    own = tmp_path / "vossloh_300.toml"
    own.write_text('description = "Vossloh 300: lateral -4..+4 mm"\nstep_mm = 1\nlateral_min_mm = -4\n'
                   "lateral_max_mm = 4\nvertical_min_mm = -4\nvertical_max_mm = 26\n", encoding="utf-8")
    assert fastener_name(load_fastener_type(own)) == "Vossloh 300"
    assert fastener_name(None, "vossloh_300") == "vossloh 300"
