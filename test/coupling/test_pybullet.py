"""The coupling in PyBullet (``contact_sim.coupling.pybullet``): the README's steel ball dropped
and thrown at 1/240 s and 1 ms, Hunt-Crossley, two free spheres, friction, bad input."""
import numpy as np
import pytest

import contact_sim as cs

import pybullet
from contact_sim.coupling.pybullet import CoupledContacts  # noqa: E402

G = 9.81
R = 0.0127
STEEL = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=R,
                                  damping_factor=8.87e5)
HUNT = cs.Contact(cs.HUNT_CROSSLEY, STEEL.stiffness, 0.08 * STEEL.stiffness)
MASS = float(cs.sphere_mass(cs.MATERIALS['steel'].density, R))
SPEEDS = np.geomspace(0.05, 10.0, 12)
PHASES = np.arange(8) / 8.0
STEPS = [1.0 / 240.0, 1e-3]


@pytest.fixture
def client():
    c = pybullet.connect(pybullet.DIRECT)
    yield c
    pybullet.disconnect(c)


def scene(client, dt, height, gravity=G, mass=MASS, radius=R, x=0.0):
    pybullet.resetSimulation(physicsClientId=client)
    pybullet.setGravity(0, 0, -gravity, physicsClientId=client)
    pybullet.setTimeStep(dt, physicsClientId=client)
    floor = pybullet.createMultiBody(0, pybullet.createCollisionShape(
        pybullet.GEOM_PLANE, physicsClientId=client), physicsClientId=client)
    ball = sphere(client, mass, radius, (x, 0.0, height + radius))
    return floor, ball


def sphere(client, mass, radius, position):
    body = pybullet.createMultiBody(mass, pybullet.createCollisionShape(
        pybullet.GEOM_SPHERE, radius=radius, physicsClientId=client),
        basePosition=position, physicsClientId=client)
    pybullet.changeDynamics(body, -1, linearDamping=0, angularDamping=0, physicsClientId=client)
    return body


def velocity(client, body):
    lin, ang = pybullet.getBaseVelocity(body, physicsClientId=client)
    return np.asarray(lin), np.asarray(ang)


@pytest.fixture(scope='module')
def exact_drop():
    return cs.simulate_drop(STEEL, MASS, height=1.0)


@pytest.mark.slow
@pytest.mark.parametrize('dt', STEPS)
def test_drop_of_the_readme_ball(client, dt, exact_drop):
    floor, ball = scene(client, dt, 1.0)
    coupled = CoupledContacts(client, [(ball, floor, STEEL)], friction=0.3)
    rest_from = exact_drop.permanent_contact_time + 0.1
    steps = int(round((rest_from + 10.0) / dt))
    heights, times = np.empty(steps), np.empty(steps)
    for i in range(steps):
        coupled.step()
        heights[i] = pybullet.getBasePositionAndOrientation(
            ball, physicsClientId=client)[0][2] - R
        times[i] = coupled.time
    touch = [i.time for i in coupled.impacts]
    apex = [heights[(times > touch[k]) & (times < touch[k + 1])].max() for k in range(10)]
    for k, (h, h_exact) in enumerate(zip(apex, exact_drop.apex_heights)):
        assert abs(h - h_exact) <= max(0.01 * h_exact, coupled.impacts[k].speed_out * dt)
    assert all(b < a for a, b in zip(apex, apex[1:]))
    z0 = STEEL.static_penetration(MASS * G)
    assert np.max(np.abs(-heights[times > rest_from] - z0)) < 1e-6


@pytest.mark.parametrize('dt', STEPS)
@pytest.mark.parametrize('contact', [STEEL, HUNT], ids=['azad_featherstone', 'hunt_crossley'])
def test_throws_at_every_phase_of_the_step(client, dt, contact):
    exact = cs.restitution(contact, MASS, SPEEDS)
    for speed, e in zip(SPEEDS, exact):
        for phase in PHASES:
            floor, ball = scene(client, dt, speed * dt * (3.0 + phase), gravity=0.0)
            pybullet.resetBaseVelocity(ball, (0, 0, -speed), physicsClientId=client)
            coupled = CoupledContacts(client, [(ball, floor, contact)])
            for _ in range(8):
                coupled.step()
            assert len(coupled.impacts) == 1
            e_host = velocity(client, ball)[0][2] / speed
            assert abs(e_host - e) < 0.005, (speed, phase, e_host, e)
            assert abs(coupled.impacts[0].restitution - e) < 0.005


