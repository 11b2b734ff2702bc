"""Vertical flight under gravity and air drag, in closed form (no integrator steps).

A sphere of mass m and radius R₁ moves vertically in still air: height y (m, up positive),
velocity v = ẏ (m/s, up positive), gravity g (m/s²) down.  Air drag opposes the motion:

    m v̇ = -m g - c v|v| - b v,      c = ½ ρ C_d A,  A = π R₁²   (quadratic, kg/m)
                                     b                            (optional linear, N·s/m)

Per unit mass, κ = c / m (1/m) and β = b / m (1/s).  Each leg of the flight is a Riccati
equation with constant coefficients and has an exact solution:

* going up (v > 0), v̇ = -(g + β v + κ v²): with h = β / 2κ and Ω² = g / κ - h²,
  v = Ω tan(θ₀ - κ Ω t) - h, θ₀ = atan((v₀ + h) / Ω) (the tan form; β = 0 gives
  v = v_t tan(atan(v₀ / v_t) - g t / v_t) with the terminal speed v_t = √(g / κ)), and the rise
  is ln(cos θ / cos θ₀) / κ - h t.  The apex comes at t_a = atan(v₀ Ω / (Ω² + h (v₀ + h))) / (κ Ω)
  at the rise ln(1 + v₀ (κ v₀ + β) / g) / 2κ - h t_a;
* coming down (speed s = -v > 0), ṡ = g - β s - κ s² = κ (s₊ - s)(s + s₋) with the terminal
  speed s₊ and r = κ (s₊ + s₋) = √(β² + 4 κ g) (the tanh / log-cosh form: β = 0 and s₀ = 0 give
  s = v_t tanh(g t / v_t) and a fall of ln cosh(g t / v_t) / κ);
* without quadratic drag (κ = 0) the same legs are exponentials, and in vacuum parabolas.

The next touch of a level (the plate, y = 0) on the way down is exact in closed form for
quadratic drag (β = 0): the speed after a fall D from s₀ is s₁² = s₀² e^(-2κD) + v_t² (1 - e^(-2κD))
and the time (D + ln((v_t + s₁) / (v_t + s₀)) / κ) / v_t.  This is atanh(s₁/v_t) - atanh(s₀/v_t)
(coth for s₀ > v_t) times v_t / g, with 1 - (s₁/v_t)² = (1 - (s₀/v_t)²) e^(-2κD) taken out of the
logarithms: no argument rounds to 1 near terminal speed, so a fall of any length lands (the atanh
form gave inf beyond about 120 m for a ping-pong ball).  With a linear term (β > 0) the
fall is an explicit function of time but its inverse is not: the touch is then the root of the
closed-form fall on a bracket [0, t_hi] grown by doubling from the vacuum time (the fall grows
monotonically without bound), located by Brent's method to 1e-15 relative.

Every formula is written without cancellation at small drag (log1p, expm1 and the tangent
subtraction formula), so κ → 0 tends smoothly to the vacuum parabola.  The linear term must be
below critical, b < 2 √(c m g) (realistic Stokes drag is four orders of magnitude below): above it
the upward leg has another form that is not implemented, and a named ``ValueError`` says so.
"""
import math
from dataclasses import InitVar, dataclass

import numpy as np

from contact_sim.validation import (InputError, require_nonnegative, require_positive,
                                    require_range, require_real)

# the air a sphere flies through, by default (the command line shows them in its help: this
# module imports numpy only, scipy's root search where a linear drag term needs it)
AIR_DENSITY = 1.204          # kg/m³: dry air at 20 °C and 101.325 kPa
SPHERE_DRAG_COEFFICIENT = 0.47   # smooth sphere, subcritical Reynolds number (1e3 - 2e5)


