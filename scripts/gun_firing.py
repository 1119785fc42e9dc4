"""Write the example gun firing, pdbfs/data/gun_firing.csv (and its copy in
docs/data): a synthetic chamber-pressure trace of one firing of a
large-calibre gun, shaped as measured ones are, not a measurement.

    python scripts/gun_firing.py

The shape, from the trigger:
- 1 ms before ignition at rest (0 Pa, the sensor's noise on it);
- the pressure rising as the charge burns to its peak, 170 MPa 3.5 ms after
  ignition (a reduced charge: full charges of large-calibre guns reach
  300-600 MPa, beyond what the paper rig's blows reach);
- falling as the projectile travels down the bore, to shot exit 8 ms after
  ignition (at about a fifth of the peak);
- the blow-down after shot exit (a time constant of 4 ms), to rest by 40 ms;
- pressure waves in the chamber on it (2.5 % of the pressure at 1.8 kHz,
  dying out within about 3 ms), and the sensor's noise (0.1 % of the peak);
sampled every 20 us, as a data-acquisition system would.
"""
from __future__ import annotations

import pathlib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
PEAK = 170e6          # Pa
IGNITION = 1e-3       # s after the trigger
RISE = 3.5e-3         # s from ignition to the peak
SHOT_EXIT = 8e-3      # s after ignition
BLOWDOWN = 4e-3       # s, time constant after shot exit
STEP, END = 20e-6, 40e-3


def shape(tau: np.ndarray) -> np.ndarray:
    """The chamber pressure over its peak, ``tau`` s after ignition."""
    x = np.maximum(tau, 0.0) / RISE
    rise = x ** 4 * np.exp(4.0 * (1.0 - x))
    fall = x ** 1.5 * np.exp(1.5 * (1.0 - x))
    xe = SHOT_EXIT / RISE
    exit_level = xe ** 1.5 * np.exp(1.5 * (1.0 - xe))
    blow = exit_level * np.exp(-(tau - SHOT_EXIT) / BLOWDOWN)
    return np.where(tau <= 0, 0.0, np.where(x <= 1, rise, np.where(tau <= SHOT_EXIT, fall, blow)))


def firing() -> tuple[np.ndarray, np.ndarray]:
    """(t, p): the trace's times (s) and pressures (Pa)."""
    t = np.round(np.arange(0.0, END + STEP / 2, STEP), 9)
    tau = t - IGNITION
    p = PEAK * shape(tau)
    waves = 0.025 * np.sin(2 * np.pi * 1.8e3 * np.maximum(tau, 0)) * np.exp(-np.maximum(tau, 0) / 3e-3)
    noise = np.random.default_rng(20261201).normal(0.0, 1e-3 * PEAK, t.size)
    return t, p * (1.0 + waves) + noise


def main():
    t, p = firing()
    text = "time [s],pressure [Pa]\n" + "".join(f"{a:.5f},{b:.0f}\n" for a, b in zip(t, p))
    for folder in ("pdbfs/data", "docs/data"):
        (ROOT / folder / "gun_firing.csv").write_text(text)
    print(f"peak {p.max() / 1e6:.2f} MPa at {t[np.argmax(p)] * 1e3:.2f} ms; {t.size} samples")


if __name__ == "__main__":
    main()
