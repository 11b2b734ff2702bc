"""``simulate_drop``: one batch run of the drop engine (``engine.DropSimulation``), its
trajectory sampled or not. Units: SI; z > 0 is penetration, ż > 0 is downward motion (approach).
"""
import math

import numpy as np

from contact_sim.drop.engine import DropSimulation
from contact_sim.drop.limits import (DROP_RTOL, DURATION_MAX, MAX_SAMPLES, MAX_STEPS,
                                     SAMPLE_RATE_MAX)
from contact_sim.drop.records import DropResult, Samples
from contact_sim.validation import InputError, require_int, require_range


def simulate_drop(contact, mass, height, gravity=9.81, duration=5.0, sample_rate=None,
                  velocity=0.0, rtol=DROP_RTOL, settle_tolerance=1e-3, radius=None,
                  max_steps=MAX_STEPS, drag=None, plate=None):
    """Drop a sphere from ``height`` and follow it for ``duration``: one ``DropSimulation`` run.

    Parameters
    ----------
    contact, mass, height, gravity, velocity, rtol, settle_tolerance, radius, drag, plate
        As in ``DropSimulation`` (``Contact``, kg, m, m/s², m/s, -, -, m, ``AirDrag``, ...).
    duration : float, optional
        The time followed, s, 0 < duration <= 1e9 (default 5).
    sample_rate : float, optional
        Hz, > 0: the result carries a trajectory on that grid plus every contact phase's own
        integrator points, so that no force peak is lost (at most ``MAX_SAMPLES`` samples).
    max_steps : int, optional
        Integrator steps allowed, 1 to 1e9 (default ``MAX_STEPS``).

    Returns
    -------
    DropResult
        The impacts, apexes, permanent contact and settle times (nan if not reached), steps.

    Raises
    ------
    InputError
        Keyed by the argument out of range, ``sample_rate`` (too many samples), ``duration``
        (more than ``max_steps`` needed: it says how far the drop got), or as ``check_drop``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> result = cs.simulate_drop(contact, mass, height=0.1, duration=2.0)
    >>> first = result.impacts[0]
    >>> print(f"{first.impact_speed:.4f} m/s, e = {first.restitution:.4f}, "
    ...       f"rest from {result.permanent_contact_time:.3f} s")
    1.4007 m/s, e = 0.7236, rest from 1.065 s
    """
    duration = require_range('duration', duration, 0.0, DURATION_MAX, low_open=True, unit='s')
    max_steps = require_int('max_steps', max_steps, 1, 10 ** 9)
    if sample_rate is not None:
        rate = require_range('sample_rate', sample_rate, 0.0, SAMPLE_RATE_MAX, low_open=True,
                             unit='Hz')
        if duration * rate > MAX_SAMPLES:
            raise InputError('sample_rate', rate, '{n[sample_rate]} = {value} Hz over '
                             '{n[duration]} = %g s makes %.4g samples: allowed at most %d '
                             '(%s x %s <= %d)' % (duration, duration * rate, MAX_SAMPLES,
                                                  '{n[sample_rate]}', '{n[duration]}',
                                                  MAX_SAMPLES))
    sim = DropSimulation(contact, mass, height, velocity=velocity, gravity=gravity, rtol=rtol,
                         settle_tolerance=settle_tolerance, radius=radius, drag=drag,
                         plate=plate)

    def reached(t):
        if sim.time < t:
            raise InputError('duration', duration, '{n[duration]} = {value} s needs more than '
                             '%d integrator steps (max_steps; reached t = %.6g s): allowed a '
                             'shorter {n[duration]}' % (max_steps, sim.time))

    def advance(t):
        part = sim.advance(t, max_steps=max_steps - sim.total_steps)
        reached(t)
        return part

    trajectory = None
    if sample_rate is None:     # no trajectory: its points are not gathered
        sim.run_to(duration, max_steps=max_steps - sim.total_steps)
        reached(duration)
    else:
        grid = np.arange(1, int(math.floor(duration * rate + 1e-9)) + 1) / rate
        if grid.size == 0 or grid[-1] < duration:
            grid = np.append(grid, duration)
        first = sim.state
        parts = [Samples.from_points([(0.0, first.penetration, first.penetration_rate,
                                       first.force)])]
        parts.extend(advance(t).samples for t in grid)
        trajectory = Samples.concatenate(parts)
    nan = math.nan
    return DropResult(tuple(sim.impacts), tuple(sim.apex_heights),
                      sim.permanent_contact_time if sim.permanent_contact_time is not None
                      else nan, sim.settle_time if sim.settle_time is not None else nan,
                      sim.total_steps, duration, trajectory)
