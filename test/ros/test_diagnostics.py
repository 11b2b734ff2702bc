"""``/diagnostics`` with real ROS: the package's node (``sim``, real time) in its own process, a
DiagnosticArray subscriber in this one: the node's status with the real-time factor achieved, the
lag, the integrator steps per second and the mode, all present and finite.
"""
import math

import pytest

rclpy = pytest.importorskip('rclpy')

from contact_sim.ros import diagnostics as cs_diag  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus  # noqa: E402
from .harness import DEEP, NODE, PROGRESS_TIMEOUT, reset  # noqa: E402


def test_rates_over_wall_time():
    before, after = cs_diag.Progress(1.0, 5.0, 10, 100), cs_diag.Progress(3.0, 9.0, 50, 500)
    assert cs_diag.rates(before, after) == (2.0, 20.0, 200.0)
    assert cs_diag.rates(after, after) == (0.0, 0.0, 0.0)


def test_diagnostics_report_the_rate_lag_steps_and_mode(sim, client):
    statuses = []

    def keep(msg):
        statuses.extend(s for s in msg.status if s.hardware_id == NODE)
    client.node.create_subscription(DiagnosticArray, '/diagnostics', keep, DEEP)
    reset(client)   # a bounce: integrator steps in the next second or two
    client.spin_until(lambda: len(statuses) >= 4, 'four /diagnostics from the node',
                      PROGRESS_TIMEOUT)
    modes = set()
    for status in statuses:
        values = {kv.key: kv.value for kv in status.values}
        assert set(values) == set(cs_diag.KEYS)
        assert status.name == f'{NODE}: simulation'
        assert status.level in (DiagnosticStatus.OK, DiagnosticStatus.WARN)
        numbers = {key: float(values[key]) for key in cs_diag.KEYS
                   if key not in ('mode', 'paced_by_recorder')}
        assert all(math.isfinite(v) and v >= 0.0 for v in numbers.values()), numbers
        assert numbers['real_time_factor'] == 1.0
        assert values['paced_by_recorder'] in ('true', 'false')
        modes.add(values['mode'])
    assert modes <= {'flight', 'contact', 'rest', 'carried'}
    later = [{kv.key: float(kv.value) for kv in s.values
              if kv.key in ('real_time_factor_achieved', 'ticks_per_second')} for s in statuses[1:]]
    assert any(v['real_time_factor_achieved'] > 0.0 and v['ticks_per_second'] > 0.0
               for v in later)
    assert any(float(next(kv.value for kv in s.values
                          if kv.key == 'integrator_steps_per_second')) > 0.0 for s in statuses)
