"""The PyBullet coupling's articulated side (``contact_sim.coupling.pybullet``): a pair that
names a link, ``(body, link)``, of a fixed-base multibody with joints.

At each step the link's joints are read (``getJointStates``, over the non-fixed joints, as
PyBullet's ``q`` lists are), and at the contact point (in the link's centre-of-mass frame, as
``calculateJacobian`` takes it): the point's linear Jacobian J, the joint-space mass matrix M
(``calculateMassMatrix``), the inverse mass along the normal n·J M⁻¹ Jᵀ n, the point's velocity
J q̇ and the rest of the system's acceleration J q̈₀, q̈₀ = −M⁻¹ τ₀ with τ₀ =
``calculateInverseDynamics(q, q̇, 0)`` (gravity, Coriolis and centrifugal forces; the J̇ q̇
term of the point's acceleration is left out).  Joint motors are not seen: PyBullet's default
velocity motors must be off (``setJointMotorControl2(..., VELOCITY_CONTROL, force=0)``) for the
exact figures.  A floating-base multibody with links is refused (its mass matrix holds the
base's 6 degrees of freedom and ``calculateInverseDynamics`` does not serve it).  Units: SI.
"""

import numpy as np
import pybullet

from contact_sim.coupling.rows import tangential_impulse
from contact_sim.validation import InputError


class _Link:
    """A link of a fixed-base multibody: its id, link index, non-fixed joints; ``read`` takes
    the step's joint state, centre-of-mass pose, M⁻¹ and q̈₀ (numpy)."""

    __slots__ = ('body', 'link', 'mass', 'moves', 'joints', 'position', 'orientation', 'q',
                 'qdot', 'zeros', 'inverse', 'rest', 'origin', 'rotation', 'velocity')

    def __init__(self, client, body, link, index):
        self.body, self.link = body, link
        info = pybullet.getDynamicsInfo(body, link, physicsClientId=client)
        self.mass = float(info[0])
        # calculateJacobian's point is taken from the link frame's origin, on the axes of the
        # centre-of-mass frame (measured against finite differences): that origin in the
        # centre-of-mass frame is R_iᵀ p_i, (p_i, R_i) the inertial frame in the link frame
        inertial = np.reshape(pybullet.getMatrixFromQuaternion(info[4]), (3, 3))
        self.origin = inertial.T @ np.asarray(info[3], dtype=float)
        kinds = [pybullet.getJointInfo(body, j, physicsClientId=client)[2]
                 for j in range(pybullet.getNumJoints(body, physicsClientId=client))]
        if any(k not in (pybullet.JOINT_REVOLUTE, pybullet.JOINT_PRISMATIC,
                         pybullet.JOINT_FIXED) for k in kinds):
            raise InputError('pairs', (body, link), '{n[pairs]}[%d] = {value}: a multibody with '
                             'a spherical or planar joint: allowed revolute, prismatic and fixed '
                             'joints' % index)
        self.joints = [j for j, k in enumerate(kinds) if k != pybullet.JOINT_FIXED]
        count = len(self.joints)
        self.zeros = [0.0] * count
        self.moves = count > 0
        floating = pybullet.getDynamicsInfo(body, -1, physicsClientId=client)[0] > 0.0
        if self.moves or floating:
            size = len(pybullet.calculateMassMatrix(body, self.zeros, physicsClientId=client))
            if floating or size != count:
                raise InputError('pairs', (body, link), '{n[pairs]}[%d] = {value}: a link of a '
                                 'floating-base multibody (its mass matrix holds the base\'s 6 '
                                 'degrees of freedom): allowed links of a fixed-base multibody'
                                 % index)
        self.position, self.orientation = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
        self.q = self.qdot = self.zeros
        self.inverse = self.rest = self.rotation = self.velocity = None

    def read(self, client):
        """Take this step's joint state, the link's centre-of-mass pose, M⁻¹ and q̈₀."""
        state = pybullet.getLinkState(self.body, self.link, computeForwardKinematics=True,
                                      physicsClientId=client)
        self.position, self.orientation = state[0], state[1]
        self.rotation = np.reshape(pybullet.getMatrixFromQuaternion(state[1]), (3, 3))
        if not self.moves:
            return
        states = pybullet.getJointStates(self.body, self.joints, physicsClientId=client)
        self.q = [s[0] for s in states]
        self.qdot = [s[1] for s in states]
        self.velocity = np.array(self.qdot)
        mass = np.array(pybullet.calculateMassMatrix(self.body, self.q, physicsClientId=client))
        self.inverse = np.linalg.inv(mass) if len(self.q) > 1 else 1.0 / mass
        bias = pybullet.calculateInverseDynamics(self.body, self.q, self.qdot, self.zeros,
                                                 physicsClientId=client)
        self.rest = -self.inverse @ np.array(bias)

    def jacobian(self, client, point):
        """The linear Jacobian (3 x joints) of the world ``point`` fixed on the link."""
        local = self.rotation.T @ (np.asarray(point) - np.asarray(self.position)) + self.origin
        return np.array(pybullet.calculateJacobian(
            self.body, self.link, local.tolist(), self.q, self.qdot, self.zeros,
            physicsClientId=client)[0])

    def response(self, client, point, gravity):
        """(velocity, acceleration of the rest of the system, W = J M⁻¹ Jᵀ) at ``point``, or
        ``None`` for a link without joints."""
        if not self.moves:
            return None
        jac = self.jacobian(client, point)
        return jac @ self.velocity, jac @ self.rest, jac @ self.inverse @ jac.T

    def cross(self, client, first, second, other):
        """The velocity at ``first`` on this link per unit impulse at ``second`` on ``other``
        (3x3, 1/kg): J₁ M⁻¹ J₂ᵀ on one body, zero across bodies."""
        if not self.moves or not isinstance(other, _Link) or other.body != self.body:
            return np.zeros((3, 3))
        return self.jacobian(client, first) @ self.inverse @ other.jacobian(client, second).T


