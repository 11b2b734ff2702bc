"""The contact law inside another simulator: one contact advanced exactly over each host step.

``core`` (``NormalCoupling``: the gap, its rate, the effective mass, the rest of the system's
normal acceleration and the step in; the impulse over the step, the impacts inside it and the
exact state it carries out), over ``flight`` (the flight inside a step in closed form) and the
compiled contact phase of ``phase``; ``friction`` (Coulomb's tangential impulse in the same
step); ``rows`` (what the adapters share about their pairs).  The host adapters, one module an engine, each importing its engine there only:
``contact_sim.coupling.mujoco``, ``contact_sim.coupling.pybullet``, ``contact_sim.coupling.drake``
(its pairs' shapes read from the scene graph by ``drake_shapes``)
(import them by their module names; this package imports no engine).  Units: SI.
"""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``); no engine here
_EXPORTS = {
    'core': ('ACCELERATION_RTOL', 'HOSTS', 'REST_ENERGY', 'TOLERANCE', 'CoupledImpact', 'CouplingStep',
             'NormalCoupling'),
    'engines': ('ENGINES', 'engine_restitution'),
    'flight': ('parabola', 'touch_time'),
    'friction': ('friction_impulse',),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['ACCELERATION_RTOL', 'ENGINES', 'HOSTS', 'REST_ENERGY', 'TOLERANCE', 'CoupledImpact',
           'CouplingStep', 'NormalCoupling', 'engine_restitution', 'friction_impulse', 'parabola',
           'touch_time']
