"""Export a contact to a simulator: the engine's parameters that best reproduce the target's
e(v) over a speed range, and the e(v) the engine gives with them.

``common`` (the target, the result, the minimax fit), one module an engine: ``mujoco_engine``
and ``pybullet_engine`` run the engine (a free sphere thrown at a plane, gravity off: measured);
``drake`` runs pydrake's MultibodyPlant (``drake_plant``) where it is installed, else evaluates
its law, a member of eq. 1 (predicted), as ``gazebo`` does.  MuJoCo and PyBullet are optional
(``pip install 'contact_sim[engines]'``), Drake too (``pip install 'contact_sim[drake]'``,
about 420 MB).  ``geom_contact`` and ``audit``
measure the e(v) a sphere geom of a user's MuJoCo model gives, ``link_contact`` and
``audit_link`` a sphere link of a URDF in PyBullet.
"""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``): ``choices`` (the
# engines' names, the time steps) without the engines
_EXPORTS = {
    'choices': ('ENGINE_NAMES', 'TIMESTEPS'),
    'common': ('Export', 'Target', 'make_target'),
    'engines': ('ENGINES', 'Engine', 'export_contact'),
    'mujoco_audit': ('GeomContact', 'audit', 'geom_contact'),
    'pybullet_audit': ('LinkContact', 'audit_link', 'link_contact'),
    'tolerance': ('TimestepSearch', 'require_tolerance', 'timestep_for_tolerance'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['ENGINES', 'Engine', 'Export', 'GeomContact', 'LinkContact', 'TIMESTEPS', 'Target',
           'TimestepSearch', 'audit', 'audit_link', 'export_contact', 'geom_contact',
           'link_contact', 'make_target', 'require_tolerance', 'timestep_for_tolerance']
