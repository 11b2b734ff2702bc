"""Synthetic bounce recordings made by the package (its tests and examples): clicks shaped like
hard-ball impacts with an echo, room noise and hum.  The onset detector's own tests use an
independent generator (test/calibration/click_recordings.py)."""
import math

import numpy as np


def impact_click(rate, duration=0.04, rise=1e-4, rng=None):
    """One impact click shaped like a hard-ball impact: a broadband burst rising in ``rise`` s
    (a few resonances 3-9 kHz, decay 1-4 ms) plus the ball's ringing (1.2-2 kHz, 15 ms)."""
    rng = rng if rng is not None else np.random.default_rng(0)
    n = int(duration * rate)
    t = np.arange(n) / rate
    attack = 1.0 - np.exp(-t / rise)
    burst = np.zeros(n)
    for f, tau in zip(rng.uniform(3000.0, 9000.0, 4), rng.uniform(1e-3, 4e-3, 4)):
        burst += np.sin(2 * math.pi * f * t + rng.uniform(0, 2 * math.pi)) * np.exp(-t / tau)
    ring = 0.3 * np.sin(2 * math.pi * rng.uniform(1200.0, 2000.0) * t) * np.exp(-t / 0.015)
    click = attack * (burst + ring)
    return click / np.max(np.abs(click))


def synthesize_recording(times, amplitudes, rate=48000, duration=None, noise=0.002,
                         echo_delay=0.008, echo_gain=0.35, hum=0.02, seed=0):
    """A mono recording of clicks starting at ``times`` (s) with peak ``amplitudes`` (full
    scale), room noise (white, ``noise`` rms, and mains hum at 50 Hz), and one echo of every
    click ``echo_delay`` s later at ``echo_gain``.  Returns float samples in [-1, 1]."""
    rng = np.random.default_rng(seed)
    times = np.asarray(times, dtype=float)
    end = duration if duration is not None else float(times.max()) + 0.2
    n = int(end * rate)
    x = rng.normal(0.0, noise, n) + hum * np.sin(2 * math.pi * 50.0 * np.arange(n) / rate)
    for t0, amp in zip(times, amplitudes):
        click = impact_click(rate, rng=rng) * amp
        for delay, gain in ((0.0, 1.0), (echo_delay, echo_gain)):
            # the click starts between samples: shift by the fraction with a sinc-free
            # linear interpolation of its own samples
            start = (t0 + delay) * rate
            i0 = int(math.ceil(start))
            frac = i0 - start
            k = np.arange(click.size - 1)
            shifted = click[k] + frac * (click[k + 1] - click[k])
            seg = slice(i0, min(i0 + shifted.size, n))
            x[seg] += gain * shifted[:seg.stop - seg.start]
    return np.clip(x, -1.0, 1.0)
