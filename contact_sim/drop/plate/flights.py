"""A flight over the plate as each plate motion plans it: when the clamped force switches on
again, and the apex of a flight after a lift-off.

The fixed plate plans in closed form (``ballistic_flight``): the touch time by the quadratic
formula (``touch_time``), with air drag the closed-form ``flight.FlightPath``.  A moving plate
plans by the first root of the gap between the sphere and the plate (``gap_flight``), rigorously
bracketed (``roots.first_gap_root``).  Both work on a flight of the drop engine: an object with
``start`` (s), ``y0`` (m) and ``v0`` (m/s, the sphere's absolute lowest point and its upward
velocity at the start), ``gravity`` (m/s²), ``path`` and ``contact_time`` (set here), and the
methods ``absolute(t)`` -> (y, v) and ``state(t)`` -> (z, ż) relative to the plate.  Units: SI;
z > 0 is penetration, ż > 0 approach.
"""
import math

from contact_sim.drop.plate.compiled_ballistic import apex_height, surface_time, vacuum_plan
from contact_sim.drop.plate.compiled_ballistic import touch_time as ballistic_touch_time
from contact_sim.drop.plate.compiled_flight import (NO_EXIT, commanded_touch_time,
                                                   sinusoid_touch_time)
from contact_sim.drop.plate.roots import EPS, first_gap_root, first_upward_root
from contact_sim.drop.plate.roots import power as _power
from contact_sim.flight import FlightPath


def reduced_force_scalar(contact):
    """φ(z, ż) of ``contact`` (``ContactLaw.reduced_force``) on floats: the same numbers
    without numpy's overhead on one value, for the root refinements of a flight."""
    law, k, lam = contact.law, contact.stiffness, contact.damping
    e_spring, q = law.n - law.p, law.q

    def phi(z, zdot):
        rate = 0.0 if zdot == 0.0 else math.copysign(_power(abs(zdot), q), zdot)
        return k * _power(max(z, 0.0), e_spring) + lam * rate
    return phi


def touch_time(z, zdot, gravity, contact):
    """Ballistic flight time (s) from (z, ż) (m, m/s) over the fixed plate under ``gravity``
    (m/s²) until the clamped force of ``contact`` switches on again (inf: never): the compiled
    ``compiled_ballistic.touch_time``."""
    law = contact.law
    return ballistic_touch_time(z, zdot, gravity, contact.stiffness, contact.damping,
                                law.n - law.p, law.q)


def ballistic_flight(flight, z, zdot, contact, drag_rates, after_lift_off):
    """Plan ``flight`` from (z, ż) (m, m/s) over the fixed plate: set its ``contact_time`` (s)
    and, with ``drag_rates`` (κ, β of ``flight.AirDrag.rates``; ``None``: vacuum) and a flight
    that leaves the surface, its drag ``path``; returns the apex height (m) of a flight
    ``after_lift_off``, or ``None``.  A brief excursion inside the undeformed surface after a
    lift-off at z > 0 stays ballistic."""
    g, t = flight.gravity, flight.start
    if drag_rates is None:
        law = contact.law
        flight.contact_time, apex = vacuum_plan(t, z, zdot, g, contact.stiffness,
                                                contact.damping, law.n - law.p, law.q,
                                                after_lift_off)
        return None if math.isnan(apex) else apex
    dt = touch_time(z, zdot, g, contact)
    flight.contact_time = t + dt
    leaves = z <= 0.0 or (zdot < 0.0 and dt > surface_time(z, zdot, g))
    if drag_rates is not None and leaves:
        flight.path = FlightPath(flight.y0, flight.v0, g, *drag_rates,
                                 surface=-math.inf)   # lift-off inside, or a moving plate
        flight.contact_time = t + flight.path.time_to_height(0.0)
        return flight.path.apex_height if after_lift_off else None
    if after_lift_off and g > 0.0 and math.isfinite(dt):
        return apex_height(t, dt, z, zdot, g)
    return None


def gap_flight(plate, flight, z, zdot, contact, drag_rates, after_lift_off):
    """Plan ``flight`` from (z, ż) (m, m/s) over the moving ``plate``: its drag ``path`` (with
    ``drag_rates``, κ and β; ``None``: vacuum) and its ``contact_time`` (s, ``gap_touch_time``);
    returns the apex height (m) of a rising flight ``after_lift_off``, or ``None``."""
    g = flight.gravity
    if drag_rates is not None:
        flight.path = FlightPath(flight.y0, flight.v0, g, *drag_rates,
                                 surface=-math.inf)   # lift-off inside, or a moving plate
    flight.contact_time = gap_touch_time(plate, flight, z, zdot, contact, drag_rates)
    if after_lift_off and flight.v0 > 0.0:
        path = flight.path
        return path.apex_height if path is not None else rise_apex(flight.y0, flight.v0, g)
    return None


def rise_apex(y0, v0, gravity):
    """The apex height (m) of a vacuum flight leaving y0 (m) upwards at v0 > 0 (m/s) under
    ``gravity`` (m/s²)."""
    return y0 + 0.5 * v0 * v0 / gravity


