"""The dimensionless impact results beyond a master curve's table: asymptotics joined to its ends.

Below the table (ζ -> 0) e = 1 - I ζ + c2 ζ² and τc, F̂, x̂ leave their elastic values linearly;
above it (ζ -> ∞, q = 1) e = ζ^(-a) (A + B ζ^(-b)).  I, a and the elastic values are pure
functions of the law's exponents (Beta functions); the other constants come from the table.
"""
import math
from dataclasses import dataclass
from functools import cache

from scipy.special import beta


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
    curve = law.master_curve
    if curve is None or not law.linear_in_rate:
        return None
    return RestitutionTails.from_curve(law, curve)
