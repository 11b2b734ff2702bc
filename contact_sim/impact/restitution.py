"""Coefficient of restitution, fast: exact reductions instead of repeated integration.

Without gravity, an impact at speed v obeys m z̈ = -k zⁿ - λ zᵖ ż|ż|^(q-1), z(0) = 0, ż(0) = v.
With Z = (m v² / k)^(1/(n+1)) (the depth at which the spring would hold all the kinetic energy),
T = Z / v, x = z / Z and τ = t / T it becomes

    x'' = -xⁿ - ζ xᵖ x'|x'|^(q-1),  x(0) = 0, x'(0) = 1,
    ζ = λ Z^(p+1) v^(q-2) / m = λ m^((p+1)/(n+1) - 1) v^(2(p+1)/(n+1) + q - 2) k^(-(p+1)/(n+1)),

so the restitution e, the dimensionless contact time τc, peak force F̂ = F / (k Zⁿ) and depth
x̂ = z / Z depend on the single group ζ.  For q = 1: Azad-Featherstone ζ = λ v^(1/5) /
(m^(2/5) k^(3/5)), Hunt-Crossley ζ = λ v / k, Lee-Wang ζ = λ v^(3/5) / (m^(1/5) k^(4/5)),
linear ζ = λ / √(m k) (velocity independent).  Two parameter sets with the same ζ give the same e.

* Hunt-Crossley has the first integral v/ζ - ln(1 + ζ v)/ζ² + (2/5) x^(5/2) = const, so
  u = 1 - ζ e solves u - ln u = 1 + ζ - ln(1 + ζ): u = -W₀(-exp(-1 - ζ + ln(1 + ζ)))
  (Lambert W), polished by Newton's method on the well-conditioned form.
* The clamped linear law separates when x + ζ x' = 0, which gives e = exp(-ζ τc / 2) with
  τc = atan2(ζ ω, ζ²/2 - 1) / ω, ω = √(1 - ζ²/4), and past critical damping (ζ > 2)
  τc = ln(ζ²/2 - 1 + ζκ) / κ, κ = √(ζ²/4 - 1).
* Everything else comes from master curves tabulated by ``simulate_impact`` on a uniform grid in
  ln ζ (``scripts/build_master_curves.py``), interpolated by cubic splines.  Beyond the table e
  follows asymptotics joined to its ends (``RestitutionTails``: 1 - I ζ + c2 ζ² below,
  ζ^(-a) (A + B ζ^(-b)) above); the other quantities there come from the exact path.

Closed forms and curves are registered per law (``register_closed_form``, the table's law
names), never found by exponents: a custom law is integrated, with a warning the first time.
"""
import math
import warnings
from dataclasses import dataclass
from functools import lru_cache, cache
from importlib import resources

import numpy as np
from scipy.integrate import quad
from scipy.interpolate import CubicSpline
from scipy.special import beta, lambertw

from contact_sim.model import require_contact
from contact_sim.impact.simulate import simulate_impact
from contact_sim.model import HUNT_CROSSLEY, LINEAR, ContactLaw
from contact_sim.validation import InputError, require_positive

QUANTITIES = ('restitution', 'duration', 'peak_force', 'max_penetration')
ZETA_MAX = 1e8   # beyond this damping group (e < 1e-10) the exact integration is not attempted
TABLE_FILE = 'master_curves.npz'


# -- the dimensionless group --------------------------------------------------------------
def impact_scales(law, stiffness, mass, speed):
    """Z (m) and T (s) of an impact at ``speed``; works on numpy arrays."""
    length = (mass * np.asarray(speed, dtype=float) ** 2 / stiffness) ** (1.0 / (law.n + 1.0))
    return length, length / speed


def require_speeds(speed, name='speed'):
    """``speed`` as a float array of finite speeds > 0 (m/s), else ``InputError``."""
    v = np.asarray(speed, dtype=float)
    if v.size and not (np.all(np.isfinite(v)) and np.all(v > 0.0)):
        bad = float(v[~(np.isfinite(v) & (v > 0.0))].flat[0])
        raise InputError(name, bad, '{n[%s]} = {value} is out of range: allowed 0 < {n[%s]} < inf '
                         '(m/s)' % (name, name))
    return v


