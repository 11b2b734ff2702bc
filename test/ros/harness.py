"""What the ROS tests share: the isolation of their ROS processes (console entry points in their
own sessions), an rclpy client node that waits on conditions with deadlines, never a fixed sleep,
and small helpers for stamps, parameters, plate commands, the README and the presets.

The fixtures that start the processes (one ``contact_sim_node`` for all of ``test/ros/``) are in
``conftest.py``.
"""
import os
import re
import signal
import subprocess
import time
from collections.abc import Sequence
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / 'config'
# s, for anything that waits on DDS discovery or on the node: discovery takes up to ~3 s and an
# answer well under 1 s on an idle machine, but on two cores at a load of 18 (four burners, the
# suite's two workers and other work) every process gets a ninth of a core (issue 16)
TIMEOUT = 60.0
# s, for a wait on the node's real-time progress as this client sees it (poses, impacts, the
# recorder): a few s of simulated time idle, and the node and this client each slowed as above
PROGRESS_TIMEOUT = 4 * TIMEOUT
NODE = '/contact_sim'
SIM_RATE = 25.0            # Hz: the publish rate of the package's shared node (conftest.sim)
SIM_TICK_NS = round(1e9 / SIM_RATE)   # ns of simulated time a tick at real_time_factor 1

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

import contact_sim as cs  # noqa: E402
from contact_sim.ros import messages as cs_msgs  # noqa: E402
from rcl_interfaces.msg import Log, Parameter, ParameterType, ParameterValue  # noqa: E402
from rcl_interfaces.srv import GetParameters, SetParameters, SetParametersAtomically  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.experimental.events_executor import EventsExecutor  # noqa: E402
from rclpy.serialization import deserialize_message  # noqa: E402
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402

TOPICS = {topic.resolve(NODE): topic.msg_type for topic in cs_msgs.TOPICS}  # the table
TYPE_NAMES = {
    f'{NODE}/wrench': 'geometry_msgs/msg/WrenchStamped',
    f'{NODE}/contact': 'geometry_msgs/msg/Vector3Stamped',
    f'{NODE}/pose': 'geometry_msgs/msg/PoseStamped',
    f'{NODE}/twist': 'geometry_msgs/msg/TwistStamped',
    f'{NODE}/impact': 'std_msgs/msg/Float64MultiArray',
    '/clock': 'rosgraph_msgs/msg/Clock',
    f'{NODE}/plate_pose': 'geometry_msgs/msg/PoseStamped',
    f'{NODE}/plate_twist': 'geometry_msgs/msg/TwistStamped',
    f'{NODE}/plate_wrench': 'geometry_msgs/msg/WrenchStamped',
}
DEEP = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10000,
                  reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
ROSOUT = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000,
                    reliability=ReliabilityPolicy.RELIABLE,
                    durability=DurabilityPolicy.TRANSIENT_LOCAL)
FIELDS = cs_msgs.IMPACT_FIELDS

# ------------------------------------------------------------------------------------------
# processes
# ------------------------------------------------------------------------------------------

def executable(name):
    """The installed console entry point, found exactly as ``ros2 run contact_sim <name>`` does."""
    from ament_index_python.packages import get_package_prefix
    path = Path(get_package_prefix('contact_sim')) / 'lib' / 'contact_sim' / name
    assert path.is_file(), f'{path} missing: run scripts/setup.sh'
    return str(path)


def _shm_in_use():
    used = set()
    for proc in Path('/proc').iterdir():
        if not proc.name.isdigit():
            continue
        try:
            used.update(line.split()[-1] for line in (proc / 'maps').read_text().splitlines()
                        if '/dev/shm/' in line)
            for fd in (proc / 'fd').iterdir():
                target = os.readlink(fd)
                if target.startswith('/dev/shm/'):
                    used.add(target)
        except OSError:
            continue
    return used


def clean_shm(since):
    """After a SIGKILL: remove shared-memory files made since ``since`` that no process uses."""
    used = _shm_in_use()
    for path in [*Path('/dev/shm').glob('*fastdds*'), *Path('/dev/shm').glob('*fastrtps*')]:
        try:
            if path.stat().st_mtime >= since and str(path) not in used:
                path.unlink()
        except OSError:
            pass


class Process:
    """A console entry point in its own session (process group), output in a file."""

    def __init__(self, name, args, env, workdir):
        self.name = name
        self.log = Path(workdir) / f'{name}-{time.monotonic_ns()}.log'
        self.started = time.time()
        with open(self.log, 'w') as out:
            self.popen = subprocess.Popen([executable(name), *args], env=env, stdout=out,
                                          stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                          start_new_session=True, cwd=workdir)

    def output(self):
        return self.log.read_text(errors='replace')

    def stop(self, timeout=TIMEOUT):
        """SIGINT to the process group; SIGKILL (and /dev/shm clean-up) only if it hangs."""
        if self.popen.poll() is None:
            os.killpg(self.popen.pid, signal.SIGINT)
            try:
                self.popen.wait(timeout)
            except subprocess.TimeoutExpired:
                os.killpg(self.popen.pid, signal.SIGKILL)
                self.popen.wait(TIMEOUT)
                clean_shm(self.started)
                pytest.fail(f'{self.name} ignored SIGINT for {timeout} s:\n{self.output()}')
        return self.popen.returncode, self.output()


