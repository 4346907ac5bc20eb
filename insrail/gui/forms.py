"""Pieces the forms share (the wizard, the settings editor, Plan survey)."""

from __future__ import annotations

from PySide6.QtWidgets import QDoubleSpinBox

#: A problem shown beside its field.
NOTE_STYLE = "color: #C00000"


def spin_box(low: float, high: float, decimals: int, value: float = 0.0, suffix: str = "",
             step: float | None = None) -> QDoubleSpinBox:
    """A number field from ``low`` to ``high`` with ``decimals`` shown (``suffix`` its unit, as " m")."""
    box = QDoubleSpinBox()
    box.setRange(low, high)
    box.setDecimals(decimals)
    if step is not None:
        box.setSingleStep(step)
    box.setSuffix(suffix)
    box.setValue(value)
    return box
