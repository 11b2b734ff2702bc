"""Click onsets from WAV recordings the package synthesises from its own bounce model."""
import numpy as np
import pytest

import contact_sim as cs
from contact_sim import cli
from contact_sim.calibration import audio
from contact_sim.calibration import bounces


def recording_times():
    """Touch times of a golf-like ball dropped from 0.8 m (the bounce model), and click
    amplitudes proportional to the impact speed, the tenth bounce almost silent."""
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, 2e8, 4500.0)
    seq = bounces.predict_bounces(contact, 0.046, height=0.8, count=16)
    times = seq.times + 0.3
    amplitudes = 0.6 * seq.impact_speeds / seq.impact_speeds[0]
    amplitudes[9] = 0.002                       # a quiet bounce, below the room noise
    return times, amplitudes


@pytest.mark.parametrize('rate', [44100, 48000])
@pytest.mark.parametrize('bits, stereo', [(16, False), (24, True), (32, False),
                                          ('float', True)])
def test_every_onset_within_0_2_ms(tmp_path, rate, bits, stereo):
    times, amplitudes = recording_times()
    x = audio.synthesize_recording(times, amplitudes, rate=rate, seed=rate)
    if stereo:
        x = np.stack([x, 0.5 * x], axis=1)
    path = tmp_path / f'bounces_{rate}_{bits}.wav'
    audio.write_wav(path, x, rate, bits)
    onsets = audio.bounce_times_from_audio(path)
    expected = np.delete(times, 9)              # the quiet bounce is not heard
    assert onsets.times.size == expected.size   # and no echo is taken for a bounce
    assert np.max(np.abs(onsets.times - expected)) < 2e-4
    assert onsets.sample_rate == rate
    assert np.all((onsets.confidence >= 0.0) & (onsets.confidence <= 1.0))
    assert onsets.confidence[0] > 0.8           # a loud click is a confident one


def test_echo_is_gated_but_a_close_real_bounce_is_not():
    rate = 48000
    # two clicks 20 ms apart of nearly equal loudness (final bounces), then one with an echo;
    # not a bounce sequence (flights grow): the clicks heard, without the sequence rules
    times = np.array([0.1, 0.12, 0.5])
    x = audio.synthesize_recording(times, [0.5, 0.45, 0.5], rate=rate, echo_gain=0.0, seed=3)
    onsets = audio.detect_onsets(x, rate, sequence=False)
    assert np.max(np.abs(onsets.times - times)) < 2e-4
    x = audio.synthesize_recording(times[:1], [0.5], rate=rate, echo_gain=0.45,
                                   echo_delay=0.012, seed=4)
    assert audio.detect_onsets(x, rate).times.size == 1


def test_wav_into_the_bounce_fit(tmp_path, capsys):
    times, amplitudes = recording_times()
    path = tmp_path / 'golf_80cm.wav'
    audio.write_wav(path, audio.synthesize_recording(times, amplitudes, rate=48000), 48000, 16)
    code = cli.main(['bounces', str(path), '--mass', '0.046', '--stiffness', '2e8',
                     '--law', 'azad_featherstone', '--law', 'linear'])
    out = capsys.readouterr().out
    assert code == 0
    assert 'released from 0.8 m' in out           # the height from the file name
    # the onsets found, kept and rejected are said before the fit
    summary = next(ln for ln in out.splitlines() if ln.startswith('# audio'))
    assert out.index(summary) < out.index('# bounce fit')
    assert f'{len(times) - 1} kept as impacts' in summary and 'onset(s) found' in summary
    assert 'missed bounce' in out                 # the quiet tenth bounce
    line = next(ln for ln in out.splitlines() if ln.startswith('azad_featherstone: lambda'))
    assert float(line.split()[3]) == pytest.approx(4500.0, rel=0.01)


def test_bad_audio_is_named(tmp_path):
    path = tmp_path / 'not.wav'
    path.write_text('hello')
    with pytest.raises(ValueError, match='audio = .* cannot be read as WAV'):
        audio.bounce_times_from_audio(path)
    with pytest.raises(ValueError, match='highpass = 30000.0 is out of range'):
        audio.detect_onsets(np.zeros(1000), 48000, highpass=30000.0)
    with pytest.raises(ValueError, match='bits = 12 is unknown'):
        audio.write_wav(tmp_path / 'x.wav', np.zeros(10), 48000, 12)


