"""GPS time: calendar dates, Unix-style stamps, UTC leap seconds, week and seconds of week.

All functions are vectorised. A time series is returned as (week of its first stamp,
seconds from the start of that week): a recording that runs past the end of the week
keeps counting beyond 604800 s instead of wrapping, so the time stays monotonic.
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


# Absolute GPS seconds (~1.4e9) carry only ~0.2 us of resolution in a double, so the
# functions below never form them: a series is (week of its first stamp, seconds
# from the start of that week), built from small numbers.

def normalise_week(week: int, seconds_of_week: np.ndarray) -> tuple[int, np.ndarray]:
    """Move whole weeks between the two parts so the first stamp lies in [0, 604800)."""
    shift = int(np.floor(seconds_of_week[0] / SECONDS_PER_WEEK))
    return week + shift, seconds_of_week - shift * SECONDS_PER_WEEK


def calendar_to_week_seconds(year, month, day, hour, minute, second) -> tuple[int, np.ndarray]:
    """(week, seconds of that week) of calendar times, read on the scale they are given in."""
    days = days_since_gps_epoch(year, month, day)
    week = int(days[0] // 7)
    seconds = ((days - 7 * week) * SECONDS_PER_DAY + np.asarray(hour, dtype=np.float64) * 3600.0
               + np.asarray(minute, dtype=np.float64) * 60.0 + np.asarray(second, dtype=np.float64))
    return normalise_week(week, seconds)


def week_tow_to_week_seconds(week, tow) -> tuple[int, np.ndarray]:
    """(week of the first stamp, seconds from its start) of per-stamp (week, time of week) pairs."""
    week = np.asarray(week, dtype=np.int64)
    first = int(week[0])
    return normalise_week(first, (week - first) * float(SECONDS_PER_WEEK) + np.asarray(tow, dtype=np.float64))


_LEAP_STEP_DAYS = days_since_gps_epoch(*np.array([d for d, _ in _LEAP_SECOND_STEPS]).T)
_LEAP_VALUES_S = np.array([0.0] + [v for _, v in _LEAP_SECOND_STEPS])


def gpst_minus_utc(week: int, utc_seconds_of_week) -> np.ndarray:
    """GPST - UTC [s] at UTC instants given as (week, seconds of week) on the UTC calendar."""
    days = week * 7 + np.floor(np.asarray(utc_seconds_of_week, dtype=np.float64) / SECONDS_PER_DAY)
    return _LEAP_VALUES_S[np.searchsorted(_LEAP_STEP_DAYS, days, side="right")]


def utc_to_gpst(week: int, utc_seconds_of_week) -> tuple[int, np.ndarray]:
    """(week, GPST seconds of week) of UTC times given as (week, seconds of week) of the UTC calendar."""
    utc = np.asarray(utc_seconds_of_week, dtype=np.float64)
    return normalise_week(week, utc + gpst_minus_utc(week, utc))


def unix_gpst_to_week_seconds(unix_s) -> tuple[int, np.ndarray]:
    """(week, seconds of week) of stamps counted like Unix time but on the GPST scale.

    Loggers that convert GPST calendar time with a Unix-time routine produce these
    (e.g. the rtklibexplorer/GNSS_IMU files): no leap seconds are involved. The
    subtraction of the week start (an exact integer) loses nothing.
    """
    unix_s = np.asarray(unix_s, dtype=np.float64)
    week = int((unix_s[0] - GPS_EPOCH_UNIX_S) // SECONDS_PER_WEEK)
    return week, unix_s - float(GPS_EPOCH_UNIX_S + week * SECONDS_PER_WEEK)


def seconds_to_week_tow(gps_week: int, seconds_of_week) -> tuple[np.ndarray, np.ndarray]:
    """Split seconds counted from the start of ``gps_week`` into (week, time of week) per stamp."""
    seconds_of_week = np.asarray(seconds_of_week, dtype=np.float64)
    carry = np.floor_divide(seconds_of_week, SECONDS_PER_WEEK)
    return (gps_week + carry).astype(np.int64), seconds_of_week - carry * SECONDS_PER_WEEK
