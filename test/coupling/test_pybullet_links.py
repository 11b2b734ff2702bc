"""The PyBullet coupling on links (``contact_sim.coupling.pybullet_links``): the inverse mass, the
rest of the system's acceleration and the velocity at a point of a link against PyBullet's own
response to an impulse there; a sphere on a pendulum (a URDF, fixed base, a revolute joint)
swung into a wall, and a ball thrown on a hinged paddle, against the same model with the law's
force evaluated every 1e-6 s step (naive force converges there); the refusals."""
import numpy as np
import pytest

import contact_sim as cs

import pybullet
from contact_sim.coupling.pybullet import CoupledContacts  # noqa: E402
from contact_sim.coupling.pybullet_links import _Link  # noqa: E402

R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
WALL = R + 0.002            # the wall's face (m): 2 mm ahead of the ball at the bottom
STRIKER = '''<robot name="striker">
  <link name="pivot"><inertial><mass value="0"/>
    <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="rod"><inertial><origin xyz="0 0 -0.14"/><mass value="0.2"/>
    <inertia ixx="0.0013" iyy="0.0013" izz="2.5e-6" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="ball"><inertial><mass value="{m!r}"/>
    <inertia ixx="{i!r}" iyy="{i!r}" izz="{i!r}" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><sphere radius="{r!r}"/></geometry></collision></link>
  <joint name="hinge" type="revolute"><parent link="pivot"/><child link="rod"/>
    <axis xyz="0 1 0"/><limit lower="-3.14" upper="3.14" effort="0" velocity="100"/></joint>
  <joint name="weld" type="fixed"><parent link="rod"/><child link="ball"/>
    <origin xyz="0 0 -0.3"/></joint>
</robot>'''


@pytest.fixture
def client():
    c = pybullet.connect(pybullet.DIRECT)
    yield c
    pybullet.disconnect(c)


def striker(client, dt, path):
    """A sphere (link 1, welded to the rod) at the end of a 0.3 m pendulum hinged at its fixed
    base, gravity on, its motor off, swung at 1 m/s into a wall 2 mm ahead."""
    pybullet.resetSimulation(physicsClientId=client)
    pybullet.setGravity(0, 0, -9.81, physicsClientId=client)
    pybullet.setTimeStep(dt, physicsClientId=client)
    path.write_text(STRIKER.format(m=MASS, i=0.4 * MASS * R * R, r=R))
    arm = pybullet.loadURDF(str(path), basePosition=(0, 0, 0.3), useFixedBase=True,
                            physicsClientId=client)
    wall = pybullet.createMultiBody(0, pybullet.createCollisionShape(
        pybullet.GEOM_BOX, halfExtents=(0.01, 0.1, 0.1), physicsClientId=client),
        basePosition=(WALL + 0.01, 0, 0), physicsClientId=client)
    for link in range(-1, pybullet.getNumJoints(arm, physicsClientId=client)):
        pybullet.changeDynamics(arm, link, linearDamping=0, angularDamping=0,
                                physicsClientId=client)
    pybullet.setJointMotorControl2(arm, 0, pybullet.VELOCITY_CONTROL, force=0,
                                   physicsClientId=client)
    pybullet.resetJointState(arm, 0, 0.0, -1.0 / 0.3, physicsClientId=client)
    return arm, wall


def test_a_pendulum_striker_against_naive_force_at_one_microsecond(client, tmp_path):
    """The pendulum's angular velocity after the impact, coupled at 1/240 s and 1 ms, within 2 %
    of the same model at a 1e-6 s step with the law's force evaluated every step."""
    path = tmp_path / 'striker.urdf'
    arm, wall = striker(client, 1e-6, path)
    pybullet.setCollisionFilterPair(arm, wall, 1, -1, 0, physicsClientId=client)
    for _ in range(5000):
        state = pybullet.getLinkState(arm, 1, computeLinkVelocity=True,
                                      computeForwardKinematics=True, physicsClientId=client)
        centre = state[0]
        depth, rate = centre[0] + R - WALL, state[6][0]
        if depth > 0.0:
            force = STEEL.force_at(depth, rate)
            pybullet.applyExternalForce(arm, 1, (-force, 0.0, 0.0),
                                        (centre[0] + R, centre[1], centre[2]),
                                        pybullet.WORLD_FRAME, physicsClientId=client)
        pybullet.stepSimulation(physicsClientId=client)
    reference = pybullet.getJointState(arm, 0, physicsClientId=client)[1]
    assert reference > 0.0                          # it came back
    for dt in (1.0 / 240.0, 1e-3):
        arm, wall = striker(client, dt, path)
        coupled = CoupledContacts(client, [((arm, 1), wall, STEEL)])
        for _ in range(int(5e-3 / dt) + 1):         # a whole step of flight after the impact
            coupled.step()
        assert len(coupled.impacts) == 1
        assert pybullet.getJointState(arm, 0, physicsClientId=client)[1] == pytest.approx(
            reference, rel=0.02), dt


