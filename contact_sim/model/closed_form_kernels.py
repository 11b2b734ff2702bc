"""The closed forms' compiled kernels (numba), apart from ``closed_forms`` so that importing the
model (and the command line's argument parsing) does not import numba: ``closed_forms`` imports
this module at the first call that needs it."""
from numba import njit

from contact_sim.model.hunt_crossley_scalar import hunt_crossley_restitution_scalar

_hunt_crossley_restitution_one = njit(cache=True, nogil=True)(hunt_crossley_restitution_scalar)


@njit(cache=True, nogil=True)
def hunt_crossley_restitution_many(zeta, out):
    """Write e(ζ) of the Hunt-Crossley law of each ``zeta[i]`` into ``out[i]`` (1-D float arrays)."""
    for i in range(zeta.size):
        out[i] = _hunt_crossley_restitution_one(zeta[i])
