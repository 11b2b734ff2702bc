"""The O(1)-per-bounce sequence model against the drop engine (which integrates every contact
with gravity), and its validity limit; fit_bounces against recordings synthesised from the
engine: coverage, the law ranking, the glitches named and the errors."""
import math

import numpy as np
import pytest

import contact_sim as cs
from contact_sim.calibration import (ImpactTimes, bounces, fit_bounces, prepare_sequence,
                                     read_impact_times)
from contact_sim.flight.drag import AirDrag

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
    contact = cs.Contact(cs.LAWS[law], k, lam)
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
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
    touches = engine_touches(contact, 0.066, None)
    predicted = bounces.predict_bounces(contact, 0.066, height=1.0, count=touches.size)
    error = np.abs(predicted.times - touches)
    assert not predicted.valid[-1] and predicted.gravity_group[-1] > 0.1
    assert error[-1] > 5e-5          # tens of microseconds off once G is large


def test_gravity_leaves_out_more_than_the_model_error():
    """Without the first-order gravity correction the sequence is off by far more."""
    contact, mass = cs.Contact(cs.AZAD_FEATHERSTONE, 2e7, 1e3), 0.0027
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
    contact, mass = cs.Contact(cs.HUNT_CROSSLEY, 5e6, 2e3), 0.0027
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
    contact = cs.Contact(cs.HUNT_CROSSLEY, 5e6, 2e3)
    with pytest.raises(ValueError, match='release is missing'):
        bounces.predict_bounces(contact, 0.0027)
    with pytest.raises(ValueError, match='height = -1.0 is out of range'):
        bounces.predict_bounces(contact, 0.0027, height=-1.0)
    with pytest.raises(ValueError, match='mass = 0.0 is out of range'):
        bounces.predict_bounces(contact, 0.0, height=1.0)
    for count in (2.5, 0, True, '3', bounces.MAX_BOUNCES + 1):
        with pytest.raises(ValueError, match=r'count = .* allowed 1 <= count'):
            bounces.predict_bounces(contact, 0.0027, height=1.0, count=count)
    # an integer count from numpy is an integer
    assert bounces.predict_bounces(contact, 0.0027, height=1.0, count=np.int64(3)).times.size == 3


def test_vectorised_over_sequences():
    law = cs.get_law('lee_wang')
    speeds = np.array([1.0, 2.0, 4.0])
    times, _, _, _ = bounces.impact_sequence(law, 1e8, 3e3, 0.046, G, speeds, 5)
    for i, v in enumerate(speeds):
        one = bounces.impact_sequence(law, 1e8, 3e3, 0.046, G, v, 5)[0][0]
        assert np.allclose(times[i], one, rtol=1e-14, atol=0)
    assert math.isfinite(times[0, -1])


# -- fit_bounces --------------------------------------------------------------------------------
GOLF_MASS, GOLF_K = 0.046, 2e8
HEIGHTS = (0.5, 0.8, 1.0, 1.2)


@pytest.fixture(scope='module')
def golf_truth():
    """Touch times from the package's own engine (gravity in every contact, drag in flight)."""
    lam = cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, GOLF_K, GOLF_MASS, 0.8, 3.0)
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, GOLF_K, lam)
    # long enough for 14 touches (e about 0.8), not for the micro-bounces after them
    return lam, {h: engine_touches(contact, GOLF_MASS, GOLF, h,
                                   duration=11.0 * math.sqrt(2.0 * h / G))[:14]
                 for h in HEIGHTS}


