"""The restitution read back from the recorded flights with a fitted law: corrected for the
drag in flight and for the contact's duration (``corrected_restitution_table``), and the fitted
law's own e(v) (``restitution_curve``).  Units: SI."""
import math

import numpy as np

from contact_sim.calibration.bounces import contact_map, impact_sequence
from contact_sim.flight import flight_to_plate
from contact_sim.impact import restitution


def _rebound_for_flight(flight, gravity, kappa, beta):
    """Rebound speed (m/s) whose flight from the plate back to it lasts ``flight`` s: Newton on
    the closed form (monotone, concave), from the vacuum value 1/2 g T, which lies below."""
    u = 0.5 * gravity * flight
    for _ in range(50):
        t, _ = flight_to_plate(u, gravity, kappa, beta)
        dt = (float(flight_to_plate(u * (1.0 + 1e-7), gravity, kappa, beta)[0]) - float(t)) \
            / (1e-7 * u)
        step = (float(t) - flight) / dt
        u -= step
        if abs(step) <= 1e-13 * u:
            break
    return u, dt


def corrected_restitution_table(fit, law_fit=None):
    """The drag- and duration-corrected restitution read from the measured flights.

    A list of (sequence, impact speed v m/s, e, σ_e), one per pair of consecutive single flights.

    A flight (click to click) minus the fitted law's contact time at its impact speed is
    turned into the rebound speed that gives it under the fitted drag (closed form, inverted by
    Newton's method); its arrival speed is the next impact speed.  e = u / v, with v from the
    flight before (or from the fit for the first recorded impact); σ_e propagates the timing
    noise √2 σ_t of each interval.

    Parameters
    ----------
    fit : BounceFit
        A ``fit_bounces`` result.
    law_fit : LawFit, optional
        The law whose contact times and drag are used (default: ``fit.best``).

    Returns
    -------
    list of tuple
        (sequence index, impact speed v in m/s, e, σ_e) per pair of consecutive single flights.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> recorded = cs.predict_bounces(contact, mass, height=0.1, count=6).times
    >>> fit = cs.fit_bounces(contact.stiffness, mass, [recorded],
    ...                      laws=[cs.AZAD_FEATHERSTONE, cs.HUNT_CROSSLEY])
    >>> from contact_sim.calibration import corrected_restitution_table
    >>> for _, speed, e, sigma in corrected_restitution_table(fit)[:2]:
    ...     print(f"v = {speed:.4f} m/s, e = {e:.4f}")
    v = 1.4007 m/s, e = 0.7235
    v = 1.0134 m/s, e = 0.7374
    """
    return [(j, v, e, se) for j, _, v, e, se in restitution_rows(fit, law_fit)]


def restitution_rows(fit, law_fit=None):
    """``corrected_restitution_table``'s rows with the bounce number of each flight's end.

    Parameters
    ----------
    fit : BounceFit
        A ``fit_bounces`` result.
    law_fit : LawFit, optional
        The law whose contact times, drag and first speeds are used (default: ``fit.best``);
        a fit of the same sequences (e.g. a hold-out's training fit).

    Returns
    -------
    list of tuple
        (sequence index, bounce number of the click that ends the flight, impact speed v m/s,
        e, σ_e) per pair of consecutive single flights.
    """
    lf = law_fit or fit.best
    law, k, lam, m, g = lf.law, lf.stiffness, lf.damping, fit.mass, fit.gravity
    kappa, beta = fit.rates(lf)
    sigma = math.sqrt(2.0) * lf.noise
    rows = []
    for j, (seq, v1) in enumerate(zip(fit.sequences, lf.first_speeds)):
        predicted = impact_sequence(law, k, lam, m, g, v1, int(seq.index[-1]) + 1,
                                    kappa, beta)[1][0]
        v_known, sv = None, 0.0
        for i in range(seq.times.size - 1):
            if seq.index[i + 1] - seq.index[i] != 1:
                v_known = None
                continue
            v = v_known if v_known is not None else float(predicted[seq.index[i]])
            if not (math.isfinite(v) and v > 0.0):
                break
            _, tau, _ = contact_map(law, k, lam, m, g, v, kappa, beta)
            u, dt_du = _rebound_for_flight(float(seq.times[i + 1] - seq.times[i]) - tau, g,
                                           kappa, beta)
            su = sigma / dt_du
            e = u / v
            rows.append((j, int(seq.index[i + 1]), v, e, e * math.hypot(su / u, sv / v)))
            v_known = float(flight_to_plate(u, g, kappa, beta)[1])
            sv = su * v_known / u
    return rows


def restitution_curve(law_fit, mass, speeds):
    """e(v) of a fitted law (no gravity) at ``speeds`` (m/s)."""
    return restitution(law_fit.contact(), mass, np.asarray(speeds, dtype=float))
