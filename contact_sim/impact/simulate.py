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
from contact_sim.impact.scales import checked_scales_at
from contact_sim.validation import (require_gravity, require_int, require_mass,
                                    require_positive, require_rtol)


@dataclass(frozen=True)
class ImpactResult:
    """Outcome of one impact (SI units), as ``simulate_impact`` returns it.

    Attributes
    ----------
    restitution : float
        e = ``rebound_speed`` / impact speed, 0 <= e <= 1.
    rebound_speed : float
        Separation speed at lift-off, m/s.
    contact_duration : float
        Touch to lift-off, s (``inf`` for a permanent contact).
    peak_force : float
        The largest contact force, N.
    max_penetration : float
        The deepest penetration, m.
    steps : int
        Integrator steps taken.
    status : int
        0 when the sphere lifted off, 1 when, under gravity, it came to rest in permanent
        contact (restitution 0, rebound 0, contact_duration inf).
    message : str
        The status in words.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> result = cs.simulate_impact(contact, mass, 1.0)
    >>> result.status, result.message
    (0, 'lifted off')
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
    """Integrate one impact of a sphere arriving at the plate at ``speed``, to lift-off.

    The slow, exact reference path: the restitution is ``rebound_speed / speed`` with both
    speeds taken at touch and at lift-off.

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The (reduced) mass, kg, > 0.
    speed : float
        Impact speed, m/s, > 0.
    gravity : float, optional
        Gravity g, m/s², 0 <= g <= ``GRAVITY_MAX`` (1e6, as for a drop; default 0: no
        gravity during contact).
    rtol : float, optional
        The integrator's relative tolerance, 1e-14 <= rtol <= 1e-3.
    max_steps : int, optional
        Integrator steps allowed, 1 to 1e9.
    engine : {None, 'compiled', 'scipy'}, optional
        The integrator (``phase.contact_phase``; default ``phase.get_engine()``); 'scipy' is
        the reference path.

    Returns
    -------
    ImpactResult
        Restitution, rebound speed, duration, peak force, depth, steps and status.

    Raises
    ------
    InputError
        Keyed ``contact``, ``mass``, ``speed``, ``gravity``, ``rtol`` or ``max_steps``: a value
        out of range.
    RuntimeError
        The impact did not end within ``max_steps`` steps.

    See Also
    --------
    restitution : The same e, fast (closed forms and master curves).

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> result = cs.simulate_impact(contact, mass, 1.0)
    >>> print(f"e = {result.restitution:.4f}, tc = {result.contact_duration * 1e6:.2f} us, "
    ...       f"F = {result.peak_force:.1f} N")
    e = 0.7381, tc = 100.24 us, F = 2019.2 N
    >>> abs(result.restitution - cs.restitution(contact, mass, 1.0)) < 1e-8
    True
    """
    contact = require_contact(contact)
    mass = require_mass(mass)
    speed = require_positive('speed', speed)
    checked_scales_at(contact, mass, speed, 'speed')   # Z, T finite doubles, ζ in range
    gravity = require_gravity(gravity)
    rtol = require_rtol('rtol', rtol)
    max_steps = require_int('max_steps', max_steps, 1, 10 ** 9)
    # heavy damping with n > p: the way out is integrated in the force (``force_tail``)
    scales = phase_scales(contact, mass, gravity, 0.0, speed)
    zeta = scales.zeta
    tail = needs_force_tail(contact.law, zeta)
    phase = contact_phase(contact, mass, gravity, 0.0, 0.0, speed, rtol=rtol, engine=engine,
                          atol=way_in_atol(zeta) if tail else DEFAULT_ATOL, keep_points=tail,
                          scales=scales)
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
