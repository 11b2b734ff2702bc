"""The node with real ROS: ``contact_sim_node`` runs as its own process, started through its console
entry point (the executable ``ros2 run`` would start), and this test process talks to it through
a separate rclpy client node.

Isolation: a ROS_DOMAIN_ID derived from this process's pid, localhost-only discovery and a
temporary ROS_LOG_DIR. Every wait is on a condition with a deadline, never a fixed sleep. One node
process serves the whole module; tests that change it put it back.
"""
import math
import os
import re
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / 'config'
TIMEOUT = 20.0          # s, for anything that waits on DDS discovery or on the node
NODE = '/contact_sim'

rclpy = pytest.importorskip('rclpy')

import contact_sim as cs  # noqa: E402
from contact_sim.ros import messages as cs_msgs  # noqa: E402
from contact_sim.ros import params as cs_params  # noqa: E402
from contact_sim.ros import recorder as cs_recorder  # noqa: E402
from rcl_interfaces.msg import Log, Parameter, ParameterType, ParameterValue  # noqa: E402
from rcl_interfaces.srv import GetParameters, SetParameters, SetParametersAtomically  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from geometry_msgs.msg import PoseStamped  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from std_msgs.msg import Float64MultiArray  # noqa: E402
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


def _clean_shm(since):
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
                _clean_shm(self.started)
                pytest.fail(f'{self.name} ignored SIGINT for {timeout} s:\n{self.output()}')
        return self.popen.returncode, self.output()


def assert_clean_exit(process):
    code, output = process.stop()
    assert code == 0, f'{process.name} exited with {code}:\n{output}'
    assert 'Traceback' not in output, output


# ------------------------------------------------------------------------------------------
# the client side
# ------------------------------------------------------------------------------------------

class Client:
    """An rclpy node in the test process with helpers that wait on conditions."""

    def __init__(self):
        self.node = rclpy.create_node('contact_sim_test_client')
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(self.node)
        self.messages = {topic: [] for topic in TOPICS}
        self.rosout = []
        for topic, msg_type in TOPICS.items():
            self.node.create_subscription(msg_type, topic, self.messages[topic].append, DEEP)
        self.node.create_subscription(Log, '/rosout', self.rosout.append, ROSOUT)
        self._clients = {}

    def spin_until(self, condition, what, timeout=TIMEOUT):
        deadline = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > deadline:
                pytest.fail(f'timed out after {timeout} s waiting for {what}')
            self.executor.spin_once(timeout_sec=0.05)

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
        while True:
            # A server that has just appeared may not have matched its reply writer to us yet
            # and then drops the reply: ask again after a while (every call here is idempotent
            # or, like ~/reset, harmless to repeat).
            future = client.call_async(request)
            retry = min(time.monotonic() + 3.0, deadline)
            self.spin_until(lambda: future.done() or time.monotonic() > retry,
                            f'a response from {name}', timeout)
            if future.done():
                return future.result()
            client.remove_pending_request(future)
            if time.monotonic() > deadline:
                pytest.fail(f'timed out after {timeout} s waiting for a response from {name}')

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


# ------------------------------------------------------------------------------------------
# fixtures
# ------------------------------------------------------------------------------------------

@pytest.fixture(scope='module')
def workdir():
    with tempfile.TemporaryDirectory(prefix='contact_sim_test_') as path:
        yield Path(path)


@pytest.fixture(scope='module')
def ros_env(workdir):
    """Environment for every ROS process of this module, the test process included."""
    saved = dict(os.environ)
    os.environ.update({
        'ROS_DOMAIN_ID': str(1 + os.getpid() % 101),
        'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST',
        'ROS_LOG_DIR': str(workdir / 'ros_log'),
        'RCUTILS_LOGGING_BUFFERED_STREAM': '0',
        'RCUTILS_COLORIZED_OUTPUT': '0',
        'PYTHONUNBUFFERED': '1',
    })
    os.environ.pop('ROS_LOCALHOST_ONLY', None)
    yield dict(os.environ)
    os.environ.clear()
    os.environ.update(saved)


@pytest.fixture(scope='module')
def client(ros_env):
    rclpy.init()
    client = Client()
    yield client
    client.node.destroy_node()
    rclpy.try_shutdown()


@pytest.fixture(scope='module')
def sim(ros_env, client, workdir):
    """contact_sim_node on its built-in defaults (steel ball, cast-iron plate, 1 m, real time)."""
    process = Process('contact_sim_node', [], ros_env, workdir)
    client.spin_until(lambda: client.count(f'{NODE}/pose') >= 5 or process.popen.poll() is not None,
                      'the node to publish')
    assert process.popen.poll() is None, process.output()
    yield process
    assert_clean_exit(process)


def reset(client):
    """Restart the drop; returns the simulated time (ns) the new drop starts at."""
    response = client.call(Trigger, f'{NODE}/reset', Trigger.Request())
    assert response.success, response.message
    match = re.search(r'at t = ([0-9.]+) s', response.message)
    assert match, response.message
    return cs_msgs.to_ns(float(match.group(1)))


# ------------------------------------------------------------------------------------------
# tests
# ------------------------------------------------------------------------------------------

def test_topics_and_services_have_the_declared_types(sim, client):
    def graph():
        return dict(client.node.get_topic_names_and_types())
    client.spin_until(lambda: all(t in graph() for t in TOPICS), 'all topics in the graph')
    topics = graph()
    for topic, type_name in TYPE_NAMES.items():
        assert topics[topic] == [type_name], topic
    services = dict(client.node.get_service_names_and_types())
    assert services[f'{NODE}/query_restitution'] == ['rcl_interfaces/srv/GetParameters']
    assert services[f'{NODE}/reset'] == ['std_srvs/srv/Trigger']


def test_stamps_are_simulated_time_monotonic_and_framed(sim, client):
    start = {topic: client.count(topic) for topic in TOPICS}
    client.spin_until(lambda: client.count(f'{NODE}/pose') >= start[f'{NODE}/pose'] + 100,
                      '100 more poses')
    for topic in TOPICS:
        new = client.messages[topic][start[topic]:]
        if topic.endswith('impact'):
            times = [m.data[0] for m in new]
            assert all(np.isfinite(m.data).all() or m.data[4] == math.inf for m in new)
        elif topic == '/clock':
            times = [stamp_ns(m.clock) for m in new]
        else:
            times = [stamp_ns(m.header.stamp) for m in new]
            assert {m.header.frame_id for m in new} == {'plate'}, topic
        assert all(b > a for a, b in zip(times, times[1:])), f'{topic} stamps not increasing'
    poses = client.messages[f'{NODE}/pose'][start[f'{NODE}/pose']:]
    clocks = {stamp_ns(m.clock) for m in client.messages['/clock']}
    assert {stamp_ns(p.header.stamp) for p in poses[:-5]} <= clocks  # /clock = pose stamps
    for p in poses:
        assert math.isfinite(p.pose.position.z) and p.pose.orientation.w == 1.0


def test_reset_restarts_the_drop_and_time_keeps_running(sim, client):
    before = client.clock_seconds()
    t0 = reset(client)
    assert t0 >= cs_msgs.to_ns(before)
    client.spin_until(lambda: impacts_after(client, t0), 'the first impact after the reset')
    first = impacts_after(client, t0)[0]
    # released from rest 1 m above the plate: touches after sqrt(2 h / g) at sqrt(2 g h)
    assert first['time'] - t0 * 1e-9 == pytest.approx(math.sqrt(2 * 1.0 / 9.81), abs=1e-6)
    assert first['impact_speed'] == pytest.approx(math.sqrt(2 * 9.81 * 1.0), rel=1e-9)
    poses = [p for p in client.messages[f'{NODE}/pose'] if stamp_ns(p.header.stamp) > t0]
    early = [p for p in poses if stamp_ns(p.header.stamp) - t0 < 100_000_000]
    assert early, 'no pose within 0.1 s of the reset'
    for p in early:  # centre height R + h - g t^2 / 2 while falling
        t = (stamp_ns(p.header.stamp) - t0) * 1e-9
        assert p.pose.position.z == pytest.approx(0.0127 + 1.0 - 9.81 * t * t / 2, abs=1e-9)
    twists = [m for m in client.messages[f'{NODE}/twist'] if t0 < stamp_ns(m.header.stamp)]
    t = (stamp_ns(twists[0].header.stamp) - t0) * 1e-9
    assert twists[0].twist.linear.z == pytest.approx(-9.81 * t, abs=1e-9)  # up is +z


