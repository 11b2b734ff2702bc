"""What time step reaches a tolerance: the largest of a set of engine time steps whose export
misses the target's e(v) by at most the tolerance, or none, with the best error found.

A linear spring-damper gives one e at every speed, so it misses a speed-dependent target by at
least half the target's spread (max - min) / 2 at any time step: below that no step is tried."""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.export.choices import TIMESTEPS
from contact_sim.export.engines import export_contact, require_engine
from contact_sim.validation import InputError, require_positive


@dataclass(frozen=True)
class TimestepSearch:
    """The outcome of ``timestep_for_tolerance``.

    Parameters
    ----------
    tolerance : float
        The largest max |engine e - target e| accepted.
    timestep : float or None
        The largest time step tried (s) that meets it, None if none does.
    best_error : float
        The smallest max |error| found (or, for a linear law below its floor, the floor; inf
        if no step tried could hold the ball up).
    floor : float or None
        For a linear law, half the target's spread: no time step does better.
    tried : tuple
        (time step in s, max |error|) of each export run, in order; the error is None where
        the step's contact cannot hold the ball up (``scene``).
    """

    tolerance: float
    timestep: object
    best_error: float
    floor: object
    tried: tuple


def require_tolerance(tolerance):
    """``tolerance`` if > 0, else ``InputError`` keyed ``tolerance``."""
    return require_positive('tolerance', tolerance)


def timestep_for_tolerance(engine, target, tolerance, timesteps=TIMESTEPS):
    """The largest of ``timesteps`` (s, tried largest first) at which ``engine``'s export of
    ``target`` misses its e(v) by at most ``tolerance``.

    Returns
    -------
    TimestepSearch

    Raises
    ------
    InputError
        If the tolerance is not > 0 (keyed ``tolerance``) or the engine is unknown.

    Examples
    --------
    >>> timestep_for_tolerance('gazebo', target, 0.01).timestep is None   # doctest: +SKIP
    True
    """
    tolerance = require_tolerance(tolerance)
    floor = float(np.ptp(target.restitution)) / 2.0 if require_engine(engine).linear else None
    if floor is not None and tolerance < floor:
        return TimestepSearch(tolerance, None, floor, floor, ())
    tried = []
    for timestep in sorted(timesteps, reverse=True):
        try:
            tried.append((timestep, export_contact(engine, target, timestep).max_abs_error))
        except InputError as error:   # this step's contact cannot hold the ball up
            if error.field != 'timestep':
                raise
            tried.append((timestep, None))
            continue
        if tried[-1][1] <= tolerance:
            return TimestepSearch(tolerance, timestep, tried[-1][1], floor, tuple(tried))
    errors = [error for _, error in tried if error is not None]
    return TimestepSearch(tolerance, None, min(errors) if errors else math.inf, floor,
                          tuple(tried))
