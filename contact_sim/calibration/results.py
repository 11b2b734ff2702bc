"""What ``fit_bounces`` returns: the fit of one law (``LawFit``) and of all laws, ranked, with
the glitches and the prepared data (``BounceFit``).  Units: SI."""
import math
from dataclasses import dataclass, field

import numpy as np

from contact_sim.flight import AirDrag
from contact_sim.model import Contact, ContactLaw


@dataclass(frozen=True)
class LawFit:
    """The fit of one law to all sequences (SI units)."""

    law: ContactLaw
    stiffness: float
    damping: float
    damping_interval: tuple       # (nan, nan) when undetermined (``message`` says why)
    drag_coefficient: float
    drag_interval: tuple          # (nan, nan) when C_d was not fitted
    start_times: np.ndarray       # t₁ per sequence (s)
    first_speeds: np.ndarray      # v₁ per sequence (m/s)
    release_heights: np.ndarray   # h(v₁) per sequence (m)
    residuals: list               # per sequence, predicted - measured (s), kept clicks only
    weights: list                 # per sequence, the robust loss weights (1 = full weight)
    rms: float                    # weighted rms timing residual (s)
    aic: float
    parameters: int
    observations: int
    noise: float                  # estimated timing noise (s)
    success: bool                 # the solver converged and every interval is determined
    message: str                  # what went wrong, or the solver's convergence message
    status: str = 'converged'     # 'converged'; 'ill-determined' (converged, but an interval
    #                               spans orders of magnitude or the clicks do not outnumber
    #                               the parameters); 'at-bound' (C_d at a bound of its range:
    #                               the law needs an implausible drag); 'FAILED' (the solver
    #                               did not converge, or lambda collapsed to 0)

    def contact(self):
        return Contact(self.law, self.stiffness, self.damping)


@dataclass(frozen=True)
class BounceFit:
    """``fit_bounces`` result: laws ranked best first, the glitches and the prepared data.

    Attributes
    ----------
    fits : list of LawFit
        One fit per law, best (lowest weighted rms timing residual) first.
    sequences : list
        The prepared sequences (``ImpactTimes``), as fitted.
    glitches : list of Glitch
        Detector glitches found: doubled clicks, missed bounces, late starts and the outliers
        the robust loss down-weighted (each says whether it was left out).
    mass : float
        The sphere's mass, kg.
    gravity : float
        Gravity g, m/s².
    drag : AirDrag or None
        The air drag in flight (``None``: vacuum).
    fit_drag : bool
        Whether C_d was fitted.
    confidence : float
        The level of the intervals.
    timing_resolution : float
        The clock's resolution, s.
    speed_dependent : bool
        True if ``delta_aic`` > ``SUPPORT_DELTA_AIC``: the data support a speed-dependent e.
    delta_aic : float
        AIC of the best constant-restitution law minus the best speed-dependent law's (nan
        unless both kinds were fitted).
    adequacy : Adequacy or None
        Whether any law describes the recording.
    holdout : list or None
        ``holdout.Holdout`` per law (the fits' order), or ``None``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> recorded = cs.predict_bounces(contact, mass, height=0.1, count=6).times
    >>> fit = cs.fit_bounces(contact.stiffness, mass, [recorded],
    ...                      laws=[cs.AZAD_FEATHERSTONE, cs.HUNT_CROSSLEY])
    >>> print(f"{fit.best.law.name}, trustworthy: {fit.trustworthy}")
    azad_featherstone, trustworthy: True
    """

    fits: list
    sequences: list
    glitches: list
    mass: float
    gravity: float
    drag: object
    fit_drag: bool
    confidence: float
    timing_resolution: float
    speed_dependent: bool = field(default=False)
    delta_aic: float = field(default=math.nan)
    adequacy: object = field(default=None)    # ``adequacy.Adequacy``: does any law describe it
    holdout: list = field(default=None)       # ``holdout.Holdout`` per law (fits' order), or None

    def rates(self, law_fit=None):
        """The drag rates in flight with the C_d of a law's fit.

        Parameters
        ----------
        law_fit : LawFit, optional
            The fit whose ``drag_coefficient`` is used (default: ``best``).

        Returns
        -------
        tuple of float
            (κ in 1/m, β in 1/s); (0, 0) in vacuum.
        """
        lf = law_fit or self.best
        if self.drag is None:
            return 0.0, 0.0
        return AirDrag(self.drag.air_density, lf.drag_coefficient, self.drag.radius,
                       self.drag.linear_coefficient).rates(self.mass, self.gravity)

    @property
    def trustworthy(self):
        """True when the best law's fit succeeded and it describes the recording."""
        return self.best.success and (self.adequacy is None or self.adequacy.adequate)

    @property
    def best(self):
        """The best fit, ``fits[0]``."""
        return self.fits[0]

    def downweighted(self, fit=None):
        """The clicks the robust loss down-weighted (weight below 0.5).

        Parameters
        ----------
        fit : LawFit, optional
            The law's fit (default: ``best``).

        Returns
        -------
        list of tuple
            (sequence index, time s, residual s, weight) per click.
        """
        fit = fit or self.best
        out = []
        for j, (seq, r, w) in enumerate(zip(self.sequences, fit.residuals, fit.weights)):
            for t, ri, wi in zip(seq.times, r, w):
                if wi < 0.5:
                    out.append((j, float(t), float(ri), float(wi)))
        return out
