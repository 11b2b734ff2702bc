"""The ROS tests keep a caller's ROS_DOMAIN_ID (issue 17, item 8): CI runners and developers
keep parallel runs apart by it."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

CALLER = os.environ.get('ROS_DOMAIN_ID')   # read at collection, before any fixture sets it
ROOT = Path(__file__).resolve().parents[2]


def test_the_package_domain_is_the_callers_when_set(ros_env):
    if CALLER is not None and CALLER.strip().isdigit():
        assert ros_env['ROS_DOMAIN_ID'] == CALLER.strip()
    else:
        assert ros_env['ROS_DOMAIN_ID'] == str(1 + os.getpid() % 101)


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
