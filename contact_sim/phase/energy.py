"""The energy of a contact above its rest: the Lyapunov function that decides permanent contact.

Units: J; z in m (z > 0 penetration), ż in m/s, g in m/s², m in kg.
"""
import functools

import numpy as np


def potential(contact, mass, gravity, z):
    """Spring energy k z₊^(n+1)/(n+1) minus gravity's work m g z (J)."""
    n = contact.law.n
    return contact.stiffness * np.maximum(z, 0.0) ** (n + 1.0) / (n + 1.0) - mass * gravity * z


def potential_at(contact, mass, gravity, z):
    """``potential`` at one depth z (m), as a float (J): the same formula without the array
    overhead (the drop's once-a-bounce energy bound)."""
    k, n = contact.stiffness, contact.law.n
    return k * max(z, 0.0) ** (n + 1.0) / (n + 1.0) - mass * gravity * z


def energy_above_rest(contact, mass, gravity, z, zdot):
    """½ m ż² + potential(z) - potential(z0): a Lyapunov function of the contact (J).

    It never increases (the damper only dissipates, flight conserves it), so once it is below
    ``lift_off_energy`` the sphere can never leave the plate again.
    """
    z0 = contact.static_penetration(mass * gravity)
    return (0.5 * mass * zdot ** 2 + potential(contact, mass, gravity, z)
            - potential(contact, mass, gravity, z0))


def lift_off_energy(contact, mass, gravity, margin=0.5):
    """A lower bound (J) on the energy above rest of any state in which the force is zero.

    Zero force means z <= 0, or z > 0 on the curve λ ż|ż|^(q-1) = -k z^(n-p); the minimum over
    that curve is taken on a fine logarithmic grid and multiplied by ``margin`` for safety.
    (Remembered per argument set: a drop asks it once per contact phase.)
    """
    return _lift_off_energy_cached(contact, float(mass), float(gravity), float(margin))


def _lift_off_energy(contact, mass, gravity, margin):
    law = contact.law
    z0 = contact.static_penetration(mass * gravity)
    candidates = [energy_above_rest(contact, mass, gravity, 0.0, 0.0)]
    if contact.damping > 0.0:
        z = z0 * np.logspace(-8.0, 2.0, 2001)
        speed = (contact.stiffness * z ** (law.n - law.p) / contact.damping) ** (1.0 / law.q)
        candidates.append(float(np.min(energy_above_rest(contact, mass, gravity, z, speed))))
    return margin * min(candidates)


_lift_off_energy_cached = functools.lru_cache(maxsize=256)(_lift_off_energy)
