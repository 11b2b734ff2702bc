"""The fixtures of the ROS tests, shared by every file of ``test/ros/`` (a package, so that
package scope ends with its last test): one environment and one client for the package, and one
``contact_sim_node`` process on its built-in defaults that serves every test asking for ``sim``.

Isolation: the caller's ROS_DOMAIN_ID when it is set (a CI runner or a developer who keeps
parallel runs apart), else one derived from this process's pid; localhost-only discovery and a
temporary ROS_LOG_DIR. Under pytest-xdist every worker runs a shared node of its own, so only the
first worker (gw0) takes the caller's domain and each other one a domain derived from it (two
``/contact_sim`` nodes in one domain would mix their topics and yield /clock to each other).
Tests that need a domain of their own derive it from the package's. Every wait is on a
condition with a deadline, never a fixed sleep. Tests that change the node put it back.
"""
import os
import tempfile
from pathlib import Path

import pytest


def caller_domain():
    """The caller's ROS_DOMAIN_ID (a whole number, as ROS reads it), or None when unset."""
    value = os.environ.get('ROS_DOMAIN_ID', '').strip()
    return value if value.isdigit() else None


def worker_index(config):
    """The pytest-xdist worker's number (``gw1`` -> 1); 0 outside xdist."""
    workerinput = getattr(config, 'workerinput', None)
    return int(workerinput['workerid'].removeprefix('gw')) if workerinput else 0


def package_domain(config):
    """The ROS domain of this process's tests (see the module's docstring), as a string."""
    caller = caller_domain()
    if caller is None:
        return str(1 + os.getpid() % 101)
    index = worker_index(config)
    return caller if index == 0 else str((int(caller) + 17 * index - 1) % 101 + 1)


@pytest.fixture(scope='package')
def workdir():
    with tempfile.TemporaryDirectory(prefix='contact_sim_test_') as path:
        yield Path(path)


@pytest.fixture(scope='package')
def ros_env(workdir, pytestconfig):
    """Environment for every ROS process of this package, the test process included."""
    saved = dict(os.environ)
    os.environ.update({
        'ROS_DOMAIN_ID': package_domain(pytestconfig),
        'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST',
        'ROS_LOG_DIR': str(workdir / 'ros_log'),
        'RCUTILS_LOGGING_BUFFERED_STREAM': '0',
        'RCUTILS_COLORIZED_OUTPUT': '0',
        'PYTHONUNBUFFERED': '1',
    })
    os.environ.pop('ROS_LOCALHOST_ONLY', None)
    yield dict(os.environ)
    os.environ.clear()
    os.environ.update(saved)


@pytest.fixture(scope='package')
def client(ros_env):
    rclpy = pytest.importorskip('rclpy')
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
