"""Whether a law fitted describes a recording, judged against the recording's own scatter.

Read bounce by bounce, a recording is a set of restitutions e_i at impact speeds v_i (each
flight corrected for the drag and the contact time, ``restitution_table.restitution_rows``).  A
law that is right leaves residuals e_i - e_law(v_i) as large as the recording's own scatter,
and no more: that scatter (the ball's bounce-to-bounce variation and the clock's) is what a
smooth curve e(v) with a free level, slope and curvature leaves, the law-free reference.  It is
estimated robustly (a Huber fit of a quadratic in v, scale 1.4826 MAD) and never below what the
clock alone gives, σ_e = e √(1/T_i² + 1/T_{i+1}²) Δ/√6 for a resolution Δ.  Points more than
``OUTLIER_SCALES`` own scatters off that curve are detector glitches for both, and left out.

* Without a hold-out, the law is nested-tested against the curve: the extra squared residual it
  leaves, per the curve's three extra parameters, over the curve's own variance is F(3, n - 3)
  distributed when the law is right; a p value below ``P_INADEQUATE`` says it is not.
* With a hold-out, the verdict is the hold-out's: the law fitted on the earlier clicks predicts
  the held-out flights' e; their squared residuals over the own variance are χ²(n_held) when it
  is right.  That variance is, per flight, the larger of the scatter and what the click times'
  noise gives there (the law-free residuals in units of the clock's σ_e, which grows as the
  flights shorten), plus the training fit's own prediction spread.  (The click times' hold-out rms is printed too; it accumulates every bounce's
  scatter, so it is no test by itself.)

A constant e with ordinary bounce-to-bounce scatter therefore passes; a trend the law cannot
follow fails, and the reason names it: the slope of the measured e against v, and of the law's,
over every flight kept (held out or not: the trend is the recording's).
``own_scatter`` (the click times' law-free scatter, s) is kept for the report.
Units: SI.
"""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.calibration.restitution_table import restitution_curve, restitution_rows

OWN_MIN_FLIGHTS = 5          # single flights in a row needed for the click times' own scatter
MIN_POINTS = 6               # restitutions needed to judge a law (3 for the curve, 3 to spare)
OUTLIER_SCALES = 5.0         # e this many own scatters off the law-free curve: a glitch
P_INADEQUATE = 1e-3          # a law whose misfit is this improbable does not describe the data
TREND_T = 3.0                # |t| of the e(v) slope above which a trend is named


