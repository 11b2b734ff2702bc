"""Drake: its point contact is Hunt-Crossley on a linear spring, f = k x (1 + d xdot), a member
of eq. 1.  The plant is run (``drake_plant``: measured), gravity off for the claim and on for
the scene (``scene``); without pydrake the export is refused (ImportError), never predicted:
the discrete plant's step loses energy of its own that the law does not have."""
import numpy as np

from contact_sim.export import drake_plant, scene
from contact_sim.export.common import (EngineFit, fit_minimax, law_restitution,
                                        linear_contact_note, require_timestep, resolved_frequency,
                                        target_frequency)
from contact_sim.model import ContactLaw

# Drake: f = k x (1 + d xdot) = k x + (k d) x xdot, i.e. n = 1, p = 1, q = 1 with lambda = k d
DRAKE_POINT_CONTACT = ContactLaw('drake_point_contact', 1.0, 1.0, 1.0)
STEPS_PER_RADIAN = 10.0   # discrete plant: w dt <= 0.1, e then moves < 0.01 with the phase
PITFALLS = ('a ground with properties of its own: Drake combines the pair in series (the '
            'comment in the snippet gives the ball\'s values for it)',
            'another discrete_contact_approximation than the snippet\'s, or another time_step: '
            'each loses energy of its own',
            'point_contact_stiffness is in N/m: the claim holds for the printed mass only')


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
    fitted again on the e Drake gives, from 0 up to 20 times the law's d.  The law's d is
    searched up to 2000 / (the lowest speed), a log grid then Brent.  The claim is checked with gravity (``scene``): the rest sag is m g / k exactly
    (at rest Hunt-Crossley's damping vanishes).

    Raises
    ------
    ImportError
        If pydrake is not installed (no claim is made then).
    InputError
        Keyed ``timestep``: out of range, or the contact cannot hold the ball up.

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
    widest = 2000.0 / float(np.min(target.speeds))   # s/m: the law's e about 5e-4 there
    # the minimax error is not unimodal over so wide a range: a log grid first, then Brent
    # between the grid's neighbours of its best
    grid = np.concatenate([[0.0], np.geomspace(widest * 1e-7, widest, 71)])
    best = int(np.argmin([np.max(np.abs(law_e(k * x) - target.restitution)) for x in grid]))
    lam, e = fit_minimax(law_e, target, k * grid[max(best - 1, 0)],
                         k * grid[min(best + 1, grid.size - 1)])
    d = lam / k
    drake_plant._pydrake()   # ImportError without pydrake: nothing is claimed

    def measured(dissipation, gravity=0.0, per_phase=False):
        return drake_plant.measure(target.radius, target.mass, target.speeds, k, dissipation,
                                   timestep, gravity, per_phase)
    top = 20.0 * d   # the discrete step loses more than the law: its d is below the law's
    # the e the damping range gives: the law's for the continuous plant (its e within 1e-4 of
    # the law's, test_continuous_plant_is_the_law), Drake's own for the discrete one
    reach = (float(np.min(law_e(widest * k))), float(np.max(law_e(0.0))))
    if timestep > 0.0:
        d, _ = fit_minimax(lambda x: measured(x)[:, 0], target, 0.0, top)
        reach = (float(np.min(measured(top)[:, 0])), float(np.max(measured(0.0)[:, 0])))
    e, duration, peak = measured(d).T
    source = 'measured'
    sag = target.mass * scene.GRAVITY / k
    with_gravity = (measured(d, scene.GRAVITY, per_phase=True)[:, :, 0] if sag < target.radius
                    else e)
    floor = 0.0 if timestep == 0.0 else 1.0 / (STEPS_PER_RADIAN * target_frequency(target))
    checked = scene.assess(target, e, with_gravity, sag, timestep, floor, source, 'Drake', sag)
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
                     duration, peak, reach=reach, scene=checked, pitfalls=PITFALLS)


def _collision(name, geometry, stiffness, dissipation):
    """An SDFormat ``<collision>`` with Drake's point-contact properties."""
    return (f'<collision name="{name}">\n  <geometry>{geometry}</geometry>\n'
            '  <drake:proximity_properties>\n'
            f'    <drake:point_contact_stiffness>{stiffness:.9g}</drake:point_contact_stiffness>\n'
            f'    <drake:hunt_crossley_dissipation>{dissipation:.9g}'
            '</drake:hunt_crossley_dissipation>\n  </drake:proximity_properties>\n</collision>')
