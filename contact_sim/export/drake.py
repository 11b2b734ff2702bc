"""Drake: its point contact is Hunt-Crossley on a linear spring, f = k x (1 + d xdot), a member
of eq. 1.  Where pydrake is installed the plant is run (``drake_plant``: measured); where it is
not, the e(v) is this library's exact restitution of that law (predicted)."""
import numpy as np

from contact_sim.export import drake_plant
from contact_sim.export.common import (EngineFit, fit_minimax, law_contact, law_restitution,
                                        linear_contact_note, require_timestep, resolved_frequency,
                                        target_frequency)
from contact_sim.model import ContactLaw

# Drake: f = k x (1 + d xdot) = k x + (k d) x xdot, i.e. n = 1, p = 1, q = 1 with lambda = k d
DRAKE_POINT_CONTACT = ContactLaw('drake_point_contact', 1.0, 1.0, 1.0)
STEPS_PER_RADIAN = 10.0   # discrete plant: w dt <= 0.1, e then moves < 0.01 with the phase


def drake_law_restitution(stiffness, dissipation, mass, speeds):
    """e at ``speeds`` (m/s) of Drake's point contact: ``stiffness`` k (N/m), Hunt-Crossley
    ``dissipation`` d (s/m), ``mass`` (kg): the law f = k x (1 + d xdot), exactly."""
    return law_restitution(DRAKE_POINT_CONTACT, stiffness, mass, speeds)(stiffness * dissipation)


def export_drake(target, timestep):
    """Drake parameters for ``target`` (``common.Target``) at ``timestep`` (s; 0 is the
    continuous plant).

    k gives the target's contact duration at the middle speed (the continuous plant), lowered
    until a step is at most 0.1 rad of it (the discrete plant); d (s/m) is fitted, minimax over
    the speeds, on the exact e(v) of f = k x (1 + d xdot).  With pydrake installed the plant is
    run with them and, for the discrete plant, whose implicit step loses energy of its own, d is
    fitted again on the e Drake gives.

    Returns
    -------
    EngineFit

    Examples
    --------
    >>> fit = export_drake(target, 0.0)   # doctest: +SKIP
    >>> fit.parameters['hunt_crossley_dissipation']   # doctest: +SKIP
    0.174...
    """
    timestep = require_timestep(timestep, continuous=True)
    w = (target_frequency(target) if timestep == 0.0
         else resolved_frequency(target, timestep, STEPS_PER_RADIAN))
    k = target.mass * w * w
    law_e = law_restitution(DRAKE_POINT_CONTACT, k, target.mass, target.speeds)
    lam, e = fit_minimax(law_e, target, 0.0, k * 20.0 / float(np.median(target.speeds)))
    d, source = lam / k, 'predicted'
    duration, peak = law_contact(DRAKE_POINT_CONTACT, k, lam, target.mass, target.speeds)
    if drake_plant.importable():
        def measured(dissipation):
            return drake_plant.measure(target.radius, target.mass, target.speeds, k,
                                       dissipation, timestep)
        if timestep > 0.0:
            d, _ = fit_minimax(lambda x: measured(x)[:, 0], target, 0.0, 2.0 * d)
        e, duration, peak = measured(d).T
        source = 'measured'
    params = {'point_contact_stiffness': k, 'hunt_crossley_dissipation': d, 'time_step': timestep}
    ball_k, ball_d = drake_plant.pair_properties(k, d)
    snippet = '\n'.join(_collision(name, geometry, ball_k, ball_d) for name, geometry in (
        ('ball', f'<sphere><radius>{target.radius:.6g}</radius></sphere>'),
        ('plane', '<plane><normal>0 0 1</normal></plane>'))) + (
        f'\n<!-- k = {k:.9g} N/m, d = {d:.9g} s/m for the pair: Drake combines the two '
        'geometries in series, k = k1 k2/(k1 + k2), d = (k2 d1 + k1 d2)/(k1 + k2), so 2k and d '
        'on each give k and d; with a ground of your own k2 > k, d2 give the ball k1 = k k2/(k2 '
        '- k), d1 = ((k1 + k2) d - k1 d2)/k2. MultibodyPlantConfig(time_step='
        f'{timestep:g}, contact_model="point", discrete_contact_approximation='
        f'"{drake_plant.DISCRETE_APPROXIMATION}") -->')
    return EngineFit(params, snippet, np.asarray(e), source, linear_contact_note(target, w),
                     duration, peak)


def _collision(name, geometry, stiffness, dissipation):
    """An SDFormat ``<collision>`` with Drake's point-contact properties."""
    return (f'<collision name="{name}">\n  <geometry>{geometry}</geometry>\n'
            '  <drake:proximity_properties>\n'
            f'    <drake:point_contact_stiffness>{stiffness:.9g}</drake:point_contact_stiffness>\n'
            f'    <drake:hunt_crossley_dissipation>{dissipation:.9g}'
            '</drake:hunt_crossley_dissipation>\n  </drake:proximity_properties>\n</collision>')
