"""Station equations (broken chainage) and station labels like "DK1+695.917".

The design alignment works on the continuous measure along the track (the
"internal station", equal to the displayed station at the alignment's start).
A station equation says that, going forward, the displayed station jumps from
``back_m`` to ``ahead_m`` (LandXML staBack / staAhead). ``ahead < back`` is a long
chain (displayed stations repeat: give the zone to resolve them), ``ahead > back`` a
short chain (displayed stations in between do not exist).

Zone k is the stretch after the k-th equation (zone 0 before the first one); it is
the sleeper table's "chain-break attribute".
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from insrail.notices import Phrase
from insrail.track.errors import DesignError

_LABEL = re.compile(r"^\s*(?P<prefix>[^\d+\-]*)(?P<sign>-?)(?P<km>\d+)\+(?P<metres>\d+(?:\.\d*)?)\s*$")


@dataclass(frozen=True)
class StationEquation:
    """Displayed station ``back_m`` (behind) equals ``ahead_m`` (ahead) at one point."""

    back_m: float
    ahead_m: float

    def __post_init__(self):
        for name in ("back_m", "ahead_m"):
            if not math.isfinite(getattr(self, name)):
                raise DesignError("station_equations", None, "StationEquation: {name} must be a finite number, got {value!r}",
                                  {"name": name, "value": getattr(self, name)})


@dataclass(frozen=True)
class StationEquations:
    """Ordered station equations along an alignment, and the label prefix ("K", "DK", ...)."""

    equations: tuple[StationEquation, ...] = ()
    prefix: str = "K"
    _internal: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "equations", tuple(self.equations))
        if any(ch.isdigit() or ch in "+-" for ch in self.prefix):
            raise DesignError("station_equations", None, "the station prefix {prefix!r} may not hold digits, '+' or '-'",
                              {"prefix": self.prefix})
        internal = []
        for index, equation in enumerate(self.equations):
            if index == 0:
                internal.append(equation.back_m)
                continue
            previous = self.equations[index - 1]
            if not equation.back_m > previous.ahead_m:
                raise DesignError(
                    "station_equations",
                    index,
                    "station equation {number} (back {back:.4f} m) does not come after equation {previous} (ahead "
                    "{ahead:.4f} m): the displayed station must increase between them",
                    {"number": index + 1, "back": equation.back_m, "previous": index, "ahead": previous.ahead_m},
                )
            internal.append(internal[-1] + (equation.back_m - previous.ahead_m))
        array = np.array(internal, dtype=float)
        array.setflags(write=False)
        object.__setattr__(self, "_internal", array)

    @property
    def internal_stations_m(self) -> np.ndarray:
        """Continuous-measure station of each equation."""
        return self._internal

    def zone_at(self, internal_m) -> np.ndarray:
        """Number of equations passed at each continuous station (an equation point is ahead)."""
        return np.searchsorted(self._internal, np.asarray(internal_m, dtype=float), side="right")

    def _zone_shift(self) -> np.ndarray:
        """displayed - internal in each zone."""
        aheads = np.array([e.ahead_m for e in self.equations])
        return np.concatenate(([0.0], aheads - self._internal))

    def displayed_from_internal(self, internal_m) -> np.ndarray:
        """Displayed (broken) station [m] of continuous stations (vectorised)."""
        internal = np.asarray(internal_m, dtype=float)
        return internal + self._zone_shift()[self.zone_at(internal)]

    def internal_from_displayed(self, displayed_m, zone=None) -> np.ndarray:
        """Continuous station of displayed stations; ``zone`` resolves long-chain repeats.

        Raises ValueError for a displayed station inside a short chain (it does not
        exist) or, without ``zone``, one that exists twice (long chain).
        """
        displayed = np.asarray(displayed_m, dtype=float)
        backs = np.array([e.back_m for e in self.equations])
        aheads = np.array([e.ahead_m for e in self.equations])
        low = np.concatenate(([-np.inf], aheads))
        high = np.concatenate((backs, [np.inf]))
        member = (displayed[..., None] >= low) & (displayed[..., None] < high)
        if zone is None:
            count = member.sum(axis=-1)
            if np.any(count == 0):
                bad = displayed[count == 0].flat[0]
                raise ValueError(Phrase("displayed station {station:.4f} m lies in a short chain: it does not exist on this "
                                        "line", {"station": float(bad)}))
            if np.any(count > 1):
                bad = displayed[count > 1].flat[0]
                raise ValueError(Phrase("displayed station {station:.4f} m exists twice (long chain): give its zone",
                                        {"station": float(bad)}))
            zones = np.argmax(member, axis=-1)
        else:
            zones = np.broadcast_to(np.asarray(zone, dtype=int), displayed.shape)
            if np.any((zones < 0) | (zones > len(self.equations))):
                raise ValueError(Phrase("zone must be between 0 and {count}", {"count": len(self.equations)}))
            if not np.all(np.take_along_axis(member, zones[..., None], axis=-1)):
                raise ValueError(Phrase("a displayed station does not exist in the zone given for it"))
        return displayed - self._zone_shift()[zones]

    def label(self, internal_m, decimals: int = 3) -> list[str] | str:
        """Station label(s) like "DK1+695.917" for continuous stations (a str for a scalar)."""
        displayed = self.displayed_from_internal(internal_m)
        scale = 10**decimals
        width = 4 + decimals if decimals else 3
        labels = []
        for value in np.atleast_1d(displayed).ravel():
            units = round(abs(float(value)) * scale)
            km, rest = divmod(units, 1000 * scale)
            sign = "-" if value < 0 and units else ""
            labels.append(f"{self.prefix}{sign}{km}+{rest / scale:0{width}.{decimals}f}")
        return labels[0] if np.ndim(displayed) == 0 else labels

    def parse_label(self, text: str, zone: int | None = None) -> float:
        """Continuous station of a label such as "DK1+695.917" (the prefix must match)."""
        return float(self.internal_from_displayed(self._displayed(text), zone))

    def parse_labels(self, texts, zone=None) -> np.ndarray:
        """Continuous stations of many labels, each read as by :meth:`parse_label` and all converted at once
        (a survey's 16 000 sleeper labels: one array operation, not one per label)."""
        return self.internal_from_displayed(np.array([self._displayed(text) for text in texts], dtype=float), zone)

    def _displayed(self, text: str) -> float:
        """The displayed station [m] a label states (its prefix checked)."""
        match = _LABEL.match(text)
        if match is None:
            raise ValueError(Phrase("{text!r} is not a station label like '{prefix}1+234.567'",
                                    {"text": text, "prefix": self.prefix}))
        if match["prefix"].strip() != self.prefix:
            raise ValueError(Phrase("station label {text!r} has prefix {found!r}, expected {prefix!r}",
                                    {"text": text, "found": match["prefix"], "prefix": self.prefix}))
        metres = float(match["metres"])
        if metres >= 1000.0:
            raise ValueError(Phrase("station label {text!r}: the metres after '+' must be below 1000", {"text": text}))
        displayed = int(match["km"]) * 1000.0 + metres
        if match["sign"]:
            displayed = -displayed
        return displayed
