"""The coupling core against the package's own exact results, through a semi-implicit Euler host
(``host.run_host``): drops, throws at every phase of the step, rest, every law, bad input."""
import math

import numpy as np
import pytest

import contact_sim as cs
from contact_sim.coupling import NormalCoupling, touch_time

from .host import apexes, run_continuous_host, run_host

G = 9.81
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=0.0127,
                                  damping_factor=8.87e5)
MASS = cs.sphere_mass(cs.MATERIALS['steel'].density, 0.0127)
SPEEDS = np.geomspace(0.05, 10.0, 12)
PHASES = np.arange(8) / 8.0


@pytest.fixture(scope='module')
def exact_drop():
    return cs.simulate_drop(STEEL, MASS, height=1.0)


@pytest.mark.parametrize('dt', [1e-4, 5e-4, 1e-3, 2e-3])
def test_drop_apexes_and_rest(dt, exact_drop):
    coupling = NormalCoupling(STEEL)
    times, gaps, rates, impulses = run_host(coupling, MASS, 1.0, 0.0, -G, dt, int(13.0 / dt))
    heights = apexes(times, gaps, coupling.impacts, 10)
    for k, (h, h_exact) in enumerate(zip(heights, exact_drop.apex_heights)):
        speed = coupling.impacts[k].speed_out
        assert abs(h - h_exact) <= max(0.01 * h_exact, speed * dt), (k, h, h_exact)
    assert all(b < a for a, b in zip(heights, heights[1:]))
    # at rest from 3 s on: the static penetration to 1 µm (here to round-off), the weight exactly
    z0 = STEEL.static_penetration(MASS * G)
    rest = times > 3.0
    assert np.max(np.abs(-gaps[rest] - z0)) < 1e-6
    assert np.max(np.abs(-gaps[rest] - z0)) < 1e-15
    np.testing.assert_allclose(impulses[rest], MASS * G * dt, rtol=1e-12)
    assert np.all(np.abs(rates[rest]) < 1e-9)


def _throw_restitution(contact, mass, speed, phase, dt, steps=8, lead=3.0):
    coupling = NormalCoupling(contact)
    out = run_host(coupling, mass, speed * dt * (lead + phase), -speed, 0.0, dt, steps)
    assert len(coupling.impacts) == 1
    return out[2, -1] / speed, coupling.impacts[0].restitution


@pytest.mark.parametrize('dt', [1e-4, 1e-3, 2e-3])
@pytest.mark.parametrize('law', ['azad_featherstone', 'hunt_crossley'])
def test_throws_at_every_phase_of_the_step(dt, law):
    # Hunt-Crossley with λ = 0.08 s/m k: e from 0.997 to 0.6 over the speeds
    contact = STEEL if law == 'azad_featherstone' else cs.Contact(
        cs.LAWS[law], STEEL.stiffness, 0.08 * STEEL.stiffness)
    exact = cs.restitution(contact, MASS, SPEEDS)
    assert np.ptp(exact) > 0.05          # e(v) varies over the speeds thrown
    for speed, e in zip(SPEEDS, exact):
        for phase in PHASES:
            e_host, e_impact = _throw_restitution(contact, MASS, speed, phase, dt)
            assert abs(e_host - e) < 0.005 and abs(e_impact - e) < 0.005, (speed, phase)


def test_a_soft_contact_spans_many_host_steps_as_one_contact():
    contact = cs.Contact(cs.HUNT_CROSSLEY, 2e5, 2e3)
    mass, dt = 0.05, 1e-4
    exact = cs.restitution(contact, mass, SPEEDS)
    for speed, e in zip(SPEEDS, exact):
        duration = float(cs.contact_duration(contact, mass, speed))
        assert duration > 5 * dt
        steps = int(duration / dt) + 10
        for phase in PHASES:
            e_host, e_impact = _throw_restitution(contact, mass, speed, phase, dt, steps)
            assert abs(e_host - e) < 0.005 and abs(e_impact - e) < 0.005, (speed, phase)


@pytest.mark.parametrize('law', [cs.LEE_WANG, cs.LINEAR,
                                 cs.ContactLaw('custom', 1.25, 0.75, 1.3)])
def test_every_law_and_a_custom_one(law):
    contact = cs.Contact(law, 1e7 if law.n > 1.0 else 1e5, 40.0 if law is not cs.LINEAR else 5.0)
    mass, dt = 0.05, 1e-3
    for speed in (0.1, 1.0, 5.0):
        exact = float(cs.simulate_impact(contact, mass, speed).restitution)
        for phase in (0.0, 0.3, 0.9):
            e_host, e_impact = _throw_restitution(contact, mass, speed, phase, dt, steps=40)
            assert abs(e_host - exact) < 0.005 and abs(e_impact - exact) < 1e-6


def test_resting_holds_the_weight_from_the_first_step_without_jitter():
    z0 = STEEL.static_penetration(MASS * G)
    coupling = NormalCoupling(STEEL)
    times, gaps, rates, impulses = run_host(coupling, MASS, -z0, 0.0, -G, 1e-3, 2000)
    assert np.ptp(impulses) <= 1e-12 * MASS * G * 1e-3
    assert abs(impulses[-1] - MASS * G * 1e-3) <= 1e-12 * MASS * G * 1e-3
    assert np.max(np.abs(-gaps - z0)) < 1e-9 * z0 + 1e-18


