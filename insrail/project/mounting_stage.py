"""The IMU mounting calibration in the processing (``insrail.nav.mounting``): where it runs and what it
leaves for the stages after it.

* Yaw and pitch, before the fusion, where the survey has GNSS (the velocity's direction must come from
  positions, not from the NHC): a smoothed pass without the NHC, on the IMU summed to 50 Hz
  (:func:`yaw_pitch_pass`). An axis more than 3 sigma off survey.toml's is applied to the trolley the
  fusion and the track use; ``fusion_log``/summary ``[fusion.mounting]`` records the estimate.
* Roll, after the track, where there is a design (its cant is the reference): :func:`roll_check`; a
  roll more than 3 sigma off is applied and the rails placed again.
Each applied axis is a warning naming survey.toml's key and the value to give it.

The yaw/pitch pass and the main fusion run side by side (:func:`fused_with_mounting`, two jobs of
:mod:`insrail.background`): the main fusion starts at once with survey.toml's mounting, a guess the pass
almost always confirms (a 10 km survey: some 8 s of wall time saved of 17). Where the pass applies an
axis the guess is thrown away and the survey fused again with the estimate, as without the guess: the
result is the same either way.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from insrail.background import BackgroundJob, cpu_budget
from insrail.nav.mounting import (
    AXES,
    SIGNIFICANT_SIGMAS,
    MountingEstimate,
    not_estimated,
    roll_from_cant,
    yaw_pitch_from_velocity,
)
from insrail.notices import Notice, Phrase
from insrail.progress import StepProgress

#: the calibration pass's trajectory at 10 Hz: enough for the velocity's direction
UPDATE_RATE_OUTPUT_HZ = 10.0
#: The pass mechanises the IMU records summed to about this rate: a mean direction of travel over the
#: survey does not need the IMU's full rate. At 10 km (200 Hz) the pass takes some 2.3 s of CPU less
#: (of 10.7, one core) and writes 0.13 GB less; its estimate moves by 0.03 sigma (yaw 0.1195 -> 0.1196
#: deg, sigma 0.0045; the truth 0.12). Its updates stay at the main fusion's rate: at 2 Hz the pass
#: took a 40 s GNSS false fix of 1 m for a yaw of -4.6 deg (+-1.5) and applied it (tests/test_nav_integrity.py's
#: false fix; 5 Hz: 0.08 deg, 10 Hz: 0.31 deg, both +-0.1 and not applied).
PASS_IMU_RATE_HZ = 50.0
#: the yaw/pitch pass's share of the progress of the pass and the main fusion (about its share of their time)
PASS_SHARE = 0.3
#: how often the caller hears of the progress of the pass and the main fusion running side by side [s]
PROGRESS_INTERVAL_S = 0.25


def yaw_pitch_pass(survey, build_aiding, profile, options, ellipsoid, fuse, progress=None, cancel=None
                   ) -> MountingEstimate:
    """Yaw and pitch of the mounting from a smoothed fusion pass without the NHC (``build_aiding(options)``:
    the survey's aiding for the options); not estimated without GNSS."""
    trolley = survey.manifest.trolley
    if survey.gnss is None:
        return not_estimated(trolley.mounting_rpy_rad, Phrase("no GNSS: only the NHC gives the direction of travel in "
                                                              "the IMU's axes"))
    pass_options = replace(options, use_nhc=False, smoother=True, estimate_play=False)
    dt = float(np.median(np.diff(survey.imu.time_s[:1000])))
    imu_every = max(int(round(1.0 / (PASS_IMU_RATE_HZ * dt))), 1)
    every = max(int(round(1.0 / (UPDATE_RATE_OUTPUT_HZ * dt * imu_every))), 1)
    try:  # a survey the pass cannot fuse is the main fusion's to refuse or to fuse: its mounting stays as given
        result = fuse(survey.imu, build_aiding(pass_options), profile, pass_options, ellipsoid, output_every=every,
                      progress=progress, cancel=cancel, imu_every=imu_every)
    except ValueError as error:
        return not_estimated(trolley.mounting_rpy_rad, Phrase("the pass without the NHC failed: {error}",
                                                              {"error": str(error)}))
    if not result.integrity.trusted:
        return not_estimated(trolley.mounting_rpy_rad, Phrase("the pass without the NHC is not consistent"))
    rail_point = trolley.imu_to_reference_rail_m if trolley.imu_to_reference_rail_m is not None else np.zeros(3)
    return yaw_pitch_from_velocity(result.trajectory, trolley.mounting_rpy_rad, rail_point)


def fused_with_mounting(survey, estimate, fuse, discard, progress=None, cancel=None):
    """(the mounting estimate, the survey with it applied, the main fusion's result): ``estimate(survey,
    progress, cancel)`` the yaw/pitch pass (:func:`yaw_pitch_pass`), ``fuse(survey, progress, cancel)`` the
    main fusion of a survey, ``discard(result)`` drops what a main fusion left (``result``: its result, or
    None after it failed). As the pass and then the main fusion with the estimate applied, one after the
    other; where the pass fuses (the survey has GNSS) and the CPU budget is two or more, side by side, each a
    :class:`~insrail.background.BackgroundJob`: the main fusion with survey.toml's mounting, its result kept
    where the pass applies no axis (the same survey to the bit, so the same result), else discarded and the
    survey fused again with the estimate. The jobs' progress reaches ``progress`` from the caller's thread;
    a cancel stops both, and either's failure stops the other; the pass's failure is raised, the main
    fusion's where it is kept (as one after the other)."""
    step = StepProgress(progress)
    share = PASS_SHARE if survey.gnss is not None else 0.0  # without GNSS the pass does not fuse
    if survey.gnss is None or cpu_budget() < 2:
        mounting = estimate(survey, step.sub(0.0, share), cancel)
        mounted = replace(survey, manifest=with_mounting(survey.manifest, mounting.applied_rpy_rad()))
        return mounting, mounted, fuse(mounted, step.sub(share, 1.0), cancel)
    given = np.asarray(survey.manifest.trolley.mounting_rpy_rad, dtype=float)
    guessed = replace(survey, manifest=with_mounting(survey.manifest, given))
    done, said = {"pass": 0.0, "fusion": 0.0}, {}

    def heard(name):  # a job's progress as relayed (forward only: a self-calibration pass starts again from 0)
        def hear(fraction, message):
            done[name], said[name] = fraction, message
        return hear

    def reached() -> float:
        return share * done["pass"] + (1.0 - share) * done["fusion"]

    def follow(job) -> None:  # both jobs' progress to the caller until ``job`` has ended
        while not job.done():
            job.wait(PROGRESS_INTERVAL_S)
            passing.relay(heard("pass"))
            fusing.relay(heard("fusion"))
            step(reached(), said.get("fusion") or said.get("pass", ""))

    kept = False
    with BackgroundJob(lambda told, stop: estimate(survey, told, stop), None, cancel, "insrail-mounting-pass",
                       threaded=True) as passing, \
            BackgroundJob(lambda told, stop: fuse(guessed, told, stop), None, cancel, "insrail-fusion",
                          threaded=True) as fusing:
        try:
            follow(passing)
            mounting = passing.result()
            mounted = replace(survey, manifest=with_mounting(survey.manifest, mounting.applied_rpy_rad()))
            kept = mounting.applied_rpy_rad().tobytes() == given.tobytes()
            if kept:
                follow(fusing)
                return mounting, mounted, fusing.result()
        finally:
            if not kept:  # the pass failed or applied an axis: the guess goes
                fusing.stop()
                discard(fusing.result() if fusing.exception() is None else None)
    return mounting, mounted, fuse(mounted, step.sub(reached(), 1.0), cancel)


def with_mounting(manifest, rpy_rad):
    """The manifest with its trolley's mounting replaced."""
    return replace(manifest, trolley=replace(manifest.trolley, mounting_rpy_rad=np.asarray(rpy_rad, dtype=float)))


def roll_check(manifest, table, design_cant_available: bool) -> MountingEstimate:
    """The roll of the mounting from the sleeper table's cant against the design's (not estimated without
    a design)."""
    trolley = manifest.trolley
    if not design_cant_available:
        return not_estimated(trolley.mounting_rpy_rad, Phrase("no design cant to compare the cant with"))
    return roll_from_cant(trolley.mounting_rpy_rad, table.cant_m, table.design_cant_m, trolley.rail_centre_spacing_m,
                          table.valid)


def mounting_notices(estimate: MountingEstimate, source: str, stage: str = "fusion") -> list[Notice]:
    """A warning when an axis is applied, naming the estimate, the key and the value to give (``source``:
    the file that gave the mounting; ``stage``: the notice's); nothing where the survey agrees with the
    given mounting (a clean survey says nothing: the estimate is in summary.toml [fusion.mounting] and
    the PDF)."""
    notices = []
    applied = [AXES[i] for i in range(3) if estimate.significant[i]]
    if applied:
        notices.append(Notice(stage, estimate.text(), severity="info"))
        values = ", ".join(f"{v:.3f}" for v in np.degrees(estimate.applied_rpy_rad()))
        apart = [Phrase("{axis} by {apart_deg:.3f} deg ({sigmas:.0f} sigma)",
                        {"axis": Phrase(AXES[i]),
                         "apart_deg": math.degrees(abs(estimate.rpy_rad[i] - estimate.given_rpy_rad[i])),
                         "sigmas": abs(estimate.rpy_rad[i] - estimate.given_rpy_rad[i]) / estimate.sigma_rad[i]})
                 for i in range(3) if estimate.significant[i]]
        notices.append(Notice(
            stage, "the IMU mounting the survey shows differs from {source}'s trolley.mounting_rpy_deg by more than "
            "{sigmas:g} sigma ({apart}): the survey is processed with the estimate; give trolley.mounting_rpy_deg = "
            "[{values}]{roll}", severity="warning",
            fields={"source": source, "sigmas": SIGNIFICANT_SIGMAS, "apart": apart, "values": values,
                    "roll": Phrase(" (the roll takes the track's mean cross-level for the design's)" if "roll" in applied
                                   else "")}))
    return notices
