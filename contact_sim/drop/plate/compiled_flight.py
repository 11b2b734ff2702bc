"""The next touch over a moving plate in compiled code: ``flights.gap_touch_time`` for a flight
in vacuum over a ``SinusoidalPlate`` p(t) = a sin(ω t + ϕ) or a ``CommandedPlate`` (its C¹
piecewise-quadratic pieces), step for step in numba.

The same algorithm as the Python path (which stays as the reference, and serves every other plate
and flights with drag): the rigorously bracketed first root of the gap (``roots.first_gap_root``,
with the plate's exact local bound of p̈), the force's return inside the undeformed surface after
a lift-off at z > 0 (64 samples of φ per stretch refined by Brent's method, scipy's brentq.c as
``phase.compiled`` ports it), and the tangent graze passed by nudging.  The search is written once
(``_touch_time``); only the plate's gap and its local range of p̈ depend on the plate
(``plate_gap``, ``plate_acceleration_range``), chosen at compile time by the type of the plate's
description: the table's (a, ω, ϕ), a tuple of floats; the commanded plate's pieces, a tuple of
arrays.  A flight's plan costs a few µs instead of about 100 µs of Python
(``python bench/bench_bounce.py``).

Compiled on first use and cached on disk (numba ``cache=True``).
"""
import math

from numba import njit, types
from numba.extending import overload

from contact_sim.drop.plate.pieces import piece_state
from contact_sim.drop.plate.roots import EPS, power, quadratic_positive
from contact_sim.phase import brent_evaluated, brent_next, brent_start

_KW = dict(cache=True, nogil=True, error_model='numpy')
# the plate's and the flight's small functions, inlined into the searches that call them many
# times a flight: a gap over the commanded plate took 122 ns called, 44 ns inlined (a throw-away
# timing of 200,000 calls, 2026-12-04), the calls passing its four arrays costing more than the
# arithmetic; one flight's plan is timed by python bench/bench_bounce.py
_INLINE = dict(_KW, inline='always')
_power, _quadratic_positive = njit(**_KW)(power), njit(**_KW)(quadratic_positive)
_piece_state = njit(**_INLINE)(piece_state)
_brent_start, _brent_next, _brent_evaluated = (njit(**_KW)(f) for f in (brent_start, brent_next,
                                                                     brent_evaluated))
TWO_PI = 2.0 * math.pi
NO_EXIT = -1.0        # the sphere never left the surface after 10000 stretches (an error)


@njit(**_INLINE)
def _flight(t, fl):
    """The sphere's height y (m) and upward velocity (m/s) at t in vacuum, as
    ``Flight.absolute``: ``fl`` = (t0, y0, v0, g)."""
    dt = t - fl[0]
    return fl[1] + fl[2] * dt - 0.5 * fl[3] * dt * dt, fl[2] - fl[3] * dt


# -- the vibrating table, ``tb`` = (a, ω, ϕ) -----------------------------------------------------

@njit(**_INLINE)
def _sinusoid_gap(t, fl, tb):
    """(G, G', scale) of the gap y - p at t over p = a sin(ω t + ϕ)."""
    y, v = _flight(t, fl)
    th = tb[1] * t + tb[2]
    p = tb[0] * math.sin(th)
    pv = tb[0] * tb[1] * math.cos(th)
    return y - p, v - pv, abs(y) + abs(p)


@njit(**_INLINE)
def _sinusoid_acceleration_range(t0, t1, tb):
    """(min, max) of p̈ over [t0, t1], as ``SinusoidalPlate.acceleration_range``."""
    a, w, ph = tb[0], tb[1], tb[2]
    aw2 = a * (w * w)
    a0 = -a * w * w * math.sin(w * t0 + ph)
    a1 = -a * w * w * math.sin(w * t1 + ph)
    lo, hi = min(a0, a1), max(a0, a1)
    th0, th1 = w * t0 + ph, w * t1 + ph
    if math.floor((th1 - 1.5 * math.pi) / TWO_PI) > math.floor((th0 - 1.5 * math.pi) / TWO_PI):
        hi = aw2
    if math.floor((th1 - 0.5 * math.pi) / TWO_PI) > math.floor((th0 - 0.5 * math.pi) / TWO_PI):
        lo = -aw2
    return lo, hi


# -- the commanded plate, ``pc`` = (starts, pos, vel, acc): ``CommandedPlate.piece_arrays``'s rows

@njit(**_KW)
def piece_index(starts, t):
    """``CommandedPlate._piece``: the last piece starting at or before t (the first before), by
    bisection as ``bisect.bisect_right`` (a third of ``np.searchsorted``'s time here)."""
    lo, hi = 0, starts.size
    while lo < hi:
        mid = (lo + hi) >> 1
        if t < starts[mid]:
            hi = mid
        else:
            lo = mid + 1
    return max(lo - 1, 0)


