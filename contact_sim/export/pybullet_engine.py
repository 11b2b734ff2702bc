"""PyBullet: contactStiffness/contactDamping make a linear spring-damper that Bullet's solver
steps with its own losses, so the engine itself is run: a free sphere thrown at a plane at each
speed, gravity off, restitution 0 (the spring-damper does the bounce).

contactStiffness = m w^2 with w the target's contact frequency, lowered until a step is at most
0.05 rad of it; contactDamping = 2 zeta m w, with zeta fitted to the measured e."""
import numpy as np

from contact_sim.export.common import (EngineFit, fit_minimax, linear_contact_note, require_timestep,
                                        resolved_frequency)
STEPS_PER_RADIAN = 20.0    # w dt <= 0.05: e then moves < 0.01 with the impact's phase
PHASES = 4                 # start offsets within one step, averaged
START_GAP = 0.03           # m: the ball starts beyond Bullet's contact margins


def _pybullet():
    import pybullet   # optional: pip install 'contact_sim[engines]'
    return pybullet


def dynamics(stiffness, damping):
    """The ``changeDynamics`` keyword arguments of the ball."""
    return {'restitution': 0.0, 'contactStiffness': stiffness, 'contactDamping': damping}


def throw(client, radius, mass, speed, gap, timestep, kwargs, ground=None):
    """(e, contact duration in s, peak normal force in N) of one throw at ``speed`` (m/s) in
    the PyBullet ``client``, the ball starting ``gap`` (m) above a plane, at ``timestep`` (s),
    with ``changeDynamics(**kwargs)`` on the ball (and ``ground`` on the plane, if given); the
    duration counts the steps with a contact point of positive normal force."""
    p = _pybullet()
    p.resetSimulation(physicsClientId=client)
    p.setGravity(0, 0, 0, physicsClientId=client)
    p.setTimeStep(timestep, physicsClientId=client)
    plane = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client),
                              physicsClientId=client)
    if ground:
        p.changeDynamics(plane, -1, physicsClientId=client, **ground)
    ball = p.createMultiBody(mass, p.createCollisionShape(p.GEOM_SPHERE, radius=radius,
                                                          physicsClientId=client),
                             basePosition=[0, 0, radius + gap], physicsClientId=client)
    p.changeDynamics(ball, -1, linearDamping=0.0, angularDamping=0.0, physicsClientId=client,
                     **kwargs)
    p.resetBaseVelocity(ball, [0, 0, -speed], physicsClientId=client)
    touching, peak = 0, 0.0
    for _ in range(1_000_000):
        p.stepSimulation(physicsClientId=client)
        force = sum(point[9] for point in p.getContactPoints(ball, physicsClientId=client))
        if force > 0.0:
            touching, peak = touching + 1, max(peak, force)
        height = p.getBasePositionAndOrientation(ball, physicsClientId=client)[0][2]
        vz = p.getBaseVelocity(ball, physicsClientId=client)[0][2]
        if vz > 0.0 and height > radius + gap:
            return vz / speed, touching * timestep, peak
    raise ArithmeticError(f'PyBullet did not rebound at {speed:g} m/s')   # never in tests


def measure_contact(radius, mass, speeds, timestep, kwargs, ground=None):
    """PyBullet's (e, duration, peak force) at each of ``speeds`` (m/s), an array (n, 3), the
    mean over ``PHASES`` start offsets within one step (s), with ``changeDynamics(**kwargs)``
    on the ball and ``ground`` on the plane."""
    p = _pybullet()
    client = p.connect(p.DIRECT)
    try:
        fractions = (np.arange(PHASES) + 0.5) / PHASES
        return np.array([np.mean([throw(client, radius, mass, v, START_GAP + f * v * timestep,
                                        timestep, kwargs, ground) for f in fractions], axis=0)
                         for v in speeds])
    finally:
        p.disconnect(physicsClientId=client)


def measure(radius, mass, speeds, timestep, kwargs, ground=None):
    """PyBullet's e at each of ``speeds`` (m/s) (``measure_contact``)."""
    return measure_contact(radius, mass, speeds, timestep, kwargs, ground)[:, 0]


def export_pybullet(target, timestep):
    """PyBullet parameters for ``target`` (``common.Target``) at ``timestep`` (s), and the e(v)
    PyBullet gives with them (measured).

    Returns
    -------
    EngineFit
        The parameters, the ``changeDynamics`` call, the measured e(v) and what the contact's
        duration and depth become.
    """
    timestep = require_timestep(timestep)
    w = resolved_frequency(target, timestep, STEPS_PER_RADIAN)
    stiffness = target.mass * w * w

    def kwargs(zeta):
        return dynamics(stiffness, 2.0 * zeta * target.mass * w)

    def engine_e(zeta):
        return measure(target.radius, target.mass, target.speeds, timestep, kwargs(zeta))
    zeta, _ = fit_minimax(engine_e, target, 0.0, 1.0)
    e, duration, peak = measure_contact(target.radius, target.mass, target.speeds, timestep,
                                        kwargs(zeta)).T
    params = dict(kwargs(zeta), timestep=timestep)
    arguments = ', '.join(f'{key}={value!r}' for key, value in kwargs(zeta).items())
    snippet = (f'p.setTimeStep({timestep!r})\n'
               f'p.changeDynamics(ball_id, -1, {arguments})')
    return EngineFit(params, snippet, e, 'measured', linear_contact_note(target, w), duration,
                     peak)


def version():
    """The installed PyBullet's API version (pybullet has no ``__version__``)."""
    return str(_pybullet().getAPIVersion())
