"""Write rosbag2 files without rosbag2, with the pure-Python ``rosbags`` library (no ROS imports).

``contact_sim_record`` (``contact_sim.ros.recorder``) hands this module already serialized CDR messages;
anything else that has CDR bytes (``rclpy.serialization.serialize_message`` or
``rosbags``' own ``typestore.serialize_cdr``) can use it too::

    with BagWriter('run1') as bag:                       # MCAP storage, rosbag2 format version 9
        bag.write('/contact_sim/wrench', 'geometry_msgs/msg/WrenchStamped', stamp_ns, cdr)

The result is a rosbag2 directory (``metadata.yaml`` plus one ``.mcap`` or ``.db3`` file) that
``ros2 bag info``/``ros2 bag play`` and ``rosbags.highlevel.AnyReader`` read. Message definitions
and type hashes come from the ``rosbags`` type store for ROS 2 Kilted, so the message types must
be standard ones (everything the node publishes is).

Crash safety: ``flush()`` puts everything written so far on disk (MCAP: closes the pending chunk
with its message index; sqlite3: commits), so a writer killed without ``close()`` loses only what
came after its last flush. ``recover_bag(path)`` then reads such a bag's storage file (its complete
MCAP chunks, or its committed sqlite3 rows) and rewrites it as a complete bag with
``metadata.yaml``, in the manner of ``ros2 bag reindex``.
"""
import os
import shutil
import sqlite3
import struct
from pathlib import Path

from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, \
    QosTime
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

STORAGES = {'mcap': StoragePlugin.MCAP, 'sqlite3': StoragePlugin.SQLITE3}
# An MCAP Message record's head: opcode 0x05, record length, channel id, sequence, log time,
# publish time (what rosbags' McapWriter.write writes field by field, in one pack)
_MCAP_MESSAGE = struct.Struct('<BQHIQQ')
_MCAP_CHUNK_MAX = 2 ** 20   # bytes: rosbags closes a chunk beyond this
BAG_VERSION = 9  # the rosbag2 metadata version Kilted's rosbag2 writes


def reliable_qos(depth=1000):
    """The QoS recorded as 'offered' for every topic: reliable, volatile, keep-last ``depth``.

    ``ros2 bag play`` re-publishes with the offered profile, so a replay is reliable too.
    """
    default = QosTime(sec=0, nsec=0)  # rmw's "unspecified": the middleware default (no limit)
    return Qos(history=QosHistory.KEEP_LAST, depth=depth, reliability=QosReliability.RELIABLE,
               durability=QosDurability.VOLATILE, deadline=default, lifespan=default,
               liveliness=QosLiveliness.AUTOMATIC, liveliness_lease_duration=default,
               avoid_ros_namespace_conventions=False)


