"""The console entry point of ``contact_sim_node``, light enough to take SIGINT and SIGTERM while
Python still imports the package (``import contact_sim.ros.node`` took 3.3 s under load, most of
it numba's kernels: ``python -X importtime``). Before, a Ctrl-C then gave a
``KeyboardInterrupt`` traceback; now the start stops with exit code 0 and no output, as from
``contact_sim.ros.node.main``'s first line on. Only the interpreter's own start and the entry
script's lookup of this function (a fraction of a second) come before it.

It imports nothing of the package but its two lazy ``__init__`` files (``contact_sim`` and
``contact_sim.ros``: 40 ms together, ``python -X importtime -c "import contact_sim.ros"``), so the
signals are taken before the slow part, the node's own import.
"""
import signal


def _stop(signum, frame):
    """The first signal stops the start; the rest (Ctrl-C pressed again) are ignored."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_IGN)
    raise KeyboardInterrupt


def node_main():
    """``contact_sim.ros.node.main`` with SIGINT and SIGTERM taken from before its import.

    Returns
    -------
    int
        ``main``'s exit code; 0 when a signal stopped the import.

    Examples
    --------
    The ``contact_sim_node`` console script (setup.py) runs it; Ctrl-C at once exits with 0:

    .. code-block:: console

        $ contact_sim_node --ros-args -p initial_height:=0.2
        ^C
        $ echo $?
        0
    """
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, _stop)
    try:
        from contact_sim.ros.node import main
        return main()    # it takes the signals over at its first line
    except KeyboardInterrupt:
        return 0
