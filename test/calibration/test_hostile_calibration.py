"""Hostile inputs to the calibration layer (issue 17)."""
import math
import warnings

import numpy as np
import pytest

import contact_sim as cs
from contact_sim.calibration import parse_impact_times

C = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
T = np.cumsum([0.0, 0.45, 0.40, 0.36, 0.32, 0.29])


def test_a_long_prediction_ends_at_the_permanent_contact_without_nan():
    # reproduced: NaN touch times from bounce 43 on with count = 60
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        b = cs.predict_bounces(C, 0.066, height=1.0, count=60)
    assert 1 < len(b.times) < 60
    for values in (b.times, b.impact_speeds, b.rebound_speeds, b.gravity_group):
        assert len(values) == len(b.times) and np.all(np.isfinite(values))
    assert b.rebound_speeds[-1] == 0.0 and np.all(b.rebound_speeds[:-1] > 0.0)
    assert np.all(np.diff(b.times) > 0.0)
    short = cs.predict_bounces(C, 0.066, height=1.0, count=10)
    assert np.allclose(short.times, b.times[:10], rtol=0, atol=1e-12)


@pytest.mark.parametrize('kwargs, field', [
    (dict(height=1e308), 'height'), (dict(height=1.0, gravity=1e308), 'gravity'),
    (dict(height=1.0, drag=0.5), 'drag')])
def test_predict_bounces_refuses_extremes(kwargs, field):
    # reproduced: all NaN for height = 1e308
    with pytest.raises(cs.InputError) as info:
        cs.predict_bounces(C, 0.066, count=5, **kwargs)
    assert info.value.field == field


@pytest.mark.parametrize('text', [1.0, None, b'0.1\n0.5\n'])
def test_parse_impact_times_refuses_what_is_not_text(text):
    # reproduced: AttributeError 'float' object has no attribute 'splitlines'
    with pytest.raises(cs.InputError, match='^text = '):
        parse_impact_times(text)


def test_fit_bounces_reads_a_2d_array_as_one_sequence_a_row():
    # reproduced: "The truth value of an array with more than one element is ambiguous"
    stacked = cs.fit_bounces(1e10, 0.066, np.vstack([T, T + 1.0]), laws=[cs.AZAD_FEATHERSTONE])
    listed = cs.fit_bounces(1e10, 0.066, [T, T + 1.0], laws=[cs.AZAD_FEATHERSTONE])
    assert stacked.fits[0].damping == pytest.approx(listed.fits[0].damping, rel=1e-9)
    with pytest.raises(cs.InputError, match='^sequences is an array of shape'):
        cs.fit_bounces(1e10, 0.066, T)


@pytest.mark.parametrize('sequences, field', [(5, 'sequences'), ([[0.0, 0.4, 'x']], 'times'),
                                              ([[0.0, 0.4, 0.7 + 1j]], 'times')])
def test_fit_bounces_refuses_sequences_that_are_not_times(sequences, field):
    with pytest.raises(cs.InputError) as info:
        cs.fit_bounces(1e10, 0.066, sequences)
    assert info.value.field == field


def test_fit_bounces_refuses_a_drag_that_is_not_an_air_drag():
    # reproduced: AttributeError 'float' object has no attribute 'rates'
    with pytest.raises(cs.InputError, match='^drag = 0.5 is not None or an AirDrag'):
        cs.fit_bounces(1e10, 0.066, [T], drag=0.5)


def test_a_sequence_longer_than_the_limit_is_refused_before_the_work():
    times = np.arange(20_001, dtype=float)
    with pytest.raises(cs.InputError, match='allowed at most'):
        cs.fit_bounces(1e10, 0.066, [times])
    assert math.isfinite(times[-1])


@pytest.mark.parametrize('release', [dict(), dict(height=1.0, first_flight=0.5)])
def test_predict_bounces_wants_exactly_one_release(release):
    # found by scripts/hostile_inputs.py: a plain ValueError
    with pytest.raises(cs.InputError,
                       match=r'^release is .*: give exactly one of height \(m\) and first_flight'):
        cs.predict_bounces(C, 0.066, count=3, **release)
