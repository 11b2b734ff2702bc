"""The coupling in PyBullet: ``CoupledContacts(client, pairs).step()`` in place of
``stepSimulation``.

Each pair names two bodies by their unique ids, one of them with a sphere collision shape on its
base, the other a plane, box, mesh or sphere (a static body, mass 0, or a free one).  Before every
``stepSimulation``:

* the gap along the normal and the nearest points from ``getClosestPoints`` (the normal is
  Bullet's ``contactNormalOnB``, from the other body to the sphere);
* the contact point's relative velocity from ``getBaseVelocity`` and the bases' mass and inertia
  (``getDynamicsInfo``, read once at construction; the base's pose is its inertial frame's): the
  inverse effective mass along the normal, n·W·n with W = Σ (1/m E - [r]× I⁻¹ [r]×) over the
  two bases, and the rest of the system's normal acceleration, gravity on each base (forces the
  user applies are not seen: PyBullet clears them each step; the next step takes their effect
  in as the host's divergence);
* ``contact_sim.coupling.NormalCoupling`` gives the step's normal impulse, ``friction_impulse``
  its tangential one, and ``applyExternalForce`` applies impulse / dt at the contact point
  (Bullet clears it after the step).

PyBullet steps velocities, then positions with the new velocities (semi-implicit Euler), as the
coupling assumes.  Its default linear and angular damping (0.04) change velocities outside the
coupling: set them to 0 (``changeDynamics``) for the exact figures.  The pair's own collision is
switched off (``setCollisionFilterPair``).  A side may name a link, ``(body, link)``, of a
fixed-base multibody with joints: its response comes from ``calculateJacobian``,
``calculateMassMatrix`` and ``calculateInverseDynamics`` (``contact_sim.coupling.pybullet_links``;
its joint motors must be off).  A moving body with links named by its id alone is refused (its
base alone is not its response; a static one may be the other side, its base only).  The
sphere's centre is its collision frame's, which may sit off the base's centre of mass.

Cost: a pair out of reach costs one ``getClosestPoints`` a step, beside the step's one
``getPhysicsEngineParameters``; a pair in reach one ``getBasePositionAndOrientation`` and one
``getBaseVelocity`` a moving base and one ``applyExternalForce`` a moving base pushed, its
arithmetic on plain floats (numpy only when the contact point slides or two pairs push).
Units: SI.
"""

import numpy as np
import pybullet

from contact_sim.coupling.core import NormalCoupling
from contact_sim.coupling.pybullet_links import _Link, check_link, couple_links, link_sides
from contact_sim.coupling.rows import (pair_rows, refuse_repeated, refuse_stack,
                                       refuse_tunnel, tangential_impulse)
from contact_sim.model import require_contact
from contact_sim.validation import InputError, require_nonnegative, require_positive

REACH = 0.05


