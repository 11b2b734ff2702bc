"""Damping from restitution: the inverse of ``restitution``, and least-squares fits to data.

As in the paper's Fig. 5: k comes from Hertz theory, and λ is tuned so that the model's
restitution e(v) best matches measured (speed, restitution) points, all points weighted equally.
Units: SI (stiffness N/m^n, mass kg, speeds m/s, damping λ N·s^q/m^(p+q)).
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from contact_sim.impact.dimensionless_outcomes import dimensionless
from contact_sim.impact.fit_options import MAX_POINTS, require_fit_options
from contact_sim.impact.outcomes import damping_from_group, restitution
from contact_sim.impact.scales import ZETA_MAX, checked_scales
from contact_sim.model import LAWS, Contact, ContactLaw, require_law
from contact_sim.validation import (InputError, require_mass, require_positive, require_range,
                                    require_real_array)


def group_for_restitution(law, target):
    """ζ with e(ζ) = target (e decreases monotonically in ζ)."""
    def residual(log_zeta):
        return float(dimensionless('restitution', law, np.array(math.exp(log_zeta)))) - target

    curve = law.master_curve
    lo, hi = (math.log(z) for z in curve.zeta_range) if curve else (math.log(1e-5),
                                                                        math.log(1e3))
    while residual(lo) < 0.0:
        lo -= 2.0
    while residual(hi) > 0.0:
        hi += 2.0
    return math.exp(brentq(residual, lo, hi, xtol=1e-14, rtol=1e-14))


def damping_for_restitution(law, stiffness, mass, restitution, speed):
    """The damping λ that gives exactly ``restitution`` for an impact at ``speed``, no gravity.

    Parameters
    ----------
    law : ContactLaw
        The law.
    stiffness : float
        Stiffness k, N/m^n, > 0.
    mass : float
        The (reduced) mass, kg, > 0.
    restitution : float
        The target e, 0 < e <= 1.
    speed : float
        The impact speed, m/s, > 0.

    Returns
    -------
    float
        Damping λ, N·s^q/m^(p+q) (0 for e = 1).

    Raises
    ------
    InputError
        Keyed ``law``, ``stiffness``, ``mass``, ``restitution`` or ``speed``: a law that is not a
        ``ContactLaw`` (a name among them), a value out of range, or an e below what the largest
        damping group gives.

    See Also
    --------
    restitution : The forward map, e for a λ.
    fit_damping : The λ fitted to many (speed, restitution) points.

    Examples
    --------
    >>> import contact_sim as cs
    >>> lam = cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, 1.0952e10, 0.06735, 0.7, 1.0)
    >>> print(f"{lam:.4e}")
    1.1878e+05
    >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.0952e10, lam)
    >>> print(f"{cs.restitution(contact, 0.06735, 1.0):.6f}")
    0.700000
    """
    return _damping_for_restitution(require_law(law), require_positive('stiffness', stiffness),
                                    require_positive('mass', mass), restitution, speed)


def _damping_for_restitution(law, stiffness, mass, restitution, speed):
    """``damping_for_restitution`` for a ``ContactLaw`` and checked k, m."""
    # Z, T of the undamped contact finite: else an InputError on speed
    checked_scales(Contact(law, stiffness, 0.0), mass, speed, 'speed')
    e = require_range('restitution', restitution, 0.0, 1.0, low_open=True)
    if e == 1.0:
        return 0.0
    e_min = _lowest_restitution(law)
    if e < e_min:   # λ would give a damping group beyond what restitution() answers
        raise InputError('restitution', e, '{n[restitution]} = {value} is out of range for law '
                         '%s: allowed %.12g <= {n[restitution]} <= 1 (damping group zeta <= %g)'
                         % (law.name, e_min * (1.0 + 1e-9), ZETA_MAX))
    zeta = group_for_restitution(law, e)
    lam = float(damping_from_group(law, stiffness, mass, speed, zeta))
    if not 0.0 < lam < math.inf:
        raise InputError('speed', speed, '{n[speed]} = {value} is out of range for this contact: '
                         'the damping lambda = %r is not a finite positive number' % lam)
    return lam


def _lowest_restitution(law):
    """e at the largest damping group ``restitution`` accepts, ζ = ZETA_MAX."""
    return float(dimensionless('restitution', law, np.array(ZETA_MAX)))


@dataclass(frozen=True)
class DampingFit:
    """Least-squares damping for one law, with diagnostics, as ``fit_damping`` returns it.

    ``pointwise_damping`` is the λ that would match each point alone: a law that describes the
    data gives nearly constant values (their spread, ``pointwise_spread``, is max/min).
    ``flagged`` lists the points with e >= 1 (measurement noise near e = 1: kept in the fit,
    but no λ matches them alone, so their pointwise λ is 0 for e = 1 and nan above); ``loss``
    is the least-squares loss used and ``weights`` the robust weight of each point (1 = full).

    Attributes
    ----------
    law : ContactLaw
        The law fitted.
    stiffness : float
        Stiffness k, N/m^n (given, not fitted).
    damping : float
        The fitted λ, N·s^q/m^(p+q).
    rms_residual : float
        Root mean square of the residuals in e (dimensionless).
    residuals : numpy.ndarray
        Model minus measured e, per point.
    pointwise_damping : numpy.ndarray
        The λ matching each point alone, N·s^q/m^(p+q) (0 for e = 1, nan above).
    confidence_interval : tuple of float
        (low, high) of λ at ``confidence_level``, N·s^q/m^(p+q); (nan, nan) for one point.
    confidence_level : float
        The interval's level, 0 < level < 1.
    flagged : tuple of int
        Indices of the points with e >= 1.
    loss : str
        The least-squares loss (one of ``LOSSES``).
    weights : numpy.ndarray
        The robust weight of each point (1 = full).

    Examples
    --------
    >>> import contact_sim as cs
    >>> v = [0.5, 1.0, 1.5, 2.0]             # impact speeds, m/s
    >>> e = [0.77, 0.735, 0.72, 0.705]       # measured restitutions
    >>> fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, 1.0952e10, 0.06735, v, e)
    >>> print(f"spread {fit.pointwise_spread:.3f}, rms {fit.rms_residual:.4f}")
    spread 1.036, rms 0.0028
    """

    law: ContactLaw
    stiffness: float
    damping: float
    rms_residual: float
    residuals: np.ndarray
    pointwise_damping: np.ndarray
    confidence_interval: tuple
    confidence_level: float
    flagged: tuple = ()
    loss: str = 'linear'
    weights: np.ndarray = None

    @property
    def pointwise_spread(self):
        """Max / min of the positive finite ``pointwise_damping`` (1: one λ fits every point).

        nan if there is none.
        """
        lam = self.pointwise_damping[np.isfinite(self.pointwise_damping)
                                     & (self.pointwise_damping > 0.0)]
        return float(np.max(lam) / np.min(lam)) if lam.size else math.nan

    def contact(self):
        """The fitted contact.

        Returns
        -------
        Contact
            ``Contact(law, stiffness, damping)``.

        Examples
        --------
        >>> import contact_sim as cs
        >>> fit = cs.fit_damping(cs.LINEAR, 1e5, 0.05, [1.0, 2.0], [0.8, 0.8])
        >>> fit.contact().law.name
        'linear'
        """
        return Contact(self.law, self.stiffness, self.damping)


def _check_points(name, values, count=None, what='', note=''):
    """``values`` as a 1-D float array of finite reals > 0 (``count`` of them if given)."""
    x = require_real_array(name, values, MAX_POINTS).ravel()
    if count is not None and x.size != count:
        raise InputError(name, x.size, '{n[speeds]} and {n[%s]} have %d and {value} values: '
                         'allowed equal lengths' % (name, count), value=str(x.size))
    if not np.all(x > 0.0):
        i = int(np.flatnonzero(~(x > 0.0))[0])
        raise InputError(name, float(x[i]), '{n[%s]}[%d] = {value} is out of range: allowed '
                         '0 < %s < inf%s' % (name, i, what, note))
    return x


def _check_data(speeds, restitutions):
    v = _check_points('speeds', speeds, what='speed')
    if v.size < 1:
        raise InputError('speeds', 0, '{n[speeds]} is empty: allowed at least one (speed, '
                         'restitution) point')
    e = _check_points('restitutions', restitutions, v.size, 'restitution',
                      ' (e >= 1 is kept and flagged)')
    return v, e


LOWER_BOUND_WIDENINGS = 12   # x 3 in ln λ (e^-36): how far points at e >= 1 may pull λ down


def robust_weights(loss, z2):
    """IRLS weight ρ'(z²) of each point for a least_squares loss (1 = full weight)."""
    if loss == 'soft_l1':
        return 1.0 / np.sqrt(1.0 + z2)
    if loss == 'huber':
        return np.where(z2 <= 1.0, 1.0, 1.0 / np.sqrt(np.maximum(z2, 1e-300)))
    if loss == 'cauchy':
        return 1.0 / (1.0 + z2)
    if loss == 'arctan':
        return 1.0 / (1.0 + z2 * z2)
    return np.ones_like(z2)


