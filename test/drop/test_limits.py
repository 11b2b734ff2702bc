"""The drops the engine refuses (``limits``): arguments out of range, contacts it cannot
follow or outside the model's validity, and the bounded work of ``simulate_drop``."""
import re

import numpy as np
import pytest

import contact_sim as cs

M = 0.066


@pytest.mark.parametrize('kwargs, pattern', [
    (dict(mass=-1.0), r'mass = -1\.0 is out of range'),
    (dict(height=float('nan')), r'height = nan is not finite'),
    (dict(gravity=-9.81), r'gravity = -9\.81 is out of range: allowed 0 <= gravity'),
])
def test_drop_rejects_bad_arguments(kwargs, pattern):
    args = dict(contact=cs.Contact(cs.LINEAR, 1e6, 1.0), mass=1.0, height=1.0, gravity=9.81)
    args.update(kwargs)
    with pytest.raises(ValueError, match=pattern):
        cs.DropSimulation(**args)
    sim = cs.DropSimulation(cs.Contact(cs.LINEAR, 1e6, 1.0), 1.0, 1.0)
    sim.advance(0.5)
    with pytest.raises(ValueError, match=r't_end = 0\.1 is out of range: allowed t_end >= 0\.5'):
        sim.advance(0.1)


def test_an_overdamped_drop_that_would_hang_is_refused_with_the_damping_bound():
    # reproduced: `contact-sim drop --stiffness 1e10 --damping 1e30 --mass 0.066` never ended
    with pytest.raises(ValueError, match=r'damping = 1e\+30 is too large .* allowed damping <= '
                                         r'2\.5\d*e\+13') as info:
        cs.DropSimulation(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e30), M, 1.0)
    assert info.value.field == 'damping'
    lam_max = float(re.search(r'damping <= (\S+)', str(info.value)).group(1))
    result = cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, lam_max * 0.999), M, 1.0,
                              duration=1.0)
    assert result.impacts[-1].permanent


@pytest.mark.parametrize('kwargs, field, pattern', [
    ({'height': -1.0}, 'height', r'height = -1\.0 is out of range: allowed 0 <= height'),
    ({'rtol': 1e300}, 'rtol', r'rtol = 1e\+300 is out of range: allowed 1e-14 <= rtol <= 0\.001'),
    ({'rtol': 1.0}, 'rtol', r'rtol = 1\.0 is out of range'),
    ({'mass': 1e-300}, 'mass', r'mass = 1e-300 is out of range: allowed 1e-12 <= mass'),
    ({'mass': 1e300}, 'mass', r'mass = 1e\+300 is out of range'),
    ({'gravity': 1e300}, 'gravity', r'gravity = 1e\+300 is out of range'),
    ({'contact': cs.Contact(cs.AZAD_FEATHERSTONE, 1e300, 1e5)}, 'stiffness',
     r'stiffness = 1e\+300 N/m\^1\.5 is too large .* allowed stiffness <= 3\.1\d*e\+28'),
    ({'contact': None}, 'contact', r'contact = None is not a Contact'),
    ({'contact': 'azad_featherstone'}, 'contact', r"contact = 'azad_featherstone' is not a"),
])
def test_drop_refuses_inputs_it_cannot_follow_naming_the_field(kwargs, field, pattern):
    # reproduced: a negative height launched the sphere at 87 km/s, rtol = 1e300 gave 86 bogus
    # impacts, k = 1e300 a restitution of 1.2e131, mass = 1e-300 a RuntimeError, None or a
    # string an AttributeError
    args = dict(contact=cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), mass=M, height=1.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=pattern) as info:
        cs.simulate_drop(**args, duration=1.0)
    assert info.value.field == field


def test_the_depth_check_is_in_the_drop_engine_with_both_bounds():
    # reproduced: simulate_drop accepted k = 5e4 (16.2 mm penetration of a 12.7 mm sphere)
    radius, n = 0.0127, 1.5
    mass = cs.sphere_mass(7850.0, radius)
    soft = cs.Contact(cs.AZAD_FEATHERSTONE, 5e4, 0.0)
    with pytest.raises(ValueError, match=r'stiffness = 5e\+04 N/m\^1\.5 is too small for this '
                                         r'drop.*allowed stiffness >= (\S+) N/m\^1\.5 or height '
                                         r'<= (\S+) m') as info:
        cs.simulate_drop(soft, mass, 1.0, radius=radius)
    assert info.value.field == 'stiffness'
    k_min = (n + 1) * (0.5 * mass * 2 * 9.81 * 1.0 + mass * 9.81 * radius) / radius ** (n + 1)
    assert f'stiffness >= {k_min:.4g}' in str(info.value)
    h_max = float(re.search(r'height <= (\S+) m', str(info.value)).group(1))
    shallow = cs.simulate_drop(soft, mass, h_max * 0.999, radius=radius, duration=0.5)
    assert 0.0 < max(imp.max_penetration for imp in shallow.impacts) <= radius
    cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, k_min * 1.0001, 0.0), mass, 1.0,
                     radius=radius, duration=0.5)                         # just above: accepted
    sim = cs.DropSimulation(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), mass, 1.0,
                            radius=radius)
    with pytest.raises(ValueError, match='too small for this drop'):     # also while running
        sim.set_contact(soft)


