"""Whether any law fitted describes a recording: the best fit's timing error (its robust noise
estimate or its weighted rms residual, whichever is larger) against what the recording itself
allows.

Two yardsticks, neither of them a law:

* the clock: the timing resolution Δ (a click cannot be timed better than Δ/√12), and a detector
  that times its onsets to a few tens of Δ (< 0.35 ms at 48 kHz): a fit whose error exceeds
  ``RESOLUTION_FACTOR`` Δ is beyond any detector error;
* the recording's own scatter: in each run of at least ``OWN_MIN_FLIGHTS`` consecutive single
  flights, the third differences of ln(flight) over the bounce number (zero for a restitution
  that changes smoothly with speed, whatever the law), turned into click-time errors, have a
  robust scale: the scatter of the clicks about *some* smooth sequence.  A fit error ``OWN_FACTOR`` times that misses a
  trend of the data, not their noise.

A fit is inadequate when its error exceeds both ``RESOLUTION_FACTOR`` Δ and ``OWN_FACTOR`` times
the recording's own scatter.  The reason then names the trend if the flights show one the laws
cannot follow: a restitution (flight ratio) that rises with the impact speed when every law
fitted has one that falls with speed or stays.
Units: SI.
"""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.calibration.restitution_table import restitution_curve

RESOLUTION_FACTOR = 100.0    # fit error above this many clock resolutions: not detector error
OWN_FACTOR = 5.0             # fit error above this many times the recording's own scatter
OWN_MIN_FLIGHTS = 5          # single flights in a row needed for the recording's own scatter
TREND_T = 3.0                # |t| of the e(v) slope above which a trend is named


@dataclass(frozen=True)
class Adequacy:
    """The verdict of ``check_adequacy`` (times in s).

    ``adequate`` is False when no law fitted describes the recording; ``reason`` says why (or
    what it was checked against); ``own_noise`` (s) is nan when no run is long enough."""

    adequate: bool
    error: float             # the best fit's timing error: max(robust noise, weighted rms)
    resolution: float
    own_noise: float
    reason: str


def _single_runs(seq):
    """Runs of consecutive single flights (arrays of flight times, s) of a prepared sequence."""
    runs, current = [], []
    for i in range(seq.times.size - 1):
        if seq.index[i + 1] - seq.index[i] == 1:
            current.append(float(seq.times[i + 1] - seq.times[i]))
        else:
            runs.append(current)
            current = []
    runs.append(current)
    return [np.array(r) for r in runs if r]


def own_scatter(sequences):
    """The recordings' own timing scatter (s), law-free (module doc), or nan.

    Parameters
    ----------
    sequences : list of PreparedSequence

    Returns
    -------
    float
        The robust scale (1.4826 × MAD) of the click times' errors from the third differences
        of ln(flight) (module doc), or nan if no run has ``OWN_MIN_FLIGHTS`` single flights.
    """
    residuals = []
    for seq in sequences:
        for flights in _single_runs(seq):
            if flights.size < OWN_MIN_FLIGHTS:
                continue
            # δ ln T_i = (ε_{i+1} - ε_i) / T_i: the third difference of ln T is a fourth
            # difference of the click errors ε (variance 70 σ²) over the local flight time
            local = np.sqrt(flights[1:-2] * flights[2:-1])
            residuals.extend(np.diff(np.log(flights), 3) * local / math.sqrt(70.0))
    if not residuals:
        return math.nan
    r = np.array(residuals)
    return 1.4826 * float(np.median(np.abs(r - np.median(r))))


def speed_trend(sequences, gravity):
    """The slope de/dv (s/m) of the flight ratios against the impact speed, and its t value.

    e ≈ T_{i+1}/T_i and v ≈ g T_i / 2 over consecutive single flights (vacuum, no contact time:
    a trend detector, not a measurement).

    Parameters
    ----------
    sequences : list of PreparedSequence
    gravity : float
        g in m/s^2.

    Returns
    -------
    (float, float, float, float)
        Slope, its t value, and the lowest and highest speed (m/s); nan if fewer than 4 ratios.
    """
    v, e = [], []
    for seq in sequences:
        for flights in _single_runs(seq):
            v.extend(0.5 * gravity * flights[:-1])
            e.extend(flights[1:] / flights[:-1])
    if len(v) < 4:
        return math.nan, math.nan, math.nan, math.nan
    v, e = np.array(v), np.array(e)
    slope, offset = np.polyfit(v, e, 1)
    r = e - (slope * v + offset)
    spread = float(np.sum((v - v.mean()) ** 2))
    se = math.sqrt(float(np.sum(r * r)) / (v.size - 2) / spread) if spread > 0.0 else math.inf
    t = float(slope) / se if se > 0.0 else math.copysign(math.inf, float(slope))
    return float(slope), t, float(v.min()), float(v.max())


def check_adequacy(fit):
    """Whether any law fitted describes the recording (module doc).

    Parameters
    ----------
    fit : BounceFit

    Returns
    -------
    Adequacy
    """
    best, resolution = fit.best, fit.timing_resolution
    error = max(best.noise, best.rms)     # the robust noise, or the weighted rms if larger
    own = own_scatter(fit.sequences)
    own_text = f'{own * 1e3:.3g} ms' if math.isfinite(own) else 'unknown (no run of ' \
        f'{OWN_MIN_FLIGHTS} single flights)'
    against = (f'timing error {error * 1e3:.3g} ms against the clock resolution '
               f'{resolution * 1e3:.3g} ms and the recording\'s own scatter {own_text}')
    too_noisy = error > RESOLUTION_FACTOR * resolution and not (
        math.isfinite(own) and error <= OWN_FACTOR * own)
    if not too_noisy:
        return Adequacy(True, error, resolution, own, against)
    reason = (f'no law here describes this recording: the best fit ({best.law.name}) has '
              f'{against}, more than {RESOLUTION_FACTOR:g} resolutions' +
              (f' and {OWN_FACTOR:g} times its own scatter' if math.isfinite(own) else ''))
    slope, t, v_low, v_high = speed_trend(fit.sequences, fit.gravity)
    if math.isfinite(t) and t > TREND_T:
        rising = [f.law.name for f in fit.fits
                  if float(restitution_curve(f, fit.mass, v_high))
                  > float(restitution_curve(f, fit.mass, v_low))]
        if not rising:
            reason += (f'; the restitution rises with speed (flight ratios {slope:+.3g} s/m '
                       f'from {v_low:.3g} to {v_high:.3g} m/s, t = {t:.1f}), which no law '
                       'fitted can follow (their e falls with speed or stays)')
    return Adequacy(False, error, resolution, own, reason)