def assert_clean_exit(process):
    code, output = process.stop()
    assert code == 0, f'{process.name} exited with {code}:\n{output}'
    assert 'Traceback' not in output, output

# ------------------------------------------------------------------------------------------
# the client side
# ------------------------------------------------------------------------------------------

SLICE = 0.02     # s: the least time spent taking messages between two checks of a condition


def spin_until(executor, condition, what, timeout=TIMEOUT):
    """Spin ``executor`` until ``condition()`` holds; fail the test after ``timeout`` s.

    Between two checks the executor takes what has arrived for at least ``SLICE`` s and ten
    times what the last check cost: a check over many messages costs more than taking one, and a
    client that checked after every message would fall ever further behind a busy node."""
    deadline = time.monotonic() + timeout
    while True:
        checked = time.monotonic()
        if condition():
            return
        now = time.monotonic()
        if now > deadline:
            pytest.fail(f'timed out after {timeout} s waiting for {what}')
        until = min(now + max(SLICE, 10.0 * (now - checked)), deadline)
        while True:
            executor.spin_once(timeout_sec=0.01)
            if time.monotonic() >= until:
                break


def domain_node(domain_id, name):
    """(context, node, executor): an rclpy node ``name`` in ROS domain ``domain_id`` of its own
    (no module node there); ``context.try_shutdown()`` ends it."""
    context = rclpy.Context()
    context.init(domain_id=domain_id)
    node = rclpy.create_node(name, context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    return context, node, executor


class Received(Sequence):
    """The messages of one topic as received: kept serialized, each deserialized when a test
    first reads it. Taking a message raw costs this client about 85 us of CPU against 145 us
    as a message object (and 226 us with rclpy's SingleThreadedExecutor), measured on the
    shared node's 800 messages a second at a load of 9-10; most messages are never read."""

    def __init__(self, msg_type):
        self._type, self._raw, self._read = msg_type, [], []

    def append(self, data):
        self._raw.append(data)

    def __len__(self):
        return len(self._raw)

    def __getitem__(self, index):
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self._raw)))]
        i = index + len(self._raw) if index < 0 else index
        if not 0 <= i < len(self._raw):
            raise IndexError(index)
        if i >= len(self._read):
            self._read.extend([None] * (len(self._raw) - len(self._read)))
        if self._read[i] is None:
            self._read[i] = deserialize_message(self._raw[i], self._type)
        return self._read[i]


