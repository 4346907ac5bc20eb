"""The recorded settings' profile digests say what a profile holds, not where its file was: results processed
by an insrail installed in another folder (its built-in profiles elsewhere) are reported, not refused."""

import shutil

from insrail.project.run_settings import RecordedSettings, _contents_digest, _legacy_digest
from insrail.track.tolerance import load_tolerance_profile, profile_path


def _copied(tmp_path, name, edit=None):
    copy = tmp_path / f"{name}.toml"
    shutil.copyfile(profile_path(name), copy)
    if edit:
        copy.write_text(edit(copy.read_text(encoding="utf-8")), encoding="utf-8")
    return load_tolerance_profile(copy)


def test_a_profile_read_from_another_folder_has_the_digest_of_its_contents(tmp_path):
    shipped = load_tolerance_profile("cn_hsr_ballastless")
    elsewhere = _copied(tmp_path, "cn_hsr_ballastless")
    assert shipped.path != elsewhere.path
    assert _contents_digest(shipped) == _contents_digest(elsewhere)
    recorded = RecordedSettings({"tolerance_profile": {"name": shipped.name, "digest": _contents_digest(shipped)}})
    assert recorded.same_tolerance_profile(elsewhere)


def test_a_profile_with_other_contents_is_not_the_same(tmp_path):
    shipped = load_tolerance_profile("cn_hsr_ballastless")
    edited = _copied(tmp_path, "cn_hsr_ballastless", lambda text: text.replace(shipped.description, "edited", 1))
    assert edited.description == "edited"
    recorded = RecordedSettings({"tolerance_profile": {"name": shipped.name, "digest": _contents_digest(shipped)}})
    assert not recorded.same_tolerance_profile(edited)


def test_results_recorded_with_the_old_digest_still_match_the_same_file():
    shipped = load_tolerance_profile("cn_hsr_ballastless")
    assert _legacy_digest(shipped) != _contents_digest(shipped)
    recorded = RecordedSettings({"tolerance_profile": {"name": shipped.name, "digest": _legacy_digest(shipped)}})
    assert recorded.same_tolerance_profile(shipped)