def arm(client, base_mass=0.0):
    """A two-link arm, revolute joints about y then x, turned inertial frames and centres of
    mass off the joints, a fixed link between them; its motors off, damping 0."""
    box = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=(0.02, 0.02, 0.1),
                                        physicsClientId=client)
    turned = pybullet.getQuaternionFromEuler((0.3, -0.4, 0.7))
    body = pybullet.createMultiBody(
        base_mass, -1, basePosition=(0.1, 0.0, 1.0),
        linkMasses=[0.8, 0.1, 0.5], linkCollisionShapeIndices=[box, -1, box],
        linkVisualShapeIndices=[-1, -1, -1],
        linkPositions=[(0, 0, 0), (0, 0, -0.2), (0, 0, 0)],
        linkOrientations=[(0, 0, 0, 1)] * 3,
        linkInertialFramePositions=[(0.01, 0.0, -0.1), (0, 0, 0), (0.0, 0.02, -0.12)],
        linkInertialFrameOrientations=[turned, (0, 0, 0, 1), turned],
        linkParentIndices=[0, 1, 2],
        linkJointTypes=[pybullet.JOINT_REVOLUTE, pybullet.JOINT_FIXED, pybullet.JOINT_REVOLUTE],
        linkJointAxis=[(0, 1, 0), (0, 0, 1), (1, 0, 0)], physicsClientId=client)
    for link in range(-1, 3):
        pybullet.changeDynamics(body, link, linearDamping=0, angularDamping=0,
                                physicsClientId=client)
    for joint in (0, 2):
        pybullet.setJointMotorControl2(body, joint, pybullet.VELOCITY_CONTROL, force=0,
                                       physicsClientId=client)
    return body


def test_the_response_at_a_link_point_is_the_engines(client):
    """v + dt a + W P at a point of the arm's second link (the rest of the system's
    acceleration from gravity and Coriolis, W = J M⁻¹ Jᵀ) against the velocity PyBullet gives
    that point after one step with the impulse P applied there (``applyExternalForce`` at the
    link, world frame)."""
    dt = 1e-3
    pybullet.setGravity(0, 0, -9.81, physicsClientId=client)
    pybullet.setTimeStep(dt, physicsClientId=client)
    rng = np.random.default_rng(5)
    for trial in range(6):
        pybullet.resetSimulation(physicsClientId=client)
        pybullet.setGravity(0, 0, -9.81, physicsClientId=client)
        pybullet.setTimeStep(dt, physicsClientId=client)
        body = arm(client)
        for joint in (0, 2):
            pybullet.resetJointState(body, joint, rng.uniform(-1.5, 1.5), rng.uniform(-3, 3),
                                     physicsClientId=client)
        link = _Link(client, body, 2, 0)
        link.read(client)
        point = np.asarray(link.position) + rng.uniform(-0.1, 0.1, 3)
        impulse = rng.normal(size=3) * 0.05 * (trial > 0)      # the first: no push at all
        velocity, rest, inverse = link.response(client, point, None)
        jacobian = link.jacobian(client, point)
        pybullet.applyExternalForce(body, 2, tuple(impulse / dt), tuple(point),
                                    pybullet.WORLD_FRAME, physicsClientId=client)
        pybullet.stepSimulation(physicsClientId=client)
        qdot = [s[1] for s in pybullet.getJointStates(body, [0, 2], physicsClientId=client)]
        expected = velocity + dt * rest + inverse @ impulse
        assert np.allclose(jacobian @ np.array(qdot), expected, rtol=0.0,
                           atol=1e-9 * (1.0 + np.abs(expected).max())), trial
        assert np.allclose(inverse, inverse.T, atol=1e-12) and \
            np.all(np.linalg.eigvalsh(inverse) > -1e-12)


