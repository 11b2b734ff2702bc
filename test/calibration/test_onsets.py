"""The onset detector against recordings of an independent generator (click_recordings.py):
bouncing-ball sequences down to 5 ms flights, clicks ringing 0.5-20 ms, room noise, a spurious
weak click, clipping.  Seeds 200 on: the detector was tuned on seeds 0-39 and 100-111."""
import numpy as np
import pytest

from contact_sim.calibration import audio, bounce_times_from_audio
from contact_sim.calibration import wav as wavmod

from click_recordings import make_recording, score

SEEDS = range(200, 209)


def recording(seed, snr=30.0):
    return make_recording(seed=seed, loudness=(0.6, 2.0, 0.15)[seed % 3], quietest_snr=snr)


def test_every_impact_heard_no_spurious_click_and_onsets_within_half_a_ms():
    # found on real recordings: 70 of 85 clicks 25-60 ms apart found, one weak tick accepted;
    # the old detector finds 66 % of these clicks (bench_onsets.py)
    found = true = false = 0
    errors, spurious = [], 0
    for seed in SEEDS:
        rec = recording(seed)
        assert np.any(np.abs(rec.samples) >= 1.0) == (seed % 3 == 1)     # clipped ones
        times = audio.detect_onsets(rec.samples, rec.rate).times
        recall, false_share, err = score(times, rec.times)
        found += round(recall * rec.times.size)
        false += round(false_share * rec.times.size)
        true += rec.times.size
        errors.append(err)
        spurious += bool(np.any(np.abs(times - rec.spurious) < 2e-3))
    err = np.concatenate(errors)
    assert found / true >= 0.98
    assert false / true <= 0.01
    assert spurious == 0
    assert err.max() <= 5e-4
    assert np.median(err) <= 1e-4


def test_clicks_5_ms_apart_on_a_15_to_20_ms_ring():
    # the hardest shape: every click rings 15-20 ms, so the last 20 land on the tails of the
    # ones before; here the detector leaves about 1 % false clicks (bench_onsets.py's figures)
    found = false = true = 0
    worst = 0.0
    for seed in range(200, 206):
        rec = make_recording(seed=seed, decay_low=0.015, decay_high=0.02, quietest_snr=30.0)
        assert np.diff(rec.times).min() < 0.0055
        recall, false_share, err = score(audio.detect_onsets(rec.samples, rec.rate).times,
                                         rec.times)
        found += round(recall * rec.times.size)
        false += round(false_share * rec.times.size)
        true += rec.times.size
        worst = max(worst, err.max())
    assert found / true >= 0.98
    assert false / true <= 0.02
    assert worst <= 5e-4


@pytest.mark.parametrize('bits, stereo', [(16, False), (24, True), ('float', False)])
def test_a_file_read_in_blocks_gives_the_onsets_of_the_whole(tmp_path, monkeypatch, bits,
                                                             stereo):
    rec = recording(201)
    x = np.stack([rec.samples, 0.7 * rec.samples], axis=1) if stereo else rec.samples
    path = tmp_path / 'r.wav'
    audio.write_wav(path, x, rec.rate, bits)
    whole = audio.detect_onsets(x, rec.rate).times
    sizes = []
    read = wavmod.WavFile.read

    def counting(self, start, stop):
        sizes.append(min(stop, self.frames) - max(start, 0))
        return read(self, start, stop)

    monkeypatch.setattr(wavmod.WavFile, 'read', counting)
    block = 1 << 15
    onsets = bounce_times_from_audio(path, block=block)
    pad = int((1.0 / 2 + 0.01 + 2e-3) * rec.rate)       # noise_window / 2 + 10 ms + lookback
    assert len(sizes) > 3 and max(sizes) <= block + 2 * pad
    assert onsets.times.size == whole.size
    assert np.max(np.abs(onsets.times - whole)) < 1e-4
    recall, false, err = score(onsets.times, rec.times)
    assert recall >= 0.97 and false == 0.0 and err.max() <= 5e-4


def test_wav_encodings_read_to_full_scale(tmp_path):
    x = 0.5 * np.sin(np.linspace(0, 20, 2000))
    for bits in (16, 24, 32, 'float'):
        path = tmp_path / f'{bits}.wav'
        audio.write_wav(path, np.stack([x, -x], axis=1), 44100, bits)
        rate, y = audio.read_wav(path)
        assert rate == 44100 and y.shape == (2000, 2)
        assert np.max(np.abs(y[:, 0] - x)) < 1e-4 and np.max(np.abs(y[:, 1] + x)) < 1e-4


