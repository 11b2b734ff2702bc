"""Coulomb friction of a coupled contact: a tangential impulse in the same host step, bounded by
μ times the step's normal impulse (no engine import).  Units: SI."""
import numpy as np


def friction_impulse(normal_impulse, slip_velocity, inverse_mass, friction):
    """The tangential impulse of one host step: stick if μ times the normal impulse suffices to
    stop the contact point's sliding, slip (μ times it, against the sliding) otherwise.

    Parameters
    ----------
    normal_impulse : float
        The step's normal impulse, N·s, >= 0.
    slip_velocity : array_like of float, shape (2,)
        The contact point's sliding velocity in the tangent plane the step would end with
        without friction (the velocity now plus the rest of the system's tangential
        acceleration times dt), m/s.
    inverse_mass : array_like of float, shape (2, 2)
        The tangential inverse effective mass at the contact point, Jₜ M⁻¹ Jₜᵀ, 1/kg.
    friction : float
        The friction coefficient μ, >= 0.

    Returns
    -------
    numpy.ndarray
        The impulse on the sliding body, N·s, shape (2,): -W⁻¹ v in stick, -μ P v / |v| in
        slip (a solid sphere on a plate: 5/7 of its sliding speed kept in stick, a loss of
        μ (1 + e) v_n in slip).

    Examples
    --------
    A 1 kg solid sphere (W = 7/2 1/kg in the tangent plane) sliding at 1 m/s:

    >>> import numpy as np
    >>> from contact_sim.coupling import friction_impulse
    >>> W = np.eye(2) * 3.5
    >>> friction_impulse(2.0, [1.0, 0.0], W, 0.5)        # stick: -v / W
    array([-0.28571429, -0.        ])
    >>> friction_impulse(0.2, [1.0, 0.0], W, 0.5)        # slip: -mu P
    array([-0.1, -0. ])
    """
    v = np.asarray(slip_velocity, dtype=float)
    speed = float(np.hypot(v[0], v[1]))
    bound = friction * max(normal_impulse, 0.0)
    if speed == 0.0 or bound == 0.0:
        return np.zeros(2)
    stick = -np.linalg.solve(np.asarray(inverse_mass, dtype=float), v)
    if float(np.hypot(stick[0], stick[1])) <= bound:
        return stick
    return -bound * v / speed