def test_wrench_shows_every_impact_with_its_peak(sim, client):
    t0 = reset(client)
    client.spin_until(lambda: len(impacts_after(client, t0)) >= 6, 'six impacts', timeout=30)
    impacts = impacts_after(client, t0)
    last_end = impacts[-1]['time'] + impacts[-1]['contact_duration']
    for topic in (f'{NODE}/wrench', f'{NODE}/contact'):
        client.spin_until(lambda: stamp_s(client.messages[topic][-1].header.stamp) > last_end,
                          f'the {topic} samples of the last impact')
    samples = [(stamp_ns(m.header.stamp), m.wrench.force.z) for m in
               client.messages[f'{NODE}/wrench'] if stamp_ns(m.header.stamp) >= t0]
    stamps = np.array([s for s, _ in samples])
    forces = np.array([f for _, f in samples])
    assert np.all(forces >= 0.0) and np.all(np.isfinite(forces))
    covered = np.zeros(len(samples), dtype=bool)
    for i, impact in enumerate(impacts):
        lo = cs_msgs.to_ns(impact['time']) - 2
        hi = cs_msgs.to_ns(impact['time'] + impact['contact_duration']) + 2
        inside = (stamps >= lo) & (stamps <= hi)
        covered |= inside
        assert inside.sum() >= 5, f'impact {i}: only {inside.sum()} wrench samples'
        assert forces[inside].max() == pytest.approx(impact['peak_force'], rel=1e-9), \
            f'impact {i}: the wrench misses the peak'
        assert impact['restitution'] == pytest.approx(
            impact['rebound_speed'] / impact['impact_speed'], rel=1e-12)
        assert 0.0 < impact['restitution'] < 1.0
        assert 2e-5 < impact['contact_duration'] < 1e-3  # steel on iron: about 0.1 ms
    # no force outside the reported contacts, up to the end of the last one
    before_end = stamps <= cs_msgs.to_ns(last_end) + 2
    assert not np.any((forces > 0.0) & ~covered & before_end)
    # the speeds chain: a bounce starts at about the previous rebound speed, never faster (the
    # sphere lifts off slightly inside the undeformed surface and climbs out against gravity)
    for a, b in zip(impacts, impacts[1:]):
        assert b['impact_speed'] <= a['rebound_speed']
        assert b['impact_speed'] == pytest.approx(a['rebound_speed'], rel=1e-3)
    # the contact state follows the wrench: same stamps, in contact exactly while F > 0
    contact = {stamp_ns(m.header.stamp): m.vector for m in client.messages[f'{NODE}/contact']
               if stamp_ns(m.header.stamp) >= t0}
    for ns, force in samples:
        if ns <= cs_msgs.to_ns(last_end):
            assert contact[ns].z == (1.0 if force > 0 else 0.0)


def test_query_restitution_answers_a_batch_with_bad_names(sim, client):
    contact, mass = default_contact_and_mass()
    good = {'2.5': ('restitution', 2.5), 'restitution:0.5': ('restitution', 0.5),
            'contact_duration:1': ('contact_duration', 1.0), 'peak_force:1': ('peak_force', 1.0),
            'max_penetration:1': ('max_penetration', 1.0), ' 1e-2 ': ('restitution', 0.01)}
    bad = ['abc', '-1', '0', 'inf', 'nan', 'speed:1', 'restitution:', '', ':2']
    names = ['2.5', 'abc', 'restitution:0.5', '-1', 'contact_duration:1', '0', 'inf',
             'peak_force:1', 'nan', 'speed:1', 'max_penetration:1', 'restitution:', '', ':2',
             ' 1e-2 ']
    values = client.query(names)
    assert len(values) == len(names)
    for name, value in zip(names, values):
        if name in bad:
            assert value.type == ParameterType.PARAMETER_NOT_SET, name
            continue
        assert value.type == ParameterType.PARAMETER_DOUBLE, name
        quantity, speed = good[name]
        exact = getattr(cs.simulate_impact(contact, mass, speed), quantity)
        assert value.double_value == pytest.approx(exact, rel=1e-6), name
    # one warning per bad name, naming it, in the node's log (/rosout)
    def warned(name):
        return any(m.level == Log.WARN and m.name == 'contact_sim' and repr(name) in m.msg
                   for m in client.rosout)
    client.spin_until(lambda: all(warned(n) for n in bad), 'a warning for each bad name')
    assert not any(warned(n) for n in good)
    assert client.query([]) == []


def test_bad_parameters_are_rejected_with_reasons_and_the_node_goes_on(sim, client):
    names = list(cs_params.PARAMETER_NAMES)
    before = client.get_parameters(NODE, names)
    answer_before = client.query(['restitution:1'])[0].double_value
    cases = [
        (dict(sphere_youngs_modulus=-1.0), 'sphere_youngs_modulus'),
        (dict(plate_youngs_modulus=float('nan')), 'plate_youngs_modulus'),
        (dict(sphere_poisson_ratio=0.5),
         'sphere_poisson_ratio = 0.5 is out of range: allowed -1 < sphere_poisson_ratio < 0.5'),
        (dict(plate_material='unobtainium'),
         "plate_material = 'unobtainium' is unknown: allowed one of"),
        (dict(contact_law='bouncy'), "contact_law = 'bouncy' is unknown: allowed one of"),
        (dict(contact_law='linear'), 'Hertz stiffness needs n = 1.5'),
        # rclpy's own range check (-1e5..1e5, the engine's) refuses NaN before the node does
        (dict(initial_velocity=float('nan')), 'initial_velocity out of range Min: -100000.0'),
        (dict(damping_factor=float('inf')), 'damping_factor = inf is not finite'),
        (dict(sphere_radius=0.0), 'sphere_radius = 0.0 is out of range: allowed 0 < sphere_radius'),
        (dict(gravity=-9.81), 'gravity'),
        (dict(stiffness=5e4), 'allowed stiffness >= 9.2'),  # the sphere would sink below R
        (dict(damping=1e30), 'damping = 1e+30 is too large for this drop'),   # a creep for ever
        (dict(drag_coefficient=-0.5), 'drag_coefficient'),
        (dict(sphere_mass=1e-300), 'or sphere_mass = 0 for the mass from sphere density'),
        (dict(publish_rate=50.0), 'read-only'),
        (dict(frame_id='world'), 'read-only'),
        (dict(gravity=10), 'type'),
    ]
    for values, reason in cases:
        (result,) = client.set_parameters(NODE, **values)
        assert not result.successful, values
        assert reason in result.reason, (values, result.reason)
        assert next(iter(values)) in result.reason or 'type' in reason, result.reason
    # a contact change acts on the running drop at once: it must suit that drop too
    (result,) = client.set_parameters(NODE, atomically=True, stiffness=5e4, initial_height=0.01)
    assert not result.successful and 'the running drop (until ~/reset) refuses it: stiffness = 5e+04' in result.reason
    # an atomic change with one bad value changes nothing at all
    (result,) = client.set_parameters(NODE, atomically=True, sphere_material='custom',
                                      sphere_youngs_modulus=-5.0)
    assert not result.successful and 'sphere_youngs_modulus' in result.reason
    assert client.get_parameters(NODE, names) == before
    assert client.query(['restitution:1'])[0].double_value == answer_before
    n = client.count(f'{NODE}/pose')
    client.spin_until(lambda: client.count(f'{NODE}/pose') >= n + 20, 'the node to keep publishing')
    assert sim.popen.poll() is None