def damping_group_of(law, length, speed, damping, mass):
    """ζ = λ Z^(p+1) v^(q-2) / m at the impact length scale Z (m) and speed v (m/s): arrays or
    floats."""
    return damping * length ** (law.p + 1.0) * speed ** (law.q - 2.0) / mass


def checked_scales(law, stiffness, mass, speed, damping=0.0, name='speed'):
    """(Z, T, ζ) of impacts at ``speed`` (arrays), refused with ``InputError`` on ``name`` when
    Z or T is not a finite positive number or ζ exceeds ``ZETA_MAX``."""
    v = require_speeds(speed, name)
    with np.errstate(all='ignore'):
        length, time = impact_scales(law, stiffness, mass, v)
        zeta = damping_group_of(law, length, v, damping, mass)
    ok = (length > 0.0) & np.isfinite(length) & (time > 0.0) & np.isfinite(time) \
        & (zeta <= ZETA_MAX)
    if not np.all(ok):
        bad = float(np.broadcast_to(v, ok.shape)[~ok].flat[0])
        raise InputError(name, bad, '{n[%s]} = {value} is out of range for mass = %r kg and this '
                         'contact: allowed speeds whose impact scales Z, T are finite and whose '
                         'damping group is at most zeta = %g' % (name, float(mass), ZETA_MAX))
    return length, time, zeta


def damping_group(law, stiffness, mass, speed, damping):
    """ζ = λ Z^(p+1) v^(q-2) / m, the one group the restitution depends on (see module doc)."""
    v = require_speeds(speed)
    length, _ = impact_scales(law, stiffness, mass, v)
    return damping_group_of(law, length, v, damping, mass)


def damping_from_group(law, stiffness, mass, speed, zeta):
    """λ that gives the group ``zeta`` at ``speed``: the inverse of ``damping_group``."""
    length, _ = impact_scales(law, stiffness, mass, speed)
    return zeta * mass / (length ** (law.p + 1.0) * np.asarray(speed, dtype=float) ** (law.q - 2.0))


# -- closed forms -------------------------------------------------------------------------
def _minus_s_minus_log1p_minus_s(s):
    """-s - ln(1 - s) = s²/2 + s³/3 + ..., without cancellation for small s."""
    small = s < 1e-3
    t = np.where(small, s, 0.0)
    series = t * t * (1 / 2 + t * (1 / 3 + t * (1 / 4 + t * (1 / 5 + t / 6))))
    return np.where(small, series, -s - np.log1p(-np.where(small, 0.0, s)))


def hunt_crossley_restitution(zeta):
    """Exact e(ζ) of the Hunt-Crossley law (n = p = 3/2, q = 1), vectorised, ζ > 0."""
    zeta = np.asarray(zeta, dtype=float)
    tiny = zeta < 1e-6           # e = 1 - 2ζ/3 + 4ζ²/9 + O(ζ³): c = ζ²/2 underflows below 1e-154
    zt = np.where(tiny, zeta, 0.0)
    return np.where(tiny, 1.0 - zt * (2.0 / 3.0 - zt * 4.0 / 9.0),
                    _hunt_crossley_restitution(np.where(tiny, 1.0, zeta)))


def _hunt_crossley_restitution(zeta):
    small = zeta < 1e-3
    zs = np.where(small, zeta, 0.0)
    series = zs ** 2 / 2 - zs ** 3 / 3 + zs ** 4 / 4 - zs ** 5 / 5 + zs ** 6 / 6 - zs ** 7 / 7
    c = np.where(small, series, zeta - np.log1p(np.where(small, 1.0, zeta)))
    u = -lambertw(-np.exp(-1.0 - c), 0).real                # u = 1 - ζ e
    # Near the branch point (u -> 1, small ζ) W loses digits: there solve for s = 1 - u by
    # Newton on f(s) = -s - ln(1 - s) - c = s²/2 + s³/3 + ... - c, f'(s) = s / (1 - s), from
    # s = √(2c), which lies right of the root of this convex f, so the iteration is monotone.
    near = ~(u <= 0.5)                                       # NaN at the branch point too
    c_near = np.where(near, c, 0.125)
    s = np.where(near, np.minimum(np.sqrt(2.0 * c_near), 0.9), 0.5)
    for _ in range(6):
        s = s - (_minus_s_minus_log1p_minus_s(s) - c_near) * (1.0 - s) / s
    s = np.where(near, s, 1.0 - u)
    return s / zeta


