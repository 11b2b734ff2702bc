"""The closed forms' compiled kernels (numba), apart from ``closed_forms`` so that importing the
model (and the command line's argument parsing) does not import numba: ``closed_forms`` imports
this module at the first call that needs it."""
import math

from numba import njit

from contact_sim.model.hunt_crossley_scalar import hunt_crossley_restitution_scalar

_hunt_crossley_restitution_one = njit(cache=True, nogil=True)(hunt_crossley_restitution_scalar)


@njit(cache=True, nogil=True)
def hunt_crossley_restitution_many(zeta, out):
    """Write e(ζ) of the Hunt-Crossley law of each ``zeta[i]`` into ``out[i]`` (1-D float arrays),
    each by the full iteration."""
    for i in range(zeta.size):
        out[i] = _hunt_crossley_restitution_one(zeta[i])


@njit(cache=True, nogil=True)
def table_value(z, s0, h, coef):
    """The cubic piece of ``coef`` (rows a, b, c, d: a t³ + b t² + c t + d from the row's start,
    t in ln ζ) at ζ = ``z`` on the grid ln ζ = s0 + h i; 0 outside the table."""
    if not z > 0.0:
        return 0.0
    x = (math.log(z) - s0) / h
    if not (x >= 0.0 and x < coef.shape[0]):
        return 0.0
    j = int(x)
    t = (x - j) * h
    return ((coef[j, 0] * t + coef[j, 1]) * t + coef[j, 2]) * t + coef[j, 3]


@njit(cache=True, nogil=True)
def hunt_crossley_restitution_tabled(zeta, out, s0, h, coef):
    """``hunt_crossley_restitution_many`` from a table's guess: inside the table one Newton step
    of the same iteration finishes it (``hunt_crossley_restitution_scalar``'s ``guess``); outside
    it (below ζ = 1e-6: the series; far above: u underflows in a step or two) the full one."""
    for i in range(zeta.size):
        z = zeta[i]
        out[i] = _hunt_crossley_restitution_one(z, table_value(z, s0, h, coef))
