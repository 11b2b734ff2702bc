#!/usr/bin/env python3
"""Speed and accuracy of the restitution fast path against the exact ``simulate_impact``.

Prints: vectorised throughput (speeds per second, 1,000,000 speeds), the mean time of one scalar
call, the time of one ``simulate_impact``, their ratio, and the worst |Δe| at random points.

    python bench/bench_restitution.py [--count 1000000]
"""
import argparse
import time

import numpy as np

import contact_sim as cs


def best_time(func, repeat=5):
    best = float('inf')
    for _ in range(repeat):
        start = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - start)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--count', type=int, default=1_000_000)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    mass = 0.066
    speeds = np.exp(rng.uniform(np.log(0.01), np.log(10.0), args.count))
    print(f'{"law":<18} {"vector (speeds/s)":>18} {"scalar (us)":>12} {"exact (ms)":>11} '
          f'{"exact/scalar":>13} {"max |de| (200 pts)":>19}')
    for law in cs.LAWS.values():
        k = 1e7 if law is cs.LINEAR else 1e10
        contact = cs.Contact(law, k, cs.damping_for_restitution(law, k, mass, 0.7, 1.0))
        cs.restitution(contact, mass, speeds[:10])                      # load the tables
        vector = best_time(lambda: cs.restitution(contact, mass, speeds), repeat=3)
        sample = speeds[:2000].tolist()
        scalar = best_time(lambda: [cs.restitution(contact, mass, v) for v in sample]) / len(sample)
        check = speeds[:200]
        start = time.perf_counter()
        slow = np.array([cs.simulate_impact(contact, mass, v).restitution for v in check])
        exact = (time.perf_counter() - start) / check.size
        err = np.max(np.abs(cs.restitution(contact, mass, check) - slow))
        print(f'{law.name:<18} {args.count / vector:18.3g} {scalar * 1e6:12.2f} '
              f'{exact * 1e3:11.2f} {exact / scalar:13.0f} {err:19.2e}')


if __name__ == '__main__':
    main()
