"""Write rosbag2 files without rosbag2, with the pure-Python ``rosbags`` library (no ROS imports).

``contact_sim_record`` (in ``contact_sim.node``) hands this module already serialized CDR messages;
anything else that has CDR bytes (``rclpy.serialization.serialize_message`` or
``rosbags``' own ``typestore.serialize_cdr``) can use it too::

    with BagWriter('run1') as bag:                       # MCAP storage, rosbag2 format version 9
        bag.write('/contact_sim/wrench', 'geometry_msgs/msg/WrenchStamped', stamp_ns, cdr)

The result is a rosbag2 directory (``metadata.yaml`` plus one ``.mcap`` or ``.db3`` file) that
``ros2 bag info``/``ros2 bag play`` and ``rosbags.highlevel.AnyReader`` read. Message definitions
and type hashes come from the ``rosbags`` type store for ROS 2 Kilted, so the message types must
be standard ones (everything the node publishes is).
"""
from pathlib import Path

from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, \
    QosTime
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

STORAGES = {'mcap': StoragePlugin.MCAP, 'sqlite3': StoragePlugin.SQLITE3}
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
        self._writer.write(connection, timestamp_ns, bytes(data))
        self.counts[topic] = self.counts.get(topic, 0) + 1

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