def paddle(client, dt):
    """A 0.3 m paddle (a box link) hinged at its fixed base, gravity off, its motor off, and a
    steel ball thrown at 1 m/s down on its far end."""
    pybullet.resetSimulation(physicsClientId=client)
    pybullet.setGravity(0, 0, 0, physicsClientId=client)
    pybullet.setTimeStep(dt, physicsClientId=client)
    board = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=(0.15, 0.02, 0.005),
                                          collisionFramePosition=(0.15, 0, 0),
                                          physicsClientId=client)
    body = pybullet.createMultiBody(
        0.0, -1, linkMasses=[0.3], linkCollisionShapeIndices=[board],
        linkVisualShapeIndices=[-1], linkPositions=[(0, 0, 0)],
        linkOrientations=[(0, 0, 0, 1)], linkInertialFramePositions=[(0.15, 0, 0)],
        linkInertialFrameOrientations=[(0, 0, 0, 1)], linkParentIndices=[0],
        linkJointTypes=[pybullet.JOINT_REVOLUTE], linkJointAxis=[(0, 1, 0)],
        physicsClientId=client)
    pybullet.changeDynamics(body, 0, linearDamping=0, angularDamping=0, physicsClientId=client)
    pybullet.setJointMotorControl2(body, 0, pybullet.VELOCITY_CONTROL, force=0,
                                   physicsClientId=client)
    ball = pybullet.createMultiBody(MASS, pybullet.createCollisionShape(
        pybullet.GEOM_SPHERE, radius=R, physicsClientId=client),
        basePosition=(0.25, 0.0, 0.005 + R + 0.002), physicsClientId=client)
    pybullet.changeDynamics(ball, -1, linearDamping=0, angularDamping=0, physicsClientId=client)
    pybullet.resetBaseVelocity(ball, (0.0, 0.0, -1.0), physicsClientId=client)
    return body, ball


def test_a_ball_thrown_on_a_hinged_paddle_against_naive_force(client):
    """The ball's and the paddle's velocities after the impact (the link the other side),
    coupled at 1/240 s and 1 ms, within 2 % of naive force at 1e-6 s."""
    body, ball = paddle(client, 1e-6)
    pybullet.setCollisionFilterPair(body, ball, 0, -1, 0, physicsClientId=client)
    for _ in range(5000):
        centre, _ = pybullet.getBasePositionAndOrientation(ball, physicsClientId=client)
        point = (centre[0], centre[1], centre[2] - R)
        # the board's top face at the ball's x, and its velocity there (small rotations)
        angle, rate = pybullet.getJointState(body, 0, physicsClientId=client)[:2]
        top = -np.sin(angle) * centre[0] + 0.005 * np.cos(angle)
        depth = top - point[2]
        if depth > 0.0:
            ball_rate = pybullet.getBaseVelocity(ball, physicsClientId=client)[0][2]
            force = STEEL.force_at(depth, -rate * centre[0] - ball_rate)
            pybullet.applyExternalForce(ball, -1, (0.0, 0.0, force), point,
                                        pybullet.WORLD_FRAME, physicsClientId=client)
            pybullet.applyExternalForce(body, 0, (0.0, 0.0, -force), point,
                                        pybullet.WORLD_FRAME, physicsClientId=client)
        pybullet.stepSimulation(physicsClientId=client)
    reference = (pybullet.getBaseVelocity(ball, physicsClientId=client)[0][2],
                 pybullet.getJointState(body, 0, physicsClientId=client)[1])
    assert reference[0] > 0.0 and reference[1] > 0.0      # the ball came back, the paddle down
    for dt in (1.0 / 240.0, 1e-3):
        body, ball = paddle(client, dt)
        coupled = CoupledContacts(client, [(ball, (body, 0), STEEL)])
        for _ in range(int(5e-3 / dt) + 1):
            coupled.step()
        assert len(coupled.impacts) == 1
        result = (pybullet.getBaseVelocity(ball, physicsClientId=client)[0][2],
                  pybullet.getJointState(body, 0, physicsClientId=client)[1])
        assert result == pytest.approx(reference, rel=0.02), dt


