"""The audit of a user's URDF in PyBullet: the e(v) it reports for a sphere link is what PyBullet
gives that URDF's ball (this test's own throw of the file as written, at a plane of restitution
1), and a link that is not a sphere, or a file that does not load, is refused naming it."""
import pytest

from contact_sim.export import audit_link, link_contact
from contact_sim.validation import InputError

import pybullet as p  # noqa: E402

INERTIAL = ('<inertial><mass value="{mass}"/><inertia ixx="4e-6" iyy="4e-6" izz="4e-6" ixy="0" '
            'ixz="0" iyz="0"/></inertial>')
LINK = ('<link name="ball"><contact>{contact}</contact>' + INERTIAL.format(mass=0.0673549)
        + '<collision><geometry><sphere radius="0.0127"/></geometry></collision></link>')
BALL = '<?xml version="1.0"?><robot name="ball">' + LINK + '</robot>'
ARM = ('<?xml version="1.0"?><robot name="arm"><link name="box">' + INERTIAL.format(mass=0.5)
       + '<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>' + LINK
       + '<joint name="j" type="fixed"><parent link="box"/><child link="ball"/>'
       '<origin xyz="0 0 0.5"/></joint></robot>')
SOFT = '<restitution value="0.3"/><stiffness value="400"/><damping value="0.5"/>'
RIGID = '<restitution value="0.7"/>'


def thrown(path, speed, timestep):
    """This test's own throw of the URDF's ball (its base link) at a plane of restitution 1,
    gravity off, straight down at ``speed`` (m/s)."""
    client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, 0, physicsClientId=client)
        p.setTimeStep(timestep, physicsClientId=client)
        plane = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client),
                                  physicsClientId=client)
        p.changeDynamics(plane, -1, restitution=1.0, physicsClientId=client)
        ball = p.loadURDF(str(path), [0, 0, 0.06], physicsClientId=client)
        p.changeDynamics(ball, -1, linearDamping=0, angularDamping=0, physicsClientId=client)
        p.resetBaseVelocity(ball, [0, 0, -speed], physicsClientId=client)
        while True:
            p.stepSimulation(physicsClientId=client)
            vz = p.getBaseVelocity(ball, physicsClientId=client)[0][2]
            if vz > 0 and p.getBasePositionAndOrientation(ball, physicsClientId=client)[0][2] > 0.06:
                return vz / speed
    finally:
        p.disconnect(physicsClientId=client)


@pytest.mark.parametrize('contact, timestep', [(SOFT, 1e-3), (RIGID, 1.0 / 240.0)])
def test_audit_gives_what_the_urdf_gives(tmp_path, contact, timestep):
    path = tmp_path / 'ball.urdf'
    path.write_text(BALL.format(contact=contact))
    link = link_contact(path, 'ball', timestep)
    assert (link.radius, link.mass) == (0.0127, 0.0673549)
    assert (link.stiffness is None) == (contact == RIGID)
    for speed, said in zip([0.5, 3.0], audit_link(link, [0.5, 3.0])):
        assert abs(thrown(path, speed, timestep) - said) < 0.01


def test_a_sphere_link_of_a_robot_is_read(tmp_path):
    path = tmp_path / 'arm.urdf'
    path.write_text(ARM.format(contact=SOFT))
    link = link_contact(path, 'ball', 1e-3)
    assert (link.radius, link.mass, link.restitution, link.stiffness, link.damping) == (
        0.0127, 0.0673549, 0.3, 400.0, 0.5)


@pytest.mark.parametrize('link', ['box', 'nope'])
def test_a_link_that_is_not_a_sphere_is_refused(tmp_path, link):
    path = tmp_path / 'arm.urdf'
    path.write_text(ARM.format(contact=SOFT))
    with pytest.raises(InputError) as error:
        link_contact(path, link)
    assert error.value.field == 'link'


@pytest.mark.parametrize('text', [None, '<robot name="x"><link'])
def test_a_file_that_does_not_load_is_refused(tmp_path, text):
    path = tmp_path / 'ball.urdf'
    if text is not None:
        path.write_text(text)
    with pytest.raises(InputError) as error:
        link_contact(path, 'ball')
    assert error.value.field == 'model'