def test_a_wav_cut_off_inside_its_header_is_refused_by_name(tmp_path):
    # found: a struct.error traceback, exit 1
    from contact_sim.calibration import bounce_times_from_audio
    path = tmp_path / 'cut.wav'
    path.write_bytes(b'RIFF\x24\x00\x00\x00WAVEfmt \x10\x00')
    with pytest.raises(ValueError, match="audio = '.*cut.wav' cannot be read as WAV"):
        bounce_times_from_audio(path)


@pytest.mark.parametrize('samples, says', [
    (np.full(5000, np.nan), r'samples\[0\] = nan is not finite'),
    (np.concatenate([np.zeros(4000), [np.inf], np.zeros(999)]), r'samples\[4000\] = inf'),
    (np.zeros(0), 'samples holds 0 frames: allowed a recording of at least 16 frames'),
    (np.zeros(5000, dtype=complex), 'samples holds complex numbers'),
    (np.zeros((2, 5000)), r'samples has shape \(2, 5000\): allowed \(n,\) or \(n, channels\) '
                          'with 1 to 64 channels'),
    (np.zeros((100, 2, 2)), r'samples has shape \(100, 2, 2\)'),
    ('0.1 0.2', 'samples = .* is not a real number'),
])
def test_samples_that_are_not_a_recording_are_refused_by_name(samples, says):
    # found (issue 34): LinAlgError from NaN samples, NaN noise from 2-D ones, an empty min()
    with pytest.raises(cs.InputError, match=says) as error:
        audio.detect_onsets(samples, 48000)
    assert error.value.field == 'samples'


def test_a_wav_with_non_finite_samples_or_too_many_channels_is_refused_by_name(tmp_path):
    x = audio.synthesize_recording([0.1, 0.4], [0.5, 0.4])
    x[3000] = np.nan
    path = tmp_path / 'nan.wav'
    audio.write_wav(path, x, 48000, 'float')
    with pytest.raises(cs.InputError, match='audio holds a non-finite sample at frame 3000') \
            as error:
        audio.bounce_times_from_audio(path)
    assert error.value.field == 'audio'
    # a header claiming 1000 channels (found: a MemoryError reading one block)
    path = tmp_path / 'wide.wav'
    audio.write_wav(path, np.zeros(1000), 48000, 16)
    raw = bytearray(path.read_bytes())
    raw[22:24] = (1000).to_bytes(2, 'little')
    path.write_bytes(bytes(raw))
    with pytest.raises(cs.InputError, match='1000 channels at 48000 Hz: allowed 1 to 64'):
        audio.bounce_times_from_audio(path)


@pytest.mark.parametrize('samples, rate, field, says', [
    (np.full(5000, 1e300), 48000, 'samples', r'a sample of 1e\+300 at frame 0: allowed '
                                             r'\|sample\| <= 1e\+06'),
    (np.zeros(5000), 1e300, 'sample_rate', r'allowed 0 < sample_rate <= 1e\+07'),
    (np.zeros(5000), '48000', 'sample_rate', 'is text'),
    (np.zeros(5000), 1.0, 'sample_rate', 'too low for the high-pass at 2000 Hz'),
])
def test_levels_and_rates_out_of_range_are_refused_by_name(samples, rate, field, says):
    # found (issue 34): a LinAlgError at 1e300 Hz, overflow at 1e300 full scale, text taken as a
    # rate, and a too-low rate reported as highpass
    with pytest.raises(cs.InputError, match=says) as error:
        audio.detect_onsets(samples, rate)
    assert error.value.field == field


def test_a_lone_spike_gives_finite_onsets():
    x = np.zeros(6001)
    x[3000] = 1.0                     # found: the square root of a rounding error below zero
    onsets = audio.detect_onsets(x, 48000)
    assert np.all(np.isfinite(onsets.times)) and np.isfinite(onsets.noise)
