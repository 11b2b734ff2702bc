"""The coupling in PyBullet: ``CoupledContacts(client, pairs).step()`` in place of
``stepSimulation``.

Each pair names two bodies by their unique ids, one of them with a sphere collision shape on its
base, the other a plane, box, mesh or sphere (a static body, mass 0, or a free one).  Before every
``stepSimulation``:

* the gap along the normal and the nearest points from ``getClosestPoints`` (the normal is
  Bullet's ``contactNormalOnB``, from the other body to the sphere);
* the contact point's relative velocity from ``getBaseVelocity`` and the bases' mass and inertia
  (``getDynamicsInfo``): the inverse effective mass along the normal, n·W·n with
  W = Σ (1/m E - [r]× I⁻¹ [r]×) over the two bases, and the rest of the system's normal
  acceleration, gravity on each base (forces the user applies are not seen: PyBullet clears
  them each step; the next step takes their effect in as the host's divergence);
* ``contact_sim.coupling.NormalCoupling`` gives the step's normal impulse, ``friction_impulse``
  its tangential one, and ``applyExternalForce`` applies impulse / dt at the contact point
  (Bullet clears it after the step).

PyBullet steps velocities, then positions with the new velocities (semi-implicit Euler), as the
coupling assumes.  Its default linear and angular damping (0.04) change velocities outside the
coupling: set them to 0 (``changeDynamics``) for the exact figures.  The pair's own collision is
switched off (``setCollisionFilterPair``).  Articulated links are not coupled here: bases only
(a moving body with links is refused; a static one may be the other side, its base only).  The
sphere's centre is its collision frame's, which may sit off the base's centre of mass.  Units: SI.
"""

import numpy as np
import pybullet

from contact_sim.coupling.core import NormalCoupling
from contact_sim.coupling.rows import (pair_rows, refuse_repeated, refuse_stack,
                                       refuse_tunnel, tangential_impulse)
from contact_sim.model import require_contact
from contact_sim.validation import InputError, require_nonnegative, require_positive

REACH = 0.05


class _Base:
    """A body's base: its id, mass and inverse inertia in its local inertial frame."""

    def __init__(self, client, body):
        info = pybullet.getDynamicsInfo(body, -1, physicsClientId=client)
        self.body, self.mass = body, float(info[0])
        inertia = np.asarray(info[2], dtype=float)
        self.inverse_mass = 1.0 / self.mass if self.mass > 0.0 else 0.0
        self.inverse_inertia = np.where(inertia > 0.0, 1.0 / np.where(inertia > 0.0, inertia, 1.0),
                                        0.0) if self.mass > 0.0 else np.zeros(3)
        self.local_orientation = info[4]

    def response(self, client, point):
        """(W 3x3 at ``point`` in 1/kg, the point's velocity m/s) of this base."""
        if self.mass == 0.0:
            return np.zeros((3, 3)), np.zeros(3)
        pos, orn = pybullet.getBasePositionAndOrientation(self.body, physicsClientId=client)
        lin, ang = pybullet.getBaseVelocity(self.body, physicsClientId=client)
        # the centre of mass and the inertia's axes in the world
        com_orn = pybullet.multiplyTransforms(pos, orn, (0.0, 0.0, 0.0),
                                              self.local_orientation)[1]
        rot = np.array(pybullet.getMatrixFromQuaternion(com_orn)).reshape(3, 3)
        com = np.asarray(pos)       # the base frame is the inertial frame (PyBullet's bases)
        r = np.asarray(point) - com
        inverse_inertia = rot @ np.diag(self.inverse_inertia) @ rot.T
        self._world = (com, inverse_inertia)
        skew = _skew(r)
        w = self.inverse_mass * np.eye(3) - skew @ inverse_inertia @ skew
        wx, wy, wz = ang            # ω × r by hand: numpy's cross costs tens of µs a call
        velocity = np.array([lin[0] + wy * r[2] - wz * r[1], lin[1] + wz * r[0] - wx * r[2],
                             lin[2] + wx * r[1] - wy * r[0]])
        return w, velocity

    def cross(self, first, second):
        """The velocity at ``first`` per unit impulse at ``second`` (3x3, 1/kg), at the pose of
        the last ``response``."""
        com, inverse_inertia = self._world
        return (self.inverse_mass * np.eye(3)
                - _skew(np.asarray(first) - com) @ inverse_inertia @ _skew(np.asarray(second) - com))