def test_accepted_changes_take_effect(sim, client):
    contact, mass = default_contact_and_mass()
    steel_iron = client.query(['restitution:1'])[0].double_value
    assert steel_iron == pytest.approx(cs.simulate_impact(contact, mass, 1.0).restitution, rel=1e-6)
    try:
        (result,) = client.set_parameters(NODE, plate_material='brass')
        assert result.successful, result.reason
        brass = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'brass', 0.0127,
                                          damping_factor=8.87e5)
        (value,) = client.query(['restitution:1'])
        assert value.double_value == pytest.approx(
            cs.simulate_impact(brass, mass, 1.0).restitution, rel=1e-6)
        # an override, then the paper's contact: k = 1e10, lambda = 1e5 with m = 66 g
        (result,) = client.set_parameters(NODE, atomically=True, stiffness=1e10, damping=1e5,
                                          sphere_mass=0.066)
        assert result.successful, result.reason
        paper = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
        (value,) = client.query(['peak_force:4.47'])
        assert value.double_value == pytest.approx(
            cs.simulate_impact(paper, 0.066, 4.47).peak_force, rel=1e-6)
    finally:
        (result,) = client.set_parameters(NODE, atomically=True, plate_material='cast_iron',
                                          stiffness=0.0, damping=0.0, sphere_mass=0.0)
        assert result.successful, result.reason
    assert client.query(['restitution:1'])[0].double_value == steel_iron


def _by_stamp(client, key, value):
    return {stamp_ns(m.header.stamp): value(m) for m in client.messages[f'{NODE}/{key}']}


def test_the_vibrating_table_moves_the_plate_at_once_and_stops(sim, client):
    # Gamma = 0.4: the resting ball is carried (a bouncing one would flood this Python client
    # with contact samples on a loaded machine)
    a, f = 0.001, 10.0
    plate_pose = f'{NODE}/plate_pose'
    try:
        (result,) = client.set_parameters(NODE, initial_height=0.0)   # the ball at rest
        assert result.successful, result.reason
        reset(client)
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=a,
                                          plate_frequency=f)
        assert result.successful, result.reason
        start = client.count(plate_pose)
        client.spin_until(lambda: client.count(plate_pose) >= start + 60, '60 plate poses')
        since = stamp_ns(client.messages[plate_pose][start].header.stamp)
        last = stamp_ns(client.messages[plate_pose][-1].header.stamp)
        for key in ('pose', 'twist', 'plate_twist'):     # the state topics: one per tick
            client.spin_until(lambda key=key: max(_by_stamp(client, key, lambda m: 0)) >= last,
                              f'~/{key} up to the last plate pose')
        # after the bridge (one period, 0.1 s): the table's motion
        bridged = since + 150_000_000
        plate = {ns: z for ns, z in _by_stamp(client, 'plate_pose',
                                              lambda m: m.pose.position.z).items()
                 if bridged <= ns <= last}
        plate_v = {ns: v for ns, v in _by_stamp(client, 'plate_twist',
                                                lambda m: m.twist.linear.z).items()
                   if bridged <= ns <= last}
        zs, vs = list(plate.values()), list(plate_v.values())
        assert len(zs) > 40 and len(vs) > 40
        assert max(zs) > 0.5 * a and min(zs) < -0.5 * a
        assert max(map(abs, zs)) <= a * (1 + 1e-9)
        assert max(map(abs, vs)) <= a * 2 * math.pi * f * (1 + 1e-9)
        # ~/pose and ~/twist are absolute, p + R1 - z and pdot - zdot: the carried ball moves
        # with the plate (z ~ 1.5e-7 m, its rate ~ 1e-6 m/s), 1 mm up and down
        pose = _by_stamp(client, 'pose', lambda m: m.pose.position.z)
        twist = _by_stamp(client, 'twist', lambda m: m.twist.linear.z)
        assert all(pose[ns] == pytest.approx(z + 0.0127, abs=1e-6) for ns, z in plate.items())
        assert all(twist[ns] == pytest.approx(v, abs=1e-4) for ns, v in plate_v.items())
        assert max(pose[ns] for ns in plate) - min(pose[ns] for ns in plate) > a

        # the reaction on the plate at every contact sample: -F (the sample topics may lag far
        # behind on a loaded machine: the stamps both have)
        def both():
            wrench = _by_stamp(client, 'wrench', lambda m: m.wrench.force.z)
            reaction = _by_stamp(client, 'plate_wrench', lambda m: m.wrench.force.z)
            return {ns: (wrench[ns], reaction[ns]) for ns in wrench.keys() & reaction.keys()
                    if since <= ns}
        client.spin_until(lambda: len(both()) >= 20, '20 samples on ~/wrench and ~/plate_wrench',
                          3 * TIMEOUT)
        assert all(reaction == -force and force > 0.0 for force, reaction in both().values())
        # refused, naming the parameter and its range; the table goes on
        for values, reason in [
                (dict(plate_amplitude=float('nan')), 'plate_amplitude'),
                (dict(plate_amplitude=-0.001), 'plate_amplitude'),
                (dict(plate_phase=7.0), 'plate_phase'),
                (dict(plate_frequency=200.0),
                 'plate_amplitude = 0.001 m at plate_frequency = 200 Hz shakes the plate at'),
                (dict(plate_amplitude=0.2), 'plate_amplitude'),
                (dict(plate_frequency=float('inf')), 'plate_frequency')]:
            (result,) = client.set_parameters(NODE, **values)
            assert not result.successful and reason in result.reason, (values, result.reason)
        assert client.get_parameters(NODE, ['plate_amplitude', 'plate_frequency']) == {
            'plate_amplitude': a, 'plate_frequency': f}
    finally:
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=0.0,
                                          plate_frequency=0.0, initial_height=1.0)
        assert result.successful, result.reason
    # stopped: bridged to rest at p = 0 (within one period; the client may lag behind)
    client.spin_until(lambda: client.messages[plate_pose][-1].pose.position.z == 0.0
                      and client.messages[f'{NODE}/plate_twist'][-1].twist.linear.z == 0.0,
                      'the plate at rest at 0')
    assert sim.popen.poll() is None


# The README's command, typed for the ros2 CLI (YAML 1.1), filled in as `ros2 topic pub` does
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


def test_the_readme_plate_commands_parse_as_yaml_and_drive_the_plate():
    """The README's `ros2 topic pub` lines: YAML 1.1 (yaml.safe_load, as the ros2 CLI reads it),
    the message's own fields, and accepted by the node's translation and the core's rules."""
    from trajectory_msgs.msg import JointTrajectory

    from contact_sim.drop.plate import command_motion
    from contact_sim.ros.node import read_plate_command
    lines = re.findall(r'ros2 topic pub --once (\S+) (\S+) "(.*)"', _readme())
    assert len(lines) >= 2 and PLATE_COMMAND_YAML in [text for _, _, text in lines]
    for topic, type_name, text in lines:
        assert topic == f'{NODE}/plate_command'
        assert type_name == 'trajectory_msgs/msg/JointTrajectory'
        msg = fill_message(JointTrajectory(), yaml.safe_load(text))
        times, positions, velocities = read_plate_command(msg, 2.0, 0.0)
        command = command_motion(2.0, 0.0, 0.0, times, positions, velocities)
        assert command.dropped == 0 and command.motion is not None
        assert command.motion.state(times[-1])[0] == pytest.approx(positions[-1])


def _rosout_has(client, text):
    return any(text in m.msg for m in client.rosout)


