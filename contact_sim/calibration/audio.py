"""Impact times from a sound recording of the bounces.

``bounce_times_from_audio(path)`` reads a WAV file in blocks (``wav.open_wav``: mono or stereo,
8/16/24/32-bit integer or 32/64-bit float) and finds the onset of every impact click, also when
the clicks come a few ms apart, each on the ringing tail of the one before:

1. high-pass (4th-order Butterworth at ``highpass`` Hz, zero phase): hard impacts are broadband
   clicks, while hum, voices and handling noise are mostly below 1-2 kHz;
2. two envelopes, each the rms over ``smooth`` s (channels averaged in power): of the high-passed
   signal (loudness), and of its prediction error by a linear predictor of order ``order``
   refitted every 1 ms to the 16 ms before (the innovation; ridge 1 % of the power).  The ringing of the ball and the plate, and the room's
   reverberation, are damped sinusoids, which a linear predictor follows: the prediction error
   stays at the noise while a click rings down and jumps at the next impact however loud the
   tail it lands on (a person hears that new crack, not a louder tone);
3. a click is where either envelope rises above ``threshold`` times its local noise floor (the
   10th percentile of its 5 ms rms over ``noise_window`` s) and above ``rise`` times its own
   maximum over the ``lookback`` s before (the tail of the previous click, which only decays);
   candidates at least ``refractory`` s apart (the strongest rise kept);
4. a click starting while the recording was clipped (full scale within ``lookback`` before it)
   is the clipped click itself, not a new one;
5. echoes and rattles: within ``gate`` s after an accepted click a candidate whose strength (its
   innovation peak) is below ``gate_ratio`` of that click's is left out; a spurious weak click,
   below ``weak`` of the strength of both its neighbours, is left out too (a real bounce is about
   as loud as the bounce before or after it);
6. the onset: from the click's peak (in the innovation when it stands well above the noise, else
   in the sharp Hilbert envelope of the high-passed signal) back to the last sample below
   ``onset_fraction`` of the rise from the level before, interpolated linearly.
7. the impacts: of the clicks heard, those that form a bounce sequence (``impact_sequence``:
   each the loudest sound for half the flights beside it, the flights shrinking by the
   restitution, the recording's echo lag); the others are returned with their reasons
   (``sequence=False``: every click heard).

Memory: the file is read and processed in blocks of ``block`` frames (2^19 by default, 11 s at
48 kHz), each with ``noise_window`` / 2 + 10 ms of neighbouring samples: about 25 float arrays
of one block, some 120 MB for mono, whatever the recording's length.

Returns ``AudioOnsets``: times (s from the start of the file), peak amplitudes (full scale = 1),
the clicks heard and those rejected (``summary()`` says how many, and why) and a confidence in [0, 1] per onset (from its signal-to-noise ratio and, for clicks that came
close to the echo gate, its margin above it).  A bounce below the noise is simply not found: the
bounce fit then names it a missed bounce.
"""
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import maximum_filter1d, percentile_filter, uniform_filter1d
from scipy.signal import butter, hilbert, sosfiltfilt

from contact_sim.calibration.impact_sequence import select_impacts, summary
from contact_sim.calibration.synthetic_audio import impact_click, synthesize_recording
from contact_sim.calibration.wav import MAX_CHANNELS, MAX_RATE, open_wav, read_wav, write_wav
from contact_sim.validation import (InputError, require_positive, require_range,
                                   require_real_array)

__all__ = ['AudioOnsets', 'bounce_times_from_audio', 'detect_onsets', 'impact_click',
           'read_wav', 'synthesize_recording', 'write_wav']

CLIP_LEVEL = 0.999        # |sample| at or above this (full scale 1) is clipped
CHUNK = 5e-3              # s, the noise floor's rms chunks
BLOCK = 1 << 19           # frames processed at once
RIDGE = 1e-2              # the predictor's ridge, relative to the signal's power
REACH = 6e-4              # s: an impact's crack peaks within this time of its onset
WEAK_WINDOW = 1.0         # s: a click this close after a louder one is compared with it
FRAME, FIT = 1e-3, 16e-3  # s: the predictor is refitted every FRAME to the FIT before it
MAX_SAMPLES = 1 << 28     # values of samples passed in memory, at most (2 GB of doubles)
HIGHPASS = 2000.0         # Hz, the high-pass corner by default
MAX_LEVEL = 1e6           # |sample| at most, full scale 1 (float recordings may exceed 1)


