"""Quality summary of a GNSS solution: how much of it a surveyor can trust.

Counts epochs by RTKLIB quality flag, the fix rate, statistics of the ambiguity ratio
(fixed epochs) and of the position sigmas per quality, and the gaps in the epoch
series with their extents. Distances in m, times in s of the GPS week.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from insrail.io.types import Gap, GnssSolution

QUALITY_NAMES = {1: "fix", 2: "float", 3: "sbas", 4: "dgps", 5: "single", 6: "ppp"}
SOLUTION_FIXED = 1


@dataclass(frozen=True)
class SigmaStats:
    """Statistics of the horizontal (hypot(sdn, sde)) and vertical (sdu) sigmas [m]."""

    horizontal_median_m: float
    horizontal_p95_m: float
    horizontal_max_m: float
    vertical_median_m: float
    vertical_p95_m: float
    vertical_max_m: float


@dataclass(frozen=True)
class GnssQc:
    """QC of a GNSS solution.

    epochs_by_quality : {quality name: epoch count}, only qualities present
    fix_rate          : fixed epochs / all epochs (0 for an empty solution)
    ratio_*           : ambiguity ratio of the fixed epochs (NaN when none or unknown)
    sigma_by_quality  : {quality name: SigmaStats}
    gaps              : gaps longer than 1.5 nominal intervals
    interval_s        : nominal (median) epoch interval
    """

    epochs: int
    first_s: float
    last_s: float
    interval_s: float
    epochs_by_quality: dict[str, int]
    fix_rate: float
    ratio_min: float
    ratio_median: float
    ratio_p05: float
    sigma_by_quality: dict[str, SigmaStats]
    gaps: tuple[Gap, ...]

    @property
    def gap_total_s(self) -> float:
        return float(sum(g.duration_s for g in self.gaps))

    def report(self) -> str:
        """Plain-text report for the processing log and the terminal."""
        lines = [(f"epochs           : {self.epochs} over {self.last_s - self.first_s:.1f} s "
                 f"(interval {self.interval_s:g} s)")]
        for name, count in self.epochs_by_quality.items():
            share = 100.0 * count / self.epochs if self.epochs else 0.0
            lines.append(f"  {name:<15}: {count:7d}  {share:6.2f} %")
        lines.append(f"fix rate         : {100.0 * self.fix_rate:.2f} %")
        lines.append(f"ratio (fixed)    : min {self.ratio_min:.1f}  5 % {self.ratio_p05:.1f}  "
                     f"median {self.ratio_median:.1f}")
        for name, s in self.sigma_by_quality.items():
            lines.append(f"sigma {name:<11}: horizontal median {1e3 * s.horizontal_median_m:.1f} mm, "
                         f"95 % {1e3 * s.horizontal_p95_m:.1f} mm, max {1e3 * s.horizontal_max_m:.1f} mm; "
                         f"vertical median {1e3 * s.vertical_median_m:.1f} mm, "
                         f"95 % {1e3 * s.vertical_p95_m:.1f} mm, max {1e3 * s.vertical_max_m:.1f} mm")
        lines.append(f"gaps             : {len(self.gaps)}, {self.gap_total_s:.1f} s in total")
        lines += [f"  {g.start_s:.3f} .. {g.end_s:.3f}  ({g.duration_s:.1f} s)" for g in self.gaps]
        return "\n".join(lines)


def _sigma_stats(sigma_ned_m: np.ndarray) -> SigmaStats:
    horizontal = np.hypot(sigma_ned_m[:, 0], sigma_ned_m[:, 1])
    vertical = sigma_ned_m[:, 2]
    h50, h95 = np.percentile(horizontal, [50, 95])
    v50, v95 = np.percentile(vertical, [50, 95])
    return SigmaStats(float(h50), float(h95), float(horizontal.max()), float(v50), float(v95),
                      float(vertical.max()))


def gnss_qc(solution: GnssSolution) -> GnssQc:
    """QC summary of ``solution``; gaps are taken from the solution (found when it was read)."""
    n = len(solution)
    if n == 0:
        return GnssQc(0, np.nan, np.nan, np.nan, {}, 0.0, np.nan, np.nan, np.nan, {}, ())
    quality = np.asarray(solution.quality)
    epochs_by_quality: dict[str, int] = {}
    sigma_by_quality: dict[str, SigmaStats] = {}
    for value in np.unique(quality):
        name = QUALITY_NAMES.get(int(value), f"quality {int(value)}")
        mask = quality == value
        epochs_by_quality[name] = int(mask.sum())
        sigma_by_quality[name] = _sigma_stats(solution.sigma_ned_m[mask])
    fixed_ratio = solution.ratio[(quality == SOLUTION_FIXED) & np.isfinite(solution.ratio)]
    if fixed_ratio.size:
        ratio_min, ratio_p05, ratio_median = (float(fixed_ratio.min()),
                                              *map(float, np.percentile(fixed_ratio, [5, 50])))
    else:
        ratio_min = ratio_p05 = ratio_median = float("nan")
    interval = float(np.median(np.diff(solution.time_s))) if n > 1 else float("nan")
    return GnssQc(
        epochs=n,
        first_s=float(solution.time_s[0]),
        last_s=float(solution.time_s[-1]),
        interval_s=interval,
        epochs_by_quality=epochs_by_quality,
        fix_rate=float(np.mean(quality == SOLUTION_FIXED)),
        ratio_min=ratio_min,
        ratio_median=ratio_median,
        ratio_p05=ratio_p05,
        sigma_by_quality=sigma_by_quality,
        gaps=tuple(solution.gaps),
    )