class _Base:
    """A body's base: its id, mass and inverse inertia in its inertial frame, read once;
    ``read`` takes its pose and velocity of the step (plain floats: numpy costs more than the
    arithmetic on 3-vectors).  PyBullet's base pose is its inertial frame's (measured: the
    response to an impulse matches I⁻¹ turned by that orientation alone, to 1e-16)."""

    __slots__ = ('body', 'link', 'mass', 'inverse_mass', 'inverse_inertia', 'isotropic', 'position',
                 'orientation', 'linear', 'angular', '_rotation')

    def __init__(self, client, body):
        info = pybullet.getDynamicsInfo(body, -1, physicsClientId=client)
        self.body, self.link, self.mass = body, -1, float(info[0])
        self.inverse_mass = 1.0 / self.mass if self.mass > 0.0 else 0.0
        self.inverse_inertia = tuple(1.0 / float(i) if i > 0.0 and self.mass > 0.0 else 0.0
                                     for i in info[2])
        # a sphere's inverse inertia is the same in every frame: no rotation to take
        self.isotropic = self.inverse_inertia[0] == self.inverse_inertia[1] \
            == self.inverse_inertia[2]
        self.position, self.orientation = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
        self.linear = self.angular = (0.0, 0.0, 0.0)
        self._rotation = None

    def read(self, client):
        """Take this step's pose and velocity (one call each; a static base has none)."""
        self.position, self.orientation = pybullet.getBasePositionAndOrientation(
            self.body, physicsClientId=client)
        self.linear, self.angular = pybullet.getBaseVelocity(self.body, physicsClientId=client)
        self._rotation = None

    def rotation(self):
        """The inertia's axes in the world (rows of a 3x3 tuple) at the pose of the last
        ``read``, or ``None`` for an isotropic inertia."""
        if self.isotropic:
            return None
        if self._rotation is None:
            self._rotation = _rotation_matrix(self.orientation)
        return self._rotation

    def inverse_inertia_along(self, u):
        """u · I⁻¹ u (1/(kg m²) · u²), I⁻¹ in the world at the pose of the last ``read``."""
        d0, d1, d2 = self.inverse_inertia
        rot = self.rotation()
        if rot is None:
            return d0 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
        (a, b, c), (e, f, g), (h, i, j) = rot      # Rᵀ u, the components on the axes
        x, y, z = a * u[0] + e * u[1] + h * u[2], b * u[0] + f * u[1] + i * u[2], \
            c * u[0] + g * u[1] + j * u[2]
        return d0 * x * x + d1 * y * y + d2 * z * z

    def inverse_inertia_times(self, u):
        """I⁻¹ u in the world (a 3-tuple) at the pose of the last ``read``."""
        d0, d1, d2 = self.inverse_inertia
        rot = self.rotation()
        if rot is None:
            return d0 * u[0], d0 * u[1], d0 * u[2]
        (a, b, c), (e, f, g), (h, i, j) = rot
        x = d0 * (a * u[0] + e * u[1] + h * u[2])
        y = d1 * (b * u[0] + f * u[1] + i * u[2])
        z = d2 * (c * u[0] + g * u[1] + j * u[2])
        return a * x + b * y + c * z, e * x + f * y + g * z, h * x + i * y + j * z

    def cross(self, first, second):
        """The velocity at ``first`` per unit impulse at ``second`` (3x3, 1/kg), at the pose of
        the last ``read``: W = 1/m E - [r₁]× I⁻¹ [r₂]× (numpy: off the resting path)."""
        if self.mass == 0.0:
            return np.zeros((3, 3))
        rot = self.rotation()
        rot = np.eye(3) if rot is None else np.array(rot)
        inverse_inertia = rot @ np.diag(self.inverse_inertia) @ rot.T
        com = np.asarray(self.position)  # the base frame is the inertial frame (PyBullet's bases)
        return (self.inverse_mass * np.eye(3)
                - _skew(np.asarray(first) - com) @ inverse_inertia @ _skew(np.asarray(second) - com))


def _rotation_matrix(q):
    """The rotation (rows of a 3x3 tuple) of an (x, y, z, w) quaternion, as
    ``getMatrixFromQuaternion`` (Bullet's ``setRotation``: scaled by 2 / |q|²)."""
    x, y, z, w = q
    s = 2.0 / (x * x + y * y + z * z + w * w)
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return ((1.0 - (yy + zz), xy - wz, xz + wy), (xy + wz, 1.0 - (xx + zz), yz - wx),
            (xz - wy, yz + wx, 1.0 - (xx + yy)))


def _skew(r):
    """[r]×: the matrix of r × (m)."""
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