@dataclass(frozen=True)
class AudioOnsets:
    """Detected impacts: onset times (s), peak amplitudes (full scale 1), confidences (0-1),
    the sample rate (Hz) and the noise level (full scale) of the high-passed signal; ``found``,
    the clicks the detector heard, and ``rejected``, those that are not impacts of the bounce
    sequence (``impact_sequence.Rejected``: time, kind, reason)."""

    times: np.ndarray
    amplitudes: np.ndarray
    confidence: np.ndarray
    sample_rate: float
    noise: float
    found: int = 0
    rejected: tuple = ()

    def summary(self):
        """How many onsets were found, kept and rejected, and why (one line)."""
        return summary(self.found, self.times.size, self.rejected)


@dataclass(frozen=True)
class _Settings:
    rate: float
    highpass: float
    threshold: float
    rise: float
    lookback: float
    refractory: float
    gate: float
    gate_ratio: float
    weak: float
    onset_fraction: float
    smooth: float
    noise_window: float
    order: int


def bounce_times_from_audio(path, block=BLOCK, sequence=True, **settings):
    """Onsets of the impacts in the WAV file at ``path``, read ``block`` frames at a time.

    Parameters
    ----------
    path : str or path
        The WAV file.
    block : int
        Frames processed at once (bounds the memory: module doc), >= 4096.
    sequence : bool
        Keep only the clicks that are impacts of a bounce sequence (``impact_sequence``: echoes,
        ringing, precursors, clicks too quiet or off the sequence rejected, each with its
        reason in ``AudioOnsets.rejected``); False: every click heard.
    **settings
        The detector's settings, as ``detect_onsets``.

    Returns
    -------
    AudioOnsets

    Raises
    ------
    InputError
        The file cannot be read as WAV or holds a non-finite sample (``audio``), or a setting
        is out of range (named).

    Examples
    --------
    >>> import tempfile, os
    >>> from contact_sim.calibration import audio
    >>> path = os.path.join(tempfile.mkdtemp(), 'two.wav')
    >>> audio.write_wav(path, audio.synthesize_recording([0.1, 0.4], [0.5, 0.4]), 48000)
    >>> [round(float(t), 3) for t in audio.bounce_times_from_audio(path).times]
    [0.1, 0.4]
    """
    wav = open_wav(path)
    return _detect(wav.read, wav.frames, wav.rate, block, _settings(wav.rate, **settings),
                   sequence, 'audio')


