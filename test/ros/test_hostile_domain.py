"""A test run cannot reach outside itself (issue 33, item 2; issue 17 kept the caller's
ROS_DOMAIN_ID, and the tests then drove a user's node there): every ROS process of the tests is
in a domain claimed for its pytest process (``domains``), never the caller's nor one in use on
this machine, with localhost-only discovery.
"""
import fcntl
import json
import os
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest
import rclpy
from std_msgs.msg import String

from . import domains
from .harness import TIMEOUT, spin_until

ROOT = Path(__file__).resolve().parents[2]
PROBE_RUN = 'CONTACT_SIM_ISOLATION_PROBE'   # set in the test run started by the last test


def test_the_package_domain_is_claimed_never_the_callers(ros_env):
    domain = int(ros_env['ROS_DOMAIN_ID'])
    assert domain != domains.callers_domain()
    assert domain in domains.POOL
    assert ros_env['ROS_AUTOMATIC_DISCOVERY_RANGE'] == 'LOCALHOST'
    assert ros_env['ROS_STATIC_PEERS'] == ''
    assert not set(domains.DROPPED) & set(ros_env)
    # the claim holds for the life of this process: no other process can take the lock
    with open(domains.LOCK_DIR / f'{domain}.lock', 'a') as other:
        with pytest.raises(OSError):
            fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)


def test_the_callers_domain_is_read_before_any_fixture_changed_it(ros_env):
    # reproduced: the domain was derived from os.environ after the fixture had set it
    assert os.environ['ROS_DOMAIN_ID'] == ros_env['ROS_DOMAIN_ID']
    assert domains.callers_domain() == domains.callers_domain(domains.CALLER_ENV)
    assert domains.callers_domain({'ROS_DOMAIN_ID': ' 17 '}) == 17
    assert domains.callers_domain({}) == 0      # ROS's default domain


def test_concurrent_processes_claim_different_domains(tmp_path):
    """Another process (an xdist worker, another run) holding its claim gets another id, and
    not the domain its caller set."""
    script = ('import sys; sys.path.insert(0, sys.argv[1]); import domains; '
              'print(domains.claim_domain(), flush=True); sys.stdin.read()')
    mine = domains.claim_domain()
    env = dict(os.environ, ROS_DOMAIN_ID=str(domains.POOL[0]))
    other = subprocess.Popen([sys.executable, '-c', script, str(Path(__file__).parent)],
                             env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        theirs = int(other.stdout.readline())
        assert theirs not in (mine, domains.POOL[0]) and theirs not in domains._held
        with open(domains.LOCK_DIR / f'{theirs}.lock', 'a') as lock, pytest.raises(OSError):
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    finally:
        other.communicate('', timeout=TIMEOUT)
    # its claim ended with it
    with open(domains.LOCK_DIR / f'{theirs}.lock', 'a') as lock:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        fcntl.flock(lock, fcntl.LOCK_UN)


def test_a_domain_in_use_on_this_machine_is_not_claimed(monkeypatch):
    """A participant of another program (a user's node) binds ports of its domain's range."""
    free = [d for d in domains.POOL if d not in domains._held and d != domains.callers_domain()
            and not domains.in_use(d)]
    used, spare = free[0], free[1]
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.bind(('127.0.0.1', domains.PORT_BASE + domains.DOMAIN_GAIN * used + 10 + 2 * 119))
        assert domains.in_use(used)
        monkeypatch.setattr(domains, 'POOL', (used, spare))
        assert domains.claim_domain() == spare


@pytest.mark.slow
@pytest.mark.skipif(os.environ.get(PROBE_RUN) == '1', reason='inside the run this test starts')
def test_a_users_node_in_the_callers_domain_receives_nothing_from_a_test_run(ros_env, workdir):
    """The issue's case: a user's node named contact_sim, with its parameters and ~/reset, runs in
    the caller's domain (the caller's own environment otherwise) while the README's test command
    runs tests that set parameters, reset and read topics; the user's node receives nothing, and
    sees no node of the tests. (It does hear its domain: a probe published there reaches it.)"""
    users_domain = domains.claim_domain()
    users_env = dict(domains.CALLER_ENV, ROS_DOMAIN_ID=str(users_domain),
                     ROS_LOG_DIR=str(workdir / 'user_log'), PYTHONUNBUFFERED='1')
    user = subprocess.Popen([sys.executable, str(Path(__file__).with_name('user_node.py'))],
                            env=users_env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True, start_new_session=True)
    lines = []
    try:
        lines.append(user.stdout.readline())
        assert lines[-1].strip() == 'ready', lines
        context = rclpy.Context()
        context.init(domain_id=users_domain)
        try:
            node = rclpy.create_node('isolation_probe', context=context)
            executor = rclpy.executors.SingleThreadedExecutor(context=context)
            executor.add_node(node)
            publisher = node.create_publisher(String, '/isolation_probe', 10)
            spin_until(executor, lambda: publisher.get_subscription_count() > 0,
                       "the user's node to hear its domain")
            publisher.publish(String(data='probe'))
            lines.append(user.stdout.readline())
            assert lines[-1].strip() == 'probe', lines
        finally:
            context.try_shutdown()
        run = subprocess.run(
            [sys.executable, '-m', 'pytest', '-q', '-p', 'no:cacheprovider', '-n', '2',
             '--dist', 'loadfile',
             'test/ros/test_node_parameters.py::test_accepted_changes_take_effect',
             'test/ros/test_node_topics.py::test_reset_restarts_the_drop_and_time_keeps_running'],
            cwd=ROOT, env=dict(users_env, **{PROBE_RUN: '1'}), capture_output=True, text=True,
            timeout=20 * TIMEOUT)
    finally:
        os.killpg(user.pid, signal.SIGINT)
        out, _ = user.communicate(timeout=TIMEOUT)
    received = json.loads(out.strip().splitlines()[-1])
    assert received['probes'] >= 1
    assert received == {'topics': {}, 'parameter_requests': [], 'reset_calls': 0, 'nodes': [],
                        'probes': received['probes']}, received
    assert run.returncode == 0 and '2 passed' in run.stdout, run.stdout[-3000:]
