"""Export a contact to a simulator: the engine's parameters that best reproduce the target's
e(v) over a speed range, the e(v) the engine gives with them, and that claim checked with
gravity on (``scene``).

``common`` (the target, the result, the minimax fit), one module an engine: ``mujoco_engine``,
``pybullet_engine`` and ``drake`` (``drake_plant``) run the engine (a free sphere thrown at a
plane, gravity off: measured; then dropped and left to rest with gravity); ``gazebo`` evaluates
its law, a member of eq. 1 (predicted: the continuous law's e).  MuJoCo, PyBullet and Drake are
in the set-up's requirements (``pip install 'contact_sim[engines]'``, ``'contact_sim[drake]'``,
elsewhere); without pydrake Drake's export is refused, never predicted.  ``geom_contact`` and
``audit`` (``mujoco_audit``) measure the e(v) a sphere geom of a user's MuJoCo model gives against
the model's own floor, ``link_contact`` and ``audit_link`` a sphere link of a URDF in PyBullet.
"""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``): ``choices`` (the
# engines' names, the time steps) without the engines
_EXPORTS = {
    'choices': ('ENGINE_NAMES', 'MAX_TIMESTEP', 'MIN_TIMESTEP', 'TIMESTEPS'),
    'common': ('Export', 'Target', 'make_target'),
    'engines': ('ENGINES', 'Engine', 'export_contact'),
    'mujoco_audit': ('GeomContact', 'audit', 'geom_contact'),
    'pybullet_audit': ('LinkContact', 'audit_link', 'link_contact'),
    'tolerance': ('TimestepSearch', 'require_tolerance', 'timestep_for_tolerance'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['ENGINES', 'Engine', 'Export', 'GeomContact', 'LinkContact', 'MAX_TIMESTEP',
           'MIN_TIMESTEP', 'TIMESTEPS', 'Target',
           'TimestepSearch', 'audit', 'audit_link', 'export_contact', 'geom_contact',
           'link_contact', 'make_target', 'require_tolerance', 'timestep_for_tolerance']
