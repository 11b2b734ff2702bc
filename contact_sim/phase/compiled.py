"""The contact phase in compiled code: DOP853, its dense output and event location, in numba.

This is the machinery of ``phase.PhaseIntegrator`` (scipy's ``DOP853`` stepped from Python, the
reference path) moved into ``@njit`` kernels, with the same mathematics step for step:

* the dimensionless σ = √τ formulation of ``phase`` (y = (x, u), dy/dσ = 2σ (u, a));
* DOP853 (Hairer's 8(5,3) pair, the tableau scipy ships, ``_dop853_coefficients``) with scipy's
  step-size control (safety 0.9, factors 0.2 ... 10, error exponent -1/8, no growth right after
  a rejection) and its 7th-order dense output built from three extra stages;
* event location on the dense output by Brent's method (a port of scipy's ``brentq``, same
  tolerances): lift-off (x or φ going down through zero), maximum depth (u = 0), force peak;
* the energy test of the drop engine after every step, so that a caller can run many steps in
  one call and still stop at the first step where the sphere can no longer leave the plate.

The right-hand side takes its forcing as data: ``a = f(σ, u) - xⁿ - ζ xᵖ u|u|^(q-1)`` with the
external, dimensionless acceleration

    f = γ + A sin(Ω τ + ϕ) - d₁ u - d₂ u|u|,       τ = σ²,

read from the parameter vector (``P_GRAVITY``, ``P_AMPLITUDE``, ``P_OMEGA``, ``P_PHASE``,
``P_DRAG1``, ``P_DRAG2``): gravity, and ``phase.Forcing`` (a harmonically moving plate's
acceleration in the plate's frame, linear and quadratic drag) fills the other slots, with no new
kernel.

Every kernel is compiled with an explicit signature when this module is imported, and cached on
disk (numba ``cache=True``, in ``contact_sim/__pycache__``), so no call ever pays the compile
time; ``scripts/setup.sh`` imports the module once so that a fresh checkout writes the cache.
"""
import math

import numpy as np
from numba import njit
from numba.np.unsafe.ndarray import to_fixed_tuple

from contact_sim.phase.brent import brent_evaluated, brent_next, brent_start
from contact_sim.phase._dop853_coefficients import A as _A16, B as _B, C as _C16, D as _D, E3 as _E3, E5 as _E5

N_STAGES = 12
A = np.ascontiguousarray(_A16)
B = np.ascontiguousarray(_B)
C = np.ascontiguousarray(_C16)
D = np.ascontiguousarray(_D)
E3 = np.ascontiguousarray(_E3)
E5 = np.ascontiguousarray(_E5)

SAFETY, MIN_FACTOR, MAX_FACTOR, ERROR_EXPONENT = 0.9, 0.2, 10.0, -1.0 / 8.0
ROOT_XTOL = ROOT_RTOL = 1e-15     # as the reference's brentq calls
ROOT_MAXITER = 100

# -- the parameter vector (float64[NPAR]) -------------------------------------------------------
P_N, P_P, P_Q, P_ZETA = 0, 1, 2, 3                       # the law and the damping group ζ
P_GRAVITY, P_AMPLITUDE, P_OMEGA, P_PHASE, P_DRAG1, P_DRAG2 = 4, 5, 6, 7, 8, 9   # forcing f
P_START, P_TIME, P_LENGTH = 10, 11, 12                   # t₀ (s), T (s), Z (m)
P_STIFFNESS, P_DAMPING, P_MASS = 13, 14, 15              # k, λ, m (SI)
P_ENERGY_GRAVITY, P_REST_POTENTIAL = 16, 17    # g (m/s²) and k z₀^(n+1)/(n+1) - m g z₀ (J)
P_RTOL, P_ATOL = 18, 19
P_KIND = 20                                              # the law's short form (ContactLaw.kernel)
P_LIFT_EVENTS = 21        # 2: lift-off at x = 0 or φ = 0; 1: at x = 0 alone (φ cannot reach 0)
P_SINE = 22               # sin(Ω·0 + ϕ): the forcing's sine where Ω = 0 (set by ``_values``)
NPAR = 23
# (n, p, q) -> kind: the right-hand side of these spends no pow() (sqrt at most)

