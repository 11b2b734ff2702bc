"""What an export can be asked for: the engines' names (the keys of ``engines.ENGINES``) and the
time steps the tolerance search tries (``tolerance.timestep_for_tolerance``), and the range of
a step an export runs.

Apart from ``engines`` and ``tolerance`` (they import the engines, scipy's solvers and the impact
engine) so that the command line can build its parsers without importing them.
"""
ENGINE_NAMES = ('mujoco', 'pybullet', 'drake', 'gazebo')   # the order of ``engines.ENGINES``
TIMESTEPS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5)   # s, largest first
MIN_TIMESTEP = 1e-5   # s: the smallest step an export runs (a throw is then 10^5 steps at 0.1 m/s)
MAX_TIMESTEP = 1e-2   # s: at longer steps a stiffness that resolves the contact sinks any ball