def test_two_free_spheres_head_on(client):
    r2, m2, dt = 0.02, 0.5, 1e-3
    contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'steel', radius=R,
                                        plate_radius=r2, damping_factor=8.87e5)
    pybullet.resetSimulation(physicsClientId=client)
    pybullet.setGravity(0, 0, 0, physicsClientId=client)
    pybullet.setTimeStep(dt, physicsClientId=client)
    a = sphere(client, MASS, R, (0.0, 0.0, 0.0))
    b = sphere(client, m2, r2, (R + r2 + 0.0031, 0.0, 0.0))
    pybullet.resetBaseVelocity(a, (2.0, 0, 0), physicsClientId=client)
    pybullet.resetBaseVelocity(b, (-0.5, 0, 0), physicsClientId=client)
    coupled = CoupledContacts(client, [(a, b, contact)])
    for _ in range(12):
        coupled.step()
    va, vb = velocity(client, a)[0][0], velocity(client, b)[0][0]
    momentum = MASS * 2.0 - m2 * 0.5
    assert abs(MASS * va + m2 * vb - momentum) <= 1e-12 * abs(momentum)
    e = float(cs.restitution(contact, MASS * m2 / (MASS + m2), 2.5))
    assert (vb - va) / 2.5 == pytest.approx(e, abs=0.005)


@pytest.mark.parametrize('friction, regime', [(0.9, 'stick'), (0.05, 'slip')])
def test_oblique_impact_with_friction(client, friction, regime):
    dt, vn, vt = 1e-3, 1.0, 0.3
    floor, ball = scene(client, dt, vn * dt * 3.4, gravity=0.0)
    pybullet.resetBaseVelocity(ball, (vt, 0, -vn), physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, floor, STEEL)], friction=friction)
    for _ in range(10):
        coupled.step()
    e = float(cs.restitution(STEEL, MASS, vn))
    expected = 5.0 / 7.0 * vt if regime == 'stick' else vt - friction * (1.0 + e) * vn
    lin, ang = velocity(client, ball)
    assert lin[0] == pytest.approx(expected, rel=0.02)
    assert ang[1] == pytest.approx(2.5 * (vt - expected) / R, rel=0.02)


def test_bad_input_names_its_field(client):
    floor, ball = scene(client, 1e-3, 0.1)
    box = pybullet.createMultiBody(1.0, pybullet.createCollisionShape(
        pybullet.GEOM_BOX, halfExtents=(0.1, 0.1, 0.1), physicsClientId=client),
        basePosition=(1, 1, 1), physicsClientId=client)
    static = pybullet.createMultiBody(0.0, pybullet.createCollisionShape(
        pybullet.GEOM_SPHERE, radius=0.01, physicsClientId=client),
        basePosition=(0, 1, 1), physicsClientId=client)
    for pairs in ([(ball, 99, STEEL)], [(box, floor, STEEL)], [(ball, floor, 'steel')],
                  [(static, floor, STEEL)], [], None, [(ball, floor)]):
        with pytest.raises(cs.InputError) as refused:
            CoupledContacts(client, pairs)
        assert refused.value.field == 'pairs', pairs
    with pytest.raises(cs.InputError) as refused:
        CoupledContacts(client, [(ball, floor, STEEL)], friction=-1.0)
    assert refused.value.field == 'friction'


def test_sub_steps_are_a_step_the_coupling_cannot_serve(client):
    floor, ball = scene(client, 1e-3, 0.1)
    pybullet.setPhysicsEngineParameter(numSubSteps=4, physicsClientId=client)
    coupled = CoupledContacts(client, [(ball, floor, STEEL)])
    with pytest.raises(cs.InputError) as refused:
        coupled.step()
    assert refused.value.field == 'numSubSteps'