def hunt_crossley_restitution_scalar(zeta):
    """``hunt_crossley_restitution`` for one float in plain Python (a few µs).

    Newton's method on a convex function from the side where it converges monotonically:
    in s = 1 - u from s = √(2c) when c < 1, in u from u = exp(-1 - c) otherwise.
    Below ζ = 1e-6 the series 1 - 2ζ/3 + 4ζ²/9 (error O(ζ³) < 1e-18).
    """
    if zeta < 1e-6:
        return 1.0 - zeta * (2.0 / 3.0 - zeta * 4.0 / 9.0)
    c = (zeta * zeta * (0.5 - zeta * (1 / 3 - zeta * (0.25 - zeta * (0.2 - zeta / 6)))))
    if zeta >= 1e-3:
        c = zeta - math.log1p(zeta)
    if c < 1.0:
        s = min(math.sqrt(2.0 * c), 0.95)
        for _ in range(60):
            f = (s * s * (0.5 + s * (1 / 3 + s * (0.25 + s * (0.2 + s / 6)))) if s < 1e-3
                 else -s - math.log1p(-s)) - c
            step = f * (1.0 - s) / s
            s -= step
            if abs(step) <= 1e-16 * s:
                break
        return s / zeta
    u = math.exp(-1.0 - c)
    if u == 0.0:                      # u underflows: e = (1 - u) / ζ = 1 / ζ to the last bit
        return 1.0 / zeta
    for _ in range(60):
        step = (u - math.log(u) - 1.0 - c) / (1.0 - 1.0 / u)
        u -= step
        if abs(step) <= 1e-16 * u:
            break
    return (1.0 - u) / zeta


def hunt_crossley_duration(zeta):
    """Exact contact duration τc of the Hunt-Crossley law at ζ > 0, by quadrature of its first
    integral (used to build the master curve where integrating the impact is ill-conditioned).

    With w = ζ x', the first integral reads w - ln(1 + w) = d(x), d = c (1 - (x/x̂)^(5/2)),
    c = ζ - ln(1 + ζ), x̂ = (c / (0.4 ζ²))^(2/5): w > 0 on the approach, -1 < w < 0 on the
    return.  The force x^(3/2) (1 + w) stays positive until x = 0, so
    τc = ζ ∫₀^x̂ (1/w_in - 1/w_out) dx, integrated in s with x = x̂ (1 - s²) (which removes the
    1/√ at x̂, and gives d = -c expm1(2.5 log1p(-s²)) without cancellation).
    """
    c = zeta - math.log1p(zeta) if zeta >= 1e-3 else \
        zeta * zeta * (0.5 - zeta * (1 / 3 - zeta * (0.25 - zeta / 5)))
    top = (c / (0.4 * zeta * zeta)) ** 0.4

    def branch(d, w):
        for _ in range(100):          # Newton on w - ln(1 + w) - d (convex in w)
            g = w - math.log1p(w) - d if abs(w) > 1e-4 else \
                w * w * (0.5 - w * (1 / 3 - w * (0.25 - w / 5))) - d
            step = g * (1.0 + w) / w
            w_new = w - step
            if w_new <= -1.0:
                w_new = 0.5 * (w - 1.0)
            if abs(w_new - w) <= 1e-15 * abs(w):
                return w_new
            w = w_new
        return w

    def integrand(s):
        if s == 0.0:
            s = 1e-300
        d = -c * math.expm1(2.5 * math.log1p(-s * s))
        w_in = branch(d, math.sqrt(2.0 * d) if d < 1.0 else d + math.log1p(d))
        if d < 0.5:
            w_out = branch(d, -math.sqrt(2.0 * d))
        else:                                  # in u = 1 + w, which may be tiny: Newton on
            u = math.exp(-1.0 - d)             # u - ln u - 1 - d from the left (monotone)
            for _ in range(100):
                if u == 0.0:
                    break
                step = (u - math.log(u) - 1.0 - d) / (1.0 - 1.0 / u)
                u -= step
                if abs(step) <= 1e-16 * u:
                    break
            w_out = u - 1.0
        return 2.0 * top * s * zeta * (1.0 / w_in - 1.0 / w_out)

    with warnings.catch_warnings():
        warnings.simplefilter('ignore')       # quad's round-off notice at the 1e-12 request
        value, _ = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=1e-12, limit=200)
    return value