@dataclass(frozen=True)
class AirDrag:
    """Air drag on a sphere of radius ``radius`` (R₁, m): ½ ρ C_d π R₁² v² (+ b v), in N.

    ``air_density`` ρ (kg/m³, 0 <= ρ <= 100), ``drag_coefficient`` C_d (0 <= C_d <= 10; about 0.47
    for a smooth sphere, 0.25-0.3 for a dimpled golf ball at speed), ``linear_coefficient`` b
    (N·s/m, >= 0; Stokes drag 6 π μ R₁ is about 3.4e-6 N·s/m for R₁ = 1 cm in air).

    Attributes
    ----------
    air_density : float
        Air density ρ, kg/m³, 0 <= ρ <= 100 (default 1.204: dry air at 20 °C, 101.325 kPa).
    drag_coefficient : float
        Drag coefficient C_d, dimensionless, 0 <= C_d <= 10 (default 0.47: a smooth sphere).
    radius : float
        The sphere's radius R₁, m, > 0 (default 0.02).
    linear_coefficient : float
        Linear drag coefficient b, N·s/m, >= 0 (default 0).

    Raises
    ------
    InputError
        Keyed by the field out of its range.

    See Also
    --------
    FlightPath : A flight with these drag rates, in closed form.

    Examples
    --------
    >>> import contact_sim as cs
    >>> drag = cs.AirDrag(radius=0.02)           # a 40 mm ball in air
    >>> print(f"c = {drag.quadratic_coefficient:.4e} kg/m")
    c = 3.5555e-04 kg/m
    >>> cs.AirDrag(drag_coefficient=11.0)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: drag_coefficient = 11.0 is out of range: allowed 0 <= drag_coefficient <= 10
    """

    air_density: float = AIR_DENSITY
    drag_coefficient: float = SPHERE_DRAG_COEFFICIENT
    radius: float = 0.02
    linear_coefficient: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, 'air_density',
                           require_range('air_density', self.air_density, 0.0, 100.0))
        object.__setattr__(self, 'drag_coefficient',
                           require_range('drag_coefficient', self.drag_coefficient, 0.0, 10.0))
        object.__setattr__(self, 'radius', require_positive('radius', self.radius))
        object.__setattr__(self, 'linear_coefficient',
                           require_nonnegative('linear_coefficient', self.linear_coefficient))

    @property
    def quadratic_coefficient(self):
        """The quadratic drag coefficient c = ½ ρ C_d π R₁² (kg/m): the drag force is c v²."""
        return 0.5 * self.air_density * self.drag_coefficient * math.pi * self.radius ** 2

    def rates(self, mass, gravity):
        """The drag per unit mass, (κ, β) = (c / m, b / m).

        Parameters
        ----------
        mass : float
            The sphere's mass, kg, > 0.
        gravity : float
            Gravity g, m/s², > 0.

        Returns
        -------
        tuple of float
            (κ in 1/m, β in 1/s).

        Raises
        ------
        InputError
            Keyed ``mass``: not a number > 0.
        ValueError
            Naming ``linear_coefficient``: b >= 2 √(c m g) (see the module doc).

        Examples
        --------
        >>> import contact_sim as cs
        >>> kappa, beta = cs.AirDrag(radius=0.02).rates(0.0027, 9.81)   # a 2.7 g ball
        >>> print(f"{kappa:.4f} 1/m, {beta} 1/s")
        0.1317 1/m, 0.0 1/s
        """
        mass = require_positive('mass', mass)
        kappa, beta = self.quadratic_coefficient / mass, self.linear_coefficient / mass
        if _linear_term_too_large(kappa, beta, gravity):
            limit = 2.0 * math.sqrt(self.quadratic_coefficient * mass * gravity)
            raise ValueError(f'linear_coefficient = {self.linear_coefficient!r} is out of '
                             f'range: allowed 0 <= linear_coefficient < 2 sqrt(c m g) = '
                             f'{limit:.6g} N s/m together with quadratic drag')
        return kappa, beta

    @property
    def active(self):
        """True if there is any drag (c > 0 or b > 0)."""
        return self.quadratic_coefficient > 0.0 or self.linear_coefficient > 0.0


def _linear_term_too_large(kappa, beta, gravity):
    """With quadratic drag, the closed forms need β² < 4 κ g (module doc)."""
    return kappa > 0.0 and beta > 0.0 and beta * beta >= 4.0 * kappa * gravity


# -- the two legs, vectorised over numpy arrays (scalars work too) --------------------------
def _rise(t, v0, g, kappa, beta):
    """Rise (m) and velocity (m/s) a time t after leaving with upward speed v0 > 0 (t <= apex)."""
    t, v0 = np.asarray(t, dtype=float), np.asarray(v0, dtype=float)
    if kappa > 0.0:
        h = beta / (2.0 * kappa)
        omega = math.sqrt(g / kappa - h * h)
        tan0 = (v0 + h) / omega
        delta = kappa * omega * t
        # cos θ / cos θ0 = cos δ + tan θ0 sin δ, θ = θ0 - δ, without cancellation at small δ
        rise = np.log1p(-2.0 * np.sin(0.5 * delta) ** 2 + tan0 * np.sin(delta)) / kappa - h * t
        td = np.tan(delta)
        v = ((v0 + h) - omega * td) / (1.0 + tan0 * td) - h
        return rise, v
    if beta > 0.0:
        em = -np.expm1(-beta * t)                     # 1 - e^(-βt)
        s = g / beta
        return (v0 + s) * em / beta - s * t, v0 - (v0 + s) * em
    return v0 * t - 0.5 * g * t * t, v0 - g * t