def _skew(r):
    """[r]×: the matrix of r × (m)."""
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


class CoupledContacts:
    """PyBullet stepped with the package's exact contacts between body pairs.

    Parameters
    ----------
    client : int
        The physics client (``pybullet.connect``).
    pairs : sequence of (int, int, Contact)
        (body, body, contact): one of the two with a sphere as its base's collision shape.
    friction : float, optional
        Coulomb's μ of every pair, >= 0 (default 0).
    reach : float, optional
        Pairs farther apart than this (m) and carrying no contact state are not looked at
        further; > 0 (default ``REACH``).

    Raises
    ------
    InputError
        Keyed ``pairs`` (a body id that is not a body, no sphere in a pair, two bodies without
        mass, a moving body with links, one body twice, a pair named twice), ``friction`` or
        ``reach``; at ``step``, keyed ``pairs`` when two pairs push at once on a body along
        lines that move each other's gap (a stack), and ``numSubSteps`` > 1.

    Examples
    --------
    >>> import pybullet
    >>> import contact_sim as cs
    >>> from contact_sim.coupling.pybullet import CoupledContacts
    >>> client = pybullet.connect(pybullet.DIRECT)
    >>> pybullet.setGravity(0, 0, -9.81, physicsClientId=client)
    >>> pybullet.setTimeStep(1e-3, physicsClientId=client)
    >>> floor = pybullet.createMultiBody(0, pybullet.createCollisionShape(
    ...     pybullet.GEOM_PLANE, physicsClientId=client), physicsClientId=client)
    >>> ball = pybullet.createMultiBody(0.0669, pybullet.createCollisionShape(
    ...     pybullet.GEOM_SPHERE, radius=0.0127, physicsClientId=client),
    ...     basePosition=(0, 0, 0.1), physicsClientId=client)
    >>> pybullet.changeDynamics(ball, -1, linearDamping=0, angularDamping=0,
    ...                         physicsClientId=client)
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> coupled = CoupledContacts(client, [(ball, floor, contact)])
    >>> for _ in range(300):
    ...     coupled.step()
    >>> print(f"e = {coupled.impacts[0].restitution:.3f}")
    e = 0.726
    >>> pybullet.disconnect(client)
    """

    def __init__(self, client, pairs, friction=0.0, reach=REACH):
        self.client = client
        self.friction = require_nonnegative('friction', friction)
        self.reach = require_positive('reach', reach)
        rows = pair_rows(pairs, '(body, body, Contact)')
        self.pairs = [self._pair(row, i) for i, row in enumerate(rows)]
        refuse_repeated([frozenset((p[0].body, p[1].body)) for p in self.pairs], rows)
        self._time = 0.0
        self._far = set()           # the pairs out of reach at the last step

    def _pair(self, row, index):
        client = self.client
        if len(row) != 3:
            raise InputError('pairs', row, '{n[pairs]}[%d] = {value}: allowed a (body, body, '
                             'Contact) triple' % index)
        count = pybullet.getNumBodies(physicsClientId=client)
        known = {pybullet.getBodyUniqueId(i, physicsClientId=client) for i in range(count)}
        for body in row[:2]:
            if isinstance(body, bool) or not isinstance(body, (int, np.integer)) \
                    or int(body) not in known:
                raise InputError('pairs', body, '{n[pairs]}[%d] names body {value}, which is no '
                                 'body of the client: allowed the ids of its bodies' % index)
        contact = require_contact(row[2], 'pairs')
        if int(row[0]) == int(row[1]):
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value} names the same body '
                             'twice: allowed two bodies' % index)
        radii = [_sphere_radius(client, int(b)) for b in row[:2]]
        if radii[0] is None and radii[1] is None:
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value} has no body whose base '
                             'is a sphere: allowed a sphere against a plane, box, mesh or sphere'
                             % index)
        sphere, other = (0, 1) if radii[0] is not None else (1, 0)
        bases = [_Base(client, int(row[sphere])), _Base(client, int(row[other]))]
        if bases[0].mass == 0.0 and bases[1].mass == 0.0:
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value}: both bodies have mass '
                             '0 (static, no degree of freedom): allowed a pair that can move'
                             % index)
        for base in bases:
            if base.mass > 0.0 and pybullet.getNumJoints(base.body, physicsClientId=client):
                raise InputError('pairs', base.body, '{n[pairs]}[%d]: body {value} moves and has '
                                 'links (its base alone is not its response to a push): allowed '
                                 'bodies without links, or a static base (mass 0)' % index)
        pybullet.setCollisionFilterPair(int(row[0]), int(row[1]), -1, -1, 0,
                                        physicsClientId=client)
        return bases[0], bases[1], radii[sphere], NormalCoupling(contact), index

    @property
    def impacts(self):
        """Every impact of every pair so far (``CoupledImpact``), in time order."""
        return sorted((i for p in self.pairs for i in p[3].impacts), key=lambda i: i.time)

    @property
    def time(self):
        """The time (s) the steps have reached (counted here: PyBullet keeps none)."""
        return self._time

    def step(self):
        """One ``stepSimulation`` with the coupled contacts applied over it."""
        client = self.client
        params = pybullet.getPhysicsEngineParameters(physicsClientId=client)
        dt = params['fixedTimeStep']
        if params['numSubSteps'] > 1:
            raise InputError('numSubSteps', params['numSubSteps'], '{n[numSubSteps]} = {value}: '
                             'allowed 0 or 1 (the coupling gives one impulse a step)')
        gravity = np.array([params['gravityAccelerationX'], params['gravityAccelerationY'],
                            params['gravityAccelerationZ']])
        pushing = [push for push in (self._couple(pair, dt, gravity) for pair in self.pairs)
                   if push is not None]
        if len(pushing) > 1:
            _refuse_coupled(pushing)
        for base, force, point in (f for push in pushing for f in push[3]):
            pybullet.applyExternalForce(base.body, -1, force.tolist(), point.tolist(),
                                        pybullet.WORLD_FRAME, physicsClientId=client)
        pybullet.stepSimulation(physicsClientId=client)
        self._time += dt

    def _couple(self, pair, dt, gravity):
        client = self.client
        sphere, other, (radius, offset), coupling, index = pair
        points = pybullet.getClosestPoints(sphere.body, other.body, self.reach, -1, -1,
                                           physicsClientId=client)
        if not points:     # out of reach (a state carried is dropped at the next call:
            self._far.add(index)    # the clock moved on)
            return None
        nearest = min(points, key=lambda p: p[8])
        flipped = nearest[1] != sphere.body     # Bullet's A is the sphere unless it swapped
        normal = np.asarray(nearest[7], dtype=float) * (-1.0 if flipped else 1.0)
        gap = float(nearest[8])
        if index in self._far and gap < 0.0:
            refuse_tunnel(index, gap, self.reach)
        self._far.discard(index)
        pos, orn = pybullet.getBasePositionAndOrientation(sphere.body, physicsClientId=client)
        centre = np.asarray(pos) + (np.array(pybullet.getMatrixFromQuaternion(orn)).reshape(
            3, 3) @ offset if offset is not None else 0.0)   # the sphere's own centre
        point = centre - radius * normal
        w_s, v_s = sphere.response(client, point)
        w_o, v_o = other.response(client, point)
        inverse = w_s + w_o
        velocity = v_s - v_o
        acceleration = gravity * ((sphere.mass > 0.0) - (other.mass > 0.0))
        w_n = float(normal @ inverse @ normal)
        step = coupling.step(self._time, gap, float(normal @ velocity), 1.0 / w_n,
                             float(normal @ acceleration), dt)
        if step.impulse == 0.0:
            return None
        impulse = step.impulse * normal
        if self.friction > 0.0:     # Coulomb's, from the velocity without friction
            impulse = impulse + tangential_impulse(
                step.impulse, velocity + dt * acceleration + inverse @ impulse, normal, inverse,
                self.friction)
        force = impulse / dt
        return (index, normal, w_n, [(base, sign * force, point) for base, sign
                                     in ((sphere, 1.0), (other, -1.0)) if base.mass > 0.0])