class BagWriter:
    """A rosbag2 file being written: one connection per (topic, type), created on first use.

    ``path`` is the bag directory to create (it must not exist yet); ``storage`` is ``'mcap'``
    (default) or ``'sqlite3'``. Timestamps are integer nanoseconds (the recording time that
    ``ros2 bag`` shows and replays by). Close the writer (or use it as a context manager),
    otherwise ``metadata.yaml`` is not written and the bag cannot be opened.
    """

    def __init__(self, path, storage='mcap', *, typestore=None, qos_depth=1000):
        if storage not in STORAGES:
            raise ValueError(f'storage = {storage!r} is unknown: allowed one of '
                             f'{", ".join(sorted(STORAGES))}')
        self.path = Path(path)
        if self.path.exists():
            raise ValueError(f'path = {str(self.path)!r} exists already: allowed a new '
                             'directory name (a bag is never overwritten)')
        self.storage = storage
        self._typestore = typestore if typestore is not None else get_typestore(Stores.ROS2_KILTED)
        self._qos = reliable_qos(qos_depth)
        self._writer = Writer(self.path, version=BAG_VERSION, storage_plugin=STORAGES[storage])
        self._writer.open()
        self._connections = {}
        self.counts = {}
        self.closed = False

    def write(self, topic, msgtype, timestamp_ns, data):
        """Append one CDR-serialized message of type ``msgtype`` (``pkg/msg/Name``) on ``topic``."""
        connection = self._connections.get((topic, msgtype))
        if connection is None:
            if msgtype not in self._typestore.fielddefs:
                raise ValueError(f'msgtype = {msgtype!r} is unknown to the rosbags type store: '
                                 'allowed a standard ROS 2 message type such as '
                                 "'geometry_msgs/msg/WrenchStamped'")
            connection = self._writer.add_connection(topic, msgtype, typestore=self._typestore,
                                                     offered_qos_profiles=[self._qos])
            self._connections[(topic, msgtype)] = connection
        timestamp_ns = int(timestamp_ns)
        if timestamp_ns < 0:
            raise ValueError(f'timestamp_ns = {timestamp_ns} is out of range: allowed '
                             '0 <= timestamp_ns')
        if self.storage == 'mcap':
            self._write_mcap(connection, timestamp_ns, data)
        else:
            self._writer.write(connection, timestamp_ns, bytes(data))
        self.counts[topic] = self.counts.get(topic, 0) + 1

    def _write_mcap(self, connection, ns, data):
        """What ``rosbags``' ``Writer.write`` and ``McapWriter.write`` (0.11.9, uncompressed)
        do for one message, the same bytes and bookkeeping, without their per-call costs (a
        linear search of the connections, a BytesIO and five writes per record): about half
        of the recorder's time per message went there."""
        storage = self._writer.storage
        chunk = storage.chunk
        cid = connection.id
        if ns < storage.message_start_time:
            storage.message_start_time = ns
        if ns > storage.message_end_time:
            storage.message_end_time = ns
        storage.channel_stats[cid] += 1
        if ns < chunk.message_start_time:
            chunk.message_start_time = ns
        if ns > chunk.message_end_time:
            chunk.message_end_time = ns
        bio = chunk.bio
        chunk.msgs[cid].append((ns, bio.tell()))
        bio.write(_MCAP_MESSAGE.pack(0x05, 22 + len(data), cid, 0, ns, ns))
        bio.write(data)
        writer = self._writer
        writer.counts[cid] += 1
        if ns < writer.min_timestamp:
            writer.min_timestamp = ns
        if ns > writer.max_timestamp:
            writer.max_timestamp = ns
        if bio.tell() > _MCAP_CHUNK_MAX:
            storage.close_chunk()

    def flush(self):
        """Put every message written so far on disk (the OS's page cache: it survives a killed
        process). A no-op after ``close()``."""
        if self.closed:
            return
        storage = self._writer.storage
        if self.storage == 'mcap':
            if storage.chunk.bio.tell():
                storage.close_chunk()
            storage.bio.flush()
        else:
            storage.conn.commit()

    def close(self):
        """Finish the bag: flush the storage file and write ``metadata.yaml``. Idempotent."""
        if not self.closed:
            self.closed = True
            self._writer.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def write_bag(path, messages, storage='mcap'):
    """Write ``(topic, msgtype, timestamp_ns, cdr_bytes)`` items; return the counts per topic."""
    with BagWriter(path, storage) as bag:
        for topic, msgtype, timestamp_ns, data in messages:
            bag.write(topic, msgtype, timestamp_ns, data)
    return dict(bag.counts)


# --------------------------------------------------------------------------------------------
# Recovery of a bag whose writer was killed
# --------------------------------------------------------------------------------------------

_MCAP_MAGIC = b'\x89MCAP0\r\n'


def _mcap_records(data):
    """(opcode, content) of every complete record of an MCAP byte stream (a truncated tail is
    ignored)."""
    offset = 0
    while offset + 9 <= len(data):
        opcode = data[offset]
        (length,) = struct.unpack_from('<Q', data, offset + 1)
        end = offset + 9 + length
        if end > len(data):
            return
        yield opcode, data[offset + 9:end]
        offset = end


def _string(data, offset):
    (length,) = struct.unpack_from('<I', data, offset)
    return bytes(data[offset + 4:offset + 4 + length]).decode(), offset + 4 + length