def detect_onsets(samples, rate, highpass=2000.0, threshold=4.0, rise=1.5, lookback=2e-3,
                  refractory=1.5e-3, gate=0.03, gate_ratio=0.5, weak=0.25, onset_fraction=0.2,
                  smooth=2e-4, noise_window=1.0, order=16, block=BLOCK, sequence=True):
    """``bounce_times_from_audio`` on samples already read.

    Parameters
    ----------
    samples : array_like
        (n,) or (n, channels) finite real samples, full scale 1: at least 16 frames, 1 to
        ``MAX_CHANNELS`` (64) channels.
    rate : float
        Sample rate in Hz, 0 < rate <= 1e7 (``MAX_RATE``), above twice ``highpass``.
    highpass : float
        High-pass corner in Hz, 0 < highpass < rate / 2.
    threshold : float
        A click rises above this many times the local noise floor, > 1.
    rise : float
        ... and above this many times the envelope's maximum over ``lookback``, > 1.
    lookback : float
        s, > 0: the tail a new click must rise above (and the clipping looked for).
    refractory : float
        s, > 0: the least time between two clicks.
    gate, gate_ratio : float
        s >= 0 and 0 <= ratio <= 1: the echo gate (module doc).
    weak : float
        0 <= weak <= 1: a click below this share of both neighbours' strength is spurious.
    onset_fraction : float
        0 < fraction < 1: share of the rise that marks the onset.
    smooth : float
        s, > 0: the envelopes' rms window.
    noise_window : float
        s, > 0: the noise floor's window.
    order : int
        The linear predictor's order, 1 to 64.
    block : int
        Frames processed at once, >= 4096.
    sequence : bool
        As ``bounce_times_from_audio``; False: every click heard (not only a bounce sequence's).

    Returns
    -------
    AudioOnsets

    Raises
    ------
    InputError
        A setting out of range, or samples that are not finite reals in that shape, named
        with the allowed range.

    Examples
    --------
    >>> from contact_sim.calibration import audio
    >>> x = audio.synthesize_recording([0.1, 0.105, 0.3], [0.5, 0.45, 0.4], echo_gain=0.0)
    >>> [round(float(t), 4) for t in audio.detect_onsets(x, 48000, sequence=False).times]
    [0.1, 0.105, 0.3]
    """
    settings = _settings(rate, highpass, threshold, rise, lookback, refractory, gate, gate_ratio,
                         weak, onset_fraction, smooth, noise_window, order)
    x = _samples(samples)
    return _detect(lambda a, b: x[a:b], x.shape[0], settings.rate, block, settings, sequence)


def _samples(samples):
    """``samples`` as an (n, channels) float array, or an ``InputError`` on ``samples``."""
    x = require_real_array('samples', samples, max_size=MAX_SAMPLES)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or not 1 <= x.shape[1] <= MAX_CHANNELS:
        raise InputError('samples', None, '{n[samples]} has shape %s: allowed (n,) or (n, '
                         'channels) with 1 to %d channels (a (channels, n) array: pass its '
                         'transpose)' % (x.shape, MAX_CHANNELS))
    if x.shape[0] < 16:
        raise InputError('samples', x.shape[0], '{n[samples]} holds {value} frames: allowed a '
                         'recording of at least 16 frames')
    _level(x, 'samples', 0)
    return x


def _level(x, name, offset):
    """Refuse samples beyond ``MAX_LEVEL`` (their powers would overflow)."""
    big = np.abs(x) > MAX_LEVEL
    if big.any():
        at = offset + int(np.flatnonzero(big.any(axis=1))[0])
        raise InputError(name, None, '{n[%s]} holds a sample of %.3g at frame %d: allowed '
                         '|sample| <= %g (full scale 1)' % (name, float(np.abs(x).max()), at,
                                                           MAX_LEVEL))


def _settings(rate, highpass=2000.0, threshold=4.0, rise=1.5, lookback=2e-3, refractory=1.5e-3,
              gate=0.03, gate_ratio=0.5, weak=0.25, onset_fraction=0.2, smooth=2e-4,
              noise_window=1.0, order=16):
    if isinstance(rate, (str, bytes)):
        raise InputError('sample_rate', rate, '{n[sample_rate]} = {value} is text: allowed a '
                         'number, 0 < {n[sample_rate]} <= %g Hz' % MAX_RATE)
    rate = require_range('sample_rate', rate, 0.0, MAX_RATE, low_open=True)
    if highpass == HIGHPASS and rate <= 2.0 * HIGHPASS:     # the caller gave the rate only
        raise InputError('sample_rate', rate, '{n[sample_rate]} = {value} Hz is too low for the '
                         'high-pass at %g Hz: allowed %g < {n[sample_rate]} <= %g Hz (or a '
                         'lower highpass)' % (HIGHPASS, 2.0 * HIGHPASS, MAX_RATE))
    order = require_range('order', order, 1, 64)
    return _Settings(
        rate, require_range('highpass', highpass, 0.0, rate / 2.0, low_open=True, high_open=True),
        require_range('threshold', threshold, 1.0, low_open=True),
        require_range('rise', rise, 1.0, low_open=True), require_positive('lookback', lookback),
        require_positive('refractory', refractory), require_range('gate', gate, 0.0),
        require_range('gate_ratio', gate_ratio, 0.0, 1.0), require_range('weak', weak, 0.0, 1.0),
        require_range('onset_fraction', onset_fraction, 0.0, 1.0, low_open=True,
                      high_open=True),
        require_positive('smooth', smooth), require_positive('noise_window', noise_window),
        int(order))


