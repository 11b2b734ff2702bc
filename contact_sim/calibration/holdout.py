"""The hold-out check of a bounce fit: fit the first part of each sequence, predict the rest.

Each sequence's clicks are numbered first (the glitches named on the whole sequence), then its
last ``fraction`` of clicks is held out: the laws are fitted on the earlier clicks too (beside
their fit on all the clicks, which stays the reported one), and each
fitted law (its λ, C_d, and the sequence's own start time and first speed) predicts the held-out
click times through the same bounce model (``bounces.impact_sequence``).  The prediction's rms,
per sequence and over every held-out click, is what the fit is worth beyond the data it saw:
drop-to-drop scatter and a wrong law both show there, not in the fit's own residuals.
Units: SI.
"""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.calibration.bounces import impact_sequence
from contact_sim.calibration.glitches import PreparedSequence
from contact_sim.model import ContactLaw
from contact_sim.validation import require_range

MIN_FITTED_CLICKS = 3      # a sequence keeps at least this many clicks to fit


@dataclass(frozen=True)
class Holdout:
    """The held-out clicks of every sequence predicted by one fitted law (s)."""

    law: ContactLaw
    held: list            # per sequence, the held-out clicks (PreparedSequence)
    residuals: list       # per sequence, predicted - measured (s)
    rms: np.ndarray       # per sequence (s)
    overall: float        # over every held-out click (s)
    fit: object = None    # the law's fit on the earlier clicks (``LawFit``) that predicts them


def split_sequences(prepared, fraction):
    """Each prepared sequence cut into the clicks fitted and the last ``fraction`` held out.

    Parameters
    ----------
    prepared : list of PreparedSequence
    fraction : float
        The share of each sequence's clicks held out, 0 < fraction < 1 (at least one click is
        held out, at least ``MIN_FITTED_CLICKS`` are fitted).

    Returns
    -------
    (list of PreparedSequence, list of PreparedSequence)
        The fitted and the held-out parts, sequence by sequence.

    Raises
    ------
    InputError, ValueError
        If ``fraction`` is out of range or leaves a sequence too few clicks to fit.
    """
    fraction = require_range('holdout', fraction, 0.0, 1.0, low_open=True, high_open=True)
    fitted, held = [], []
    for seq in prepared:
        n = seq.times.size
        cut = n - max(1, round(fraction * n))
        if cut < MIN_FITTED_CLICKS:
            name = seq.name or 'a sequence'
            raise ValueError(f'holdout = {fraction:g} leaves {cut} click(s) of {name} ({n} '
                             f'kept) to fit: allowed a share that keeps at least '
                             f'{MIN_FITTED_CLICKS}')
        fitted.append(PreparedSequence(seq.times[:cut], seq.index[:cut], seq.height, seq.name,
                                       seq.restitution_guess))
        held.append(PreparedSequence(seq.times[cut:], seq.index[cut:], seq.height, seq.name,
                                     seq.restitution_guess))
    return fitted, held


def predict_held(fit, law_fit, held):
    """The held-out clicks predicted by one law fitted on the others (module doc).

    Parameters
    ----------
    fit : BounceFit
        A fit of these sequences (its mass, gravity and drag).
    law_fit : LawFit
        The law fitted on the earlier clicks (its λ, C_d, start times and first speeds).
    held : list of PreparedSequence
        The held-out clicks, sequence by sequence (``split_sequences``).

    Returns
    -------
    Holdout
    """
    kappa, beta = fit.rates(law_fit)
    count = max(int(s.index[-1]) for s in held) + 1
    relative = impact_sequence(law_fit.law, law_fit.stiffness, law_fit.damping, fit.mass,
                               fit.gravity, np.asarray(law_fit.first_speeds, dtype=float),
                               count, kappa, beta)[0]
    residuals = [law_fit.start_times[j] + relative[j, s.index] - s.times
                 for j, s in enumerate(held)]
    rms = np.array([math.sqrt(float(np.mean(r * r))) for r in residuals])
    every = np.concatenate(residuals)
    return Holdout(law_fit.law, held, residuals, rms, math.sqrt(float(np.mean(every * every))),
                   law_fit)