def _mcap_messages(path):
    """(topic, msgtype, log_time_ns, cdr) of every message in the complete chunks of an MCAP
    file, in file order. Schemas and channels are read as they come (rosbags writes them in the
    first chunk that uses them)."""
    data = path.read_bytes()
    if not data.startswith(_MCAP_MAGIC):
        raise ValueError(f'{path} is not an MCAP file: it does not start with the MCAP magic')
    schemas, channels = {}, {}

    def visit(opcode, content):
        if opcode == 0x03:    # Schema: id u16, name, encoding, data
            (schema_id,) = struct.unpack_from('<H', content, 0)
            schemas[schema_id], _ = _string(content, 2)
        elif opcode == 0x04:  # Channel: id u16, schema_id u16, topic, ...
            channel_id, schema_id = struct.unpack_from('<HH', content, 0)
            topic, _ = _string(content, 4)
            channels[channel_id] = (topic, schemas.get(schema_id))
        elif opcode == 0x05:  # Message: channel u16, sequence u32, log_time u64, publish u64
            channel_id, _, log_time, _ = struct.unpack_from('<HIQQ', content, 0)
            topic, msgtype = channels[channel_id]
            yield topic, msgtype, log_time, bytes(content[22:])

    for opcode, content in _mcap_records(memoryview(data)[len(_MCAP_MAGIC):]):
        if opcode == 0x06:    # Chunk: start u64, end u64, size u64, crc u32, compression, records
            compression, offset = _string(content, 28)
            if compression:
                raise ValueError(f'{path}: compressed chunks ({compression}) cannot be recovered')
            (length,) = struct.unpack_from('<Q', content, offset)
            for inner in _mcap_records(content[offset + 8:offset + 8 + length]):
                yield from visit(*inner)
        else:
            yield from visit(opcode, content)


def _sqlite_messages(path):
    """(topic, msgtype, timestamp_ns, cdr) of every committed row of a rosbag2 sqlite3 file."""
    connection = sqlite3.connect(f'file:{path}?mode=ro', uri=True)
    try:
        rows = connection.execute(
            'SELECT topics.name, topics.type, messages.timestamp, messages.data FROM messages '
            'JOIN topics ON messages.topic_id = topics.id ORDER BY messages.id').fetchall()
    except sqlite3.DatabaseError as error:
        raise ValueError(f'{path} cannot be read as a rosbag2 sqlite3 file: {error}') from None
    finally:
        connection.close()
    return iter(rows)


def recover_bag(path):
    """Make a bag that a killed writer left (no ``metadata.yaml``; an MCAP file without its
    summary, or sqlite3 rows) readable again: its messages are read from the storage file and
    written again as a complete bag, which replaces it. Returns the message counts per topic.

    Raises ValueError if ``path`` is not such a bag (e.g. it has a ``metadata.yaml`` already).
    """
    path = Path(path)
    if not path.is_dir():
        raise ValueError(f'path = {str(path)!r} is not a bag directory')
    if (path / 'metadata.yaml').exists():
        raise ValueError(f'path = {str(path)!r} has a metadata.yaml already: nothing to recover')
    files = sorted(path.glob('*.mcap')) + sorted(path.glob('*.db3'))
    if len(files) != 1:
        raise ValueError(f'path = {str(path)!r} holds {len(files)} storage files: allowed one '
                         '.mcap or .db3 file')
    (source,) = files
    storage = 'mcap' if source.suffix == '.mcap' else 'sqlite3'
    messages = list(_mcap_messages(source) if storage == 'mcap' else _sqlite_messages(source))
    staging = path.with_name(path.name + '.recovering')
    if staging.exists():
        shutil.rmtree(staging)
    counts = write_bag(staging, messages, storage)
    # the new storage file takes the old one's name (rosbags names it after the directory)
    (written,) = [f for f in staging.iterdir() if f.suffix in ('.mcap', '.db3')]
    os.replace(written, source)
    text = (staging / 'metadata.yaml').read_text().replace(written.name, source.name)
    (path / 'metadata.yaml').write_text(text)
    shutil.rmtree(staging)
    for extra in path.glob(source.name + '-*'):   # sqlite3 journal of the killed writer
        extra.unlink()
    return counts