def _detect(read, frames, rate, block, s, sequence=True, name='samples'):
    block = int(require_range('block', block, 4096))
    pad = int((s.noise_window / 2 + 0.01 + s.lookback) * rate)
    found, noise = [], []
    for start in range(0, frames, block):
        a, b = max(start - pad, 0), min(start + block + pad, frames)
        x = read(a, b)
        if not np.all(np.isfinite(x)):
            at = a + int(np.flatnonzero(~np.isfinite(x).all(axis=1))[0])
            raise InputError(name, None, '{n[%s]} holds a non-finite sample at frame %d: '
                             'allowed finite samples (full scale 1)' % (name, at))
        _level(x, name, a)
        cands, floor = _candidates(x, s)
        keep = (cands[:, 0] + a >= start) & (cands[:, 0] + a < start + block)
        cands = cands[keep]
        cands[:, 0] += a
        cands[:, 1] += a / rate
        found.append(cands)
        noise.append(floor)
    cands = np.concatenate(found) if found else np.zeros((0, 7))
    rows, conf = _accept(cands, s)
    heard, rejected = rows.shape[0], []
    if sequence and heard:
        kept, rejected = select_impacts(rows[:, 1], rows[:, 2])
        rows, conf = rows[kept], conf[kept]
    return AudioOnsets(rows[:, 1], rows[:, 3], conf, rate, float(np.median(noise)), heard,
                       tuple(rejected))