def fit_damping(law, stiffness, mass, speeds, restitutions, confidence=0.95, loss='linear',
                uncertainties=None):
    """Fit λ to measured (speed, restitution) points by least squares in e.

    The confidence interval is linearised in ln λ: λ exp(± t σ / abs(J)), with J = ∂e/∂ln λ at the
    optimum and σ² the residual variance (N - 1 degrees of freedom); one point leaves no
    residual variance, and every point at e >= 1 gives λ = 0 (no ln λ): the interval is then
    (nan, nan).
    Points with e >= 1 (noise near e = 1) are kept in the fit and listed in ``flagged``.
    ``uncertainties`` (σ_e per point, > 0) weight each residual by 1/σ_e.  ``loss`` (one of
    ``LOSSES``, as in ``scipy.optimize.least_squares``) makes the fit robust: its scale is one
    σ_e when uncertainties are given, else 1.4826 × the median absolute residual of the plain fit;
    ``weights`` reports how much each point still counts.

    Parameters
    ----------
    law : ContactLaw
        The law.
    stiffness : float
        Stiffness k, N/m^n, > 0 (from Hertz theory, ``hertz_stiffness``).
    mass : float
        The (reduced) mass, kg, > 0.
    speeds : array_like of float
        Impact speeds, m/s, > 0, one per point.
    restitutions : array_like of float
        Measured e, > 0 (e >= 1 is kept and flagged), one per point.
    confidence : float, optional
        The interval's level, 0 < confidence <= 0.999999 (default 0.95).
    loss : str, optional
        One of ``LOSSES`` (default ``'linear'``: plain least squares).
    uncertainties : array_like of float, optional
        Uncertainty σ_e of each point, > 0 (default: all equal).

    Returns
    -------
    DampingFit
        The fitted λ, its interval, the residuals and the diagnostics.

    Raises
    ------
    InputError
        Keyed ``law``, ``stiffness``, ``mass``, ``confidence``, ``loss``, ``speeds`` or
        ``restitutions`` (with the point's index): a value out of range, a law that is not a
        ``ContactLaw`` (a name among them) or an unknown loss.
    ValueError
        ``speeds``, ``restitutions`` or ``uncertainties`` of different lengths, empty, or with
        a value out of range.

    See Also
    --------
    compare_laws : Every law fitted to the same points, ranked.

    Examples
    --------
    >>> import contact_sim as cs
    >>> v = [0.5, 1.0, 1.5, 2.0]             # impact speeds, m/s
    >>> e = [0.77, 0.735, 0.72, 0.705]       # measured restitutions
    >>> fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, 1.0952e10, 0.06735, v, e)
    >>> low, high = fit.confidence_interval
    >>> print(f"lambda = {fit.damping:.4e} ({low:.3e} to {high:.3e}) N s/m^1.5")
    lambda = 1.0031e+05 (9.794e+04 to 1.027e+05) N s/m^1.5
    """
    law = require_law(law)
    stiffness = require_positive('stiffness', stiffness)
    mass = require_mass(mass)
    confidence, loss = require_fit_options(confidence, loss)
    v, e = _check_data(speeds, restitutions)
    if uncertainties is None:
        sigma, unit = np.ones(v.size), 1.0
    else:
        sigma = _check_points('uncertainties', uncertainties, v.size, 'uncertainty')
        # in units of their largest: 1e-300 or 1e300 (equal) weigh the points as 1 does
        unit = float(sigma.max())
        sigma = sigma / unit
        if not np.all(sigma > 0.0):
            raise InputError('uncertainties', float(sigma.min() * unit), '{n[uncertainties]} '
                             'spans more than the doubles hold (smallest {value}, largest %g): '
                             'allowed ratios largest/smallest < 1e300' % unit)
    flagged = tuple(int(i) for i in np.flatnonzero(e >= 1.0))
    pointwise = np.full(v.size, math.nan)      # nan where e > 1: no damping gives it
    for i, (vi, ei) in enumerate(zip(v, e)):
        try:     # (e > 1: the speed is checked all the same, and the point has no λ)
            lam_i = _damping_for_restitution(law, stiffness, mass, min(ei, 1.0), vi)
            pointwise[i] = lam_i if ei <= 1.0 else math.nan
        except InputError as error:    # name the data point it came from
            which = {'speed': 'speeds', 'restitution': 'restitutions'}.get(error.field)
            if which is None:          # the contact's own (stiffness, mass): as it is
                raise
            template = error.template.replace('{n[%s]}' % error.field,
                                              '{n[%s]}[%d]' % (which, i))
            raise InputError(which, error.value, template, **error.params) from None

    def model(lam):
        return restitution(Contact(law, stiffness, lam), mass, v)

    def sse(log_lam):
        return float(np.sum(((model(math.exp(log_lam)) - e) / sigma) ** 2))

    usable = pointwise[np.isfinite(pointwise) & (pointwise > 0.0)]
    weights = np.ones(v.size)
    if usable.size == 0:
        lam = 0.0          # every point at e >= 1: the elastic contact fits best
    else:
        lo, hi = math.log(usable.min()), math.log(usable.max())
        if hi - lo < 1e-12 and not flagged:
            lam = float(usable[0])
        else:
            # points at e >= 1 pull λ below every pointwise value: widen the search downwards
            # for as long as its optimum sits on the lower bound (e is monotone in λ)
            for _ in range(LOWER_BOUND_WIDENINGS if flagged else 1):
                if flagged:
                    lo -= 3.0
                best = minimize_scalar(sse, bounds=(lo, hi), method='bounded',
                                       options={'xatol': 1e-10})
                if best.x > lo + 1e-3:
                    break
            lam = math.exp(best.x)
        if loss != 'linear':
            from scipy.optimize import least_squares
            r0 = (model(lam) - e) / sigma
            scale = unit if uncertainties is not None else max(
                1.4826 * float(np.median(np.abs(r0))), 1e-12)
            robust = least_squares(lambda x: (model(math.exp(x[0])) - e) / sigma,
                                   [math.log(lam)], loss=loss, f_scale=scale,
                                   xtol=1e-12, ftol=1e-12)
            lam = math.exp(float(robust.x[0]))
            weights = robust_weights(loss, (((model(lam) - e) / sigma) / scale) ** 2)
    residuals = model(lam) - e
    rms = float(np.sqrt(np.mean(residuals ** 2)))
    # linearised in ln λ, so the interval stays positive: ln λ ± t σ / |∂e/∂ln λ|
    h = 1e-6
    jac = (model(lam * math.exp(h)) - model(lam * math.exp(-h))) / (2 * h) if lam > 0.0 \
        else np.zeros(v.size)
    dof = v.size - 1
    if dof == 0 or lam == 0.0:   # one point: no residual variance to estimate a spread from;
        # every point at e >= 1: λ = 0 fits best, and no interval in ln λ is defined
        return DampingFit(law, stiffness, lam, rms, residuals, pointwise, (math.nan, math.nan),
                          confidence, flagged, loss, weights)
    if np.any(jac != 0.0):
        from scipy.stats import t as student_t  # slow to import: only when needed
        w = weights / sigma ** 2
        scale2 = float(np.sum(w * residuals ** 2)) / dof
        half = float(student_t.ppf(0.5 + confidence / 2, dof) * math.sqrt(scale2)
                     / np.sqrt(np.sum(w * jac ** 2)))
    else:
        half = 0.0
    return DampingFit(law, stiffness, lam, rms, residuals, pointwise,
                      (lam * math.exp(-half), lam * math.exp(half)), confidence, flagged,
                      loss, weights)


