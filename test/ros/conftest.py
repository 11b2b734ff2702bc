"""The fixtures of the ROS tests, shared by every file of ``test/ros/`` (a package, so that
package scope ends with its last test): one environment and one client for the package, and one
``contact_sim_node`` process on its built-in defaults that serves every test asking for ``sim``.

Isolation (``domains``): every ROS process of a test run is in a domain claimed for its pytest
process alone, never the caller's ROS_DOMAIN_ID nor one in use on this machine, with
localhost-only discovery and no static peers, and a temporary ROS_LOG_DIR: nothing a user runs
on any domain sees the tests' traffic, and xdist workers and concurrent runs each have their own
domain (each runs a shared node of its own: two ``/contact_sim`` nodes in one domain would mix
their topics and yield /clock to each other). Tests that need a domain of their own claim one
more. Every wait is on a condition with a deadline, never a fixed sleep. Tests that change the
node put it back.
"""
import os
import tempfile
from pathlib import Path

import pytest

from .domains import claim_domain, isolated_env


@pytest.fixture(scope='package')
def workdir():
    with tempfile.TemporaryDirectory(prefix='contact_sim_test_') as path:
        yield Path(path)


@pytest.fixture(scope='package')
def ros_env(workdir):
    """Environment for every ROS process of this package, the test process included."""
    saved = dict(os.environ)
    env = isolated_env(claim_domain(), saved)
    env.update({
        'ROS_LOG_DIR': str(workdir / 'ros_log'),
        'RCUTILS_LOGGING_BUFFERED_STREAM': '0',
        'RCUTILS_COLORIZED_OUTPUT': '0',
        'PYTHONUNBUFFERED': '1',
    })
    os.environ.clear()
    os.environ.update(env)
    yield dict(os.environ)
    os.environ.clear()
    os.environ.update(saved)


@pytest.fixture(scope='package')
def client(ros_env):
    import rclpy

    from .harness import Client
    rclpy.init()
    client = Client()
    yield client
    client.node.destroy_node()
    rclpy.try_shutdown()


@pytest.fixture(scope='package')
def sim(ros_env, client, workdir):
    """contact_sim_node on its built-in defaults (steel ball, cast-iron plate, 1 m, real time),
    but for its publish rate, ``harness.SIM_RATE``: at the default 100 Hz (800 messages a second
    at rest) this Python client fell minutes behind the node on two cores shared with four
    burners (about 200 messages a second taken; issue 16). Nodes started by the tests
    themselves run at the default rate."""
    from .harness import NODE, SIM_RATE, Process, assert_clean_exit
    process = Process('contact_sim_node', ['--ros-args', '-p', f'publish_rate:={SIM_RATE}'],
                      ros_env, workdir)
    client.spin_until(lambda: client.count(f'{NODE}/pose') >= 5 or process.popen.poll() is not None,
                      'the node to publish')
    assert process.popen.poll() is None, process.output()
    yield process
    assert_clean_exit(process)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """A failed test that used the shared node shows the node's last log lines and the stamp of
    the last message the client received on each topic (what a timeout waited behind)."""
    outcome = yield
    report = outcome.get_result()
    if report.when != 'call' or not report.failed:
        return
    process, client = item.funcargs.get('sim'), item.funcargs.get('client')
    if process is not None:
        lines = process.output().splitlines()[-40:]
        report.sections.append(('contact_sim_node (shared) log, last lines', '\n'.join(lines)))
    if client is not None:
        from .harness import last_stamps
        report.sections.append(('client: messages and last stamp per topic', last_stamps(client)))
