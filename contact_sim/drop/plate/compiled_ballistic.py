"""A flight over the fixed plate in compiled code: when the clamped force switches on again and
the apex of a flight after a lift-off, in closed form (numba).

``flights.ballistic_flight`` (a flight planned by the fixed plate) calls these functions.
Units: SI; z > 0 is penetration, ż > 0 approach, g >= 0 along +z.

Compiled with explicit signatures when imported and cached on disk (numba ``cache=True``).
"""
import math

from numba import njit

from contact_sim.drop.plate.compiled_flight import ballistic_force_return

_KW = dict(cache=True, nogil=True, error_model='numpy')
_SIG4 = 'float64(float64, float64, float64, float64, float64, float64, float64)'


@njit('float64(float64, float64, float64)', **_KW)
def surface_time(z, zdot, gravity):
    """Ballistic time (s) to rise from z > 0 (m) at ż (m/s) to the undeformed surface of the
    fixed plate under ``gravity`` (m/s²); inf: never."""
    disc = zdot * zdot - 2.0 * gravity * z
    return 2.0 * z / (-zdot + math.sqrt(disc)) if disc >= 0.0 and zdot < 0.0 else math.inf


@njit(**_KW)
def _touch_from_surface(z, zdot, g):
    """The flight time (s) from z <= 0 (m) at ż (m/s) to the surface (inf: never)."""
    if g > 0.0:
        disc = zdot * zdot - 2.0 * g * z
        if zdot >= 0.0:
            return 2.0 * -z / (zdot + math.sqrt(disc)) if z < 0.0 else 0.0
        return (-zdot + math.sqrt(disc)) / g
    return -z / zdot if zdot > 0.0 else math.inf


@njit(_SIG4, **_KW)
def touch_time(z, zdot, g, k, lam, spring_exponent, q):
    """Ballistic flight time (s) from (z, ż) (m, m/s) over the fixed plate under g (m/s²) until
    the clamped force k zⁿ + λ zᵖ ż|ż|^(q-1) switches on again (inf: never); ``spring_exponent``
    is n - p.

    Inside the undeformed surface with zero force (after a lift-off at z > 0) the force returns
    when φ = k z^(n-p) + λ ż|ż|^(q-1) turns positive while z > 0 (``ballistic_force_return``), or
    when ż reaches 0 there (the spring pushes again); else the sphere leaves the surface and
    flies back to it."""
    if not z > 0.0:
        return _touch_from_surface(z, zdot, g)
    if g > 0.0:
        t_out = surface_time(z, zdot, g)
        t_search = min(t_out, max(-zdot / g, 0.0))
    else:
        t_out = math.inf
        t_search = -z / zdot if zdot < 0.0 else 0.0
    if t_search > 0.0:
        root = ballistic_force_return(z, zdot, g, t_search, k, lam, spring_exponent, q)
        if root >= 0.0:
            return root
    if g == 0.0:
        return math.inf
    if t_search < t_out:
        return t_search
    return t_out + _touch_from_surface(0.0, zdot + g * t_out, g)


@njit('float64(float64, float64, float64, float64, float64)', **_KW)
def apex_height(start, flight_time, z, zdot, g):
    """The apex height (m) above the fixed plate of a flight after a lift-off at ``start`` (s)
    from (z, ż) (m, m/s) under g > 0 (m/s²), which touches again ``flight_time`` (s, finite)
    later: the lowest z of the flight, negated (the top of the parabola if it comes inside the
    flight, else the lower of the flight's two ends, z and the touch, evaluated as
    ``Flight.state`` evaluates it)."""
    t_top = -zdot / g
    if 0.0 < t_top < flight_time:
        return -(z - zdot * zdot / (2.0 * g))
    dt = (start + flight_time) - start
    touch = 0.0 - ((0.0 - z) + (0.0 - zdot) * dt - 0.5 * g * dt * dt)
    return -(touch if touch < z else z)


@njit('UniTuple(float64, 2)(float64, float64, float64, float64, float64, float64, float64, '
      'float64, boolean)', **_KW)
def vacuum_plan(start, z, zdot, g, k, lam, spring_exponent, q, after_lift_off):
    """A vacuum flight over the fixed plate from (z, ż) (m, m/s) at ``start`` (s), planned in
    one call: (the touch time s, inf: never; the apex height m of a flight ``after_lift_off``
    that touches again under g > 0, else nan): ``touch_time`` and ``apex_height``."""
    dt = touch_time(z, zdot, g, k, lam, spring_exponent, q)
    if after_lift_off and g > 0.0 and math.isfinite(dt):
        return start + dt, apex_height(start, dt, z, zdot, g)
    return start + dt, math.nan
