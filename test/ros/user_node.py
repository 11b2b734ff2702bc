"""A user's node, run by ``test_hostile_domain`` in a process of its own with the caller's
environment: a plain rclpy node named ``contact_sim`` (the tests' node's name) that declares the
node's parameters and serves ``~/reset``, and counts everything that reaches it from others: the
contact_sim topics, /diagnostics, /rosout, parameter requests, service calls, and the other nodes
it sees in the graph. It prints ``ready`` once up, ``probe`` when its probe topic
(``/isolation_probe``) first delivers (the test's proof that this node does hear its domain),
and at SIGINT one JSON line: what it received.
"""
import json
import signal
import sys

import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from rcl_interfaces.msg import Log, SetParametersResult
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions
from std_msgs.msg import String
from std_srvs.srv import Trigger

from contact_sim.ros import messages as cs_msgs
from contact_sim.ros.params import DEFAULTS, NODE_NAME

PROBE = '/isolation_probe'
PROBE_NODE = 'isolation_probe'   # the test's node that publishes the probe (not counted)


def main():
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node(NODE_NAME)
    received = {'topics': {}, 'parameter_requests': [], 'reset_calls': 0, 'nodes': []}

    def count(topic, _msg):
        received['topics'][topic] = received['topics'].get(topic, 0) + 1
    for topic in cs_msgs.TOPICS:
        name = topic.resolve(f'/{NODE_NAME}')
        node.create_subscription(topic.msg_type, name, lambda m, n=name: count(n, m), 10,
                                 raw=True)
    node.create_subscription(DiagnosticArray, '/diagnostics',
                             lambda m: count('/diagnostics', m), 10)
    node.create_subscription(Log, '/rosout', lambda m: m.name not in (NODE_NAME, PROBE_NODE)
                             and count(f'/rosout from {m.name}', m), 100)
    probe = []

    def on_probe(msg):
        if not probe:
            print('probe', flush=True)
        probe.append(msg.data)
    node.create_subscription(String, PROBE, on_probe, 10)
    for name, value in DEFAULTS.items():
        node.declare_parameter(name, value)

    def on_parameters(parameters):
        received['parameter_requests'].append([p.name for p in parameters])
        return SetParametersResult(successful=True)
    node.add_on_set_parameters_callback(on_parameters)

    def on_reset(_request, response):
        received['reset_calls'] += 1
        response.success = True
        return response
    node.create_service(Trigger, '~/reset', on_reset)

    def look():
        for name, namespace in node.get_node_names_and_namespaces():
            full = f'{namespace.rstrip("/")}/{name}'
            if name not in (NODE_NAME, PROBE_NODE) and full not in received['nodes']:
                received['nodes'].append(full)
    node.create_timer(0.1, look)
    stop = []
    signal.signal(signal.SIGINT, lambda *_: stop.append(True))
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    print('ready', flush=True)
    while not stop:
        executor.spin_once(timeout_sec=0.1)
    look()
    received['probes'] = len(probe)
    print(json.dumps(received), flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
