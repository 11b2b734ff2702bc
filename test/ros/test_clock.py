"""One /clock with several instances of the node (issue 22: every instance published the global
/clock, and with three in namespaces it went backwards 262 times in 5 s): an instance that finds
another publisher of /clock says so and does not publish it, so /clock never goes backwards.
"""


import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from rclpy.qos import QoSProfile, ReliabilityPolicy  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402

from . import harness  # noqa: E402
from .domains import claim_domain  # noqa: E402
from .harness import Process, assert_clean_exit, domain_node, stamp_ns  # noqa: E402

MESSAGE = '/contact_sim publishes /clock already: this node does not'
TIMEOUT = 60.0


def test_namespaced_instances_leave_clock_to_one_and_it_never_goes_backwards(ros_env, workdir):
    # in a domain of its own (the module's node, which other tests read /clock from, never sees
    # these instances): /contact_sim and three instances whose names sort after it
    env = {**ros_env, 'ROS_DOMAIN_ID': str(claim_domain())}
    context, watch, executor = domain_node(int(env['ROS_DOMAIN_ID']), 'contact_sim_clock_watch')
    clock = []

    def spin_until(condition, what):
        harness.spin_until(executor, condition, what, TIMEOUT)

    first = Process('contact_sim_node', [], env, workdir)
    processes = [Process('contact_sim_node', ['--ros-args', '-r', f'__ns:={ns}'], env, workdir)
                 for ns in ('/x1', '/x2', '/x3')]
    try:
        spin_until(lambda: all(MESSAGE in p.output() or p.popen.poll() is not None
                               for p in processes), 'every instance to yield /clock')
        for process in processes:
            assert process.popen.poll() is None and MESSAGE in process.output(), process.output()
        spin_until(lambda: [(i.node_namespace, i.node_name) for i in
                            watch.get_publishers_info_by_topic('/clock')] == [('/', 'contact_sim')],
                   'one publisher of /clock')
        # A reader made now matches the one publisher left. (One made before, as this test's
        # was, still had samples of the instances that yielded in its queue: on a loaded machine
        # it read them after the graph had lost their publishers, and saw the clock go back.)
        watch.create_subscription(Clock, '/clock', lambda m: clock.append(stamp_ns(m.clock)),
                                  QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE))
        spin_until(lambda: len(clock) >= 300, '300 /clock messages')
        stamps = list(clock)
        assert all(b > a for a, b in zip(stamps, stamps[1:])), 'the clock went backwards'
        assert first.popen.poll() is None
        assert 'yield' not in first.output() and 'publishes /clock already' not in first.output()
    finally:
        for process in [*processes, first]:
            assert_clean_exit(process)
        watch.destroy_node()
        context.try_shutdown()


class _Info:
    def __init__(self, full):
        self.node_namespace, _, self.node_name = full.rpartition('/')
        self.node_namespace = self.node_namespace or '/'


class _Graph:
    """A node's view of the graph: the /clock publishers, and the instances whose ~/impact and
    ~/query_restitution it has discovered so far."""

    def __init__(self, me, clocks, instances=()):
        self.me, self.clocks, self.instances = me, clocks, set(instances)

    def get_namespace(self):
        return self.me.rpartition('/')[0] or '/'

    def get_name(self):
        return self.me.rpartition('/')[2]

    def get_publishers_info_by_topic(self, topic):
        return [_Info(full) for full in self.clocks]

    def get_publisher_names_and_types_by_node(self, name, namespace):
        full = full_name(namespace, name)
        return [(f'{full}/impact', ['std_msgs/msg/Float64MultiArray'])] \
            if full in self.instances else []

    def get_service_names_and_types_by_node(self, name, namespace):
        full = full_name(namespace, name)
        return [(f'{full}/query_restitution', ['rcl_interfaces/srv/GetParameters'])] \
            if full in self.instances else []


from contact_sim.ros.clock import FOREIGN_GRACE, clock_to_yield_to, full_name  # noqa: E402


def test_a_new_instance_seen_before_its_topics_is_not_taken_for_a_foreign_clock():
    # the race of a fresh-clone CI run: /x1's /clock publisher was discovered before its
    # ~/impact, so /contact_sim yielded to it, and /x1 then had nothing to yield to
    seen = {}
    graph = _Graph('/contact_sim', ['/contact_sim', '/x1/contact_sim'])
    assert clock_to_yield_to(graph, seen, 0.0) is None
    graph.instances.add('/x1/contact_sim')              # its topics arrive
    assert clock_to_yield_to(graph, seen, FOREIGN_GRACE + 1.0) is None
    # the later instance yields to the earlier one at once
    later = _Graph('/x1/contact_sim', ['/contact_sim', '/x1/contact_sim'])
    assert clock_to_yield_to(later, {}, 0.0) == '/contact_sim'


def test_a_foreign_clock_is_yielded_to_once_it_has_been_seen_for_the_grace_time():
    seen = {}
    graph = _Graph('/contact_sim', ['/contact_sim', '/rosbag2_player'])
    assert clock_to_yield_to(graph, seen, 10.0) is None
    assert clock_to_yield_to(graph, seen, 10.0 + FOREIGN_GRACE - 0.1) is None
    assert clock_to_yield_to(graph, seen, 10.0 + FOREIGN_GRACE) == '/rosbag2_player'
