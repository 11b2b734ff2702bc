"""Parameter sweeps on any ``concurrent.futures.Executor``: local processes by default, a Dask
cluster through ``distributed.Client(...).get_executor()``, or threads for debugging.

``sweep(function, values)`` returns ``[function(v) for v in values]`` in order; ``function`` must be
picklable (a top-level function or a frozen dataclass such as ``table.VibratingTable``).
"""
import os
from concurrent.futures import Executor, ProcessPoolExecutor

import numpy as np

from contact_sim.validation import InputError, require_int


def max_workers_limit():
    """The most local worker processes a sweep may start: 4 per CPU of this machine."""
    return 4 * (os.cpu_count() or 1)


def sweep(function, values, executor=None, max_workers=None):
    """Evaluate ``function`` at every value of ``values``, in parallel.

    Parameters
    ----------
    function : callable
        Picklable: a top-level function or a frozen dataclass such as ``table.VibratingTable``.
    values : iterable
        The arguments, one call each.
    executor : concurrent.futures.Executor, optional
        Where to run: any ``concurrent.futures.Executor`` the caller made and still owns (it is
        not shut down here), e.g. a ``ProcessPoolExecutor`` kept warm across sweeps or a Dask
        cluster's ``distributed.Client(...).get_executor()`` (the optional ``dask`` extra;
        ``bench/bench_cluster.py`` measures both).  Default: a ``ProcessPoolExecutor`` of this
        machine, started here and shut down after.
    max_workers : int, optional
        The local pool's processes: 1 to ``max_workers_limit()`` (4 per CPU); default
        ``os.cpu_count()``.  Never more are started than there are values.  Only without
        ``executor``.

    Returns
    -------
    list
        ``[function(v) for v in values]``, in order.

    Raises
    ------
    InputError
        ``values`` not iterable, ``max_workers`` not an integer in its range or given with an
        ``executor``, or ``executor`` not an ``Executor`` or one that takes no work (shut down
        or broken).

    Examples
    --------
    >>> from contact_sim.drop import sweep
    >>> sweep(abs, [-1, 2, -3], max_workers=1)
    [1, 2, 3]
    """
    try:
        if isinstance(values, (str, bytes)):   # its characters are not the values meant
            raise TypeError
        values = list(values)
    except TypeError:
        raise InputError('values', values, '{n[values]} = {value} is not a sequence: allowed a '
                         'list (or any iterable) of the values to call {n[function]} with',
                         value=repr(values)) from None
    if executor is not None and not isinstance(executor, Executor):
        raise InputError('executor', executor, '{n[executor]} = {value} is invalid: allowed None '
                         'or a concurrent.futures.Executor (e.g. '
                         'distributed.Client.get_executor())', value=repr(executor))
    if max_workers is not None:
        if executor is not None:        # the caller's executor has its own workers
            raise InputError('max_workers', max_workers, '{n[max_workers]} = {value} with an '
                             '{n[executor]}: allowed None (the executor\'s own workers run); '
                             '{n[max_workers]} sizes only the local pool')
        max_workers = require_int('max_workers', max_workers, 1, max_workers_limit())
    own = executor is None
    if own:
        workers = min(max_workers or os.cpu_count() or 1, max(len(values), 1))
        executor = ProcessPoolExecutor(max_workers=workers)
    futures = []
    try:
        for v in values:
            futures.append(_submit(executor, function, v))
        return [f.result() for f in futures]
    except BaseException:
        for future in futures:   # a refusal midway: what was submitted does not run on
            future.cancel()
        raise
    finally:
        if own:
            executor.shutdown()


def _submit(executor, function, value):
    try:
        return executor.submit(function, value)
    except RuntimeError as error:   # shut down, or broken (BrokenExecutor is a RuntimeError)
        raise InputError('executor', executor, '{n[executor]} = {value} takes no work '
                         '({error}): allowed an executor not shut down nor broken',
                         value=repr(executor), error=error) from error


def bifurcation_diagram(table, gammas, executor=None, max_workers=None):
    """The points of a bifurcation diagram: ``table`` at every Γ of ``gammas``, through ``sweep``.

    Parameters
    ----------
    table : VibratingTable
        The table (its ``bounces`` last impacts per Γ are the points).
    gammas : array_like of float
        The Γ values, dimensionless.
    executor, max_workers : optional
        As in ``sweep`` (default: local processes).

    Returns
    -------
    tuple of numpy.ndarray
        (Γ, table phase in rad) of every point.

    Raises
    ------
    InputError
        As ``sweep`` and ``VibratingTable.run``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> from contact_sim.drop import VibratingTable
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> table = VibratingTable(contact, cs.build_mass(sphere='steel', radius=0.0127),
    ...                        frequency=20.0, bounces=4, transient=20)
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> from contact_sim.drop import bifurcation_diagram
    >>> with ThreadPoolExecutor(1) as pool:
    ...     gamma, phase = bifurcation_diagram(table, [0.8, 1.0], executor=pool)
    >>> gamma.tolist()
    [0.8, 0.8, 0.8, 0.8, 1.0, 1.0, 1.0, 1.0]
    """
    gammas = np.asarray(gammas, dtype=float).ravel()
    if gammas.size == 0:
        return np.empty(0), np.empty(0)
    phases = sweep(table, gammas.tolist(), executor=executor, max_workers=max_workers)
    x = np.concatenate([np.full(len(p), g) for g, p in zip(gammas, phases)])
    return x, np.concatenate(phases) if phases else np.empty(0)
