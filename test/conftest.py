"""The suite's markers; the tests mirror the package tree (``test/drop/`` tests ``contact_sim/drop/``).

* ``ros``: the test starts a ROS process or needs rclpy.  Every test under ``test/ros/`` has it (the
  ROS face), and any other that needs ROS says so with ``@pytest.mark.ros``.
  ``python -m pytest -m "not ros"`` runs the core library alone, with no ROS process started
  (``test/ros/`` is then not even imported, so rclpy need not be installed for it).
* ``slow``: the test takes more than about 10 s on its own (a node run for a simulated minute, a
  colcon build, a flat-out recording); ``-m "not slow"`` leaves them out of a quick run.

Pinned dependencies (requirements.txt: rclpy, rosbags, mujoco, pybullet, pydrake, sphinx,
distributed, ...) are imported plainly, never behind ``pytest.importorskip``: a broken install
fails the suite instead of skipping part of it (issue 33, item 7). ``.ci/run`` fails on any
skip not in its allow-list.
"""
import os
from pathlib import Path

import pytest

ROS_TESTS = Path(__file__).resolve().parent / 'ros'
# The skips CI allows (``CI=true``, as .ci/run sets it): test id (its parameters left out) -> the
# start of the one reason it may skip for, each a place the suite runs from that lacks what the
# test needs. Any other skip fails the test there: a skip must never hide a broken install
# (issue 33, item 7).
SKIPS_ALLOWED = {
    # the suite run by `colcon test` inside the workspace that test builds (test_packaging.py)
    'test/test_packaging.py::test_the_checkout_builds_and_tests_with_plain_colcon_in_a_ros_workspace':
        'already inside the workspace this test builds',
    'test/test_packaging.py::test_activating_the_venv_puts_the_executables_on_path':
        "needs the checkout's .venv made by scripts/setup.sh",
    'test/test_packaging.py::'
    'test_deactivate_restores_the_environment_and_activating_twice_adds_nothing':
        "needs the checkout's .venv made by scripts/setup.sh",
    'test/phase/test_compiled.py::test_the_colcon_symlink_install_loads_the_same_cache':
        'no colcon --symlink-install build at',
    # inside the test run that this test starts (test_hostile_domain.py)
    'test/ros/test_hostile_domain.py::'
    'test_a_users_node_in_the_callers_domain_receives_nothing_from_a_test_run':
        'inside the run this test starts',
}


def _clear_stale_numba_cache():
    """numba's cache cleared if a source it compiles from changed (``scripts/numba_cache.py``):
    numba itself checks a kernel's own file only."""
    import importlib.util
    path = Path(__file__).resolve().parents[1] / 'scripts' / 'numba_cache.py'
    spec = importlib.util.spec_from_file_location('contact_sim_numba_cache', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.clear_if_stale()


def pytest_configure(config):
    if not hasattr(config, 'workerinput'):   # once, before any xdist worker starts
        _clear_stale_numba_cache()
    config.addinivalue_line('markers', 'ros: starts a ROS process or needs rclpy (all of test/ros/)')
    config.addinivalue_line('markers', 'slow: takes more than about 10 s on its own')


def pytest_collection_modifyitems(config, items):
    for item in items:
        if ROS_TESTS in Path(item.path).resolve().parents:
            item.add_marker(pytest.mark.ros)


def _may_select(markexpr, marks):
    """Whether the ``-m`` expression selects a test that has exactly ``marks``."""
    if not markexpr:
        return True
    try:
        from _pytest.mark.expression import Expression   # pytest's own -m parser
        return Expression.compile(markexpr).evaluate(lambda name, **_: name in marks)
    except Exception:   # noqa: BLE001  (another pytest: collect, as without the hook)
        return True


def pytest_ignore_collect(collection_path, config):
    """With ``-m`` leaving out every ``ros`` test, ``test/ros/`` is not imported at all."""
    if Path(collection_path).resolve() == ROS_TESTS:
        markexpr = config.getoption('markexpr')
        if not any(_may_select(markexpr, marks) for marks in ({'ros'}, {'ros', 'slow'})):
            return True
    return None


def skip_refused(nodeid, report, environ=os.environ):
    """Why a skip fails the run (with ``CI=true``, a skip not in ``SKIPS_ALLOWED`` for its
    reason), or None."""
    if environ.get('CI') != 'true' or not report.skipped or hasattr(report, 'wasxfail'):
        return None
    longrepr = report.longrepr
    reason = longrepr[2] if isinstance(longrepr, tuple) else str(longrepr)
    reason = reason.removeprefix('Skipped: ')
    allowed = SKIPS_ALLOWED.get(nodeid.split('[')[0])
    if allowed is not None and reason.startswith(allowed):
        return None
    return (f'{nodeid} skipped in CI ({reason}): not in the allow-list (test/conftest.py, '
            'SKIPS_ALLOWED); CI fails on any other skip, since a skip can hide a broken install')


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    why = skip_refused(item.nodeid, report)
    if why:
        report.outcome, report.longrepr = 'failed', why


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector):
    outcome = yield
    report = outcome.get_result()
    why = skip_refused(report.nodeid, report)
    if why:
        report.outcome, report.longrepr = 'failed', why