def _lpc_residual(y, order, frame, fit):
    """Prediction error of ``y`` by a linear predictor of order ``order`` refitted for every
    ``frame`` samples to the ``fit`` samples just before it (the tail the frame continues)."""
    n = y.size
    count = n // frame
    if count < 2 or fit <= 4 * order:
        return y
    # lag products' running sums: r_k over [start - fit, start) for every frame start
    starts = np.arange(count) * frame
    lo = np.maximum(starts - fit, 0)
    r = np.empty((count, order + 1))
    for k in range(order + 1):
        prod = np.zeros(n + 1)
        np.cumsum(y[k:] * y[:n - k], out=prod[k + 1:])
        prod[1:k + 1] = 0.0
        r[:, k] = prod[starts] - prod[np.minimum(lo + k, starts)]
    r[:, 0] = r[:, 0] * (1.0 + RIDGE) + 1e-30
    lags = np.abs(np.arange(order)[:, None] - np.arange(order)[None, :])
    try:
        a = np.linalg.solve(r[:, lags], r[:, 1:, None])[:, :, 0]       # (count, order)
    except np.linalg.LinAlgError:       # a degenerate signal: no prediction
        return y
    a[starts < fit] = 0.0                    # no tail before: no prediction
    which = np.minimum(np.arange(n) // frame, count - 1)
    e = y.copy()
    for k in range(1, order + 1):
        e[k:] -= a[which[k:], k - 1] * y[:n - k]
    return e


def _floor(env, rate, window):
    """Local noise floor: the 10th percentile of the 5 ms rms over ``window`` s."""
    m = max(int(CHUNK * rate), 1)
    count = max(env.size // m, 1)
    rms = np.sqrt(np.mean(env[:count * m].reshape(count, m) ** 2, axis=1))
    low = percentile_filter(rms, 10, size=max(int(window / CHUNK), 3), mode='nearest')
    full = np.repeat(low, m)
    full = np.concatenate([full, np.full(env.size - full.size, low[-1])])
    return np.maximum(full, 1e-12)


def _before(env, lookback, gap):
    """Maximum of ``env`` over [i - lookback, i - gap] samples, for each i."""
    size = max(lookback - gap, 1)
    m = maximum_filter1d(env, size, mode='nearest')
    shift = gap + size // 2
    return np.concatenate([np.full(shift, m[0]), m[:env.size - shift]])


def _mean_before(power, lookback, gap):
    """Mean of ``power`` over [i - lookback, i - gap] samples, for each i."""
    size = max(lookback - gap, 1)
    m = uniform_filter1d(power, size, mode='nearest')
    shift = gap + size // 2
    return np.concatenate([np.full(shift, m[0]), m[:power.size - shift]])


def _candidates(x, s):
    """Candidate clicks in one block: rows (index, onset s, strength, amplitude, snr) and the
    block's noise level (median floor of the high-passed envelope)."""
    rate = s.rate
    empty = np.zeros((0, 7))
    if x.shape[0] < 32:
        return empty, 0.0
    sos = butter(4, s.highpass, btype='highpass', fs=rate, output='sos')
    hp = sosfiltfilt(sos, x, axis=0)
    width = max(int(round(s.smooth * rate)), 1)
    env = np.sqrt(np.maximum(uniform_filter1d((hp * hp).mean(axis=1), width), 0.0))
    frame, fit = max(int(FRAME * rate), 1), max(int(FIT * rate), 4 * s.order + 1)
    res2 = np.mean([_lpc_residual(hp[:, c], s.order, frame, fit) ** 2
                    for c in range(hp.shape[1])], axis=0)
    res = np.sqrt(np.maximum(uniform_filter1d(res2, max(width // 3, 1)), 0.0))   # a spike
    look, gap = max(int(s.lookback * rate), 2), max(2 * width, 2)
    floors, scores = [], []
    tail_rms = np.sqrt(np.maximum(_mean_before(res2, look, gap), 0.0))
    env_before = _before(env, look, gap)
    for e, tail in ((env, env_before), (res, tail_rms)):
        floor = _floor(e, rate, s.noise_window)
        ref = np.maximum(tail, floor)
        ok = (e >= s.threshold * floor) & (e >= s.rise * ref)
        floors.append(floor)
        scores.append(np.where(ok, e / ref, 0.0))
    score = np.maximum(scores[0], scores[1])
    clipped = np.abs(x).max(axis=1) >= CLIP_LEVEL
    if clipped.any():
        recent = _before(clipped.astype(float), look, gap) > 0
        score[recent] = 0.0
    peaks = _peaks(score, max(int(s.refractory * rate), 1))
    fine = np.sqrt((np.abs(hilbert(hp, axis=0)) ** 2).mean(axis=1))
    sharp = np.sqrt(res2)
    rows = []
    near = max(int(0.75e-3 * rate), gap + 1)    # the onset lies this close before the peak
    reach = max(int(REACH * rate), 1)
    for p in peaks:
        lo, hi = max(p - near, 1), min(p + gap + 1, x.shape[0])
        # the innovation's energy over the click's first ms, above the noise's
        energy = float(res2[p - gap if p >= gap else 0:p + look // 2].sum())
        noise_energy = (look // 2 + gap) * float(floors[1][p]) ** 2
        strength = max(energy - noise_energy, 0.0) ** 0.5
        amp = float(np.abs(hp[p - gap if p >= gap else 0:min(p + look, x.shape[0])]).max())
        onset = _first_rise(sharp, res2, lo, hi, look, s.onset_fraction, reach)
        if onset is None:
            onset = _onset(fine, lo, hi, s.onset_fraction)
        snr = max(env[p] / floors[0][p], res[p] / floors[1][p])
        top = float(env[p - gap if p >= gap else 0:p + look // 2].max())
        # the tail the click rises from: its highest over the lookback (a beating ring's
        # next swell does not rise above the swell before it)
        level = max(float(env[max(int(onset) - gap, 0)]), float(env_before[p]))
        rows.append((p, onset / rate, strength, amp, snr, top, max(top - level, 0.0)))
    return (np.array(rows) if rows else empty), float(np.median(floors[0]))


def _peaks(score, distance):
    """Indices of the local maxima of ``score`` > 0, at least ``distance`` apart (greedy by
    height, like ``scipy.signal.find_peaks``'s distance rule)."""
    idx = np.flatnonzero(score > 0)
    if idx.size == 0:
        return idx
    # runs of consecutive positive samples: one maximum each, then the distance rule
    splits = np.flatnonzero(np.diff(idx) > 1) + 1
    tops = np.array([run[np.argmax(score[run])] for run in np.split(idx, splits)])
    order = np.argsort(-score[tops], kind='stable')
    taken = np.zeros(tops.size, bool)
    blocked = np.zeros(tops.size, bool)
    for k in order:
        if blocked[k]:
            continue
        taken[k] = True
        near = np.abs(tops - tops[k]) < distance
        blocked |= near
    return np.sort(tops[taken])


def _first_rise(sharp, power, lo, hi, look, fraction, reach):
    """Fractional sample where the innovation ``sharp`` first exceeds both ``fraction`` of its
    peak in [lo, hi) and 4 times its rms over the ``look`` samples before ``lo``, at most
    ``reach`` samples before that peak; None if never."""
    seg = sharp[lo:hi]
    q = int(np.argmax(seg))
    before = float(np.sqrt(np.mean(power[max(lo - look, 0):lo]))) if lo > 0 else 0.0
    target = max(fraction * float(seg[q]), 4.0 * before)
    first = max(q - reach, 0)            # the crack peaks within ``reach`` of the onset
    above = np.flatnonzero(seg[first:q + 1] >= target)
    if above.size == 0:
        return None
    j = lo + first + int(above[0])
    a, b = float(sharp[j - 1]), float(sharp[j])
    frac = (target - a) / (b - a) if b > a else 1.0
    return j - 1 + min(max(frac, 0.0), 1.0)


def _onset(signal, lo, hi, fraction):
    """Fractional sample where ``signal`` last rises through ``fraction`` of its rise (from its
    level at ``lo`` to its peak in [lo, hi)) before that peak."""
    seg = signal[lo:hi]
    q = int(np.argmax(seg))
    base = float(np.median(signal[max(lo - (hi - lo), 0):lo + 1]))
    target = base + fraction * (float(seg[q]) - base)
    below = np.flatnonzero(seg[:q + 1] < target)
    if below.size == 0:
        return float(lo)
    j = min(int(below[-1]), seg.size - 2)
    a, b = float(seg[j]), float(seg[j + 1])
    frac = (target - a) / (b - a) if b > a else 0.0
    return lo + j + min(max(frac, 0.0), 1.0)


def _accept(cands, s):
    """Refractory (of two clicks closer than it, the louder), echo gate and weak-click rules
    over all candidates (rows sorted by index)."""
    cands = cands[np.argsort(cands[:, 0], kind='stable')]
    kept, conf = [], []
    last_t, last_strength, last_amp, last_top = -np.inf, 0.0, 0.0, 0.0
    for row in cands:
        t, strength = row[1], row[2]
        margin = 1.0
        if t - last_t < s.refractory:
            if kept and strength > last_strength:
                # the same click heard twice (its onsets closer than its peaks): the louder
                kept[-1] = row
                conf[-1] = float(np.clip(1.0 - s.threshold / row[4], 0.0, 1.0))
                last_t, last_strength, last_amp, last_top = t, strength, row[3], row[5]
            continue
        if t - last_t < WEAK_WINDOW and row[3] < s.weak * last_amp:
            continue          # far quieter than the click before: a rattle or a tick
        if t - last_t < s.gate:
            # an echo, a rattle or the ring of the click before: neither its crack (innovation)
            # nor its rise above the tail reaches gate_ratio of that click's
            ratio = max(strength / last_strength, row[6] / last_top)
            if ratio < s.gate_ratio:
                continue
            if s.gate_ratio > 0:
                margin = min(1.0, ratio / s.gate_ratio - 1.0)
        kept.append(row)
        conf.append(float(np.clip(1.0 - s.threshold / row[4], 0.0, 1.0)) * margin)
        last_t, last_strength, last_amp, last_top = t, strength, row[3], row[5]
    if not kept:
        return np.zeros((0, 7)), np.zeros(0)
    return np.array(kept), np.array(conf)
