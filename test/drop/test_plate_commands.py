"""The plate's changes from outside in the core: trajectory commands (``plate.command_motion``:
past points, C1 joins, the brake after the last point, estimated velocities, refusals naming the
field) on the drop engine, the vibrating table's ranges and the bridge between tables."""
import math
import re

import numpy as np
import pytest

from contact_sim.drop import DropSimulation
from contact_sim.drop.plate import (COMMAND_ACCELERATION_MAX, COMMAND_POSITION_MAX, COMMAND_STOP_TIME,
                               COMMAND_VELOCITY_MAX, TABLE_ACCELERATION_MAX, CommandedPlate,
                               SinusoidalPlate, command_motion, vibrating_table)
from contact_sim.drop import plate
from contact_sim.model import AZAD_FEATHERSTONE, LINEAR, Contact
from contact_sim.validation import InputError

MASS = 0.066
STEEL = Contact(AZAD_FEATHERSTONE, 1e10, 1e5)


def test_past_points_are_dropped_and_the_motion_starts_from_the_current_state():
    now = 2.0
    command = command_motion(now, 0.01, -0.05, [1.0, 2.0, 2.5, 3.0], [0.0, 0.0, 0.02, 0.03],
                             [0.0, 0.0, 0.1, 0.0])
    assert command.dropped == 2
    motion = command.motion
    assert isinstance(motion, CommandedPlate)
    assert motion.state(now)[:2] == pytest.approx((0.01, -0.05))     # C1 from where it is
    assert motion.state(2.5)[:2] == pytest.approx((0.02, 0.1))
    assert motion.state(3.0)[:2] == pytest.approx((0.03, 0.0))
    assert motion.state(30.0) == pytest.approx((0.03, 0.0, 0.0))     # last velocity 0: stays


def test_a_command_with_no_point_left_is_ignored():
    command = command_motion(5.0, 0.0, 0.0, [4.0, 5.0], [0.01, 0.02], None)
    assert command.motion is None and command.dropped == 2


def test_a_jump_is_followed_c1_never_teleported():
    # the plate at rest at 0; a point 1 cm up 0.1 s later: p and ṗ continuous from now on
    motion = command_motion(0.0, 0.0, 0.0, [0.1], [0.01], [0.0]).motion
    ts = np.linspace(0.0, 0.1, 2001)
    states = np.array([motion.state(t) for t in ts])
    assert states[0, :2] == pytest.approx((0.0, 0.0))
    assert np.max(np.abs(np.diff(states[:, 0]))) < 1e-4      # no step in p
    assert np.max(np.abs(np.diff(states[:, 1]))) < 1e-2      # no step in ṗ
    assert motion.state(0.1)[:2] == pytest.approx((0.01, 0.0))


def test_when_commands_stop_the_plate_brakes_to_rest():
    motion = command_motion(0.0, 0.0, 0.0, [0.5], [0.0], [1.0]).motion
    end = 0.5 + COMMAND_STOP_TIME
    assert motion.state(0.5)[1] == pytest.approx(1.0)
    for t in np.linspace(0.5, end, 9)[1:-1]:
        assert motion.state(t)[2] == pytest.approx(-1.0 / COMMAND_STOP_TIME)    # constant
    assert motion.state(end)[:2] == pytest.approx((0.5 * COMMAND_STOP_TIME, 0.0), abs=1e-12)
    assert motion.state(end + 10.0)[:2] == pytest.approx((0.5 * COMMAND_STOP_TIME, 0.0),
                                                          abs=1e-12)


def test_velocities_not_given_are_estimated_by_central_differences_zero_at_the_end():
    motion = command_motion(0.0, 0.0, 0.0, [0.1, 0.2, 0.4], [0.01, 0.03, 0.0], None).motion
    assert motion.velocities == pytest.approx((0.0, (0.03 - 0.0) / 0.2, (0.0 - 0.01) / 0.3, 0.0))
    assert motion.state(0.4)[:2] == pytest.approx((0.0, 0.0))


@pytest.mark.parametrize('args, field, allowed', [
    (([0.1, math.nan], [0.0, 0.0], None), 'times', 'finite'),
    (([0.1, 0.2], [0.0, math.inf], None), 'positions', 'finite'),
    (([0.2, 0.1], [0.0, 0.0], None), 'times', 'strictly increasing'),
    (([0.1, 0.1], [0.0, 0.0], None), 'times', 'strictly increasing'),
    (([0.1], [2.0], None), 'positions', f'<= {COMMAND_POSITION_MAX:g} m'),
    (([0.1], [0.0], [50.0]), 'velocities', f'<= {COMMAND_VELOCITY_MAX:g} m/s'),
    (([0.1], [0.0], [0.0, 0.0]), 'velocities', 'one per point'),
    (([1e-3], [0.5], [0.0]), 'accelerations', f'<= {COMMAND_ACCELERATION_MAX:g} m/s^2'),
])
def test_bad_commands_are_refused_naming_the_field_and_range(args, field, allowed):
    with pytest.raises(InputError, match=re.escape(allowed)) as info:
        command_motion(0.0, 0.0, 0.0, *args)
    assert info.value.field == field


