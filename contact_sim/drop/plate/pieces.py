"""A commanded plate's pieces: its state at a time and its forcing pieces, written once as
plain Python over indexable sequences, which ``CommandedPlate`` calls on its tuples and numba
compiles as it stands for the compiled flights (``compiled_flight``) on its arrays.

The pieces are four sequences of one length: start times (s, increasing), positions (m),
velocities (m/s) and accelerations (m/s²) at each start; the last piece runs to +inf, and
before the first the plate moves at the first velocity with no acceleration.  ``i`` is the
piece at t: the last one starting at or before t (the first before it), which the caller finds
(``bisect`` on tuples, ``compiled_flight.piece_index`` in numba).
"""
import math

KNOT_TOLERANCE = 1e-12      # a knot whose acceleration differs by less (relative) changes nothing


def piece_state(starts, positions, velocities, accelerations, i, t):
    """(p m, ṗ m/s, p̈ m/s²) of the plate at t (s) on piece ``i`` (module docstring).

    Examples
    --------
    >>> piece_state((0.0, 1.0), (0.0, 0.5), (0.0, 1.0), (1.0, 0.0), 0, 0.5)
    (0.125, 0.5, 1.0)
    """
    a = accelerations[i]
    if t < starts[0]:       # before the first piece: its velocity, no acceleration
        i, a = 0, 0.0
    dt = t - starts[i]
    return positions[i] + velocities[i] * dt + 0.5 * a * dt * dt, velocities[i] + a * dt, a


def piece_forcing(starts, accelerations, i, t):
    """(p̈ m/s², until s): the plate's constant acceleration for a contact phase starting at t
    (s) on piece ``i``, and when that forcing ends: the start of the first later piece whose
    acceleration differs from piece ``i``'s by more than ``KNOT_TOLERANCE`` of it (knots that
    change nothing, up to the rounding of the interpolant's coefficients, are passed), inf after
    the last; before the first piece, no acceleration until the first piece starts.

    Examples
    --------
    >>> piece_forcing((0.0, 1.0, 2.0), (3.0, 3.0, 0.0), 0, 0.5)       # the knot at 1 s passed
    (3.0, 2.0)
    >>> piece_forcing((0.0, 1.0, 2.0), (3.0, 3.0, 0.0), 0, -0.5)      # before the first piece
    (0.0, 0.0)
    """
    if t < starts[0]:
        return 0.0, starts[0]
    j = i
    while (j + 1 < len(starts)
           and abs(accelerations[j + 1] - accelerations[i]) <= KNOT_TOLERANCE
           * abs(accelerations[i])):
        j += 1
    return accelerations[i], (starts[j + 1] if j + 1 < len(starts) else math.inf)
