"""One impact: ``simulate_impact``; restitution, duration, peak force and depth for any speed
(closed forms and master curves, exact where they do not reach); fits of the damping λ.

``simulate`` (the exact reference path), ``scales`` (Z, T and the damping group ζ),
``tails`` (asymptotics beyond a master curve), ``dimensionless_outcomes`` (e, τc, F̂, x̂ of ζ
from the best source the law has), ``outcomes`` (the dimensional results), ``damping_fit`` (λ from
restitution, fits to data) and ``fit_options`` (a fit's point limit, losses and confidence,
which the command line reads without importing the engine).
"""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``)
_EXPORTS = {
    'damping_fit': ('DampingFit', 'compare_laws', 'damping_for_restitution', 'fit_damping',
                    'group_for_restitution', 'robust_weights'),
    'dimensionless_outcomes': ('dimensionless', 'master_curve'),
    'fit_options': ('LOSSES', 'MAX_POINTS', 'require_fit_options'),
    'outcomes': ('contact_duration', 'damping_from_group', 'damping_group', 'max_penetration',
                 'peak_force', 'restitution'),
    'scales': ('CONTACT_LENGTH_MAX', 'CONTACT_TIME_MIN', 'ZETA_MAX', 'ZETA_MIN', 'checked_scales',
               'damping_group_of', 'impact_scales', 'require_speeds'),
    'simulate': ('ImpactResult', 'simulate_impact'),
    'tails': ('elastic_limits',),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['CONTACT_LENGTH_MAX', 'CONTACT_TIME_MIN', 'DampingFit', 'ImpactResult', 'LOSSES',
           'MAX_POINTS', 'ZETA_MAX', 'ZETA_MIN', 'checked_scales', 'compare_laws',
           'contact_duration', 'damping_for_restitution', 'damping_from_group', 'damping_group', 'damping_group_of',
           'dimensionless', 'elastic_limits', 'fit_damping', 'group_for_restitution',
           'impact_scales', 'master_curve', 'max_penetration', 'peak_force',
           'require_fit_options', 'require_speeds', 'restitution', 'robust_weights',
           'simulate_impact']
