"""The suite's markers; the tests mirror the package tree (``test/drop/`` tests ``contact_sim/drop/``).

* ``ros``: the test starts a ROS process or needs rclpy.  Every test under ``test/ros/`` has it (the
  ROS face), and any other that needs ROS says so with ``@pytest.mark.ros``.
  ``python -m pytest -m "not ros"`` runs the core library alone, with no ROS process started.
* ``slow``: the test takes more than about 10 s on its own (a node run for a simulated minute, a
  colcon build, a flat-out recording); ``-m "not slow"`` leaves them out of a quick run.
"""
from pathlib import Path

import pytest

ROS_TESTS = Path(__file__).resolve().parent / 'ros'


def pytest_configure(config):
    config.addinivalue_line('markers', 'ros: starts a ROS process or needs rclpy (all of test/ros/)')
    config.addinivalue_line('markers', 'slow: takes more than about 10 s on its own')


def pytest_collection_modifyitems(config, items):
    for item in items:
        if ROS_TESTS in Path(item.path).resolve().parents:
            item.add_marker(pytest.mark.ros)
