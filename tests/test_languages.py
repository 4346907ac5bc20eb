"""Every text a user reads exists in every language (insrail.names: the reports' tables; the .ts: the
desktop application), and a Chinese report carries the field's standard terms and no English words."""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

import insrail
from insrail import names
from insrail.names_zh import ZH_CN

PACKAGE = Path(insrail.__file__).parent


def source_nodes(path: Path) -> tuple[ast.AST, ...]:
    """Every node of the module's syntax tree, in ast.walk's order."""
    return _nodes_of_source(path.read_text(encoding="utf-8"))


@functools.cache
def _nodes_of_source(source: str) -> tuple[ast.AST, ...]:
    # parsed once per worker: six walks read the whole package (the trees are only read)
    return tuple(ast.walk(ast.parse(source)))


def translated_literals(folder: Path, function: str = "t") -> dict[str, str]:
    """Every string literal passed to ``function(...)`` under ``folder``: text -> where (file:line)."""
    found = {}
    for path in sorted(folder.rglob("*.py")):
        for node in source_nodes(path):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == function
                    and node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)):
                found.setdefault(node.args[0].value, f"{path.relative_to(PACKAGE.parent)}:{node.lineno}")
    return found


def table_texts() -> set[str]:
    """The English wording of every display-name table (translated where it is looked up)."""
    from insrail.project.model import HEIGHT_MODELS
    from insrail.project.run_settings import NOT_RECORDED
    from insrail.track.adjustment import REASONS, STRATEGIES
    from insrail.track.events import KIND_NAMES as EVENT_NAMES
    from insrail.report.content import SEVERITIES, SEVERITY_RULE, ADJUSTMENT_GROUP, GAUGE_LEVEL_GROUP, \
        OTHER_CHECKS_GROUP, PARAMETER_GROUP, SLEEPER_GROUP
    from insrail.report.labels import SIGNS
    from insrail.report.excel import CREW_TITLES, SHEETS, TAMPING_SHEET, TAMPING_TITLES
    from insrail.report.content import RELATIVE_SURVEY_TEXT, REDESIGN_BOUNDS, TAMPING_MARKS
    from insrail.project.redesign import TAMPING_AMOUNTS, TAMPING_CONVENTION
    from insrail.quality.tables import EXCEEDS, ROWS as FIGURE_ROWS
    from insrail.io.events import EVENT_KINDS
    from insrail.report.pdf import ADJUSTMENT_TITLES

    texts = {n.name for n in names.COLUMN_NAMES.values()} | {n.name for n in names.QUANTITY_NAMES.values()}
    texts |= set(names.KIND_NAMES.values()) | {wording for _, wording in names.CHECK_NAMES.values()}
    texts |= set(names.RAIL_NAMES.values()) | set(names.DIRECTION_NAMES.values()) | set(names.SETTING_NAMES.values())
    texts |= {f"{rail}, {direction}" for rail in names.RAIL_NAMES.values() for direction in names.DIRECTION_NAMES.values()
              if rail and direction}  # a rail's channel in one word where the language has one (左轨向)
    texts |= {text for choices in names.CHOICE_NAMES.values() for text in choices.values()}
    texts |= set(STRATEGIES.values()) | set(EVENT_NAMES.values()) | {name for name, _ in SEVERITIES}
    texts |= set(REASONS.values()) | set(HEIGHT_MODELS) | {NOT_RECORDED, "none (ellipsoidal heights)"}
    texts |= {SEVERITY_RULE, SIGNS, ADJUSTMENT_GROUP, GAUGE_LEVEL_GROUP, OTHER_CHECKS_GROUP, PARAMETER_GROUP,
              SLEEPER_GROUP, *CREW_TITLES, *ADJUSTMENT_TITLES, *(name for name, _, _ in SHEETS)}
    texts |= {TAMPING_SHEET[0], *TAMPING_TITLES, *TAMPING_MARKS.values(), *REDESIGN_BOUNDS, TAMPING_AMOUNTS,
              TAMPING_CONVENTION, RELATIVE_SURVEY_TEXT}
    texts |= {label for label, _ in FIGURE_ROWS.values()} | {EXCEEDS} | set(EVENT_KINDS.values())
    return texts - {""}