def linear_restitution_scalar(zeta):
    """``linear_restitution_and_duration(ζ)[0]`` for one float in plain Python."""
    disc = 1.0 - zeta * zeta / 4.0
    if disc > 0.0:
        w = math.sqrt(disc)
        tau = math.atan2(zeta * w, zeta * zeta / 2.0 - 1.0) / w
    elif disc < 0.0:
        kappa = math.sqrt(-disc)
        tau = math.log(zeta * zeta / 2.0 - 1.0 + zeta * kappa) / kappa   # = atanh(ζκ/(ζ²/2-1))/κ
    else:
        tau = 2.0
    return math.exp(-zeta * tau / 2.0)


def linear_restitution_and_duration(zeta):
    """Exact (e, τc) of the clamped linear law for ζ = λ / √(m k) > 0; τc in units √(m/k)."""
    zeta = np.asarray(zeta, dtype=float)
    disc = 1.0 - zeta ** 2 / 4.0
    under = disc > 0.0
    over = disc < 0.0
    w = np.sqrt(np.where(under, disc, 1.0))
    kappa = np.sqrt(np.where(over, -disc, 1.0))
    tau_under = np.arctan2(zeta * w, zeta ** 2 / 2.0 - 1.0) / w
    # atanh(ζκ / (ζ²/2 - 1)) = ln(ζ²/2 - 1 + ζκ), since (ζ²/2 - 1)² - (ζκ)² = 1
    tau_over = np.log(np.where(over, zeta ** 2 / 2.0 - 1.0 + zeta * kappa, 1.0)) / kappa
    tau = np.where(under, tau_under, np.where(over, tau_over, 2.0))
    return np.exp(-zeta * tau / 2.0), tau


# -- closed forms, registered per law -----------------------------------------------------
@dataclass(frozen=True)
class ClosedForm:
    """Exact dimensionless results of one law: ``vector`` maps a quantity to a function of an
    array of ζ > 0; ``scalar`` is e(ζ) for one float ζ > 0 in plain Python."""

    vector: dict
    scalar: object = None


CLOSED_FORMS = {}   # ContactLaw (its name and exponents) -> ClosedForm


def register_closed_form(law, vector, scalar=None):
    """Use the exact functions ``vector`` (quantity -> f(ζ array)) and ``scalar`` (e(ζ)) for
    ``law``, a ``ContactLaw``: keyed by the law itself, not by its exponents."""
    CLOSED_FORMS[law] = ClosedForm(dict(vector), scalar)


register_closed_form(HUNT_CROSSLEY, {'restitution': hunt_crossley_restitution},
                     hunt_crossley_restitution_scalar)
register_closed_form(LINEAR, {'restitution': lambda z: linear_restitution_and_duration(z)[0],
                              'duration': lambda z: linear_restitution_and_duration(z)[1]},
                     linear_restitution_scalar)


