"""insrail.gui: the surveyor's desktop application (PySide6 + pyqtgraph).

A shell around the core: it calls :mod:`insrail.project` (load, save, process, load_results) and
draws what :mod:`insrail.project.plotdata` derives; nothing is computed in a widget. Processing runs
in a worker thread; the core's progress callback and cancel token are marshalled with Qt signals.

Start it with ``insrail gui [PROJECT]`` or :func:`insrail.gui.app.run`.
"""

from insrail.gui._binding_fix import make_singletons_immortal

make_singletons_immortal()
