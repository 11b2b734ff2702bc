"""The ROS tests keep a caller's ROS_DOMAIN_ID (issue 17, item 8): CI runners and developers
keep parallel runs apart by it."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import package_domain, worker_index

CALLER = os.environ.get('ROS_DOMAIN_ID')   # read at collection, before any fixture sets it
ROOT = Path(__file__).resolve().parents[2]


def test_the_package_domain_is_the_callers_when_set(ros_env, pytestconfig):
    if CALLER is None or not CALLER.strip().isdigit():
        assert ros_env['ROS_DOMAIN_ID'] == str(1 + os.getpid() % 101)
    elif worker_index(pytestconfig) == 0:
        assert ros_env['ROS_DOMAIN_ID'] == CALLER.strip()
    else:   # another xdist worker: its own domain, derived from the caller's
        assert ros_env['ROS_DOMAIN_ID'] != CALLER.strip()
        assert ros_env['ROS_DOMAIN_ID'] == package_domain(pytestconfig)


def test_xdist_workers_under_a_callers_domain_get_one_domain_each(monkeypatch):
    # reproduced: with ROS_DOMAIN_ID set, both workers of `-n 2` ran a /contact_sim node in it
    class Worker:
        def __init__(self, name):
            self.workerinput = {'workerid': name}
    monkeypatch.setenv('ROS_DOMAIN_ID', '77')
    domains = [package_domain(Worker(f'gw{i}')) for i in range(4)]
    assert domains[0] == package_domain(object()) == '77'    # the first worker: the caller's
    assert len(set(domains)) == 4 and all(1 <= int(d) <= 101 for d in domains[1:])
    monkeypatch.setenv('ROS_DOMAIN_ID', '232')     # the largest domain: derived ones stay valid
    domains = [package_domain(Worker(f'gw{i}')) for i in range(4)]
    assert domains[0] == '232' and len(set(domains)) == 4
    assert all(1 <= int(d) <= 101 for d in domains[1:])


@pytest.mark.skipif(os.environ.get('CONTACT_SIM_DOMAIN_PROBE') == '1', reason='the probe itself')
def test_a_run_with_a_callers_domain_uses_it(tmp_path):
    # reproduced: the suite set 1 + pid % 101 whatever the caller had set
    env = dict(os.environ, ROS_DOMAIN_ID='77', CONTACT_SIM_DOMAIN_PROBE='1')
    done = subprocess.run(
        [sys.executable, '-m', 'pytest', '-q', '-p', 'no:cacheprovider',
         f'{Path(__file__).relative_to(ROOT)}::test_the_package_domain_is_the_callers_when_set'],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:]
    assert '1 passed' in done.stdout
