"""GNSS post-processing with RTKLIB (pyrtklib): PPK, receiver-log conversion, solution QC.

Pure core (no Qt). GNSS processing itself is RTKLIB's; insrail checks inputs, holds
the trolley defaults as an RTKLIB .conf in resources/gnss/, runs RTKLIB in a child
process and writes results atomically.
"""

from insrail.gnss.convert import convert_to_rinex
from insrail.gnss.options import OptionError, load_options, rtklib_option_table
from insrail.gnss.ppk import (ApproximateBaseWarning, BasePosition, GnssProcessingError, LongBaselineWarning,
                              PpkResult, ppk)
from insrail.gnss.qc import GnssQc, SigmaStats, gnss_qc

__all__ = ["ApproximateBaseWarning", "BasePosition", "GnssProcessingError", "GnssQc", "LongBaselineWarning",
           "OptionError", "PpkResult", "SigmaStats", "convert_to_rinex", "gnss_qc", "load_options", "ppk",
           "rtklib_option_table"]
