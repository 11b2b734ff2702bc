"""contact_sim.ros.bag: rosbag2 files written with rosbags (no ROS needed), read back by rosbags."""
import json
from pathlib import Path
import subprocess
import sys

import pytest
import yaml

from rosbags.highlevel import AnyReader  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

from contact_sim.ros.bag import BagWriter, write_bag

TYPESTORE = get_typestore(Stores.ROS2_KILTED)
WRENCH = 'geometry_msgs/msg/WrenchStamped'
CLOCK = 'rosgraph_msgs/msg/Clock'


def wrench_cdr(ns, force):
    t = TYPESTORE.types
    msg = t[WRENCH](
        header=t['std_msgs/msg/Header'](
            stamp=t['builtin_interfaces/msg/Time'](sec=ns // 10**9, nanosec=ns % 10**9),
            frame_id='plate'),
        wrench=t['geometry_msgs/msg/Wrench'](
            force=t['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=force),
            torque=t['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=0.0)))
    return TYPESTORE.serialize_cdr(msg, WRENCH)


def clock_cdr(ns):
    t = TYPESTORE.types
    msg = t[CLOCK](clock=t['builtin_interfaces/msg/Time'](sec=ns // 10**9, nanosec=ns % 10**9))
    return TYPESTORE.serialize_cdr(msg, CLOCK)


def messages():
    for i in range(50):
        ns = 1_000_000 * i + 7
        yield '/contact_sim/wrench', WRENCH, ns, wrench_cdr(ns, 10.0 * i)
        if i % 10 == 0:
            yield '/clock', CLOCK, ns, clock_cdr(ns)


@pytest.mark.parametrize('storage, suffix', [('mcap', '.mcap'), ('sqlite3', '.db3')])
def test_written_bag_reads_back_with_types_counts_stamps_and_values(tmp_path, storage, suffix):
    path = tmp_path / 'bag'
    counts = write_bag(path, messages(), storage=storage)
    assert counts == {'/contact_sim/wrench': 50, '/clock': 5}
    assert len(list(path.glob(f'*{suffix}'))) == 1
    with AnyReader([path]) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == {
            '/contact_sim/wrench': WRENCH, '/clock': CLOCK}
        assert {c.topic: c.msgcount for c in reader.connections} == counts
        forces, stamps = [], []
        for connection, timestamp, raw in reader.messages():
            msg = reader.deserialize(raw, connection.msgtype)
            if connection.topic == '/clock':
                assert timestamp == msg.clock.sec * 10**9 + msg.clock.nanosec
                continue
            assert timestamp == msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
            assert msg.header.frame_id == 'plate'
            stamps.append(timestamp)
            forces.append(msg.wrench.force.z)
    assert forces == [10.0 * i for i in range(50)]
    assert stamps == sorted(stamps)


def test_metadata_is_what_ros2_bag_info_reads(tmp_path):
    path = tmp_path / 'bag'
    write_bag(path, messages())
    info = yaml.safe_load((path / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    assert info['version'] == 9
    assert info['storage_identifier'] == 'mcap'
    assert info['message_count'] == 55
    assert info['starting_time']['nanoseconds_since_epoch'] == 7
    assert info['duration']['nanoseconds'] == 49_000_000
    topics = {t['topic_metadata']['name']: t for t in info['topics_with_message_count']}
    wrench = topics['/contact_sim/wrench']
    assert wrench['message_count'] == 50
    assert wrench['topic_metadata']['type'] == WRENCH
    assert wrench['topic_metadata']['serialization_format'] == 'cdr'
    (qos,) = wrench['topic_metadata']['offered_qos_profiles']
    assert qos['reliability'] == 'reliable' and qos['durability'] == 'volatile'


def test_type_hashes_match_the_installed_ros_interfaces(tmp_path):
    """The bag's RIHS01 type hashes are the ones ROS 2 Kilted's own interfaces declare."""
    from ament_index_python import packages
    from rclpy import serialization
    from geometry_msgs.msg import PoseStamped, TwistStamped, Vector3Stamped, WrenchStamped
    from rosgraph_msgs.msg import Clock
    from std_msgs.msg import Float64MultiArray
    path = tmp_path / 'bag'
    with BagWriter(path) as bag:
        for i, msg_type in enumerate((PoseStamped, TwistStamped, Vector3Stamped, WrenchStamped,
                                      Clock, Float64MultiArray)):
            name = f'{msg_type.__module__.split(".")[0]}/msg/{msg_type.__name__}'
            bag.write(f'/t{i}', name, i, serialization.serialize_message(msg_type()))
    info = yaml.safe_load((path / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    assert len(info['topics_with_message_count']) == 6
    for entry in info['topics_with_message_count']:
        meta = entry['topic_metadata']
        package, _, name = meta['type'].split('/')
        share = packages.get_package_share_directory(package)
        with open(f'{share}/msg/{name}.json') as f:
            expected = json.load(f)['type_hashes'][0]
        assert expected['type_name'] == meta['type']
        assert meta['type_description_hash'] == expected['hash_string'], meta['type']


def test_cdr_from_rclpy_is_stored_verbatim_and_decodes(tmp_path):
    from rclpy import serialization
    from geometry_msgs.msg import WrenchStamped
    msg = WrenchStamped()
    msg.header.stamp.sec, msg.header.stamp.nanosec = 3, 250
    msg.header.frame_id = 'plate'
    msg.wrench.force.z = 1234.5
    data = serialization.serialize_message(msg)
    path = tmp_path / 'bag'
    write_bag(path, [('/w', WRENCH, 3_000_000_250, data)])
    with AnyReader([path]) as reader:
        ((connection, timestamp, raw),) = list(reader.messages())
        assert bytes(raw) == data
        decoded = reader.deserialize(raw, connection.msgtype)
    assert timestamp == 3_000_000_250
    assert decoded.wrench.force.z == 1234.5 and decoded.header.frame_id == 'plate'


@pytest.mark.parametrize('call, pattern', [
    (lambda p: BagWriter(p, storage='rosbag1'), r"storage = 'rosbag1' is unknown: allowed one of"),
    (lambda p: BagWriter(p).write('/x', 'my_msgs/msg/Nope', 0, b''),
     r"msgtype = 'my_msgs/msg/Nope' is unknown"),
    (lambda p: BagWriter(p).write('/c', CLOCK, -1, clock_cdr(0)),
     r'timestamp_ns = -1 is out of range: allowed 0 <= timestamp_ns'),
])
def test_bad_arguments_are_rejected_naming_the_field(tmp_path, call, pattern):
    with pytest.raises(ValueError, match=pattern):
        call(tmp_path / 'bag')


def test_an_existing_bag_is_never_overwritten(tmp_path):
    path = tmp_path / 'bag'
    write_bag(path, messages())
    before = sorted(p.name for p in path.iterdir())
    with pytest.raises(ValueError, match='exists already'):
        BagWriter(path)
    assert sorted(p.name for p in path.iterdir()) == before


def test_bag_module_imports_no_ros():
    code = ('import sys, contact_sim.ros.bag; '
            'assert not [m for m in sys.modules if m.split(".")[0] in '
            '("rclpy", "std_msgs", "geometry_msgs", "rosgraph_msgs")], "ROS imported"')
    subprocess.run([sys.executable, '-c', code], check=True)


@pytest.mark.parametrize('storage', ['mcap', 'sqlite3'])
def test_a_killed_writer_loses_only_what_came_after_its_last_flush_and_recovers(tmp_path,
                                                                               storage):
    """A writer process killed without close(): what it flushed is recovered by recover_bag,
    which writes the missing metadata, so rosbags opens the bag; what came after is lost."""
    path = tmp_path / 'bag'
    code = f'''
import os, sys
sys.path.insert(0, {str(Path(__file__).parent)!r})
from test_bag import messages
from contact_sim.ros.bag import BagWriter
bag = BagWriter({str(path)!r}, {storage!r})
items = list(messages())
for i, item in enumerate(items):
    bag.write(*item)
    if i == 29:
        bag.flush()
os._exit(9)   # killed: no close(), no metadata.yaml
'''
    assert subprocess.run([sys.executable, '-c', code]).returncode == 9
    assert not (path / 'metadata.yaml').exists()
    from contact_sim.ros.bag import recover_bag
    counts = recover_bag(path)
    flushed = list(messages())[:30]
    expected = {}
    for topic, *_ in flushed:
        expected[topic] = expected.get(topic, 0) + 1
    assert counts == expected
    with AnyReader([path]) as reader:
        got = [(c.topic, ts, bytes(raw)) for c, ts, raw in reader.messages()]
    assert sorted(got) == sorted((topic, ts, bytes(data)) for topic, _, ts, data in flushed)
    with pytest.raises(ValueError, match='metadata.yaml already'):
        recover_bag(path)


def test_recover_names_what_is_wrong(tmp_path):
    from contact_sim.ros.bag import recover_bag
    with pytest.raises(ValueError, match='not a bag directory'):
        recover_bag(tmp_path / 'missing')
    (tmp_path / 'empty').mkdir()
    with pytest.raises(ValueError, match='holds 0 storage files'):
        recover_bag(tmp_path / 'empty')
    (tmp_path / 'junk').mkdir()
    (tmp_path / 'junk' / 'junk.mcap').write_bytes(b'not an mcap file')
    with pytest.raises(ValueError, match='not an MCAP file'):
        recover_bag(tmp_path / 'junk')


def test_the_mcap_fast_path_writes_the_bytes_rosbags_writes(tmp_path, monkeypatch):
    """BagWriter writes an MCAP message itself (the recorder's hot path); the bag is the one
    rosbags' own Writer.write makes of the same messages, byte for byte, across chunks."""
    import contact_sim.ros.bag as cs_bag
    big = [(f'/t{i % 3}', WRENCH if i % 3 else CLOCK, 10**6 * (i + 1),
            wrench_cdr(10**6 * (i + 1), float(i)) if i % 3 else clock_cdr(10**6 * (i + 1)))
           for i in range(30000)]   # > 1 MiB: several chunks
    write_bag(tmp_path / 'fast' / 'bag', big)   # (the same name: the summary holds it)
    monkeypatch.setattr(cs_bag.BagWriter, '_write_mcap', lambda self, c, ns, data:
                        self._writer.write(c, ns, bytes(data)))
    write_bag(tmp_path / 'slow' / 'bag', big)
    fast = (tmp_path / 'fast' / 'bag' / 'bag.mcap').read_bytes()
    slow = (tmp_path / 'slow' / 'bag' / 'bag.mcap').read_bytes()
    assert len(fast) > 2 ** 21 and fast == slow
    fast, slow = ((tmp_path / n / 'bag' / 'metadata.yaml').read_text() for n in ('fast', 'slow'))
    assert fast == slow
    assert yaml.safe_load(fast)['rosbag2_bagfile_information']['message_count'] == 30000