def test_plate_command_moves_the_plate_and_reset_clears_it(sim, client):
    from trajectory_msgs.msg import JointTrajectory
    pub = client.node.create_publisher(JointTrajectory, f'{NODE}/plate_command', 10)
    client.spin_until(lambda: pub.get_subscription_count() > 0, 'the node to subscribe')
    plate_pose, plate_twist = f'{NODE}/plate_pose', f'{NODE}/plate_twist'
    command = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))

    def at(height):
        poses, twists = client.messages[plate_pose], client.messages[plate_twist]
        return (poses and poses[-1].pose.position.z == pytest.approx(height, abs=1e-12)
                and twists and twists[-1].twist.linear.z == pytest.approx(0.0, abs=1e-12))

    try:
        deadline = time.monotonic() + TIMEOUT
        while not at(0.01):     # (a repeated command starts again from where the plate is)
            pub.publish(command)
            client.spin_until(lambda: at(0.01) or time.monotonic() > deadline, 'the plate',
                              TIMEOUT + 5.0)
            assert time.monotonic() <= deadline, 'the plate never reached 1 cm'
        n = client.count(plate_pose)
        client.spin_until(lambda: client.count(plate_pose) >= n + 20, '20 more plate poses')
        assert at(0.01)         # and stays there: the command has ended, the plate rests
        # refusals: a warning naming the field; the plate stays where it is
        bad = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))
        bad.joint_names = ['paddle']
        pub.publish(bad)
        client.spin_until(lambda: _rosout_has(client, "joint_names = ['paddle'] is invalid: "
                                              "allowed ['plate_z']"), 'the refusal')
        bad = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))
        bad.points[0].positions = [5.0]
        pub.publish(bad)
        client.spin_until(lambda: _rosout_has(client, 'points[].positions reaches |positions| = 5 '
                                              'm: allowed -1 <= points[].positions <= 1 m'),
                          'the position refusal')
        past = fill_message(JointTrajectory(), yaml.safe_load(PLATE_COMMAND_YAML))
        past.header.stamp.nanosec = 1   # stamped 1 ns of simulated time, the point then: past
        past.points[0].time_from_start.sec = 0
        pub.publish(past)
        client.spin_until(lambda: _rosout_has(client, 'no point after now'), 'the ignored one')
        assert at(0.01)
        # refused while the table runs
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=0.0005,
                                          plate_frequency=10.0)
        assert result.successful, result.reason
        pub.publish(command)
        client.spin_until(lambda: _rosout_has(client, 'refused: the vibrating table runs '
                                              '(plate_amplitude = 0.0005, plate_frequency = 10 '
                                              '> 0)'), 'the refusal')
    finally:
        (result,) = client.set_parameters(NODE, atomically=True, plate_amplitude=0.0,
                                          plate_frequency=0.0)
        assert result.successful, result.reason
        client.node.destroy_publisher(pub)
    t0 = reset(client)   # the new drop's plate is the table's: fixed at 0 (the command cleared)

    def after_reset():
        return [m.pose.position.z for m in client.messages[plate_pose]
                if stamp_ns(m.header.stamp) > t0]
    client.spin_until(lambda: len(after_reset()) >= 20, '20 plate poses after the reset')
    assert set(after_reset()) == {0.0}


def test_the_example_juggler_keeps_the_ball_bouncing_for_60_simulated_seconds(client, ros_env,
                                                                           workdir):
    """examples/juggler.py against a real node (its own process, named /juggled, at 3x real
    time): the ball starts at rest on the plate, is thrown, and keeps bouncing to the target."""
    import sys
    target, radius = 0.3, 0.0127
    node = Process('contact_sim_node', ['--ros-args', '-r', '__node:=juggled', '-p',
                                        'real_time_factor:=3.0', '-p', 'publish_clock:=false',
                                        '-p', 'initial_height:=0.0'], ros_env, workdir)
    log = Path(workdir) / f'juggler-{time.monotonic_ns()}.log'
    with open(log, 'w') as out:
        juggler = subprocess.Popen([sys.executable, str(ROOT / 'examples' / 'juggler.py'),
                                    '--ros-args', '-p', 'node:=/juggled', '-p',
                                    f'target_apex:={target}'], env=ros_env, stdout=out,
                                   stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                   start_new_session=True, cwd=workdir)
    poses, impacts = [], []
    subs = [client.node.create_subscription(PoseStamped, '/juggled/pose', poses.append, DEEP),
            client.node.create_subscription(Float64MultiArray, '/juggled/impact',
                                            impacts.append, DEEP)]
    try:
        n = client.node
        client.spin_until(lambda: n.count_subscribers('/juggled/pose') >= 2
                          and n.count_publishers('/juggled/plate_command') >= 1
                          and n.count_subscribers('/juggled/plate_command') >= 1
                          or node.popen.poll() is not None or juggler.poll() is not None,
                          'the juggler and the node to discover each other', 60.0)
        assert node.popen.poll() is None and juggler.poll() is None, log.read_text()
        response = client.call(Trigger, '/juggled/reset', Trigger.Request())
        assert response.success, response.message
        t0 = float(re.search(r'at t = ([0-9.]+) s', response.message).group(1))
        end = t0 + 80.0     # the throw within 20 s (discovery), then 60 s of bouncing

        def reached():
            return poses and stamp_s(poses[-1].header.stamp) >= end
        client.spin_until(lambda: reached() or juggler.poll() is not None, '80 simulated s',
                          240.0)
        assert juggler.poll() is None, log.read_text()
    finally:
        for sub in subs:
            client.node.destroy_subscription(sub)
        if juggler.poll() is None:
            os.killpg(juggler.pid, signal.SIGINT)
            juggler.wait(TIMEOUT)
        assert_clean_exit(node)
    assert 'Traceback' not in log.read_text(), log.read_text()
    records = [dict(zip(FIELDS, m.data)) for m in impacts if m.data[0] >= t0]
    bounces = [r for r in records if r['impact_speed'] > 0.5]
    assert bounces and bounces[0]['time'] < t0 + 20.0, records[:5]     # thrown from rest
    first = bounces[0]['time']
    end = first + 60.0
    bounces = [r for r in bounces if r['time'] <= end]
    # impacts keep arriving through the whole window, never a permanent contact after the throw
    assert not [r for r in records if first <= r['time'] <= end
                and math.isinf(r['contact_duration'])]
    times = [first] + [r['time'] for r in bounces] + [end]
    assert max(b - a for a, b in zip(times, times[1:])) < 2.0, times
    assert len(bounces) > 60
    # the apex of each flight after the first 10 s: near the target
    heights = [(stamp_s(p.header.stamp), p.pose.position.z - radius) for p in poses]
    apexes = []
    for a, b in zip(times[1:], times[2:-1]):
        flight = [y for t, y in heights if a < t < b]
        if a > first + 10.0 and flight:
            apexes.append(max(flight))
    assert len(apexes) > 50
    assert float(np.median(apexes)) == pytest.approx(target, rel=0.05), apexes
    assert np.mean(np.abs(np.array(apexes) - target) < 0.1 * target) > 0.8, apexes


def test_every_tick_is_published_on_the_real_time_factors_grid(sim, client):
    """In real time ticks are real_time_factor/publish_rate s of simulated time apart, and every
    tick reaches every state topic (the node skips ticks only when real time cannot be held, and
    then says so in its log). (As fast as possible, ticks are 1/publish_rate s apart: the
    recorded flat-out test checks every sample of every topic; this module's Python client is
    too slow a reader for a flat-out run.)"""
    pose = f'{NODE}/pose'
    factor, step_ns = 2.0, 20_000_000
    try:
        (result,) = client.set_parameters(NODE, real_time_factor=factor)
        assert result.successful, result.reason
        t0 = reset(client)   # the new grid starts here
        start = client.count(pose)

        def after_reset():
            return np.array([ns for ns in (stamp_ns(m.header.stamp)
                                           for m in client.messages[pose][start:]) if ns > t0])
        client.spin_until(lambda: len(after_reset()) >= 300, '300 poses after the reset',
                          timeout=2 * TIMEOUT)
        after = after_reset()
        assert np.all((after - t0) % step_ns == 0)  # on the grid
        if 'cannot be held' not in sim.output():
            assert np.all(np.diff(after) == step_ns)  # no tick left out
        for topic in (f'{NODE}/twist', '/clock'):
            def stamps_of(topic=topic):
                return {stamp_ns(m.clock if topic == '/clock' else m.header.stamp)
                        for m in client.messages[topic]}
            client.spin_until(lambda: max(stamps_of() | {0}) >= after[-1], f'{topic}')
            assert set(after.tolist()) <= stamps_of(), topic  # every tick on every topic
        assert client.query(['1'])[0].type == ParameterType.PARAMETER_DOUBLE  # serving
    finally:
        (result,) = client.set_parameters(NODE, real_time_factor=1.0)
        assert result.successful, result.reason


