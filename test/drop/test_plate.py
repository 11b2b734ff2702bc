"""The moving plate: sinusoidal table, commanded set-points, exact flights, the carried state."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from contact_sim.model import AZAD_FEATHERSTONE, HUNT_CROSSLEY, LINEAR
from contact_sim.model.contact import Contact
from contact_sim.drop.engine import DropSimulation
from contact_sim.drop.simulate import simulate_drop
from contact_sim.flight.drag import AirDrag, FlightPath
from contact_sim.drop.plate import CommandedPlate, SinusoidalPlate, SwitchedPlate, table_transition

G = 9.81
MASS = 0.066
STEEL = Contact(AZAD_FEATHERSTONE, 1e10, 1e5)


def test_a_plate_that_does_not_move_is_the_fixed_plate():
    base = simulate_drop(STEEL, MASS, 0.1, duration=1.0)
    for plate in (SinusoidalPlate(0.0, 50.0, 1.0), SinusoidalPlate(0.01, 0.0, 0.0)):
        assert simulate_drop(STEEL, MASS, 0.1, duration=1.0, plate=plate) == base


def test_commanded_plate_fields_are_validated():
    with pytest.raises(ValueError, match='times'):
        CommandedPlate([0.0, 0.0], [0.0, 1.0], [0.0, 0.0])
    with pytest.raises(ValueError, match='velocities'):
        CommandedPlate([0.0, 1.0], [0.0, 1.0], [0.0])
    with pytest.raises(ValueError, match='positions'):
        CommandedPlate([0.0], [math.nan], [0.0])
    with pytest.raises(ValueError, match='plate'):
        DropSimulation(STEEL, MASS, 0.1, plate='table')
    with pytest.raises(ValueError, match='gravity'):
        DropSimulation(STEEL, MASS, 0.1, gravity=0.0, plate=SinusoidalPlate(1e-3, 10.0))


def _relative_reference(contact, plate, t0, z0, zdot0, t_max):
    """The contact phase on the moving plate by scipy's DOP853 at tight tolerances (the slow
    path): m z̈ = m (g + p̈) - F(z, ż) until the force vanishes."""
    law, k, lam = contact.law, contact.stiffness, contact.damping

    def rhs(t, y):
        z, zd = y
        f = float(contact.force(z, zd))
        return [zd, G + plate.state(t)[2] - f / MASS]

    def lift(t, y):
        return float(law.reduced_force(y[0], y[1], k, lam)) if y[0] > 0 else y[0]
    lift.terminal, lift.direction = True, -1
    sol = solve_ivp(rhs, (t0, t_max), [z0, zdot0], method='DOP853', rtol=1e-12, atol=1e-16,
                    events=lift, first_step=1e-8, max_step=1e-6)
    return sol.t_events[0][0], sol.y_events[0][0]


def test_contact_on_a_vibrating_plate_matches_the_slow_path():
    # a soft contact (duration ~ 10 ms) on a plate whose acceleration changes a lot meanwhile
    soft = Contact(AZAD_FEATHERSTONE, 2e6, 2e3)
    plate = SinusoidalPlate(0.002, 25.0, 0.3)
    sim = DropSimulation(soft, MASS, 0.02, plate=plate)
    sim.advance(0.2)
    first = sim.impacts[0]
    p, pv, _ = plate.state(first.time)
    t_ref, (z_ref, zd_ref) = _relative_reference(soft, plate, first.time, 0.0,
                                                  first.impact_speed, first.time + 0.1)
    assert first.contact_duration == pytest.approx(t_ref - first.time, rel=1e-6)
    assert first.rebound_speed == pytest.approx(-zd_ref, rel=1e-6)
    # the drive mattered: the same impact on a fixed plate is clearly different
    fixed = simulate_drop(soft, MASS, 0.0, velocity=first.impact_speed, duration=0.05)
    assert abs(fixed.impacts[0].contact_duration - first.contact_duration) > 1e-4


def test_force_on_sphere_and_reaction_on_plate():
    plate = SinusoidalPlate(0.001, 30.0)
    sim = DropSimulation(STEEL, MASS, 0.01, plate=plate)
    adv = sim.advance(0.1)
    assert np.max(adv.samples.force) > 0.0
    np.testing.assert_array_equal(adv.samples.plate_force, -adv.samples.force)
    p, pv, pa = sim.plate_samples(adv.samples)
    assert p.shape == adv.samples.time.shape
    assert sim.state.plate_position == pytest.approx(plate.state(0.1)[0])
    assert sim.state.plate_force == -sim.state.force


def _brute_first_touch(gap, t0, t1, n=2_000_001):
    ts = np.linspace(t0, t1, n)
    gs = gap(ts)
    i = int(np.argmax(gs <= 0.0))
    assert gs[i] <= 0.0, 'no touch in the brute-force window'
    return brentq(gap, ts[i - 1], ts[i], xtol=1e-16, rtol=1e-15)


def test_a_plate_overtaking_a_slow_sphere():
    # the sphere is thrown up slowly; the plate below rises fast and catches it before its apex
    plate = CommandedPlate([0.0, 0.05], [0.0, 0.04], [0.8, 0.8])
    y0, v0 = 0.01, 0.3                       # 1 cm above, 0.3 m/s up

    def gap(t):
        p = 0.8 * t
        return y0 + v0 * t - 0.5 * G * t * t - p
    t_ref = _brute_first_touch(gap, 0.0, 0.1)
    sim = DropSimulation(STEEL, MASS, y0, velocity=-v0, plate=plate)
    sim.advance(t_ref + 1e-3)
    assert sim.impacts[0].time == pytest.approx(t_ref, abs=1e-12)
    assert sim.impacts[0].time < v0 / G          # before the apex: the plate overtook


def _graze_setup(depth):
    """A sphere whose apex comes 1e-9 m into (depth > 0) or above (depth < 0) a vibrating
    table at the table's highest point, t* = 1/(4 f)."""
    f, a = 10.0, 0.005                     # Γ ≈ 2
    plate = SinusoidalPlate(a, f)
    t_star = 1.0 / (4.0 * f)
    top = a - depth                        # apex height of the sphere's lowest point
    height, up = top - 0.5 * G * t_star ** 2, G * t_star
    return plate, t_star, top, height, up


