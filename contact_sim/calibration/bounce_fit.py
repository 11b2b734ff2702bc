"""Calibrating a contact from recorded bounce sequences: ``fit_bounces`` fits every law to the
impact times themselves (``timing_fit``) after naming the detector glitches (``glitches``), and
ranks the laws.

Laws have equal parameter counts, so they are ranked by the weighted rms timing residual; the
Akaike criterion N ln(SSE / N) + 2P is reported too (it ranks the same way then, and is the one to
compare when counts differ, e.g. with and without a fitted C_d).  The constant-restitution law is
the linear law (its e does not depend on speed); its stiffness, when not given, is chosen so that
its undamped contact lasts as long as the Hertz contact at the median impact speed.  The data are
said to support a speed-dependent restitution when the best speed-dependent law beats the constant
law by ΔAIC > 10; that verdict means something only if the best law describes the recording
(``BounceFit.adequacy``, judged on the held-out flights with ``holdout``;
``BounceFit.trustworthy``).  With ``holdout`` the laws are fitted twice: on all the clicks (the
fits returned) and on the earlier clicks (``Holdout.fit``, which predicts the held-out ones).
The robust loss's down-weighted points (weight < 0.5) are reported as outliers.
Units: SI.
"""
import math
from dataclasses import replace

import numpy as np

from contact_sim.calibration.adequacy import check_adequacy
from contact_sim.calibration.glitches import (MICRO_BOUNCE_RATIO, Glitch, MicroBounceCut,
                                              prepare_sequence)
from contact_sim.calibration.holdout import predict_held, split_sequences
from contact_sim.calibration.recordings import ImpactTimes, require_sizes
from contact_sim.calibration.results import BounceFit
from contact_sim.calibration.timing_fit import fit_law
from contact_sim.drop import VELOCITY_MAX
from contact_sim.flight import AirDrag
from contact_sim.impact import elastic_limits, impact_scales, require_fit_options
from contact_sim.model import LAWS, require_law
from contact_sim.validation import InputError, require_positive

SUPPORT_DELTA_AIC = 10.0     # evidence needed to call the restitution speed dependent


def _linear_stiffness(hertz_law, hertz_k, mass, speed):
    """k of a linear spring whose undamped contact π √(m/k) lasts as long as the Hertz one."""
    tau_unit = elastic_limits(hertz_law)['duration']   # dimensionless τc at ζ -> 0
    length, _ = impact_scales(hertz_law, hertz_k, mass, speed)
    return mass * (math.pi * speed / (tau_unit * length)) ** 2


def check_recording(sequence, gravity, resolution):
    """Refuse a sequence no bounce recording can be: an interval shorter than the clock's
    resolution, or a flight whose impact speed g T / 2 exceeds the drop's ``VELOCITY_MAX``.

    Parameters
    ----------
    sequence : ImpactTimes
    gravity, resolution : float
        g in m/s^2 and the timing resolution in s.

    Raises
    ------
    ValueError
        Naming the sequence, the interval and the allowed range.
    """
    dt = np.diff(sequence.times)
    name = sequence.name or 'sequence'
    shortest, longest = int(np.argmin(dt)), int(np.argmax(dt))
    if dt[shortest] < resolution:
        raise ValueError(f'{name}: times[{shortest + 1}] - times[{shortest}] = '
                         f'{float(dt[shortest]):g} s is out of range: allowed intervals of at '
                         f'least the timing resolution {resolution:g} s')
    flight_max = 2.0 * VELOCITY_MAX / gravity
    if dt[longest] > flight_max:
        raise ValueError(f'{name}: times[{longest + 1}] - times[{longest}] = '
                         f'{float(dt[longest]):g} s is out of range: allowed flights up to '
                         f'{flight_max:g} s (impacts up to {VELOCITY_MAX:g} m/s)')