def test_a_push_from_outside_is_taken_from_the_host():
    """The host's velocity changed beyond what the coupling gave it: the exact state follows."""
    z0 = STEEL.static_penetration(MASS * G)
    coupling = NormalCoupling(STEEL)
    y, v, t, dt = -z0, 0.0, 0.0, 1e-3
    for i in range(20):
        step = coupling.step(t, y, v, MASS, -G, dt)
        v += -G * dt + step.impulse / MASS + (2.0 if i == 10 else 0.0)   # a kick up at step 10
        y += dt * v
        t += dt
    # the kick launched a flight: a rising ball, no contact and no pull
    assert y > 0.01 and not coupling.carrying or coupling._carried.mode == 'flight'


def test_the_flight_touch_is_the_parabola_root():
    t = touch_time(STEEL, -0.01, 1.0, G, 1.0)
    assert abs(-0.01 + t + 0.5 * G * t * t) < 1e-15
    assert math.isinf(touch_time(STEEL, -0.01, -1.0, -G, 10.0))
    assert touch_time(STEEL, 0.0, 0.0, G, 0.0) == 0.0
    assert math.isinf(touch_time(STEEL, 0.0, 0.0, -G, 1.0))


@pytest.mark.parametrize('field, args', [
    ('gap', (0.0, math.nan, 0.0, 1.0, -G, 1e-3)),
    ('gap_rate', (0.0, 0.1, 'fast', 1.0, -G, 1e-3)),
    ('mass', (0.0, 0.1, 0.0, 0.0, -G, 1e-3)),
    ('gap_acceleration', (0.0, 0.1, 0.0, 1.0, math.inf, 1e-3)),
    ('dt', (0.0, 0.1, 0.0, 1.0, -G, -1e-3)),
    ('dt', (0.0, 0.1, 0.0, 1.0, -G, 0.0)),
    ('time', (math.nan, 0.1, 0.0, 1.0, -G, 1e-3)),
])
def test_bad_input_names_its_field(field, args):
    with pytest.raises(cs.InputError) as refused:
        NormalCoupling(STEEL).step(*args)
    assert refused.value.field == field


def test_bad_construction_names_its_field():
    with pytest.raises(cs.InputError) as refused:
        NormalCoupling('steel')
    assert refused.value.field == 'contact'
    with pytest.raises(cs.InputError) as refused:
        NormalCoupling(STEEL, tolerance=0.0)
    assert refused.value.field == 'tolerance'


@pytest.mark.parametrize('dt', [1e-3, 2e-3])
def test_a_continuous_host_follows_the_exact_state(dt, exact_drop):
    """A host that integrates the step's linear force exactly (Drake's continuous plant) ends
    every step at the exact gap and velocity: apexes, rest and throws as the exact ones."""
    coupling = NormalCoupling(STEEL, host='continuous')
    times, gaps, rates, impulses = run_continuous_host(coupling, MASS, 1.0, 0.0, -G, dt,
                                                       int(4.0 / dt))
    heights = apexes(times, gaps, coupling.impacts, 10)
    for k, (h, h_exact) in enumerate(zip(heights, exact_drop.apex_heights)):
        assert abs(h - h_exact) <= max(0.01 * h_exact, coupling.impacts[k].speed_out * dt)
    z0 = STEEL.static_penetration(MASS * G)
    assert np.max(np.abs(-gaps[times > 3.0] - z0)) < 1e-15
    for speed, e in zip(SPEEDS, cs.restitution(STEEL, MASS, SPEEDS)):
        for phase in PHASES:
            coupling = NormalCoupling(STEEL, host='continuous')
            out = run_continuous_host(coupling, MASS, speed * dt * (3.0 + phase), -speed, 0.0,
                                      dt, 8)
            assert abs(out[2, -1] / speed - e) < 1e-6


def test_an_unknown_host_is_refused():
    with pytest.raises(cs.InputError) as refused:
        NormalCoupling(STEEL, host='rk4')
    assert refused.value.field == 'host'


def test_a_step_out_of_reach_returns_finite_numbers():
    out = NormalCoupling(STEEL).step(0.0, 0.5, -1.0, MASS, -G, 1e-3)
    assert out.impulse == 0.0 and not out.touched and not NormalCoupling(STEEL).carrying
    assert math.isfinite(out.penetration) and math.isfinite(out.penetration_rate)
    assert out.penetration == pytest.approx(-(0.5 - 1e-3 * (1.0 + 0.5 * G * 1e-3)
                                              - 0.5 * G * 1e-6), rel=1e-12)


def test_the_force_returns_inside_the_surface_on_a_strong_push():
    # a flight inside the surface (z > 0, force zero: receding fast enough) pushed back in:
    # the force's return was bracketed, then brentq refused its own rtol (ValueError raised
    # from the step of a coupled ball on a crate standing on MuJoCo's floor)
    law, k, lam = STEEL.law, STEEL.stiffness, STEEL.damping
    z = 1e-6
    v = -1.01 * (k * z ** (law.n - law.p) / lam) ** (1.0 / law.q)
    for a in (1e4, 1e5):
        t = touch_time(STEEL, z, v, a, 1e-3)
        assert 0.0 < t < 1e-3
        zt, vt = z + v * t + 0.5 * a * t * t, v + a * t
        assert abs(k * zt ** (law.n - law.p) + lam * vt) <= 1e-9 * k * z ** (law.n - law.p)