@njit(**_INLINE)
def commanded_state(t, pc):
    """(p m, ṗ m/s, p̈ m/s²) of the commanded plate at t (s): ``pieces.piece_state``, as
    ``CommandedPlate.state`` (constant velocity before the first piece, the last piece running
    to +inf)."""
    return _piece_state(pc[0], pc[1], pc[2], pc[3], piece_index(pc[0], t), t)


@njit(**_INLINE)
def _commanded_gap(t, fl, pc):
    """(G, G', scale) of the gap y - p at t over the commanded plate."""
    y, v = _flight(t, fl)
    p, pv, _ = commanded_state(t, pc)
    return y - p, v - pv, abs(y) + abs(p)


@njit(**_INLINE)
def _commanded_acceleration_range(t0, t1, pc):
    """(min, max) of p̈ over [t0, t1], as ``CommandedPlate.acceleration_range``: over the
    pieces it overlaps, and 0 before the first."""
    starts, acc = pc[0], pc[3]
    lo, hi = math.inf, -math.inf
    if t0 < starts[0]:
        lo, hi = 0.0, 0.0
    if t1 >= starts[0]:
        for i in range(piece_index(starts, max(t0, starts[0])), piece_index(starts, t1) + 1):
            lo, hi = min(lo, acc[i]), max(hi, acc[i])
    return lo, hi


# -- the plate's two functions, chosen at compile time by the type of its description ---------

def _is_table(pl):
    return isinstance(pl, types.UniTuple) and isinstance(pl.dtype, types.Float)


def _is_commanded(pl):
    return isinstance(pl, types.UniTuple) and isinstance(pl.dtype, types.Array)


def plate_gap(t, fl, pl):
    """(G, G', scale) of the gap y - p at t (m, m/s, m): the sphere's flight ``fl`` over the
    plate ``pl`` (the table's (a, ω, ϕ) or the commanded plate's pieces); in numba only."""
    raise NotImplementedError('plate_gap is compiled code: call it from an njit function')


def plate_acceleration_range(t0, t1, pl):
    """(min, max) of the plate's p̈ over [t0, t1] (m/s²); in numba only."""
    raise NotImplementedError('plate_acceleration_range is compiled code: call it from an '
                              'njit function')


@overload(plate_gap, jit_options=_KW)
def _plate_gap(t, fl, pl):
    if _is_table(pl):
        return lambda t, fl, pl: _sinusoid_gap(t, fl, pl)
    if _is_commanded(pl):
        return lambda t, fl, pl: _commanded_gap(t, fl, pl)
    return None


@overload(plate_acceleration_range, jit_options=_KW)
def _plate_acceleration_range(t0, t1, pl):
    if _is_table(pl):
        return lambda t0, t1, pl: _sinusoid_acceleration_range(t0, t1, pl)
    if _is_commanded(pl):
        return lambda t0, t1, pl: _commanded_acceleration_range(t0, t1, pl)
    return None


# -- the search, for any plate -----------------------------------------------------------------

@njit(**_KW)
def _first_gap_root(sign, t0, bound, t_max, fl, pl):
    """``roots.first_gap_root`` of sign·G (sign -1: the way out of the surface) with the local
    curvature bound of ``flights.gap_touch_time``; returns (found, t, G, G')."""
    t = t0
    M = max(bound, 1e-300)
    trial = 0.0
    g = fl[3]
    for _ in range(100000):
        G, dG, scale = plate_gap(t, fl, pl)
        G, dG = sign * G, sign * dG
        if G <= 16.0 * EPS * max(scale, 1e-9):
            return True, t, G, dG
        disc = math.sqrt(dG * dG + 2.0 * M * G)
        h = (dG + disc) / M if dG >= 0.0 else 2.0 * G / (disc - dG)
        if h >= 0.5 * trial:
            trial = 2.0 * max(trial, h)
            lo, hi = plate_acceleration_range(t, t + trial, pl)
            local = -g - hi if sign > 0.0 else lo + g
            if _quadratic_positive(G, dG, local, trial):
                h = trial
        trial = h
        t_next = t + h
        if t_next == t:
            return True, t, G, dG
        if t_next > t_max:
            return False, t, G, dG
        t = t_next
    return False, t, 0.0, 0.0


@njit(**_INLINE)
def _phi(dt, start, fl, pl, law):
    """φ = k z₊^(n-p) + λ ż|ż|^(q-1) at start + dt; ``law`` = (k, λ, n - p, q)."""
    t = start + dt
    G, dG, _ = plate_gap(t, fl, pl)
    z, zdot = -G, -dG
    rate = 0.0 if zdot == 0.0 else math.copysign(_power(abs(zdot), law[3]), zdot)
    return law[0] * _power(max(z, 0.0), law[2]) + law[1] * rate