def test_recorder_writes_a_bag_that_reads_back(sim, client, ros_env, workdir):
    from rosbags.highlevel import AnyReader
    bag = workdir / 'recorded'
    recorder = Process('contact_sim_record', ['-o', str(bag), '--ros-args', '--log-level',
                                              'contact_sim_record:=debug'], ros_env, workdir)
    timed = Process('contact_sim_record', ['-o', str(workdir / 'timed'), '-s', 'sqlite3',
                                           '--duration', '4'], ros_env, workdir)
    try:
        def receiving():  # the recorder logs matches and the first message on each topic
            out = recorder.output()
            return all(f'matched {t}' in out and (t.endswith('impact') or f'receiving {t}' in out)
                       for t in TOPICS) or recorder.popen.poll() is not None
        client.spin_until(receiving, 'the recorder to receive')
        assert recorder.popen.poll() is None, recorder.output()
        t0 = reset(client)
        client.spin_until(lambda: len(impacts_after(client, t0)) >= 3, 'three impacts')
        n = client.count(f'{NODE}/pose')
        client.spin_until(lambda: client.count(f'{NODE}/pose') >= n + 10, 'ten more poses')

        def recorded_impacts():  # the recorder may lag behind this client: wait for it too
            times = re.findall(r'recorded the impact at t = ([0-9.]+) s', recorder.output())
            return sum(cs_msgs.to_ns(float(t)) >= t0 for t in times)
        client.spin_until(lambda: recorded_impacts() >= 3, 'the recorder to record 3 impacts')
    finally:
        assert_clean_exit(recorder)
    assert (bag / 'metadata.yaml').is_file() and list(bag.glob('*.mcap'))
    with AnyReader([bag]) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        assert types == TYPE_NAMES
        recorded = {topic: [] for topic in TOPICS}
        for connection, timestamp, raw in reader.messages():
            msg = reader.deserialize(raw, connection.msgtype)
            recorded[connection.topic].append((timestamp, msg))
        counts = {c.topic: c.msgcount for c in reader.connections}
    for topic, items in recorded.items():
        assert counts[topic] == len(items) > 0, topic
    # same messages as the client got, over the window both were surely listening
    for topic, items in recorded.items():
        if topic.endswith('impact'):
            bag_ns = [cs_msgs.to_ns(m.data[0]) for _, m in items]
            got = [cs_msgs.to_ns(m.data[0]) for m in client.messages[topic]]
        elif topic == '/clock':
            bag_ns = [stamp_ns(m.clock) for _, m in items]
            got = [stamp_ns(m.clock) for m in client.messages[topic]]
        else:
            bag_ns = [stamp_ns(m.header.stamp) for _, m in items]
            got = [stamp_ns(m.header.stamp) for m in client.messages[topic]]
        assert [ts for ts, _ in items] == bag_ns  # bag time = simulated time
        end = min(bag_ns[-1], got[-1])
        window = [ns for ns in got if t0 <= ns <= end]
        assert [ns for ns in bag_ns if t0 <= ns <= end] == window, topic
        if topic.endswith('impact'):
            assert len(window) >= 3
    # --duration stops by itself; an sqlite3 bag reads back too
    assert timed.popen.wait(TIMEOUT) == 0, timed.output()
    assert list((workdir / 'timed').glob('*.db3'))
    with AnyReader([workdir / 'timed']) as reader:
        # (what it got depends on how much of its 4 s discovery took)
        assert {c.topic: c.msgtype for c in reader.connections}.items() <= TYPE_NAMES.items()
        assert all(len(raw) > 0 for _, _, raw in reader.messages())
    # the stop is a consistent cut: every recorded impact has its whole wrench trace, peak
    # included, and every continuous topic reaches the end of the last recorded contact
    log = recorder.output()
    assert 'stopped before' not in log, log
    wrench = np.array([(ts, m.wrench.force.z) for ts, m in recorded[f'{NODE}/wrench']])
    impacts = [dict(zip(FIELDS, m.data)) for _, m in recorded[f'{NODE}/impact']
               if math.isfinite(m.data[4])]  # (not the final, permanent contact)
    ends = [cs_msgs.to_ns(i['time'] + i['contact_duration']) for i in impacts]
    assert sum(cs_msgs.to_ns(i['time']) >= t0 for i in impacts) >= 3
    for impact, end in zip(impacts, ends):
        start = cs_msgs.to_ns(impact['time'])
        if start < wrench[0, 0]:
            continue  # it began before the recorder got its first wrench
        inside = (wrench[:, 0] >= start) & (wrench[:, 0] <= end + 2)
        assert inside.any() and wrench[inside, 1].max() == pytest.approx(
            impact['peak_force'], rel=1e-12), (impact, log)
    for topic, items in recorded.items():
        if not topic.endswith('impact'):
            assert items[-1][0] >= max(ends), (topic, log)


def test_a_stopping_recorder_keeps_pacing_the_node_until_it_is_gone(tmp_path):
    """At the stop the acknowledgement stands still but its publisher stays: a node running as
    fast as possible stays within LEAD_TICKS of it while the lagging topics drain (let loose, it
    outran its writers' histories and the drain lost samples)."""
    context = rclpy.Context()
    context.init()
    recorder = cs_recorder.Recorder(tmp_path / 'bag', context=context)
    probe = rclpy.create_node('probe', context=context)
    acks = []
    probe.create_subscription(Clock, f'{NODE}/recorded',
                              lambda m: acks.append(stamp_ns(m.clock)), cs_msgs.PROGRESS.qos)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(probe)
    try:
        def deliver(ns):
            for topic in recorder.topics:
                key = topic.rsplit('/', 1)[-1]
                if key in ('pose', 'twist', 'clock'):
                    msg = (cs_msgs.clock_msg(ns) if key == 'clock' else
                           cs_msgs.pose_msg(ns, 0.01, 0.0, 'plate') if key == 'pose' else
                           cs_msgs.twist_msg(ns, 0.0, 'plate'))
                    recorder._on_message(topic, cs_msgs.type_name(type(msg)),
                                         serialize_message(msg))
        deliver(1_000_000_000)
        deadline = time.monotonic() + TIMEOUT
        while not acks and time.monotonic() < deadline:
            recorder.report()
            executor.spin_once(timeout_sec=0.05)
        assert acks == [1_000_000_000]
        for topic in recorder.topics:
            recorder.publishers_matched[topic] = 1
        done = recorder.cut()
        assert not done()   # the other topics lag
        assert probe.count_publishers(f'{NODE}/recorded') == 1   # still pacing the node
        deliver(2_000_000_000)
        recorder.report()
        executor.spin_once(timeout_sec=0.2)
        assert acks == [1_000_000_000]     # it stands still while stopping
    finally:
        probe.destroy_node()
        recorder.close()
        recorder.destroy_node()
        context.try_shutdown()


