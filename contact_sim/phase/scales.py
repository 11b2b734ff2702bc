"""The scales of one contact phase, the tolerances they make uniform, and its start.

Z is the penetration at which the spring would store the phase's kinetic energy (or the static
deflection under gravity, whichever is larger) and T = √(m Z^(1-n) / k), so that x = z / Z and
x' = dx/dτ (τ = t / T) are of order one and the tolerances mean the same at every speed (see
``phase``).
"""
import math
from dataclasses import dataclass

DEFAULT_RTOL = 1e-12
DEFAULT_ATOL = 1e-14
# The right-hand side in σ = √τ vanishes at σ = 0, which misleads an automatic first step; a
# contact lasts σ ≈ 1.8 in these units, so a phase starts at a step a few per cent of that.
FIRST_STEP = 0.05


@dataclass(frozen=True)
class PhaseScales:
    """Length Z (m), time T (s) and the dimensionless gravity ``gamma`` γ and damping ``zeta`` ζ
    of one phase."""

    length: float
    time: float
    gamma: float
    zeta: float


def scales_of(k, lam, mass, gravity, n, p, q, penetration, penetration_rate):
    """(Z m, T s, γ, ζ) of a phase starting at (z, ż) (m, m/s) of the law (n, p, q) with
    stiffness k and damping λ, mass (kg) and gravity (m/s²): the module docstring's scales on
    floats (Z <= 0 where there is no motion and no gravity, with T = γ = ζ = 0);
    ``phase_scales`` checks it.  Squares are products (libm's pow(x, 2) is not always the same
    double as x * x)."""
    z = max(penetration, 0.0)
    energy_speed_sq = (penetration_rate * penetration_rate
                       + 2.0 * k * z ** (n + 1.0) / ((n + 1.0) * mass))
    length = (mass * energy_speed_sq / k) ** (1.0 / (n + 1.0))
    if gravity > 0.0:
        length = max(length, (mass * gravity / k) ** (1.0 / n))
    if not length > 0.0:
        return length, 0.0, 0.0, 0.0
    time = math.sqrt(mass * length ** (1.0 - n) / k)
    return (length, time, gravity * (time * time) / length,
            lam * length ** (p + q - 1.0) * time ** (2.0 - q) / mass)


def phase_scales(contact, mass, gravity, penetration, penetration_rate):
    """Scales for a phase starting at (z, ż): see the module docstring (``scales_of``)."""
    law = contact.law
    length, time, gamma, zeta = scales_of(contact.stiffness, contact.damping, mass, gravity,
                                          law.n, law.p, law.q, penetration, penetration_rate)
    if not length > 0.0:
        raise ValueError('a contact phase needs motion or gravity: penetration_rate = 0, '
                         'penetration <= 0 and gravity = 0 give no contact')
    return PhaseScales(length, time, gamma, zeta)


def start_peak_force(contact, penetration, penetration_rate, force):
    """The largest force of a phase at its start.

    Parameters
    ----------
    contact : Contact
        The contact.
    penetration, penetration_rate : float
        z (m) and ż (m/s) at the start.
    force : float
        The force at (z, ż) in N, as the engine evaluates it.

    Returns
    -------
    float
        ``force``, or at the touch (z <= 0, ż > 0) of a law that damps at touch (p = 0) the
        limit λ ż^q (N) as z -> 0+ if that is larger: the force jumps to it at once.
    """
    law = contact.law
    return start_peak(law.p, contact.damping, law.q, penetration, penetration_rate, force)


def start_peak(p, lam, q, penetration, penetration_rate, force):
    """``start_peak_force`` of a law with exponents p, q and damping λ on floats: plain Python
    that numba compiles as it stands (``compiled_phase.start_phase`` calls it)."""
    if penetration <= 0.0 and p == 0.0 and penetration_rate > 0.0:   # the law damps at touch
        return max(force, lam * penetration_rate ** q)
    return force
