"""Synthetic bounce recordings for the onset detector's tests and benchmark.

Written apart from ``contact_sim.calibration.audio`` on purpose (no code shared with the detector
or the package's own ``synthesize_recording``): a recording here is

* a bouncing-ball sequence: the first flight ``first_interval`` s, each next one ``e`` times the
  one before, down to ``min_interval`` s (300 ms to 5 ms with e = 0.9: 40 impacts); each impact's
  loudness proportional to the impact speed, i.e. to the flight before it, with a 10 % scatter;
* every click the impulse response of the ball and plate: one to three damped sinusoids (2.5 to
  12 kHz, decays drawn in [``decay_low``, ``decay_high``] s, 0.5 to 20 ms), started at rest with
  a rise of 30 to 150 µs, each mode's frequency shifted by up to 1 % from click to click, plus a
  low ring (600 to 1500 Hz) and an impulsive broadband part;
* room noise: white, its rms ``quietest_snr`` times below the quietest impact's peak (the last
  impacts are the quiet ones: 60 times below the first with e = 0.9); a low rumble (below 300 Hz, 5 × the white noise) and 50 Hz
  hum;
* one spurious weak click (a tick of 8 % of its neighbours' loudness, another shape) in the middle
  of a flight, which is not an impact;
* clipping at full scale: the first impacts are made ``loudness`` times full scale when it is > 1.

The failure modes of real recordings (issue 32), each optional (``make_recording``'s keywords):

* ``echo_lag``, ``echo_gain``: every impact heard again ``echo_lag`` s later (a reflection from
  a surface near the microphone), ``echo_gain`` times as loud, slightly low-passed;
* ``rattle``: the ringing of a hollow ball: after each impact, a burst of small cracks (one every
  1.5-4 ms, random) decaying over ``rattle`` s from a fifth of the impact's loudness, each a new
  onset for a detector;
* ``spurious_count`` spurious clicks between impacts (one per flight chosen at random), of
  ``spurious_ratio`` of their neighbours' loudness (the first one is ``spurious``);
* ``pre_click``: a click ``pre_click`` s before the first impact at a tenth of its loudness (a
  hand, the release).

``score(found, true)`` gives recall, false clicks and timing errors: a true click is found when an
onset lies within 2 ms of it (each onset used once).
"""
import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Recording:
    samples: np.ndarray      # (n,) in [-1, 1]
    rate: float
    times: np.ndarray        # true impact onsets, s
    spurious: float          # the weak click's onset, s (not an impact)
    modes: tuple             # the clicks' (frequencies Hz, decays s, weights)
    others: np.ndarray = None   # onsets of every click that is not an impact, s


def ball_times(first_interval=0.3, e=0.9, min_interval=0.005, start=0.25):
    intervals = []
    interval = first_interval
    while interval >= min_interval:
        intervals.append(interval)
        interval *= e
    return start + np.concatenate([[0.0], np.cumsum(intervals)]), np.array(intervals)


def _modes(rng, decay_low, decay_high):
    count = int(rng.integers(1, 4))
    freqs = rng.uniform(2500.0, 12000.0, count)
    decays = np.exp(rng.uniform(math.log(decay_low), math.log(decay_high), count))
    weights = rng.uniform(0.3, 1.0, count)
    return freqs, decays, weights / weights.sum()


def _click(rng, rate, t0, length, modes, jitter=0.01):
    """Samples of one click starting at t0 (s) on a grid of ``length`` s after floor(t0)."""
    freqs, decays, weights = modes
    i0 = int(math.floor(t0 * rate))
    n = int(length * rate)
    t = (i0 + np.arange(n)) / rate - t0
    on = t >= 0.0
    tt = np.where(on, t, 0.0)
    rise = rng.uniform(3e-5, 1.5e-4)
    y = np.zeros(n)
    for f, tau, w in zip(freqs, decays, weights):
        f = f * (1.0 + rng.uniform(-jitter, jitter))
        y += w * np.sin(2 * math.pi * f * tt) * np.exp(-tt / tau)
    low = rng.uniform(600.0, 1500.0)
    y += 0.3 * np.sin(2 * math.pi * low * tt) * np.exp(-tt / 0.01)
    y += 0.3 * rng.normal(0.0, 1.0, n) * np.exp(-tt / 2e-4)        # the impact's own crack
    y *= (1.0 - np.exp(-tt / rise)) * on
    return i0, y