def test_recorder_stops_on_a_consistent_cut(tmp_path):
    """The stop waits until every continuous topic with a publisher reaches the furthest
    simulated time any topic shows, an impact counting to the end of its contact."""
    context = rclpy.Context()
    context.init()
    recorder = cs_recorder.Recorder(tmp_path / 'bag', context=context)
    try:
        topics = recorder.topics
        wrench, contact, pose = (f'{NODE}/{name}' for name in ('wrench', 'contact', 'pose'))
        impact = f'{NODE}/impact'
        for topic in topics:
            recorder.publishers_matched[topic] = 1
        assert recorder.cut()()  # nothing recorded yet: nothing to wait for
        # /clock is global (any node may publish it): it neither sets the cut nor is waited for
        clock = cs_msgs.clock_msg(5_000_000_000)
        recorder._on_message('/clock', cs_msgs.type_name(type(clock)), serialize_message(clock))
        assert recorder.cut()() and recorder.cut_ns is None
        record = cs.ImpactRecord(time=1.0, impact_speed=1.0, rebound_speed=0.5, restitution=0.5,
                                 contact_duration=2e-4, peak_force=10.0, max_penetration=1e-6)
        messages = [(wrench, cs_msgs.wrench_msg(1_000_000_000, 0.0, 'plate')),
                    (contact, cs_msgs.contact_msg(1_000_100_000, 1e-7, 1.0, 5.0, 'plate')),
                    (impact, cs_msgs.impact_msg(record, 0.0))]
        for topic, msg in messages:
            recorder._on_message(topic, cs_msgs.type_name(type(msg)), serialize_message(msg))
        assert recorder.covered_ns[impact] == 1_000_200_000  # the end of the contact
        done = recorder.cut()
        assert recorder.cut_ns == 1_000_200_000
        assert sorted(recorder.lagging()) == sorted(t for t in topics
                                                    if t not in (impact, '/clock'))
        assert not done()
        for topic, msg in [(wrench, cs_msgs.wrench_msg(1_000_200_000, 0.0, 'plate')),
                           (contact, cs_msgs.contact_msg(1_000_300_000, 0.0, 0.0, 0.0, 'plate')),
                           (pose, cs_msgs.pose_msg(1_000_300_000, 0.01, 0.0, 'plate')),
                           (f'{NODE}/plate_wrench', cs_msgs.plate_wrench_msg(1_000_200_000, 0.0,
                                                                             'plate')),
                           (f'{NODE}/plate_pose', cs_msgs.plate_pose_msg(1_000_300_000, 0.0,
                                                                         'plate')),
                           (f'{NODE}/plate_twist', cs_msgs.plate_twist_msg(1_000_300_000, 0.0,
                                                                           'plate'))]:
            recorder._on_message(topic, cs_msgs.type_name(type(msg)), serialize_message(msg))
        assert recorder.lagging() == [f'{NODE}/twist'] and not done()
        msg = cs_msgs.twist_msg(1_000_250_000, 0.0, 'plate')
        recorder._on_message(f'{NODE}/twist', cs_msgs.type_name(type(msg)), serialize_message(msg))
        assert done()
        # an impact that arrives while stopping and began before the cut moves the cut on to
        # the end of its contact; one that began after the cut is not recorded
        count = recorder.bag.counts[impact]
        late = cs_msgs.impact_msg(cs.ImpactRecord(1.0001, 0.5, 0.25, 0.5, 3e-4, 5.0, 1e-7), 0.0)
        after = cs_msgs.impact_msg(cs.ImpactRecord(1.5, 0.5, 0.25, 0.5, 3e-4, 5.0, 1e-7), 0.0)
        for msg in (late, after):
            recorder._on_message(impact, cs_msgs.type_name(type(msg)), serialize_message(msg))
        assert recorder.cut_ns == 1_000_400_000 and not done()
        assert recorder.bag.counts[impact] == count + 1
        # garbage on ~/impact from another publisher cannot overflow a bag timestamp
        for data in ([1e300, 0, 0, 0, 1e300], [float('nan')] * 7, [-5.0, 0, 0, 0, -1.0]):
            junk = Float64MultiArray(data=data)
            assert 0 <= cs_msgs.covered_time_ns(junk) <= 2 ** 63 - 1
            assert 0 <= cs_msgs.message_time_ns(junk) <= cs_msgs.covered_time_ns(junk)
        permanent = cs_msgs.impact_msg(
            cs.ImpactRecord(2.0, 0.1, 0.0, 0.0, math.inf, 1.0, 1e-7), 0.0)
        assert cs_msgs.covered_time_ns(permanent) == 2_000_000_000
    finally:
        recorder.close()
        recorder.destroy_node()
        context.try_shutdown()


def test_the_stop_drain_ends_when_done_on_timeout_or_on_a_signal():
    context = rclpy.Context()
    context.init()
    node = rclpy.create_node('drain_test', context=context)
    handler = signal.getsignal(signal.SIGINT)
    try:
        calls = []

        def done_after_three():
            calls.append(1)
            return len(calls) > 3
        assert cs_recorder.spin_until_signal(node, stop_after=0.0, drain=lambda: done_after_three)
        assert len(calls) == 4
        start = time.monotonic()
        assert not cs_recorder.spin_until_signal(node, stop_after=0.0, drain=lambda: lambda: False,
                                             drain_timeout=0.3)
        assert time.monotonic() - start >= 0.3
        # Ctrl-C while draining (here after a --duration stop) ends the wait at once
        start = time.monotonic()
        assert not cs_recorder.spin_until_signal(
            node, stop_after=0.0, drain=lambda: lambda: os.kill(os.getpid(), signal.SIGINT),
            drain_timeout=30.0)  # (not drained: the caller warns)
        assert time.monotonic() - start < 10.0
        assert signal.getsignal(signal.SIGINT) is handler  # restored
    finally:
        node.destroy_node()
        context.try_shutdown()


def _yaml_parameters(path):
    data = yaml.safe_load(path.read_text())
    (section,) = data.values()
    return section['ros__parameters']


def test_default_yaml_equals_the_built_in_defaults():
    values = _yaml_parameters(CONFIG / 'default.yaml')
    assert values == cs_params.DEFAULTS
    for path in sorted(CONFIG.glob('*.yaml')):
        values = {**cs_params.DEFAULTS, **_yaml_parameters(path)}
        assert set(values) == set(cs_params.DEFAULTS), path.name  # no unknown keys
        cs_params.build_model(values)  # valid


def test_every_config_file_loads_with_params_file(client, ros_env, workdir):
    files = sorted(CONFIG.glob('*.yaml'))
    assert len(files) >= 8
    processes = {}
    try:
        for path in files:
            name = 'cfg_' + path.stem
            processes[name] = (path, Process('contact_sim_node', [
                '--ros-args', '-r', f'__node:={name}', '--params-file', str(path),
                '-p', 'publish_clock:=false', '-p', 'publish_rate:=10.0'], ros_env, workdir))
        for name, (path, process) in processes.items():
            expected = {**_yaml_parameters(path), 'publish_clock': False, 'publish_rate': 10.0}
            got = client.get_parameters(f'/{name}', list(expected))
            assert got == expected, path.name
            assert 'ignoring unknown parameters' not in process.output()
        # the paper's drop experiment: k = 1e10, lambda = 1e5, m = 66 g
        paper = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
        (value,) = client.query(['restitution:4.47'], node='/cfg_paper_drop')
        assert value.double_value == pytest.approx(
            cs.simulate_impact(paper, 0.066, 4.47).restitution, rel=1e-6)
    finally:
        for _, process in processes.values():
            assert_clean_exit(process)


def test_invalid_startup_parameters_exit_with_a_reason(ros_env, workdir):
    cases = {'contact_law:=bouncy': "contact_law = 'bouncy' is unknown",
             'sphere_poisson_ratio:=0.7': 'sphere_poisson_ratio',
             'sphere_material:=unobtainium': "sphere_material = 'unobtainium' is unknown"}
    processes = {arg: Process('contact_sim_node', ['--ros-args', '-p', arg], ros_env, workdir)
                 for arg in cases}
    for arg, process in processes.items():
        try:
            code = process.popen.wait(TIMEOUT)
        except subprocess.TimeoutExpired:
            process.stop()
            pytest.fail(f'{arg}: the node kept running')
        output = process.output()
        assert code == 2, output
        assert 'Traceback' not in output and cases[arg] in output, output


@pytest.mark.parametrize('path', sorted(CONFIG.glob('*.yaml')), ids=lambda p: p.stem)
def test_every_preset_simulates_to_rest_without_error(path):
    model = cs_params.build_model({**cs_params.DEFAULTS, **_yaml_parameters(path)})
    sim = cs_params.make_simulation(model)
    for t in np.arange(0.5, 10.01, 0.5):
        while sim.time < t:
            sim.advance(t, max_steps=20000)
        state = sim.state
        assert all(math.isfinite(v) for v in (state.penetration, state.penetration_rate,
                                              state.force))
    assert math.isfinite(sim.settle_time), path.name


def test_a_contact_too_soft_for_the_drop_is_rejected_at_the_exact_bound():
    """k below (n+1)(m v1²/2 + m g R)/R^(n+1) lets the undamped sphere sink deeper than its
    radius R: such a value is rejected with the bound, and the bound is where the depth is R."""
    values = {**cs_params.DEFAULTS, 'stiffness': 5e4}
    with pytest.raises(ValueError) as error:
        cs_params.build_model(values)
    match = re.search(r'allowed stiffness >= ([0-9.e+]+) N/m\^1.5 or initial_height <= '
                      r'([0-9.e+]+) m', str(error.value))
    assert match and str(error.value).startswith('stiffness = 5e+04'), error.value
    minimum, highest = float(match.group(1)), float(match.group(2))
    model = cs_params.build_model({**values, 'stiffness': minimum * 1.001})
    cs_params.build_model({**values, 'initial_height': highest * 0.999})  # accepted
    radius = model.radius

    def first_depth(stiffness, height=model.height):
        undamped = cs.Contact(model.contact.law, stiffness, 0.0)
        sim = cs.DropSimulation(undamped, model.mass, height, gravity=model.gravity)
        while not sim.advance(sim.time + 0.1).impacts:
            pass
        return sim.impacts[0].max_penetration

    assert first_depth(minimum * 1.01) < radius < first_depth(minimum * 0.99)
    assert first_depth(5e4, highest * 0.99) < radius < first_depth(5e4, highest * 1.01)
    # the Hertz stiffness of soft custom materials is checked the same way
    soft = {**cs_params.DEFAULTS, 'sphere_material': 'custom', 'sphere_youngs_modulus': 1e3}
    with pytest.raises(ValueError, match=r'^stiffness = 165.1 N/m\^1.5 is too small for this '
                                         r'drop: .*\(stiffness = 0: k is the Hertz stiffness'):
        cs_params.build_model(soft)
    # no drop (no gravity, no speed), no bound
    cs_params.build_model({**values, 'stiffness': 1e-300, 'gravity': 0.0, 'initial_velocity': 0.0})


