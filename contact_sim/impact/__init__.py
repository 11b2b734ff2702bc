"""One impact: ``simulate_impact``; restitution, duration, peak force and depth for any speed
(closed forms and master curves, exact where they do not reach); fits of the damping λ."""
from contact_sim.impact.damping_fit import (DampingFit, compare_laws, damping_for_restitution,
                                            fit_damping)
from contact_sim.impact.restitution import (contact_duration, damping_from_group, damping_group,
                                            max_penetration, peak_force, restitution)
from contact_sim.impact.simulate import ImpactResult, simulate_impact
from contact_sim.impact.damping_fit import (LOSSES, group_for_restitution, require_fit_options,
                                            robust_weights)
from contact_sim.impact.restitution import (damping_group_of, dimensionless, elastic_limits,
                                            impact_scales, master_curve)

__all__ = ['DampingFit', 'ImpactResult', 'LOSSES', 'compare_laws', 'contact_duration',
           'damping_for_restitution', 'damping_from_group', 'damping_group', 'damping_group_of',
           'dimensionless', 'elastic_limits', 'fit_damping', 'group_for_restitution',
           'impact_scales', 'master_curve', 'max_penetration', 'peak_force', 'require_fit_options',
           'restitution', 'robust_weights', 'simulate_impact']
