"""Per-sleeper coordinates of the centreline and both rails (CSV for survey and CAD programs):
``number,chainage,station_m,valid,centre_E_m,centre_N_m,centre_H_m,left_E_m,...,right_H_m,gauge_mm,cant_mm``,
engineering CRS, normal heights, empty cells where not measured."""

from __future__ import annotations

import numpy as np

POINT_COLUMNS = [f"{prefix}_{axis}_m" for prefix in ("centre", "left", "right") for axis in "ENH"]
HEADER = ["number", "chainage", "station_m", "valid", *POINT_COLUMNS, "gauge_mm", "cant_mm"]


def format_points(project, results) -> str:
    """``insrail export --format csv``."""
    c = dict(results.columns)
    if "centre_E_m" not in c:  # results of older versions
        for axis in "ENH":
            c[f"centre_{axis}_m"] = 0.5 * (c[f"left_{axis}_m"] + c[f"right_{axis}_m"])

    def cell(value: float, digits: int) -> str:
        return f"{value:.{digits}f}" if np.isfinite(value) else ""

    lines = [",".join(HEADER)]
    for i, number in enumerate(results.number):
        label = results.label[i] or f"{c['station_m'][i]:.4f}"
        lines.append(",".join([str(int(number)), label, cell(c["station_m"][i], 4), str(int(c["valid"][i] > 0)),
                               *(cell(c[name][i], 4) for name in POINT_COLUMNS),
                               cell(c["gauge_mm"][i], 2), cell(c["cant_mm"][i], 2)]))
    return "\n".join(lines) + "\n"
