"""MuJoCo: its soft contact depends on ``solref``, ``solimp``, the time step and the integrator,
so the engine itself is run: a free sphere thrown at a plane at each speed, gravity off (the
claim), then dropped and left to rest with gravity on (``scene``).

With ``solref = (-K, -B)`` (the direct form) and ``solimp`` with dmin = dmax, the penetration r
obeys r'' = -d (B r' + K r) (the constraint force never pulls), so e does not depend on the speed
nor on the mass: one linear choice.  K = w^2 with w the target's contact frequency, lowered until
a step is at most 0.1 rad of it; B = 2 zeta w, with zeta fitted to the measured e from 0 up to
``max_zeta``, past critical damping as far as the step stays stable.  The ball's geom gets
``priority="1"``, so that a floor at priority 0 does not mix its own solref/solimp in."""
import math

import numpy as np

from contact_sim.export import scene
from contact_sim.export.common import (EngineFit, fit_minimax, linear_contact_note, require_timestep,
                                        resolved_frequency, target_frequency)

STEPS_PER_RADIAN = 10.0           # w dt <= 0.1: e then moves < 0.01 with the impact's phase
SOLIMP = (0.95, 0.95, 0.001, 0.5, 2.0)   # constant impedance: the contact stays linear
INTEGRATOR = 'Euler'
PHASES = 4                        # start offsets within one step, averaged
PRIORITY = 1                      # the ball's geom priority: its contact wins over the floor's
UNSTABLE = 1.5                    # e above this: the step gave the ball energy, unstable
STABLE_DAMPING = 1.0              # B dt at most this: unstable near 2 (zeta 10 at w dt 0.1)
# what in a user's model changes the claim (the throw has none of these)
PITFALLS = ('a floor geom with priority >= 1 (the ball\'s solref/solimp are then mixed with '
            'the floor\'s, by solmix, or ignored)',
            'the floor\'s own margin or gap, or the ball\'s (MuJoCo uses the larger margin: 1 mm '
            'moves e by several hundredths)',
            'a second <option> element: put timestep and integrator in the model\'s own <option>, '
            'a second one overrides the first\'s attributes',
            'other geoms or an <inertial> on the ball\'s body change nothing here (solref in '
            'this form is per unit mass), but a softer or moving floor does')


def _mujoco():
    import mujoco   # optional: pip install 'contact_sim[engines]'
    return mujoco


def geom_attributes(solref, solimp):
    """The MJCF attributes ``solref="..." solimp="..."`` of the ball's geom."""
    return (f'solref="{solref[0]:.9g} {solref[1]:.9g}" '
            f'solimp="{" ".join(f"{x:g}" for x in solimp)}" priority="{PRIORITY}"')


def model_xml(radius, mass, timestep, ball, integrator=INTEGRATOR, floor='', gravity=False):
    """The MJCF of the throw: a free sphere of ``radius`` (m) and ``mass`` (kg) over a plane,
    gravity off (on with ``gravity``), at ``timestep`` (s) with ``integrator``; ``ball`` and
    ``floor`` are the geoms' contact attributes (MJCF text)."""
    g = f'0 0 {-scene.GRAVITY:g}' if gravity else '0 0 0'
    return (f'<mujoco><option timestep="{timestep!r}" gravity="{g}" integrator="{integrator}"/>'
            f'<worldbody><geom name="plane" type="plane" size="1 1 0.1" {floor}/>'
            f'<body name="ball" pos="0 0 1"><freejoint/><geom name="ball" type="sphere" '
            f'size="{radius!r}" mass="{mass!r}" {ball}/></body></worldbody></mujoco>')


def load(xml):
    """The ``MjModel`` of ``xml``, MuJoCo's warnings kept out of MUJOCO_LOG.TXT (``quiet``)."""
    quiet()
    return _mujoco().MjModel.from_xml_string(xml)


def quiet():
    """Route MuJoCo's warnings to Python's ``warnings`` instead of MUJOCO_LOG.TXT in the
    working directory (MuJoCo writes the file only when no user handler is set)."""
    import warnings
    mujoco = _mujoco()
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(
            lambda text: warnings.warn(f'MuJoCo: {text}', RuntimeWarning, stacklevel=2))


def throw(model, radius, speed, gap, patience, margin=0.0):
    """(e, contact duration in s, peak normal force in N) of one throw at ``speed`` (m/s), the
    ball starting ``gap`` (m) above the plane: e is the separation speed at the plate (the ball
    back at the surface, moving up, no force) over the impact speed there (with gravity, the
    free flight's own gain and loss taken out), 0 if the ball has not left the plate
    ``patience`` steps after it touched.  The duration is the
    steps with a contact force > 0 times the step.  With a contact ``margin`` (m) the plate's
    surface is that much higher: the throw starts and ends beyond it."""
    mujoco = _mujoco()
    data = mujoco.MjData(model)
    surface = radius + margin
    data.qpos[2] = surface + gap
    data.qvel[2] = -speed
    g = -float(model.opt.gravity[2])
    impact = math.sqrt(speed * speed + 2.0 * g * gap)
    force = np.zeros(6)
    touching, peak, touched = 0, 0.0, None
    for step in range(10_000_000):
        mujoco.mj_step(model, data)
        pushing = False
        if data.ncon:
            mujoco.mj_contactForce(model, data, 0, force)
            pushing = force[0] > 0.0
            if pushing:
                touching, peak = touching + 1, max(peak, float(force[0]))
                touched = step if touched is None else touched
        if data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number:   # MuJoCo reset the data
            raise ArithmeticError(f'MuJoCo went unstable at {speed:g} m/s (a NaN or huge '
                                  'acceleration): this contact and step cannot be run')
        z, vz = float(data.qpos[2]), float(data.qvel[2])
        if vz > 0.0 and (g == 0.0 and z > surface + gap
                         or touched is not None and z >= surface and not pushing):   # lift-off
            e = math.sqrt(vz * vz + 2.0 * g * (z - surface)) / impact
            if e > UNSTABLE:   # a passive contact cannot give the ball this energy
                raise ArithmeticError(f'MuJoCo went unstable at {speed:g} m/s (the ball came '
                                      f'back {e:.3g} times as fast): this contact and step '
                                      'cannot be run')
            return e, touching * model.opt.timestep, peak
        if touched is not None and step - touched > patience:   # it stays on the plate
            return 0.0, touching * model.opt.timestep, peak
    raise ArithmeticError(f'MuJoCo did not rebound at {speed:g} m/s')   # never in tests


