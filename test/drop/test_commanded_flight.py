"""The compiled next touch over a commanded plate (``compiled_flight.commanded_touch_time``)
against the Python path it replaces in vacuum (``flights.gap_touch_time``, kept as the
reference and for flights with drag)."""
import math
from dataclasses import dataclass

import numpy as np
import pytest

from contact_sim.drop.engine import DropSimulation
from contact_sim.drop.mode_flight import Flight
from contact_sim.drop.plate import (FIXED, CommandedPlate, PlateMotion, SinusoidalPlate,
                                    SwitchedPlate, command_motion)
from contact_sim.drop.plate.compiled_flight import plate_gap
from contact_sim.drop.plate.flights import gap_touch_time
from test_table_flight import G, LAWS, MASS, contact_of  # the table's flights: same contacts


@dataclass(frozen=True)
class ReferenceCommandedPlate(CommandedPlate):
    """The same plate, its flights planned by the Python reference path."""

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        return PlateMotion.plan_flight(self, flight, z, zdot, contact, drag_rates,
                                       after_lift_off)


def random_plate(rng):
    """Set-points 5 ms to 0.2 s apart, mm and 0.1 m/s: accelerations up to tens of m/s²."""
    n = int(rng.integers(1, 9))
    times = rng.uniform(0.0, 0.5) + np.cumsum(rng.uniform(0.005, 0.2, n))
    positions = rng.uniform(-3e-3, 3e-3, n)
    velocities = rng.uniform(-0.1, 0.1, n)
    return times, positions, velocities


def lift_off_state(rng, contact):
    """(z, ż) just past a lift-off inside the undeformed surface: φ(z, ż) < 0 with z > 0."""
    law, k, lam = contact.law, contact.stiffness, contact.damping
    z = 10.0 ** rng.uniform(-10.0, -6.0)
    zdot = -(k * z ** (law.n - law.p) / lam) ** (1.0 / law.q) * (1.0 + 10.0 ** rng.uniform(-6, 0))
    return z, zdot - rng.uniform(0.0, 0.3) * rng.integers(0, 2)


def flight_start(rng, times):
    """Before the first set-point, between them (knots ahead) or after the last."""
    where = rng.integers(0, 3)
    if where == 0:
        return times[0] - rng.uniform(0.0, 0.3)
    if where == 1:
        return rng.uniform(times[0], times[-1])
    return times[-1] + rng.uniform(0.0, 0.3)


def both(plate_args, t0, z, zdot, contact, after=True):
    fast = Flight(CommandedPlate(*plate_args), G, t0, z, zdot, contact, None, after)
    slow = Flight(ReferenceCommandedPlate(*plate_args), G, t0, z, zdot, contact, None, after)
    return fast, slow


def assert_same_touch(fast, slow):
    assert math.isfinite(slow.contact_time) and slow.contact_time >= fast.start
    assert fast.contact_time == pytest.approx(slow.contact_time, rel=1e-12, abs=1e-12)
    assert fast.apex == slow.apex


@pytest.mark.parametrize('law', sorted(LAWS))
def test_flights_above_a_commanded_plate_touch_where_the_reference_does(law):
    contact = contact_of(law)
    rng = np.random.default_rng(11)
    crossed = 0
    for _ in range(150):
        args = random_plate(rng)
        t0 = flight_start(rng, args[0])
        z = -10.0 ** rng.uniform(-6.0, -1.5)          # above the plate
        zdot = rng.uniform(-3.0, 1.0)
        fast, slow = both(args, t0, z, zdot, contact, after=bool(rng.integers(0, 2)))
        assert_same_touch(fast, slow)
        crossed += np.count_nonzero((args[0] > t0) & (args[0] < slow.contact_time)) > 0
    assert crossed > 30                                # set-points passed during the flight


@pytest.mark.parametrize('law', ['azad_featherstone', 'linear', 'lee_wang'])
def test_flights_after_a_lift_off_inside_the_surface_touch_where_the_reference_does(law):
    """z0 > 0: the force returns inside the surface, or the sphere leaves it first."""
    contact = contact_of(law)
    rng = np.random.default_rng(12)
    inside = 0
    for _ in range(150):
        args = random_plate(rng)
        t0 = flight_start(rng, args[0])
        z, zdot = lift_off_state(rng, contact)
        fast, slow = both(args, t0, z, zdot, contact)
        assert_same_touch(fast, slow)
        inside += slow.state(slow.contact_time)[0] > 0.0
    assert inside > 10


