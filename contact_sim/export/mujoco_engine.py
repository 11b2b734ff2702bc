"""MuJoCo: its soft contact depends on ``solref``, ``solimp``, the time step and the integrator,
so the engine itself is run: a free sphere thrown at a plane at each speed, gravity off.

With ``solref = (-K, -B)`` (the direct form) and ``solimp`` with dmin = dmax, the penetration r
obeys r'' = -(B r' + K r) per unit mass (the constraint force never pulls), so e does not depend
on the speed: one linear choice.  K = w^2 with w the target's contact frequency, lowered until a
step is at most 0.1 rad of it; B = 2 zeta w, with zeta fitted to the measured e."""
from dataclasses import dataclass

import numpy as np

from contact_sim.export.common import (EngineFit, fit_minimax, linear_contact_note, require_timestep,
                                        resolved_frequency)
from contact_sim.validation import InputError

STEPS_PER_RADIAN = 10.0           # w dt <= 0.1: e then moves < 0.01 with the impact's phase
SOLIMP = (0.95, 0.95, 0.001, 0.5, 2.0)   # constant impedance: the contact stays linear
INTEGRATOR = 'Euler'
PHASES = 4                        # start offsets within one step, averaged


def _mujoco():
    import mujoco   # optional: pip install 'contact_sim[engines]'
    return mujoco


def geom_attributes(solref, solimp):
    """The MJCF attributes ``solref="..." solimp="..."`` of the ball's geom."""
    return (f'solref="{solref[0]:.9g} {solref[1]:.9g}" '
            f'solimp="{" ".join(f"{x:g}" for x in solimp)}"')


def model_xml(radius, mass, timestep, solref, solimp=SOLIMP, integrator=INTEGRATOR):
    """The MJCF of the throw: a free sphere of ``radius`` (m) and ``mass`` (kg) over a plane,
    gravity off, at ``timestep`` (s) with ``integrator``; the ball's geom carries the contact."""
    return (f'<mujoco><option timestep="{timestep!r}" gravity="0 0 0" integrator="{integrator}"/>'
            '<worldbody><geom name="plane" type="plane" size="1 1 0.1"/>'
            f'<body name="ball" pos="0 0 1"><freejoint/><geom name="ball" type="sphere" '
            f'size="{radius!r}" mass="{mass!r}" {geom_attributes(solref, solimp)}/></body>'
            '</worldbody></mujoco>')


def throw(model, radius, speed, gap):
    """(e, contact duration in s, peak normal force in N) of one throw at ``speed`` (m/s), the
    ball starting ``gap`` (m) above the plane: e is the rebound speed over ``speed`` once the
    ball is back above its start, the duration the steps with a contact force > 0 times the
    step."""
    mujoco = _mujoco()
    data = mujoco.MjData(model)
    data.qpos[2] = radius + gap
    data.qvel[2] = -speed
    force = np.zeros(6)
    touching, peak = 0, 0.0
    for _ in range(1_000_000):
        mujoco.mj_step(model, data)
        if data.ncon:
            mujoco.mj_contactForce(model, data, 0, force)
            if force[0] > 0.0:
                touching, peak = touching + 1, max(peak, float(force[0]))
        if data.qvel[2] > 0.0 and data.qpos[2] > radius + gap:
            return data.qvel[2] / speed, touching * model.opt.timestep, peak
    raise ArithmeticError(f'MuJoCo did not rebound at {speed:g} m/s')   # never in tests


def measure_contact(radius, mass, speeds, timestep, solref, solimp=SOLIMP,
                    integrator=INTEGRATOR):
    """MuJoCo's (e, duration, peak force) at each of ``speeds`` (m/s), an array (n, 3), the
    mean over ``PHASES`` start offsets within one step (s), with the geom ``solref``,
    ``solimp``."""
    model = _mujoco().MjModel.from_xml_string(
        model_xml(radius, mass, timestep, solref, solimp, integrator))
    offsets = (np.arange(PHASES) + 0.5) / PHASES
    return np.array([np.mean([throw(model, radius, v, f * v * timestep) for f in offsets],
                             axis=0) for v in speeds])


def measure(radius, mass, speeds, timestep, solref, solimp=SOLIMP, integrator=INTEGRATOR):
    """MuJoCo's e at each of ``speeds`` (m/s) (``measure_contact``): the e a user gets from
    the geom ``solref``, ``solimp``."""
    return measure_contact(radius, mass, speeds, timestep, solref, solimp, integrator)[:, 0]


