"""The accuracy table of docs/limits.md: ``python scripts/impact_accuracy.py`` (about 30 s).

Relative error of the contact duration / absolute error of the restitution of
``simulate_impact`` (default tolerances, default engine) against a reference: the closed forms
(linear, Hunt-Crossley) or, for Azad-Featherstone and Lee-Wang, a solve_ivp of this script's own
at rtol 1e-13 in the physical time: in (z, ż) to the deepest point, then in (z, F) to F = 0
(the force as a state, so that its zero is not a difference of two nearly equal terms; for the
linear law this reference is within 2e-12 of the closed form up to ζ = 1e6).
"""
from scipy.integrate import solve_ivp

import contact_sim as cs
from contact_sim.model.closed_forms import (hunt_crossley_duration, hunt_crossley_restitution_scalar,
                                            linear_restitution_and_duration)
ZETAS = [1, 10, 100, 300, 1e3, 1e4, 1e5, 1e6]


def reference(n, p, lam):
    """(e, τc) of z̈ = -(zⁿ + λ zᵖ ż), z(0) = 0, ż(0) = 1 (k = m = v = 1)."""
    def way_in(t, y):
        z = max(y[0], 0.0)
        return [y[1], -(z ** n + lam * z ** p * y[1])]

    def deepest(t, y):
        return y[1]
    deepest.terminal, deepest.direction = True, -1
    first = solve_ivp(way_in, (0.0, 1e3), [0.0, 1.0], method='DOP853', rtol=1e-13, atol=1e-40,
                      events=deepest)
    t0, (z0, v0) = first.t_events[0][0], first.y_events[0][0]

    def way_out(t, y):
        z, f = y
        v = (f - z ** n) / (lam * z ** p)
        return [v, n * z ** (n - 1) * v + lam * p * z ** (p - 1) * v * v - lam * z ** p * f]

    def gone(t, y):
        return y[1]
    gone.terminal, gone.direction = True, -1
    second = solve_ivp(way_out, (t0, 1e3), [z0, z0 ** n + lam * z0 ** p * v0], method='DOP853',
                       rtol=1e-13, atol=1e-300, events=gone)
    z = second.y_events[0][0][0]
    return z ** (n - p) / lam, float(second.t_events[0][0])     # ż = -z^(n-p) / λ at F = 0


def main():
    print('| law | ' + ' | '.join('ζ = %g' % z for z in ZETAS) + ' |')
    print('| --- |' + ' --- |' * len(ZETAS))
    for law in ['azad_featherstone', 'hunt_crossley', 'lee_wang', 'linear']:
        cells = []
        for zeta in ZETAS:
            c = cs.Contact(cs.LAWS[law], 1.0, zeta)
            r = cs.simulate_impact(c, 1.0, 1.0, max_steps=10**8)
            if law == 'linear':
                e, tau = (float(x) for x in linear_restitution_and_duration(zeta))
            elif law == 'hunt_crossley':
                e, tau = hunt_crossley_restitution_scalar(zeta), hunt_crossley_duration(zeta)
            else:
                e, tau = reference(c.law.n, c.law.p, zeta)
            cells.append('%.0e / %.0e' % (abs(r.contact_duration / tau - 1), abs(r.restitution - e)))
        print('| %s | %s |' % (law, ' | '.join(cells)))


if __name__ == '__main__':
    main()
