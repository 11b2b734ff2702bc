"""The audit of a user's URDF in PyBullet: the contact a sphere link carries (its URDF
``<contact>``: restitution, stiffness, damping, as PyBullet reads them) and the e(v) PyBullet
gives it, the sphere thrown at a plane, gravity off.

Bullet multiplies the two bodies' restitutions; the plane here has restitution 1, so the link's
own value acts as written (against a ground of restitution r it is r times as much)."""
from dataclasses import dataclass
from pathlib import Path

from contact_sim.export import pybullet_engine
from contact_sim.export.common import require_timestep
from contact_sim.validation import InputError

DEFAULT_TIMESTEP = 1.0 / 240.0   # s: PyBullet's own default step
GROUND = {'restitution': 1.0}    # the plane's changeDynamics in the audit's throw


@dataclass(frozen=True)
class LinkContact:
    """What a user's URDF gives a sphere link's contact: radius (m), mass (kg), restitution,
    contactStiffness (N/m) and contactDamping (N s/m) (None where the URDF sets none: Bullet's
    rigid contact), and the time step (s) it is run at."""

    radius: float
    mass: float
    restitution: float
    stiffness: object
    damping: object
    timestep: float

    def dynamics(self):
        """The ``changeDynamics`` keyword arguments that give the ball this contact."""
        kwargs = {'restitution': self.restitution}
        if self.stiffness is not None:
            kwargs.update(contactStiffness=self.stiffness, contactDamping=self.damping)
        return kwargs

    def describe(self):
        """One line: the link's contact as PyBullet reads it."""
        contact = ('rigid (no <contact> stiffness)' if self.stiffness is None else
                   f'contactStiffness = {self.stiffness:g} N/m, contactDamping = '
                   f'{self.damping:g} N s/m')
        return (f'restitution = {self.restitution:g} (ground 1), {contact}, timestep = '
                f'{self.timestep:g} s, R = {self.radius:g} m, m = {self.mass:.6g} kg')


def link_contact(path, link, timestep=DEFAULT_TIMESTEP):
    """The contact of the sphere ``link`` (a name) in the URDF file ``path``, run at
    ``timestep`` (s).

    Raises
    ------
    InputError
        Keyed ``model`` if the file does not load in PyBullet, ``link`` if the link is not a
        sphere of it, ``timestep`` if out of range.
    """
    timestep = require_timestep(timestep)
    if not Path(path).is_file():
        raise InputError('model', path, '{n[model]} = {value} is not a file',
                         value=repr(str(path)))
    p = pybullet_engine._pybullet()
    client = p.connect(p.DIRECT)
    try:
        try:
            body = p.loadURDF(str(path), physicsClientId=client)
        except p.error:
            raise InputError('model', path, '{n[model]} = {value} does not load in PyBullet',
                             value=repr(str(path))) from None
        names = [p.getBodyInfo(body, physicsClientId=client)[0].decode()] + [
            p.getJointInfo(body, j, physicsClientId=client)[12].decode()
            for j in range(p.getNumJoints(body, physicsClientId=client))]
        index = names.index(link) - 1 if link in names else None
        shapes = () if index is None else p.getCollisionShapeData(body, index,
                                                                  physicsClientId=client)
        if not shapes or shapes[0][2] != p.GEOM_SPHERE:
            raise InputError('link', link, '{n[link]} = {value} is not a link of the model with '
                             'a sphere collision: allowed ' + ', '.join(names),
                             value=repr(link))
        info = p.getDynamicsInfo(body, index, physicsClientId=client)
    finally:
        p.disconnect(physicsClientId=client)
    stiffness, damping = float(info[9]), float(info[8])
    rigid = stiffness <= 0.0
    return LinkContact(float(shapes[0][3][0]), float(info[0]), float(info[5]),
                       None if rigid else stiffness, None if rigid else damping, timestep)


def audit_link(contact, speeds):
    """PyBullet's e at ``speeds`` (m/s) of a ``LinkContact``: a free sphere of its radius and
    mass with its contact, thrown at a plane of restitution 1, gravity off."""
    return pybullet_engine.measure(contact.radius, contact.mass, speeds, contact.timestep,
                                   contact.dynamics(), GROUND)
