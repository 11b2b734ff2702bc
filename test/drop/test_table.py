"""Vibrating table: the closed-form thresholds Γ₁(e), Γ₂(e) and the full engine against them."""
import math

import numpy as np
import pytest

from contact_sim import InputError
from contact_sim.drop import bifurcation_diagram
from contact_sim.model import LINEAR
from contact_sim.model.contact import Contact
from contact_sim.drop.simulate import simulate_drop
from contact_sim.drop.table import (VibratingTable, period_doubling_threshold, period_one_phase,
                               period_one_threshold)

G, MASS, FREQ = 9.81, 0.01, 20.0


def _impact_map(e, gamma, theta0, v0, n, w=2 * math.pi * FREQ):
    """The exact constant-e impact map (module docstring), iterated in phase: the slow reference
    of the closed forms (independent of the engine)."""
    from scipy.optimize import brentq
    a = gamma * G / w ** 2
    t, v, out = theta0 / w, v0, []
    for _ in range(n):
        def gap(s, t=t, v=v):
            return a * math.sin(w * t) + v * s - 0.5 * G * s * s - a * math.sin(w * (t + s))
        # first root after the take-off: scan finely, then Brent
        s = 1e-9
        while True:
            s_new = s + 1e-4
            if gap(s_new) < 0.0:
                break
            s = s_new
        dt = brentq(gap, s, s_new, xtol=1e-15)
        t += dt
        v = -e * (v - G * dt) + (1 + e) * a * w * math.cos(w * t)
        out.append(dt)
    return np.array(out)


@pytest.mark.parametrize('e', [0.5, 0.8])
def test_closed_forms_against_the_exact_constant_e_map(e):
    w = 2 * math.pi * FREQ
    V = math.pi * G / w
    g1, g2 = period_one_threshold(e), period_doubling_threshold(e)
    for gamma, periodic in ((0.99 * g2, True), (1.01 * g2, False)):
        theta = period_one_phase(e, gamma)
        d = _impact_map(e, gamma, theta + 1e-3, V, 400)[-20:] * FREQ
        assert (np.ptp(d) < 1e-6) == periodic
    assert period_one_phase(e, g1) == 0.0
    with pytest.raises(ValueError, match='gamma'):
        period_one_phase(e, 0.9 * g1)


def test_threshold_arguments_are_validated():
    with pytest.raises(ValueError, match='restitution'):
        period_one_threshold(1.5)


def _classify(contact, e, gamma, bounces=300):
    table = VibratingTable(contact, MASS, FREQ, bounces=bounces, transient=0,
                           restitution_guess=e, max_periods=40 if gamma < period_one_threshold(e)
                           else 5000)
    times = table.run(gamma)[0]
    d = np.diff(times) * FREQ
    if len(d) < bounces - 1:
        return 'other'            # stopped bouncing (carried) or chattering
    d = d[-20:]
    if np.ptp(d) < 1e-5 and abs(d.mean() - 1.0) < 1e-5:
        return 'period-1'
    if np.max(np.abs(d[:-2] - d[2:])) < 1e-5 and np.ptp(d) > 1e-3:
        return 'period-2'
    return 'other'


@pytest.mark.parametrize('damping', [1360.0, 715.0, 327.0])
def test_engine_thresholds_within_one_percent(damping):
    # the linear law (constant e) with 10 µs contacts on a 20 Hz table
    contact = Contact(LINEAR, 1e9, damping)
    speed = math.pi * G / (2 * math.pi * FREQ)
    e = simulate_drop(contact, MASS, 0.0, velocity=1.3 * speed, duration=1e-3).impacts[0] \
        .restitution
    g1, g2 = period_one_threshold(e), period_doubling_threshold(e)
    assert _classify(contact, e, 0.99 * g1) == 'other'
    assert _classify(contact, e, 1.01 * g1) == 'period-1'
    assert _classify(contact, e, 0.99 * g2) == 'period-1'
    assert _classify(contact, e, 1.01 * g2) == 'period-2'


@pytest.mark.parametrize('kwargs, pattern', [
    (dict(frequency=0.0), r'frequency = 0\.0 is out of range: allowed 0 < frequency <= 1000'),
    (dict(bounces=2.5), r'bounces = 2\.5 is not an integer: allowed 1 <= bounces'),
    (dict(transient=-1), r'transient = -1 is out of range'),
    (dict(restitution_guess=1.0), r'restitution_guess = 1\.0 is out of range'),
    (dict(mass=0.0), r'mass = 0\.0 is out of range'),
])
def test_a_vibrating_table_checks_its_fields(kwargs, pattern):
    # issue 17, reproduced: frequency = 0 was a ZeroDivisionError, bounces = 2.5 a TypeError
    args = dict(contact=Contact(LINEAR, 1e9, 715.0), mass=0.01, frequency=20.0)
    with pytest.raises(InputError, match=pattern):
        VibratingTable(**{**args, **kwargs})


@pytest.mark.parametrize('gamma', [-1.0, 1e6, float('nan')])
def test_a_vibrating_table_refuses_a_gamma_no_table_reaches(gamma):
    # issue 17, reproduced: Gamma = 1e6 gave empty arrays, Gamma = -1 an error about `amplitude`
    table = VibratingTable(Contact(LINEAR, 1e9, 715.0), 0.01, 20.0, bounces=3, transient=0)
    top = table.gamma_max()     # 1000 m/s^2 of the table's peak acceleration over g
    assert top == pytest.approx(1000.0 / 9.81)
    with pytest.raises(InputError, match=r'gamma = .* (is out of range: allowed 0 <= gamma '
                       r'<= 101\.937|is not finite)'):
        table(gamma)


def test_an_empty_bifurcation_diagram_is_empty():
    # issue 17, reproduced: bifurcation_diagram(T, []) said "need at least one array to concatenate"
    table = VibratingTable(Contact(LINEAR, 1e9, 715.0), 0.01, 20.0, bounces=3, transient=0)
    x, phases = bifurcation_diagram(table, [])
    assert x.shape == phases.shape == (0,)