def test_a_touch_lasting_microseconds_is_not_missed():
    plate, t_star, top, height, up = _graze_setup(1e-9)
    sim = DropSimulation(STEEL, MASS, height, velocity=-up, plate=plate)
    sim.advance(t_star + 1e-3)
    assert len(sim.impacts) >= 1
    w2 = plate.amplitude * plate.angular_frequency ** 2
    # near t*: gap ≈ -1e-9 + ½ (a ω² - g) (t - t*)²: the first root
    expected = t_star - math.sqrt(2e-9 / (w2 - G))
    first = sim.impacts[0]
    assert first.time == pytest.approx(expected, abs=1e-8)
    assert first.contact_duration < 1e-4
    # a sampled search over the flight would see only positive gaps
    ts = np.linspace(0.0, t_star + 1e-3, 65)
    ys = height + up * ts - 0.5 * G * ts ** 2
    assert np.all(ys - np.array([plate.state(t)[0] for t in ts]) > 0.0)


def test_a_tangent_graze_above_the_plate_is_passed_and_the_next_touch_found():
    plate, t_star, top, height, up = _graze_setup(-1e-12)
    sim = DropSimulation(STEEL, MASS, height, velocity=-up, plate=plate)

    def gap(t):
        return height + up * t - 0.5 * G * t * t - plate.amplitude * np.sin(
            plate.angular_frequency * t)
    t_ref = _brute_first_touch(gap, t_star + 1e-4, 1.0)
    sim.advance(t_ref + 1e-3)
    assert sim.impacts[0].time == pytest.approx(t_ref, abs=1e-11)


