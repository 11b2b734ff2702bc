"""Where a tick's CPU goes: the node's flat-out tick and its settling turn, split into parts.

    python bench/profile_tick.py

Measured in this process (no subscriber; wall time of tight loops, so run it on a quiet machine):

  tick     the default drop at rest, 100 Hz: µs per tick of the engine's ``advance`` (one call
           per tick), of ``advance_ticks`` (many ticks per call), of the node's per-tick
           bookkeeping (``contact_samples``, ``to_ns``, tuples), and of encoding and publishing
           the tick on every per-tick topic of ``messages.TOPICS`` (the floor)
  settle   the default drop from just before its permanent contact to the closed-form rest: the
           engine's CPU (integrator steps and the Python driving them, in the node's 20-step
           calls and in one call), the contact points it passes, and the CPU to encode and
           publish them (each point is one message on every ``sample`` topic)
"""
import os
import tempfile
import time

import numpy as np


def _per_call(func, repeat):
    t0 = time.perf_counter()
    for _ in range(repeat):
        func()
    return (time.perf_counter() - t0) / repeat


def default_sim():
    from contact_sim.ros import params
    return params.make_simulation(params.build_model(dict(params.DEFAULTS)))


def tick_costs(ticks=20000, dt=0.01):
    from contact_sim.ros import messages as m
    sim = default_sim()
    sim.advance(5.0)                       # at rest
    t = [sim.time]

    def one():
        t[0] += dt
        return sim.advance(t[0])
    engine = _per_call(one, ticks) * 1e6
    advance = one()
    book = _per_call(lambda: (m.contact_samples(advance.samples, 0.0, -1),
                              m.to_ns(float(advance.samples.time[-1])),
                              float(advance.samples.penetration[-1]),
                              float(advance.samples.penetration_rate[-1])), ticks) * 1e6
    batch = None
    if hasattr(sim, 'advance_ticks'):
        chunk = 256
        times = sim.time + dt * np.arange(1, chunk + 1)
        t0 = time.perf_counter()
        for _ in range(ticks // chunk):
            sim.advance_ticks(times)
            times = times + chunk * dt
        batch = (time.perf_counter() - t0) / (ticks // chunk * chunk) * 1e6
    return engine, book, batch


def floor_costs(ticks=20000):
    """µs per tick to encode, and to encode and publish, one tick on every per-tick topic."""
    import rclpy
    from contact_sim.ros import messages as m
    topics = [t for t in m.TOPICS if t.kind in ('sample', 'state', 'clock')]
    values = {t.key: (0.5,) * len(t.fields) for t in topics}
    enc = {t.key: t.template('plate').packer() for t in topics}   # as the node's
    rclpy.init()
    node = rclpy.create_node('profile_floor')
    pubs = {t.key: node.create_publisher(t.msg_type, f'/profile_floor/{t.key}', t.qos)
            for t in topics}
    t0 = time.perf_counter()
    for i in range(ticks):
        ns = 1_000_000_000 + i * 10_000_000
        for key, encode in enc.items():
            encode(ns, *values[key])
    encode_only = (time.perf_counter() - t0) / ticks * 1e6
    t0 = time.perf_counter()
    for i in range(ticks):
        ns = 1_000_000_000 + i * 10_000_000
        for key, encode in enc.items():
            pubs[key].publish(encode(ns, *values[key]))
    both = (time.perf_counter() - t0) / ticks * 1e6
    per_sample_msg = both / len(topics)
    node.destroy_node()
    rclpy.shutdown()
    return encode_only, both, len(topics), per_sample_msg, [t.key for t in topics]


def settle_costs():
    from contact_sim.ros import messages as m
    probe = default_sim()
    probe.advance(10.0)
    t_perm, t_rest = probe.permanent_contact_time, probe.settle_time
    # to the tick before the permanent contact begins, on the 100 Hz grid
    start = np.floor(t_perm * 100.0) / 100.0
    end = np.ceil(t_rest * 100.0) / 100.0 + 0.01

    def run(budget):
        sim = default_sim()
        sim.advance(start)
        steps0 = sim.total_steps
        t0 = time.process_time()
        points = calls = 0
        tick = start
        while tick < end - 1e-12:
            tick = round(tick + 0.01, 10)
            while True:
                adv = sim.advance(tick, max_steps=budget)
                calls += 1
                points += len(adv.samples.time)
                if sim.time >= tick:
                    break
        return time.process_time() - t0, points, calls, sim.total_steps - steps0
    node_way = run(20)
    one_call = run(None)
    keys = [t.key for t in m.TOPICS if t.kind == 'sample']
    return t_perm, t_rest, start, end, node_way, one_call, keys


def main():
    os.environ.setdefault('ROS_DOMAIN_ID', str(1 + os.getpid() % 101))
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    with tempfile.TemporaryDirectory(prefix='profile_tick_') as workdir:
        os.environ['ROS_LOG_DIR'] = workdir
        encode_only, floor, n_topics, per_msg, keys = floor_costs()
        engine, book, batch = tick_costs()
        print(f'tick    floor (encode + publish on {n_topics} per-tick topics: '
              f'{", ".join(keys)}): {floor:.1f} us, of which encoding {encode_only:.1f} us')
        print(f'        engine advance() once per tick at rest: {engine:.1f} us; node bookkeeping '
              f'(contact_samples, to_ns, floats): {book:.1f} us'
              + (f'; advance_ticks() 256 ticks per call: {batch:.2f} us per tick'
                 if batch is not None else ''))
        print(f'        so a tick of the one-call-per-tick node is about {floor + engine + book:.1f}'
              f' us = {(floor + engine + book) / floor:.2f} x the floor before the executor')
        t_perm, t_rest, start, end, node_way, one_call, sample_keys = settle_costs()
        cpu, points, calls, steps = node_way
        print(f'settle  permanent contact at t = {t_perm:.4f} s, closed-form rest from '
              f't = {t_rest:.4f} s; ticks {start:.2f} .. {end:.2f} s at 100 Hz')
        print(f'        engine, 20 steps per call (as the node): {cpu * 1e3:.1f} ms CPU, '
              f'{calls} calls, {steps} integrator steps, {points} samples passed')
        cpu1, points1, calls1, _ = one_call
        print(f'        engine, one call per tick: {cpu1 * 1e3:.1f} ms CPU, {calls1} calls, '
              f'{points1} samples')
        print(f'        publishing them: {points} samples x {len(sample_keys)} sample topics '
              f'({", ".join(sample_keys)}) x {per_msg:.1f} us = '
              f'{points * len(sample_keys) * per_msg * 1e-3:.1f} ms CPU')


if __name__ == '__main__':
    main()
