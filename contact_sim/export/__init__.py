"""Export a contact to a simulator: the engine's parameters that best reproduce the target's
e(v) over a speed range, and the e(v) the engine gives with them.

``common`` (the target, the result, the minimax fit), one module an engine: ``mujoco_engine``
and ``pybullet_engine`` run the engine (a free sphere thrown at a plane, gravity off: measured),
``drake`` and ``gazebo`` evaluate the engine's law, a member of eq. 1 (predicted).  MuJoCo and
PyBullet are optional (``pip install 'contact_sim[engines]'``).  ``geom_contact`` and ``audit``
measure the e(v) a sphere geom of a user's MuJoCo model gives.
"""
from contact_sim.export.common import Export, Target, make_target
from contact_sim.export.engines import ENGINES, Engine, export_contact
from contact_sim.export.mujoco_engine import GeomContact, audit, geom_contact

__all__ = ['ENGINES', 'Engine', 'Export', 'GeomContact', 'Target', 'audit', 'export_contact',
           'geom_contact', 'make_target']