def compare_laws(stiffness, mass, speeds, restitutions, laws=None, confidence=0.95,
                 loss='linear', uncertainties=None):
    """Fit each law to the same data and rank them, best (lowest rms residual) first.

    Parameters
    ----------
    stiffness : float or dict
        One k for every law (N/m^n), or a mapping ``ContactLaw`` -> k (the linear law's k has
        other units than the Hertz k; its fitted restitution does not depend on k).
    mass : float
        The (reduced) mass, kg, > 0.
    speeds : array_like of float
        Impact speeds, m/s, > 0.
    restitutions : array_like of float
        Measured e, > 0, one per speed.
    laws : list of ContactLaw, optional
        The laws fitted (default: every law of ``LAWS``).
    confidence, loss, uncertainties : optional
        As in ``fit_damping``.

    Returns
    -------
    list of DampingFit
        One fit per law, lowest ``rms_residual`` first.

    Raises
    ------
    InputError
        As ``fit_damping``, or keyed ``laws`` (not a list of ``ContactLaw``) or ``stiffness``
        (a mapping without a law fitted).
    ValueError
        As ``fit_damping``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> v = [0.5, 1.0, 1.5, 2.0]             # impact speeds, m/s
    >>> e = [0.77, 0.735, 0.72, 0.705]       # measured restitutions
    >>> fits = cs.compare_laws(1.0952e10, 0.06735, v, e,
    ...                        laws=[cs.AZAD_FEATHERSTONE, cs.HUNT_CROSSLEY])
    >>> for fit in fits:
    ...     print(f"{fit.law.name}: rms {fit.rms_residual:.4f}")
    azad_featherstone: rms 0.0028
    hunt_crossley: rms 0.0681
    """
    if laws is not None and (isinstance(laws, (str, ContactLaw)) or not hasattr(laws, '__iter__')):
        raise InputError('laws', laws, '{n[laws]} = {value} is not a list of laws: allowed a list '
                         'of ContactLaw objects (cs.LAWS: %s)' % ', '.join(LAWS))
    chosen = [require_law(law, 'laws') for law in (laws if laws is not None else LAWS.values())]
    if isinstance(stiffness, dict):
        missing = [law.name for law in chosen if law not in stiffness]
        if missing:
            raise InputError('stiffness', stiffness, '{n[stiffness]} has no value for %s: '
                             'allowed one stiffness for every law, or a mapping with an entry '
                             'for each law fitted (%s)' % (', '.join(missing),
                                                          ', '.join(law.name for law in chosen)))
    fits = []
    for law in chosen:
        k = stiffness[law] if isinstance(stiffness, dict) else stiffness
        fits.append(fit_damping(law, k, mass, speeds, restitutions, confidence, loss,
                                uncertainties))
    return sorted(fits, key=lambda fit: fit.rms_residual)