def shipped_resource_texts() -> set[str]:
    """The shipped tolerance profiles', fastener types' and IMU profiles' descriptions and fastener parts."""
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.track.adjustment import load_fastener_type
    from insrail.track.tolerance import load_tolerance_profile, shipped_tolerance_profiles
    from insrail.resources import resource

    texts = set()
    for name in shipped_tolerance_profiles():
        profile = load_tolerance_profile(name)
        texts |= {profile.description.split(":")[0].strip(), profile.source}
    for path in sorted(resource("fastener_types").glob("*.toml")):
        fastener = load_fastener_type(path.stem)
        texts.add(fastener.description)
        for table in fastener.parts.values():
            texts |= {table.note} | {position.name for position in table.positions}
    for path in sorted(resource("imu_profiles").glob("*.toml")):
        texts.add(load_imu_profile(path.stem).description)
    return texts - {""}


def test_every_report_text_has_its_chinese():
    literals = translated_literals(PACKAGE)
    missing = {text: where for text, where in literals.items() if text not in ZH_CN}
    missing.update({text: "a display-name table" for text in table_texts() | shipped_resource_texts()
                    if text not in ZH_CN})
    assert not missing, "no Chinese in insrail/names_zh.py for:\n" + "\n".join(
        f"  {where}: {text!r}" for text, where in sorted(missing.items(), key=lambda item: item[1]))


def test_chinese_texts_keep_the_fields_of_their_english():
    """A template's fields ({count}, {chord_m:g}) are the same in both languages: a translation that drops one
    would print a wrong or missing number."""
    import string

    def fields(text):
        return sorted(f"{name}:{spec}" for _, name, spec, _ in string.Formatter().parse(text) if name is not None)

    wrong = {en: zh for en, zh in ZH_CN.items() if fields(en) != fields(zh)}
    assert not wrong, wrong
    assert all(zh.strip() for zh in ZH_CN.values())


def test_no_function_hides_the_translation_function_under_a_variable_of_its_name():
    """A local variable ``t`` (a time) in a function that calls ``t("...")`` makes the call fail at run time
    (the GNSS residual plot did): every module calling t() keeps the name free in its function scopes."""
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for function in (n for n in source_nodes(path) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))):
            body = [n for statement in function.body for n in ast.walk(statement)]
            calls = any(isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "t" for n in body)
            binds = [n.lineno for n in body if isinstance(n, ast.Name) and n.id == "t" and isinstance(n.ctx, ast.Store)]
            binds += [function.lineno for a in function.args.args if a.arg == "t"]
            if calls and binds:
                offenders.append(f"{path.relative_to(PACKAGE.parent)}:{binds[0]}")
    assert not offenders, offenders


def test_the_embedded_font_has_every_character_of_the_chinese_texts():
    """The PDF sets Chinese in the shipped CJK subset: a character of a translation outside it prints as a box
    (regenerate the subset with installer/cjk_font_subset.py when one is missing)."""
    from reportlab.pdfbase.ttfonts import TTFontFile

    from insrail.report.fonts import CJK_FONT_FILE
    from insrail.resources import resource

    shown = set(TTFontFile(str(resource(*CJK_FONT_FILE))).charToGlyph)
    missing = {c for text in ZH_CN.values() for c in text if ord(c) > 0x7F and ord(c) not in shown}
    assert not missing, "".join(sorted(missing))