@dataclass(frozen=True)
class Adequacy:
    """The verdict of ``check_adequacy``.

    ``adequate`` is False when the law judged (the best) does not describe the recording;
    ``reason`` says why, or what it was checked against.  ``error`` (s) is the best fit's
    timing error, ``own_noise`` (s) the click times' law-free scatter (nan when no run is long
    enough); ``scatter`` is the recording's own scatter of e, ``misfit`` the law's rms e
    residual on the points judged, ``p_value`` the test's; ``judged_on`` is ``'fit'`` or
    ``'hold-out'`` (or ``'none'``: too few flights to judge)."""

    adequate: bool
    error: float
    resolution: float
    own_noise: float
    reason: str
    scatter: float = math.nan
    misfit: float = math.nan
    p_value: float = math.nan
    judged_on: str = 'fit'
    points: int = 0


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
    """The click times' own timing scatter (s), law-free, or nan.

    In each run of at least ``OWN_MIN_FLIGHTS`` consecutive single flights the third
    differences of ln(flight) over the bounce number (zero for a restitution that changes
    smoothly with speed, whatever the law) are turned into click-time errors.

    Parameters
    ----------
    sequences : list of PreparedSequence

    Returns
    -------
    float
        The robust scale (1.4826 × MAD) of those errors, or nan if no run is long enough.
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


def _flights(fit):
    """The flight before and after each impact of ``restitution_rows`` (s), keyed (j, bounce)."""
    out = {}
    for j, seq in enumerate(fit.sequences):
        for i in range(1, seq.times.size - 1):
            if seq.index[i + 1] - seq.index[i - 1] == 2:
                out[(j, int(seq.index[i + 1]))] = (float(seq.times[i] - seq.times[i - 1]),
                                                   float(seq.times[i + 1] - seq.times[i]))
    return out


def law_free_curve(v, e, floor):
    """The law-free reference: a robust (Huber) quadratic e(v) and its residual scale.

    Parameters
    ----------
    v, e : numpy.ndarray
        Impact speeds (m/s) and restitutions, at least 4.
    floor : numpy.ndarray
        The clock's σ_e of each point, the least scatter there can be.

    Returns
    -------
    (numpy.ndarray, float)
        The residuals e - curve(v) and the scale (never below the median ``floor``).
    """
    x = (v - v.mean()) / max(float(np.ptp(v)), 1e-12)
    basis = np.vander(x, 3)
    w = np.ones_like(e)
    low = float(np.median(floor))
    scale = low
    for _ in range(8):
        coef = np.linalg.lstsq(basis * w[:, None], e * w, rcond=None)[0]
        r = e - basis @ coef
        scale = max(1.4826 * float(np.median(np.abs(r))) * math.sqrt(e.size / (e.size - 3.0)),
                    low)
        w = np.sqrt(np.minimum(1.0, 1.5 * scale / np.maximum(np.abs(r), 1e-300)))
    return r, scale


def _timing_scale(free, floor):
    """The law-free residuals' robust scale in units of each point's clock floor: the held-out
    flights are the shortest, where the click times' noise scatters e the most (σ_e ∝ 1/T), so
    a scatter read as one number over all flights would understate theirs."""
    ratio = np.abs(free) / floor
    return 1.4826 * float(np.median(ratio)) * math.sqrt(ratio.size / max(ratio.size - 3.0, 1.0))


def _trend(v, y):
    """Slope of y against v and its t value (nan for fewer than 4 points or one speed)."""
    if v.size < 4 or np.ptp(v) <= 0.0:
        return math.nan, math.nan
    slope, offset = np.polyfit(v, y, 1)
    r = y - (slope * v + offset)
    se = math.sqrt(float(np.sum(r * r)) / (v.size - 2) / float(np.sum((v - v.mean()) ** 2)))
    return float(slope), (float(slope) / se if se > 0.0 else math.copysign(math.inf, slope))


def _prediction_spread(law_fit, mass, speeds):
    """The standard error of a fitted law's e(v) from its λ's interval (taken as 95 %, ±1.96
    standard errors in ln λ): what the training fit's own uncertainty adds to a prediction."""
    from dataclasses import replace
    low, high = law_fit.damping_interval
    base = np.asarray(restitution_curve(law_fit, mass, speeds), dtype=float)
    if not (math.isfinite(low) and math.isfinite(high) and high > low > 0.0):
        return np.zeros_like(base)
    shifted = replace(law_fit, damping=law_fit.damping * math.exp(math.log(high / low) / 3.92))
    return np.abs(np.asarray(restitution_curve(shifted, mass, speeds), dtype=float) - base)