def test_a_command_drives_a_sphere_on_the_drop_engine():
    # the plate lifted 1 cm under a resting sphere: carried up, no impact, lands with the plate
    sim = DropSimulation(Contact(LINEAR, 1e6, 400.0), MASS, 0.001)
    sim.advance(1.0)
    count = len(sim.impacts)
    state = sim.state
    sim.set_plate(command_motion(1.0, state.plate_position, state.plate_velocity, [1.5], [0.01],
                                 [0.0]).motion)
    sim.advance(2.0)
    assert sim.in_contact and len(sim.impacts) == count
    assert sim.state.plate_position == pytest.approx(0.01)
    assert sim.state.penetration == pytest.approx(MASS * 9.81 / 1e6, rel=1e-3)


def test_vibrating_table_ranges():
    assert vibrating_table(0.0, 50.0, 1.0) is None                    # a = 0: the fixed plate
    assert vibrating_table(0.001, 20.0, 0.5) == SinusoidalPlate(0.001, 20.0, 0.5)
    for args, field in [((math.nan, 10.0, 0.0), 'amplitude'), ((-1e-3, 10.0, 0.0), 'amplitude'),
                        ((0.5, 10.0, 0.0), 'amplitude'), ((1e-3, -1.0, 0.0), 'frequency'),
                        ((1e-3, 2000.0, 0.0), 'frequency'), ((1e-3, 10.0, 7.0), 'phase')]:
        with pytest.raises(InputError) as info:
            vibrating_table(*args)
        assert info.value.field == field
    with pytest.raises(InputError, match=f'<= {TABLE_ACCELERATION_MAX:g} m/s'):
        vibrating_table(0.05, 100.0, 0.0)


def test_a_table_change_far_from_the_plate_is_bridged_no_harder_than_a_table_may_shake():
    # a 10 Hz table at its crest changed to 1000 Hz: one new period (1 ms) would take 1e4 m/s^2
    old = plate.SinusoidalPlate(0.0025, 10.0, 0.0)
    new = plate.vibrating_table(2.5e-5, 1000.0, 0.0)
    now = 0.025                                   # p = a, the crest
    motion = plate.table_transition(now, old, new, old.frequency)
    bridge = motion.before
    assert bridge.acceleration_bound() <= plate.TABLE_ACCELERATION_MAX
    assert motion.switch_time > now + 1e-3        # longer than one new period
    for t in (now, motion.switch_time):           # C1 at both ends
        a, b = (old if t == now else new).state(t), motion.state(t)
        assert b[:2] == pytest.approx(a[:2], abs=1e-12)
    # from a commanded plate 5 cm down, too
    held = plate.command_motion(0.0, 0.0, 0.0, [0.5], [-0.05], [0.0]).motion
    motion = plate.table_transition(1.0, held, new, 0.0)
    assert motion.before.acceleration_bound() <= plate.TABLE_ACCELERATION_MAX
    # and no faster than BRIDGE_SPEED_MAX: from a plate held 1 m down, not a launch at 29 m/s
    held = plate.command_motion(0.0, 0.0, 0.0, [2.0], [-1.0], [0.0]).motion
    motion = plate.table_transition(3.0, held, new, 0.0)
    assert motion.before.speed_bound() <= plate.BRIDGE_SPEED_MAX
    assert motion.before.acceleration_bound() <= plate.TABLE_ACCELERATION_MAX


def test_a_command_beyond_the_horizon_or_braking_out_of_range_is_refused():
    with pytest.raises(InputError, match=r'times reach .* after now: allowed up to 600 s ahead'):
        plate.command_motion(1.0, 0.0, 0.0, [1.0 + 1.8e9], [0.01], [0.0])   # a wall-clock stamp
    # the given points are within 1 m, the brake after the last one is not
    with pytest.raises(InputError, match=r'positions reaches \|positions\| = 2 m .*braking'):
        plate.command_motion(0.0, 0.0, 0.0, [0.2, 0.4], [0.9, 1.0], [9.0, 10.0])
    # refusals show plain numbers
    with pytest.raises(InputError, match=r'^positions\[0\] = nan is not finite'):
        plate.command_motion(0.0, 0.0, 0.0, [1.0], [float('nan')])


def test_a_table_without_frequency_is_the_fixed_plate():
    # not a plate held at a sin(phi), which would block ~/plate_command for nothing
    assert plate.vibrating_table(0.001, 0.0, 1.0) is None
    assert plate.vibrating_table(0.0, 20.0, 1.0) is None
    assert plate.vibrating_table(0.001, 20.0, 1.0) == plate.SinusoidalPlate(0.001, 20.0, 1.0)