def test_a_flight_from_the_surface_itself_and_tangent_grazes_are_passed_as_the_reference():
    """z0 = 0 at lift-off (G = 0 with G' >= 0 at the start: the nudge), and flights that only
    graze the plate's crest."""
    contact = contact_of('hunt_crossley')
    rng = np.random.default_rng(13)
    for _ in range(100):
        args = random_plate(rng)
        t0 = flight_start(rng, args[0])
        fast, slow = both(args, t0, 0.0, -rng.uniform(0.0, 0.5) * rng.integers(0, 2), contact)
        assert_same_touch(fast, slow)
    # a plate decelerating at exactly g from 1 m/s, the sphere leaving with it: tangent at t0
    plate = ((0.0, 0.1), (0.0, 0.1 - 0.5 * G * 0.01), (1.0, 1.0 - G * 0.1))
    for t0 in (0.0, 0.03, 0.07):
        fast, slow = both(plate, t0, 0.0, 0.0, contact)
        assert_same_touch(fast, slow)


def test_the_compiled_search_is_the_reference_function_for_a_plate_given_by_its_pieces():
    """``commanded_touch_time`` on the pieces equals ``gap_touch_time`` of the plate, and the
    compiled gap is the plate's ``state`` (the same floats), at the knots too (bisect_right)."""
    from numba import njit
    from contact_sim.drop.plate.compiled_flight import commanded_touch_time

    @njit
    def gap_at(t, fl, starts, pos, vel, acc):
        return plate_gap(t, fl, (starts, pos, vel, acc))

    contact = contact_of('azad_featherstone')
    law = contact.law
    rng = np.random.default_rng(14)
    for _ in range(100):
        plate = CommandedPlate(*random_plate(rng))
        t0 = flight_start(rng, np.array(plate.times))
        flight = Flight(plate, G, t0, -1e-3, -0.5, contact, None)
        for t in np.concatenate((t0 + rng.uniform(0.0, 0.5, 5), plate.piece_arrays[0])):
            y, v = flight.absolute(t)
            p, pv, _ = plate.state(t)
            assert gap_at(t, (t0, flight.y0, flight.v0, G), *plate.piece_arrays) \
                == (y - p, v - pv, abs(y) + abs(p))
        fast = commanded_touch_time(t0, flight.y0, flight.v0, G, -1e-3, -0.5,
                                    *plate.piece_arrays, contact.stiffness, contact.damping,
                                    law.n - law.p, law.q, G + plate.acceleration_bound())
        slow = gap_touch_time(plate, flight, -1e-3, -0.5, contact, None)
        assert fast == pytest.approx(slow, rel=1e-12)


def juggling_plate(t_hit=0.25, period=0.3, speed=0.4, strokes=12):
    """Strokes as ``examples/juggler.py`` sends them: up to ``speed`` (m/s) at each impact."""
    times, positions, velocities = [0.0], [0.0], [0.0]
    T = 0.05
    for i in range(strokes):
        t = t_hit + i * period
        times += [t - T, t, t + T, t + T + 0.1]
        positions += [-speed * T / 2, 0.0, speed * T / 2, 0.0]
        velocities += [0.0, speed, 0.0, 0.0]
    return tuple(times), tuple(positions), tuple(velocities)


@pytest.mark.parametrize('law', ['azad_featherstone', 'linear'])
def test_a_drop_on_a_commanded_plate_with_compiled_flights_matches_the_reference_drop(law):
    contact = contact_of(law)
    runs = []
    for cls in (CommandedPlate, ReferenceCommandedPlate):
        sim = DropSimulation(contact, MASS, 0.3, plate=cls(*juggling_plate()))
        sim.advance(3.0)
        runs.append(sim)
    fast, slow = runs
    assert len(fast.impacts) == len(slow.impacts) >= 20
    t_fast = np.array([i.time for i in fast.impacts])
    t_slow = np.array([i.time for i in slow.impacts])
    v_fast = np.array([i.impact_speed for i in fast.impacts])
    v_slow = np.array([i.impact_speed for i in slow.impacts])
    np.testing.assert_allclose(t_fast, t_slow, rtol=0, atol=1e-9)
    np.testing.assert_allclose(v_fast, v_slow, rtol=1e-7)