class Client:
    """An rclpy node in the test process with helpers that wait on conditions.

    It subscribes to every topic of the shared node for the whole package (``messages``, one
    ``Received`` per topic) and spins rclpy's events executor, the cheaper one per message: on
    two loaded cores a client slower than the node's output falls ever further behind it."""

    def __init__(self):
        self.node = rclpy.create_node('contact_sim_test_client')
        self.executor = EventsExecutor()
        self.executor.add_node(self.node)
        self.messages = {topic: Received(msg_type) for topic, msg_type in TOPICS.items()}
        self.rosout = []
        for topic, msg_type in TOPICS.items():
            self.node.create_subscription(msg_type, topic, self.messages[topic].append, DEEP,
                                          raw=True)
        self.node.create_subscription(Log, '/rosout', self.rosout.append, ROSOUT)
        self._clients = {}

    def spin_until(self, condition, what, timeout=TIMEOUT):
        spin_until(self.executor, condition, what, timeout)

    def spin_for(self, seconds):
        """Keep receiving for a while (used only to collect more data, never to wait for DDS)."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.02)

    def call(self, srv_type, name, request, timeout=TIMEOUT):
        client = self._clients.get(name)
        if client is None:
            client = self._clients[name] = self.node.create_client(srv_type, name)
        deadline = time.monotonic() + timeout
        self.spin_until(client.service_is_ready, f'service {name}', timeout)
        futures, wait = [client.call_async(request)], 3.0
        while True:
            # A server that has just appeared may not have matched its reply writer to us yet
            # and then drops the reply: ask again after a while (every call here is idempotent
            # or, like ~/reset, harmless to repeat), each time waiting twice as long. The answer
            # taken is that to the last request (the server answers in order: after it, nothing
            # of this call is left to change the node); once an earlier one has been answered,
            # the server is answering, and on a loaded machine the last is just late: no more
            # requests then.
            answering = any(f.done() for f in futures[:-1])
            retry = deadline if answering else min(time.monotonic() + wait, deadline)
            self.spin_until(lambda: futures[-1].done() or time.monotonic() > retry,
                            f'a response from {name}', timeout)
            if futures[-1].done():
                for future in futures[:-1]:
                    if not future.done():
                        client.remove_pending_request(future)
                return futures[-1].result()
            if time.monotonic() > deadline:
                for future in futures:
                    client.remove_pending_request(future)
                pytest.fail(f'timed out after {timeout} s waiting for a response from {name}')
            if not any(f.done() for f in futures):
                futures.append(client.call_async(request))
                wait *= 2.0

    def set_parameters(self, node, atomically=False, **values):
        params = [Parameter(name=k, value=parameter_value(v)) for k, v in values.items()]
        if atomically:
            return [self.call(SetParametersAtomically, f'{node}/set_parameters_atomically',
                              SetParametersAtomically.Request(parameters=params)).result]
        return self.call(SetParameters, f'{node}/set_parameters',
                         SetParameters.Request(parameters=params)).results

    def get_parameters(self, node, names):
        response = self.call(GetParameters, f'{node}/get_parameters',
                             GetParameters.Request(names=list(names)))
        return dict(zip(names, (value_of(v) for v in response.values)))

    def query(self, names, node=NODE):
        response = self.call(GetParameters, f'{node}/query_restitution',
                             GetParameters.Request(names=list(names)))
        return response.values

    def count(self, topic):
        return len(self.messages[topic])

    def clock_seconds(self):
        self.spin_until(lambda: self.messages['/clock'], 'a /clock message')
        return stamp_s(self.messages['/clock'][-1].clock)


def parameter_value(value):
    if isinstance(value, bool):
        return ParameterValue(type=ParameterType.PARAMETER_BOOL, bool_value=value)
    if isinstance(value, int):
        return ParameterValue(type=ParameterType.PARAMETER_INTEGER, integer_value=value)
    if isinstance(value, float):
        return ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=value)
    return ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=value)


def value_of(value):
    return {ParameterType.PARAMETER_BOOL: lambda v: v.bool_value,
            ParameterType.PARAMETER_INTEGER: lambda v: v.integer_value,
            ParameterType.PARAMETER_DOUBLE: lambda v: v.double_value,
            ParameterType.PARAMETER_STRING: lambda v: v.string_value}.get(
                value.type, lambda v: None)(value)


def stamp_ns(stamp):
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def stamp_s(stamp):
    return stamp_ns(stamp) * 1e-9


def last_stamps(client):
    """One line per topic: how many messages the client has received and the simulated time
    (s) of the last (for a failure report)."""
    lines = []
    for topic, messages in client.messages.items():
        last = f'{cs_msgs.message_time_ns(messages[-1]) * 1e-9:.3f} s' if messages else '-'
        lines.append(f'{topic}: {len(messages)} messages, last at {last}')
    return '\n'.join(lines)


def impacts_after(client, ns):
    out = []
    for msg in client.messages[f'{NODE}/impact']:
        record = dict(zip(FIELDS, msg.data))
        if cs_msgs.to_ns(record['time']) >= ns:
            out.append(record)
    return out


def default_contact_and_mass():
    """The default configuration, built here from the library alone (not through the node)."""
    contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', 0.0127,
                                        damping_factor=8.87e5)
    return contact, cs.sphere_mass(cs.MATERIALS['steel'].density, 0.0127)


def reset(client):
    """Restart the drop; returns the simulated time (ns) the new drop starts at."""
    response = client.call(Trigger, f'{NODE}/reset', Trigger.Request())
    assert response.success, response.message
    match = re.search(r'at t = ([0-9.]+) s', response.message)
    assert match, response.message
    return cs_msgs.to_ns(float(match.group(1)))

# ------------------------------------------------------------------------------------------
# plate commands, the README, the presets
# ------------------------------------------------------------------------------------------


PLATE_COMMAND_YAML = ('{joint_names: [plate_z], points: [{positions: [0.01], velocities: [0.0], '
                      'time_from_start: {sec: 1}}]}')


def fill_message(msg, values):
    """Set a message's fields from a YAML mapping, as ``ros2 topic pub`` does."""
    import importlib
    types = msg.get_fields_and_field_types()
    for name, value in values.items():
        assert name in types, name
        if isinstance(value, dict):
            fill_message(getattr(msg, name), value)
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            package, _, cls = types[name][len('sequence<'):-1].partition('/')
            item = getattr(importlib.import_module(f'{package}.msg'), cls)
            setattr(msg, name, [fill_message(item(), v) for v in value])
        else:
            setattr(msg, name, value)
    return msg


def readme():
    """The README and the node's docs page (docs/node.md), where its `ros2` examples are."""
    return (ROOT / 'README.md').read_text() + (ROOT / 'docs' / 'node.md').read_text()


def yaml_parameters(path):
    data = yaml.safe_load(path.read_text())
    (section,) = data.values()
    return section['ros__parameters']


def rosout_has(client, text):
    return any(text in m.msg for m in client.rosout)
