"""Impact times from a sound recording of the bounces, and synthetic recordings to test it.

``bounce_times_from_audio(path)`` reads a WAV file (``scipy.io.wavfile``: mono or stereo, 8/16/
24/32-bit integer or float) and finds the onset of every impact click with ``scipy.signal``:

1. high-pass (4th-order Butterworth at ``highpass`` Hz, zero phase): hard impacts are broadband
   clicks, while hum, voices and handling noise are mostly below 1-2 kHz;
2. envelope: the magnitude of the analytic signal, smoothed over ``smooth`` s, the channels
   combined by their maximum;
3. adaptive threshold: ``threshold`` times the local noise floor, a running median of the
   envelope over ``noise_window`` s (so slow changes of the room noise are followed), never below
   ``threshold`` times the global noise (the median of the whole envelope);
4. candidates are the envelope peaks above it, at least the refractory gap ``refractory`` s apart
   (the click's own ringing cannot fire again);
5. amplitude gating against echoes and the ball's rattle: a candidate within ``gate`` s after an
   accepted click must reach, and rise from the tail by, ``gate_ratio`` of that click's peak (an
   echo or rattle is much quieter than the impact before it, a real bounce only a little
   quieter); a candidate rising by less than half its own height is the ringing of a click;
6. the onset of each accepted click: scanning forward from the foot of its rise (at most 5 ms
   before the peak), the first sample where the sharp (unsmoothed Hilbert) envelope reaches
   ``onset_fraction`` of the click's peak and four times the median envelope (so that noise
   cannot start a quiet click early), interpolated linearly between samples.

Returns ``AudioOnsets``: times (s from the start of the file), peak amplitudes (full scale = 1)
and a confidence in [0, 1] per onset (from its signal-to-noise ratio and, for clicks that came
close to the echo gate, its margin above it).  A quiet late bounce below the threshold is simply
not found: the bounce fit then names it a missed bounce.
"""
import math
from dataclasses import dataclass

import struct

import numpy as np
from scipy.io import wavfile
from scipy.ndimage import median_filter, uniform_filter1d
from scipy.signal import butter, find_peaks, hilbert, sosfiltfilt

from contact_sim.validation import require_positive, require_range


@dataclass(frozen=True)
class AudioOnsets:
    """Detected clicks: onset times (s), peak amplitudes (full scale 1), confidences (0-1),
    the sample rate (Hz) and the noise level (full scale) of the high-passed signal."""

    times: np.ndarray
    amplitudes: np.ndarray
    confidence: np.ndarray
    sample_rate: float
    noise: float


def read_wav(path):
    """(sample rate Hz, samples as float array (n, channels) in full-scale units)."""
    try:
        rate, data = wavfile.read(path)
    except (OSError, ValueError, struct.error) as error:   # struct: a header cut off
        reason = getattr(error, 'strerror', None) or str(error)
        raise ValueError(f'audio = {str(path)!r} cannot be read as WAV: {reason}') from None
    data = np.asarray(data)
    if data.dtype == np.uint8:
        x = (data.astype(float) - 128.0) / 128.0
    elif np.issubdtype(data.dtype, np.integer):
        x = data.astype(float) / float(-np.iinfo(data.dtype).min)
    else:
        x = data.astype(float)
    if x.ndim == 1:
        x = x[:, None]
    if x.shape[0] < 16:
        raise ValueError(f'audio = {str(path)!r} holds {x.shape[0]} samples: allowed a recording '
                         'of at least 16 samples')
    return float(rate), x


def bounce_times_from_audio(path, highpass=2000.0, threshold=8.0, refractory=0.002, gate=0.03,
                            gate_ratio=0.6, onset_fraction=0.1, smooth=1e-3, noise_window=0.5):
    """Onsets of the impact clicks in a WAV file (the steps are in the module doc).

    Parameters
    ----------
    path : str or path-like
        The WAV file (mono or stereo; 8/16/24/32-bit integer or float).
    highpass : float, optional
        The high-pass corner, Hz, 0 < f < rate/2 (default 2000).
    threshold : float, optional
        Times the local noise floor a click must reach, > 1 (default 8).
    refractory : float, optional
        The shortest gap between two clicks, s, > 0 (default 0.002).
    gate : float, optional
        The echo gate after a click, s, >= 0 (default 0.03).
    gate_ratio : float, optional
        The share of the click's peak a candidate in the gate must reach, 0 to 1 (default 0.6).
    onset_fraction : float, optional
        The share of the peak that marks the onset, 0 < x < 1 (default 0.1).
    smooth : float, optional
        The envelope's smoothing window, s (default 1e-3).
    noise_window : float, optional
        The running noise floor's window, s (default 0.5).

    Returns
    -------
    AudioOnsets
        Onset times (s from the start of the file), peak amplitudes (full scale 1) and a
        confidence in [0, 1] per click.

    Raises
    ------
    InputError
        Keyed by the option out of its range.
    ValueError
        The file cannot be read as WAV, or holds fewer than 16 samples.

    Examples
    --------
    >>> import os, tempfile
    >>> from contact_sim.calibration import bounce_times_from_audio
    >>> from contact_sim.calibration.audio import synthesize_recording, write_wav
    >>> path = os.path.join(tempfile.mkdtemp(), 'drop.wav')
    >>> write_wav(path, synthesize_recording([0.1, 0.4, 0.6], [0.8, 0.6, 0.45], duration=0.8),
    ...           48000)
    >>> print(*(f"{t:.3f}" for t in bounce_times_from_audio(path).times))
    0.100 0.400 0.600
    """
    rate, x = read_wav(path)
    return detect_onsets(x, rate, highpass, threshold, refractory, gate, gate_ratio,
                         onset_fraction, smooth, noise_window)


