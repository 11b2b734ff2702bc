"""The way out of a heavily damped impact whose force vanishes inside, integrated in its force.

A law with n > p (Azad-Featherstone, Lee-Wang, linear) lifts off where the reduced force
φ = x^(n-p) + ζ u (q = 1, in the phase's units x = z / Z, u = dx/dτ) returns to zero while
x > 0.  With heavy damping (ζ >> 1) the two terms of φ agree near lift-off to about 1/ζ² of
their size, and the lift-off instant is set by a remnant of the fast overdamped mode far below
the resolution of u: an integration in (x, u) gets the contact duration wrong by 1e-5 at
ζ = 1e3 and by 2 % at ζ = 1e4 (linear law), whatever its tolerances, since the rounding of u
limits it.  φ itself obeys a smooth equation,

    φ' = (n - p) x^(n-p-1) u + ζ (γ - xᵖ φ),    u = (φ - x^(n-p)) / ζ,

in which the fast mode is φ alone and decays with relative accuracy; lift-off is then a root
of a state variable.  From the maximum penetration (u = 0, φ = x^(n-p): no cancellation) to
lift-off the impact is integrated in (x, φ); the rebound rate there is u = -x^(n-p) / ζ.
That start carries the fast mode as φ = x^(n-p) + ζ u ≈ x^(n-p), so u must be known there to
about rtol x^(n-p) / ζ: the phase before it is integrated at atol / ζ² (``way_in_atol``; the
deepest penetration x^(n-p) falls no faster than 1/ζ for these laws).
"""
from scipy.integrate import solve_ivp

from contact_sim.phase import DEFAULT_ATOL

# ζ above which ``simulate_impact`` takes the way out in (x, φ): below it the (x, u) phase is
# within 3e-11 of the closed forms (docs/limits.md, scripts/impact_accuracy.py)
TAIL_DAMPING = 10.0


def needs_force_tail(law, damping):
    """Whether an impact of ``law`` at damping group ζ = ``damping`` leaves by ``force_tail``.

    Parameters
    ----------
    law : ContactLaw
        The contact law.
    damping : float
        The phase's damping group ζ (dimensionless).

    Returns
    -------
    bool
        The force can vanish inside (n > p), the damping is linear in the rate (q = 1, so that
        u follows from φ) and ζ > ``TAIL_DAMPING``.
    """
    return law.force_vanishes_inside and law.linear_in_rate and damping > TAIL_DAMPING


def way_in_atol(damping):
    """The absolute tolerance of the phase up to the deepest point of a ``force_tail`` impact:
    ``DEFAULT_ATOL / ζ²`` (module doc)."""
    return DEFAULT_ATOL / damping ** 2


def deepest_point(points):
    """The recorded point (t, z, ż, F) of largest penetration (located where ż = 0)."""
    return max(points, key=lambda point: point[1])


def force_tail(law, scales, start_time, deepest, rtol, horizon):
    """Integrate from the deepest point to lift-off in (x, φ).

    Parameters
    ----------
    law : ContactLaw
        The contact law (n > p, q = 1).
    scales : PhaseScales
        Z (m), T (s), γ and ζ of the phase.
    start_time : float
        Time (s) at which the phase started (τ = 0).
    deepest : tuple of float
        (t, z, ż, F) at the maximum penetration, in s, m, m/s, N.
    rtol : float
        Relative tolerance of the integration.
    horizon : float
        A time (s) after ``deepest[0]`` by which lift-off must have come; the search runs to
        ten times that interval.

    Returns
    -------
    tuple or None
        (t, z, ż, steps) at lift-off in s, m, m/s and the number of steps taken, or ``None``
        if φ did not return to zero in the search (the sphere stays in contact).

    Examples
    --------
    >>> from contact_sim.model import LINEAR
    >>> from contact_sim.phase import PhaseScales
    >>> t, z, zdot, steps = force_tail(LINEAR, PhaseScales(1.0, 1.0, 0.0, 1e4), 0.0,
    ...                                (1e-3, 1e-4, 0.0, 1e-4), 1e-12, 1e-2)
    >>> zdot < 0.0 < z
    True
    """
    n, p = law.n, law.p
    length, time, gamma, zeta = scales.length, scales.time, scales.gamma, scales.zeta
    tau0 = (deepest[0] - start_time) / time
    x0 = deepest[1] / length
    u0 = deepest[2] * time / length
    m = n - p

    def rhs(tau, y):
        x, phi = y
        x = max(x, 0.0)
        u = (phi - x ** m) / zeta
        return [u, m * x ** (m - 1.0) * u + zeta * (gamma - x ** p * phi)]

    def lift_off(tau, y):
        return y[1]
    lift_off.terminal, lift_off.direction = True, -1

    tau1 = tau0 + 10.0 * max(horizon - deepest[0], 0.0) / time
    # φ decays by many orders on the way out: its error is controlled relative to itself
    sol = solve_ivp(rhs, (tau0, tau1), [x0, x0 ** m + zeta * u0], method='DOP853', rtol=rtol,
                    events=lift_off, atol=[rtol * x0 * 1e-3, 1e-300])
    if sol.status != 1 or not sol.t_events[0].size:
        return None
    tau, (x, _) = float(sol.t_events[0][0]), sol.y_events[0][0]
    x = max(float(x), 0.0)
    u = -x ** m / zeta
    return (start_time + tau * time, x * length, u * length / time, len(sol.t) - 1)
