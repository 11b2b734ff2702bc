"""Hostile inputs to the moving plate and the drop's entry points (issue 34): each refused with an
InputError naming the argument, never a RuntimeWarning, a TypeError or a non-finite answer."""
import math
import warnings

import pytest

import contact_sim as cs
from contact_sim.drop import CommandedPlate, SinusoidalPlate, command_motion, sphere_motion

C = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)


@pytest.fixture(autouse=True)
def warnings_are_errors():
    with warnings.catch_warnings():
        warnings.simplefilter('error', RuntimeWarning)
        yield


@pytest.mark.parametrize('args, kwargs, field', [
    (('a', 0.0, 0.0), {}, 'radius'), ((math.nan, 0.0, 0.0), {}, 'radius'),
    ((True, 0.0, 0.0), {}, 'radius'), ((0.01, math.inf, 0.0), {}, 'penetration'),
    ((0.01, 0.0, math.nan), {}, 'penetration_rate'),
    ((0.01, 0.0, 0.0), {'plate_position': None}, 'plate_position'),
    ((0.01, 0.0, 0.0), {'plate_velocity': -math.inf}, 'plate_velocity'),
    ((1e308, -1e308, 0.0), {'plate_position': 1e308}, 'radius')])
def test_sphere_motion_refuses_what_is_not_a_finite_number(args, kwargs, field):
    # reproduced: TypeError for 'a' and None, (nan, 0.0) for a nan radius
    with pytest.raises(cs.InputError) as info:
        sphere_motion(*args, **kwargs)
    assert info.value.field == field


def test_sphere_motion_keeps_floats_floats():
    height, velocity = sphere_motion(0.01, 0.001, -0.5, 0.002, 0.1)
    assert type(height) is float and height == pytest.approx(0.011)
    assert velocity == pytest.approx(0.6)


@pytest.mark.parametrize('times, positions, velocities, field', [
    ((0.0, 1e-300), (0.0, 0.01), (0.0, 0.0), 'times'),      # accelerations of 1e298 m/s^2
    ((0.0, 1e300), (0.0, 0.01), (0.0, 0.0), 'times'),
    ((0.0, 1.0), (0.0, 1e300), (0.0, 0.0), 'positions'),
    ((0.0, 1.0), (0.0, 0.0), (0.0, -1e300), 'velocities'),
    ((0.0, 1.0), (0.0, True), (0.0, 0.0), 'positions'),
    ((0.0, '1'), (0.0, 0.0), (0.0, 0.0), 'times')])
def test_a_commanded_plate_refuses_set_points_its_doubles_cannot_follow(times, positions,
                                                                        velocities, field):
    # reproduced: divide-by-zero and overflow warnings, inf and nan states
    with pytest.raises(cs.InputError) as info:
        CommandedPlate(times, positions, velocities)
    assert info.value.field == field


def test_tiny_set_points_are_followed():
    plate = CommandedPlate((0.0, 1.0), (0.0, 1e-300), (0.0, 0.0))
    assert all(math.isfinite(x) for x in plate.state(0.5))


@pytest.mark.parametrize('now, times, positions, field', [
    (0.0, [1e-300, 1.0], [0.01, 0.0], 'times'), (0.0, [0.5, 1.0], ['0.01', 0.0], 'positions'),
    (1e300, [1.0], [0.0], 'now')])
def test_command_motion_refuses_naming_the_field(now, times, positions, field):
    with pytest.raises(cs.InputError) as info:
        command_motion(now, 0.0, 0.0, times, positions)
    assert info.value.field == field


@pytest.mark.parametrize('frequency', [5e-324, 1e-300, 1e-4])
def test_a_table_frequency_is_zero_or_at_least_a_millihertz(frequency):
    # reproduced (node): plate_frequency = 5e-324 refused with 'math domain error'
    with pytest.raises(cs.InputError, match=r'^frequency = .* allowed frequency = 0') as info:
        SinusoidalPlate(0.001, frequency, 0.0)
    assert info.value.field == 'frequency'
    assert SinusoidalPlate(0.001, 1e-3, 0.0).frequency == 1e-3


@pytest.mark.parametrize('damping', [5e-324, 1e-320, 1e-200])
def test_a_damping_whose_group_underflows_is_refused_by_the_drop(damping):
    # reproduced: 5e-324 accepted with an overflow warning though ZETA_MIN refuses it
    with pytest.raises(cs.InputError, match=r'^damping = .* allowed damping = 0') as info:
        cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, damping), 0.066, 1.0,
                         duration=1.0)
    assert info.value.field == 'damping'
    # a single impact still answers (e = 1 to every digit)
    assert cs.restitution(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, damping), 0.066, 1.0) == 1.0


@pytest.mark.parametrize('gravity', [1e300, 1e7, -1.0, '9.81'])
def test_an_impact_takes_gravity_by_the_drops_rule(gravity):
    # reproduced: OverflowError for 1e300; 1e7 accepted by simulate_impact, refused by the drop
    for call in (lambda: cs.simulate_impact(C, 0.066, 1.0, gravity=gravity),
                 lambda: cs.simulate_drop(C, 0.066, 1.0, duration=0.1, gravity=gravity)):
        with pytest.raises(cs.InputError, match=r'^gravity = ') as info:
            call()
        assert info.value.field == 'gravity'


@pytest.mark.parametrize('plate_speed', [1e300, -1.0, math.nan])
def test_check_drop_names_the_plate_speed(plate_speed):
    # reproduced: plate_speed = 1e300 reported as 'speed'
    with pytest.raises(cs.InputError, match=r'^plate_speed = ') as info:
        cs.check_drop(C, 0.066, 9.81, 1.0, 0.0, plate_speed=plate_speed)
    assert info.value.field == 'plate_speed'


@pytest.mark.parametrize('args', [(0.01, 0.0, 1j), (0.01, 0.0, 0.0, 0.0, 1 + 2j),
                                  (0.01, 0.0, 0.0, 1j, 0.0)])
def test_sphere_motion_refuses_complex_numbers(args):
    # reproduced (this campaign): a complex velocity returned, its imaginary part carried on
    with pytest.raises(cs.InputError, match='not a real number'):
        sphere_motion(*args)


def test_sphere_motion_takes_integers():
    assert sphere_motion(0, 0, 0) == (0, 0)


@pytest.mark.parametrize('kwargs, field', [
    (dict(height=5e-324), 'height'), (dict(height=1e-320), 'height'),
    (dict(gravity=5e-324), 'gravity'), (dict(plate_speed=1e-300, height=0.0), 'plate_speed')])
def test_a_landing_too_slow_for_the_doubles_names_what_made_it(kwargs, field):
    # reproduced (this branch's probe): `drop --height 5e-324` refused as '--speeds = 9.9e-162'
    args = dict(contact=C, mass=0.066, gravity=9.81, height=1.0, velocity=0.0)
    args.update(kwargs)
    with pytest.raises(cs.InputError, match=rf'^{field} = .* gives a first impact at') as info:
        cs.check_drop(**args)
    assert info.value.field == field
