"""How a contact phase can end: which roots end it, and whether its end is a stiff creep.

Lift-off is the first instant the clamped force returns to zero.  A law with n > p
(Azad-Featherstone, Lee-Wang, linear) can lose its force while z > 0 (the root of
φ = z^(n-p) + (λ/k) ż|ż|^(q-1)).  With n = p (Hunt-Crossley) φ obeys
φ̇ = λ q |ż|^(q-1) (a - zⁿ φ / m), a the other forces per unit mass: under gravity and drag
(a >= 0 on the way out) φ only decays towards zero, the sphere leaves at z = 0, and a heavily
damped impact creeps out on the damper's time scale (stiff, as the creep into rest under gravity).
"""


def force_can_vanish_inside(law, gravity, forcing=None):
    """Whether lift-off may come at a zero of the force while z > 0, not only at the surface.

    Parameters
    ----------
    law : ContactLaw
        The contact law.
    gravity : float
        g in m/s² (>= 0), along +z.
    forcing : Forcing, optional
        The forcing besides gravity.

    Returns
    -------
    bool
        ``law.force_vanishes_inside`` (n > p), or a forcing that can pull the sphere out
        (|A| > g): only then is the force-zero root tested.  Otherwise a root of φ inside is
        round-off, which ended heavily damped Hunt-Crossley impacts early (54-98 % short at
        ζ >= 46).
    """
    pulls = forcing is not None and pulls_out(gravity, forcing.acceleration_amplitude)
    return law.force_vanishes_inside or pulls


def pulls_out(gravity, acceleration_amplitude):
    """Whether a forcing of amplitude A (m/s²) can pull the sphere out against ``gravity`` g
    (m/s²): |A| > g.

    Examples
    --------
    >>> pulls_out(9.81, -12.0), pulls_out(9.81, 5.0)
    (True, False)
    """
    return abs(acceleration_amplitude) > gravity


def is_stiff(law, gravity, damping, threshold):
    """Whether a phase of damping group ζ = ``damping`` ends in a stiff creep.

    Parameters
    ----------
    law : ContactLaw
        The contact law.
    gravity : float
        g in m/s² (>= 0).
    damping : float
        The phase's damping group ζ (dimensionless).
    threshold : float
        The ζ above which a creep is stiff for the integrator at hand.

    Returns
    -------
    bool
        ζ > ``threshold`` and the phase can creep: into rest under gravity, or out to the
        surface when the force cannot vanish inside (module doc).
    """
    creeps = gravity > 0.0 or not force_can_vanish_inside(law, gravity)
    return creeps and damping > threshold