# -- master curves ------------------------------------------------------------------------
@dataclass(frozen=True)
class MasterCurve:
    """Splines of the four dimensionless results on a uniform grid s = ln ζ ∈ [s0, s0 + h N]."""

    law_key: tuple
    s0: float
    h: float
    coefficients: dict  # quantity -> (4, N) cubic coefficients, highest power first

    @property
    def zeta_range(self):
        n = next(iter(self.coefficients.values())).shape[1]
        return math.exp(self.s0), math.exp(self.s0 + self.h * n)

    def evaluate(self, quantity, zeta):
        """Interpolated value at ``zeta`` (array) and the mask of points inside the table."""
        c = self.coefficients[quantity]
        s = np.log(np.asarray(zeta, dtype=float))
        x = (s - self.s0) / self.h
        n = c.shape[1]
        inside = (x >= 0.0) & (x <= n)
        i = np.clip(np.floor(x).astype(int), 0, n - 1)
        ds = (np.clip(x, 0.0, n) - i) * self.h
        value = ((c[0, i] * ds + c[1, i]) * ds + c[2, i]) * ds + c[3, i]
        return value, inside

    def evaluate_scalar(self, quantity, zeta):
        """The same for one float, in plain Python (no numpy overhead); ``None`` if outside."""
        x = (math.log(zeta) - self.s0) / self.h
        rows = self._rows(quantity)
        n = len(rows)
        if not 0.0 <= x <= n:
            return None
        i = min(int(x), n - 1)
        ds = (x - i) * self.h
        a, b, c, d = rows[i]
        return ((a * ds + b) * ds + c) * ds + d

    def _rows(self, quantity):
        cache = self.__dict__.setdefault('_row_cache', {})
        if quantity not in cache:
            cache[quantity] = [tuple(col) for col in self.coefficients[quantity].T.tolist()]
        return cache[quantity]


# -- asymptotics of e beyond the table (q = 1) ---------------------------------------------
def elastic_dissipation_integral(law):
    """I with e = 1 - I ζ + O(ζ²) as ζ -> 0 (any law).

    The energy lost is ζ ∫ xᵖ |x'|^(q+1) dτ along the elastic impact x'² = 1 - 2 x^(n+1)/(n+1);
    with w = 2 x^(n+1)/(n+1) this is a Beta function, and e² = 1 - 2 ζ I/1 gives
    I = 2/(n+1) ((n+1)/2)^((p+1)/(n+1)) B((p+1)/(n+1), q/2 + 1).  Hunt-Crossley: I = 2/3.
    """
    n, p, q = law.n, law.p, law.q
    a = (p + 1.0) / (n + 1.0)
    return 2.0 / (n + 1.0) * ((n + 1.0) / 2.0) ** a * float(beta(a, q / 2.0 + 1.0))


def elastic_limits(law):
    """τc, F̂ and x̂ of the undamped impact x'' = -xⁿ (ζ = 0): x̂ = ((n+1)/2)^(1/(n+1)),
    F̂ = x̂ⁿ and τc = 2 ∫ dx/x' = 2/(n+1) ((n+1)/2)^(1/(n+1)) B(1/(n+1), 1/2) (π for n = 1)."""
    n = law.n
    depth = ((n + 1.0) / 2.0) ** (1.0 / (n + 1.0))
    return {'duration': 2.0 / (n + 1.0) * depth * float(beta(1.0 / (n + 1.0), 0.5)),
            'peak_force': depth ** n, 'max_penetration': depth}


def heavy_damping_exponent(law):
    """a with e ∝ ζ^(-a) as ζ -> ∞, for q = 1: the damper stops the sphere within
    x_m ~ ζ^(-1/(p+1)) and the spring pushes it out on the creep x' = -x^(n-p)/ζ, so
    e ~ x_m^(n-p)/ζ: a = 1 + (n-p)/(p+1) (Hunt-Crossley 1, linear 2, Azad-Featherstone 5/3,
    Lee-Wang 5/4)."""
    return 1.0 + (law.n - law.p) / (law.p + 1.0)