# -- the integrator state (float64[NSTATE]) -----------------------------------------------------
S_S, S_X, S_U, S_FX, S_FU, S_H = 0, 1, 2, 3, 4, 5        # σ, y, dy/dσ at σ, next |h|
S_S_OLD, S_X_OLD, S_U_OLD, S_FX_OLD, S_FU_OLD = 6, 7, 8, 9, 10   # start of the last step
S_PEAK, S_DEPTH, S_LIFTED, S_STEPS = 11, 12, 13, 14
S_END_T, S_END_Z, S_END_RATE, S_DENSE = 15, 16, 17, 18
NSTATE = 19

# -- why ``run`` returned -----------------------------------------------------------------------
LIFTED_OFF, TIME_REACHED, BUDGET_SPENT, ENERGY_BELOW, BUFFER_FULL, STEP_TOO_SMALL = 0, 1, 2, 3, 4, -1
POINT_BUFFER = 512
MAX_STEPS = 2 ** 62

_KW = dict(cache=True, nogil=True, error_model='numpy')
_brent_start, _brent_next, _brent_evaluated = (njit(**_KW)(f) for f in (brent_start, brent_next,
                                                                     brent_evaluated))


@njit(**_KW)
def _power(x, e):
    """x ** e for x >= 0, with the exponents of the named laws (0, 1/2, 1, 3/2) without pow()."""
    if e == 1.5:
        return x * math.sqrt(x)
    if e == 0.5:
        return math.sqrt(x)
    if e == 1.0:
        return x
    if e == 0.0:
        return 1.0
    return x ** e


@njit(**_KW)
def _signed_power(u, q):
    return u if q == 1.0 else math.copysign(_power(abs(u), q), u)


@njit(**_KW)
def _forcing(s, u, par):
    """The external dimensionless acceleration f(σ, u) (see the module docstring)."""
    f = par[P_GRAVITY] - par[P_DRAG1] * u - par[P_DRAG2] * u * abs(u)
    if par[P_AMPLITUDE] != 0.0:
        if par[P_OMEGA] == 0.0:     # a constant acceleration (a commanded plate's piece): the
            f += par[P_AMPLITUDE] * par[P_SINE]     # same sine at every σ, found once
        else:
            f += par[P_AMPLITUDE] * math.sin(par[P_OMEGA] * s * s + par[P_PHASE])
    return f


@njit(**_KW)
def _accel(s, x, u, par):
    # Unclamped beyond φ = 0, as in the reference: the phase ends at that located root anyway.
    ext = _forcing(s, u, par)
    if x <= 0.0:
        return ext
    kind = par[P_KIND]
    zeta = par[P_ZETA]
    if kind == 1.0:                  # n = 3/2, p = 1/2, q = 1 (Azad-Featherstone)
        r = math.sqrt(x)
        return ext - x * r - zeta * r * u
    if kind == 2.0:                  # n = p = 3/2, q = 1 (Hunt-Crossley)
        r = x * math.sqrt(x)
        return ext - r - zeta * r * u
    if kind == 3.0:                  # n = 3/2, p = q = 1 (Lee-Wang)
        return ext - x * math.sqrt(x) - zeta * x * u
    if kind == 4.0:                  # n = q = 1, p = 0 (linear)
        return ext - x - zeta * u
    return ext - _power(x, par[P_N]) - par[P_ZETA] * _power(x, par[P_P]) * _signed_power(u, par[P_Q])


@njit(**_KW)
def _phi(x, u, par):
    """x^(n-p) + ζ u|u|^(q-1): the force divided by xᵖ."""
    return _power(x if x > 0.0 else 0.0, par[P_N] - par[P_P]) + par[P_ZETA] * _signed_power(u, par[P_Q])


@njit(**_KW)
def _event(which, s, x, u, par):
    """0: x (touch/lift-off), 1: φ (lift-off), 2: u (maximum depth), 3: x^(1-p) dF/dτ (peak)."""
    if which == 0:
        return x
    if which == 1:
        return _phi(x, u, par)
    if which == 2:
        return u
    n, p, q = par[P_N], par[P_P], par[P_Q]
    phi = _phi(x, u, par)
    xp = x if x > 0.0 else 0.0
    a = _forcing(s, u, par) - _power(xp, p) * phi
    uq = 1.0 if q == 1.0 else q * _power(abs(u), q - 1.0)
    return p * u * phi + (n - p) * _power(xp, n - p) * u + par[P_ZETA] * uq * x * a