def test_flights_with_drag_over_a_vibrating_plate():
    drag = AirDrag(radius=0.02, drag_coefficient=0.47)
    plate = SinusoidalPlate(0.001, 20.0)
    sim = DropSimulation(STEEL, MASS, 0.2, plate=plate, drag=drag)
    sim.advance(0.5)
    first = sim.impacts[0]
    # the reference: the closed-form drag fall against the plate, by Brent on a bracket
    path = FlightPath(0.2, 0.0, G, *drag.rates(MASS, G))

    def gap(t):
        return path.state(t)[0] - plate.amplitude * np.sin(plate.angular_frequency * t)
    t_ref = brentq(lambda t: float(gap(t)), 0.15, 0.25)
    assert first.time == pytest.approx(t_ref, abs=1e-12)


def test_sphere_carried_then_released_by_a_commanded_plate():
    # rest for 0.5 s, accelerate up at 5 m/s² for 0.2 s (carried), then decelerate at 20 m/s²
    # (more than g: the sphere is released at t = 0.7 with the plate's 1 m/s, at 0.1 m)
    plate = CommandedPlate([0.0, 0.5, 0.7, 0.9], [0.0, 0.0, 0.1, -0.1], [0.0, 0.0, 1.0, -3.0])
    lossy = Contact(AZAD_FEATHERSTONE, 1e10, 2e6)
    sim = DropSimulation(lossy, MASS, 0.005, plate=plate)
    sim.advance(0.45)
    assert sim.carried
    n = len(sim.impacts)
    sim.advance(0.65)
    assert sim.carried and sim.state.force == pytest.approx(MASS * (G + 5.0), rel=1e-3)
    steps_before = sim.total_steps
    sim.advance(0.69)
    assert sim.carried and len(sim.impacts) == n
    sim.advance(0.8)
    assert not sim.in_contact
    assert sim.total_steps - steps_before < 5000    # the release: one contact phase, no chatter
    release = sim.impacts[-1]
    assert release.time + release.contact_duration == pytest.approx(0.7, abs=1e-3)
    # released with the plate's velocity, plus what the spring's stored energy E = 2/5 F z_s
    # adds relative to the plate (at most √(2E/m) ≈ 1.6 mm/s): apex 0.1 m + (1 m/s)² / 2g
    spring = 0.4 * MASS * (G + 5.0) * lossy.static_penetration(MASS * (G + 5.0))
    dv = math.sqrt(2.0 * spring / MASS)
    assert 0.0 < release.rebound_speed <= dv
    assert sim.apex_heights[-1] == pytest.approx(0.1 + 1.0 / (2.0 * G), abs=1.0 * dv / G)


def test_vibrating_table_below_one_g_carries_a_lossy_sphere():
    lossy = Contact(LINEAR, 1e6, 400.0)   # e about 0.1
    plate = SinusoidalPlate(0.0005, 15.0)   # Γ ≈ 0.45
    sim = DropSimulation(lossy, MASS, 0.002, plate=plate)
    sim.advance(1.0)
    assert sim.carried
    steps = sim.total_steps
    sim.advance(3.0)
    assert sim.carried and sim.total_steps == steps     # carried: no steps at all
    z = sim.state.penetration
    acc = plate.state(3.0)[2]
    assert z == pytest.approx(MASS * (G + acc) / lossy.stiffness, rel=1e-9)


def test_chunked_advance_and_step_budget_on_a_vibrating_table():
    plate = SinusoidalPlate(0.002, 20.0, 0.5)        # Γ ≈ 3.2: bouncing, never carried
    one = DropSimulation(STEEL, MASS, 0.02, plate=plate)
    one.advance(0.5)
    chunked = DropSimulation(STEEL, MASS, 0.02, plate=plate)
    for t in np.linspace(0.0013, 0.5, 97):
        chunked.advance(float(t))
    assert chunked.impacts == one.impacts and len(one.impacts) > 5
    limited = DropSimulation(STEEL, MASS, 0.02, plate=plate)
    while limited.time < 0.5:
        before = limited.total_steps
        limited.advance(0.5, max_steps=5)
        assert limited.total_steps - before <= 5 + DropSimulation.PLATE_CHUNK
    assert limited.impacts == one.impacts


