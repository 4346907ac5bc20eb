"""GPS time: calendar dates, Unix-style stamps, UTC leap seconds, week and seconds of week.

All functions are vectorised. "GPS seconds" below means seconds since the GPS epoch
1980-01-06 00:00:00 GPST, on the GPST scale (no leap seconds). A time series is
returned as (week of its first stamp, seconds of that week): a recording that runs
past the end of the week keeps counting beyond 604800 s instead of wrapping, so the
time stays monotonic.
"""

from __future__ import annotations

import numpy as np

SECONDS_PER_WEEK = 604_800
SECONDS_PER_DAY = 86_400
GPS_EPOCH_UNIX_S = 315_964_800
"""1980-01-06T00:00:00 expressed as seconds since 1970-01-01 (calendar arithmetic, no leap seconds)."""

# UTC date from which GPST - UTC takes the given value [s] (IERS Bulletin C; last change 2017-01-01).
_LEAP_SECOND_STEPS = (
    ((1981, 7, 1), 1), ((1982, 7, 1), 2), ((1983, 7, 1), 3), ((1985, 7, 1), 4),
    ((1988, 1, 1), 5), ((1990, 1, 1), 6), ((1991, 1, 1), 7), ((1992, 7, 1), 8),
    ((1993, 7, 1), 9), ((1994, 7, 1), 10), ((1996, 1, 1), 11), ((1997, 7, 1), 12),
    ((1999, 1, 1), 13), ((2006, 1, 1), 14), ((2009, 1, 1), 15), ((2012, 7, 1), 16),
    ((2015, 7, 1), 17), ((2017, 1, 1), 18),
)


def days_since_gps_epoch(year, month, day) -> np.ndarray:
    """Whole days from 1980-01-06 to the given calendar dates (proleptic Gregorian)."""
    year, month, day = (np.asarray(a, dtype=np.int64) for a in (year, month, day))
    months = (year - 1970) * 12 + (month - 1)
    dates = months.astype("datetime64[M]").astype("datetime64[D]") + (day - 1)
    return (dates - np.datetime64("1980-01-06", "D")).astype(np.int64)


def calendar_to_gps_seconds(year, month, day, hour, minute, second) -> np.ndarray:
    """Seconds since the GPS epoch of calendar times, read on the same scale as the epoch."""
    days = days_since_gps_epoch(year, month, day)
    return (days * SECONDS_PER_DAY + np.asarray(hour, dtype=np.float64) * 3600.0
            + np.asarray(minute, dtype=np.float64) * 60.0 + np.asarray(second, dtype=np.float64))


_LEAP_STEP_UTC_S = calendar_to_gps_seconds(*np.array([d for d, _ in _LEAP_SECOND_STEPS]).T, 0, 0, 0)
_LEAP_STEP_VALUE_S = np.array([v for _, v in _LEAP_SECOND_STEPS], dtype=np.float64)


def gpst_minus_utc(utc_seconds) -> np.ndarray:
    """GPST - UTC [s] at UTC instants given as calendar seconds since 1980-01-06 UTC."""
    index = np.searchsorted(_LEAP_STEP_UTC_S, np.asarray(utc_seconds, dtype=np.float64), side="right")
    return np.concatenate(([0.0], _LEAP_STEP_VALUE_S))[index]


def utc_to_gps_seconds(utc_seconds) -> np.ndarray:
    """GPS seconds of UTC calendar seconds (since 1980-01-06 UTC), adding the leap seconds."""
    utc_seconds = np.asarray(utc_seconds, dtype=np.float64)
    return utc_seconds + gpst_minus_utc(utc_seconds)


def unix_gpst_to_gps_seconds(unix_s) -> np.ndarray:
    """GPS seconds of stamps counted like Unix time but on the GPST scale.

    Loggers that convert GPST calendar time with a Unix-time routine produce these
    (e.g. the rtklibexplorer/GNSS_IMU files): no leap seconds are involved.
    """
    return np.asarray(unix_s, dtype=np.float64) - GPS_EPOCH_UNIX_S


def week_and_seconds(gps_seconds) -> tuple[int, np.ndarray]:
    """(week of the first stamp, seconds of that week) of a series of GPS seconds."""
    gps_seconds = np.asarray(gps_seconds, dtype=np.float64)
    week = int(gps_seconds.flat[0] // SECONDS_PER_WEEK)
    return week, gps_seconds - week * SECONDS_PER_WEEK


def seconds_to_week_tow(gps_week: int, seconds_of_week) -> tuple[np.ndarray, np.ndarray]:
    """Split seconds counted from the start of ``gps_week`` into (week, time of week) per stamp."""
    seconds_of_week = np.asarray(seconds_of_week, dtype=np.float64)
    carry = np.floor_divide(seconds_of_week, SECONDS_PER_WEEK)
    return (gps_week + carry).astype(np.int64), seconds_of_week - carry * SECONDS_PER_WEEK
