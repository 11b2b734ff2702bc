"""Export a contact to a simulator: the engine's parameters that best reproduce the target's
e(v) over a speed range, and the e(v) the engine gives with them.

``common`` (the target, the result, the minimax fit), one module an engine: ``mujoco_engine``
and ``pybullet_engine`` run the engine (a free sphere thrown at a plane, gravity off: measured),
``drake`` and ``gazebo`` evaluate the engine's law, a member of eq. 1 (predicted).  MuJoCo and
PyBullet are optional (``pip install 'contact_sim[engines]'``).
"""
from contact_sim.export.common import Export, Target, make_target
from contact_sim.export.engines import ENGINES, Engine, export_contact

__all__ = ['ENGINES', 'Engine', 'Export', 'Target', 'export_contact', 'make_target']
