"""One impact: ``simulate_impact``; restitution, duration, peak force and depth for any speed
(closed forms and master curves, exact where they do not reach); fits of the damping λ."""
from contact_sim.impact.damping_fit import (DampingFit, compare_laws, damping_for_restitution,
                                            fit_damping)
from contact_sim.impact.restitution import (contact_duration, damping_from_group, damping_group,
                                            max_penetration, peak_force, restitution)
from contact_sim.impact.simulate import ImpactResult, simulate_impact

__all__ = ['DampingFit', 'ImpactResult', 'compare_laws', 'contact_duration',
           'damping_for_restitution', 'damping_from_group', 'damping_group', 'fit_damping',
           'max_penetration', 'peak_force', 'restitution', 'simulate_impact']
