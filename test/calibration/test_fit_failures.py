"""Fits that say when they fail (issue 19): parameters that stay inside their bounds, a success
flag and message, no interval from too few observations or an undetermined parameter, and the
model-adequacy check."""
import math

import numpy as np
import pytest

import contact_sim as cs
from contact_sim.calibration import fit_bounces
from contact_sim.calibration.adequacy import check_adequacy
from contact_sim.calibration.timing_fit import CD_BOUNDS, drag_coefficient_of, log_interval
from contact_sim.flight import AirDrag

G = 9.81
PP_MASS, PP_K, PP_RADIUS = 0.0027, 5e6, 0.02


@pytest.fixture(scope='module')
def heavy_drag_times():
    """A light ball with C_d = 5: fitted with a third of its radius, it needs C_d = 45 > 10."""
    lam = cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, PP_K, PP_MASS, 0.9, 2.0)
    result = cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, PP_K, lam), PP_MASS, 0.5,
                              duration=2.0, drag=AirDrag(1.2, 5.0, PP_RADIUS))
    return np.array([imp.time for imp in result.impacts if not imp.permanent])[:10]


def test_drag_coefficient_never_leaves_its_bounds():
    # found: exp(log(10)) = 10.000000000000002, refused by AirDrag
    assert math.exp(math.log(10.0)) > 10.0
    assert drag_coefficient_of(math.log(10.0)) == 10.0
    assert drag_coefficient_of(1e3) == CD_BOUNDS[1] and drag_coefficient_of(-1e3) == CD_BOUNDS[0]


def test_fit_drag_at_its_upper_bound_is_a_failed_fit_not_a_crash(heavy_drag_times):
    # found: fit_bounces(..., fit_drag=True) raised "drag_coefficient = 10.000000000000002 is
    # out of range"
    seq = cs.calibration.ImpactTimes(heavy_drag_times, 0.5, 'table tennis')
    fit = fit_bounces(PP_K, PP_MASS, [seq], laws=[cs.AZAD_FEATHERSTONE],
                      drag=AirDrag(1.2, 0.47, PP_RADIUS / 3.0), fit_drag=True)
    best = fit.best
    assert best.drag_coefficient <= CD_BOUNDS[1]
    assert best.drag_coefficient > 0.99 * CD_BOUNDS[1]
    assert not best.success and 'at a bound' in best.message
    assert not fit.trustworthy


def test_fewer_observations_than_parameters_are_refused():
    # found: N <= P printed an interval of zero width with exit 0
    with pytest.raises(ValueError, match='allowed more observations than parameters'):
        fit_bounces(1e8, 0.05, [np.array([0.0, 0.5, 0.9])], laws=[cs.HUNT_CROSSLEY])


def test_degenerate_or_undetermined_intervals_are_no_intervals():
    # found: lambda collapsing to 0 printed [0, 0]
    for value, half, word in ((0.0, 1.0, 'collapsed'), (5.0, 0.0, 'zero width'),
                              (5.0, 1e3, 'undetermined'), (math.nan, 1.0, 'collapsed')):
        interval, reason = log_interval('lambda', value, half)
        assert all(math.isnan(x) for x in interval) and word in reason
    interval, reason = log_interval('lambda', 2.0, math.log(2.0))
    assert interval == pytest.approx((1.0, 4.0)) and reason == ''


def rising_restitution_times(noise=30e-6):
    """Vacuum flights of a ball whose restitution rises with speed, e = 0.7 + 0.05 s/m v."""
    v, t = 3.0, [0.0]
    for _ in range(12):
        u = (0.7 + 0.05 * v) * v
        t.append(t[-1] + 2.0 * u / G)
        v = u
    return np.array(t) + np.random.default_rng(1).normal(0.0, noise, len(t))