def apex(v0, g, kappa, beta):
    """(t_a, rise) of the apex after leaving with upward speed v0 >= 0 (m/s): closed form."""
    v0 = np.asarray(v0, dtype=float)
    if kappa > 0.0:
        h = beta / (2.0 * kappa)
        omega = math.sqrt(g / kappa - h * h)
        t_a = np.arctan(v0 * omega / (omega * omega + h * (v0 + h))) / (kappa * omega)
        return t_a, np.log1p(v0 * (kappa * v0 + beta) / g) / (2.0 * kappa) - h * t_a
    if beta > 0.0:
        t_a = np.log1p(beta * v0 / g) / beta
        return t_a, (v0 - g * t_a) / beta
    return v0 / g, 0.5 * v0 * v0 / g


def _terminal(g, kappa, beta):
    """(s₊, s₋, r) of the descent ṡ = κ (s₊ - s)(s + s₋), r = √(β² + 4κg)."""
    r = math.sqrt(beta * beta + 4.0 * kappa * g)
    s_plus = 2.0 * g / (beta + r)
    return s_plus, (s_plus + beta / kappa) if kappa > 0.0 else math.inf, r


def _fall(t, s0, g, kappa, beta):
    """Fall (m) and downward speed (m/s) a time t after moving down at speed s0 >= 0."""
    t, s0 = np.asarray(t, dtype=float), np.asarray(s0, dtype=float)
    if kappa > 0.0:
        s_plus, s_minus, r = _terminal(g, kappa, beta)
        f = np.exp(-r * t)
        em = -np.expm1(-r * t)                         # 1 - e^(-rt)
        den = (s_plus - s0) * f + (s0 + s_minus)
        speed = s0 + (s0 + s_minus) * (s_plus - s0) * em / den
        fall = s_plus * t - np.log1p((s_plus - s0) * em / den) / kappa
        return fall, speed
    if beta > 0.0:
        em = -np.expm1(-beta * t)
        s_plus = g / beta
        return s_plus * t - (s_plus - s0) * em / beta, s0 + (s_plus - s0) * em
    return s0 * t + 0.5 * g * t * t, s0 + g * t


def fall_time(distance, s0, g, kappa, beta):
    """(time, arrival speed) of a fall through ``distance`` >= 0 (m) from downward speed s0."""
    d, s0 = np.asarray(distance, dtype=float), np.asarray(s0, dtype=float)
    if beta == 0.0:
        if kappa > 0.0:
            vt = math.sqrt(g / kappa)
            em = -np.expm1(-2.0 * kappa * d)                   # 1 - e^(-2κD)
            s1 = np.sqrt(s0 * s0 + (vt * vt - s0 * s0) * em)
            with np.errstate(invalid='ignore'):                # 0/0 at D = s0 = 0: no gain
                gain = np.where(em > 0.0, (vt - s0) * (vt + s0) * em / (s1 + s0), 0.0)
            t = (d + np.log1p(gain / (vt + s0)) / kappa) / vt
            return t, s1
        s1 = np.sqrt(s0 * s0 + 2.0 * g * d)
        return 2.0 * d / (s0 + s1), s1                  # = (s1 - s0)/g without cancellation
    # linear term: invert the closed-form fall on a growing bracket (module doc)
    ts, ss = np.empty(d.shape), np.empty(d.shape)
    for i, (di, si) in enumerate(zip(d.ravel(), np.broadcast_to(s0, d.shape).ravel())):
        ts.flat[i] = _fall_root(float(di), float(si), g, kappa, beta)
        ss.flat[i] = float(_fall(ts.flat[i], si, g, kappa, beta)[1])
    return (ts, ss) if d.ndim else (float(ts), float(ss))


def _fall_root(d, s0, g, kappa, beta):
    if d <= 0.0:
        return 0.0
    hi = 2.0 * d / (s0 + math.sqrt(s0 * s0 + 2.0 * g * d))   # vacuum time: a lower bound
    lo = 0.0
    while float(_fall(hi, s0, g, kappa, beta)[0]) < d:
        lo, hi = hi, 2.0 * hi
    from scipy.optimize import brentq   # only a linear drag term (β > 0) has no closed form
    return brentq(lambda t: float(_fall(t, s0, g, kappa, beta)[0]) - d, lo, hi,
                  xtol=1e-300, rtol=1e-15, maxiter=200)