def no_exit(start):
    """The error of a search that found no exit from the plate's surface after ``start`` (s)."""
    return RuntimeError(f'no exit from the plate surface found after t = {start!r}')


def _compiled_flight(flight, touch, after_lift_off):
    """Set ``flight``'s ``contact_time`` to ``touch`` (s, from a compiled search of
    ``compiled_flight``); returns the apex height (m) of a rising flight ``after_lift_off``."""
    if touch == NO_EXIT:
        raise no_exit(flight.start)
    flight.contact_time = touch
    if after_lift_off and flight.v0 > 0.0:
        return rise_apex(flight.y0, flight.v0, flight.gravity)
    return None


def table_flight(plate, flight, z, zdot, contact, after_lift_off):
    """``gap_flight`` over a ``SinusoidalPlate`` in vacuum, its touch time in compiled code
    (``compiled_flight.sinusoid_touch_time``: the algorithm of ``gap_touch_time``, step for
    step); returns the apex height (m) of a rising flight ``after_lift_off``, or ``None``."""
    g, law = flight.gravity, contact.law
    t = sinusoid_touch_time(flight.start, flight.y0, flight.v0, g, z, zdot, plate.amplitude,
                            plate.angular_frequency, plate.phase, contact.stiffness,
                            contact.damping, law.n - law.p, law.q,
                            g + plate.acceleration_bound())
    return _compiled_flight(flight, t, after_lift_off)


def commanded_flight(plate, flight, z, zdot, contact, after_lift_off):
    """``gap_flight`` over a ``CommandedPlate`` in vacuum, its touch time in compiled code
    (``compiled_flight.commanded_touch_time``, the same search as ``table_flight``'s); returns
    the apex height (m) of a rising flight ``after_lift_off``, or ``None``."""
    g, law = flight.gravity, contact.law
    t = commanded_touch_time(flight.start, flight.y0, flight.v0, g, z, zdot,
                             *plate.piece_rows, contact.stiffness, contact.damping,
                             law.n - law.p, law.q, g + plate.acceleration_bound())
    return _compiled_flight(flight, t, after_lift_off)


def gap_touch_time(plate, flight, z0, zdot0, contact, drag_rates):
    """Absolute time (s) at which the force switches on again over the moving ``plate``.

    Above the plate (z <= 0) it is the first root of the gap G = y - p going down, rigorously
    bracketed (``first_gap_root``, |G''| <= g + drag + max|p̈|); a tangent graze with G' >= 0 at
    the root (within rounding) is passed.  Inside the undeformed surface with zero force (after
    a lift-off at z > 0) the force returns when φ turns positive, searched on 64 samples per
    stretch as for the fixed plate, unless the sphere leaves the surface first.
    """
    g, t0 = flight.gravity, flight.start
    v_up = max(flight.v0, 0.0)
    kappa, beta = drag_rates if drag_rates is not None else (0.0, 0.0)
    bound = g + kappa * v_up * v_up + beta * v_up + plate.acceleration_bound()

    def gap(t):
        y, v = flight.absolute(t)
        p, pv, _ = plate.state(t)
        return y - p, v - pv, abs(y) + abs(p)

    def curvature(t, h):      # a lower bound of G'' = y'' - p̈ on [t, t + h]
        return -(g + kappa * v_up * v_up + beta * v_up) - plate.acceleration_range(t, t + h)[1]

    t = t0
    if z0 > 0.0:
        law, phi_at = contact.law, reduced_force_scalar(contact)
        stretch = 2.0 * abs(zdot0) / g + 1e-9

        def inside(t):
            G, dG, scale = gap(t)
            return -G, -dG, scale

        def curvature_inside(t, h):   # a lower bound of -G'' = p̈ - y'' (y'' <= -g in vacuum,
            return plate.acceleration_range(t, t + h)[0] + (  # <= 0 with drag)
                g if drag_rates is None else 0.0)

        for _ in range(10000):
            out = first_gap_root(inside, t, bound, t + stretch, local_curvature=curvature_inside)
            t_stop = out[0] if out is not None else t + stretch

            def phi(dt, start=t):
                return phi_at(*flight.state(start + dt))

            def phi_many(dt, start=t):
                y, v = flight.absolute(start + dt)
                p, pv = plate.search_states(start + dt)
                return law.reduced_force(p - y, pv - v, contact.stiffness, contact.damping)

            root = first_upward_root(phi, t_stop - t, func_many=phi_many)
            if root is not None:
                return t + root
            t = t_stop
            if out is not None:
                break
            stretch *= 2.0
        else:
            raise no_exit(t0)
    while True:
        t_root, G, dG = first_gap_root(gap, t, bound, local_curvature=curvature)
        if dG < 0.0:
            return t_root
        # a tangent graze (or the lift-off point itself): pass it, nudging until G > 0
        nudge = max(1e-12, 4.0 * EPS * abs(t_root))
        for _ in range(200):
            G2, dG2, scale = gap(t_root + nudge)
            if G2 > 16.0 * EPS * max(scale, 1e-9):
                break
            if G2 < 0.0 and dG2 < 0.0:
                return t_root + nudge
            nudge *= 2.0
        t = t_root + nudge

