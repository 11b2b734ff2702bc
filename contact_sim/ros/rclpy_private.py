"""The one module that reaches into rclpy's private API: each name here has no public
counterpart in rclpy (Kilted), and each use is commented. The node's other modules import these
names from here.

- ``RCLError``: the exception rclpy's C extension raises when rcl fails (a publish after the
  context was shut down, an argument rcl cannot parse). rclpy exports no public alias of it;
  ``rclpy.impl.implementation_singleton.rclpy_implementation`` is the extension module as rclpy
  itself loads it.
- ``parameter_overrides(node)``: the parameter overrides a node was given (``-p``,
  ``--params-file``), which rclpy keeps in ``Node._parameter_overrides`` with no public getter;
  the node reads them to warn about unknown parameter names.
"""
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy

# private: the C extension's exception type (rclpy re-exports it nowhere public)
RCLError = _rclpy.RCLError


def parameter_overrides(node):
    """The names of the parameter overrides ``node`` was given (``-p``, ``--params-file``).

    Parameters
    ----------
    node : rclpy.node.Node
        Any rclpy node.

    Returns
    -------
    list of str
        The names, empty if rclpy keeps none.
    """
    # private: rclpy.node.Node._parameter_overrides (no public getter; read only)
    return list(getattr(node, '_parameter_overrides', {}))
