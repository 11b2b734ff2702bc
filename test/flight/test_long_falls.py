"""Long falls with quadratic drag land: the touch time near terminal speed, against the closed
form t = (v_t / g) acosh(e^(κH)) of a fall from rest and a tight solve_ivp of thrown flights.

Before the fix the touch time was atanh of an argument that rounds to 1 near terminal speed:
a ping-pong ball (κ = 0.1396 /m) was 5e-3 off at 120 m and never landed from 130 m on.
"""
import math

import pytest
from scipy.integrate import solve_ivp

import contact_sim as cs
from contact_sim.flight.drag import AirDrag, FlightPath

G = 9.81
PING_PONG = 0.1396   # κ = c / m (1/m) of a 2.7 g, 20 mm ball: v_t = 8.38 m/s


def integrated_touch(y0, v0, kappa):
    """(time, downward speed) of the first downward crossing of y = 0 of y'' = -g - κ v|v|, by
    DOP853 at rtol 1e-13 (its own error is below 1e-11 relative over these flights)."""
    def rhs(t, s):
        return [s[1], -G - kappa * s[1] * abs(s[1])]

    def cross(t, s):
        return s[0]
    cross.terminal, cross.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1e4), [y0, v0], method='DOP853', rtol=1e-13, atol=1e-12,
                    events=cross)
    return float(sol.t_events[0][0]), -float(sol.y_events[0][0][1])


@pytest.mark.parametrize('height', [1e-3, 1.0, 100.0, 120.0, 130.0, 150.0, 1000.0])
def test_a_fall_from_rest_lands_at_the_closed_form_time(height):
    vt = math.sqrt(G / PING_PONG)
    t_exact = vt / G * math.acosh(math.exp(PING_PONG * height))
    s_exact = vt * math.sqrt(-math.expm1(-2.0 * PING_PONG * height))
    t, s = FlightPath(height, 0.0, G, PING_PONG).touch()
    # 1e-13: the closed forms in double precision, a few ulps each (was inf from 130 m on)
    assert t == pytest.approx(t_exact, rel=1e-13)
    assert s == pytest.approx(s_exact, rel=1e-13)


@pytest.mark.parametrize('height, velocity', [(150.0, 0.0), (150.0, -25.0), (1.0, 50.0),
                                              (60.0, 30.0), (200.0, -8.0)])
def test_thrown_flights_land_where_the_integration_does(height, velocity):
    t_ref, s_ref = integrated_touch(height, velocity, PING_PONG)
    t, s = FlightPath(height, velocity, G, PING_PONG).touch()
    # 1e-10: the reference integration's error (rtol 1e-13 over thousands of steps)
    assert t == pytest.approx(t_ref, rel=1e-10)
    assert s == pytest.approx(s_ref, rel=1e-10)


def test_a_ball_thrown_up_into_thick_air_lands():
    # AirDrag(100, 10, 0.02) on a 2.7 g ball: κ = 233 /m, v_t = 0.21 m/s, thrown up at 50 m/s
    kappa, beta = AirDrag(100.0, 10.0, 0.02).rates(2.7e-3, G)
    t_ref, s_ref = integrated_touch(1.0, 50.0, kappa)
    t, s = FlightPath.with_drag(1.0, 50.0, G, 2.7e-3, AirDrag(100.0, 10.0, 0.02)).touch()
    assert beta == 0.0
    assert t == pytest.approx(t_ref, rel=1e-10)
    assert s == pytest.approx(s_ref, rel=1e-10)


def test_a_drop_from_150_m_with_drag_touches_at_the_closed_form_time():
    drag = AirDrag(1.2, 0.5, 0.02)
    kappa, _ = drag.rates(2.7e-3, G)
    vt = math.sqrt(G / kappa)
    t_exact = vt / G * math.acosh(math.exp(kappa * 150.0))      # 18.4876 s
    result = cs.simulate_drop(cs.Contact(cs.HUNT_CROSSLEY, 1e7, 1e6), 2.7e-3, height=150.0,
                              gravity=G, duration=30.0, drag=drag)
    assert result.impacts, 'the drop never touched the plate'
    assert result.impacts[0].time == pytest.approx(t_exact, rel=1e-12)
    assert result.impacts[0].impact_speed == pytest.approx(
        vt * math.sqrt(-math.expm1(-2.0 * kappa * 150.0)), rel=1e-12)
