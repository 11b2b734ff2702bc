"""The plate's motions without a sphere: the sinusoidal table, commanded set-points, a switch,
the table's bridge, and the rigorous first root of a flight's gap."""
import math

import pytest

from contact_sim.drop.plate import (CommandedPlate, SinusoidalPlate, SwitchedPlate, first_gap_root,
                                    table_transition)


@pytest.mark.parametrize('kwargs, field', [
    (dict(amplitude=-1e-3), 'amplitude'), (dict(frequency=math.nan), 'frequency'),
    (dict(phase=math.inf), 'phase')])
def test_sinusoidal_plate_fields_are_validated(kwargs, field):
    with pytest.raises(ValueError, match=field):
        SinusoidalPlate(**kwargs)


def test_commanded_plate_interpolates_position_and_velocity_c1():
    times, pos, vel = [0.0, 0.3, 1.0, 1.2], [0.0, 0.02, -0.01, 0.0], [0.0, 0.1, -0.05, 0.2]
    plate = CommandedPlate(times, pos, vel)
    for t, p, v in zip(times, pos, vel):
        assert plate.state(t)[:2] == pytest.approx((p, v), abs=1e-15)
    # continuity of p and ṗ at every knot (midpoints included), constant acceleration inside
    for knot in plate._pieces[0][1:]:
        left, right = plate.state(knot - 1e-9), plate.state(knot)
        assert left[0] == pytest.approx(right[0], abs=1e-9)
        assert left[1] == pytest.approx(right[1], abs=1e-7)
    # outside: constant velocity (before t0 backwards, after the last set-point the last one)
    assert plate.state(2.2) == pytest.approx((0.2, 0.2, 0.0))
    assert plate.state(-1.0) == pytest.approx((0.0, 0.0, 0.0))


def test_first_gap_root_never_steps_over_a_dip():
    # G(t) = (t - 1)² + 1e-12 - 2e-12 bump: the rigorous stepping finds the first root
    def gap(t):
        g = (t - 1.0) ** 2 - 1e-10
        return g, 2.0 * (t - 1.0), 1.0
    t, g, dg = first_gap_root(gap, 0.0, 2.0)
    assert t == pytest.approx(1.0 - 1e-5, abs=1e-12)
    assert first_gap_root(gap, 0.0, 2.0, t_max=0.9) is None


def test_switched_plate_is_each_motion_on_its_side():
    a, b = SinusoidalPlate(0.001, 10.0), CommandedPlate([0.0, 1.0], [0.0, 0.01], [0.0, 0.0])
    plate = SwitchedPlate(a, b, 0.3)
    assert plate.state(0.2999) == a.state(0.2999) and plate.state(0.3) == b.state(0.3)
    assert plate.forcing_piece(0.1)[1] == 0.3                 # a's piece cut at the switch
    assert plate.forcing_piece(0.3) == b.forcing_piece(0.3)
    assert plate.acceleration_bound() == max(a.acceleration_bound(), b.acceleration_bound())
    assert plate.speed_bound() == max(a.speed_bound(), b.speed_bound())
    lo, hi = plate.acceleration_range(0.25, 0.6)
    assert lo <= min(b._pieces[3]) and hi >= a.acceleration_range(0.25, 0.3)[1]
    # p̈ of a is <= -1 first at 0.25 + ...; with a level below a's range it is b's first piece
    assert plate.next_acceleration_below(0.0, -1.0) == a.next_acceleration_below(0.0, -1.0)
    assert plate.next_acceleration_below(0.0, -10.0) == b.next_acceleration_below(0.3, -10.0)
    with pytest.raises(ValueError, match='after'):
        SwitchedPlate(a, 'table', 1.0)


@pytest.mark.parametrize('table', [SinusoidalPlate(0.001, 20.0, 0.7), None], ids=['on', 'off'])
def test_table_transition_bridges_c1_in_one_period(table):
    old = SinusoidalPlate(0.002, 25.0, 0.3)
    now = 0.4123
    motion = table_transition(now, old, table, previous_frequency=old.frequency)
    period = 1.0 / (table.frequency if table is not None else old.frequency)
    assert motion.switch_time == pytest.approx(now + period)
    assert motion.state(now)[:2] == pytest.approx(old.state(now)[:2], abs=1e-15)
    target = table if table is not None else SinusoidalPlate()
    end = now + period
    assert motion.state(end) == target.state(end)
    left = motion.state(math.nextafter(end, 0.0))
    assert left[:2] == pytest.approx(target.state(end)[:2], abs=1e-12)
    assert table_transition(now, None, SinusoidalPlate()) is None      # fixed stays fixed