def test_simulate_drop_bounds_its_work_and_says_the_limit():
    # reproduced: `drop --duration 1e6 --plot` reached 15.7 GB in 60 s
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
    with pytest.raises(ValueError, match=r'makes 1e\+09 samples: allowed at most 200000') as info:
        cs.simulate_drop(contact, M, 1.0, duration=1e6, sample_rate=1000.0)
    assert info.value.field == 'sample_rate'
    with pytest.raises(ValueError, match=r'sample_rate = 1000000000\.0 is out of range'):
        cs.simulate_drop(contact, M, 1.0, duration=0.5, sample_rate=1e9)
    elastic = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 0.0)
    with pytest.raises(ValueError, match=r'duration = 1000\.0 s needs more than 500 integrator '
                                         r'steps') as info:
        cs.simulate_drop(elastic, M, 1.0, duration=1e3, max_steps=500)
    assert info.value.field == 'duration'


# -- issue 17: every path of the drop layer checks its inputs in the constructor it goes through
C = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)


@pytest.mark.parametrize('args, pattern', [
    ((C, 0.066, 9.81, float('nan'), 0.0), r'height = nan is not finite'),
    ((C, -1.0, 9.81, 1.0, 0.0), r'mass = -1\.0 is out of range: allowed 1e-12 <= mass'),
    ((C, 0.066, -1.0, 1.0, 0.0), r'gravity = -1\.0 is out of range'),
    ((C, 0.066, 9.81, 1.0, 1e300), r'velocity = 1e\+300 is out of range'),
    (('contact', 0.066, 9.81, 1.0, 0.0), r'contact = .* is not a Contact'),
])
def test_check_drop_checks_its_own_arguments(args, pattern):
    # reproduced: a nan height gave "allowed stiffness >= nan", a negative mass a TypeError
    with pytest.raises(cs.InputError, match=pattern):
        cs.check_drop(*args, radius=0.0127)


@pytest.mark.parametrize('kwargs, pattern', [
    (dict(drag=0.5), r'drag = 0\.5 is not None or an AirDrag'),
    (dict(plate=0.5), r'plate = 0\.5 is invalid: allowed None, a SinusoidalPlate'),
    (dict(radius=1e-308), r'radius = 1e-308 is out of range: allowed 1e-09 <= radius <= 1000'),
    (dict(radius=1e308), r'radius = 1e\+308 is out of range'),
])
def test_a_drop_refuses_what_is_not_a_drag_a_plate_or_a_radius(kwargs, pattern):
    # reproduced: AttributeError ('float' has no attribute 'active'), ZeroDivisionError
    with pytest.raises(cs.InputError, match=pattern):
        cs.simulate_drop(C, 0.066, 1.0, duration=0.1, **kwargs)


@pytest.mark.parametrize('plate, pattern', [
    (dict(amplitude=0.1, frequency=100.0), r'amplitude = 0\.1 m at frequency = 100 Hz shakes the '
     r'plate at 3\.948e\+04 m/s\^2: allowed a \(2 pi f\)\^2 <= 1000 m/s\^2'),
    (dict(amplitude=1e308, frequency=20.0), r'amplitude = 1e\+308 is out of range: allowed 0 <= '
     r'amplitude <= 0\.1 \(m\)'),
    (dict(amplitude=0.001, frequency=1e4), r'frequency = 10000\.0 is out of range'),
    (dict(amplitude=0.001, frequency=10.0, phase=7.0), r'phase = 7\.0 is out of range'),
])
def test_every_table_is_in_the_tables_ranges_whatever_builds_it(plate, pattern):
    # reproduced: simulate_drop ran a 3.9e4 m/s^2 table that the node refuses, and a 1e308 m
    # amplitude was blamed on the stiffness
    with pytest.raises(cs.InputError, match=pattern):
        cs.simulate_drop(C, 0.066, 1.0, duration=0.1,
                         plate=cs.drop.SinusoidalPlate(**plate))


def test_advance_refuses_times_beyond_its_range_and_too_many_ticks():
    # reproduced: advance(1e308) raised "math domain error"; advance_ticks took 1e8 ticks
    # into memory
    sim = cs.DropSimulation(C, 0.066, 1.0)
    with pytest.raises(cs.InputError, match=r't_end = 1e\+308 is out of range: allowed t_end '
                       r'<= 1e\+09 s'):
        sim.advance(1e308)
    with pytest.raises(cs.InputError, match=r'times has 1000001 tick times: allowed at most '
                       r'1000000 a call'):
        sim.advance_ticks(np.zeros(1_000_001))
    for bad in ('abc', [[0.1]], [0.1, float('nan')], [0.2, 0.1], [1e308]):
        with pytest.raises(cs.InputError, match='times'):
            sim.advance_ticks(bad)
    assert sim.time == 0.0
