"""Every topic of the node in one table (name, type, QoS, encoder, decoder), iterated by the node,
the recorder and the tests, and the small pure functions that turn results into messages.

Times are integer nanoseconds of simulated time. Two encoders per topic, producing identical bytes
(a test checks): the ``*_msg`` functions build rclpy message objects (readable, used by tests and
tools), and ``Topic.encode`` writes the CDR bytes directly into a per-topic template, which the
node publishes as a serialized message: the message's fixed layout is found once, from
``rclpy.serialization.serialize_message`` of a marked example, so only the stamp and the values are
packed per message (about 1 us instead of about 15 us to build and 14 us to convert an rclpy
message). Decoders (``Topic.stamp_ns``, ``Topic.covered_ns``) read the simulated time a received
message belongs to.
"""
import math
import struct
from dataclasses import dataclass

import numpy as np
from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, TwistStamped, Vector3Stamped, WrenchStamped
from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile, \
    ReliabilityPolicy
from rclpy.serialization import deserialize_message, serialize_message
from rosgraph_msgs.msg import Clock as ClockMsg
from std_msgs.msg import Float64MultiArray, MultiArrayDimension, MultiArrayLayout
from visualization_msgs.msg import MarkerArray

from contact_sim.drop import sphere_motion

IMPACT_FIELDS = ('time', 'impact_speed', 'rebound_speed', 'restitution', 'contact_duration',
                 'peak_force', 'max_penetration')


def to_ns(seconds):
    """Simulated time in s -> integer ns (the stamp's resolution)."""
    return int(round(seconds * 1e9))


def time_msg(ns):
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)


def wrench_msg(ns, force, frame_id):
    """The contact force on the sphere: +z (up, away from the plate), magnitude F >= 0 in N."""
    msg = WrenchStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    msg.wrench.force.z = float(force)
    return msg


def contact_msg(ns, penetration, penetration_rate, force, frame_id):
    """Contact state: x = penetration z (m), y = its rate zdot (m/s), z = 1 in contact (F > 0)
    else 0."""
    msg = Vector3Stamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    msg.vector.x = float(penetration)
    msg.vector.y = float(penetration_rate)
    msg.vector.z = 1.0 if force > 0.0 else 0.0
    return msg


def height_msg(ns, height, frame_id):
    """A PoseStamped at ``height`` (m) on the frame's z axis, orientation identity."""
    msg = PoseStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    msg.pose.position.z = float(height)
    msg.pose.orientation.w = 1.0
    return msg


def vertical_velocity_msg(ns, velocity, frame_id):
    """A TwistStamped moving at ``velocity`` (m/s, > 0 up) along the frame's z axis."""
    msg = TwistStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    msg.twist.linear.z = float(velocity)
    return msg


def pose_msg(ns, radius, penetration, frame_id, plate_position=0.0):
    """Sphere centre in the plate frame (the plate's surface at rest at z = 0): z = p + R1 -
    penetration (height of the undeformed centre; p = 0 for the fixed plate)."""
    return height_msg(ns, sphere_motion(radius, penetration, 0.0, plate_position)[0], frame_id)


def twist_msg(ns, penetration_rate, frame_id, plate_velocity=0.0):
    """Sphere velocity in the plate frame: linear.z = pdot - zdot (> 0 moving up; pdot = 0 for
    the fixed plate)."""
    return vertical_velocity_msg(ns, sphere_motion(0.0, 0.0, penetration_rate, 0.0,
                                                   plate_velocity)[1], frame_id)


def plate_pose_msg(ns, position, frame_id):
    """The plate's surface in the plate frame: position.z = p (m; 0 for the fixed plate)."""
    return height_msg(ns, position, frame_id)


def plate_twist_msg(ns, velocity, frame_id):
    """The plate's velocity: linear.z = ṗ (m/s, > 0 moving up)."""
    return vertical_velocity_msg(ns, velocity, frame_id)


