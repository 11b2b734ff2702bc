"""The flat-out rate of contact_sim_node recorded by contact_sim_record, beside the unrecorded one.

    python bench/bench_recording.py              # 15 s windows (about 3 minutes)
    python bench/bench_recording.py --window 5

Scenarios (the node and the recorder are the installed console entry points, each in its own
process and session, in a ROS domain of their own; real_time_factor .inf, 100 Hz ticks):
  rest      the default drop, measured once it has come to rest (simulated t > 4 s)
  bouncing  a vibrating table (plate_amplitude 2 mm, plate_frequency 20 Hz: a (2 pi f)^2 = 3.2 g),
            the sphere bouncing on it all along (impacts counted in the bag)
each alone (a best-effort /clock reader only) and recorded (the recorder started first). Printed:
simulated s per wall s (from /clock), the CPU of the node and of the recorder (% of a core,
/proc), whether the bag holds every tick from t = 0.01 s to the last /clock seen (no gap on
~/pose, ~/twist, /clock), and the machine's load average (the machine is shared: the rates are
what it gave, not what the code can do on idle cores). Simulated s per CPU s of each process
says what the work costs: with a core each, the recorded rate could be at most the smaller.
The messages a simulated s in the bag times the rate is what went through the middleware a wall
s; ``bench/bench_dds_floor.py`` measures how many it carries on one topic with nothing else to
do (not a ceiling for the node, which publishes on 9).
"""
import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_node import cpu_seconds, executable  # noqa: E402

SCENARIOS = {'rest': [], 'bouncing': ['plate_amplitude:=0.002', 'plate_frequency:=20.0']}


EXECUTABLES = {}   # name -> path, instead of the installed one (--recorder-exe, --node-exe)


class Proc:
    def __init__(self, name, args, env, workdir):
        self.log = Path(workdir) / f'{name}-{time.monotonic_ns()}.log'
        with open(self.log, 'w') as out:
            program = EXECUTABLES.get(name) or executable(name)
            self.popen = subprocess.Popen([program, *args], env=env, stdout=out,
                                          stderr=subprocess.STDOUT, start_new_session=True)

    def output(self):
        return self.log.read_text(errors='replace')

    def cpu(self):
        return cpu_seconds(self.popen.pid)

    def stop(self, timeout=30.0):
        os.killpg(self.popen.pid, signal.SIGINT)
        self.popen.wait(timeout)


def until(condition, spin, timeout, what):
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise RuntimeError(f'timed out waiting for {what}')
        spin()


