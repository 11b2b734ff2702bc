"""PyBullet: contactStiffness/contactDamping make a linear spring-damper that Bullet's solver
steps with its own losses, so the engine itself is run: a free sphere thrown at a plane at each
speed, gravity off, restitution 0 (the spring-damper does the bounce), no linear or angular
damping (the snippet sets both to 0: PyBullet's defaults, 0.04, slow the ball in flight); then
the ball is dropped and left to rest with gravity on (``scene``).

contactStiffness = m w^2 with w the target's contact frequency, lowered until a step is at most
0.05 rad of it; contactDamping = 2 zeta m w, with zeta fitted to the measured e from 0 to
``MAX_ZETA`` (Bullet steps the spring-damper implicitly: past critical damping is stable)."""
import math

import numpy as np

from contact_sim.export import scene
from contact_sim.export.common import (EngineFit, fit_minimax, linear_contact_note, require_timestep,
                                        resolved_frequency, target_frequency)
STEPS_PER_RADIAN = 20.0    # w dt <= 0.05: e then moves < 0.01 with the impact's phase
PHASES = 4                 # start offsets within one step, averaged
START_GAP = 0.03           # m: the ball starts beyond Bullet's contact margins
MAX_ZETA = 50.0            # the largest damping ratio tried
PITFALLS = ('contactStiffness and contactDamping are in N/m and N s/m: they hold for the '
            'printed mass and step only (another mass or step changes e; export again)',
            'the ball\'s restitution stays 0 and the plane\'s is PyBullet\'s default; '
            'Bullet multiplies the two bodies\' restitutions',
            'linearDamping and angularDamping are set to 0 here; PyBullet\'s defaults (0.04) '
            'slow the ball in flight and lower e')


def _pybullet():
    import pybullet   # optional: pip install 'contact_sim[engines]'
    return pybullet


def dynamics(stiffness, damping):
    """The ``changeDynamics`` keyword arguments of the ball (PyBullet's flight damping off)."""
    return {'restitution': 0.0, 'contactStiffness': stiffness, 'contactDamping': damping,
            'linearDamping': 0.0, 'angularDamping': 0.0}


def throw(client, radius, mass, speed, gap, timestep, kwargs, ground=None, gravity=False,
          patience=1_000_000):
    """(e, contact duration in s, peak normal force in N) of one throw at ``speed`` (m/s) in
    the PyBullet ``client``, the ball starting ``gap`` (m) above a plane, at ``timestep`` (s),
    with ``changeDynamics(**kwargs)`` on the ball (and ``ground`` on the plane, if given); the
    duration counts the steps with a contact point of positive normal force.  e is the
    separation speed at the plate over the impact speed there (with gravity, the free flight
    taken out), 0 if the ball has not left the plate
    ``patience`` steps after it touched."""
    p = _pybullet()
    g = scene.GRAVITY if gravity else 0.0
    ball = _scene(client, radius, mass, radius + gap, timestep, kwargs, ground, g)
    p.resetBaseVelocity(ball, [0, 0, -speed], physicsClientId=client)
    impact = math.sqrt(speed * speed + 2.0 * g * gap)
    touching, peak, touched = 0, 0.0, None
    for step in range(10_000_000):
        p.stepSimulation(physicsClientId=client)
        force = sum(point[9] for point in p.getContactPoints(ball, physicsClientId=client))
        if force > 0.0:
            touching, peak = touching + 1, max(peak, force)
            touched = step if touched is None else touched
        height = p.getBasePositionAndOrientation(ball, physicsClientId=client)[0][2]
        vz = p.getBaseVelocity(ball, physicsClientId=client)[0][2]
        if g == 0.0 and vz > 0.0 and height > radius + gap:
            return vz / speed, touching * timestep, peak
        if touched is not None and vz > 0.0 and height >= radius and force <= 0.0:
            rebound = math.sqrt(vz * vz + 2.0 * g * (height - radius))   # lift-off
            return rebound / impact, touching * timestep, peak
        if touched is not None and step - touched > patience:   # it stays on the plate
            return 0.0, touching * timestep, peak
    raise ArithmeticError(f'PyBullet did not rebound at {speed:g} m/s')   # never in tests