@njit(**_KW)
def _stages(K, first, last, s, x, u, h, par):
    """Runge-Kutta stages first..last-1 of a step of size h from (σ, x, u) into K (rows: the
    stages; columns: dx/dσ, du/dσ), from the Butcher rows A and nodes C."""
    for i in range(first, last):
        dx = 0.0
        du = 0.0
        for j in range(i):
            dx += K[j, 0] * A[i, j]
            du += K[j, 1] * A[i, j]
        si = s + C[i] * h
        ui = u + du * h
        K[i, 0] = 2.0 * si * ui
        K[i, 1] = 2.0 * si * _accel(si, x + dx * h, ui, par)


@njit(**_KW)
def _step(st, K, par):
    """One accepted DOP853 step from st[S_S] (scipy's RungeKutta._step_impl); False if the step
    size fell below ten ulps of σ."""
    s, x, u = st[S_S], st[S_X], st[S_U]
    rtol, atol = par[P_RTOL], par[P_ATOL]
    min_step = 10.0 * abs(np.nextafter(s, np.inf) - s)
    h_abs = st[S_H]
    if h_abs < min_step:
        h_abs = min_step
    rejected = False
    while True:
        if h_abs < min_step:
            return False
        s_new = s + h_abs
        h = s_new - s
        h_abs = abs(h)
        K[0, 0], K[0, 1] = st[S_FX], st[S_FU]
        _stages(K, 1, N_STAGES, s, x, u, h, par)
        bx = 0.0
        bu = 0.0
        for j in range(N_STAGES):
            bx += K[j, 0] * B[j]
            bu += K[j, 1] * B[j]
        x_new = x + h * bx
        u_new = u + h * bu
        fx_new = 2.0 * s_new * u_new
        fu_new = 2.0 * s_new * _accel(s_new, x_new, u_new, par)
        K[N_STAGES, 0], K[N_STAGES, 1] = fx_new, fu_new
        scale_x = atol + max(abs(x), abs(x_new)) * rtol
        scale_u = atol + max(abs(u), abs(u_new)) * rtol
        e5x = 0.0
        e5u = 0.0
        e3x = 0.0
        e3u = 0.0
        for j in range(N_STAGES + 1):
            e5x += K[j, 0] * E5[j]
            e5u += K[j, 1] * E5[j]
            e3x += K[j, 0] * E3[j]
            e3u += K[j, 1] * E3[j]
        e5x /= scale_x
        e5u /= scale_u
        e3x /= scale_x
        e3u /= scale_u
        e5 = e5x * e5x + e5u * e5u
        e3 = e3x * e3x + e3u * e3u
        if e5 == 0.0 and e3 == 0.0:
            error_norm = 0.0
        else:
            error_norm = abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * 2.0)
        if error_norm < 1.0:
            if error_norm == 0.0:
                factor = MAX_FACTOR
            else:
                factor = min(MAX_FACTOR, SAFETY * error_norm ** ERROR_EXPONENT)
            if rejected:
                factor = min(1.0, factor)
            h_abs *= factor
            break
        h_abs *= max(MIN_FACTOR, SAFETY * error_norm ** ERROR_EXPONENT)
        rejected = True
    st[S_S_OLD], st[S_X_OLD], st[S_U_OLD] = s, x, u
    st[S_FX_OLD], st[S_FU_OLD] = st[S_FX], st[S_FU]
    st[S_S], st[S_X], st[S_U], st[S_FX], st[S_FU] = s_new, x_new, u_new, fx_new, fu_new
    st[S_H] = h_abs
    st[S_DENSE] = 0.0
    return True


@njit(**_KW)
def _build_dense(st, K, F, par):
    """The 7th-order interpolant of the last step (scipy's DOP853._dense_output_impl)."""
    if st[S_DENSE] != 0.0:
        return
    s_old, x_old, u_old = st[S_S_OLD], st[S_X_OLD], st[S_U_OLD]
    h = st[S_S] - s_old
    _stages(K, N_STAGES + 1, K.shape[0], s_old, x_old, u_old, h, par)
    dx = st[S_X] - x_old
    du = st[S_U] - u_old
    F[0, 0], F[0, 1] = dx, du
    F[1, 0] = h * st[S_FX_OLD] - dx
    F[1, 1] = h * st[S_FU_OLD] - du
    F[2, 0] = 2.0 * dx - h * (st[S_FX] + st[S_FX_OLD])
    F[2, 1] = 2.0 * du - h * (st[S_FU] + st[S_FU_OLD])
    for r in range(D.shape[0]):
        fx = 0.0
        fu = 0.0
        for j in range(K.shape[0]):
            fx += D[r, j] * K[j, 0]
            fu += D[r, j] * K[j, 1]
        F[3 + r, 0] = h * fx
        F[3 + r, 1] = h * fu
    st[S_DENSE] = 1.0


