"""Compile the node's numba kernels ahead of its first start: ``python -m
contact_sim.ros.precompile``.

Importing the package compiles nothing (its modules load lazily, and many kernels compile at
their first call): a node's first start then compiled them itself (34.8 s in issue 33). This
runs the engine as the node does (``params.build_model``, ``make_simulation``,
``DropSimulation.advance_ticks`` in ticks of 10 ms) through the default drop to rest, and through
the same drop on the vibrating table (the README's example), so that numba compiles and caches
(``cache=True``: beside the sources, or in the user's cache directory where those are read-only)
every kernel those runs use; a node started afterwards loads them.
"""
import sys
import time

import numpy as np

from .params import DEFAULTS, build

RUNS = (
    ('the default drop', {}),
    ('the vibrating table', {'plate_amplitude': 0.002, 'plate_frequency': 20.0,
                             'initial_height': 0.05}),
)
SECONDS = 3.0   # s of simulated time a run (the default drop settles in about 1.5 s)
TICK = 0.01     # s: the node's tick at its default publish rate


def precompile(out=sys.stdout):
    """Run the node's engine through ``RUNS`` so that numba compiles and caches its kernels.

    Parameters
    ----------
    out : file, optional
        Where each run's line is written (default ``sys.stdout``).

    Returns
    -------
    float
        s of wall time it took (compiling included).

    Examples
    --------
    From a shell, once after an install or a copying ``colcon build`` (not run as a doctest:
    it compiles for about 10-40 s):

    .. code-block:: console

        $ python3 -m contact_sim.ros.precompile
    """
    start = time.monotonic()
    for name, values in RUNS:
        began = time.monotonic()
        _, sim = build({**DEFAULTS, **values})   # the model and its drop, as the node builds
        times = np.arange(1, round(SECONDS / TICK) + 1) * TICK
        done = 0
        while done < times.size:
            done += sim.advance_ticks(times[done:], max_steps=20).ticks
        out.write(f'{name}: {SECONDS:g} simulated s in {time.monotonic() - began:.1f} s\n')
    return time.monotonic() - start


def main():
    """``python -m contact_sim.ros.precompile``: exit code 0."""
    took = precompile()
    print(f'the node\'s kernels are compiled and cached ({took:.1f} s)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