@dataclass(frozen=True)
class RestitutionTails:
    """e outside a master curve's table [ζ0, ζ1], joined to the table's end values.

    Below ζ0: e = 1 - I ζ + c2 ζ², c2 from e(ζ0) (the next term is O(ζ³) < 1e-15); τc, F̂ and
    x̂ are their elastic values (``elastic_limits``) plus a slope in ζ from the table's start
    (``near_elastic``; within 1e-10 relative of the exact path, a test).
    Above ζ1: e = ζ^(-a) r with r = A + (r1 - A)(ζ/ζ1)^(-b), the leading power and one
    correction whose A and b come from r = e ζ^a at ζ1, ζ1/e and ζ1/e² of the table.
    """

    zeta0: float
    zeta1: float
    slope: float       # I
    curvature: float   # c2
    power: float       # a
    limit: float       # A
    r1: float
    decay: float       # b
    linear: dict = None   # quantity -> (elastic value, slope in ζ) for τc, F̂, x̂

    @classmethod
    def from_curve(cls, law, curve):
        z0, z1 = curve.zeta_range
        e0 = curve.evaluate_scalar('restitution', z0)
        slope = elastic_dissipation_integral(law)
        a = heavy_damping_exponent(law)
        r = [curve.evaluate_scalar('restitution', z1 * math.exp(-k)) * (z1 * math.exp(-k)) ** a
             for k in range(3)]
        ratio = (r[1] - r[0]) / (r[2] - r[1])
        decay = -math.log(ratio) if 0.0 < ratio < 1.0 else 1.0
        limit = r[0] - (r[1] - r[0]) / (math.exp(decay) - 1.0)
        linear = {}
        for quantity, v0 in elastic_limits(law).items():
            linear[quantity] = (v0, (curve.evaluate_scalar(quantity, z0) - v0) / z0)
        return cls(z0, z1, slope, (e0 - 1.0 + slope * z0) / z0 ** 2, a, limit, r[0], decay,
                   linear)

    def near_elastic(self, quantity, zeta):
        v0, slope = self.linear[quantity]
        return v0 + slope * zeta

    def small(self, zeta):
        return 1.0 - zeta * (self.slope - zeta * self.curvature)

    def large(self, zeta):
        return zeta ** -self.power * (self.limit + (self.r1 - self.limit)
                                      * (zeta / self.zeta1) ** -self.decay)


@cache
def restitution_tails(law):
    """The tails of ``law``'s master curve, or ``None`` (no curve, or q != 1)."""
    curve = master_curve(law)
    if curve is None or law.q != 1.0:
        return None
    return RestitutionTails.from_curve(law, curve)


_WARNED = set()


def _warn_integrating(law):
    if law.name not in _WARNED:
        _WARNED.add(law.name)
        warnings.warn(f'law {law.name!r} has no master curve or closed form here: its '
                      'restitution is integrated impact by impact (milliseconds each)',
                      RuntimeWarning, stacklevel=4)


@lru_cache(maxsize=1)
def _load_tables():
    path = resources.files('contact_sim') / 'data' / TABLE_FILE
    curves = {}
    with resources.as_file(path) as real_path, np.load(real_path) as data:
        for name in data['laws']:
            name = str(name)
            key = tuple(float(v) for v in data[f'{name}/key'])
            s = data[f'{name}/s']
            h = float(s[1] - s[0])
            coefficients = {q: CubicSpline(s, data[f'{name}/{q}']).c for q in QUANTITIES}
            curves[ContactLaw(name, *key)] = MasterCurve(key, float(s[0]), h, coefficients)
    return curves


def master_curve(law):
    """The shipped master curve of ``law`` (registered per law: its name and exponents), or
    ``None``: a custom law is integrated even where its exponents equal a named law's."""
    return _load_tables().get(law)


# -- the public fast path -----------------------------------------------------------------
def _exact_dimensionless(law, zeta):
    """(e, τc, F̂, x̂) of the unit problem, by ``simulate_impact`` (the slow path)."""
    from contact_sim.model import Contact
    r = simulate_impact(Contact(law, 1.0, float(zeta)), 1.0, 1.0)
    return {'restitution': r.restitution, 'duration': r.contact_duration,
            'peak_force': r.peak_force, 'max_penetration': r.max_penetration}


