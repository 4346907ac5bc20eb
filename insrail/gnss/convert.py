"""Receiver binary logs to RINEX 3.04 with RTKLIB's converter (convrnx, as rtkconv/convbin).

The format comes from the file extension (RTKLIB's own conventions) or is given by
name. Output: ``<out_dir>/<log stem>.obs`` (all systems, all observation types and
frequencies) and ``<log stem>.nav`` (mixed navigation) when the log holds ephemerides.
RTKLIB reads the log and writes the RINEX in a private temporary folder under names
insrail makes (:mod:`insrail.gnss.staging`); the results are moved to ``out_dir`` only
when the conversion succeeded and produced observation epochs; a log RTKLIB cannot
decode is an InputError naming it.
"""

from __future__ import annotations

from pathlib import Path

from insrail.gnss.rinex import read_obs_info
from insrail.gnss.staging import install_output, rtklib_workdir, stage_file
from insrail.io.errors import InputError

# format name -> (pyrtklib STRFMT constant name, file extensions)
RECEIVER_FORMATS = {
    "ubx": ("STRFMT_UBX", (".ubx",)),
    "rtcm3": ("STRFMT_RTCM3", (".rtcm3", ".rtcm", ".rtc3")),
    "rtcm2": ("STRFMT_RTCM2", (".rtcm2",)),
    "novatel": ("STRFMT_OEM4", (".gps", ".oem")),
    "septentrio": ("STRFMT_SEPT", (".sbf",)),
    "binex": ("STRFMT_BINEX", (".bnx", ".binex")),
    "javad": ("STRFMT_JAVAD", (".jps",)),
    "nvs": ("STRFMT_NVS", (".nvs",)),
    "skytraq": ("STRFMT_STQ", (".stq",)),
    "trimble-rt17": ("STRFMT_RT17", (".rt17",)),
    "hemisphere": ("STRFMT_CRES", (".bin",)),
}
RINEX_VERSION = 304  # RTKLIB writes RINEX 3.04
_OUTPUT_SLOTS = 9  # RTKLIB ofile[]: obs, nav, gnav, hnav, qnav, lnav, cnav, inav, sbas
_MASK_ROWS, _MASK_COLUMNS = 7, 64


def format_from_extension(path: Path) -> str:
    suffix = path.suffix.lower()
    for name, (_, extensions) in RECEIVER_FORMATS.items():
        if suffix in extensions:
            return name
    raise InputError(path, None, "cannot tell the receiver format from the extension {suffix!r}: give the "
                     "format, one of {receiver_formats}", fields={"suffix": suffix, "receiver_formats": list(RECEIVER_FORMATS)})


def _rnxopt():
    import pyrtklib

    opt = pyrtklib.rnxopt_t()
    opt.rnxver = RINEX_VERSION
    opt.navsys = pyrtklib.SYS_ALL
    opt.obstype = pyrtklib.OBSTYPE_ALL
    opt.freqtype = pyrtklib.FREQTYPE_ALL
    opt.ttol = 0.005  # s, RTKLIB's default tolerance for epoch time tags
    mask = opt.mask  # every signal of every system: '1' = convert
    for row in range(_MASK_ROWS):
        for column in range(_MASK_COLUMNS - 1):
            mask[row, column] = "1"
    return opt


def _has_records(path: Path) -> bool:
    if not path.exists():  # RTKLIB deletes outputs it wrote nothing to
        return False
    text = path.read_text(encoding="ascii", errors="replace")
    _, _, body = text.partition("END OF HEADER")
    return bool(body.strip())


def convert_to_rinex(log_path: str | Path, out_dir: str | Path, format: str | None = None) -> tuple[Path, ...]:
    """Convert a receiver log to RINEX; returns (obs file, nav file if ephemerides were decoded)."""
    import pyrtklib

    log_path, out_dir = Path(log_path), Path(out_dir)
    if not log_path.is_file():
        raise InputError(log_path, None, "file not found")
    if not out_dir.is_dir():
        raise InputError(out_dir, None, "output folder does not exist")
    name = format.lower() if format else format_from_extension(log_path)
    if name not in RECEIVER_FORMATS:
        raise InputError(log_path, None, "unknown receiver format {format!r}: expected one of "
                         "{receiver_formats}", fields={"format": format, "receiver_formats": list(RECEIVER_FORMATS)})
    targets = (out_dir / f"{log_path.stem}.obs", out_dir / f"{log_path.stem}.nav")
    with rtklib_workdir() as workdir:
        log = stage_file(log_path, workdir, "receiver", RECEIVER_FORMATS[name][1][0])
        produced = (workdir / "converted.obs", workdir / "converted.nav")
        slots = [str(p) for p in produced] + [""] * (_OUTPUT_SLOTS - len(produced))
        status = pyrtklib.convrnx(getattr(pyrtklib, RECEIVER_FORMATS[name][0]), _rnxopt(), str(log), slots)
        if status != 1 or not _has_records(produced[0]):
            raise InputError(log_path, None, "unreadable receiver log: RTKLIB decoded no observations as "
                             "{name} (check the format)", fields={"name": name})
        read_obs_info(produced[0])  # the RINEX written must be one insrail reads back
        written = [targets[0]]
        install_output(produced[0], targets[0])
        if _has_records(produced[1]):
            install_output(produced[1], targets[1])
            written.append(targets[1])
        return tuple(written)