class CoupledContacts:
    """PyBullet stepped with the package's exact contacts between body pairs.

    Parameters
    ----------
    client : int
        The physics client (``pybullet.connect``).
    pairs : sequence of (side, side, Contact)
        (side, side, contact), a side a body id (its base) or ``(body id, link index)`` (a link
        of a fixed-base multibody, -1 the base): one of the two with a sphere as its collision
        shape.
    friction : float, optional
        Coulomb's μ of every pair, >= 0 (default 0).
    reach : float, optional
        Pairs farther apart than this (m) and carrying no contact state are not looked at
        further; > 0 (default ``REACH``).

    Raises
    ------
    InputError
        Keyed ``pairs`` (a body id that is not a body, a link it does not have, a link of a
        floating-base multibody, no sphere in a pair, two static sides, a moving body with links
        named by its id, one body twice, a pair named twice), ``friction`` or
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
        refuse_repeated([frozenset(((p[5], p[7]), (p[6], p[8]))) for p in self.pairs], rows)
        self._time = 0.0
        self._far = set()           # the pairs out of reach at the last step

    def _pair(self, row, index):
        client = self.client
        if len(row) != 3:
            raise InputError('pairs', row, '{n[pairs]}[%d] = {value}: allowed a (body, body, '
                             'Contact) triple' % index)
        sides = link_sides(client, row, index)
        count = pybullet.getNumBodies(physicsClientId=client)
        known = {pybullet.getBodyUniqueId(i, physicsClientId=client) for i in range(count)}
        for body, _ in sides:
            if isinstance(body, bool) or not isinstance(body, (int, np.integer)) \
                    or int(body) not in known:
                raise InputError('pairs', body, '{n[pairs]}[%d] names body {value}, which is no '
                                 'body of the client: allowed the ids of its bodies' % index)
        sides = [(int(body), link) for body, link in sides]
        for body, link in sides:
            check_link(client, body, link, index)
        contact = require_contact(row[2], 'pairs')
        if sides[0][0] == sides[1][0]:
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value} names the same body '
                             'twice: allowed two bodies' % index)
        radii = [_sphere_radius(client, body, link) for body, link in sides]
        if radii[0] is None and radii[1] is None:
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value} has no side whose '
                             'collision shape is a sphere: allowed a sphere against a plane, box, '
                             'mesh or sphere' % index)
        sphere, other = (0, 1) if radii[0] is not None else (1, 0)
        links = any(link >= 0 for _, link in sides)
        ends = [_Link(client, *sides[k], index) if sides[k][1] >= 0 else _Base(client, sides[k][0])
                for k in (sphere, other)]
        if not any(end.moves if isinstance(end, _Link) else end.mass > 0.0 for end in ends):
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value}: both sides are static '
                             '(mass 0 or no joint, no degree of freedom): allowed a pair that can '
                             'move' % index)
        for end in ends:
            if isinstance(end, _Base) and end.mass > 0.0 \
                    and pybullet.getNumJoints(end.body, physicsClientId=client):
                raise InputError('pairs', end.body, '{n[pairs]}[%d]: body {value} moves and has '
                                 'links (its base alone is not its response to a push): allowed '
                                 'bodies without links, a static base (mass 0), or a link of a '
                                 'fixed-base multibody as (body, link)' % index)
        (body_a, link_a), (body_b, link_b) = sides[sphere], sides[other]
        pybullet.setCollisionFilterPair(body_a, body_b, link_a, link_b, 0,
                                        physicsClientId=client)
        return (ends[0], ends[1], radii[sphere], NormalCoupling(contact), index, body_a, body_b,
                link_a, link_b, (lambda *args: couple_links(self, *args)) if links
                else self._couple)

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
        if params['numSubSteps'] > 1:
            raise InputError('numSubSteps', params['numSubSteps'], '{n[numSubSteps]} = {value}: '
                             'allowed 0 or 1 (the coupling gives one impulse a step)')
        dt = params['fixedTimeStep']
        pushing, reach, far = None, self.reach, self._far
        for pair in self.pairs:
            points = pybullet.getClosestPoints(pair[5], pair[6], reach, pair[7], pair[8],
                                               physicsClientId=client)
            if not points:      # out of reach (a state carried is dropped at the next call:
                far.add(pair[4])    # the clock moved on)
                continue
            push = pair[9](pair, points, dt, params)
            if push is not None:
                pushing = [push] if pushing is None else pushing + [push]
        if pushing is not None:
            if len(pushing) > 1:
                _refuse_coupled(pushing, client)
            for push in pushing:
                for base, force, point in push[3]:
                    pybullet.applyExternalForce(base.body, base.link, force, point,
                                                pybullet.WORLD_FRAME, physicsClientId=client)
        pybullet.stepSimulation(physicsClientId=client)
        self._time += dt

    def _reached(self, pair, points):
        """The unit normal (towards the sphere) and the gap (m) of a pair in reach, from its
        ``getClosestPoints``; one found penetrating right after a step out of reach is refused
        (``InputError`` keyed ``reach``)."""
        nearest = points[0] if len(points) == 1 else min(points, key=lambda p: p[8])
        nx, ny, nz = nearest[7]
        if nearest[1] != pair[0].body:          # Bullet's A is the sphere unless it swapped
            nx, ny, nz = -nx, -ny, -nz
        gap = float(nearest[8])
        index = pair[4]
        if index in self._far:
            if gap < 0.0:
                refuse_tunnel(index, gap, self.reach)
            self._far.discard(index)
        return (nx, ny, nz), gap

    def _couple(self, pair, points, dt, params):
        """The push of the step of a pair in reach (``points``: its ``getClosestPoints``),
        (index, normal, w_n, [(base, force, point)]), or ``None`` (no impulse)."""
        client = self.client
        sphere, other, (radius, offset), coupling, index = pair[0], pair[1], pair[2], pair[3], \
            pair[4]
        (nx, ny, nz), gap = self._reached(pair, points)
        # the contact point: the sphere's own centre (its collision frame's) less r n
        if sphere.mass == 0.0:
            cx, cy, cz = pybullet.getBasePositionAndOrientation(sphere.body,
                                                                physicsClientId=client)[0]
        else:
            sphere.read(client)
            cx, cy, cz = sphere.position
        if offset is not None:
            (a, b, c), (e, f, g), (h, i, j) = _rotation_matrix(
                pybullet.getBasePositionAndOrientation(sphere.body, physicsClientId=client)[1]
                if sphere.mass == 0.0 else sphere.orientation)
            cx, cy, cz = (cx + a * offset[0] + b * offset[1] + c * offset[2],
                          cy + e * offset[0] + f * offset[1] + g * offset[2],
                          cz + h * offset[0] + i * offset[1] + j * offset[2])
        point = (cx - radius * nx, cy - radius * ny, cz - radius * nz)
        normal = (nx, ny, nz)
        # n·W·n = Σ 1/m + (r × n)·I⁻¹(r × n), and the contact point's relative velocity
        w_n, vx, vy, vz = 0.0, 0.0, 0.0, 0.0
        for base, sign in ((sphere, 1.0), (other, -1.0)):
            if base.mass == 0.0:
                continue
            if base is other:
                base.read(client)
            px, py, pz = base.position
            rx, ry, rz = point[0] - px, point[1] - py, point[2] - pz
            w_n += base.inverse_mass + base.inverse_inertia_along(
                (ry * nz - rz * ny, rz * nx - rx * nz, rx * ny - ry * nx))
            (lx, ly, lz), (wx, wy, wz) = base.linear, base.angular
            vx += sign * (lx + wy * rz - wz * ry)
            vy += sign * (ly + wz * rx - wx * rz)
            vz += sign * (lz + wx * ry - wy * rx)
        moving = (sphere.mass > 0.0) - (other.mass > 0.0)
        ax, ay, az = (moving * params['gravityAccelerationX'],
                      moving * params['gravityAccelerationY'],
                      moving * params['gravityAccelerationZ'])
        step = coupling.step(self._time, gap, nx * vx + ny * vy + nz * vz, 1.0 / w_n,
                             nx * ax + ny * ay + nz * az, dt)
        p = step.impulse
        if p == 0.0:
            return None
        jx, jy, jz = p * nx, p * ny, p * nz
        if self.friction > 0.0:     # Coulomb's, from the velocity without friction
            jx, jy, jz = self._friction(sphere, other, point, normal, p, (
                vx + dt * ax, vy + dt * ay, vz + dt * az), (jx, jy, jz))
        fx, fy, fz = jx / dt, jy / dt, jz / dt
        on = [(sphere, (fx, fy, fz), point)] if sphere.mass > 0.0 else []
        if other.mass > 0.0:
            on.append((other, (-fx, -fy, -fz), point))
        return index, normal, w_n, on

    def _friction(self, sphere, other, point, normal, p, free, impulse):
        """The step's impulse with Coulomb's tangential part (``tangential_impulse``), from the
        point's velocity ``free`` the step ends with under the rest of the system alone: the
        sliding velocity with the normal impulse's (W n p) is tested in floats first, and a
        point that does not slide (a ball at rest) keeps the normal impulse."""
        sx, sy, sz = free
        for base in (sphere, other):
            if base.mass == 0.0:    # W n = n / m + (I⁻¹ (r × n)) × r on each moving base
                continue
            px, py, pz = base.position
            rx, ry, rz = point[0] - px, point[1] - py, point[2] - pz
            nx, ny, nz = normal
            ix, iy, iz = base.inverse_inertia_times(
                (ry * nz - rz * ny, rz * nx - rx * nz, rx * ny - ry * nx))
            m = base.inverse_mass
            sx += p * (m * nx + iy * rz - iz * ry)
            sy += p * (m * ny + iz * rx - ix * rz)
            sz += p * (m * nz + ix * ry - iy * rx)
        along = sx * normal[0] + sy * normal[1] + sz * normal[2]
        tx, ty, tz = sx - along * normal[0], sy - along * normal[1], sz - along * normal[2]
        if not tx * tx + ty * ty + tz * tz > 0.0:
            return impulse
        inverse = sphere.cross(point, point) + other.cross(point, point)
        n = np.array(normal)
        total = np.array(impulse) + tangential_impulse(
            p, np.array(free) + inverse @ np.array(impulse), n, inverse, self.friction)
        return tuple(total.tolist())


def _sphere_radius(client, body, link=-1):
    """(The radius (m) of the sphere of the body's base or ``link``, its centre in that link's
    centre-of-mass frame (m) or ``None`` at the origin), or ``None``."""
    shapes = pybullet.getCollisionShapeData(body, link, physicsClientId=client)
    if len(shapes) == 1 and shapes[0][2] == pybullet.GEOM_SPHERE:
        offset = tuple(float(x) for x in shapes[0][5])
        return float(shapes[0][3][0]), (offset if any(offset) else None)
    return None


def _refuse_coupled(pushing, client=None):
    """Refuse two pairs pushing in one step on a common body along lines that move each
    other's gap: each is integrated alone, and together they would pump energy in (a stack)."""
    for k, (first, n_first, w_first, on_first) in enumerate(pushing):
        for second, n_second, w_second, on_second in pushing[k + 1:]:
            cross = 0.0
            for base, _, p_first in on_first:
                for other, _, p_second in on_second:
                    if isinstance(base, _Link):
                        response = base.cross(client, p_first, p_second, other)
                    elif other is base or other.body == base.body:
                        response = base.cross(p_first, p_second)
                    else:
                        continue
                    cross += float(np.asarray(n_first) @ response @ np.asarray(n_second))
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