# -- one flight ------------------------------------------------------------------------------
@dataclass(frozen=True)
class FlightPath:
    """A vertical flight under gravity and air drag, in closed form (see the module doc).

    Attributes
    ----------
    height : float
        The start height y0, m (up positive).
    velocity : float
        The start velocity, m/s, up positive.
    gravity : float
        Gravity g, m/s², > 0.
    kappa : float
        Quadratic drag rate κ = c / m, 1/m, >= 0 (default 0: no quadratic drag).
    beta : float
        Linear drag rate β = b / m, 1/s, >= 0, below 2 √(κ g) (default 0).
    surface : float, optional
        Keyword only, not stored: the plate's surface at the start, m (default 0, the fixed
        plate); ``height`` below it starts inside the plate and is refused.  A moving plate's
        flight, planned relative to the plate, passes ``-math.inf``.

    Raises
    ------
    InputError
        Keyed ``height`` (below ``surface``: inside the plate), ``gravity``, ``kappa`` or
        ``beta``: out of range.
    ValueError
        Naming ``beta``: β >= 2 √(κ g).

    Examples
    --------
    >>> import contact_sim as cs
    >>> flight = cs.FlightPath(0.0, 3.0, 9.81)          # thrown up at 3 m/s, vacuum
    >>> print(f"apex {flight.apex_height:.4f} m at {flight.apex_time:.4f} s")
    apex 0.4587 m at 0.3058 s
    >>> path = cs.FlightPath.with_drag(0.0, 3.0, 9.81, 0.0027, cs.AirDrag(radius=0.02))
    >>> print(f"apex {path.apex_height:.4f} m with drag")
    apex 0.4331 m with drag
    """

    height: float
    velocity: float
    gravity: float
    kappa: float = 0.0
    beta: float = 0.0
    surface: InitVar[float] = 0.0

    def __post_init__(self, surface):
        if surface != -math.inf:
            surface = require_real('surface', surface)
            require_range('height', self.height, surface,
                          unit='m: a flight starts on or above the plate' if surface == 0.0
                          else 'm: a flight starts on or above the plate at %g m' % surface)
        for name, value in (('height', require_real('height', self.height)),
                            ('velocity', require_real('velocity', self.velocity)),
                            ('gravity', require_positive('gravity', self.gravity)),
                            ('kappa', require_nonnegative('kappa', self.kappa)),
                            ('beta', require_nonnegative('beta', self.beta))):
            object.__setattr__(self, name, value)
        if _linear_term_too_large(self.kappa, self.beta, self.gravity):
            raise ValueError(f'beta = {self.beta!r} is out of range: allowed beta < '
                             f'2 sqrt(kappa g) = {2.0 * math.sqrt(self.kappa * self.gravity):g}')

    @classmethod
    def with_drag(cls, height, velocity, gravity, mass, drag=None):
        """The flight of a sphere with an ``AirDrag``.

        Parameters
        ----------
        height : float
            The start height, m.
        velocity : float
            The start velocity, m/s, up positive.
        gravity : float
            Gravity g, m/s², > 0.
        mass : float
            The sphere's mass, kg, > 0.
        drag : AirDrag, optional
            The drag; ``None`` (default): vacuum.

        Returns
        -------
        FlightPath
            The flight with κ, β = ``drag.rates(mass, gravity)``.

        Examples
        --------
        >>> import contact_sim as cs
        >>> path = cs.FlightPath.with_drag(1.0, 0.0, 9.81, 0.0027, cs.AirDrag(radius=0.02))
        >>> print(f"{path.kappa:.4f}")
        0.1317
        """
        kappa, beta = drag.rates(mass, gravity) if drag is not None else (0.0, 0.0)
        return cls(height, velocity, gravity, kappa, beta)

    @property
    def apex_time(self):
        """Time (s) from the start to the highest point (0 if moving down at the start)."""
        if self.velocity <= 0.0:
            return 0.0
        return float(apex(self.velocity, self.gravity, self.kappa, self.beta)[0])

    @property
    def apex_height(self):
        """Highest height reached (m)."""
        if self.velocity <= 0.0:
            return self.height
        return self.height + float(apex(self.velocity, self.gravity, self.kappa, self.beta)[1])

    def state(self, t):
        """The height and velocity at a time after the start.

        Parameters
        ----------
        t : float or array_like of float
            Time after the start, s, >= 0.

        Returns
        -------
        tuple
            (height m, upward velocity m/s): floats for a scalar ``t``, else arrays.

        Examples
        --------
        >>> import contact_sim as cs
        >>> y, v = cs.FlightPath(0.0, 3.0, 9.81).state(0.1)
        >>> print(f"{y:.5f} m, {v:.3f} m/s")
        0.25095 m, 2.019 m/s
        """
        t = np.asarray(t, dtype=float)
        g, kappa, beta = self.gravity, self.kappa, self.beta
        if self.velocity > 0.0:
            t_a, rise_a = apex(self.velocity, g, kappa, beta)
            up = t <= t_a
            rise, v = _rise(np.where(up, t, t_a), self.velocity, g, kappa, beta)
            fall, s = _fall(np.where(up, 0.0, t - t_a), 0.0, g, kappa, beta)
            y = self.height + np.where(up, rise, rise_a - fall)
            v = np.where(up, v, -s)
        else:
            fall, s = _fall(t, -self.velocity, g, kappa, beta)
            y, v = self.height - fall, -s
        return (float(y), float(v)) if t.ndim == 0 else (y, v)

    def time_to_height(self, level=0.0):
        """The first time the sphere passes ``level`` on its way down.

        Closed form without a linear term, a bracketed root with one.

        Parameters
        ----------
        level : float, optional
            The height, m (default 0: the plate).

        Returns
        -------
        float
            The time after the start, s; ``inf`` if the apex is below ``level``.

        Examples
        --------
        >>> import contact_sim as cs
        >>> print(f"{cs.FlightPath(0.0, 3.0, 9.81).time_to_height():.4f} s")
        0.6116 s
        """
        g, kappa, beta = self.gravity, self.kappa, self.beta
        if self.velocity > 0.0:
            t_a, rise_a = (float(x) for x in apex(self.velocity, g, kappa, beta))
            top = self.height + rise_a
            if top < level:
                return math.inf
            return t_a + float(fall_time(top - level, 0.0, g, kappa, beta)[0])
        if self.height < level:
            return math.inf
        return float(fall_time(self.height - level, -self.velocity, g, kappa, beta)[0])

    def touch(self, level=0.0):
        """The time and speed of the next passage of ``level`` going down.

        Parameters
        ----------
        level : float, optional
            The height, m (default 0: the plate).

        Returns
        -------
        tuple of float
            (time s, downward speed m/s).

        Raises
        ------
        InputError
            Keyed ``level``: the flight never comes down through it (its apex is below it), or
            it is not a finite number.

        Examples
        --------
        >>> import contact_sim as cs
        >>> t, speed = cs.FlightPath(0.0, 3.0, 9.81).touch()
        >>> print(f"{t:.4f} s at {speed:.4f} m/s")
        0.6116 s at 3.0000 m/s
        """
        level = require_real('level', level)
        t = self.time_to_height(level)
        if not math.isfinite(t):
            raise InputError('level', level, '{n[level]} = {value} m is above the flight: its '
                             'apex is at %g m; allowed {n[level]} <= %g m'
                             % (self.apex_height, self.apex_height))
        return t, -self.state(t)[1]


def flight_to_plate(rebound_speed, gravity, kappa=0.0, beta=0.0):
    """(flight time s, arrival speed m/s) of a bounce leaving the plate (y = 0) upward at
    ``rebound_speed`` (m/s, array) and landing on it again: apex in closed form, then the fall."""
    u = np.asarray(rebound_speed, dtype=float)
    if beta == 0.0 and kappa > 0.0:
        # up: atan(w) vt/g, down: atanh(s1/vt) vt/g with s1 = u/√(1 + w²), w = u/vt, and
        # atanh(w/√(1 + w²)) = asinh(w)
        vt = math.sqrt(gravity / kappa)
        w = u / vt
        return (np.arctan(w) + np.arcsinh(w)) * vt / gravity, u / np.sqrt(1.0 + w * w)
    t_a, rise = apex(u, gravity, kappa, beta)
    t_f, s1 = fall_time(rise, 0.0, gravity, kappa, beta)
    return t_a + t_f, s1


def contact_drag_impulse_ratio(kappa, speed, contact_duration):
    """Relative size of the drag impulse neglected over one contact: c v² τc / (m v) = κ v τc
    (an upper bound: the speed only falls from v during the contact)."""
    return kappa * speed * contact_duration
