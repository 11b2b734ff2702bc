"""One /clock with several instances of the node (issue 22: every instance published the global
/clock, and with three in namespaces it went backwards 262 times in 5 s): an instance that finds
another publisher of /clock says so and does not publish it, so /clock never goes backwards.
"""
import pytest

rclpy = pytest.importorskip('rclpy')

from .harness import NODE, Process, assert_clean_exit, stamp_ns  # noqa: E402

MESSAGE = '/contact_sim publishes /clock already: this node does not'


def test_namespaced_instances_leave_clock_to_one_and_it_never_goes_backwards(
        sim, client, ros_env, workdir):
    namespaces = ['/x1', '/x2', '/x3']       # their names sort after the package's /contact_sim
    processes = [Process('contact_sim_node', ['--ros-args', '-r', f'__ns:={ns}'], ros_env,
                         workdir) for ns in namespaces]
    try:
        client.spin_until(lambda: all(MESSAGE in p.output() or p.popen.poll() is not None
                                      for p in processes), 'every instance to yield /clock',
                          timeout=60.0)
        for process in processes:
            assert process.popen.poll() is None and MESSAGE in process.output(), process.output()
        infos = client.node.get_publishers_info_by_topic('/clock')
        assert [(i.node_namespace, i.node_name) for i in infos] == [('/', NODE[1:])]
        clock = client.messages['/clock']
        start = len(clock)
        client.spin_until(lambda: len(clock) >= start + 300, '300 more /clock messages')
        stamps = [stamp_ns(m.clock) for m in clock[start:]]
        assert all(b > a for a, b in zip(stamps, stamps[1:])), 'the clock went backwards'
        assert 'yield' not in sim.output() and 'publishes /clock already' not in sim.output()
    finally:
        for process in processes:
            assert_clean_exit(process)