def run(params, recorded, window, workdir, domain, node_env=None, recorder_env=None):
    env = {**os.environ, 'ROS_DOMAIN_ID': str(domain), 'ROS_LOG_DIR': str(workdir)}
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=domain)
    node = rclpy.create_node('bench_recording_watch', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    clock = [0]
    node.create_subscription(Clock, '/clock', lambda m: clock.__setitem__(
        0, m.clock.sec + m.clock.nanosec * 1e-9), QoSProfile(
            depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))

    def spin():
        executor.spin_once(timeout_sec=0.05)
    recorder, bag = None, Path(workdir) / f'bag-{time.monotonic_ns()}'
    if recorded:
        recorder = Proc('contact_sim_record', ['-o', str(bag)], {**env, **(recorder_env or {})},
                        workdir)
        until(lambda: 'recording' in recorder.output(), spin, 60, 'the recorder')
    args = ['--ros-args'] + sum((['-p', p] for p in ['real_time_factor:=.inf', *params]), [])
    process = Proc('contact_sim_node', args, {**env, **(node_env or {})}, workdir)
    try:
        until(lambda: clock[0] > 4.0, spin, 120, 'simulated t > 4 s')
        w0, s0, c0 = time.monotonic(), clock[0], process.cpu()
        r0 = recorder.cpu() if recorder else 0.0
        until(lambda: time.monotonic() - w0 > window, spin, window + 5, 'the window')
        w1, s1, c1 = time.monotonic(), clock[0], process.cpu()
        r1 = recorder.cpu() if recorder else 0.0
        wall = w1 - w0
        out = {'rate': (s1 - s0) / wall, 'node': 100 * (c1 - c0) / wall,
               'recorder': 100 * (r1 - r0) / wall}
        process.stop()   # the node first: its last ticks must reach the bag
        last = clock[0]
        out['node_log'] = process.output()
        out['errors'] = errors(out['node_log'])
        out['start'] = [line for line in out['node_log'].splitlines()
                        if 'paced by a recorder' in line or 'no recorder found' in line]
        if recorder is not None:
            recorder.stop()
            out['errors'] += errors(recorder.output())
            out['bag'], out['messages'] = check_bag(bag, last)
    finally:
        for p in (process, recorder):
            if p is not None and p.popen.poll() is None:
                p.stop()
        node.destroy_node()
        context.try_shutdown()
    return out


def errors(log):
    """The lines of a process's log that say something went wrong (errors, a refused publish)."""
    return [line for line in log.splitlines()
            if any(word in line for word in ('[ERROR]', '[FATAL]', 'cannot publish', 'Traceback'))]


def check_bag(bag, last_seen):
    """Whether ~/pose, ~/twist and /clock hold every tick from 0.01 s to the last /clock seen,
    and the number of impacts."""
    from rosbags.highlevel import AnyReader
    stamps = {}
    with AnyReader([bag]) as reader:
        for connection, timestamp, _ in reader.messages():
            stamps.setdefault(connection.topic, []).append(timestamp)
    report = []
    for topic in ('/contact_sim/pose', '/contact_sim/twist', '/clock'):
        ns = np.array(stamps.get(topic, [0]))
        ticks = np.rint(ns / 1e7).astype(int)
        gaps = int(np.count_nonzero(np.diff(ticks) != 1))
        whole = ticks[0] == 1 and not gaps and ns[-1] >= last_seen * 1e9 - 1e3
        report.append(f'{topic.rsplit("/", 1)[1]} {len(ns)} ticks to {ns[-1] * 1e-9:.2f} s '
                      + ('complete' if whole else f'INCOMPLETE (from tick {ticks[0]}, '
                                                  f'{gaps} gaps)'))
    samples = [np.array(stamps.get(f'/contact_sim/{t}', [])) for t in ('wrench', 'contact',
                                                                       'plate_wrench')]
    same = all(len(ns) == len(samples[0]) and np.array_equal(ns, samples[0]) for ns in samples)
    rising = all(np.all(np.diff(ns) > 0) for ns in samples)
    report.append(f'wrench/contact/plate_wrench {len(samples[0])} samples, '
                  + ('the same stamps, increasing' if same and rising else 'DIFFER'))
    impacts = len(stamps.get('/contact_sim/impact', []))
    messages = sum(len(ns) for ns in stamps.values()) / max(last_seen, 1e-9)
    return ('; '.join(report) + f'; {impacts} impacts (last /clock seen {last_seen:.2f} s); '
            f'{messages:.0f} messages a simulated s'), messages


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--window', type=float, default=15.0, help='wall s measured (15)')
    parser.add_argument('--scenario', choices=tuple(SCENARIOS), action='append', default=None,
                        help='run only this scenario (repeatable; default: all)')
    parser.add_argument('--recorded-only', action='store_true',
                        help='only the recorded runs (not the node alone)')
    parser.add_argument('--node-env', action='append', default=[], metavar='NAME=VALUE',
                        help="set in the node's environment only (repeatable)")
    parser.add_argument('--recorder-env', action='append', default=[], metavar='NAME=VALUE',
                        help="set in the recorder's environment only (repeatable)")
    parser.add_argument('--recorder-exe', default=None, metavar='PATH',
                        help='the contact_sim_record to run (default: the installed one), e.g. '
                        "another checkout's, to compare")
    parser.add_argument('--node-exe', default=None, metavar='PATH',
                        help='the contact_sim_node to run (default: the installed one)')
    options = parser.parse_args()
    for name, path in (('contact_sim_record', options.recorder_exe),
                       ('contact_sim_node', options.node_exe)):
        if path:
            EXECUTABLES[name] = path
            print(f'{name}: {path}')
    node_env = dict(item.split('=', 1) for item in options.node_env)
    recorder_env = dict(item.split('=', 1) for item in options.recorder_env)
    for what, extra in (('node', node_env), ('recorder', recorder_env)):
        if extra:
            print(f'{what} environment: ' + ' '.join(f'{k}={v}' for k, v in extra.items()))
    domain = 150 + os.getpid() % 80
    print(f'load average at the start: {os.getloadavg()[0]:.1f} (2 cores: '
          f'{os.cpu_count()} CPUs)')
    with tempfile.TemporaryDirectory(prefix='bench_recording_') as workdir:
        for name, params in SCENARIOS.items():
            if options.scenario and name not in options.scenario:
                continue
            for recorded in (True,) if options.recorded_only else (False, True):
                out = run(params, recorded, options.window, workdir, domain, node_env,
                          recorder_env)
                what = 'recorded' if recorded else 'alone   '
                per_cpu = [100 * out['rate'] / out[k] for k in ('node', 'recorder') if out[k]]
                print(f'{name:8s} {what} {out["rate"]:6.1f} x real time; node '
                      f'{out["node"]:3.0f} %, recorder {out["recorder"]:3.0f} % of a core; '
                      f'load {os.getloadavg()[0]:.1f}; simulated s per CPU s: '
                      + ', '.join(f'{v:.0f}' for v in per_cpu)
                      + (f' (a core each: at most {min(per_cpu):.0f} x real time)'
                         if len(per_cpu) == 2 else ''))
                for line in out['errors'][:5]:
                    print(f'         log: {line}')
                if recorded and 'INCOMPLETE' in out['bag']:
                    for line in out['start']:   # how the node began: paced, or not
                        print(f'         node: {line}')
                if recorded:
                    print(f'         bag: {out["bag"]}: {out["rate"] * out["messages"]:.0f} '
                          'messages recorded a wall s (the middleware alone on one topic: '
                          'bench/bench_dds_floor.py)')


if __name__ == '__main__':
    import _table   # --markdown OUT: the table for the docs (bench/_table.py; its run, not ours)
    _table.run(main)
