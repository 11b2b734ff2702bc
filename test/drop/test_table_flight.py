"""The compiled next touch over a vibrating table (``plate.compiled_flight``) against the Python
path it replaces (``flights.gap_flight``, kept as the reference and for flights with drag)."""
import math
from dataclasses import dataclass

import numpy as np
import pytest

from contact_sim.drop.engine import DropSimulation
from contact_sim.drop.mode_flight import Flight
from contact_sim.drop.plate import PlateMotion, SinusoidalPlate
from contact_sim.impact.damping_fit import damping_for_restitution
from contact_sim.model import get_law
from contact_sim.model.contact import Contact

G, MASS = 9.81, 0.066
LAWS = {'azad_featherstone': 1e10, 'hunt_crossley': 1e10, 'lee_wang': 1e10, 'linear': 1e7}


def contact_of(law, restitution=0.7):
    k, law = LAWS[law], get_law(law)
    return Contact(law, k, damping_for_restitution(law, k, MASS, restitution, 1.0))


@dataclass(frozen=True)
class ReferenceTable(SinusoidalPlate):
    """The same table, its flights planned by the Python reference path."""

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        return PlateMotion.plan_flight(self, flight, z, zdot, contact, drag_rates,
                                       after_lift_off)


@dataclass(frozen=True)
class RecordingTable(SinusoidalPlate):
    """The same table, recording the start of every flight it plans (compiled path)."""

    starts: list = None

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        self.starts.append((flight.start, z, zdot, after_lift_off))
        return super().plan_flight(flight, z, zdot, contact, drag_rates, after_lift_off)


def table_args(gamma, frequency=10.0, phase=0.4):
    w = 2.0 * math.pi * frequency
    return gamma * G / (w * w), frequency, phase


@pytest.mark.parametrize('law', sorted(LAWS))
@pytest.mark.parametrize('gamma', [0.8, 2.0, 3.7])
def test_every_flight_of_a_table_run_plans_the_touch_of_the_reference(law, gamma):
    contact = contact_of(law)
    starts = []
    table = RecordingTable(*table_args(gamma), starts=starts)
    sim = DropSimulation(contact, MASS, 0.01, plate=table)
    sim.advance(3.0)
    reference = ReferenceTable(*table_args(gamma))
    inside = [s for s in starts if s[1] > 0.0]
    assert len(starts) > 10 and (law == 'hunt_crossley' or inside)  # HC lifts off at z = 0
    for start, z, zdot, after in list(starts):      # (the table records these too)
        fast = Flight(table, G, start, z, zdot, contact, None, after)
        slow = Flight(reference, G, start, z, zdot, contact, None, after)
        assert fast.contact_time == pytest.approx(slow.contact_time, rel=1e-14, abs=1e-13)
        assert fast.apex == slow.apex


@pytest.mark.parametrize('law', ['azad_featherstone', 'linear'])
def test_a_table_run_on_the_compiled_flights_matches_the_reference_run(law):
    contact = contact_of(law)
    args = table_args(2.5)
    runs = []
    for plate in (SinusoidalPlate(*args), ReferenceTable(*args)):
        sim = DropSimulation(contact, MASS, 0.02, plate=plate)
        sim.advance(5.0)
        runs.append(sim)
    fast, slow = runs
    n = min(len(fast.impacts), len(slow.impacts))
    assert n >= 30
    t_fast = np.array([i.time for i in fast.impacts[:n]])
    t_slow = np.array([i.time for i in slow.impacts[:n]])
    v_fast = np.array([i.impact_speed for i in fast.impacts[:n]])
    v_slow = np.array([i.impact_speed for i in slow.impacts[:n]])
    # a chaotic orbit would amplify round-off; Γ = 2.5 is period-1, stable
    np.testing.assert_allclose(t_fast, t_slow, rtol=0, atol=1e-9)
    np.testing.assert_allclose(v_fast, v_slow, rtol=1e-7)


def test_a_flight_from_inside_the_surface_rising_above_a_fast_table():
    """After a lift-off at z > 0 the sphere may leave the surface before the force returns:
    both paths find the touch above it."""
    contact = contact_of('azad_featherstone')
    table = SinusoidalPlate(*table_args(3.0, frequency=40.0, phase=1.0))
    reference = ReferenceTable(*table_args(3.0, frequency=40.0, phase=1.0))
    rng = np.random.default_rng(3)
    for _ in range(50):
        z = rng.uniform(1e-9, 1e-6)
        zdot = -contact.stiffness * z / contact.damping * rng.uniform(1.0, 3.0) \
            - rng.uniform(0.0, 1.0)
        t0 = rng.uniform(0.0, 1.0)
        fast = Flight(table, G, t0, z, zdot, contact, None, True)
        slow = Flight(reference, G, t0, z, zdot, contact, None, True)
        assert fast.contact_time > t0
        assert fast.contact_time == pytest.approx(slow.contact_time, rel=1e-14, abs=1e-13)


@pytest.mark.parametrize('law', ['azad_featherstone', 'linear'])   # where φ can return
def test_the_fixed_plates_force_return_inside_the_surface_is_the_reference_search(law):
    """``compiled_flight.ballistic_force_return`` (``flights.touch_time``'s search after a
    lift-off at z > 0) against ``roots.first_upward_root`` on numpy's φ, the Python path."""
    from contact_sim.drop.plate import first_upward_root, touch_time
    from contact_sim.drop.plate.compiled_flight import ballistic_force_return
    from contact_sim.drop.plate.flights import surface_time
    contact = contact_of(law)
    k, lam, lw = contact.stiffness, contact.damping, contact.law
    rng = np.random.default_rng(5)
    found = 0
    for _ in range(200):
        z = 10.0 ** rng.uniform(-10.0, -5.0)     # just past a lift-off: φ(0) < 0
        zdot = -(k * z ** (lw.n - lw.p) / lam) ** (1.0 / lw.q) * (1.0 + 10.0 ** rng.uniform(-6, -1))
        t_search = min(surface_time(z, zdot, G), max(-zdot / G, 0.0))

        def phi(dt):
            return float(lw.reduced_force(z + zdot * dt + 0.5 * G * dt * dt, zdot + G * dt, k,
                                          lam))
        slow = first_upward_root(phi, t_search)
        fast = ballistic_force_return(z, zdot, G, t_search, k, lam, lw.n - lw.p, lw.q)
        if slow is None:
            assert fast == -1.0
        else:
            found += 1
            assert fast == pytest.approx(slow, rel=1e-14, abs=1e-18)
            assert touch_time(z, zdot, G, contact) == fast
    assert found > 10