@njit(**_KW)
def _dense(st, F, s):
    """y(σ) inside the last step (σ clamped to it); the dense output must be built."""
    s_old, s_new = st[S_S_OLD], st[S_S]
    s = min(max(s, s_old), s_new)
    r = (s - s_old) / (s_new - s_old)
    x = 0.0
    u = 0.0
    for i in range(F.shape[0]):
        x += F[F.shape[0] - 1 - i, 0]
        u += F[F.shape[0] - 1 - i, 1]
        w = r if i % 2 == 0 else 1.0 - r
        x *= w
        u *= w
    return x + st[S_X_OLD], u + st[S_U_OLD]


@njit(**_KW)
def _g(which, st, F, s, par):
    x, u = _dense(st, F, s)
    return _event(which, s, x, u, par)


@njit(**_KW)
def _root(which, xa, xb, st, F, par):
    """Brent's root of event ``which`` on the dense output in [xa, xb] (scipy's brentq.c)."""
    xpre, xcur = xa, xb
    fpre = _g(which, st, F, xpre, par)
    fcur = _g(which, st, F, xcur, par)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    if (fpre < 0.0) == (fcur < 0.0):
        # the step's end values bracketed it; the interpolant's ends round the other way
        return xpre if abs(fpre) < abs(fcur) else xcur
    state = _brent_start(xpre, xcur, fpre, fcur)
    x = xcur
    for _ in range(ROOT_MAXITER):
        done, x, state = _brent_next(state, ROOT_XTOL, ROOT_RTOL)
        if done:
            return x
        state = _brent_evaluated(state, _g(which, st, F, x, par))
    return x


@njit(**_KW)
def _dimensional(s, x, u, par):
    """(t, z, ż) in s, m, m/s."""
    length, time = par[P_LENGTH], par[P_TIME]
    return par[P_START] + time * s * s, x * length, u * length / time


@njit(**_KW)
def _values(par):
    """The parameter vector as a tuple, which the kernels below pass to the functions they call
    (passed by value: an array would be reference-counted at every call, a stage's ``_accel``
    and an event's evaluation included, which cost more than the arithmetic); with its
    ``P_SINE`` slot set first: sin(Ω σ² + ϕ) of a forcing with Ω = ±0, whose Ω σ² is Ω itself
    at every σ >= 0 (the same double the sine is then taken of)."""
    par[P_SINE] = math.sin(par[P_OMEGA] + par[P_PHASE])
    return to_fixed_tuple(par, NPAR)


@njit(**_KW)
def _contact_force(z, zdot, par):
    """``contact_force`` of the parameters as a tuple.  (A point a step: the powers
    that are the same double without pow() are taken so: zᵖ = zⁿ when p = n, and |ż|^1 = |ż|,
    which pow returns exactly.)"""
    if not z > 0.0:
        return 0.0
    sign = 1.0 if zdot > 0.0 else (-1.0 if zdot < 0.0 else 0.0)
    n, p, q = par[P_N], par[P_P], par[P_Q]
    zn = z ** n
    zp = zn if p == n else z ** p
    rate = abs(zdot) if q == 1.0 else abs(zdot) ** q
    f = par[P_STIFFNESS] * zn + par[P_DAMPING] * zp * sign * rate
    return f if f > 0.0 else 0.0


@njit('float64(float64, float64, float64[::1])', **_KW)
def contact_force(z, zdot, par):
    """The clamped force (N) of eq. 11, as ``ContactLaw.force``."""
    return _contact_force(z, zdot, _values(par))


@njit(**_KW)
def _record(st, s, x, u, par, pts, npts):
    t, z, zdot = _dimensional(s, x, u, par)
    f = _contact_force(z, zdot, par)
    pts[npts, 0], pts[npts, 1], pts[npts, 2], pts[npts, 3] = t, z, zdot, f
    if f > st[S_PEAK]:
        st[S_PEAK] = f
    if z > st[S_DEPTH]:
        st[S_DEPTH] = z
    return npts + 1