def fit_bounces(stiffness, mass, sequences, laws=None, gravity=9.81, drag=None, fit_drag=False,
                timing_resolution=1.0 / 48000.0, height_error=0.01, loss='soft_l1',
                confidence=0.95, holdout=None, micro_bounce_ratio=MICRO_BOUNCE_RATIO,
                min_flight=0.0):
    """Fit λ (and optionally C_d) of each law to recorded bounce sequences; see module doc.

    Parameters
    ----------
    stiffness : float or dict
        One k for the Hertz laws (N/m^1.5), or a mapping ``ContactLaw`` -> k in that law's
        N/m^n; for the constant-restitution (linear) law a missing k is derived
        (module doc).
    mass : float
        The sphere's mass in kg.
    sequences : list of ImpactTimes or of arrays of times (s)
        The recorded sequences.
    laws : list of ContactLaw, optional
        The laws fitted (default: all, or with a mapping ``stiffness`` the laws it has and the
        linear law).
    gravity : float
        Gravity g, m/s^2.
    drag : AirDrag, optional
        The air drag in flight (its C_d the start value when ``fit_drag``); None: vacuum.
    fit_drag : bool
        Fit the drag coefficient too.
    timing_resolution : float
        The clock's resolution in s, 1/48000 s for a phone.
    height_error : float
        The uncertainty of a measured release height in m.
    loss : str
        The robust least-squares loss (``impact.LOSSES``).
    confidence : float
        The level of the intervals, 0 < confidence < 1.
    holdout : float, optional
        Hold out this share of each sequence's last clicks, 0 < holdout < 1: the laws are
        fitted on the others and predict them (``holdout`` module; ``BounceFit.holdout``).
    micro_bounce_ratio, min_flight : float
        Where the final micro-bounces are cut (``glitches.MicroBounceCut``): a contact time
        (of the softest law given) above this share of the flight before it, or a flight
        shorter than ``min_flight`` s.

    Returns
    -------
    BounceFit
        The laws' fits (``LawFit``), best first (``best``), with the glitches found.

    Raises
    ------
    InputError, ValueError
        For a law that is not a ``ContactLaw`` (a name among them), a value out of range, a missing stiffness, no sequences, a
        sequence ``check_recording`` refuses, or ``fit_drag`` without a drag to fit.

    See Also
    --------
    predict_bounces : The forward model, touch times for a contact.

    Examples
    --------
    Touch times predicted for λ = 9.996e4 N·s/m^1.5 are fitted back:

    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> recorded = cs.predict_bounces(contact, mass, height=0.1, count=6).times
    >>> fit = cs.fit_bounces(contact.stiffness, mass, [recorded],
    ...                      laws=[cs.AZAD_FEATHERSTONE, cs.HUNT_CROSSLEY])
    >>> best = fit.best
    >>> print(f"{best.law.name}: lambda = {best.damping:.5e}")
    azad_featherstone: lambda = 9.99598e+04
    """
    mass = require_positive('mass', mass)
    gravity = require_positive('gravity', gravity)
    resolution = require_positive('timing_resolution', timing_resolution)
    height_error = require_positive('height_error', height_error)
    confidence, loss = require_fit_options(confidence, loss)
    if drag is not None and not isinstance(drag, AirDrag):
        raise InputError('drag', drag, '{n[drag]} = {value} is not None or an AirDrag(air_density, '
                         'drag_coefficient, radius)')
    if fit_drag and (drag is None or drag.air_density == 0.0):
        raise ValueError('drag is missing: fitting the drag coefficient needs an AirDrag with '
                         'the air density and the sphere radius')
    if drag is not None and fit_drag and drag.drag_coefficient <= 0.0:
        drag = AirDrag(drag.air_density, 0.47, drag.radius, drag.linear_coefficient)
    if isinstance(sequences, np.ndarray):
        if sequences.ndim != 2:
            raise InputError('sequences', sequences.shape, '{n[sequences]} is an array of shape '
                             '{value}: allowed a list of sequences of times, or a 2-D array with '
                             'one sequence a row', value=str(sequences.shape))
        sequences = list(sequences)
    if isinstance(sequences, (str, bytes, ImpactTimes)) or not hasattr(sequences, '__len__'):
        raise InputError('sequences', sequences, '{n[sequences]} = {value} is not a list of '
                         'sequences: allowed a list of ImpactTimes or of arrays of times (s)')
    if len(sequences) == 0:
        raise InputError('sequences', 0, '{n[sequences]} is empty: allowed one or more recorded '
                         'sequences')
    seqs = [s if isinstance(s, ImpactTimes)
            else ImpactTimes(s, None, f'sequence {i + 1}')
            for i, s in enumerate(sequences)]
    require_sizes(seqs)
    for s in seqs:
        check_recording(s, gravity, resolution)
    chosen = [require_law(law, 'laws') for law in (laws if laws is not None else LAWS.values())]
    if isinstance(stiffness, dict):
        ks = {require_law(law, 'stiffness'): k for law, k in stiffness.items()}
        if laws is None:      # every law with a k, and the constant law (k derivable)
            chosen = [law for law in chosen if law in ks or law.constant_restitution]
    else:
        ks = {law: require_positive('stiffness', stiffness) for law in chosen if law.hertz}
    # the softest contact given decides where the micro-bounces begin
    cut_law, cut_k = min(ks.items(), key=lambda lk: lk[1] ** (1.0 / (lk[0].n + 1.0)),
                         default=(None, None))
    cut = MicroBounceCut(cut_law, cut_k, mass, micro_bounce_ratio, min_flight)
    prepared, glitches = [], []
    kappa0 = drag.rates(mass, gravity)[0] if drag is not None else 0.0
    for j, s in enumerate(seqs):
        p, g = prepare_sequence(j, s, gravity, kappa0, cut)
        prepared.append(p)
        glitches.extend(g)
    speeds = np.concatenate([gravity * np.diff(p.times) / np.diff(p.index) / 2.0
                             for p in prepared])
    v_med = float(np.median(speeds))
    laws_k = []
    for law in chosen:
        k = ks.get(law)
        if k is None and law.constant_restitution:
            hertz = next((other for other in ks if other.hertz), None)
            if hertz is None:
                raise InputError('stiffness', None, '{n[stiffness]} is missing for law %s: '
                                 'give its k (N/m), or fit a Hertz law beside it to derive it '
                                 'from' % law.name)
            k = _linear_stiffness(hertz, ks[hertz], mass, v_med)
        if k is None:
            raise InputError('stiffness', None, '{n[stiffness]} is missing for law %s: allowed '
                             'a k for every law fitted' % law.name)
        laws_k.append((law, k))
    trained, held = {}, None
    try:
        if holdout is not None:  # the laws fitted on the earlier clicks, to predict the rest
            training, held = split_sequences(prepared, holdout)
            trained = {law: fit_law(law, k, mass, gravity, drag, fit_drag, training,
                                    resolution, height_error, loss, confidence)
                       for law, k in laws_k}
        fits = [fit_law(law, k, mass, gravity, drag, fit_drag, prepared, resolution,
                        height_error, loss, confidence) for law, k in laws_k]
    except ValueError as error:   # too few observations: say what the glitches left out
        read = sum(s.times.size for s in seqs)
        kept = sum(p.times.size for p in prepared)
        if kept == read or isinstance(error, InputError):
            raise
        raise ValueError(f'{error}; {read} click(s) read, {read - kept} left out: '
                         + '; '.join(g.describe() for g in glitches if g.left_out)) from None
    fits.sort(key=lambda f: f.rms)
    # outliers the robust loss down-weighted (after the named glitches)
    best = fits[0]
    for j, (seq, r, w) in enumerate(zip(prepared, best.residuals, best.weights)):
        for t, ri, wi in zip(seq.times, r, w):
            if wi < 0.5:
                glitches.append(Glitch(j, 'outlier', float(t), False,
                                       f'residual {ri * 1e3:+.3f} ms, weight {wi:.2f} in the '
                                       f'robust fit of {best.law.name}'))
    constant = [f for f in fits if f.law.constant_restitution]
    varying = [f for f in fits if not f.law.constant_restitution]
    delta = math.nan
    if constant and varying:
        delta = constant[0].aic - min(f.aic for f in varying)
    fit = BounceFit(fits, prepared, glitches, mass, gravity, drag, fit_drag, confidence,
                    resolution, bool(delta > SUPPORT_DELTA_AIC), delta)
    if held is not None:
        fit = replace(fit, holdout=[predict_held(fit, trained[f.law], held) for f in fit.fits])
    return replace(fit, adequacy=check_adequacy(fit))

