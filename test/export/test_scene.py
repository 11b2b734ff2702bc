"""The real scene's verdict: the lowest speed at which a claim holds with gravity, the refusal of
a contact that cannot hold the ball up, and the step suggested to hold lower."""
import math

import numpy as np
import pytest
from .test_export import steel_on_cast_iron

from contact_sim.export import scene
from contact_sim.validation import InputError

SPEEDS = [0.1, 1.0, 10.0]


def test_the_lowest_speed_is_where_every_faster_speed_holds():
    claimed = np.array([0.7, 0.7, 0.7])
    assert scene.lowest_holding_speed(SPEEDS, claimed, [0.75, 0.704, 0.701]) == 1.0
    assert scene.lowest_holding_speed(SPEEDS, claimed, [0.701, 0.75, 0.701]) == 10.0
    assert scene.lowest_holding_speed(SPEEDS, claimed, [0.701, 0.701, 0.72]) is None
    assert scene.lowest_holding_speed(SPEEDS, claimed, claimed) == 0.1


def test_every_phase_must_hold():
    claimed = np.array([0.7, 0.7, 0.7])
    phases = np.array([[0.7, 0.7], [0.7, 0.71], [0.7, 0.7]])   # the mean is within 0.005
    assert scene.lowest_holding_speed(SPEEDS, claimed, phases) == 10.0


def test_a_ball_sunk_by_its_radius_is_refused_with_the_step_that_holds_it():
    target = steel_on_cast_iron(SPEEDS)
    e = np.full(3, 0.7)
    with pytest.raises(InputError) as error:
        scene.assess(target, e, e, 4 * target.radius, 1e-3, 1e-6, 'measured', 'X', 1.0)
    assert error.value.field == 'timestep'
    assert 'cannot hold the ball up' in str(error.value)
    # the sag grows as the step squared: half the step for a quarter of the sag, less 1 %
    assert 'allowed a step below 0.00049 s' in str(error.value)
    with pytest.raises(InputError) as error:   # fell through: the spring's own sag decides
        scene.assess(target, e, e, math.inf, 1e-3, 1e-6, 'measured', 'X', target.radius / 16)
    assert 'allowed a step below 0.004 s' in str(error.value)   # 4 times, less 1 %


def test_the_step_suggested_scales_the_worst_error():
    target = steel_on_cast_iron(SPEEDS)
    claimed = np.full(3, 0.7)
    checked = scene.assess(target, claimed, [0.75, 0.7, 0.7], 1e-4, 1e-3, 1e-6, 'measured', 'X',
                           1e-4)
    assert checked.lowest_speed == 1.0
    assert checked.suggested_timestep == pytest.approx(1e-3 * 0.005 / 0.05)
    assert 'from 1 m/s up only' in ' '.join(checked.lines(target.speeds))
    # the stiffness is the target's own (the step does not set it): no step is suggested
    held = scene.assess(target, claimed, [0.75, 0.7, 0.7], 1e-4, 1e-3, 1e-2, 'measured', 'X',
                        1e-4)
    assert held.suggested_timestep is None
