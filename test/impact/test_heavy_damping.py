"""simulate_impact at heavy damping against an independent solve_ivp of the same impact.

A Hunt-Crossley force zⁿ (k + λ ż) with n = p can reach zero only at the surface: under gravity
φ = k + λ ż decays towards zero but never crosses it while z > 0.  Before the fix a round-off
root of φ ended the impact early: at ζ = 100 the duration was 5.877e-4 s instead of 2.3139e-3 s
(54-98 % short for ζ >= 46, on both engines).
"""
import math

import pytest
from scipy.integrate import solve_ivp

import contact_sim as cs
from contact_sim.phase import use_engine

K, MASS, SPEED = 1e8, 0.01, 1.0
LENGTH = (MASS * SPEED ** 2 / K) ** 0.4          # Z of the impact (m)


def integrated_duration(stiffness, damping, mass, speed):
    """Contact duration (s) of m z̈ = -zⁿ (k + λ ż), n = 3/2, z(0) = 0, ż(0) = speed, to the
    return to z = 0, by DOP853 at rtol 1e-13 in the physical time (its own error ~1e-11)."""
    def rhs(t, y):
        z = max(y[0], 0.0)
        return [y[1], -z * math.sqrt(z) * (stiffness + damping * y[1]) / mass]

    def surface(t, y):
        return y[0]
    surface.terminal, surface.direction = True, -1
    scale = LENGTH / speed
    sol = solve_ivp(rhs, (0.0, 1e6 * scale), [0.0, speed], method='DOP853', rtol=1e-13,
                    atol=1e-13 * LENGTH, first_step=1e-3 * scale, events=surface)
    return float(sol.t_events[0][-1])


@pytest.mark.parametrize('engine', ['compiled', 'scipy'])
@pytest.mark.parametrize('zeta', [10.0, 46.0, 100.0, 1e3])
def test_hunt_crossley_duration_at_heavy_damping(engine, zeta):
    damping = zeta * MASS / LENGTH ** 2.5        # ζ = λ Z^(p+1) v^(q-2) / m
    reference = integrated_duration(K, damping, MASS, SPEED)
    with use_engine(engine):
        result = cs.simulate_impact(cs.Contact(cs.HUNT_CROSSLEY, K, damping), MASS, SPEED)
    # 1e-9: the accuracy the README claims of the exact path; the reference is good to ~1e-11
    assert result.contact_duration == pytest.approx(reference, rel=1e-9)


def test_the_issue_case_lasts_2_3139_ms():
    result = cs.simulate_impact(cs.Contact(cs.HUNT_CROSSLEY, 1e8, 1e10), 0.01, 1.0)
    assert result.contact_duration == pytest.approx(
        integrated_duration(1e8, 1e10, 0.01, 1.0), rel=1e-9)
    assert result.contact_duration == pytest.approx(2.3139e-3, rel=1e-4)