@njit(**_KW)
def _brentq(xa, xb, start, fl, pl, law):
    """scipy's brentq.c (xtol 1e-18, rtol 1e-15, 100 iterations) on ``_phi``."""
    xtol, rtol = 1e-18, 1e-15
    xpre, xcur = xa, xb
    fpre = _phi(xpre, start, fl, pl, law)
    fcur = _phi(xcur, start, fl, pl, law)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    state = _brent_start(xpre, xcur, fpre, fcur)
    x = xcur
    for _ in range(100):
        done, x, state = _brent_next(state, xtol, rtol)
        if done:
            return x
        state = _brent_evaluated(state, _phi(x, start, fl, pl, law))
    return x


@njit(**_KW)
def _first_upward_root(t_max, start, fl, pl, law):
    """``roots.first_upward_root`` of φ on 64 stretches of (0, t_max]; -1: none seen."""
    samples = 64
    step = t_max / samples
    prev_t = 0.0
    prev_v = _phi(0.0, start, fl, pl, law)
    for i in range(1, samples + 1):
        t = i * step if i < samples else t_max
        v = _phi(t, start, fl, pl, law)
        if v > 0.0 and prev_v <= 0.0:
            return _brentq(prev_t, t, start, fl, pl, law)
        prev_t, prev_v = t, v
    return -1.0


@njit(**_KW)
def _touch_time(t0, y0, v0, g, z0, zdot0, pl, law, bound):
    """``flights.gap_touch_time`` in vacuum over the plate ``pl``; ``NO_EXIT`` where it
    raises."""
    fl = (t0, y0, v0, g)
    t = t0
    if z0 > 0.0:
        stretch = 2.0 * abs(zdot0) / g + 1e-9
        left = False
        for _ in range(10000):
            found, t_root, _, _ = _first_gap_root(-1.0, t, bound, t + stretch, fl, pl)
            t_stop = t_root if found else t + stretch
            root = _first_upward_root(t_stop - t, t, fl, pl, law)
            if root >= 0.0:
                return t + root
            t = t_stop
            if found:
                left = True
                break
            stretch *= 2.0
        if not left:
            return NO_EXIT
    while True:
        _, t_root, G, dG = _first_gap_root(1.0, t, bound, math.inf, fl, pl)
        if dG < 0.0:
            return t_root
        nudge = max(1e-12, 4.0 * EPS * abs(t_root))
        for _ in range(200):
            G2, dG2, scale = plate_gap(t_root + nudge, fl, pl)
            if G2 > 16.0 * EPS * max(scale, 1e-9):
                break
            if G2 < 0.0 and dG2 < 0.0:
                return t_root + nudge
            nudge *= 2.0
        t = t_root + nudge


@njit('float64(float64, float64, float64, float64, float64, float64, float64, float64, '
      'float64, float64, float64, float64, float64, float64)', **_KW)
def sinusoid_touch_time(t0, y0, v0, g, z0, zdot0, a, w, ph, k, lam, spring_exponent, q,
                        bound):
    """Absolute time (s) at which the force switches on again over the table p = a sin(ω t + ϕ)
    after a flight in vacuum from t0 (s): the sphere's lowest point at y0 (m) moving up at v0
    (m/s) under g (m/s²), at (z0, ż0) (m, m/s) relative to the plate; the law's φ from k, λ,
    n - p and q; ``bound`` the gap's |G''| bound (m/s²).  ``NO_EXIT`` if the sphere never
    leaves the surface (``flights.gap_touch_time`` raises there)."""
    return _touch_time(t0, y0, v0, g, z0, zdot0, (a, w, ph), (k, lam, spring_exponent, q),
                       bound)


@njit('float64(float64, float64, float64, float64, float64, float64, float64[::1], '
      'float64[::1], float64[::1], float64[::1], float64, float64, float64, float64, float64)',
      **_KW)
def commanded_touch_time(t0, y0, v0, g, z0, zdot0, starts, pos, vel, acc, k, lam,
                         spring_exponent, q, bound):
    """``sinusoid_touch_time`` over a ``CommandedPlate``: its pieces' start times (s,
    increasing), positions (m), velocities (m/s) and accelerations (m/s², the last piece's 0)
    as contiguous float64 arrays (the rows of ``CommandedPlate.piece_arrays``)."""
    return _touch_time(t0, y0, v0, g, z0, zdot0, (starts, pos, vel, acc),
                       (k, lam, spring_exponent, q), bound)


@njit('float64(float64, float64, float64, float64, float64, float64, float64, float64)', **_KW)
def ballistic_force_return(z, zdot, g, t_search, k, lam, spring_exponent, q):
    """Over the fixed plate, inside the undeformed surface with zero force (after a lift-off at
    z > 0 (m), ż (m/s), under g (m/s²)): the first time dt in (0, t_search] (s) at which φ
    turns positive, as ``flights.touch_time`` looks for it (64 samples, Brent); -1: none.
    The flight's gap with a plate at rest is exactly z + ż dt + ½ g dt² (negations are exact)."""
    return _first_upward_root(t_search, 0.0, (0.0, -z, -zdot, g), (0.0, 0.0, 0.0),
                              (k, lam, spring_exponent, q))
