"""``/diagnostics`` with real ROS: the package's node (``sim``, real time) in its own process, a
DiagnosticArray subscriber in this one: the node's status with the real-time factor achieved, the
lag, the integrator steps per second and the mode, all present and finite.
"""
import math

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

from contact_sim.ros import diagnostics as cs_diag

from .domains import claim_domain
from .harness import DEEP, NODE, PROGRESS_TIMEOUT, Process, assert_clean_exit, domain_node, \
    reset, spin_until


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


def test_a_flat_out_node_says_its_rate_once_a_wall_second(ros_env, workdir):
    """Issue 33: flat out, /diagnostics came as a burst of 28 in 0.75 s, then nothing for 12 s,
    and paced, a second message 10-20 ms after the first read `0 x real time`. Here, a flat-out
    node of its own (no recorder: unpaced after its grace): once it ticks, every message has a
    rate above zero, measured over a wall second or more (the period each message states)."""
    env = {**ros_env, 'ROS_DOMAIN_ID': str(claim_domain())}
    context, watch, executor = domain_node(int(env['ROS_DOMAIN_ID']), 'contact_sim_diag_watch')
    received = []
    watch.create_subscription(DiagnosticArray, '/diagnostics', lambda m: received.append(
        {kv.key: kv.value for kv in m.status[0].values}), DEEP)
    node = Process('contact_sim_node', ['--ros-args', '-p', 'real_time_factor:=0.0'], env,
                   workdir)
    try:
        def ticking():
            return [i for i, v in enumerate(received) if float(v['ticks_per_second']) > 0]
        spin_until(executor, lambda: len(received) - (ticking() or [len(received)])[0] >= 6,
                   'six /diagnostics after the node began to tick', PROGRESS_TIMEOUT)
    finally:
        assert_clean_exit(node)
        context.try_shutdown()
    start = ticking()[0]
    later = received[start + 1:start + 6]   # (the first of them may span the start's pause)
    for values in later:
        assert values['real_time_factor'] == 'inf'
        assert float(values['real_time_factor_achieved']) > 0.0, values
        assert float(values['ticks_per_second']) > 0.0, values
        # measured over a wall second or more, as the node says: never a burst
        assert float(values['period']) >= cs_diag.PERIOD - cs_diag.EARLY, values
