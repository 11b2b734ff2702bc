"""Gazebo (ODE): kp/kd is a linear spring-damper F = kp x + kd xdot clamped at zero, a member of
eq. 1.  Gazebo is not run here: its e(v) is this library's exact restitution of that law, the
continuous law's (predicted), with gravity too (``contact_sim.impact.simulate_impact``).  ODE's
own step is not modelled; kp is lowered, as for the engines that are run, until a step is at
most 0.1 rad of the contact, where a step changes the continuous law's e by little."""
import numpy as np

from contact_sim.export import scene
from contact_sim.export.common import (EngineFit, fit_minimax, law_contact, law_restitution,
                                        linear_contact_note, require_timestep, resolved_frequency,
                                        target_frequency)
from contact_sim.model import LINEAR, Contact

STEPS_PER_RADIAN = 10.0   # as MuJoCo's: w dt <= 0.1
MAX_DAMPING_RATIO = 10.0  # kd up to 10 times critical
STATEMENT = ('Gazebo is not run: the e is the continuous law\'s (kp, kd integrated exactly); '
             'ODE\'s step is not modelled, kp is lowered so that a step is at most 0.1 rad of '
             'the contact')
PITFALLS = ('kp and kd are in N/m and N s/m: they hold for the printed mass only',
            'ODE\'s erp/cfm, a restitution_coefficient above 0 with a threshold below the '
            'impact speed, or a min_depth above 0 change the contact',
            'the other surface\'s kp/kd: ODE combines the two surfaces\' values')


def _with_gravity(kp, kd, mass, speeds):
    """e of the law kp, kd with gravity at ``speeds`` (m/s), 0 where the ball stays."""
    from contact_sim.impact import simulate_impact
    contact = Contact(LINEAR, kp, kd)
    return np.array([simulate_impact(contact, mass, float(v), gravity=scene.GRAVITY).restitution
                     for v in speeds])


def export_gazebo(target, timestep):
    """Gazebo (ODE) parameters for ``target`` (``common.Target``) at ``timestep`` (s).

    kp (N/m) gives the target's contact duration at the middle speed, lowered until a step is
    at most 0.1 rad of the contact; kd (N s/m) is fitted, minimax over the speeds, from 0 to
    ``MAX_DAMPING_RATIO`` times critical, on the exact e(v) of the linear spring-damper
    F = kp x + kd xdot clamped at zero; the restitution coefficient is 0 (the spring-damper
    does the bounce).  The claim is checked with gravity on the same law (predicted).

    Returns
    -------
    EngineFit
        The parameters, the SDFormat ``<surface>``, the predicted e(v) and what the contact's
        duration and depth become.

    Raises
    ------
    InputError
        Keyed ``timestep``: out of range, or the contact cannot hold the ball up.
    """
    timestep = require_timestep(timestep)
    w = resolved_frequency(target, timestep, STEPS_PER_RADIAN)
    kp = target.mass * w * w
    law_e = law_restitution(LINEAR, kp, target.mass, target.speeds)
    critical = 2.0 * np.sqrt(kp * target.mass)
    kd, e = fit_minimax(law_e, target, 0.0, MAX_DAMPING_RATIO * critical)
    reach = (float(np.min(law_e(MAX_DAMPING_RATIO * critical))), float(np.max(law_e(0.0))))
    sag = target.mass * scene.GRAVITY / kp
    with_gravity = (_with_gravity(kp, kd, target.mass, target.speeds) if sag < target.radius
                    else e)
    floor = 1.0 / (STEPS_PER_RADIAN * target_frequency(target))
    checked = scene.assess(target, e, with_gravity, sag, timestep, floor, 'predicted', 'Gazebo',
                           sag)
    max_vel = 2.0 * float(target.speeds.max())
    params = {'kp': kp, 'kd': kd, 'restitution_coefficient': 0.0, 'threshold': 0.0}
    snippet = ('<surface>\n  <bounce>\n    <restitution_coefficient>0</restitution_coefficient>\n'
               '    <threshold>0</threshold>\n  </bounce>\n  <contact>\n    <ode>\n'
               f'      <kp>{kp:.9g}</kp>\n      <kd>{kd:.9g}</kd>\n'
               f'      <max_vel>{max_vel:.6g}</max_vel>\n      <min_depth>0</min_depth>\n'
               f'    </ode>\n  </contact>\n</surface>\n<!-- physics max_step_size = {timestep:g} s;'
               ' the e claimed is the continuous law\'s: ODE\'s step is not modelled -->')
    duration, peak = law_contact(LINEAR, kp, kd, target.mass, target.speeds)
    return EngineFit(params, snippet, e, 'predicted',
                     STATEMENT + '; ' + linear_contact_note(target, w), duration, peak,
                     reach=reach, scene=checked, pitfalls=PITFALLS)
