"""Drake: its point contact is Hunt-Crossley on a linear spring, f = k x (1 + d xdot), a member
of eq. 1; its e(v) is this library's exact restitution of that law (predicted, not measured)."""
import numpy as np

from contact_sim.export.common import (fit_minimax, law_restitution, linear_contact_note,
                                        require_timestep, target_frequency)
from contact_sim.model import ContactLaw

# Drake: f = k x (1 + d xdot) = k x + (k d) x xdot, i.e. n = 1, p = 1, q = 1 with lambda = k d
DRAKE_POINT_CONTACT = ContactLaw('drake_point_contact', 1.0, 1.0, 1.0)


def drake_law_restitution(stiffness, dissipation, mass, speeds):
    """e at ``speeds`` (m/s) of Drake's point contact: ``stiffness`` k (N/m), Hunt-Crossley
    ``dissipation`` d (s/m), ``mass`` (kg): the law f = k x (1 + d xdot), exactly."""
    return law_restitution(DRAKE_POINT_CONTACT, stiffness, mass, speeds)(stiffness * dissipation)


def export_drake(target, timestep):
    """Drake parameters for ``target`` (``common.Target``) at ``timestep`` (s).

    k gives the target's contact duration at the middle speed; d (s/m) is fitted, minimax over
    the speeds, on the exact e(v) of f = k x (1 + d xdot) (Drake's continuous point contact;
    a discrete ``time_step`` approximates it).

    Returns
    -------
    (dict, str, numpy.ndarray, str)
        The parameters, the SDFormat snippet the predicted e(v) and
        what the contact's duration and depth become.
    """
    timestep = require_timestep(timestep)
    k = target.mass * target_frequency(target) ** 2
    speeds = target.speeds
    law_e = law_restitution(DRAKE_POINT_CONTACT, k, target.mass, speeds)
    lam, e = fit_minimax(law_e, target, 0.0, k * 20.0 / float(np.median(speeds)))
    d = lam / k
    params = {'point_contact_stiffness': k, 'hunt_crossley_dissipation': d, 'time_step': timestep}
    snippet = '\n'.join(_collision(name, geometry, 2.0 * k, d) for name, geometry in (
        ('ball', f'<sphere><radius>{target.radius:.6g}</radius></sphere>'),
        ('plane', '<plane><normal>0 0 1</normal></plane>'))) + (
        f'\n<!-- k = {k:.9g} N/m for the pair: Drake combines the two geometries\' stiffnesses '
        'in series, 2k with 2k; MultibodyPlant time_step = '
        f'{timestep:g} s (the e(v) is exact for the continuous point contact) -->')
    return params, snippet, e, linear_contact_note(target, target_frequency(target))


def _collision(name, geometry, stiffness, dissipation):
    """An SDFormat ``<collision>`` with Drake's point-contact properties."""
    return (f'<collision name="{name}">\n  <geometry>{geometry}</geometry>\n'
            '  <drake:proximity_properties>\n'
            f'    <drake:point_contact_stiffness>{stiffness:.9g}</drake:point_contact_stiffness>\n'
            f'    <drake:hunt_crossley_dissipation>{dissipation:.9g}'
            '</drake:hunt_crossley_dissipation>\n  </drake:proximity_properties>\n</collision>')