def plate_wrench_msg(ns, force, frame_id):
    """The contact's reaction on the plate: force.z = -F (N, <= 0: pushed down)."""
    return wrench_msg(ns, -force, frame_id)


def impact_msg(record, offset):
    """One completed contact phase as a labelled 1-D Float64MultiArray (fields IMPACT_FIELDS)."""
    values = [record.time + offset] + [float(getattr(record, f)) for f in IMPACT_FIELDS[1:]]
    layout = MultiArrayLayout(dim=[MultiArrayDimension(
        label=','.join(IMPACT_FIELDS), size=len(IMPACT_FIELDS), stride=len(IMPACT_FIELDS))],
        data_offset=0)
    return Float64MultiArray(layout=layout, data=values)


def clock_msg(ns):
    return ClockMsg(clock=time_msg(ns))


def _finite(*values):
    return all(math.isfinite(v) for v in values)


def impact_ok(message):
    """Publishable: every field finite, except contact_duration = +inf for the final, permanent
    contact (the sphere has come to rest)."""
    data = dict(zip(IMPACT_FIELDS, message.data))
    duration = data.pop('contact_duration')
    return _finite(*data.values()) and (math.isfinite(duration) or duration == math.inf)


def contact_samples(samples, offset, after_ns):
    """The engine's samples as (ns, z, zdot, F) tuples with strictly increasing stamps > after_ns.

    Samples closer than the stamps' 1 ns resolution share a stamp: of those only the one with the
    largest force is kept, so a located force peak is never dropped. Returns (tuples, number of
    non-finite samples dropped).
    """
    out, dropped = [], 0
    for t, z, zdot, force in zip(np.asarray(samples.time, dtype=float).tolist(),
                                 np.asarray(samples.penetration, dtype=float).tolist(),
                                 np.asarray(samples.penetration_rate, dtype=float).tolist(),
                                 np.asarray(samples.force, dtype=float).tolist()):
        if not _finite(t, z, zdot, force):
            dropped += 1
            continue
        ns = to_ns(offset + t)
        if ns <= after_ns:
            continue
        if out and ns == out[-1][0]:
            if force > out[-1][3]:
                out[-1] = (ns, z, zdot, force)
        else:
            out.append((ns, z, zdot, force))
    return out, dropped


def to_ns_array(seconds):
    """``to_ns`` over an array: the same rounding (half to even) of the same product."""
    return np.rint(np.asarray(seconds, dtype=float) * 1e9).astype(np.int64)


def sample_columns(time, penetration, penetration_rate, force, offset, after_ns):
    """``contact_samples`` over arrays, as columns: (ns, z, zdot, F) lists of the samples kept
    and the number of non-finite samples dropped. Stamped offset + t; when all are finite and
    the stamps do not decrease (the engine's samples in time order) the selection is made over
    arrays (a run of equal stamps keeps its first sample of largest force), else sample by
    sample."""
    ns = to_ns_array(offset + np.asarray(time, dtype=float)) if len(time) else np.empty(0, int)
    finite = np.isfinite(time) & np.isfinite(penetration) & np.isfinite(penetration_rate) \
        & np.isfinite(force)
    if finite.all() and np.all(ns[1:] >= ns[:-1]):
        first = int(np.searchsorted(ns, after_ns, side='right'))
        columns = [ns[first:], penetration[first:], penetration_rate[first:], force[first:]]
        ns = columns[0]
        if ns.size > 1 and not np.all(ns[1:] > ns[:-1]):
            new = np.concatenate([[True], ns[1:] != ns[:-1]])
            group = np.cumsum(new) - 1
            largest = np.maximum.reduceat(columns[3], np.flatnonzero(new))
            candidates = np.flatnonzero(columns[3] == largest[group])
            _, firsts = np.unique(group[candidates], return_index=True)
            keep = candidates[firsts]
            columns = [c[keep] for c in columns]
        return (*(c.tolist() for c in columns), 0)
    samples = _Columns(time, penetration, penetration_rate, force)
    out, dropped = contact_samples(samples, offset, after_ns)
    columns = [list(c) for c in zip(*out)] if out else [[], [], [], []]
    return (*columns, dropped)