def export_mujoco(target, timestep):
    """MuJoCo parameters for ``target`` (``common.Target``) at ``timestep`` (s), and the e(v)
    MuJoCo gives with them (measured).

    Returns
    -------
    EngineFit
        The parameters, the MJCF ``<geom>``, the measured e(v) and what the contact's
        duration and depth become.
    """
    timestep = require_timestep(timestep)
    w = resolved_frequency(target, timestep, STEPS_PER_RADIAN)

    def solref(zeta):
        return (-w * w, -2.0 * zeta * w)

    def engine_e(zeta):
        return measure(target.radius, target.mass, target.speeds, timestep, solref(zeta))
    zeta, _ = fit_minimax(engine_e, target, 0.0, 1.0)
    e, duration, peak = measure_contact(target.radius, target.mass, target.speeds, timestep,
                                        solref(zeta)).T
    params = {'solref': list(solref(zeta)), 'solimp': list(SOLIMP), 'timestep': timestep,
              'integrator': INTEGRATOR}
    snippet = (f'<option timestep="{timestep:g}" integrator="{INTEGRATOR}"/>\n'
               f'<geom name="ball" type="sphere" size="{target.radius:g}" '
               f'mass="{target.mass:.6g}" {geom_attributes(solref(zeta), SOLIMP)}/>')
    return EngineFit(params, snippet, e, 'measured', linear_contact_note(target, w), duration,
                     peak)


def version():
    """The installed MuJoCo's version."""
    return _mujoco().__version__


# MuJoCo's integrator enum -> its MJCF name
INTEGRATORS = {'mjINT_EULER': 'Euler', 'mjINT_RK4': 'RK4', 'mjINT_IMPLICIT': 'implicit',
               'mjINT_IMPLICITFAST': 'implicitfast'}


@dataclass(frozen=True)
class GeomContact:
    """What a user's MuJoCo model gives a sphere geom's contact: its radius (m), its body's mass
    (kg), ``solref``, ``solimp``, the model's time step (s) and integrator."""

    radius: float
    mass: float
    solref: tuple
    solimp: tuple
    timestep: float
    integrator: str

    def describe(self):
        """One line: the geom's contact as MuJoCo reads it."""
        return (f'solref = {list(self.solref)}, solimp = {list(self.solimp)}, timestep = '
                f'{self.timestep:g} s, integrator {self.integrator}, R = {self.radius:g} m, '
                f'm = {self.mass:.6g} kg')


def geom_contact(path, geom):
    """The contact of the sphere ``geom`` (a name) in the MJCF file ``path``.

    Raises
    ------
    InputError
        Keyed ``model`` if the file does not load, ``geom`` if the geom is not a sphere of it.
    """
    mujoco = _mujoco()
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as error:   # MuJoCo's parse and compile errors
        raise InputError('model', path, '{n[model]} = {value} does not load in MuJoCo: '
                         f'{str(error).strip()}', value=repr(str(path))) from None
    index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    if index < 0 or model.geom_type[index] != mujoco.mjtGeom.mjGEOM_SPHERE:
        raise InputError('geom', geom, '{n[geom]} = {value} is not a sphere geom of the model: '
                         'allowed the name of a sphere geom on a free body', value=repr(geom))
    integrator = mujoco.mjtIntegrator(model.opt.integrator).name
    if integrator not in INTEGRATORS:
        raise InputError('model', path, '{n[model]} = {value} uses the integrator '
                         f'{integrator}: allowed ' + ', '.join(INTEGRATORS.values()),
                         value=repr(str(path)))
    return GeomContact(float(model.geom_size[index][0]),
                       float(model.body_mass[model.geom_bodyid[index]]),
                       tuple(map(float, model.geom_solref[index])),
                       tuple(map(float, model.geom_solimp[index])),
                       float(model.opt.timestep), INTEGRATORS[integrator])


def audit(contact, speeds):
    """MuJoCo's e at ``speeds`` (m/s) of a ``GeomContact`` (a free sphere thrown at a plane at
    MuJoCo's defaults, gravity off, as ``measure``)."""
    return measure(contact.radius, contact.mass, speeds, contact.timestep, contact.solref,
                   contact.solimp, contact.integrator)