def make_recording(seed=0, rate=48000, e=0.9, first_interval=0.3, min_interval=0.005,
                   decay_low=5e-4, decay_high=2e-2, quietest_snr=10.0, loudness=0.6,
                   spurious_ratio=0.08, echo_lag=None, echo_gain=0.5, rattle=0.0,
                   spurious_count=1, pre_click=None, rattle_gain=0.2):
    rng = np.random.default_rng(seed)
    times, intervals = ball_times(first_interval, e, min_interval)
    times = times + rng.uniform(0.0, 0.05) + (pre_click or 0.0)
    flights = np.concatenate([[first_interval / e], intervals])
    amps = loudness * flights / flights[0] * rng.uniform(0.9, 1.1, flights.size)
    noise = float(amps.min()) / quietest_snr
    duration = times[-1] + 0.3 + max(rattle, echo_lag or 0.0)
    n = int(duration * rate)
    x = rng.normal(0.0, noise, n)
    rumble = np.cumsum(rng.normal(0.0, 1.0, n))
    rumble -= np.convolve(rumble, np.ones(201) / 201, mode='same')   # below ~300 Hz, no drift
    rumble *= 5 * noise / max(float(np.std(rumble)), 1e-12)
    x += rumble + 0.01 * np.sin(2 * math.pi * 50.0 * np.arange(n) / rate)
    modes = _modes(rng, decay_low, decay_high)
    length = min(8 * float(modes[1].max()) + 0.02, 0.25)
    others = []

    def add(t0, amp, shape, span, smooth=1):
        i0, y = _click(rng, rate, t0, span, shape)
        if smooth > 1:
            y = np.convolve(y, np.ones(smooth) / smooth, mode='same')
        stop = min(i0 + y.size, n)
        x[i0:stop] += amp * y[:stop - i0]

    tick = (np.array([9000.0]), np.array([3e-4]), np.array([1.0]))
    for t0, amp in zip(times, amps):
        add(t0, amp, modes, length)
        if echo_lag:
            add(t0 + echo_lag, echo_gain * amp, modes, length, smooth=3)
            others.append(t0 + echo_lag)
        t = t0 + rng.uniform(1.5e-3, 4e-3) if rattle else math.inf
        while t < t0 + rattle:
            add(t, rattle_gain * amp * math.exp(-(t - t0) / (rattle / 4)), tick, 0.004)
            others.append(t)
            t += rng.uniform(1.5e-3, 4e-3)
    # the spurious ticks: the first in the middle of the longest flight after the third impact
    spurious = []
    k = 3 + int(rng.integers(0, 5))
    chosen = [k]
    if spurious_count > 1:
        rest = np.setdiff1d(np.arange(1, times.size - 2), [k])
        chosen += list(rng.choice(rest, spurious_count - 1, replace=False))
    for k in chosen[:spurious_count]:
        t_sp = 0.5 * (times[k] + times[k + 1]) + rng.uniform(-0.02, 0.02) * min(
            1.0, 10.0 * (times[k + 1] - times[k]))
        add(t_sp, spurious_ratio * 0.5 * (amps[k] + amps[k + 1]), tick, 0.01)
        spurious.append(t_sp)
    if pre_click:
        add(times[0] - pre_click, 0.1 * amps[0], tick, 0.01)
        others.append(times[0] - pre_click)
    return Recording(np.clip(x, -1.0, 1.0), float(rate), times,
                     float(spurious[0]) if spurious else math.nan, modes,
                     np.sort(np.array(others + spurious)))


def score(found, true, tolerance=2e-3):
    """(recall, false clicks per true click, timing errors of the found clicks in s)."""
    found = np.sort(np.asarray(found, dtype=float))
    used = np.zeros(found.size, bool)
    errors = []
    for t in true:
        if found.size == 0:
            break
        j = int(np.argmin(np.where(used, np.inf, np.abs(found - t))))
        if not used[j] and abs(found[j] - t) <= tolerance:
            used[j] = True
            errors.append(found[j] - t)
    recall = len(errors) / len(true)
    false = (found.size - used.sum()) / len(true)
    return recall, false, np.abs(np.array(errors))