def check_adequacy(fit):
    """Whether the best law describes the recording (module doc).

    Parameters
    ----------
    fit : BounceFit
        With its ``holdout`` when one was asked for (the verdict is then the hold-out's).

    Returns
    -------
    Adequacy
    """
    from scipy.stats import chi2, f as fisher
    best, resolution = fit.best, fit.timing_resolution
    error = max(best.noise, best.rms)
    own = own_scatter(fit.sequences)
    held = None
    if fit.holdout:
        held = next(h for h in fit.holdout if h.law is best.law)
    judged = held.fit if held is not None else best
    rows = restitution_rows(fit, judged)
    flights = _flights(fit)
    rows = [r for r in rows if (r[0], r[1]) in flights and math.isfinite(r[3])]
    base = dict(error=error, resolution=resolution, own_noise=own)
    if len(rows) < MIN_POINTS:
        return Adequacy(True, reason=f'not judged: {len(rows)} restitution(s) read from '
                        f'consecutive single flights, {MIN_POINTS} needed', judged_on='none',
                        points=len(rows), **base)
    j, bounce, v, e, _ = (np.array(c, dtype=float) for c in zip(*rows))
    t_before, t_after = (np.array(c) for c in zip(*(flights[(int(a), int(b))]
                                                     for a, b in zip(j, bounce))))
    floor = e * np.sqrt(1.0 / t_before ** 2 + 1.0 / t_after ** 2) * resolution / math.sqrt(6.0)
    free, scatter = law_free_curve(v, e, floor)
    keep = np.abs(free) <= OUTLIER_SCALES * scatter
    d = e - np.asarray(restitution_curve(judged, fit.mass, v), dtype=float)
    if held is not None:
        first_held = {k: int(s.index[0]) for k, s in enumerate(held.held)}
        on = keep & np.array([b >= first_held[int(k)] for k, b in zip(j, bounce)])
        n = int(on.sum())
        if n == 0:
            return Adequacy(True, reason='not judged: no held-out restitution (the held-out '
                            'clicks hold no two consecutive single flights)',
                            scatter=scatter, judged_on='none', **base)
        spread = _prediction_spread(judged, fit.mass, v[on])
        own = np.maximum(scatter, _timing_scale(free[keep], floor[keep]) * floor[on])
        stat = float(np.sum(d[on] ** 2 / (own ** 2 + spread ** 2)))
        p = float(chi2.sf(stat, n))
        where = f'on {n} held-out restitution(s), the law fitted on the earlier clicks'
    else:
        on = keep
        n = int(on.sum())
        ssr_free = max(float(np.sum(free[on] ** 2)), (n - 3) * float(np.median(floor)) ** 2)
        extra = max(float(np.sum(d[on] ** 2)) - ssr_free, 0.0)
        stat = extra / 3.0 / (ssr_free / (n - 3)) if n > 3 else math.nan
        p = float(fisher.sf(stat, 3, n - 3)) if n > 3 else math.nan
        where = f'on {n} restitution(s)'
    misfit = math.sqrt(float(np.mean(d[on] ** 2))) if n else math.nan
    dropped = int((~keep).sum())
    against = (f'{best.law.name} leaves an rms e residual of {misfit:.3g} against the '
               f'recording\'s own scatter {scatter:.3g} {where} (p = {p:.2g}'
               + (f'; {dropped} glitch(es) beyond {OUTLIER_SCALES:g} scatters left out'
                  if dropped else '') + f'); timing error {error * 1e3:.3g} ms')
    verdict = dict(scatter=scatter, misfit=misfit, p_value=p,
                   judged_on='hold-out' if held is not None else 'fit', points=n, **base)
    if not p < P_INADEQUATE:
        return Adequacy(True, reason=against, **verdict)
    reason = f'{best.law.name} does not describe this recording: {against}'
    # the trend is the recording's: read from every flight kept, held out or not
    slope, t = _trend(v[keep], e[keep])
    law_slope, _ = _trend(v[keep], e[keep] - d[keep])
    if math.isfinite(t) and abs(t) > TREND_T:
        lo, hi = float(v[keep].min()), float(v[keep].max())
        rising = [f.law.name for f in fit.fits
                  if float(restitution_curve(f, fit.mass, hi))
                  > float(restitution_curve(f, fit.mass, lo))]
        way = 'rises' if slope > 0.0 else 'falls'
        reason += (f'; the restitution {way} with speed ({slope:+.3g} s/m from {lo:.3g} to '
                   f'{hi:.3g} m/s, t = {t:.1f}), the law\'s by {law_slope:+.3g} s/m')
        if slope > 0.0 and not rising:
            reason += ': no law fitted can follow it (their e falls with speed or stays)'
    return Adequacy(False, reason=reason, **verdict)
