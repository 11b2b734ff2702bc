"""Tabulate the bounce model's contact corrections (contact_sim/bounces.py) for the shipped laws.

For each law: on a grid uniform in ln ζ, the lift-off depth x_l = z_lift / Z and the first-order
gravity coefficients a = -∂e/∂G, b = ∂τ/∂G of the unit impact, by exact integration.
Writes contact_sim/data/bounce_tables.npz.  Run: python scripts/build_bounce_tables.py
"""
import pathlib
import time

import numpy as np

from contact_sim.calibration.contact_tables import build_contact_table
from contact_sim.model import LAWS
from contact_sim.model.laws import BOUNCE_TABLE_FILE


def main():
    out = {'laws': np.array(list(LAWS))}
    start = time.perf_counter()
    for name, law in LAWS.items():
        grid, x_l, a, b = build_contact_table(law)
        out[f'{name}/key'] = np.array([law.n, law.p, law.q])
        out[f'{name}/log_zeta'], out[f'{name}/x_lift'] = grid, x_l
        out[f'{name}/a'], out[f'{name}/b'] = a, b
    path = pathlib.Path(__file__).resolve().parent.parent / 'contact_sim' / 'data' / BOUNCE_TABLE_FILE
    np.savez_compressed(path, **out)
    print(f'wrote {path} in {time.perf_counter() - start:.1f} s')


if __name__ == '__main__':
    main()
