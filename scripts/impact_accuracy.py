"""The accuracy table of docs/limits.md: ``python scripts/impact_accuracy.py`` (about 25 s).

Relative error of the contact duration / absolute error of the restitution of
``simulate_impact`` (default tolerances, default engine) against a reference: the closed forms
(linear, Hunt-Crossley) or the same phase at rtol 1e-13, atol 1e-24 (Azad-Featherstone,
Lee-Wang; for the linear law that tight run is within 1e-8 of the closed form up to ζ = 1e4).
"""
import contact_sim as cs
from contact_sim.model.closed_forms import (hunt_crossley_duration, hunt_crossley_restitution_scalar,
                                            linear_restitution_and_duration)
from contact_sim.phase import contact_phase
ZETAS = [1, 10, 100, 300, 1e3, 1e4, 1e5, 1e6]


def main():
    print('| law | ' + ' | '.join('ζ = %g' % z for z in ZETAS) + ' |')
    print('| --- |' + ' --- |' * len(ZETAS))
    for law in ['azad_featherstone', 'hunt_crossley', 'lee_wang', 'linear']:
        cells = []
        for zeta in ZETAS:
            c = cs.Contact(law, 1.0, zeta)
            r = cs.simulate_impact(c, 1.0, 1.0, max_steps=10**8)
            if law == 'linear':
                e, tau = (float(x) for x in linear_restitution_and_duration(zeta))
            elif law == 'hunt_crossley':
                e, tau = hunt_crossley_restitution_scalar(zeta), hunt_crossley_duration(zeta)
            else:
                ph = contact_phase(c, 1.0, 0.0, 0.0, 0.0, 1.0, rtol=1e-13, atol=1e-24, keep_points=False)
                ph.run()
                tau, e = ph.end[0], -ph.end[2]
            cells.append('%.0e / %.0e' % (abs(r.contact_duration / tau - 1), abs(r.restitution - e)))
        print('| %s | %s |' % (law, ' | '.join(cells)))


if __name__ == '__main__':
    main()