def patience_steps(frequency, timestep):
    """Steps of 50 periods of a contact of angular ``frequency`` (rad/s) at ``timestep`` (s)."""
    return int(100.0 * math.pi / (frequency * timestep)) + 10


def rest_sag(model, radius, patience):
    """The ball's depth in the plate at rest (m): dropped from touching it, with gravity, the
    mean depth over the last tenth of ``patience`` steps (inf if it fell through)."""
    mujoco = _mujoco()
    data = mujoco.MjData(model)
    data.qpos[2] = radius
    depths = []
    for step in range(patience):
        mujoco.mj_step(model, data)
        if data.qpos[2] < -radius:
            return math.inf
        if step >= patience - patience // 10 - 1:
            depths.append(radius - float(data.qpos[2]))
    return float(np.mean(depths))


def measure_contact(radius, mass, speeds, timestep, ball, integrator=INTEGRATOR, floor='',
                    gravity=False, patience=100_000, per_phase=False, margin=0.0):
    """MuJoCo's (e, duration, peak force) at each of ``speeds`` (m/s), an array (n, 3), the
    mean over ``PHASES`` start offsets within one step (s) (each, (n, PHASES, 3), with
    ``per_phase``), with the geoms' contact attributes ``ball`` and ``floor`` (MJCF text),
    gravity off (on with ``gravity``), the pair's contact ``margin`` (m) as ``throw`` says."""
    model = load(model_xml(radius, mass, timestep, ball, integrator, floor, gravity))
    offsets = (np.arange(PHASES) + 0.5) / PHASES
    rows = np.array([[throw(model, radius, v, f * v * timestep, patience, margin)
                      for f in offsets] for v in speeds])
    return rows if per_phase else rows.mean(axis=1)


def measure(radius, mass, speeds, timestep, ball, integrator=INTEGRATOR, floor='', margin=0.0):
    """MuJoCo's e at each of ``speeds`` (m/s), gravity off (``measure_contact``)."""
    return measure_contact(radius, mass, speeds, timestep, ball, integrator, floor,
                           margin=margin)[:, 0]


def max_zeta(frequency, timestep):
    """The largest damping ratio the export tries at ``frequency`` (rad/s) and ``timestep``
    (s): B dt = 2 zeta w dt at most ``STABLE_DAMPING``, and at most 50."""
    return min(STABLE_DAMPING / (2.0 * frequency * timestep), 50.0)


def export_mujoco(target, timestep):
    """MuJoCo parameters for ``target`` (``common.Target``) at ``timestep`` (s), the e(v)
    MuJoCo gives with them (measured, gravity off), and the claim checked with gravity.

    Returns
    -------
    EngineFit
        The parameters, the MJCF ``<geom>``, the measured e(v), what the contact's duration
        and depth become, the e the damping range reaches and the ``scene.Scene``.

    Raises
    ------
    InputError
        Keyed ``timestep``: out of range, or the contact cannot hold the ball up.
    """
    timestep = require_timestep(timestep)
    w = resolved_frequency(target, timestep, STEPS_PER_RADIAN)

    def solref(zeta):
        return (-w * w, -2.0 * zeta * w)

    def engine_e(zeta):
        return measure(target.radius, target.mass, target.speeds, timestep,
                       geom_attributes(solref(zeta), SOLIMP))
    top = max_zeta(w, timestep)
    zeta, _ = fit_minimax(engine_e, target, 0.0, top)
    ball = geom_attributes(solref(zeta), SOLIMP)
    e, duration, peak = measure_contact(target.radius, target.mass, target.speeds, timestep,
                                        ball).T
    reach = (float(np.mean(engine_e(top))), float(np.mean(engine_e(0.0))))
    patience = patience_steps(w, timestep)
    model = load(model_xml(target.radius, target.mass, timestep, ball, gravity=True))
    sag = rest_sag(model, target.radius, patience)
    with_gravity = (measure_contact(target.radius, target.mass, target.speeds, timestep, ball,
                                    gravity=True, patience=patience, per_phase=True)[:, :, 0]
                    if sag < target.radius else e)
    floor = 1.0 / (STEPS_PER_RADIAN * target_frequency(target))
    checked = scene.assess(target, e, with_gravity, sag, timestep, floor, 'measured', 'MuJoCo',
                           scene.GRAVITY / (w * w))
    params = {'solref': list(solref(zeta)), 'solimp': list(SOLIMP), 'priority': PRIORITY,
              'timestep': timestep, 'integrator': INTEGRATOR}
    snippet = (f'<option timestep="{timestep:.9g}" integrator="{INTEGRATOR}"/>\n'
               f'<geom name="ball" type="sphere" size="{target.radius:g}" '
               f'mass="{target.mass:.6g}" {ball}/>')
    return EngineFit(params, snippet, e, 'measured', linear_contact_note(target, w), duration,
                     peak, reach=reach, scene=checked, pitfalls=PITFALLS)


def version():
    """The installed MuJoCo's version."""
    return _mujoco().__version__