def _literals(node) -> list[str] | None:
    """The string literals a template argument can take (a literal, or either side of ``a if c else b``);
    None for anything else (an f-string, a concatenation, a variable)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.IfExp):
        body, orelse = _literals(node.body), _literals(node.orelse)
        return None if body is None or orelse is None else body + orelse
    return None


def notice_templates() -> tuple[dict[str, str], list[str]]:
    """Every template of a notice (insrail.notices): the literal message of ``Notice(...)`` (and its stage) and the
    literal template of ``Phrase(...)``: text -> where; and where a notice's message is an f-string or a
    concatenation (an English sentence no table can translate). A message or template given by a variable or a
    call is a Phrase made elsewhere (walked there) or a word of :func:`phrase_vocabulary`."""
    found, sentences = {}, []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in source_nodes(path):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("Notice", "Phrase")):
                continue
            where = f"{path.relative_to(PACKAGE.parent)}:{node.lineno}"
            arguments = list(node.args) + [k.value for k in node.keywords if k.arg in ("message", "template")]
            if node.func.id == "Notice":
                stage, arguments = _literals(node.args[0]) if node.args else None, arguments[1:]
                for text in stage or ():
                    found.setdefault(text, where)
            if not arguments:
                continue
            texts = _literals(arguments[0])
            if texts is None and isinstance(arguments[0], (ast.JoinedStr, ast.BinOp)):
                sentences.append(where)
            for text in texts or ():
                found.setdefault(text, where)
    return {text: where for text, where in found.items() if text}, sentences


def phrase_vocabulary() -> set[str]:
    """The words a Phrase takes from a variable: the aiding sources, the states a filter reset widens, the IMU's
    axes of mounting and their reasons, an IMU outlier's reasons, a check's directions, the recorded settings."""
    from insrail.nav import measurements
    from insrail.nav.fusion import RESET_STATES
    from insrail.nav.imu_screening import OUTLIER_REASONS
    from insrail.nav.mounting import AXES
    from insrail.project.run_settings import _DESCRIBED as RECORDED_SETTINGS

    sources = {cls.name for cls in vars(measurements).values()
               if isinstance(cls, type) and isinstance(getattr(cls, "name", None), str)}
    return (sources | {label for label, _, _ in RESET_STATES} | set(AXES) | set(OUTLIER_REASONS)
            | set(names.DIRECTION_NAMES) | {"{stage}: {message}"} | {what for _, what, _ in RECORDED_SETTINGS}) - {""}


def test_every_notice_is_a_template_with_its_chinese():
    """A notice reaches the PDF and the workbook: its message is a template (never an f-string: its numbers and
    names go in ``fields``) and every template, stage and word of it has its Chinese (insrail/notices.py)."""
    templates, sentences = notice_templates()
    assert not sentences, "notices written as f-strings or concatenations (make them templates):\n" + "\n".join(sentences)
    assert len(templates) > 80  # the walk finds them (the package has over a hundred)
    missing = {text: where for text, where in templates.items() if text not in ZH_CN}
    missing |= {text: "a word of a phrase (test_languages.phrase_vocabulary)" for text in phrase_vocabulary()
                if text not in ZH_CN}
    assert not missing, "no Chinese in insrail/names_zh.py for:\n" + "\n".join(
        f"  {where}: {text!r}" for text, where in sorted(missing.items(), key=lambda item: item[1]))


#: The readers' helpers that raise an InputError with the message (and fields) they are given: a call's first
#: string argument is a template like InputError's own.
_ERROR_HELPERS = {"fail": None, "error": "insrail/track/landxml.py"}
#: Where an InputError's message is another error's English text (a geometry core's DesignError, a parser's
#: ValueError, a list of problems joined): said in English in every language until those speak in templates.
ENGLISH_MESSAGES: set[str] = set()


def input_error_templates() -> tuple[dict[str, str], list[str], set[str]]:
    """Every template of an ``InputError`` (insrail/io/errors.py) written in the package: the literal message of
    ``InputError(...)``, ``LandXMLError(...)`` and of the readers' helpers that raise one (text -> where); where a
    message is an f-string or a concatenation (an English sentence no table can translate); and the files where a
    message is another text's English (``str(error)``, ``"; ".join(...)``)."""
    found, sentences, english = {}, [], set()
    for path in sorted(PACKAGE.rglob("*.py")):
        relative = str(path.relative_to(PACKAGE.parent))
        for node in source_nodes(path):
            if not isinstance(node, ast.Call):
                continue
            name = node.func.id if isinstance(node.func, ast.Name) else getattr(node.func, "attr", None)
            message = next((k.value for k in node.keywords if k.arg == "message"), None)
            if name in ("InputError", "LandXMLError", "DesignError"):
                index = 3 if name == "LandXMLError" else 2  # a DesignError's: part, index, message
                message = node.args[index] if len(node.args) > index else message
            elif name in _ERROR_HELPERS and _ERROR_HELPERS[name] in (None, relative):
                message = next((a for a in node.args if isinstance(a, (ast.Constant, ast.JoinedStr, ast.IfExp, ast.BinOp))
                                and not (isinstance(a, ast.Constant) and not isinstance(a.value, str))), message)
            else:
                continue
            if message is None:
                continue
            where = f"{relative}:{node.lineno}"
            texts = _literals(message)
            if texts is None and isinstance(message, (ast.JoinedStr, ast.BinOp)):
                sentences.append(where)
            elif texts is None and isinstance(message, ast.Call) and (
                    (isinstance(message.func, ast.Name) and message.func.id == "str")
                    or (isinstance(message.func, ast.Attribute) and message.func.attr == "join")):
                english.add(relative)
            for text in texts or ():
                found.setdefault(text, where)
    return {text: where for text, where in found.items() if text}, sentences, english