def dimensionless(quantity, law, zeta):
    """e, τc, F̂ or x̂ at the groups ``zeta`` (array, ζ >= 0) for ``law``: closed form, table or
    exact integration, in that order of preference."""
    zeta = np.asarray(zeta, dtype=float)
    closed = CLOSED_FORMS.get(law)
    out = np.full(zeta.shape, np.nan)
    todo = np.ones(zeta.shape, dtype=bool)
    positive = zeta > 0.0
    if quantity == 'restitution':      # no damping: perfectly elastic, exactly
        out = np.where(positive, out, 1.0)
        todo = positive
    if closed is not None and quantity in closed.vector:
        out = np.where(positive, closed.vector[quantity](np.where(positive, zeta, 1.0)), out)
        todo &= ~positive
    else:
        curve = master_curve(law)
        if curve is not None:
            value, inside = curve.evaluate(quantity, np.where(positive, zeta, 1.0))
            inside &= positive
            out = np.where(inside, value, out)
            todo &= ~inside
            tails = restitution_tails(law)
            if tails is not None and quantity != 'restitution':
                low = todo & positive & (zeta < tails.zeta0)
                out = np.where(low, tails.near_elastic(quantity, np.where(low, zeta, 0.0)), out)
                todo &= ~low
            elif tails is not None:
                low = todo & (zeta < tails.zeta0)
                high = todo & (zeta > tails.zeta1)
                out = np.where(low, tails.small(np.where(low, zeta, 0.0)), out)
                out = np.where(high, tails.large(np.where(high, zeta, tails.zeta1)), out)
                todo &= ~(low | high)
        elif np.any(todo):
            _warn_integrating(law)
    for z in np.unique(zeta[todo]):
        out[todo & (zeta == z)] = _exact_dimensionless(law, z)[quantity]
    return np.minimum(out, 1.0) if quantity == 'restitution' else out


def _dimensional(quantity, contact, mass, speeds):
    contact = require_contact(contact)
    law = contact.law
    mass = require_positive('mass', mass)
    scalar = np.ndim(speeds) == 0
    k = contact.stiffness
    length, time, zeta = checked_scales(law, k, mass, speeds, contact.damping)
    value = dimensionless(quantity, law, zeta)
    scale = {'restitution': 1.0, 'duration': time, 'peak_force': k * length ** law.n,
             'max_penetration': length}[quantity]
    result = value * scale
    return float(result) if scalar else result


def _scalar_restitution(contact, mass, speed):
    """One speed, fully in Python floats: the ≤ 20 µs path used by services."""
    contact = require_contact(contact)
    law = contact.law
    length = (mass * speed * speed / contact.stiffness) ** (1.0 / (law.n + 1.0))
    zeta = damping_group_of(law, length, speed, contact.damping, mass)
    if not (zeta <= ZETA_MAX and 0.0 < length < math.inf):
        return _dimensional('restitution', contact, mass, speed)   # raises, naming the speed
    closed = CLOSED_FORMS.get(law)
    if zeta > 0.0 and closed is not None and closed.scalar is not None:
        return closed.scalar(zeta)
    if zeta > 0.0:
        curve = master_curve(law)
        if curve is not None:
            value = curve.evaluate_scalar('restitution', zeta)
            if value is not None:
                return min(value, 1.0)
            tails = restitution_tails(law)
            if tails is not None:
                return tails.small(zeta) if zeta < tails.zeta0 else tails.large(zeta)
    return float(dimensionless('restitution', law, np.array(zeta)))


def restitution(contact, mass, speeds):
    """Coefficient of restitution of impacts at ``speeds`` (m/s, > 0) without gravity.

    ``mass`` is the (reduced) mass in kg.  Vectorised: a scalar gives a float, an array an
    array of the same shape.  Agrees with ``simulate_impact`` to 1e-8 or better.
    """
    if isinstance(speeds, (int, float)) and not isinstance(speeds, bool) \
            and math.isfinite(speeds) and speeds > 0.0 \
            and isinstance(mass, (int, float)) and 0.0 < mass < math.inf:
        return _scalar_restitution(contact, float(mass), float(speeds))
    return _dimensional('restitution', contact, mass, speeds)


def contact_duration(contact, mass, speeds):
    """Contact duration (s) of impacts at ``speeds`` (m/s), touch to lift-off, no gravity."""
    return _dimensional('duration', contact, mass, speeds)


def peak_force(contact, mass, speeds):
    """Peak contact force (N) of impacts at ``speeds`` (m/s), no gravity."""
    return _dimensional('peak_force', contact, mass, speeds)


def max_penetration(contact, mass, speeds):
    """Maximum penetration (m) of impacts at ``speeds`` (m/s), no gravity."""
    return _dimensional('max_penetration', contact, mass, speeds)