def link_sides(client, row, index):
    """The two sides of a row, ``(body, link)`` each (a plain id is the base, -1)."""
    sides = []
    for side in row[:2]:
        if isinstance(side, (tuple, list)):
            if len(side) != 2 or any(isinstance(x, bool) or not isinstance(x, (int, np.integer))
                                     for x in side):
                raise InputError('pairs', side, '{n[pairs]}[%d] names {value}: allowed a body '
                                 'id or a (body id, link index) pair' % index)
            sides.append((int(side[0]), int(side[1])))
        else:
            sides.append((side, -1))
    return sides


def check_link(client, body, link, index):
    """Refuse a link index the body does not have."""
    count = pybullet.getNumJoints(body, physicsClientId=client)
    if not -1 <= link < count:
        raise InputError('pairs', (body, link), '{n[pairs]}[%d] = {value}: body %d has no link '
                         '%d: allowed -1 (the base) to %d' % (index, body, link, count - 1))


def response_of_base(base, point, gravity):
    """(velocity, acceleration of the rest of the system, W) of a free base at ``point``, or
    ``None`` for a static one."""
    if base.mass == 0.0:
        return None
    r = np.asarray(point) - np.asarray(base.position)
    velocity = np.asarray(base.linear) + np.cross(base.angular, r)
    return velocity, np.asarray(gravity), base.cross(point, point)


def couple_links(coupled, pair, points, dt, params):
    """The push of the step of a pair with a link in reach, as ``CoupledContacts._couple``'s,
    or ``None`` (no impulse)."""
    client = coupled.client
    sphere, other, (radius, offset), coupling, index = pair[:5]
    normal, gap = coupled._reached(pair, points)
    normal = np.array(normal, dtype=float)
    gravity = (params['gravityAccelerationX'], params['gravityAccelerationY'],
               params['gravityAccelerationZ'])
    for side in (sphere, other):
        if isinstance(side, _Link) or side.mass > 0.0:
            side.read(client)
        else:
            side.position, side.orientation = pybullet.getBasePositionAndOrientation(
                side.body, physicsClientId=client)
    centre = np.asarray(sphere.position, dtype=float)
    if offset is not None:
        rotation = sphere.rotation if isinstance(sphere, _Link) else np.reshape(
            pybullet.getMatrixFromQuaternion(sphere.orientation), (3, 3))
        centre = centre + rotation @ np.asarray(offset)
    point = centre - radius * normal
    total = [np.zeros(3), np.zeros(3), np.zeros((3, 3))]
    for side, sign in ((sphere, 1.0), (other, -1.0)):
        if isinstance(side, _Link):
            parts = side.response(client, point, gravity)
        else:
            parts = response_of_base(side, point, gravity)
        if parts is None:
            continue
        total[0] += sign * parts[0]
        total[1] += sign * parts[1]
        total[2] += parts[2]
    velocity, acceleration, inverse = total
    w_n = float(normal @ inverse @ normal)
    if not w_n > 0.0:
        raise InputError('pairs', pair[5:7], '{n[pairs]}[%d] = {value}: neither side can move '
                         'along the contact normal here (n·J M⁻¹ Jᵀ n = %g): allowed a pair '
                         'that can move' % (index, w_n))
    step = coupling.step(coupled._time, gap, float(normal @ velocity), 1.0 / w_n,
                         float(normal @ acceleration), dt)
    p = step.impulse
    if p == 0.0:
        return None
    impulse = p * normal
    if coupled.friction > 0.0:      # Coulomb's, from the velocity without friction
        impulse = impulse + tangential_impulse(
            p, velocity + dt * acceleration + inverse @ impulse, normal, inverse,
            coupled.friction)
    force = tuple((impulse / dt).tolist())
    on = []
    for side, sign in ((sphere, 1.0), (other, -1.0)):
        if isinstance(side, _Link) and side.moves or not isinstance(side, _Link) \
                and side.mass > 0.0:
            on.append((side, tuple(sign * f for f in force), tuple(point.tolist())))
    return index, tuple(normal.tolist()), w_n, on