def test_every_input_error_is_a_template_with_its_chinese():
    """A reader's error reaches the desktop application, said in its language (InputError.said): its message is a
    template (file and key names, numbers in ``fields``) with its Chinese; the files that still pass another text's
    English are listed (ENGLISH_MESSAGES), so the gap is seen and only shrinks."""
    from insrail.io.errors import _PLACES

    templates, sentences, english = input_error_templates()
    assert not sentences, "InputError messages written as f-strings or concatenations (make them templates):\n" + \
        "\n".join(sentences)
    assert len(templates) > 150  # the walk finds them (the package has over two hundred)
    missing = {text: where for text, where in templates.items() if text not in ZH_CN}
    missing |= {text: "insrail/io/errors.py" for text in
                ("{file}: {message}", "1 problem:", "{count} problems:", *_PLACES.values()) if text not in ZH_CN}
    assert not missing, "no Chinese in insrail/names_zh.py for:\n" + "\n".join(
        f"  {where}: {text!r}" for text, where in sorted(missing.items(), key=lambda item: item[1]))
    assert english <= ENGLISH_MESSAGES, f"new InputErrors passing English text: {sorted(english - ENGLISH_MESSAGES)}"
    assert english == ENGLISH_MESSAGES, f"translated now, strike from ENGLISH_MESSAGES: {sorted(ENGLISH_MESSAGES - english)}"


def test_an_input_error_is_said_in_the_language_in_use():
    """The English stays what the CLI and the tests read; the Chinese keeps the file name and the values verbatim."""
    from insrail.io.errors import InputError, ManifestError
    from insrail.notices import Phrase

    error = InputError("imu.txt", 12, "expected {wanted} columns, found {count}", fields={"wanted": 7, "count": 6})
    assert str(error) == "imu.txt, line 12: expected 7 columns, found 6"
    assert error.message == "expected 7 columns, found 6"
    with names.in_language("zh-CN"):
        said = error.said()
    assert said.startswith("imu.txt，第 12 行：") and "7" in said and "6" in said and "expected" not in said
    manifest = ManifestError("survey.toml", [Phrase("{key}.path: file not found: {path}",
                                                    {"key": "files.gnss", "path": "gnss.pos"})])
    assert str(manifest) == "survey.toml: 1 problem:\n  files.gnss.path: file not found: gnss.pos"
    assert manifest.problems == ("files.gnss.path: file not found: gnss.pos",)
    with names.in_language("zh-CN"):
        said = manifest.said()
    assert "files.gnss.path" in said and "gnss.pos" in said and "file not found" not in said


def test_every_template_is_given_the_fields_it_names():
    """A template written with its fields in one call (``InputError(..., "... {count}", fields={"count": n})``,
    ``Phrase("... {count}", {"count": n})``, a notice's): a field named but not given would turn a reader's error
    (or a notice) into a KeyError, where it is raised."""
    import string

    checked, wrong = 0, []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in source_nodes(path):
            if not isinstance(node, ast.Call):
                continue
            name = node.func.id if isinstance(node.func, ast.Name) else getattr(node.func, "attr", None)
            if name not in ("InputError", "LandXMLError", "DesignError", "fail", "error", "Phrase", "Notice"):
                continue
            arguments = node.args[1:] if name == "Notice" else node.args  # a notice's first is its stage
            template = next((a.value for a in arguments if isinstance(a, ast.Constant) and isinstance(a.value, str)), None)
            fields = next((k.value for k in node.keywords if k.arg == "fields"), None)
            if name == "Phrase" and fields is None and len(node.args) > 1:
                fields = node.args[1]
            if template is None or not isinstance(fields, ast.Dict) or any(key is None for key in fields.keys):
                continue
            named = {field for _, field, _, _ in string.Formatter().parse(template) if field}
            checked += 1
            if named != {key.value for key in fields.keys}:
                wrong.append(f"{path.relative_to(PACKAGE.parent)}:{node.lineno}: {sorted(named)}")
    assert checked > 200
    assert not wrong, wrong