def test_the_depth_check_skips_a_sphere_that_never_lands_and_guards_the_running_drop():
    values = {**cs_params.DEFAULTS, 'stiffness': 1.0, 'damping': 0.0}
    soft = cs_params.Model(**{**vars(cs_params.build_model(cs_params.DEFAULTS)),
                              'contact': cs.Contact(cs.AZAD_FEATHERSTONE, 1.0, 0.0)})
    upwards = cs.DropSimulation(soft.contact, 0.067, 1.0, velocity=-1.0, gravity=0.0,
                                radius=0.0127)
    cs_params.check_running(upwards, soft, values, soft)  # never lands: nothing to check
    falling = cs.DropSimulation(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 0.0), 0.067, 1.0,
                                velocity=-1.0, gravity=9.81, radius=0.0127)
    with pytest.raises(ValueError, match=r'^the running drop \(until ~/reset\) refuses it: '
                                         r'stiffness = 1 N/m\^1.5 is too small for this drop: '
                                         r'.* allowed stiffness >= '):
        cs_params.check_running(falling, soft, values, soft)
    with pytest.raises(ValueError, match='stiffness = 1 N/m'):   # as set_contact would refuse
        falling.set_contact(soft.contact)


# ------------------------------------------------------------------------------------------
# encoders, YAML
# ------------------------------------------------------------------------------------------

def test_the_cdr_encoders_give_the_message_functions_messages():
    from rclpy.serialization import deserialize_message
    ns = 12_345_678_901
    cases = {'wrench': ((ns, 42.5), cs_msgs.wrench_msg(ns, 42.5, 'plate')),
             'contact': ((ns, 1e-6, 0.25, 1.0), cs_msgs.contact_msg(ns, 1e-6, 0.25, 7.0, 'plate')),
             'pose': ((ns, 0.0127 - 1e-6), cs_msgs.pose_msg(ns, 0.0127, 1e-6, 'plate')),
             'twist': ((ns, -0.25), cs_msgs.twist_msg(ns, 0.25, 'plate')),
             'clock': ((ns,), cs_msgs.clock_msg(ns)),
             'plate_pose': ((ns, -0.002), cs_msgs.plate_pose_msg(ns, -0.002, 'plate')),
             'plate_twist': ((ns, 0.3), cs_msgs.plate_twist_msg(ns, 0.3, 'plate')),
             'plate_wrench': ((ns, -42.5), cs_msgs.plate_wrench_msg(ns, 42.5, 'plate'))}
    assert set(cases) == {t.key for t in cs_msgs.TOPICS} - {'impact'}
    # the sphere's pose and twist over a moving plate: absolute, p + R1 - z and pdot - zdot
    assert cs_msgs.pose_msg(ns, 0.0127, 1e-6, 'plate', 0.003).pose.position.z == \
        pytest.approx(0.003 + 0.0127 - 1e-6)
    assert cs_msgs.twist_msg(ns, 0.25, 'plate', 0.5).twist.linear.z == 0.25
    for key, (args, expected) in cases.items():
        topic = cs_msgs.TOPIC[key]
        data = topic.template('plate').encode(*args)
        assert deserialize_message(data, topic.msg_type) == expected, key
        assert topic.times_of_cdr(data) == (ns, ns)
    impact = cs_msgs.impact_msg(cs.ImpactRecord(1.0, 1.0, 0.5, 0.5, 2e-4, 10.0, 1e-6), 0.5)
    assert cs_msgs.TOPIC['impact'].times_of_cdr(serialize_message(impact)) == (
        1_500_000_000, 1_500_200_000)


def _readme():
    return (ROOT / 'README.md').read_text()


def test_every_readme_param_set_value_has_the_declared_type_for_the_ros2_cli():
    # `ros2 param set` reads its value with PyYAML (YAML 1.1): 5.0e5 would be a string there
    examples = re.findall(r'ros2 param set /contact_sim (\w+) (\S+)', _readme())
    assert len(examples) >= 4
    for name, text in examples:
        value = yaml.safe_load(text)
        default = cs_params.DEFAULTS[name]
        assert type(value) is type(default), (name, text, type(value))


def test_parameter_values_survive_dump_and_load(sim, client, workdir):
    """What `ros2 param dump` writes (PyYAML of every value) reads back through rclpy's own
    parser (`ros2 param load`, `--params-file`) as the same values and types; so do the presets."""
    from rclpy.parameter import parameter_dict_from_yaml_file
    names = list(cs_params.PARAMETER_NAMES)
    values = client.get_parameters(NODE, names)
    dump = workdir / 'dump.yaml'
    dump.write_text(yaml.dump({NODE: {'ros__parameters': values}}, default_flow_style=False))
    loaded = parameter_dict_from_yaml_file(str(dump), target_nodes=[NODE])
    assert {k: value_of(p.value) for k, p in loaded.items()} == values
    for name, parameter in loaded.items():
        assert type(value_of(parameter.value)) is type(cs_params.DEFAULTS[name]), name
    # loading the dump into the running node changes nothing and is accepted
    results = client.set_parameters(NODE, **{k: v for k, v in values.items()
                                             if k not in ('publish_rate', 'frame_id',
                                                          'publish_clock')})
    assert all(r.successful for r in results), [r.reason for r in results]
    for path in sorted(CONFIG.glob('*.yaml')):
        loaded = parameter_dict_from_yaml_file(str(path), use_wildcard=True)
        for name, parameter in loaded.items():
            assert type(value_of(parameter.value)) is type(cs_params.DEFAULTS[name]), (path.name, name)


def test_plate_radius_zero_is_the_flat_plate():
    flat = cs_params.build_model(dict(cs_params.DEFAULTS))
    assert math.isinf(flat.plate_radius)
    assert cs_params.build_model({**cs_params.DEFAULTS, 'plate_radius': math.inf}) == flat
    sphere = cs_params.build_model({**cs_params.DEFAULTS, 'plate_radius': 0.0127})
    assert sphere.contact.stiffness < flat.contact.stiffness  # R = R1 R2 / (R1 + R2)
    with pytest.raises(ValueError, match='plate_radius'):
        cs_params.build_model({**cs_params.DEFAULTS, 'plate_radius': -1.0})


# ------------------------------------------------------------------------------------------
# lossless and crash-safe recording (own processes, in a domain of their own)
# ------------------------------------------------------------------------------------------

@pytest.fixture(scope='module')
def own_domain(ros_env):
    """Environment and a client context in another ROS domain (no module node there)."""
    env = {**ros_env, 'ROS_DOMAIN_ID': str(120 + os.getpid() % 101)}
    context = rclpy.Context()
    context.init(domain_id=int(env['ROS_DOMAIN_ID']))
    node = rclpy.create_node('contact_sim_test_watch', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    clock = []
    node.create_subscription(Clock, '/clock', lambda m: clock.append(stamp_ns(m.clock)),
                             QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))

    def spin_until(condition, what, timeout=TIMEOUT):
        deadline = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > deadline:
                pytest.fail(f'timed out after {timeout} s waiting for {what}')
            executor.spin_once(timeout_sec=0.05)
    reset_client = node.create_client(Trigger, f'{NODE}/reset')

    def reset_drop():
        """~/reset; returns the simulated time (s) the new drop starts at, as the reply says."""
        spin_until(reset_client.service_is_ready, 'the reset service')
        while True:
            future = reset_client.call_async(Trigger.Request())
            retry = time.monotonic() + 3.0
            spin_until(lambda: future.done() or time.monotonic() > retry, 'a reset reply')
            if future.done():
                return float(re.search(r'at t = ([0-9.]+) s', future.result().message).group(1))
            reset_client.remove_pending_request(future)
    yield env, clock, spin_until, reset_drop
    node.destroy_node()
    context.try_shutdown()


