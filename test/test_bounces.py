"""The O(1)-per-bounce sequence model against the drop engine (which integrates every contact
with gravity), and its validity limit."""
import math

import numpy as np
import pytest

import contact_sim as cs
from contact_sim import bounces
from contact_sim.flight import AirDrag

G = 9.81
TABLE_TENNIS = AirDrag(1.2, 0.5, 0.02)
GOLF = AirDrag(1.2, 0.3, 0.0214)

CONFIGS = [  # law, k, lambda, mass, drag
    ('azad_featherstone', 1e10, 1e5, 0.066, None),          # the paper's steel ball
    ('hunt_crossley', 5e6, 2e3, 0.0027, TABLE_TENNIS),
    ('lee_wang', 1e8, 3e3, 0.046, GOLF),
    ('linear', 1e6, 8.0, 0.046, None),                       # constant restitution
    ('azad_featherstone', 2e7, 1e3, 0.0027, TABLE_TENNIS),
]


def engine_touches(contact, mass, drag, height=1.0, duration=20.0):
    result = cs.simulate_drop(contact, mass, height, duration=duration, drag=drag)
    return np.array([imp.time for imp in result.impacts if not imp.permanent])


@pytest.mark.parametrize('law, k, lam, mass, drag', CONFIGS)
def test_sequence_matches_the_engine_while_gravity_group_is_small(law, k, lam, mass, drag):
    contact = cs.Contact(law, k, lam)
    touches = engine_touches(contact, mass, drag)
    predicted = bounces.predict_bounces(contact, mass, height=1.0, count=touches.size, drag=drag)
    error = np.abs(predicted.times - touches)
    valid = predicted.valid
    assert valid[:3].all()
    n_valid = int(np.argmin(valid)) if not valid.all() else valid.size
    # about 1 µs per bounce where G < 2e-3 ...
    assert np.all(error[:n_valid] <= 1e-6 * np.arange(1, n_valid + 1) + 1e-9)
    # ... and the model's own restitution is the fast path's, corrected by O(G)
    e_fast = cs.restitution(contact, mass, predicted.impact_speeds[:3])
    assert np.allclose(predicted.restitutions[:3], e_fast, atol=30 * predicted.gravity_group[2])


def test_model_stops_being_valid_in_the_final_micro_bounces():
    contact = cs.Contact('azad_featherstone', 1e10, 1e5)
    touches = engine_touches(contact, 0.066, None)
    predicted = bounces.predict_bounces(contact, 0.066, height=1.0, count=touches.size)
    error = np.abs(predicted.times - touches)
    assert not predicted.valid[-1] and predicted.gravity_group[-1] > 0.1
    assert error[-1] > 5e-5          # tens of microseconds off once G is large


def test_gravity_leaves_out_more_than_the_model_error():
    """Without the first-order gravity correction the sequence is off by far more."""
    contact, mass = cs.Contact('azad_featherstone', 2e7, 1e3), 0.0027
    touches = engine_touches(contact, mass, None, duration=2.0)[:4]
    v = bounces.release_speed(1.0, G)
    plain, t = [0.0], 0.0
    for _ in range(3):   # e(v) v and τc(v) of the fast path only, vacuum flight
        u = cs.restitution(contact, mass, v) * v
        t += cs.contact_duration(contact, mass, v) + 2 * u / G
        plain.append(t)
        v = u
    corrected = bounces.predict_bounces(contact, mass, height=1.0, count=4).times
    assert np.max(np.abs(corrected - touches)) < 0.1 * np.max(np.abs(
        np.array(plain) + touches[0] - touches))


def test_release_and_first_flight_agree():
    contact, mass = cs.Contact('hunt_crossley', 5e6, 2e3), 0.0027
    kappa, beta = TABLE_TENNIS.rates(mass, G)
    v = bounces.release_speed(0.8, G, kappa, beta)
    assert bounces.release_height(v, G, kappa, beta) == pytest.approx(0.8, rel=1e-12)
    assert bounces.release_height(3.0, G) == pytest.approx(9.0 / (2 * G))
    a = bounces.predict_bounces(contact, mass, height=0.8, count=6, drag=TABLE_TENNIS)
    flight = a.times[1] - a.times[0]
    b = bounces.predict_bounces(contact, mass, first_flight=flight, count=6, drag=TABLE_TENNIS,
                                start_time=a.times[0])
    assert np.allclose(a.times, b.times, rtol=0, atol=1e-10)


def test_predict_bounces_errors_name_the_field():
    contact = cs.Contact('hunt_crossley', 5e6, 2e3)
    with pytest.raises(ValueError, match='release is missing'):
        bounces.predict_bounces(contact, 0.0027)
    with pytest.raises(ValueError, match='height = -1.0 is out of range'):
        bounces.predict_bounces(contact, 0.0027, height=-1.0)
    with pytest.raises(ValueError, match='mass = 0.0 is out of range'):
        bounces.predict_bounces(contact, 0.0, height=1.0)


def test_vectorised_over_sequences():
    law = cs.get_law('lee_wang')
    speeds = np.array([1.0, 2.0, 4.0])
    times, _, _, _ = bounces.impact_sequence(law, 1e8, 3e3, 0.046, G, speeds, 5)
    for i, v in enumerate(speeds):
        one = bounces.impact_sequence(law, 1e8, 3e3, 0.046, G, v, 5)[0][0]
        assert np.allclose(times[i], one, rtol=1e-14, atol=0)
    assert math.isfinite(times[0, -1])
