"""Glitch naming without caps (issue 19): any number of clicks missing from one interval."""
import numpy as np
import pytest

from contact_sim.calibration import ImpactTimes, fit_bounces, prepare_sequence
from contact_sim.model import LINEAR

G = 9.81


def constant_restitution_clicks(e=0.85, v=3.0, count=25, noise=100e-6):
    """Vacuum click times of a ball of constant restitution from impact speed v (m/s)."""
    t = [0.0]
    for _ in range(count - 1):
        v *= e
        t.append(t[-1] + 2.0 * v / G)
    return np.array(t) + np.random.default_rng(2).normal(0.0, noise, count)


@pytest.mark.parametrize('missing', [1, 3, 9])
def test_any_number_of_missing_clicks_is_named_once_and_numbered_right(missing):
    # found: at most 2 missing clicks per interval; with 9 missing the later clicks were
    # mis-numbered and their residuals reached -200 to -280 ms
    t = constant_restitution_clicks()
    kept = np.r_[0:5, 5 + missing:t.size]
    prepared, glitches = prepare_sequence(0, ImpactTimes(t[kept]), G)
    assert np.array_equal(prepared.index, kept)
    (glitch,) = glitches
    assert glitch.kind == 'missed bounce' and f'{missing} click(s) missing' in glitch.detail
    fit = fit_bounces({LINEAR: 1e6}, 0.05, [t[kept]], laws=[LINEAR])
    assert fit.best.rms < 1e-3


def kinds(glitches):
    return [g.kind for g in glitches]


def test_a_spurious_click_that_splits_an_interval_is_one_spurious_click():
    # found: it became 5 invented missed bounces
    t = constant_restitution_clicks()
    split = 0.5 * (t[6] + t[7]) + 0.01
    prepared, glitches = prepare_sequence(0, ImpactTimes(np.sort(np.r_[t, split])), G)
    assert kinds(glitches) == ['spurious click']
    assert glitches[0].time == pytest.approx(split) and glitches[0].left_out
    assert np.array_equal(prepared.index, np.arange(t.size))


def test_missing_doubled_and_spurious_clicks_together_each_named_once():
    t = constant_restitution_clicks(count=30)
    kept = np.r_[0:4, 13:t.size]                        # 9 missing after the 4th click
    clicks = np.sort(np.r_[t[kept], t[15] + 0.002,     # an echo 2 ms after a click
                           0.4 * t[20] + 0.6 * t[21]])  # a tick inside a flight
    prepared, glitches = prepare_sequence(0, ImpactTimes(clicks), G)
    assert sorted(kinds(glitches)) == ['doubled click', 'missed bounce', 'spurious click']
    assert np.array_equal(prepared.index, kept)
    missed = next(g for g in glitches if g.kind == 'missed bounce')
    assert '9 click(s) missing' in missed.detail


def test_a_late_start_of_four_bounces_is_named_and_renumbered():
    # found: at most 2 late bounces were looked for
    e, h = 0.85, 1.0
    v = np.sqrt(2 * G * h)
    t = [np.sqrt(2 * h / G)]
    for _ in range(24):
        v *= e
        t.append(t[-1] + 2 * v / G)
    t = np.array(t)
    prepared, glitches = prepare_sequence(0, ImpactTimes(t[4:] + 3.0, h), G)
    assert kinds(glitches) == ['late start']
    assert 'the first 4 impact(s) were not recorded' in glitches[0].detail
    assert np.array_equal(prepared.index, np.arange(4, t.size))


def test_an_interval_that_grows_in_mid_run_is_named():
    # found: only down-weighted, never named
    t = constant_restitution_clicks()
    grown = t.copy()
    grown[10:] += 0.25 * (t[10] - t[9])                # one flight 25 % longer than its own
    prepared, glitches = prepare_sequence(0, ImpactTimes(grown), G)
    assert kinds(glitches) == ['growing interval']
    assert glitches[0].time == pytest.approx(grown[10]) and not glitches[0].left_out
    assert np.array_equal(prepared.index, np.arange(t.size))
