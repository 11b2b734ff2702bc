"""One impact: ``simulate_impact``; restitution, duration, peak force and depth for any speed
(closed forms and master curves, exact where they do not reach); fits of the damping λ.

``simulate`` (the exact reference path), ``scales`` (Z, T and the damping group ζ),
``tails`` (asymptotics beyond a master curve), ``dimensionless`` (e, τc, F̂, x̂ of ζ from the
best source the law has), ``restitution`` (the dimensional results), ``damping_fit`` (λ from
restitution, fits to data).
"""
from contact_sim.impact.damping_fit import (DampingFit, compare_laws, damping_for_restitution,
                                            fit_damping)
from contact_sim.impact.restitution import (contact_duration, damping_from_group, damping_group,
                                            max_penetration, peak_force, restitution)
from contact_sim.impact.simulate import ImpactResult, simulate_impact
from contact_sim.impact.damping_fit import (LOSSES, MAX_POINTS, group_for_restitution,
                                            require_fit_options, robust_weights)
from contact_sim.impact.dimensionless import dimensionless, master_curve
from contact_sim.impact.scales import (CONTACT_LENGTH_MAX, CONTACT_TIME_MIN, ZETA_MAX, ZETA_MIN,
                                      checked_scales, damping_group_of, impact_scales,
                                      require_speeds)
from contact_sim.impact.tails import elastic_limits

__all__ = ['CONTACT_LENGTH_MAX', 'CONTACT_TIME_MIN', 'DampingFit', 'ImpactResult', 'LOSSES',
           'MAX_POINTS', 'ZETA_MAX', 'ZETA_MIN', 'checked_scales', 'compare_laws',
           'contact_duration', 'damping_for_restitution', 'damping_from_group', 'damping_group', 'damping_group_of',
           'dimensionless', 'elastic_limits', 'fit_damping', 'group_for_restitution',
           'impact_scales', 'master_curve', 'max_penetration', 'peak_force',
           'require_fit_options', 'require_speeds', 'restitution', 'robust_weights',
           'simulate_impact']