def _sphere_radius(client, body):
    """(The radius (m) of the body's base sphere, its centre in the base's frame (m) or ``None``
    at the origin), or ``None``."""
    shapes = pybullet.getCollisionShapeData(body, -1, physicsClientId=client)
    if len(shapes) == 1 and shapes[0][2] == pybullet.GEOM_SPHERE:
        offset = np.asarray(shapes[0][5], dtype=float)
        return float(shapes[0][3][0]), (offset if np.any(offset) else None)
    return None


def _refuse_coupled(pushing):
    """Refuse two pairs pushing in one step on a common body along lines that move each
    other's gap: each is integrated alone, and together they would pump energy in (a stack)."""
    for k, (first, n_first, w_first, on_first) in enumerate(pushing):
        for second, n_second, w_second, on_second in pushing[k + 1:]:
            cross = 0.0
            for base, _, p_first in on_first:
                for other, _, p_second in on_second:
                    if other is base or other.body == base.body:
                        cross += float(n_first @ base.cross(p_first, p_second) @ n_second)
            refuse_stack(first, second, cross, w_first, w_second)


def coupled_restitution(contact, radius, mass, speeds, timestep):
    """The e(v) the coupling gives in PyBullet: a free sphere thrown at a plane, gravity off, one
    throw a speed (``contact-sim audit pybullet ... --coupled``).

    Parameters
    ----------
    contact : Contact
        The contact coupled in.
    radius, mass : float
        The sphere's radius (m) and mass (kg), > 0.
    speeds : array_like of float
        Impact speeds, m/s, > 0.
    timestep : float
        PyBullet's step, s, > 0.

    Returns
    -------
    numpy.ndarray
        e at each speed, read from PyBullet's velocity a whole step after the impact.

    Examples
    --------
    >>> import contact_sim as cs
    >>> from contact_sim.coupling.pybullet import coupled_restitution
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> e = coupled_restitution(contact, 0.0127, 0.0674, [0.1, 1.0], 1.0 / 240.0)
    >>> print(f"{e[0]:.4f} {e[1]:.4f}")
    0.8220 0.7381
    """
    radius, mass = require_positive('radius', radius), require_positive('mass', mass)
    timestep = require_positive('timestep', timestep)
    out = []
    client = pybullet.connect(pybullet.DIRECT)
    try:
        for speed in np.atleast_1d(np.asarray(speeds, dtype=float)).tolist():
            speed = require_positive('speeds', speed)
            pybullet.resetSimulation(physicsClientId=client)
            pybullet.setGravity(0, 0, 0, physicsClientId=client)
            pybullet.setTimeStep(timestep, physicsClientId=client)
            floor = pybullet.createMultiBody(0, pybullet.createCollisionShape(
                pybullet.GEOM_PLANE, physicsClientId=client), physicsClientId=client)
            ball = pybullet.createMultiBody(mass, pybullet.createCollisionShape(
                pybullet.GEOM_SPHERE, radius=radius, physicsClientId=client),
                basePosition=(0.0, 0.0, radius + 3.5 * speed * timestep), physicsClientId=client)
            pybullet.changeDynamics(ball, -1, linearDamping=0, angularDamping=0,
                                    physicsClientId=client)
            pybullet.resetBaseVelocity(ball, (0.0, 0.0, -speed), physicsClientId=client)
            coupled = CoupledContacts(client, [(ball, floor, contact)])
            for _ in range(1_000_000):
                coupled.step()
                if coupled.impacts:
                    break
            coupled.step()      # a whole step of flight: PyBullet's velocity is the exact one
            out.append(pybullet.getBaseVelocity(ball, physicsClientId=client)[0][2] / speed)
    finally:
        pybullet.disconnect(client)
    return np.array(out)