def read_bag(path):
    from rosbags.highlevel import AnyReader
    out = {}
    with AnyReader([path]) as reader:
        for connection, timestamp, raw in reader.messages():
            out.setdefault(connection.topic, []).append(
                (timestamp, reader.deserialize(raw, connection.msgtype)))
    return out


def replay(ticks, offset):
    """What the node publishes in ``ticks`` ticks of the default drop flat out (100 Hz) started
    by a ~/reset at simulated time ``offset``: the same engine, tick by tick. Returns
    {topic: [stamp ns]} and {stamp ns: wrench force}."""
    model = cs_params.build_model(dict(cs_params.DEFAULTS))
    sim = cs_params.make_simulation(model)
    samples, states, impacts, last = [], [], [], cs_msgs.to_ns(offset)
    for k in range(ticks):
        advance = sim.advance(0.0 + (k + 1) * 0.01)
        points, _ = cs_msgs.contact_samples(advance.samples, offset, last)
        samples += points
        last = points[-1][0] if points else last
        states.append(cs_msgs.to_ns(offset + float(advance.samples.time[-1])))
        impacts += [cs_msgs.to_ns(r.time + offset) for r in advance.impacts]
    sample_ns = [p[0] for p in samples]
    return ({f'{NODE}/wrench': sample_ns, f'{NODE}/contact': sample_ns, f'{NODE}/pose': states,
             f'{NODE}/twist': states, '/clock': states, f'{NODE}/impact': impacts,
             f'{NODE}/plate_pose': states, f'{NODE}/plate_twist': states,
             f'{NODE}/plate_wrench': sample_ns},
            {p[0]: p[3] for p in samples})


def stamps_in_bag(topic, items):
    if topic.endswith('impact'):
        return [cs_msgs.to_ns(m.data[0]) for _, m in items]
    return [stamp_ns(m.clock if topic == '/clock' else m.header.stamp) for _, m in items]


def test_a_recorded_flat_out_run_holds_every_sample_of_every_topic(own_domain, workdir):
    """Flat out, the recorder's keep-all subscriptions and its ~/recorded acknowledgements make
    the node wait for it: from a ~/reset on, the bag holds every sample the node published (the
    same engine replayed here gives the stamps and values), for more than 60 simulated s."""
    env, clock, spin_until, reset_drop = own_domain
    bag = workdir / 'flat_out'
    recorder = Process('contact_sim_record', ['-o', str(bag)], env, workdir)
    spin_until(lambda: 'recording' in recorder.output(), 'the recorder to start')
    node = Process('contact_sim_node', ['--ros-args', '-p', 'real_time_factor:=0.0'], env,
                   workdir)
    try:
        spin_until(lambda: all(f'receiving {t}' in recorder.output() for t in TOPICS
                               if not t.endswith('impact')), 'the recorder to receive')
        # paced from here on (before, the node may run ahead of what the recorder can take)
        spin_until(lambda: 'pacing 1 node(s)' in recorder.output(), 'the node to be paced')
        offset = reset_drop()   # a drop that bounces, recorded from its start
        ticks_before = round(offset * 100)
        assert offset == pytest.approx(ticks_before * 0.01, abs=1e-9)  # on the tick grid
        offset = 0.0 + ticks_before * 0.01
        # (the node runs up to LEAD_TICKS = 3 simulated s ahead of what the recorder has)
        spin_until(lambda: clock and clock[-1] > (offset + 80) * 1e9, '80 simulated seconds',
                   timeout=300)
    finally:
        try:
            assert_clean_exit(recorder)
        finally:
            assert_clean_exit(node)
    assert 'stopped before' not in recorder.output()
    recorded = read_bag(bag)
    assert set(recorded) == set(TYPE_NAMES)
    reset_ns = cs_msgs.to_ns(offset)
    end = max(max(stamps_in_bag(t, items)) for t, items in recorded.items())
    expected, forces = replay(int(round((end - reset_ns) * 1e-7)) + 1, offset)
    assert len(expected[f'{NODE}/impact']) > 30   # the bounces are in it
    for topic, items in recorded.items():
        got = stamps_in_bag(topic, items)
        assert [ts for ts, _ in items] == got  # bag time = simulated time
        got = [ns for ns in got if ns > reset_ns]
        want = [ns for ns in expected[topic] if ns <= got[-1]]
        missing = sorted(set(want) - set(got))
        assert got == want, (topic, len(got), len(want), missing[:3], missing[-3:],
                             reset_ns, got[-1])  # every sample, in order
        if not topic.endswith('impact'):
            assert got[-1] - reset_ns >= 60e9, topic  # >= 60 simulated seconds
    # the same values, and the sample topics end together at the stop
    wrench = [m for _, m in recorded[f'{NODE}/wrench'] if stamp_ns(m.header.stamp) > reset_ns]
    # (to round-off: the node evaluates rest and flight over arrays, where numpy's SIMD exp, sin
    # and cos may differ from the C library's in the last bit on some CPUs)
    assert all(m.wrench.force.z == pytest.approx(forces[stamp_ns(m.header.stamp)], rel=1e-12,
                                                 abs=0.0) for m in wrench)
    assert recorded[f'{NODE}/wrench'][-1][0] == recorded[f'{NODE}/contact'][-1][0]


def test_a_recorder_killed_with_sigkill_loses_at_most_a_second_and_recovers(own_domain,
                                                                            workdir):
    env, clock, spin_until, _ = own_domain
    bag = workdir / 'killed'
    clock.clear()   # (from an earlier node in this domain)
    node = Process('contact_sim_node', [], env, workdir)
    recorder = Process('contact_sim_record', ['-o', str(bag)], env, workdir)
    try:
        spin_until(lambda: 'receiving /contact_sim/pose' in recorder.output(), 'recording')
        spin_until(lambda: clock and clock[-1] < 30e9, "this node's /clock")  # (not stale)
        start = clock[-1]
        spin_until(lambda: clock[-1] > start + 3e9, '3 more simulated seconds')
        os.killpg(recorder.popen.pid, signal.SIGKILL)
        killed_at = clock[-1]   # (this reader lags the node: the node had reached at least this)
        recorder.popen.wait(TIMEOUT)
        _clean_shm(recorder.started)
    finally:
        if recorder.popen.poll() is None:   # the test failed before the kill
            recorder.stop()
        assert_clean_exit(node)
    assert not (bag / 'metadata.yaml').exists()
    out = subprocess.run([executable('contact_sim_record'), '--recover', str(bag)], env=env,
                         capture_output=True, text=True, timeout=TIMEOUT)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith(f'recovered {bag}: ')
    recorded = read_bag(bag)
    poses = stamps_in_bag(f'{NODE}/pose', recorded[f'{NODE}/pose'])
    assert np.all(np.diff(poses) == 10_000_000)  # nothing missing up to the last flush
    assert poses[-1] >= killed_at - 1_000_000_000, (poses[-1], killed_at)
    # a second recovery is refused: the bag is complete
    again = subprocess.run([executable('contact_sim_record'), '--recover', str(bag)], env=env,
                           capture_output=True, text=True, timeout=TIMEOUT)
    assert again.returncode == 2 and 'metadata.yaml already' in again.stderr


@pytest.mark.parametrize('change, reason', [
    # found in review: each refusal named a core field, or a parameter the user had not set
    (dict(drag_coefficient=0.47, gravity=0.0),
     'gravity = 0.0 is out of range with air drag: .*drag_coefficient = 0 turns the air drag off'),
    (dict(sphere_radius=1e-12),
     r'sphere_mass = .* is out of range: .*\(sphere_mass = 0: the mass is \(4/3\) pi R1\^3 rho'),
    (dict(damping_factor=1e30),
     r'damping = .* is too large .*\(damping = 0: lambda = damping_factor sqrt\(R\)'),
    (dict(contact_law='linear'), "stiffness is missing: contact_law = 'linear' has n = 1"),
    (dict(plate_radius=-1.0), 'allowed 0 < plate_radius, or plate_radius = 0 for a flat plate'),
])
def test_refusals_name_the_parameter_the_user_set(change, reason):
    with pytest.raises(ValueError, match=reason):
        cs_params.build_model({**cs_params.DEFAULTS, **change})
