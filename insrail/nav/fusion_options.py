"""The fusion's options (:class:`FusionOptions`), apart from the filter (``insrail.nav.fusion``): the
project's settings and the reports read them without importing the filter and its compiled kernels."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from insrail.nav.error_model import trolley_play_drift_m2_per_m


@dataclass(frozen=True)
class FusionOptions:
    """What the filter uses and how much it trusts it."""

    use_gnss_velocity: bool = True  # when the GNSS file has velocities
    use_odometer: bool = True
    use_nhc: bool = True
    use_zupt: bool = True
    smoother: bool = True
    update_rate_hz: float = 10.0
    gnss_sigma_scale: float = 1.0
    #: (RTKLIB quality flag, factor on its sigmas or None to exclude): 0 unknown, 1 fix, 2 float,
    #: 3 SBAS, 4 DGPS, 5 single, 6 PPP. Float solutions are kept with inflated sigmas, single ones left out.
    gnss_quality_policy: tuple[tuple[int, float | None], ...] = (
        (0, 1.0), (1, 1.0), (2, 3.0), (3, 5.0), (4, 5.0), (5, None), (6, 2.0),
    )
    gnss_sigma_floor_m: float = 0.002
    #: correlated part of the GNSS position error (Gauss-Markov): short-baseline PPK
    gnss_correlated_sigma_ned_m: tuple[float, float, float] = (0.005, 0.005, 0.010)
    gnss_correlated_tau_s: float = 300.0
    # Calibrated so that the mean NIS per degree of freedom of odometer/NHC is within 0.5-2 on the
    # simulator (0.57-0.60; benchmarks/fusion.py) with the clean accuracy unchanged (within 2 %):
    # the NHC innovations are 0.33 mm/s RMS (the trolley's play), the thesis's Table 3-2 says
    # 0.1 mm/s/sqrt(Hz), i.e. 0.3 mm/s at 10 Hz; tighter than 0.45 mm/s the solution follows the play.
    odometer_sigma_mps: float = 0.0005  # plus the pulse quantisation over the segment
    #: factors on the odometer's and the ZUPT's 1-sigma (the survey's own, ``insrail.nav.self_calibration``)
    odometer_sigma_scale: float = 1.0
    zupt_sigma_scale: float = 1.0
    #: the odometer's, the ZUPT's and the GNSS classes' noise from the innovations, fused again with it
    estimate_noise: bool = True
    nhc_sigma_mps: float = 0.00045
    #: The trolley's play as position process noise where the NHC holds the trolley to the rail:
    #: (lateral, vertical) drift variance per metre run [m^2/m], ``resources/trolley_play.toml``.
    #: The NHC noise above is set for its 10 Hz innovations; the play's drift over tens of metres
    #: (between prism fixes) is this (docs/fusion.md).
    play_drift_m2_per_m: tuple[float, float] = field(default_factory=trolley_play_drift_m2_per_m)
    #: the survey's own play from its NHC innovations, fused again with it (insrail.nav.self_calibration)
    estimate_play: bool = True
    # The ZUPT's velocity noise where the platform shows no motion beyond the accelerometers' noise;
    # a stop where they show more (an operator's touch, a hand) adds that motion's velocity
    # (``alignment.stop_motion_sigma``). Between two 10 Hz ZUPTs of a still trolley the INS velocity
    # errs only by the random walk's vrw sqrt(0.1 s) (4 um/s for `nav`): 1 mm/s (as before) gave
    # NIS/dof 0.25 on the simulator, its velocity rows 0.005 (docs/fusion.md).
    zupt_sigma_mps: float = 2e-6
    gate_probability: float = 0.9999
    initial_heading_rad: float | None = None  # None: gyrocompassing in the static start
    initial_sigma_heading_rad: float = math.radians(0.1)
    initial_sigma_level_rad: float = math.radians(0.01)
    initial_sigma_odometer_scale: float = 0.01
    min_static_s: float = 30.0
    max_imu_gap_s: float = 5.0  # longer IMU gaps are refused, shorter ones bridged with a warning
    #: Gating that cannot lock out: an aiding source rejected without a break for this long means
    #: the filter is wrong, not the sensor: the filter is reset (``FilterReset``). Longer than a
    #: GNSS false fix lasts (a wrong ambiguity fix of 10-20 cm for some seconds) so that one is
    #: rejected, not followed; the shorter limit applies while another source is rejected too
    #: (every sensor disagreeing with the filter: an IMU fault, a lost filter).
    reset_after_s: float = 20.0
    reset_after_s_all_rejected: float = 2.0
    #: the limit for observations that doubt themselves (GNSS float, DGPS): a float stretch is
    #: rejected for as long as it disagrees, the filter reset only after this long
    reset_after_s_doubtful: float = 120.0
    #: what the reset widens at least to: position (or twice the largest rejected position
    #: innovation), velocity (or that position over the time rejected), level and heading
    reset_sigma_position_m: float = 0.5
    reset_sigma_velocity_mps: float = 0.1
    reset_sigma_level_rad: float = math.radians(0.2)
    reset_sigma_heading_rad: float = math.radians(10.0)
