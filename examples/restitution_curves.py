#!/usr/bin/env python3
"""Figs. 3 and 4 of Azad & Featherstone (2014): restitution against impact speed, zero gravity.

Fig. 3: the linear, Hunt-Crossley and new laws, each tuned (``damping_for_restitution``) to
e = 0.7 at 1 m/s for a 66 g sphere with k = 1e10 N/m^1.5 (k = 1e7 N/m for the linear law).
Fig. 4: a fixed k and several λ; the new law's e is nearly linear in log(speed), the
Hunt-Crossley law's is not.  Measured here by the worst deviation of e from its least-squares
straight line in ln v over 0.1-10 m/s.

    python examples/restitution_curves.py [--plot fig3.png fig4.png]
"""
import argparse

import numpy as np

import contact_sim as cs

MASS, STIFFNESS, LINEAR_STIFFNESS = 0.066, 1e10, 1e7
SPEEDS = np.geomspace(0.1, 10.0, 41)


def tuned_contact(law, restitution=0.7, speed=1.0):
    k = LINEAR_STIFFNESS if law is cs.LINEAR else STIFFNESS
    return cs.Contact(law, k, cs.damping_for_restitution(law, k, MASS, restitution, speed))


def fig3(speeds=SPEEDS):
    """{law name: e(speeds)} for the three laws of Fig. 3."""
    return {law.name: cs.restitution(tuned_contact(law), MASS, speeds)
            for law in (cs.LINEAR, cs.HUNT_CROSSLEY, cs.AZAD_FEATHERSTONE)}


def log_linearity(e, speeds=SPEEDS):
    """Worst |e - (a + b ln v)| of the least-squares line, and its slope b."""
    x = np.log(speeds)
    b, a = np.polyfit(x, e, 1)
    return float(np.max(np.abs(e - (a + b * x)))), float(b)


def fig4(restitutions_at_1ms=(0.9, 0.8, 0.7, 0.6, 0.5), speeds=SPEEDS):
    """{law name: [(λ, e(speeds)), ...]} at fixed k, for λ giving the listed e at 1 m/s."""
    out = {}
    for law in (cs.HUNT_CROSSLEY, cs.AZAD_FEATHERSTONE):
        rows = []
        for e1 in restitutions_at_1ms:
            contact = tuned_contact(law, e1)
            rows.append((contact.damping, cs.restitution(contact, MASS, speeds)))
        out[law.name] = rows
    return out


def _plot(curves3, curves4, paths):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name, e in curves3.items():
        ax.plot(SPEEDS, e, label=name.replace('_', ' '))
    ax.set(xlabel='impact speed (m/s)', ylabel='coefficient of restitution',
           title='Fig. 3: e(v), each law tuned to e = 0.7 at 1 m/s')
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(paths[0], dpi=120)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name, style in (('azad_featherstone', '-'), ('hunt_crossley', '--')):
        for i, (lam, e) in enumerate(curves4[name]):
            ax.semilogx(SPEEDS, e, style, color=f'C{i}',
                        label=f'{name.replace("_", " ")}, λ = {lam:.3g}')
    ax.set(xlabel='impact speed (m/s, log scale)', ylabel='coefficient of restitution',
           title='Fig. 4: e against log(speed), k = 1e10 N/m^1.5')
    ax.grid(True, which='both', alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(paths[1], dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--plot', nargs=2, metavar=('FIG3', 'FIG4'), help='write two PNGs')
    args = parser.parse_args()
    curves3 = fig3()
    print('Fig. 3: restitution at 0.1, 1, 10 m/s (each law tuned to e = 0.7 at 1 m/s)')
    for name, e in curves3.items():
        print(f'  {name:<18} {e[0]:.4f} {e[20]:.4f} {e[-1]:.4f}')
    curves4 = fig4()
    print('Fig. 4: worst deviation of e from a straight line in ln(v), 0.1-10 m/s')
    for name, rows in curves4.items():
        for lam, e in rows:
            dev, slope = log_linearity(e)
            print(f'  {name:<18} lambda = {lam:10.4g}  e(1 m/s) = {e[20]:.2f}  '
                  f'slope = {slope:+.4f} per ln(m/s)  worst deviation = {dev:.4f}')
    if args.plot:
        _plot(curves3, curves4, args.plot)
        print('wrote', *args.plot)


if __name__ == '__main__':
    main()