def synthetic_recording(truth, seed):
    """A phone-like recording: timing jitter 50 µs, a random experiment start, times in
    multiples of 1/48000 s, a release height measured to ± 1 cm, and in one seed of three a
    glitch: a missed bounce, a doubled click (echo 3-15 ms later) or a late start."""
    rng = np.random.default_rng(seed)
    h = HEIGHTS[seed % len(HEIGHTS)]
    n = int(rng.integers(9, 13))
    t = truth[h][:n] + rng.normal(0.0, 50e-6, n) + rng.uniform(0.5, 3.0)
    planted = None
    if seed % 3 == 0:
        planted = ('missed bounce', 'doubled click', 'late start')[(seed // 3) % 3]
        if planted == 'missed bounce':
            t = np.delete(t, int(rng.integers(3, n - 2)))
        elif planted == 'doubled click':
            i = int(rng.integers(2, n - 2))
            t = np.sort(np.append(t, t[i] + rng.uniform(0.003, 0.015)))
        else:
            t = t[1:]
    t = np.round(t * 48000.0) / 48000.0
    return ImpactTimes(t, h + rng.normal(0.0, 0.01)), planted


def test_fit_bounces_coverage_law_choice_and_glitches(golf_truth):
    """200 seeds: λ inside its 95 % interval in >= 90 %, the true law ranked first, every
    planted glitch named, no glitch invented."""
    lam, truth = golf_truth
    inside = picked = flagged = planted_count = invented = 0
    seeds = 200
    for seed in range(seeds):
        recording, planted = synthetic_recording(truth, seed)
        fit = fit_bounces(GOLF_K, GOLF_MASS, [recording], drag=GOLF)
        af = next(f for f in fit.fits if f.law.name == 'azad_featherstone')
        low, high = af.damping_interval
        inside += low <= lam <= high
        picked += fit.best.law.name == 'azad_featherstone'
        kinds = [g.kind for g in fit.glitches if g.kind != 'outlier']
        if planted:
            planted_count += 1
            flagged += planted in kinds
        invented += sum(kind != planted for kind in kinds)
    assert inside >= 0.9 * seeds
    assert picked == seeds
    assert flagged == planted_count == 67
    assert invented == 0


def test_fit_bounces_several_sequences_and_drag_coefficient(golf_truth):
    lam, truth = golf_truth
    recordings = [synthetic_recording(truth, seed)[0] for seed in (1, 2, 4, 5)]
    fit = fit_bounces(GOLF_K, GOLF_MASS, recordings, laws=[cs.AZAD_FEATHERSTONE],
                      drag=AirDrag(1.2, 0.5, 0.0214), fit_drag=True)
    best = fit.best
    assert best.damping_interval[0] <= lam <= best.damping_interval[1]
    assert best.drag_interval[0] <= 0.3 <= best.drag_interval[1]
    assert best.drag_interval[1] / best.drag_interval[0] < 2.0
    assert len(best.residuals) == 4 and best.rms < 1e-4


def test_constant_restitution_is_not_called_speed_dependent():
    """Data made by a constant-restitution contact (the linear law) with drag: the fit must not
    claim a speed-dependent restitution, and drag must not be mistaken for one."""
    mass = 0.0027
    k_lin = 3e4
    lam = cs.damping_for_restitution(cs.LINEAR, k_lin, mass, 0.9, 1.0)
    contact = cs.Contact(cs.LINEAR, k_lin, lam)
    touches = engine_touches(contact, mass, TABLE_TENNIS, 0.6, duration=4.0)[:12]
    rng = np.random.default_rng(7)
    t = np.round((touches + rng.normal(0.0, 50e-6, touches.size)) * 48000.0) / 48000.0
    fit = fit_bounces({cs.AZAD_FEATHERSTONE: 5e6, cs.HUNT_CROSSLEY: 5e6, cs.LINEAR: k_lin}, mass,
                      [ImpactTimes(t, 0.6)],
                      drag=TABLE_TENNIS)
    assert fit.best.law.name == 'linear'
    assert not fit.speed_dependent
    # ignoring the drag makes the same data look speed dependent (the trap)
    naive = fit_bounces({cs.AZAD_FEATHERSTONE: 5e6, cs.HUNT_CROSSLEY: 5e6, cs.LINEAR: k_lin}, mass,
                        [ImpactTimes(t, 0.6)])
    assert naive.speed_dependent and naive.best.law.name != 'linear'
    assert naive.best.rms > 30 * fit.best.rms


def test_glitch_detection_names_each_kind():
    t = np.cumsum([0.0] + [0.6 * 0.85 ** i for i in range(10)])
    prepared, glitches = prepare_sequence(0, ImpactTimes(t))
    assert glitches == [] and list(prepared.index) == list(range(11))
    missed = np.delete(t, 5)
    prepared, glitches = prepare_sequence(0, ImpactTimes(missed))
    assert [g.kind for g in glitches] == ['missed bounce']
    assert list(prepared.index) == [0, 1, 2, 3, 4, 6, 7, 8, 9, 10]
    two_missed = np.delete(t, [5, 6])
    prepared, glitches = prepare_sequence(0, ImpactTimes(two_missed))
    assert list(prepared.index) == [0, 1, 2, 3, 4, 7, 8, 9, 10]
    doubled = np.sort(np.append(t, t[4] + 0.008))
    prepared, glitches = prepare_sequence(0, ImpactTimes(doubled))
    assert [(g.kind, g.left_out) for g in glitches] == [('doubled click', True)]
    assert np.array_equal(prepared.times, t)
    h = (0.6 / 1.7) ** 2 * G / 2.0       # the release whose first bounce flight lasts 0.6 s
    prepared, glitches = prepare_sequence(0, ImpactTimes(t[1:] - t[1], h), G)
    assert [g.kind for g in glitches] == ['late start'] and prepared.index[0] == 1
    prepared, glitches = prepare_sequence(0, ImpactTimes(t, h), G)
    assert glitches == []


def test_fit_bounces_errors_name_the_field():
    t = np.cumsum([0.0] + [0.6 * 0.85 ** i for i in range(6)])
    with pytest.raises(ValueError, match='loss = .nope. is unknown'):
        fit_bounces(2e8, 0.046, [t], loss='nope')
    with pytest.raises(ValueError, match='timing_resolution = 0.0 is out of range'):
        fit_bounces(2e8, 0.046, [t], timing_resolution=0.0)
    with pytest.raises(ValueError, match='drag is missing'):
        fit_bounces(2e8, 0.046, [t], fit_drag=True)
    with pytest.raises(ValueError, match=r'times\[2\] = .* allowed times\[2\] > times\[1\]'):
        ImpactTimes([0.0, 1.0, 0.5])
    with pytest.raises(ValueError, match='at least 3'):
        ImpactTimes([0.0, 1.0])


def test_example_recording_round_trip(tmp_path):
    """examples/bounce_recording.py (the README's workflow): its CSV and WAV give back λ."""
    import importlib.util
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / 'examples' / 'bounce_recording.py'
    spec = importlib.util.spec_from_file_location('bounce_recording', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    csv_path, wav_path, lam = module.main(tmp_path)
    sequences = read_impact_times(csv_path)
    assert [s.height for s in sequences] == [pytest.approx(0.8), pytest.approx(0.5)]
    fit = fit_bounces(module.STIFFNESS, module.MASS, sequences, laws=[cs.AZAD_FEATHERSTONE],
                      drag=AirDrag(1.204, 0.47, module.RADIUS), fit_drag=True)
    assert fit.best.damping_interval[0] <= lam <= fit.best.damping_interval[1]
    assert sorted(g.kind for g in fit.glitches) == ['doubled click', 'missed bounce']
    assert wav_path.exists()


def test_final_micro_bounces_are_left_out_and_named():
    """A steel ball recorded to the end: the clicks past G = 0.01 are cut, the rest fitted."""
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
    touches = engine_touches(contact, 0.066, None, height=0.5)
    rng = np.random.default_rng(5)
    t = np.round((touches + rng.normal(0.0, 50e-6, touches.size)) * 48000.0) / 48000.0
    fit = fit_bounces(1e10, 0.066, [ImpactTimes(t, 0.5)])
    kinds = [g.kind for g in fit.glitches]
    assert kinds == ['micro-bounces']
    kept = fit.sequences[0].times.size
    assert 10 < kept < touches.size
    assert fit.best.law.name == 'azad_featherstone'
    assert fit.best.damping_interval[0] <= 1e5 <= fit.best.damping_interval[1]


def test_a_twin_of_a_named_law_tabulates_its_own_bounce_table_and_finds_the_shipped_one():
    # the bounce table is the law's (ContactLaw.bounce_table), not its exponents': a custom law
    # with Azad-Featherstone's exponents has none and is tabulated, by the general kernel, to
    # the shipped numbers (its 9-point grid is every 12th node of the shipped 97)
    from contact_sim.calibration.contact_tables import build_contact_table
    twin = cs.ContactLaw('af_twin', 1.5, 0.5, 1.0)
    assert twin.bounce_table is None and twin.kernel == 0
    with pytest.warns(RuntimeWarning, match="'af_twin' has no master curve"):
        grid, x_lift, a, b = build_contact_table(twin, points=9)
    shipped = cs.AZAD_FEATHERSTONE.bounce_table
    assert np.allclose(grid, shipped.log_zeta[::12], rtol=0.0, atol=1e-8)
    for mine, theirs in ((x_lift, shipped.x_lift), (a, shipped.a), (b, shipped.b)):
        assert np.allclose(mine, theirs[::12], rtol=1e-5, atol=1e-7)
