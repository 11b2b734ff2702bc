"""A free Drake body's terms at a point, from the plant's state vector alone, for
``contact_sim.coupling.drake.CoupledContacts``: a floating base with a quaternion, no body
outboard of it, its centre of mass at its origin.  Its pose and velocities are read from the
state (quaternion and position; angular then translational velocity, in the world), its mass
and rotational inertia once (constant in its frame), and the point's velocity, free
acceleration (gravity and the gyroscopic ω × I ω) and 3x3 inverse mass follow in plain floats
(numpy costs more on 3-vectors).  ``test/coupling/test_drake.py`` holds them to the plant
context's to 1e-12.  Units: SI.
"""
import numpy as np

WORLD = False      # a pair's side that is the world (falsy: no free body)


class FreeBody:
    """A free body's constants: where its state sits in the plant's state vector, its mass (kg),
    rotational inertia about its origin (kg m², body frame) and whether gravity acts on it."""

    __slots__ = ('q', 'v', 'inverse_mass', 'inertia', 'inverse_inertia', 'isotropic', 'falls')

    def __init__(self, body, v, mass, inertia, falls):
        self.q, self.v = body.floating_positions_start(), v
        self.inverse_mass = 1.0 / mass
        self.inertia, self.inverse_inertia = inertia, np.linalg.inv(inertia)
        # a uniform sphere's: its inverse is a number, the same in every frame
        self.isotropic = (float(self.inverse_inertia[0, 0]) if np.all(
            self.inverse_inertia == self.inverse_inertia[0, 0] * np.eye(3)) else None)
        self.falls = bool(falls)

    def rotation(self, x):
        """Its rotation matrix (body to world) from its quaternion (w, x, y, z) in the state
        ``x``, normalized as Drake's ``RotationMatrix(Quaternion)``."""
        w, i, j, k = x[self.q:self.q + 4]
        s = 2.0 / (w * w + i * i + j * j + k * k)
        return np.array(((1.0 - s * (j * j + k * k), s * (i * j - k * w), s * (i * k + j * w)),
                         (s * (i * j + k * w), 1.0 - s * (i * i + k * k), s * (j * k - i * w)),
                         (s * (i * k - j * w), s * (j * k + i * w), 1.0 - s * (i * i + j * j))))

    def terms(self, x, arm, gravity):
        """The velocity (m/s), the free acceleration (``gravity``, m/s², if it acts on the body,
        and the gyroscopic ω × I ω) and the 3x3 inverse mass 1/m − [r]× I⁻¹ [r]× (1/kg) of its
        point at ``arm`` (m, world, from its origin), from the state ``x`` (a list)."""
        w0, w1, w2, v0, v1, v2 = x[self.v:self.v + 6]
        a0, a1, a2 = arm
        velocity = [v0 + w1 * a2 - w2 * a1, v1 + w2 * a0 - w0 * a2, v2 + w0 * a1 - w1 * a0]
        if not self.falls:
            gravity = [0.0, 0.0, 0.0]
        c = self.isotropic
        if c is not None:           # 1/m + c (|r|² − r rᵀ); ω × I ω = 0
            d = self.inverse_mass + c * (a0 * a0 + a1 * a1 + a2 * a2)
            ca0, ca1, ca2 = c * a0, c * a1, c * a2
            return velocity, gravity, [[d - ca0 * a0, -ca0 * a1, -ca0 * a2],
                                            [-ca1 * a0, d - ca1 * a1, -ca1 * a2],
                                            [-ca2 * a0, -ca2 * a1, d - ca2 * a2]]
        rotation, cross, omega = self.rotation(x), skew(arm), np.array((w0, w1, w2))
        inverse_inertia = rotation @ self.inverse_inertia @ rotation.T
        alpha = -inverse_inertia @ (skew(omega) @ (rotation @ (self.inertia @ (rotation.T
                                                                                @ omega))))
        inverse = self.inverse_mass * np.eye(3) - cross @ inverse_inertia @ cross
        return velocity, (gravity - cross @ alpha).tolist(), inverse.tolist()


def free_terms(sides, x, point, origins, gravity):
    """A pair's terms (as ``CoupledContacts._terms``) from the state ``x`` and the plant's
    ``gravity`` vector alone: each side is a ``FreeBody`` (its origin, m, world, in ``origins``)
    or the world."""
    sphere, other = sides
    velocity, acceleration, inverse = sphere.terms(
        x, [p - c for p, c in zip(point, origins[0])], gravity)
    if other is not WORLD:
        v, a, w = other.terms(x, [p - c for p, c in zip(point, origins[1])], gravity)
        velocity = [p - q for p, q in zip(velocity, v)]
        acceleration = [p - q for p, q in zip(acceleration, a)]
        inverse = [[p + q for p, q in zip(r, s)] for r, s in zip(inverse, w)]
    return velocity, acceleration, inverse


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def skew(u):
    """The matrix of u × (plain arithmetic: numpy's cross costs more)."""
    x, y, z = (float(c) for c in u)
    return np.array(((0.0, -z, y), (z, 0.0, -x), (-y, x, 0.0)))
