"""Parameter sweeps on any ``concurrent.futures.Executor``: local processes by default, a Dask
cluster through ``distributed.Client(...).get_executor()``, or threads for debugging.

``sweep(function, values)`` returns ``[function(v) for v in values]`` in order; ``function`` must be
picklable (a top-level function or a frozen dataclass such as ``table.VibratingTable``).
"""
import os
from concurrent.futures import Executor, ProcessPoolExecutor

import numpy as np


def sweep(function, values, executor=None, max_workers=None):
    """Evaluate ``function`` at every value of ``values``, in parallel on ``executor`` (default: a
    ``ProcessPoolExecutor`` with ``max_workers``, default ``os.cpu_count()``, shut down after)."""
    values = list(values)
    if executor is not None and not isinstance(executor, Executor):
        raise ValueError(f'executor = {executor!r} is invalid: allowed None or a '
                         'concurrent.futures.Executor (e.g. distributed.Client.get_executor())')
    if max_workers is not None and (not isinstance(max_workers, int) or max_workers < 1):
        raise ValueError(f'max_workers = {max_workers!r} is out of range: allowed an integer >= 1')
    own = executor is None
    if own:
        executor = ProcessPoolExecutor(max_workers=max_workers or os.cpu_count() or 1)
    try:
        futures = [executor.submit(function, v) for v in values]
        return [f.result() for f in futures]
    finally:
        if own:
            executor.shutdown()


def bifurcation_diagram(table, gammas, executor=None, max_workers=None):
    """(Γ, phase) point arrays of a bifurcation diagram: ``table`` (a ``table.VibratingTable``)
    called at every Γ of ``gammas`` through ``sweep``; each Γ contributes its last bounces."""
    gammas = np.asarray(gammas, dtype=float)
    phases = sweep(table, gammas.tolist(), executor=executor, max_workers=max_workers)
    x = np.concatenate([np.full(len(p), g) for g, p in zip(gammas, phases)])
    return x, np.concatenate(phases) if phases else np.empty(0)
