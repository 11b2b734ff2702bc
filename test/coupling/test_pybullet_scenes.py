"""The PyBullet coupling on scenes as users write them (``contact_sim.coupling.pybullet``): a
sphere off its body's centre of mass, a moving body with links and a stack of coupled contacts
(refused by an ``InputError`` naming ``pairs``)."""
import numpy as np
import pytest

import contact_sim as cs

import pybullet
from contact_sim.coupling.pybullet import CoupledContacts  # noqa: E402

R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))


@pytest.fixture
def client():
    c = pybullet.connect(pybullet.DIRECT)
    pybullet.setTimeStep(1e-3, physicsClientId=c)
    yield c
    pybullet.disconnect(c)


def floor(client):
    return pybullet.createMultiBody(0, pybullet.createCollisionShape(
        pybullet.GEOM_PLANE, physicsClientId=client), physicsClientId=client)


def sphere(client, position, offset=(0.0, 0.0, 0.0)):
    body = pybullet.createMultiBody(MASS, pybullet.createCollisionShape(
        pybullet.GEOM_SPHERE, radius=R, collisionFramePosition=offset, physicsClientId=client),
        basePosition=position, physicsClientId=client)
    pybullet.changeDynamics(body, -1, linearDamping=0, angularDamping=0, physicsClientId=client)
    return body


def test_a_sphere_off_the_centre_of_mass_is_pushed_at_its_own_lowest_point(client):
    # the sphere 3 cm beside the centre of mass, thrown down at 1 m/s, gravity off: the
    # floor's impulse J (up) at the sphere's lowest point spins the body, I w = r x J
    arm = 0.03
    ball = sphere(client, (0.0, 0.0, R + 0.002), offset=(arm, 0.0, 0.0))
    pybullet.resetBaseVelocity(ball, (0.0, 0.0, -1.0), physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, floor(client), STEEL)])
    while not coupled.impacts:
        coupled.step()
    coupled.step()          # a whole step of flight after the lift-off
    lin, ang = pybullet.getBaseVelocity(ball, physicsClientId=client)
    inertia = pybullet.getDynamicsInfo(ball, -1, physicsClientId=client)[2][1]
    impulse = MASS * (lin[2] + 1.0)
    assert impulse > 0.0 and len(coupled.impacts) == 1
    # (to 1.6e-5 measured: the body turns 0.045 rad over the step of flight after it)
    assert ang[1] == pytest.approx(-arm * impulse / inertia, rel=1e-4)


def test_a_moving_body_with_links_is_refused(client):
    shape = pybullet.createCollisionShape(pybullet.GEOM_SPHERE, radius=R, physicsClientId=client)
    rod = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=(0.01, 0.01, 0.05),
                                        physicsClientId=client)
    body = pybullet.createMultiBody(
        MASS, shape, basePosition=(0, 0, 0.2), linkMasses=[0.5], linkCollisionShapeIndices=[rod],
        linkVisualShapeIndices=[-1], linkPositions=[(0, 0, 0.1)],
        linkOrientations=[(0, 0, 0, 1)], linkInertialFramePositions=[(0, 0, 0)],
        linkInertialFrameOrientations=[(0, 0, 0, 1)], linkParentIndices=[0],
        linkJointTypes=[pybullet.JOINT_FIXED], linkJointAxis=[(0, 0, 1)],
        physicsClientId=client)
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(client, [(body, floor(client), STEEL)])
    assert refused.value.field == 'pairs' and 'links' in str(refused.value)


def test_a_pair_named_twice_is_refused(client):
    ball, ground = sphere(client, (0, 0, 0.2)), floor(client)
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(client, [(ball, ground, STEEL), (ground, ball, STEEL)])
    assert refused.value.field == 'pairs' and 'twice' in str(refused.value)
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(client, [(ball, ball, STEEL)])
    assert refused.value.field == 'pairs' and 'same body' in str(refused.value)


def test_a_stack_of_coupled_contacts_is_refused_not_launched(client):
    # measured before the refusal: the upper ball launched to 75 m
    pybullet.setGravity(0, 0, -9.81, physicsClientId=client)
    ground, low, up = floor(client), sphere(client, (0, 0, R)), sphere(client, (0, 0, 0.2))
    coupled = CoupledContacts(client, [(low, ground, STEEL), (up, low, STEEL)])
    with pytest.raises(cs.InputError) as refused:
        for _ in range(3000):
            coupled.step()
            heights = [pybullet.getBasePositionAndOrientation(b, physicsClientId=client)[0][2]
                       for b in (low, up)]
            assert np.all(np.abs(heights) < 1.0)
    assert refused.value.field == 'pairs' and 'pairs[0] and pairs[1]' in str(refused.value)


def test_a_ball_closing_more_than_the_reach_in_a_step_is_refused_not_launched(client):
    # 20 m/s at 5 ms: 10 cm a step, beyond the default reach of 5 cm
    pybullet.setTimeStep(0.005, physicsClientId=client)
    ground, ball = floor(client), sphere(client, (0, 0, 0.5))
    pybullet.resetBaseVelocity(ball, (0.0, 0.0, -20.0), physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, ground, STEEL)])
    with pytest.raises(cs.InputError) as refused:
        for _ in range(100):
            coupled.step()
    assert refused.value.field == 'reach'
    pybullet.resetBasePositionAndOrientation(ball, (0, 0, 0.5), (0, 0, 0, 1),
                                             physicsClientId=client)
    pybullet.resetBaseVelocity(ball, (0.0, 0.0, -20.0), physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, ground, STEEL)], reach=0.2)
    for _ in range(100):
        coupled.step()
    out = pybullet.getBaseVelocity(ball, physicsClientId=client)[0][2] / 20.0
    assert out == pytest.approx(coupled.impacts[0].restitution, rel=1e-6) and 0.5 < out < 0.7