@pytest.mark.parametrize('moving', [False, True], ids=['fixed', 'vibrating'])
def test_a_contact_change_inside_the_surface_after_lift_off_is_no_impact(moving):
    """After a lift-off at z > 0 (the damped linear law's force vanishes inside the surface) a
    new contact that pushes at once is a resumed contact, not an impact, on a moving plate too
    (found in review: the vibrating plate logged impact_speed = 0, restitution = 0)."""
    plate = SinusoidalPlate(1e-4, 5.0) if moving else None
    sim = DropSimulation(Contact(LINEAR, 1e5, 50.0), 0.05, 0.05, plate=plate)
    while not sim.impacts:
        sim.advance(sim.time + 1e-3)
    assert sim.state.penetration > 0.0 and sim.state.force == 0.0   # inside, force off
    count = len(sim.impacts)
    sim.set_contact(Contact(LINEAR, 1e5, 0.0))      # undamped: pushes at once
    sim.advance(sim.time + 0.01)
    assert len(sim.impacts) == count, sim.impacts[count:]


# -- changing the plate's motion at a time: set_plate, SwitchedPlate, the table's bridge -------


def _absolute(sim):
    s = sim.state
    return s.plate_position - s.penetration, s.plate_velocity - s.penetration_rate


def _set_plate_continuously(sim, plate):
    """set_plate, asserting the sphere's absolute state and, for a continuous motion, p, ṗ."""
    before, p_before = _absolute(sim), (sim.state.plate_position, sim.state.plate_velocity)
    sim.set_plate(plate)
    assert _absolute(sim) == pytest.approx(before, abs=1e-15, rel=1e-12)
    assert (sim.state.plate_position, sim.state.plate_velocity) == pytest.approx(
        p_before, abs=1e-15, rel=1e-12)


def test_set_plate_keeps_the_sphere_and_plate_continuous_in_flight():
    sim = DropSimulation(STEEL, MASS, 0.1)
    sim.advance(0.05)
    _set_plate_continuously(sim, table_transition(0.05, None, SinusoidalPlate(0.002, 20.0)))
    assert not sim.in_contact and sim.plate is not None
    sim.advance(0.3)
    assert sim.impacts
    # a discontinuous motion: the sphere stays where it is, its relative state jumps
    sim = DropSimulation(STEEL, MASS, 0.1)
    sim.advance(0.05)
    y, v = _absolute(sim)
    sim.set_plate(SinusoidalPlate(0.01, 5.0))     # p(0.05) = 0.01 sin(π / 2)
    assert _absolute(sim) == pytest.approx((y, v), rel=1e-12)
    assert sim.state.plate_position == pytest.approx(0.01)


@pytest.mark.parametrize('to_fixed', [False, True], ids=['to-table', 'to-fixed'])
def test_set_plate_in_a_contact_phase_carries_the_impact_across(to_fixed):
    start = None if to_fixed else SinusoidalPlate(0.001, 20.0)
    ref = DropSimulation(STEEL, MASS, 0.02, plate=start)
    ref.advance(0.2)
    first = ref.impacts[0]
    sim = DropSimulation(STEEL, MASS, 0.02, plate=start)
    sim.advance(first.time + 0.5 * first.contact_duration)
    assert sim.in_contact and not sim.impacts
    now = sim.time
    target = None if to_fixed else SinusoidalPlate()
    _set_plate_continuously(sim, table_transition(now, start or None, target or
                                                  SinusoidalPlate(0.001, 30.0), 20.0))
    sim.advance(now + first.contact_duration)
    assert len(sim.impacts) == 1
    got = sim.impacts[0]
    assert got.time == first.time and got.impact_speed == first.impact_speed  # carried across
    assert got.peak_force >= sim.state.force and got.max_penetration > 0.0
    assert got.contact_duration == pytest.approx(first.contact_duration, rel=0.05)