@dataclass(frozen=True)
class ReferenceSwitchedPlate(SwitchedPlate):
    """A switched plate whose every flight is planned over both parts by the Python path."""

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        return PlateMotion.plan_flight(self, flight, z, zdot, contact, drag_rates,
                                       after_lift_off)


def test_a_commanded_plate_after_a_switch_plans_its_flights_as_the_reference():
    """``set_plate`` of a trajectory command mid-drop (``command_motion``, what the node's
    ~/plate_command does) and a switched plate whose later part is commanded: the same
    impacts as the reference flights over the whole switched plate."""
    contact = contact_of('azad_featherstone')
    runs = []
    for compiled in (True, False):
        sim = DropSimulation(contact, MASS, 0.2)
        sim.advance(0.5)
        times, positions, velocities = juggling_plate(t_hit=0.9, strokes=6)
        motion = command_motion(sim.time, 0.0, 0.0, times[1:], positions[1:],
                                velocities[1:]).motion
        sim.set_plate(motion if compiled else ReferenceCommandedPlate(
            motion.times, motion.positions, motion.velocities))
        sim.advance(1.5)
        now = sim.time
        p, pv, _ = sim.plate.state(now)
        times, positions, velocities = juggling_plate(t_hit=now + 0.2, strokes=4)
        later = command_motion(now, p, pv, times[1:], positions[1:], velocities[1:]).motion
        switched = (SwitchedPlate if compiled else ReferenceSwitchedPlate)(sim.plate, later, now)
        sim.set_plate(switched)
        sim.advance(3.5)
        runs.append(sim)
    fast, slow = runs
    assert len(fast.impacts) == len(slow.impacts) >= 20
    assert sum(i.time > now for i in slow.impacts) >= 5
    for a, b in zip(fast.impacts, slow.impacts):
        assert a.time == pytest.approx(b.time, rel=0, abs=1e-9)
        assert a.impact_speed == pytest.approx(b.impact_speed, rel=1e-7)


def test_with_drag_a_commanded_plate_plans_by_the_reference_path():
    contact = contact_of('azad_featherstone')
    rng = np.random.default_rng(15)
    for _ in range(20):
        args = random_plate(rng)
        t0 = flight_start(rng, args[0])
        z, zdot = -10.0 ** rng.uniform(-5.0, -2.0), rng.uniform(-2.0, 0.5)
        fast = Flight(CommandedPlate(*args), G, t0, z, zdot, contact, (0.02, 0.001), True)
        slow = Flight(ReferenceCommandedPlate(*args), G, t0, z, zdot, contact, (0.02, 0.001),
                      True)
        assert fast.path is not None
        assert fast.contact_time == slow.contact_time and fast.apex == slow.apex


def test_a_flight_after_a_switch_to_the_fixed_plate_is_planned_over_the_switched_plate():
    """A hand-built switch to the fixed plate: its flights after the switch are planned as the
    reference plans the switched plate (the fixed plate's closed-form plan gave an apex where
    the reference gives none: a reviewer's case, start 1.5 s, z = -1 mm, ż = 0.5 m/s)."""
    table = SinusoidalPlate(0.002, 10.0)
    contact = contact_of('azad_featherstone')
    for start, z, zdot, after in ((1.5, -1e-3, 0.5, True), (1.2, -2e-3, -0.3, False)):
        fast = Flight(SwitchedPlate(table, FIXED, 1.0), G, start, z, zdot, contact, None, after)
        slow = Flight(ReferenceSwitchedPlate(table, FIXED, 1.0), G, start, z, zdot, contact,
                      None, after)
        assert fast.apex == slow.apex
        assert fast.contact_time == pytest.approx(slow.contact_time, rel=1e-12)