def test_wav_refusals_are_named(tmp_path):
    path = tmp_path / 'alaw.wav'
    audio.write_wav(path, np.zeros(100), 8000, 16)
    raw = bytearray(path.read_bytes())
    raw[20:22] = (6).to_bytes(2, 'little')        # A-law
    path.write_bytes(bytes(raw))
    with pytest.raises(ValueError, match="audio = '.*alaw.wav' cannot be read as WAV: encoding 6"):
        bounce_times_from_audio(path)
    with pytest.raises(ValueError, match='cannot be read as WAV: No such file'):
        bounce_times_from_audio(tmp_path / 'missing.wav')
    with pytest.raises(ValueError, match='block = 10.0 is out of range: allowed 4096 <= block'):
        audio.detect_onsets(np.zeros(5000), 48000, block=10)
    with pytest.raises(ValueError, match='rise = 1.0 is out of range'):
        audio.detect_onsets(np.zeros(5000), 48000, rise=1.0)


# the failure modes of real recordings (issue 32): on a table-tennis WAV the detector heard
# 1,493 clicks for 59 impacts (echoes 7 ms after each, a hollow ball's rattle, clipping, a click
# before the drop).  Seeds 400 on; the sequence rules were developed on seeds 0-2 and 300-303.
CASES = {
    # a table-tennis-like ball: e 0.9, a loud echo 7 ms after every impact, a rattle 0.2 s
    # long, the first impacts clipped (2 x full scale), three spurious clicks at 30 % between
    # impacts and a click 1.5 s before the drop
    'hollow ball': dict(e=0.9, first_interval=0.5, min_interval=0.02, echo_lag=0.007,
                        echo_gain=0.9, rattle=0.2, rattle_gain=0.6, loudness=2.0,
                        quietest_snr=10.0, spurious_count=3, spurious_ratio=0.3, pre_click=1.5),
    # steel-like: clicks ringing 0.3-2 ms, e 0.95 down to 10 ms flights, an echo at 12 ms
    'steel': dict(e=0.95, first_interval=0.3, min_interval=0.01, decay_low=3e-4,
                  decay_high=2e-3, echo_lag=0.012, echo_gain=0.8, loudness=0.8,
                  quietest_snr=15.0, spurious_count=2, spurious_ratio=0.5),
    # a long sequence of high restitution (metallic glass): e 0.98, 115 impacts
    'high e': dict(e=0.98, first_interval=0.2, min_interval=0.02, decay_low=1e-3,
                   decay_high=5e-3, echo_lag=0.009, echo_gain=0.8, loudness=0.8,
                   quietest_snr=15.0, spurious_count=2, spurious_ratio=0.5),
}


@pytest.mark.parametrize('case', sorted(CASES))
def test_the_impacts_heard_are_kept_and_nothing_else(case):
    for seed in range(400, 403):
        rec = make_recording(seed=seed, **CASES[case])
        heard = audio.detect_onsets(rec.samples, rec.rate, sequence=False).times
        onsets = audio.detect_onsets(rec.samples, rec.rate)
        assert onsets.found == heard.size == onsets.times.size + len(onsets.rejected)
        assert onsets.summary().startswith(f'{heard.size} onset(s) found, '
                                           f'{onsets.times.size} kept as impacts')
        # where a flight is longer than 2.5 echo lags the sequence tells echo from impact:
        # there every impact heard (within 1 ms) is kept and no other click
        lag = CASES[case]['echo_lag']
        flights = np.diff(rec.times)
        clear = rec.times[:-1][flights > 2.5 * lag]
        span = (clear[0] - 1e-3, clear[-1] + 1e-3)
        impacts_heard = [t for t in clear if np.min(np.abs(heard - t)) <= 1e-3]
        assert len(impacts_heard) >= 0.9 * clear.size
        for t in impacts_heard:
            assert np.min(np.abs(onsets.times - t)) <= 1e-3, (seed, t)
        inside = onsets.times[(onsets.times > span[0]) & (onsets.times < span[1])]
        extra = [t for t in inside if np.min(np.abs(rec.times - t)) > 1e-3]
        assert not extra, (seed, extra)
        # the reasons: every echo, rattle and spurious click heard in that span is rejected
        # with a reason
        for r in onsets.rejected:
            assert r.kind in ('echo or ringing', 'precursor', 'before the sequence',
                              'after the sequence', 'off the sequence') and r.reason
        if case == 'hollow ball':      # the failure mode is there: many more clicks heard
            assert heard.size > 3 * rec.times.size
            first = min(onsets.rejected, key=lambda r: r.time)
            assert first.kind == 'before the sequence'    # the click before the drop