def test_bad_links_are_refused(client, tmp_path):
    arm_body, wall = striker(client, 1e-3, tmp_path / 'striker.urdf')
    ball = pybullet.createCollisionShape(pybullet.GEOM_SPHERE, radius=R, physicsClientId=client)
    floating = pybullet.createMultiBody(
        1.0, -1, basePosition=(1.0, 0.0, 1.0), linkMasses=[MASS], linkCollisionShapeIndices=[ball],
        linkVisualShapeIndices=[-1], linkPositions=[(0, 0, -0.3)],
        linkOrientations=[(0, 0, 0, 1)], linkInertialFramePositions=[(0, 0, 0)],
        linkInertialFrameOrientations=[(0, 0, 0, 1)], linkParentIndices=[0],
        linkJointTypes=[pybullet.JOINT_REVOLUTE], linkJointAxis=[(0, 1, 0)],
        physicsClientId=client)
    for pairs in ([((arm_body, 5), wall, STEEL)], [((arm_body, -2), wall, STEEL)],
                  [((arm_body, 1, 0), wall, STEEL)], [((arm_body, 1.0), wall, STEEL)],
                  [((99, 1), wall, STEEL)], [((arm_body, 1), (arm_body, 0), STEEL)],
                  [((arm_body, 0), wall, STEEL)], [((floating, 0), wall, STEEL)],
                  [((arm_body, 1), wall, STEEL), (wall, (arm_body, 1), STEEL)]):
        with pytest.raises(cs.InputError) as refused:
            CoupledContacts(client, pairs)
        assert refused.value.field == 'pairs', pairs
    spherical = pybullet.createMultiBody(
        0.0, -1, basePosition=(2.0, 0.0, 1.0), linkMasses=[MASS], linkCollisionShapeIndices=[ball],
        linkVisualShapeIndices=[-1], linkPositions=[(0, 0, -0.3)],
        linkOrientations=[(0, 0, 0, 1)], linkInertialFramePositions=[(0, 0, 0)],
        linkInertialFrameOrientations=[(0, 0, 0, 1)], linkParentIndices=[0],
        linkJointTypes=[pybullet.JOINT_SPHERICAL], linkJointAxis=[(0, 1, 0)],
        physicsClientId=client)
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(client, [((spherical, 0), wall, STEEL)])
    assert refused.value.field == 'pairs' and 'spherical' in str(refused.value)
    welded = pybullet.createMultiBody(
        1.0, -1, basePosition=(3.0, 0.0, 1.0), linkMasses=[MASS], linkCollisionShapeIndices=[ball],
        linkVisualShapeIndices=[-1], linkPositions=[(0, 0, -0.3)],
        linkOrientations=[(0, 0, 0, 1)], linkInertialFramePositions=[(0, 0, 0)],
        linkInertialFrameOrientations=[(0, 0, 0, 1)], linkParentIndices=[0],
        linkJointTypes=[pybullet.JOINT_FIXED], linkJointAxis=[(0, 1, 0)],
        physicsClientId=client)
    for body in (floating, welded):     # a free body's link moves with it, joints or not
        with pytest.raises(cs.InputError) as refused:
            CoupledContacts(client, [((body, 0), wall, STEEL)])
        assert refused.value.field == 'pairs' and 'floating-base' in str(refused.value)
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(client, [((floating, 0), wall, STEEL)])
    assert 'floating-base' in str(refused.value)
    # a plain id is the base: a fixed base with links is static, and (body, -1) is the same
    CoupledContacts(client, [((arm_body, 1), (wall, -1), STEEL)])


def test_friction_on_a_link_bounds_the_tangential_impulse(client):
    """A ball thrown obliquely (0.5 m/s along the paddle, 1 m/s down) on the hinged paddle with
    μ = 0.1: it slips, and Coulomb's impulse takes μ times the normal one off its tangential
    velocity, against the sliding."""
    body, ball = paddle(client, 1e-3)
    pybullet.resetBaseVelocity(ball, (0.5, 0.0, -1.0), physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, (body, 0), STEEL)], friction=0.1)
    for _ in range(6):
        coupled.step()
    assert len(coupled.impacts) == 1
    (vx, vy, vz), spin = pybullet.getBaseVelocity(ball, physicsClientId=client)
    assert vz > 0.0 and vx < 0.5 and abs(vy) < 1e-12
    assert 0.5 - vx == pytest.approx(0.1 * (vz + 1.0), rel=0.02)
    assert spin[1] > 0.0            # the friction at its bottom spins it forward


def test_two_balls_pushing_on_one_link_at_once_are_refused(client):
    """Two balls striking the paddle in the same step push along lines the joint couples (a
    stack): refused, naming ``pairs``."""
    body, ball = paddle(client, 1e-3)
    second = pybullet.createMultiBody(MASS, pybullet.createCollisionShape(
        pybullet.GEOM_SPHERE, radius=R, physicsClientId=client),
        basePosition=(0.15, 0.0, 0.005 + R + 0.002), physicsClientId=client)
    pybullet.resetBaseVelocity(second, (0.0, 0.0, -1.0), physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, (body, 0), STEEL), (second, (body, 0), STEEL)])
    with pytest.raises(cs.InputError) as refused:
        for _ in range(10):
            coupled.step()
    assert refused.value.field == 'pairs'