def test_no_law_describes_a_restitution_rising_with_speed():
    # found: the fit's timing noise (tens of ms, a thousand resolutions) was never checked,
    # and the speed dependence was declared from it
    fit = fit_bounces(1e8, 0.05, [rising_restitution_times()])
    assert not fit.adequacy.adequate and not fit.trustworthy
    assert 'does not describe this recording' in fit.adequacy.reason
    assert 'rises with speed' in fit.adequacy.reason and 'no law fitted can follow' in \
        fit.adequacy.reason
    assert fit.adequacy.misfit > 10 * fit.adequacy.scatter and fit.adequacy.p_value < 1e-3


def test_a_rising_restitution_is_judged_on_the_held_out_clicks():
    fit = fit_bounces(1e8, 0.05, [rising_restitution_times()], holdout=0.4)
    verdict = fit.adequacy
    assert verdict.judged_on == 'hold-out' and not verdict.adequate
    assert 'held-out' in verdict.reason and 'rises with speed' in verdict.reason


def scattered_constant_e(seed, spread=0.01, e=0.8, count=14):
    """Vacuum flights of a ball whose e is 0.8 on average and scatters by ``spread`` from bounce
    to bounce (the surface, the spin): no trend, ordinary scatter."""
    rng = np.random.default_rng(seed)
    v, t = 3.0, [1.0]
    for _ in range(count - 1):
        u = (e + rng.normal(0.0, spread)) * v
        t.append(t[-1] + 2.0 * u / G)
        v = u
    return np.round(np.array(t) * 48000.0) / 48000.0


def test_a_constant_restitution_with_ordinary_scatter_is_not_no_law():
    # found: bounce-to-bounce scatter of a constant e was reported as "no law describes this"
    verdicts = [fit_bounces(1e8, 0.05, [scattered_constant_e(seed)]).adequacy
                for seed in range(4)]
    assert all(v.adequate and v.judged_on == 'fit' for v in verdicts), \
        [v.reason for v in verdicts]
    # its scatter of e is the recording's own, about the 0.01 put in
    assert all(0.004 < v.scatter < 0.03 for v in verdicts), [v.scatter for v in verdicts]
    # two halves of one recording (two drops each) get the verdict of the whole
    drops = [scattered_constant_e(seed) for seed in range(4, 8)]
    halves = [fit_bounces(1e8, 0.05, d).adequacy for d in (drops[:2], drops[2:], drops)]
    assert [h.adequate for h in halves] == [True, True, True], [h.reason for h in halves]


def test_a_fit_with_no_more_clicks_than_parameters_is_ill_determined_not_converged():
    # found: a law ranked first at 0.02 ms on 6 clicks for 6 parameters, "converged"
    seqs = [cs.calibration.ImpactTimes(scattered_constant_e(s, count=3), 0.46, f'drop {s}')
            for s in (1, 2)]
    fit = fit_bounces(1e8, 0.05, seqs, laws=[cs.HUNT_CROSSLEY],
                      drag=AirDrag(1.2, 0.47, 0.02), fit_drag=True)
    best = fit.best
    assert best.status in ('ill-determined', 'at-bound') and not best.success
    assert '6 clicks for 6 fitted parameters' in best.message
    assert not fit.trustworthy


def test_an_interval_spanning_orders_of_magnitude_is_ill_determined():
    # found: a drag coefficient interval of [0.003, 2158] passed as converged
    interval, reason = log_interval('C_d', 2.5, math.log(2158 / 2.5))
    assert interval == pytest.approx((2.5 * 2.5 / 2158, 2158)) and 'ill-determined' in reason


def test_a_recording_of_the_model_itself_is_adequate():
    lam = cs.damping_for_restitution(cs.HUNT_CROSSLEY, 1e8, 0.05, 0.8, 3.0)
    result = cs.simulate_drop(cs.Contact(cs.HUNT_CROSSLEY, 1e8, lam), 0.05, 0.8, duration=3.0)
    t = np.array([imp.time for imp in result.impacts if not imp.permanent])[:12]
    t = t + np.random.default_rng(3).normal(0.0, 50e-6, t.size)
    fit = fit_bounces(1e8, 0.05, [t])
    verdict = check_adequacy(fit)
    assert verdict.adequate and fit.trustworthy, verdict.reason
    assert 25e-6 < verdict.own_noise < 1e-3      # law-free: at least the 50 us put in


