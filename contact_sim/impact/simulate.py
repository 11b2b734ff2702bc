"""One impact, simulated exactly: the slow reference path behind every fast formula.

``simulate_impact`` follows a sphere that touches a plate (z = 0) with penetration rate ż = v
until lift-off, the first instant the clamped force returns to zero (for the Azad-Featherstone
law that happens while z > 0).  See ``phase`` for the formulation.  Units: SI.
"""
import math
from dataclasses import dataclass

from contact_sim.impact.force_tail import deepest_point, force_tail, needs_force_tail, way_in_atol
from contact_sim.model import require_contact
from contact_sim.phase import (DEFAULT_ATOL, DEFAULT_RTOL, contact_phase, lift_off_energy,
                               phase_scales)
from contact_sim.validation import require_int, require_nonnegative, require_positive, require_rtol


@dataclass(frozen=True)
class ImpactResult:
    """Outcome of one impact (SI units).

    ``status`` is 0 when the sphere lifted off and 1 when, under gravity, it came to rest in
    permanent contact (restitution 0, rebound 0, contact_duration inf).
    """

    restitution: float
    rebound_speed: float
    contact_duration: float
    peak_force: float
    max_penetration: float
    steps: int
    status: int
    message: str


def simulate_impact(contact, mass, speed, gravity=0.0, rtol=DEFAULT_RTOL, max_steps=200_000,
                    engine=None):
    """Integrate one impact of a sphere of (reduced) mass ``mass`` (kg) arriving at ``speed`` (m/s).

    Returns an ``ImpactResult``; the restitution is ``rebound_speed / speed`` with both speeds
    taken at touch and at lift-off.  ``engine`` is 'compiled' or 'scipy' (the reference path;
    default ``phase.get_engine()``), see ``phase.contact_phase``.
    """
    contact = require_contact(contact)
    mass = require_positive('mass', mass)
    speed = require_positive('speed', speed)
    gravity = require_nonnegative('gravity', gravity)
    rtol = require_rtol('rtol', rtol)
    max_steps = require_int('max_steps', max_steps, 1, 10 ** 9)
    # heavy damping with n > p: the way out is integrated in the force (``force_tail``)
    zeta = phase_scales(contact, mass, gravity, 0.0, speed).damping
    tail = needs_force_tail(contact.law, zeta)
    phase = contact_phase(contact, mass, gravity, 0.0, 0.0, speed, rtol=rtol, engine=engine,
                          atol=way_in_atol(zeta) if tail else DEFAULT_ATOL, keep_points=tail)
    floor = lift_off_energy(contact, mass, gravity) if gravity > 0.0 else -math.inf
    while not phase.lifted_off:
        if phase.steps >= max_steps:
            raise RuntimeError(f'impact not finished after max_steps = {max_steps} steps')
        # every step is followed by the energy test: run() stops where it may hold
        phase.run(max_steps=max_steps - phase.steps, stop_energy=floor)
        if floor > -math.inf and phase.energy_above_rest() < floor:
            return ImpactResult(0.0, 0.0, math.inf, phase.peak_force, phase.max_penetration,
                                phase.steps, 1, 'came to rest in permanent contact (no bounce)')
    t_end, _, zdot_end = phase.end
    steps = phase.steps
    if tail:
        end = force_tail(contact.law, phase.scales, 0.0, deepest_point(phase.points), rtol,
                         t_end)
        if end is None:
            return ImpactResult(0.0, 0.0, math.inf, phase.peak_force, phase.max_penetration,
                                steps, 1, 'came to rest in permanent contact (no bounce)')
        t_end, _, zdot_end, tail_steps = end
        steps += tail_steps
    rebound = min(max(-zdot_end, 0.0), speed)   # the contact only dissipates: e <= 1
    return ImpactResult(rebound / speed, rebound, t_end, phase.peak_force, phase.max_penetration,
                        steps, 0, 'lifted off')
