"""The PyBullet adapter's own geometry (``contact_sim.coupling.pybullet``) against PyBullet's: the
rotation of a quaternion against ``getMatrixFromQuaternion``, and the inverse mass at a point
(n·W·n, W n in floats; W in numpy) against the engine's response to an impulse there, on bodies
with an anisotropic inertia, a turned inertial frame and a sphere off the centre of mass."""
import numpy as np
import pytest

import pybullet
from contact_sim.coupling.pybullet import _Base, _rotation_matrix  # noqa: E402

DT = 1e-3


@pytest.fixture
def client():
    c = pybullet.connect(pybullet.DIRECT)
    pybullet.setGravity(0, 0, 0, physicsClientId=c)
    pybullet.setTimeStep(DT, physicsClientId=c)
    yield c
    pybullet.disconnect(c)


def test_the_rotation_of_a_quaternion_is_bullets():
    rng = np.random.default_rng(7)
    quaternions = [(0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 1.0, 0.0), (0.3, -0.2, 0.1, 2.0)]
    quaternions += [tuple(q) for q in rng.normal(size=(20, 4))]
    for q in quaternions:
        expected = np.reshape(pybullet.getMatrixFromQuaternion(q), (3, 3))
        assert np.allclose(np.array(_rotation_matrix(q)), expected, rtol=0.0, atol=1e-15), q


def _body(client, kind, inertial_orientation, orientation):
    """A free base of 2 kg: an anisotropic box, or a sphere whose collision frame sits 3 cm off
    its centre of mass (a compound in Bullet)."""
    if kind == 'box':
        shape = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=(0.1, 0.05, 0.02),
                                              physicsClientId=client)
    else:
        shape = pybullet.createCollisionShape(pybullet.GEOM_SPHERE, radius=0.04,
                                              collisionFramePosition=(0.03, 0.0, 0.01),
                                              physicsClientId=client)
    body = pybullet.createMultiBody(
        2.0, shape, basePosition=(0.1, -0.2, 1.0), baseOrientation=orientation,
        baseInertialFrameOrientation=inertial_orientation, physicsClientId=client)
    pybullet.changeDynamics(body, -1, linearDamping=0, angularDamping=0, physicsClientId=client)
    return body


@pytest.mark.parametrize('kind', ['box', 'offset_sphere'])
@pytest.mark.parametrize('inertial', [(0.0, 0.0, 0.0), (0.3, -0.5, 1.1)],
                         ids=['inertial_frame_aligned', 'inertial_frame_turned'])
def test_the_inverse_mass_at_a_point_is_the_engines_response(client, kind, inertial):
    rng = np.random.default_rng(3)
    for pose in range(4):
        body = _body(client, kind, pybullet.getQuaternionFromEuler(inertial),
                     pybullet.getQuaternionFromEuler(tuple(rng.uniform(-1.5, 1.5, 3))))
        base = _Base(client, body)
        base.read(client)
        com = np.array(base.position)
        r = rng.uniform(-0.1, 0.1, 3)
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        point = com + r
        # a unit impulse along n at the point over one step, from rest: the point's change of
        # velocity is W n
        pybullet.applyExternalForce(body, -1, (n / DT).tolist(), point.tolist(),
                                    pybullet.WORLD_FRAME, physicsClientId=client)
        pybullet.stepSimulation(physicsClientId=client)
        lin, ang = (np.array(v) for v in pybullet.getBaseVelocity(body, physicsClientId=client))
        response = lin + np.cross(ang, r)
        scale = np.linalg.norm(response)
        assert np.allclose(base.cross(point, point) @ n, response, rtol=0.0, atol=1e-12 * scale)
        u = np.cross(r, n)
        w_n = base.inverse_mass + base.inverse_inertia_along(tuple(u))
        assert w_n == pytest.approx(float(n @ response), rel=1e-12)
        w_times_n = n * base.inverse_mass + np.cross(base.inverse_inertia_times(tuple(u)), r)
        assert np.allclose(w_times_n, response, rtol=0.0, atol=1e-12 * scale), (kind, pose)
        pybullet.removeBody(body, physicsClientId=client)