@dataclass(frozen=True)
class _Columns:
    time: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    force: np.ndarray


# --------------------------------------------------------------------------------------------
# QoS
# --------------------------------------------------------------------------------------------

def reliable(depth):
    """Reliable, volatile, keep-last ``depth``."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)


SAMPLE_QOS = reliable(10000)  # ~/wrench, ~/contact: a whole bouncing phase fits
# A writer keeps this many samples for reliable readers that lost some (a full shared-memory
# queue, say) and wait for the repair: 10 s of ticks at the default 100 Hz.
STATE_QOS = reliable(1000)
IMPACT_QOS = reliable(1000)
CLOCK_QOS = reliable(1000)  # also matches rclpy's best-effort /clock subscribers
# A recorder keeps every sample it has not yet taken (keep-all): a reader that falls behind
# slows the node through the acknowledgements instead of losing the oldest samples.
RECORD_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0,
                        reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.VOLATILE)

# --------------------------------------------------------------------------------------------
# CDR templates: the serialized message with only the stamp and the values packed in
# --------------------------------------------------------------------------------------------

_DOUBLE = struct.Struct('<d')
_STAMP = struct.Struct('<iI')
_MARK_SEC, _MARK_NSEC = 0x5EC0FFEE, 0x0ACE0FF5


class CdrTemplate:
    """The CDR bytes of one message type with a fixed frame_id, ready to be filled in.

    ``fields`` are attribute paths of float64 fields (``'wrench.force.z'``); ``constants`` are
    paths set to a fixed value in every message (``'pose.orientation.w': 1.0``). The offsets are
    found by serializing a message with distinct marker values, so the layout is rclpy's own.
    """

    def __init__(self, msg_type, fields, frame_id=None, constants=None, stamp='header.stamp'):
        msg = msg_type()
        for path, value in (constants or {}).items():
            _set(msg, path, value)
        if frame_id is not None:
            msg.header.frame_id = frame_id
        _set(msg, stamp, Time(sec=_MARK_SEC, nanosec=_MARK_NSEC))
        markers = [math.pi * (1 + i) * 1e-300 for i in range(len(fields))]
        for path, marker in zip(fields, markers):
            _set(msg, path, marker)
        data = serialize_message(msg)
        self.stamp_offset = _find(data, _STAMP.pack(_MARK_SEC, _MARK_NSEC))
        offsets = [_find(data, _DOUBLE.pack(marker)) for marker in markers]
        self.offsets = offsets
        for o in offsets:
            data = data[:o] + bytes(8) + data[o + 8:]
        self.template = bytes(data[:self.stamp_offset]) + bytes(8) + bytes(
            data[self.stamp_offset + 8:])
        self.msg_type = msg_type

    def encode(self, ns, *values):
        """The serialized message stamped ``ns`` with the fields set to ``values``."""
        buffer = bytearray(self.template)
        sec, nanosec = divmod(ns, 1_000_000_000)
        _STAMP.pack_into(buffer, self.stamp_offset, sec, nanosec)
        for offset, value in zip(self.offsets, values):
            _DOUBLE.pack_into(buffer, offset, value)
        return bytes(buffer)

    def packer(self):
        """``encode`` as one ``struct`` call: a function ``(ns, *values)`` -> the same bytes.

        For the usual layout (the stamp, then the fields back to back in order): the template
        cut into its constant bytes before the stamp, between the stamp and the fields, and after
        them, packed with the stamp and the values by one format; any other layout gets
        ``encode``."""
        offsets, stamp = self.offsets, self.stamp_offset
        if offsets != sorted(offsets) or any(b - a != 8 for a, b in zip(offsets, offsets[1:])) \
                or (offsets and offsets[0] < stamp + 8):
            return self.encode
        template, first = self.template, offsets[0] if offsets else stamp + 8
        end = first + 8 * len(offsets)
        head, middle, tail = template[:stamp], template[stamp + 8:first], template[end:]
        pack = struct.Struct(f'<{len(head)}siI{len(middle)}s{"d" * len(offsets)}'
                             f'{len(tail)}s').pack

        def encode(ns, *values):
            return pack(head, ns // 1_000_000_000, ns % 1_000_000_000, middle, *values, tail)
        return encode


def _set(msg, path, value):
    *parents, name = path.split('.')
    for parent in parents:
        msg = getattr(msg, parent)
    setattr(msg, name, value)


def _find(data, pattern):
    index = bytes(data).find(pattern)
    if index < 0 or bytes(data).find(pattern, index + 1) >= 0:
        raise RuntimeError(f'cannot locate a field in the CDR layout ({pattern.hex()})')
    return index


# --------------------------------------------------------------------------------------------
# The topic table
# --------------------------------------------------------------------------------------------

def _header_ns(msg):
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


def _clock_ns(msg):
    return msg.clock.sec * 1_000_000_000 + msg.clock.nanosec


_MAX_NS = 2 ** 63 - 1  # a bag timestamp is a signed 64-bit count of ns


def _bag_ns(seconds):
    """Seconds -> ns clamped to [0, 2^63 - 1]; NaN -> 0 (an impact array from any publisher)."""
    if not seconds > 0.0:
        return 0
    return _MAX_NS if seconds * 1e9 >= _MAX_NS else to_ns(seconds)


def _impact_ns(msg):
    return _bag_ns(msg.data[0]) if len(msg.data) else 0


def _impact_end_ns(msg):
    """An impact reaches the end of its contact (its start if the contact is permanent)."""
    if len(msg.data) >= 5 and math.isfinite(msg.data[4]):
        return _bag_ns(msg.data[0] + max(0.0, msg.data[4]))
    return _impact_ns(msg)


@dataclass(frozen=True)
class Topic:
    """One topic of the node.

    ``name`` is relative to the node (``~/wrench``) or absolute (``/clock``); ``kind`` says when
    the node publishes it: ``sample`` (every contact point and each tick's end), ``state`` (once
    per tick), ``impact`` (once per completed contact phase), ``clock`` (once per tick, with
    ``publish_clock``). ``fields`` are the float64 fields ``encode`` fills, in order;
    ``stamp_ns(msg)`` is the simulated time a message belongs to, ``covered_ns(msg)`` how far in
    simulated time it shows the simulation (an impact: to the end of its contact).
    """

    key: str
    name: str
    msg_type: type
    qos: QoSProfile
    kind: str
    fields: tuple = ()
    constants: tuple = ()     # ((path, value), ...) set in every message
    stamp_ns: object = _header_ns
    covered_ns: object = None

    @property
    def type_name(self):
        return type_name(self.msg_type)

    @property
    def continuous(self):
        """Published at every tick (so a recording of it reaches every tick's time)."""
        return self.kind in ('sample', 'state')

    @property
    def paced(self):
        """Covered by a recorder's acknowledgement: the node's own per-tick topics and /clock
        (a keep-last writer: unacknowledged, its oldest samples would be overwritten)."""
        return self.continuous or self.kind == 'clock'

    def resolve(self, node_name):
        """The full name for a node ``/ns/name`` (``~/x`` -> ``/ns/name/x``)."""
        if self.name.startswith('~/'):
            return '/' + node_name.strip('/') + self.name[1:]
        return self.name

    def template(self, frame_id):
        """A CdrTemplate for this topic's messages (stamped types carry ``frame_id``)."""
        stamped = self.kind != 'clock'
        return CdrTemplate(self.msg_type, self.fields, frame_id if stamped else None,
                           dict(self.constants), 'header.stamp' if stamped else 'clock')

    def covered(self, msg):
        return (self.covered_ns or self.stamp_ns)(msg)

    def times_of_cdr(self, data):
        """(stamp_ns, covered_ns) of a serialized message: read in place for the stamped types
        and /clock (the stamp follows the 4-byte CDR header), deserialized for an impact."""
        if self.kind == 'impact':
            msg = deserialize_message(data, self.msg_type)
            return self.stamp_ns(msg), self.covered(msg)
        sec, nanosec = _STAMP.unpack_from(data, 4)
        ns = sec * 1_000_000_000 + nanosec
        return ns, ns


TOPICS = (
    Topic('wrench', '~/wrench', WrenchStamped, SAMPLE_QOS, 'sample', ('wrench.force.z',)),
    Topic('contact', '~/contact', Vector3Stamped, SAMPLE_QOS, 'sample',
          ('vector.x', 'vector.y', 'vector.z')),
    Topic('pose', '~/pose', PoseStamped, STATE_QOS, 'state', ('pose.position.z',),
          (('pose.orientation.w', 1.0),)),
    Topic('twist', '~/twist', TwistStamped, STATE_QOS, 'state', ('twist.linear.z',)),
    Topic('impact', '~/impact', Float64MultiArray, IMPACT_QOS, 'impact',
          stamp_ns=_impact_ns, covered_ns=_impact_end_ns),
    Topic('clock', '/clock', ClockMsg, CLOCK_QOS, 'clock', stamp_ns=_clock_ns),
    # the plate: its surface's height p and velocity ṗ once per tick, the reaction -F on it at
    # every contact sample (a fixed plate: p = ṗ = 0)
    Topic('plate_pose', '~/plate_pose', PoseStamped, STATE_QOS, 'state', ('pose.position.z',),
          (('pose.orientation.w', 1.0),)),
    Topic('plate_twist', '~/plate_twist', TwistStamped, STATE_QOS, 'state', ('twist.linear.z',)),
    Topic('plate_wrench', '~/plate_wrench', WrenchStamped, SAMPLE_QOS, 'sample',
          ('wrench.force.z',)),
)
TOPIC = {topic.key: topic for topic in TOPICS}
# For viewers (RViz, Foxglove), derived from the topics above and not recorded: the sphere, the
# plate and the contact force as markers (``markers``), once per tick in real time, at most
# publish_rate a wall second as fast as possible; how the node keeps up (``diagnostics``), once a
# wall second. Published by ``view.View``; a reader that falls behind loses old ones.
VIEW_TOPICS = (
    Topic('markers', '~/markers', MarkerArray, reliable(10), 'view'),
    Topic('diagnostics', '/diagnostics', DiagnosticArray, reliable(10), 'view'),
)
# The recorder's acknowledgement (not recorded): the simulated time up to which it has recorded
# every per-tick topic. The node, running as fast as possible, stays within a lead of it
# (``pacing``). Transient-local: a node that matches the recorder late gets its last word.
# Liveliness AUTOMATIC with a lease of RECORDER_LEASE s: the middleware asserts the recorder's
# writer every 2/3 of it from its own thread, so a recorder killed (SIGKILL, a crash) is known to
# be gone within the lease, where the graph keeps it for the participant's lease of 20 s.
RECORDER_LEASE = 1.5   # s
PROGRESS = Topic('recorded', '~/recorded', ClockMsg, QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=1, reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL, liveliness=LivelinessPolicy.AUTOMATIC,
    liveliness_lease_duration=Duration(seconds=RECORDER_LEASE)), 'progress', stamp_ns=_clock_ns)
_BY_TYPE = {topic.msg_type: topic for topic in TOPICS}


def type_name(msg_type):
    """``geometry_msgs.msg.WrenchStamped`` -> ``'geometry_msgs/msg/WrenchStamped'``."""
    return f'{msg_type.__module__.split(".")[0]}/msg/{msg_type.__name__}'


def message_time_ns(msg):
    """The simulated time a message of any of the node's types belongs to, in ns."""
    return _BY_TYPE[type(msg)].stamp_ns(msg)


def covered_time_ns(msg):
    """How far in simulated time (ns) a message shows the simulation: its time, or for an
    impact the end of its contact (its start if the contact is permanent)."""
    return _BY_TYPE[type(msg)].covered(msg)