def _scene(client, radius, mass, height, timestep, kwargs, ground, gravity):
    """The ball's body id in a fresh scene: a plane, the ball at ``height`` (m) above it."""
    p = _pybullet()
    p.resetSimulation(physicsClientId=client)
    p.setGravity(0, 0, -gravity, physicsClientId=client)
    p.setTimeStep(timestep, physicsClientId=client)
    plane = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client),
                              physicsClientId=client)
    if ground:
        p.changeDynamics(plane, -1, physicsClientId=client, **ground)
    ball = p.createMultiBody(mass, p.createCollisionShape(p.GEOM_SPHERE, radius=radius,
                                                          physicsClientId=client),
                             basePosition=[0, 0, height], physicsClientId=client)
    p.changeDynamics(ball, -1, physicsClientId=client,
                     **{'linearDamping': 0.0, 'angularDamping': 0.0, **kwargs})
    return ball


def rest_sag(radius, mass, timestep, kwargs, patience):
    """The ball's depth in the plate at rest (m): set on it with gravity, the mean depth over
    the last tenth of ``patience`` steps (inf if it fell through)."""
    p = _pybullet()
    client = p.connect(p.DIRECT)
    try:
        ball = _scene(client, radius, mass, radius, timestep, kwargs, None, scene.GRAVITY)
        depths = []
        for step in range(patience):
            p.stepSimulation(physicsClientId=client)
            height = p.getBasePositionAndOrientation(ball, physicsClientId=client)[0][2]
            if height < -radius:
                return math.inf
            if step >= patience - patience // 10 - 1:
                depths.append(radius - height)
        return float(np.mean(depths))
    finally:
        p.disconnect(physicsClientId=client)


def measure_contact(radius, mass, speeds, timestep, kwargs, ground=None, gravity=False,
                    patience=1_000_000, per_phase=False):
    """PyBullet's (e, duration, peak force) at each of ``speeds`` (m/s), an array (n, 3), the
    mean over ``PHASES`` start offsets within one step (s) (each, (n, PHASES, 3), with
    ``per_phase``), with ``changeDynamics(**kwargs)`` on the ball and ``ground`` on the plane,
    gravity off (on with ``gravity``)."""
    p = _pybullet()
    client = p.connect(p.DIRECT)
    try:
        fractions = (np.arange(PHASES) + 0.5) / PHASES
        rows = np.array([[throw(client, radius, mass, v, START_GAP + f * v * timestep,
                                timestep, kwargs, ground, gravity, patience)
                          for f in fractions] for v in speeds])
        return rows if per_phase else rows.mean(axis=1)
    finally:
        p.disconnect(physicsClientId=client)


def measure(radius, mass, speeds, timestep, kwargs, ground=None):
    """PyBullet's e at each of ``speeds`` (m/s), gravity off (``measure_contact``)."""
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
    zeta, _ = fit_minimax(engine_e, target, 0.0, MAX_ZETA)
    e, duration, peak = measure_contact(target.radius, target.mass, target.speeds, timestep,
                                        kwargs(zeta)).T
    reach = (float(np.mean(engine_e(MAX_ZETA))), float(np.mean(engine_e(0.0))))
    patience = int(100.0 * math.pi / (w * timestep)) + 10   # 50 contact periods
    sag = rest_sag(target.radius, target.mass, timestep, kwargs(zeta), patience)
    with_gravity = (measure_contact(target.radius, target.mass, target.speeds, timestep,
                                    kwargs(zeta), gravity=True, patience=patience,
                                    per_phase=True)[:, :, 0]
                    if sag < target.radius else e)
    floor = 1.0 / (STEPS_PER_RADIAN * target_frequency(target))
    checked = scene.assess(target, e, with_gravity, sag, timestep, floor, 'measured',
                           'PyBullet', scene.GRAVITY / (w * w))
    params = dict(kwargs(zeta), timestep=timestep)
    arguments = ', '.join(f'{key}={value!r}' for key, value in kwargs(zeta).items())
    snippet = (f'p.setTimeStep({timestep!r})\n'
               f'p.changeDynamics(ball_id, -1, {arguments})\n'
               f'# for a ball of mass {target.mass:.6g} kg at this step only')
    return EngineFit(params, snippet, e, 'measured', linear_contact_note(target, w), duration,
                     peak, reach=reach, scene=checked, pitfalls=PITFALLS)


def version():
    """The installed PyBullet's API version (pybullet has no ``__version__``)."""
    return str(_pybullet().getAPIVersion())