def detect_onsets(samples, rate, highpass=2000.0, threshold=8.0, refractory=0.002, gate=0.03,
                  gate_ratio=0.6, onset_fraction=0.1, smooth=1e-3, noise_window=0.5):
    """``bounce_times_from_audio`` on samples already read: array (n,) or (n, channels)."""
    rate = require_positive('sample_rate', rate)
    highpass = require_range('highpass', highpass, 0.0, rate / 2.0, low_open=True,
                             high_open=True)
    threshold = require_range('threshold', threshold, 1.0, low_open=True)
    refractory = require_positive('refractory', refractory)
    gate = require_range('gate', gate, 0.0)
    gate_ratio = require_range('gate_ratio', gate_ratio, 0.0, 1.0)
    onset_fraction = require_range('onset_fraction', onset_fraction, 0.0, 1.0, low_open=True,
                                   high_open=True)
    x = np.asarray(samples, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    sos = butter(4, highpass, btype='highpass', fs=rate, output='sos')
    hp = sosfiltfilt(sos, x, axis=0)
    fine = np.abs(hilbert(hp, axis=0)).max(axis=1)          # sharp, beats inside a click
    width = max(int(round(smooth * rate)), 1)
    coarse = np.sqrt(uniform_filter1d((hp * hp).max(axis=1), width))   # smooth rms envelope
    noise_global = float(np.median(coarse))
    fine_noise = float(np.median(fine))
    window = max(int(noise_window * rate) | 1, 3)
    step = max(window // 8, 1)
    # running median on a decimated envelope (cheap), brought back to full length
    local = median_filter(coarse[::step], size=max(window // step, 3), mode='nearest')
    floor = np.maximum(np.repeat(local, step)[:coarse.size], noise_global)
    level = threshold * floor
    distance = max(int(refractory * rate), 1)
    peaks, props = find_peaks(coarse, height=level, distance=distance, prominence=0.0)
    # a new click rises from at most half its height (a ringing tail does not)
    fresh = props['prominences'] >= 0.5 * props['peak_heights']
    peaks, bases = peaks[fresh], props['left_bases'][fresh]
    rises = props['prominences'][fresh]
    times, amps, conf = [], [], []
    last_peak_time, last_amp = -math.inf, 0.0
    back, ahead = int(5e-3 * rate), int(1e-3 * rate)
    for p, base, rise in zip(peaks, bases, rises):
        t_peak = p / rate
        amp = float(coarse[p])
        margin = 1.0
        if t_peak - last_peak_time < gate:
            # an echo, the rattle or the beating ring of the click before: quieter than it,
            # or rising by less than gate_ratio of it from that click's tail
            if min(amp, float(rise)) < gate_ratio * last_amp:
                continue
            margin = min(1.0, float(rise) / (gate_ratio * last_amp) - 1.0)
        # onset: scanning forward from the rise's foot, the first sample of the sharp envelope
        # above onset_fraction of the click's sharp peak, interpolated linearly
        start = max(int(base), p - back, 1)
        stop = min(p + ahead, fine.size - 1)
        top = float(fine[start:stop + 1].max())
        target = max(onset_fraction * top, 4.0 * fine_noise)   # above the noise's envelope
        above = np.flatnonzero(fine[start:stop + 1] >= target)
        j = start + int(above[0])
        a, b = float(fine[j - 1]), float(fine[j])
        frac = (target - a) / (b - a) if b > a else 1.0
        t_on = (j - 1 + min(max(frac, 0.0), 1.0)) / rate
        snr = amp / float(floor[p])
        times.append(t_on)
        amps.append(top)
        conf.append(float(np.clip(1.0 - threshold / snr, 0.0, 1.0)) * margin)
        last_peak_time, last_amp = t_peak, amp
    return AudioOnsets(np.array(times), np.array(amps), np.array(conf), rate, noise_global)


# -- synthetic recordings (tests and demonstrations) --------------------------------------------
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


def write_wav(path, samples, rate, bits=16):
    """Write float samples (n,) or (n, channels) in [-1, 1] as a WAV file: ``bits`` 16, 24 or
    32 (integer PCM) or 'float' (32-bit IEEE float).  24-bit is written by hand (scipy's writer
    has no 24-bit integer type)."""
    x = np.asarray(samples, dtype=float)
    if bits == 'float':
        wavfile.write(path, int(rate), x.astype(np.float32))
        return
    if bits == 16:
        wavfile.write(path, int(rate), np.round(x * 32767.0).astype(np.int16))
        return
    if bits == 32:
        wavfile.write(path, int(rate), np.round(x * 2147483647.0).astype(np.int32))
        return
    if bits != 24:
        raise ValueError(f'bits = {bits!r} is unknown: allowed 16, 24, 32 or float')
    channels = 1 if x.ndim == 1 else x.shape[1]
    ints = np.round(np.clip(x, -1.0, 1.0) * 8388607.0).astype('<i4').reshape(-1)
    raw = ints.view(np.uint8).reshape(-1, 4)[:, :3].tobytes()
    block = 3 * channels
    header = b''.join([
        b'RIFF', (36 + len(raw)).to_bytes(4, 'little'), b'WAVE',
        b'fmt ', (16).to_bytes(4, 'little'), (1).to_bytes(2, 'little'),
        channels.to_bytes(2, 'little'), int(rate).to_bytes(4, 'little'),
        (int(rate) * block).to_bytes(4, 'little'), block.to_bytes(2, 'little'),
        (24).to_bytes(2, 'little'), b'data', len(raw).to_bytes(4, 'little')])
    with open(path, 'wb') as f:
        f.write(header + raw)
