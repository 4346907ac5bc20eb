"""Track irregularities as analytic functions of station.

A random irregularity is a sum of many sinusoids with wavelengths spread
log-uniformly over a band (3-70 m by default) and random phases: band-limited,
close to Gaussian, infinitely smooth and exactly evaluable at any station, so the
per-sleeper truth needs no interpolation. Isolated defects ("bumps") are
sin^4-shaped, whose first three derivatives vanish at both ends, so the trolley's
acceleration and jerk stay continuous.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Bump:
    """An isolated defect of peak ``amplitude_m`` spread over ``length_m`` from ``start_station_m``."""

    start_station_m: float
    length_m: float
    amplitude_m: float


@dataclass(frozen=True)
class Irregularity:
    """Sum of sinusoids plus bumps; ``evaluate(station)`` gives the offset [m]."""

    wavenumber_rad_per_m: np.ndarray
    amplitude_m: np.ndarray
    phase_rad: np.ndarray
    bumps: tuple[Bump, ...] = ()

    def evaluate(self, station_m, chunk: int = 20000) -> np.ndarray:
        s = np.asarray(station_m, dtype=float)
        flat = s.ravel()
        out = np.empty_like(flat)
        for i in range(0, flat.size, chunk):
            part = flat[i : i + chunk]
            out[i : i + chunk] = np.cos(np.outer(part, self.wavenumber_rad_per_m) + self.phase_rad) @ self.amplitude_m
        for bump in self.bumps:
            x = (flat - bump.start_station_m) / bump.length_m
            inside = (x > 0.0) & (x < 1.0)
            out[inside] += bump.amplitude_m * np.sin(np.pi * x[inside]) ** 4
        return out.reshape(s.shape)

    def plus(self, other: Irregularity) -> Irregularity:
        """The sum of two irregularities (their sinusoids and bumps together)."""
        return Irregularity(np.concatenate([self.wavenumber_rad_per_m, other.wavenumber_rad_per_m]),
                            np.concatenate([self.amplitude_m, other.amplitude_m]),
                            np.concatenate([self.phase_rad, other.phase_rad]), self.bumps + other.bumps)

    @property
    def random_rms_m(self) -> float:
        """RMS of the random (sinusoid) part."""
        return float(np.sqrt(0.5 * np.sum(self.amplitude_m**2)))


def random_irregularity(
    rng: np.random.Generator,
    rms_m: float,
    shortest_wavelength_m: float = 3.0,
    longest_wavelength_m: float = 70.0,
    components: int = 300,
    spectral_slope: float = 1.0,
    bumps: tuple[Bump, ...] = (),
) -> Irregularity:
    """Band-limited random irregularity of RMS ``rms_m``.

    Amplitudes grow as wavelength**spectral_slope (real track has more energy at long
    wavelengths); the sum is scaled to the requested RMS.
    """
    if rms_m < 0 or not 0 < shortest_wavelength_m < longest_wavelength_m:
        raise ValueError("irregularity needs rms >= 0 and 0 < shortest < longest wavelength")
    wavelength = np.exp(rng.uniform(np.log(shortest_wavelength_m), np.log(longest_wavelength_m), components))
    amplitude = wavelength**spectral_slope
    amplitude *= rms_m / np.sqrt(0.5 * np.sum(amplitude**2)) if rms_m > 0 else 0.0
    return Irregularity(2.0 * np.pi / wavelength, amplitude, rng.uniform(0.0, 2.0 * np.pi, components), bumps)