@njit(**_KW)
def _energy_above_rest(st, par):
    """½ m ż² + potential(z) - potential(z₀) at the end of the last step (J), as
    ``phase.energy_above_rest``."""
    _, z, zdot = _dimensional(st[S_S], st[S_X], st[S_U], par)
    n = par[P_N]
    zp = z if z > 0.0 else 0.0
    potential = (par[P_STIFFNESS] * zp ** (n + 1.0) / (n + 1.0)
                 - par[P_MASS] * par[P_ENERGY_GRAVITY] * z)
    return 0.5 * par[P_MASS] * zdot ** 2 + potential - par[P_REST_POTENTIAL]


@njit(**_KW)
def _events(st, K, F, par, pts, npts):
    """Locate lift-off, maximum depth and force peak in the last step; record its points."""
    s0, x0, u0 = st[S_S_OLD], st[S_X_OLD], st[S_U_OLD]
    s1, x1, u1 = st[S_S], st[S_X], st[S_U]
    s_end = np.inf
    for which in range(int(par[P_LIFT_EVENTS])):              # lift-off: the first root of x or φ
        if _event(which, s0, x0, u0, par) > 0.0 and _event(which, s1, x1, u1, par) <= 0.0:
            _build_dense(st, K, F, par)
            s_end = min(s_end, _root(which, s0, s1, st, F, par))
    lifted = s_end < np.inf
    if lifted:
        x_end, u_end = _dense(st, F, s_end)
    else:
        s_end, x_end, u_end = s1, x1, u1
    r0 = np.inf
    r1 = np.inf
    if s_end > s0:
        for which in range(2, 4):                             # maximum depth, force peak
            if (_event(which, s0, x0, u0, par) > 0.0
                    and _event(which, s_end, x_end, u_end, par) <= 0.0):
                _build_dense(st, K, F, par)
                r = _root(which, s0, s_end, st, F, par)
                if r0 == np.inf:
                    r0 = r
                else:
                    r1 = r
    if r1 < r0:
        r0, r1 = r1, r0
    for r in (r0, r1):
        if r < np.inf:
            xr, ur = _dense(st, F, r)
            npts = _record(st, r, xr, ur, par, pts, npts)
    if lifted:
        x_end = max(x_end, 0.0)
        t, z, zdot = _dimensional(s_end, x_end, u_end, par)
        st[S_LIFTED] = 1.0
        st[S_END_T], st[S_END_Z], st[S_END_RATE] = t, z, zdot
        pts[npts, 0], pts[npts, 1], pts[npts, 2], pts[npts, 3] = t, z, zdot, 0.0
        npts += 1
    else:
        npts = _record(st, s1, x1, u1, par, pts, npts)
    return npts


@njit('UniTuple(int64, 3)(float64[::1], float64[:, ::1], float64[:, ::1], float64[::1], '
      'float64[:, ::1], float64, int64, float64)', **_KW)
def run(st, K, F, par, pts, t_stop, max_steps, stop_energy):
    """Step until lift-off, until the time reaches ``t_stop`` (s), for ``max_steps`` steps, or
    until, after a step that did not lift off, the energy above rest is below ``stop_energy`` (J).

    The step's points (t, z, ż, F) go to ``pts`` from row 0.  Returns (reason, points, steps).
    """
    values = _values(par)
    npts = 0
    taken = 0
    cap = pts.shape[0] - 3
    while True:
        if st[S_LIFTED] != 0.0:
            return LIFTED_OFF, npts, taken
        if par[P_START] + par[P_TIME] * st[S_S] * st[S_S] >= t_stop:
            return TIME_REACHED, npts, taken
        if taken >= max_steps:
            return BUDGET_SPENT, npts, taken
        if npts >= cap:
            return BUFFER_FULL, npts, taken
        if not _step(st, K, values):
            return STEP_TOO_SMALL, npts, taken
        taken += 1
        st[S_STEPS] += 1.0
        npts = _events(st, K, F, values, pts, npts)
        if (stop_energy > -np.inf and st[S_LIFTED] == 0.0
                and _energy_above_rest(st, values) < stop_energy):
            return ENERGY_BELOW, npts, taken


@njit('UniTuple(float64, 2)(float64[::1], float64[:, ::1], float64[:, ::1], float64[::1], '
      'float64)', **_KW)
def state_in_last_step(st, K, F, par, s):
    """(x, u) at σ within the last step, from its dense output (built on first use)."""
    _build_dense(st, K, F, _values(par))
    return _dense(st, F, s)


@njit('float64(float64[::1], float64[::1])', **_KW)
def energy_above_rest(st, par):
    """The energy above rest (J) at the integrator's state."""
    return _energy_above_rest(st, _values(par))

