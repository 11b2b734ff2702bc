"""Gazebo (ODE): kp/kd is a linear spring-damper F = kp x + kd xdot clamped at zero, a member of
eq. 1; its e(v) is this library's exact restitution of that law (predicted, not measured)."""
import numpy as np

from contact_sim.export.common import (EngineFit, fit_minimax, law_contact, law_restitution,
                                        linear_contact_note, require_timestep, target_frequency)
from contact_sim.model import LINEAR


def export_gazebo(target, timestep):
    """Gazebo (ODE) parameters for ``target`` (``common.Target``) at ``timestep`` (s).

    kp (N/m) gives the target's contact duration at the middle speed; kd (N s/m) is fitted,
    minimax over the speeds, on the exact e(v) of the linear spring-damper F = kp x + kd xdot
    clamped at zero; the restitution coefficient is 0 (the spring-damper does the bounce).

    Returns
    -------
    EngineFit
        The parameters, the SDFormat ``<surface>``, the predicted e(v) and what the contact's
        duration and depth become.
    """
    timestep = require_timestep(timestep)
    kp = target.mass * target_frequency(target) ** 2
    law_e = law_restitution(LINEAR, kp, target.mass, target.speeds)
    kd, e = fit_minimax(law_e, target, 0.0, 2.0 * np.sqrt(kp * target.mass))
    max_vel = 2.0 * float(target.speeds.max())
    params = {'kp': kp, 'kd': kd, 'restitution_coefficient': 0.0, 'threshold': 0.0}
    snippet = ('<surface>\n  <bounce>\n    <restitution_coefficient>0</restitution_coefficient>\n'
               '    <threshold>0</threshold>\n  </bounce>\n  <contact>\n    <ode>\n'
               f'      <kp>{kp:.9g}</kp>\n      <kd>{kd:.9g}</kd>\n'
               f'      <max_vel>{max_vel:.6g}</max_vel>\n      <min_depth>0</min_depth>\n'
               f'    </ode>\n  </contact>\n</surface>\n<!-- physics max_step_size = {timestep:g} s'
               ' -->')
    duration, peak = law_contact(LINEAR, kp, kd, target.mass, target.speeds)
    return EngineFit(params, snippet, e, 'predicted',
                     linear_contact_note(target, target_frequency(target)), duration, peak)
