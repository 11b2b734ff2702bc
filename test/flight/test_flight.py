"""Closed-form flight with air drag against a tight solve_ivp of the same flight, and its use in
the drop engine."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import contact_sim as cs
from contact_sim.flight.drag import AirDrag, FlightPath, contact_drag_impulse_ratio, flight_to_plate

G = 9.81


def reference(y0, v0, kappa, beta, t_max):
    """DOP853 at rtol 1e-13 of y'' = -g - κ v|v| - β v, with the downward crossing of y = 0."""
    def rhs(t, s):
        return [s[1], -G - kappa * s[1] * abs(s[1]) - beta * s[1]]

    def cross(t, s):
        return s[0]
    cross.terminal, cross.direction = True, -1
    sol = solve_ivp(rhs, (0.0, t_max), [y0, v0], method='DOP853', rtol=1e-13, atol=1e-14,
                    events=cross, dense_output=True)
    hits = [t for t in sol.t_events[0] if t > 1e-9]
    return sol, (hits[0] if hits else math.inf)


CASES = [  # (y0, v0, kappa 1/m, beta 1/s): table-tennis-like, golf, linear only, both, vacuum
    (0.0, 5.0, 0.13, 0.0), (0.0, 5.0, 0.13, 0.02), (1.0, 0.0, 0.13, 0.0),
    (0.3, -2.0, 0.05, 0.01), (0.0, 3.0, 0.0, 0.3), (0.0, 3.0, 0.0, 0.0),
    (0.0, 40.0, 0.13, 0.0), (2.0, -20.0, 0.13, 0.0), (0.0, 3.0, 1e-9, 0.0),
    (-1e-6, 2.0, 0.005, 0.0),
]


@pytest.mark.parametrize('y0, v0, kappa, beta', CASES)
def test_flight_matches_tight_integration(y0, v0, kappa, beta):
    path = FlightPath(y0, v0, G, kappa, beta, surface=min(y0, 0.0))   # a lift-off inside
    t_touch = path.time_to_height(0.0)
    sol, t_ref = reference(y0, v0, kappa, beta, 3.0 * t_touch + 1.0)
    assert t_touch == pytest.approx(t_ref, rel=1e-12, abs=1e-13)
    ts = np.linspace(0.0, t_touch, 41)
    y, v = path.state(ts)
    ref = sol.sol(ts)
    scale = max(abs(v0), 1.0)
    assert np.max(np.abs(y - ref[0])) < 1e-11 * scale
    assert np.max(np.abs(v - ref[1])) < 1e-11 * scale
    if v0 > 0.0:   # apex: velocity zero there, the highest point of the dense solution
        assert path.state(path.apex_time)[1] == pytest.approx(0.0, abs=1e-12 * scale)
        assert path.apex_height == pytest.approx(np.max(sol.sol(np.linspace(
            0.0, t_touch, 20001))[0]), abs=1e-9 * scale)
    t1, s1 = path.touch()
    assert t1 == t_touch and s1 == pytest.approx(-ref[1][-1], rel=1e-11)


def test_scalar_state_is_a_float_and_vacuum_is_the_parabola():
    path = FlightPath(0.5, 2.0, G)
    y, v = path.state(0.3)
    assert isinstance(y, float)
    assert y == pytest.approx(0.5 + 2.0 * 0.3 - 0.5 * G * 0.09, rel=1e-15)
    assert path.time_to_height(0.0) == pytest.approx((2.0 + math.sqrt(4.0 + 2 * G * 0.5)) / G,
                                                     rel=1e-15)
    assert FlightPath(-0.1, 0.5, G, surface=-0.1).time_to_height(0.0) == math.inf   # apex < 0


def test_quadratic_drag_classical_forms():
    """Exact textbook results: apex ln(1 + v0²/vt²)/2κ, fall from rest ln cosh(g t / vt)/κ."""
    kappa, v0 = 0.2, 6.0
    vt = math.sqrt(G / kappa)
    path = FlightPath(0.0, v0, G, kappa)
    assert path.apex_height == pytest.approx(math.log1p(v0 ** 2 / vt ** 2) / (2 * kappa),
                                             rel=1e-14)
    assert path.apex_time == pytest.approx(vt / G * math.atan(v0 / vt), rel=1e-14)
    drop = FlightPath(1.0, 0.0, G, kappa)
    t = 0.4
    assert 1.0 - drop.state(t)[0] == pytest.approx(math.log(math.cosh(G * t / vt)) / kappa,
                                                   rel=1e-13)
    assert -drop.state(t)[1] == pytest.approx(vt * math.tanh(G * t / vt), rel=1e-14)
    # the bounce helper is the same flight, vectorised
    times, speeds = flight_to_plate(np.array([1.0, v0]), G, kappa)
    assert times[1] == pytest.approx(path.time_to_height(0.0), rel=1e-14)
    assert speeds[1] == pytest.approx(path.touch()[1], rel=1e-13)


def test_air_drag_validation_names_the_field():
    with pytest.raises(ValueError, match=r'air_density = -1.0 is out of range: allowed 0 <= '
                                         r'air_density <= 100'):
        AirDrag(air_density=-1.0)
    with pytest.raises(ValueError, match=r'drag_coefficient = 20.0 is out of range'):
        AirDrag(drag_coefficient=20.0)
    with pytest.raises(ValueError, match=r'radius = 0.0 is out of range'):
        AirDrag(radius=0.0)
    with pytest.raises(ValueError, match=r'linear_coefficient = 1.0 is out of range: allowed '
                                         r'0 <= linear_coefficient < 2 sqrt\(c m g\)'):
        AirDrag(radius=0.02, linear_coefficient=1.0).rates(0.0027, G)
    drag = AirDrag(1.2, 0.5, 0.02)
    assert drag.quadratic_coefficient == pytest.approx(0.5 * 1.2 * 0.5 * math.pi * 4e-4)


def test_drop_with_drag_flights_match_integration_and_vacuum_is_unchanged():
    contact = cs.Contact(cs.HUNT_CROSSLEY, 5e6, 2e3)
    mass, drag = 0.0027, AirDrag(1.2, 0.5, 0.02)
    vacuum = cs.simulate_drop(contact, mass, 1.0, duration=3.0)
    assert vacuum == cs.simulate_drop(contact, mass, 1.0, duration=3.0, drag=None)
    assert vacuum == cs.simulate_drop(contact, mass, 1.0, duration=3.0,
                                      drag=AirDrag(0.0, 0.5, 0.02))   # zero drag: vacuum
    result = cs.simulate_drop(contact, mass, 1.0, duration=3.0, drag=drag)
    kappa, _ = drag.rates(mass, G)
    first = reference(1.0, 0.0, kappa, 0.0, 5.0)[1]
    assert result.impacts[0].time == pytest.approx(first, rel=1e-12)
    assert result.impacts[0].time > vacuum.impacts[0].time
    # each flight between two contacts: lift-off speed -> next touch, against solve_ivp
    for before, after in zip(result.impacts[:3], result.impacts[1:4]):
        lift_off = before.time + before.contact_duration
        sol, t_ref = reference(0.0, before.rebound_speed, kappa, 0.0, 5.0)
        assert after.time - lift_off == pytest.approx(t_ref, abs=1e-9)
        assert after.impact_speed == pytest.approx(-sol.y[1][-1], rel=1e-8)
    assert result.apex_heights[0] == pytest.approx(
        FlightPath(0.0, result.impacts[0].rebound_speed, G, kappa).apex_height, rel=1e-8)
    # the steppable engine gives the same impacts in chunks, and no steps in flight
    sim = cs.DropSimulation(contact, mass, 1.0, drag=drag)
    sim.advance(0.2)
    assert sim.total_steps == 0
    for t in (0.5, 1.0, 2.0, 3.0):
        sim.advance(t)
    assert tuple(sim.impacts) == result.impacts
    with pytest.raises(ValueError, match='gravity = 0.0 is out of range'):
        cs.DropSimulation(contact, mass, 1.0, gravity=0.0, drag=drag)


def test_drag_neglected_in_contact_is_small():
    """The drag impulse over one contact, κ v τc, relative to the momentum m v."""
    contact = cs.Contact(cs.HUNT_CROSSLEY, 5e6, 2e3)
    mass, drag = 0.0027, AirDrag(1.2, 0.5, 0.02)
    kappa, _ = drag.rates(mass, G)
    tau = cs.contact_duration(contact, mass, 3.0)
    ratio = contact_drag_impulse_ratio(kappa, 3.0, tau)
    assert 0.0 < ratio < 1e-3