#: the names a progress callback goes by where it is called (``insrail.progress``), besides ``..._progress`` and
#: ``..._step`` (a sub-step's: ``imu_step``)
PROGRESS_CALLBACKS = {"progress", "step", "report", "bar", "forward_progress"}


def progress_messages(folder: Path = PACKAGE) -> tuple[dict[str, str], list[str]]:
    """Every literal message of a progress call ``progress(fraction, "message")`` under ``folder``: text -> where;
    and where a message is an f-string or a concatenation (English the GUI's log cannot say in its language). A
    message that is a ``Phrase(...)`` is walked by :func:`notice_templates`; one given by a variable is a Phrase
    made elsewhere."""
    found, sentences = {}, []
    for path in sorted(folder.rglob("*.py")):
        for node in source_nodes(path):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and len(node.args) == 2
                    and (node.func.id in PROGRESS_CALLBACKS or node.func.id.endswith(("_progress", "_step")))):
                continue
            where = f"{path.relative_to(folder.parent)}:{node.lineno}"
            message = node.args[1]
            texts = _literals(message)
            if texts is None and isinstance(message, (ast.JoinedStr, ast.BinOp)):
                sentences.append(where)
            for text in texts or ():
                found.setdefault(text, where)
    return {text: where for text, where in found.items() if text}, sentences


def test_every_progress_message_is_a_template_with_its_chinese():
    """The GUI's log and status bar show the core's progress in the window's language, the CLI's bar in English:
    a progress message is a literal or a Phrase (never an f-string) and has its Chinese."""
    messages, sentences = progress_messages()
    assert not sentences, "progress messages written as f-strings or concatenations (make them Phrases):\n" + "\n".join(
        sentences)
    assert len(messages) > 40  # the walk finds them (the package has over fifty)
    missing = {text: where for text, where in messages.items() if text not in ZH_CN}
    assert not missing, "no Chinese in insrail/names_zh.py for:\n" + "\n".join(
        f"  {where}: {text!r}" for text, where in sorted(missing.items(), key=lambda item: item[1]))


def test_the_walks_find_an_untranslated_text(tmp_path):
    """The walks above can fail: a module with an f-string progress message, an untranslated literal one and an
    f-string notice is found out."""
    module = tmp_path / "insrail_like" / "stage.py"
    module.parent.mkdir()
    module.write_text('def run(progress, step, name):\n'
                      '    progress(0.5, f"reading {name}")\n'
                      '    step(1.0, "an untranslated step")\n', encoding="utf-8")
    messages, sentences = progress_messages(module.parent)
    assert sentences == ["insrail_like/stage.py:2"]
    assert [text for text in messages if text not in ZH_CN] == ["an untranslated step"]


def test_the_cores_errors_reach_a_reader_in_the_language_in_use():
    """A design element's own check (the geometry core's DesignError), a missing lever arm and a missing IMU
    profile: English on the CLI as before, the user's language in the window, names and values verbatim."""
    from insrail.io.errors import InputError, reason_of, said
    from insrail.io.survey import TrolleyGeometry, track_lever_arm_problems
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.notices import one_after_another
    from insrail.track.alignment import Arc

    with pytest.raises(ValueError) as raised:
        Arc(100.0, -5.0, "left")
    error = InputError("design.csv", 7, reason_of(raised.value))
    assert str(error) == "design.csv, line 7: Arc: radius must be a positive finite number of metres, got -5.0"
    with names.in_language("zh-CN"):
        assert error.said().startswith("design.csv，第 7 行：圆曲线") and "-5.0" in error.said()
    problems = track_lever_arm_problems(TrolleyGeometry(), {"imu", "sleepers"})
    error = InputError("project.toml", None, one_after_another(problems))
    assert str(error).count("; trolley.") == 1 and "needs it because files.sleepers is given" in str(error)
    with names.in_language("zh-CN"):
        assert "trolley.imu_to_sleeper_detector_m：缺失" in error.said() and "because" not in error.said()
    with pytest.raises(ValueError) as raised:
        load_imu_profile("no-such-profile")
    assert str(raised.value).startswith("IMU profile not found: no-such-profile (shipped profiles: ")
    with names.in_language("zh-CN"):
        assert said(raised.value).startswith("未找到 IMU 配置文件：no-such-profile")
