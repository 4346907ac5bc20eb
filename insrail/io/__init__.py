"""Readers and writers of raw survey data, one function per format.

Conventions: time stamps are GPS seconds of the week; body frame b is the IMU's
forward-right-down; positions in files are geodetic degrees and ellipsoidal metres
unless the format says otherwise (prism observations are in the engineering frame);
gauge files are in mm, everything returned is SI. Every reader raises
:class:`~insrail.io.errors.InputError` naming the file, the line and what was
expected; none lets a bare numpy/parser traceback through.
"""

from insrail.io.errors import InputError

__all__ = ["InputError"]