def test_set_plate_on_a_resting_and_on_a_carried_sphere_records_no_impact():
    lossy = Contact(LINEAR, 1e6, 400.0)
    sim = DropSimulation(lossy, MASS, 0.002)
    sim.advance(2.0)
    assert sim.settle_time is not None
    count = len(sim.impacts)
    _set_plate_continuously(sim, table_transition(2.0, None, SinusoidalPlate(0.0005, 15.0)))
    sim.advance(4.0)
    assert sim.carried and len(sim.impacts) == count      # Γ ≈ 0.45: carried, no new impact
    _set_plate_continuously(sim, table_transition(4.0, sim.plate, None, 15.0))
    sim.advance(5.0)
    assert sim.in_contact and len(sim.impacts) == count
    assert sim.state.plate_position == 0.0 and sim.state.plate_velocity == 0.0
    assert sim.state.penetration == pytest.approx(MASS * G / lossy.stiffness, rel=1e-6)
    sim.set_plate(None)                                    # and back to the fixed plate
    sim.advance(5.5)
    assert sim.in_contact and len(sim.impacts) == count and sim.plate is None


def test_a_table_switched_on_changed_and_off_matches_the_switched_plate_from_the_start():
    t1, t2, t3, end = 0.3, 0.8, 1.3, 2.0
    t_a, t_b = SinusoidalPlate(0.001, 30.0), SinusoidalPlate(0.0015, 25.0, 1.0)
    live = DropSimulation(STEEL, MASS, 0.05)
    live.advance(t1)
    m1 = table_transition(t1, None, t_a)
    live.set_plate(m1)
    live.advance(t2)
    m2 = table_transition(t2, m1, t_b, t_a.frequency)
    live.set_plate(m2)
    live.advance(t3)
    m3 = table_transition(t3, m2, None, t_b.frequency)
    live.set_plate(m3)
    live.advance(end)
    whole = SwitchedPlate(SwitchedPlate(SwitchedPlate(SinusoidalPlate(), m1, t1), m2, t2), m3, t3)
    ref = DropSimulation(STEEL, MASS, 0.05, plate=whole)
    ref.advance(end)
    assert len(live.impacts) == len(ref.impacts) > 10
    assert any(i.time > t3 for i in ref.impacts) and any(t1 < i.time < t2 for i in ref.impacts)
    for a, b in zip(live.impacts, ref.impacts):
        assert a.time == pytest.approx(b.time, abs=1e-9)
        assert a.impact_speed == pytest.approx(b.impact_speed, rel=1e-6, abs=1e-9)
        assert a.restitution == pytest.approx(b.restitution, rel=1e-6, abs=1e-9)
    assert _absolute(live) == pytest.approx(_absolute(ref), rel=1e-6, abs=1e-9)


def test_the_depth_check_counts_the_plate_speed():
    soft = Contact(LINEAR, 200.0, 0.0)
    sim = DropSimulation(soft, MASS, 0.0001, radius=0.0127)
    with pytest.raises(ValueError, match=r'stiffness .*with the plate moving at up to 6\.283 m/s'):
        sim.set_plate(SinusoidalPlate(0.05, 20.0))
    assert sim.plate is None
    sim.set_plate(SinusoidalPlate(0.0005, 2.0))     # slow enough: accepted
    assert sim.plate is not None


def test_a_stiff_phase_after_a_knot_goes_to_the_reference_integrator():
    # the plate accelerates down at 5 m/s² until 0.2 s, then moves on at constant velocity: the
    # forced phase is compiled, the unforced one after the knot too damped for DOP853 (Radau)
    from contact_sim.drop.mode_contact import InContact
    from contact_sim.phase import CompiledPhase, PhaseIntegrator
    contact = Contact(HUNT_CROSSLEY, 1e9, 1e15)
    sim = DropSimulation(contact, MASS, 0.005, plate=CommandedPlate((0.0, 0.2), (0.0, -0.1),
                                                                    (0.0, -1.0)))
    sim.run_to(0.19)
    assert isinstance(sim._mode, InContact)
    assert isinstance(sim._mode.integrator, CompiledPhase)
    sim.run_to(0.3)
    assert isinstance(sim._mode, InContact)
    assert isinstance(sim._mode.integrator, PhaseIntegrator)
    assert sim._mode.integrator.start_time == 0.2            # restarted at the knot
    assert sim.in_contact and 0.0 < sim.state.penetration < 1e-3


def test_the_pieces_examples_run():
    import doctest
    from contact_sim.drop.plate import pieces
    assert doctest.testmod(pieces).failed == 0
