"""Brent's method one iteration at a time (a port of scipy's ``brentq.c``), for the compiled
root searches: the contact phase's events on its dense output (``compiled._root``) and a flight's
touch on a moving plate (``drop.plate.compiled_flight``). Plain Python over a tuple of floats,
which each caller compiles with numba and drives with its own function:

    state = brent_start(xa, xb, f(xa), f(xb))      # f(xa), f(xb) nonzero, of opposite signs
    for _ in range(maxiter):
        done, x, state = brent_next(state, xtol, rtol)
        if done:
            break
        state = brent_evaluated(state, f(x))
    # x: the root

The state is (xpre, xcur, xblk, fpre, fcur, fblk, spre, scur), brentq.c's names.
"""


def brent_start(xa, xb, fa, fb):
    """The state of a search bracketed by [xa, xb] with f(xa) = fa and f(xb) = fb."""
    return (xa, xb, 0.0, fa, fb, 0.0, 0.0, 0.0)


def brent_next(state, xtol, rtol):
    """One iteration of brentq.c: (done, x, state). Done: x is the root within
    xtol + rtol |x| (as scipy's ``brentq``); otherwise x is the next point, whose value the
    caller gives to ``brent_evaluated``."""
    xpre, xcur, xblk, fpre, fcur, fblk, spre, scur = state
    if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
        xblk = xpre
        fblk = fpre
        spre = scur = xcur - xpre
    if abs(fblk) < abs(fcur):
        xpre, xcur, xblk = xcur, xblk, xcur
        fpre, fcur, fblk = fcur, fblk, fcur
    delta = (xtol + rtol * abs(xcur)) / 2.0
    sbis = (xblk - xcur) / 2.0
    if fcur == 0.0 or abs(sbis) < delta:
        return True, xcur, (xpre, xcur, xblk, fpre, fcur, fblk, spre, scur)
    if abs(spre) > delta and abs(fcur) < abs(fpre):
        if xpre == xblk:
            stry = -fcur * (xcur - xpre) / (fcur - fpre)          # interpolate
        else:
            dpre = (fpre - fcur) / (xpre - xcur)                  # extrapolate
            dblk = (fblk - fcur) / (xblk - xcur)
            stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
        if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
            spre = scur                                           # good short step
            scur = stry
        else:
            spre = sbis
            scur = sbis
    else:
        spre = sbis
        scur = sbis
    xpre = xcur
    fpre = fcur
    if abs(scur) > delta:
        xcur += scur
    else:
        xcur += delta if sbis > 0.0 else -delta
    return False, xcur, (xpre, xcur, xblk, fpre, fcur, fblk, spre, scur)


def brent_evaluated(state, fx):
    """The state after the caller evaluated f at the point ``brent_next`` gave: f = ``fx``."""
    xpre, xcur, xblk, fpre, _, fblk, spre, scur = state
    return (xpre, xcur, xblk, fpre, fx, fblk, spre, scur)