def test_recordings_no_bounce_can_make_are_refused_by_name():
    # found: bounce times 1e12 s apart and 12 clicks 1 ns apart printed a "result", exit 0
    t = np.array([0.0, 0.8, 1.44, 1.952, 2.36])
    with pytest.raises(ValueError, match=r'times\[1\] - times\[0\] = 8e\+11 s is out of range: '
                                         r'allowed flights up to 20387.4 s'):
        fit_bounces(1e8, 0.05, [t * 1e12])
    with pytest.raises(ValueError, match=r'= 1e-09 s is out of range: allowed intervals of at '
                                         r'least the timing resolution 2.08333e-05 s'):
        fit_bounces(1e8, 0.05, [np.arange(12) * 1e-9])


def test_a_start_value_that_is_not_finite_is_an_input_error(monkeypatch):
    # found (issue 34): scipy's "Initial guess is outside of provided bounds" reached the
    # caller when the start value of lambda was not finite
    from contact_sim.calibration import timing_fit
    monkeypatch.setattr(timing_fit, '_damping_guess', lambda *args: math.nan)
    with pytest.raises(cs.InputError, match='no start value for the fit of hunt_crossley: with '
                                            'stiffness = 100000000.0'):
        fit_bounces(1e8, 0.05, [scattered_constant_e(0)], laws=[cs.HUNT_CROSSLEY])


def slowly_rising_restitution_times(count=40, noise=1e-4):
    """Vacuum clicks of a 1 m drop whose e rises from 0.975 at 0.5 m/s to 0.986 at 4.5 m/s (the
    issue's steel ball), timed to 0.1 ms."""
    v, t = math.sqrt(2.0 * G), [math.sqrt(2.0 / G)]
    for _ in range(count - 1):
        v *= 0.975 + 0.011 * min(max((v - 0.5) / 4.0, 0.0), 1.0)
        t.append(t[-1] + 2.0 * v / G)
    return np.array(t) + np.random.default_rng(3).normal(0.0, noise, count)


def test_a_slow_rise_held_out_is_named_from_every_flight():
    # found (review of issue 32): on the last 30 % of one such drop the rise is no trend in
    # itself (t < 3 on 12 flights), so the INADEQUATE verdict gave no reason; the trend is a
    # property of the whole recording, read from every flight
    fit = fit_bounces({cs.LINEAR: 1.3e8}, 0.064, [slowly_rising_restitution_times()],
                      holdout=0.3)
    verdict = fit.adequacy
    assert verdict.judged_on == 'hold-out' and not verdict.adequate
    assert 'rises with speed' in verdict.reason


def test_a_constant_e_held_out_is_not_called_inadequate_for_its_short_flights():
    # found (review of issue 32): the held-out flights are the last and shortest, where 0.1 ms
    # click noise scatters e the most; judged against one scatter for all flights, 2 of these
    # 12 drops of a constant e (the linear law exact) were INADEQUATE (p < 0.001), none without
    # the hold-out, and one run of a recording flipped against the other
    verdicts = []
    for seed in range(100, 112):
        rng = np.random.default_rng(seed)
        v, t = math.sqrt(2.0 * G), [0.2 + math.sqrt(2.0 / G)]
        for _ in range(39):
            v *= 0.98
            t.append(t[-1] + 2.0 * v / G)
        fit = fit_bounces({cs.LINEAR: 1.3e8}, 0.064, [np.array(t) + rng.normal(0.0, 1e-4, 40)],
                          holdout=0.3)
        verdicts.append(fit.adequacy.adequate and fit.adequacy.judged_on == 'hold-out')
    assert all(verdicts)
