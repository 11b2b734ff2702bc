"""Hostile inputs to FlightPath (issue 17): its constructor checks every field."""
import math

import pytest

import contact_sim as cs


@pytest.mark.parametrize('height, velocity, gravity, field', [
    (math.nan, 0.0, 9.81, 'height'), (math.inf, 0.0, 9.81, 'height'), ('abc', 0.0, 9.81, 'height'),
    (1.0, math.nan, 9.81, 'velocity'), (1.0, -math.inf, 9.81, 'velocity'),
    (1.0, 0.0, math.inf, 'gravity'), (1.0, 0.0, 0.0, 'gravity'), (None, 0.0, 9.81, 'height')])
def test_flight_path_refuses_fields_that_are_not_finite_reals(height, velocity, gravity, field):
    # reproduced: FlightPath(nan, ...) and FlightPath('abc', 0, 9.81) accepted
    with pytest.raises(cs.InputError, match=f'^{field} = ') as info:
        cs.FlightPath(height, velocity, gravity)
    assert info.value.field == field


@pytest.mark.parametrize('height', [-1.0, -1e-9, -1e300])
def test_a_flight_starting_inside_the_plate_is_refused(height):
    # reproduced (issue 34): FlightPath(-1.0, 0.0, 9.81), 1 m inside the plate, accepted
    with pytest.raises(cs.InputError, match=r'^height = .* allowed 0 <= height') as info:
        cs.FlightPath(height, 0.0, 9.81)
    assert info.value.field == 'height'


def test_a_touch_the_flight_never_reaches_is_refused():
    # reproduced: FlightPath(-1.0, 0.0, 9.81).touch() -> (inf, nan); a flight over a plate
    # whose surface is at -1.5 m
    path = cs.FlightPath(-1.0, 0.0, 9.81, surface=-1.5)
    with pytest.raises(cs.InputError, match=r'^level = 0.0 m is above the flight.*allowed level'):
        path.touch()
    t, speed = path.touch(-2.0)
    assert t == pytest.approx(math.sqrt(2.0 / 9.81)) and speed == pytest.approx(math.sqrt(2 * 9.81))


def test_fields_are_stored_as_floats():
    path = cs.FlightPath(1, 0, 10)
    assert type(path.height) is float and type(path.gravity) is float
