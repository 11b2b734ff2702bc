"""The dimensionless impact results e, τc, F̂ and x̂ as functions of the damping group ζ.

For each ζ the best source the law has: its closed form (``ContactLaw.closed_form``), its
master curve (``ContactLaw.master_curve``) and the tails beyond it (``tails``), and where
neither reaches, the exact integration of the unit impact by ``simulate_impact`` (a custom law
is integrated, with a warning the first time).
"""
import warnings

import numpy as np

from contact_sim.impact.simulate import simulate_impact
from contact_sim.impact.tails import restitution_tails
from contact_sim.model import Contact


def master_curve(law):
    """The shipped master curve of a law.

    Parameters
    ----------
    law : ContactLaw
        The law.

    Returns
    -------
    MasterCurve or None
        ``law.master_curve``: registered per law (its name and exponents), so a custom law has
        none even where its exponents equal a named law's, and is integrated.
    """
    return law.master_curve


_WARNED = set()


def _warn_integrating(law):
    if law.name not in _WARNED:
        _WARNED.add(law.name)
        warnings.warn(f'law {law.name!r} has no master curve or closed form here: its '
                      'restitution is integrated impact by impact (milliseconds each)',
                      RuntimeWarning, stacklevel=4)


def _exact_dimensionless(law, zeta):
    """(e, τc, F̂, x̂) of the unit problem, by ``simulate_impact`` (the slow path)."""
    r = simulate_impact(Contact(law, 1.0, float(zeta)), 1.0, 1.0)
    return {'restitution': r.restitution, 'duration': r.contact_duration,
            'peak_force': r.peak_force, 'max_penetration': r.max_penetration}


def dimensionless(quantity, law, zeta):
    """e, τc, F̂ or x̂ at the groups ``zeta`` (array, ζ >= 0) for ``law``: closed form, table or
    exact integration, in that order of preference."""
    zeta = np.asarray(zeta, dtype=float)
    closed = law.closed_form
    out = np.full(zeta.shape, np.nan)
    todo = np.ones(zeta.shape, dtype=bool)
    positive = zeta > 0.0
    if quantity == 'restitution':      # no damping: perfectly elastic, exactly
        out = np.where(positive, out, 1.0)
        todo = positive
    if closed is not None and quantity in closed.vector:
        out = np.where(positive, closed.vector[quantity](np.where(positive, zeta, 1.0)), out)
        todo &= ~positive
    else:
        curve = law.master_curve
        if curve is not None:
            value, inside = curve.evaluate(quantity, np.where(positive, zeta, 1.0))
            inside &= positive
            out = np.where(inside, value, out)
            todo &= ~inside
            tails = restitution_tails(law)
            if tails is not None and quantity != 'restitution':
                low = todo & positive & (zeta < tails.zeta0)
                out = np.where(low, tails.near_elastic(quantity, np.where(low, zeta, 0.0)), out)
                todo &= ~low
            elif tails is not None:
                low = todo & (zeta < tails.zeta0)
                high = todo & (zeta > tails.zeta1)
                out = np.where(low, tails.small(np.where(low, zeta, 0.0)), out)
                out = np.where(high, tails.large(np.where(high, zeta, tails.zeta1)), out)
                todo &= ~(low | high)
        elif np.any(todo):
            _warn_integrating(law)
    for z in np.unique(zeta[todo]):
        out[todo & (zeta == z)] = _exact_dimensionless(law, z)[quantity]
    return np.minimum(out, 1.0) if quantity == 'restitution' else out
