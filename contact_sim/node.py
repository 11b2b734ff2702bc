"""The ROS 2 face of contact_sim: the ``contact_sim_node`` simulator and the ``contact_sim_record``
recorder.

This is the only module of the package that imports rclpy or a ROS message package; the physics
comes from the core library (``import contact_sim as cs``). Data flows one way:

    parameters --build_model--> materials, contact law, Contact --> cs.DropSimulation
        --advance--> samples and impact records --*_msg functions--> messages

Frames and signs (REP 103, SI units): the plate frame (``frame_id``, default ``plate``) has z up
and the plate's surface (the top of the lower sphere, for two spheres) at z = 0. The sphere moves
along that z axis only. Penetration z > 0 means the undeformed bodies overlap; its rate ż > 0 means
approach. README.md documents every topic, service and parameter.
"""
import argparse
import math
import re
import signal
import sys
import time
from dataclasses import dataclass
from functools import partial

import numpy as np
import rclpy
import rclpy.logging
from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseStamped, TwistStamped, Vector3Stamped, WrenchStamped
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, ParameterType, \
    ParameterValue, SetParametersResult
from rcl_interfaces.srv import GetParameters
from rclpy.clock import Clock, ClockType
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import serialize_message
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args
from rosgraph_msgs.msg import Clock as ClockMsg
from std_msgs.msg import Float64MultiArray, MultiArrayDimension, MultiArrayLayout
from std_srvs.srv import Trigger

import contact_sim as cs
from .validation import require_nonnegative, require_positive, require_range, require_real

NODE_NAME = 'contact_sim'
INF = math.inf

# --------------------------------------------------------------------------------------------
# Parameters
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Spec:
    """One declared parameter: default, description (with units), range, read-only flag."""

    name: str
    default: object
    description: str
    range: tuple = None          # closed FloatingPointRange (from, to) for rclpy's own check
    read_only: bool = False
    constraints: str = ''        # the exact rule, as the core library enforces it


def _custom_material(body, material, density_note=''):
    """The three constants of a custom material for ``body``, defaulting to ``material``'s."""
    def spec(field, description, rng, constraint):
        return Spec(f'{body}_{field}', getattr(material, field),
                    f'{description} of the {body} when {body}_material is custom (otherwise '
                    'checked but unused)', rng, constraints=constraint.format(f'{body}_{field}'))
    return (spec('youngs_modulus', "Young's modulus E [Pa]", (0.0, INF), '0 < {}'),
            spec('poisson_ratio', 'Poisson ratio nu [-]', (-1.0, 0.5), '-1 < {} < 0.5'),
            spec('density', 'Density rho [kg/m^3]' + density_note, (0.0, INF), '0 < {}'))


_LAWS = ', '.join(sorted(cs.LAWS))
_MATERIALS = ', '.join(sorted(cs.MATERIALS))
_STEEL, _IRON = cs.MATERIALS['steel'], cs.MATERIALS['cast_iron']   # the default pair
_CONTACT_NOTE = 'takes effect from the next contact phase'
_RESET_NOTE = 'takes effect at the next ~/reset'

PARAMETERS = (
    Spec('contact_law', 'azad_featherstone',
         f'Normal-force law F = k z^n + lambda z^p zdot^q (paper eq. 1); {_CONTACT_NOTE}',
         constraints=f'one of: {_LAWS}'),
    Spec('sphere_material', 'steel',
         f'Material of the falling sphere: a library name or custom; elastic constants '
         f'{_CONTACT_NOTE}, a density-derived mass at the next ~/reset',
         constraints=f'one of: {_MATERIALS}, custom'),
    *_custom_material('sphere', _STEEL),
    Spec('sphere_radius', 0.0127,
         f'Sphere radius R1 [m]; the Hertz stiffness {_CONTACT_NOTE}, a density-derived mass at '
         'the next ~/reset', (0.0, INF), constraints='0 < sphere_radius < inf'),
    Spec('sphere_mass', 0.0,
         f'Sphere mass [kg]; 0 = from sphere density and radius, (4/3) pi R1^3 rho; {_RESET_NOTE}',
         (0.0, INF), constraints='0 <= sphere_mass < inf'),
    Spec('plate_material', 'cast_iron',
         f'Material of the plate (or of the lower sphere); {_CONTACT_NOTE}',
         constraints=f'one of: {_MATERIALS}, custom'),
    *_custom_material('plate', _IRON, ' (the plate is immovable: its mass never enters)'),
    Spec('plate_radius', INF,
         f'Radius R2 of the body struck [m]: .inf = flat plate, finite = a fixed second sphere '
         f'(1/R = 1/R1 + 1/R2, eq. 10); {_CONTACT_NOTE}', (0.0, INF),
         constraints='0 < plate_radius <= inf'),
    Spec('stiffness', 0.0,
         f'Stiffness override k [N/m^n]; 0 = Hertz, k = (4/3) E* sqrt(R) (eqs. 5, 6); '
         f'{_CONTACT_NOTE}', (0.0, INF), constraints='0 <= stiffness < inf'),
    Spec('damping', 0.0,
         f'Damping override lambda [N s^q/m^(p+q)]; 0 = lambda* sqrt(R) (eq. 9); '
         f'{_CONTACT_NOTE}', (0.0, INF), constraints='0 <= damping < inf'),
    Spec('damping_factor', 8.87e5,
         f'Damping factor lambda* [N s/m^(p+q+1/2)], N s/m^2 for azad_featherstone; used when '
         f'damping is 0; {_CONTACT_NOTE}', (0.0, INF), constraints='0 <= damping_factor < inf'),
    Spec('gravity', 9.81, f'Gravitational acceleration g, pulling the sphere down [m/s^2]; '
         f'{_RESET_NOTE}', (0.0, INF), constraints='0 <= gravity < inf'),
    Spec('initial_height', 1.0,
         f'Initial height of the sphere\'s lowest point above the plate [m]; {_RESET_NOTE}',
         (0.0, INF), constraints='0 <= initial_height < inf'),
    Spec('initial_velocity', 0.0,
         f'Initial downward velocity [m/s] (> 0 = towards the plate); {_RESET_NOTE}',
         constraints='finite'),
    Spec('publish_rate', 100.0,
         'Publish ticks per second [Hz]: wall-clock rate at a finite real_time_factor, simulated '
         'ticks per simulated second when real_time_factor is 0 or .inf',
         (0.1, 10000.0), read_only=True, constraints='0.1 <= publish_rate <= 10000'),
    Spec('real_time_factor', 1.0,
         'Simulated seconds per wall-clock second [-]; 0 or .inf = as fast as possible (each '
         'executor turn advances 1/publish_rate simulated seconds); takes effect at once',
         (0.0, INF), constraints='0 <= real_time_factor <= inf'),
    Spec('frame_id', 'plate', 'frame_id of every stamped message: the plate frame, z up, the '
         'plate surface at z = 0', read_only=True, constraints='non-empty'),
    Spec('publish_clock', True, 'Publish the simulated time on /clock (rosgraph_msgs/Clock)',
         read_only=True),
)
PARAMETER_NAMES = tuple(spec.name for spec in PARAMETERS)
DEFAULTS = {spec.name: spec.default for spec in PARAMETERS}


def descriptor(spec):
    """The ParameterDescriptor of one Spec (type follows the default's Python type)."""
    result = ParameterDescriptor(description=spec.description, read_only=spec.read_only,
                                 additional_constraints=spec.constraints)
    if spec.range is not None:
        result.floating_point_range = [FloatingPointRange(
            from_value=float(spec.range[0]), to_value=float(spec.range[1]), step=0.0)]
    return result


# --------------------------------------------------------------------------------------------
# Parameters -> model (no ROS here: plain values in, core-library objects out)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Model:
    """Everything the simulation needs, validated; built from parameter values by build_model."""

    contact: cs.Contact
    mass: float           # kg
    radius: float         # m, sphere radius R1
    gravity: float        # m/s^2
    height: float         # m, initial height of the lowest point
    velocity: float       # m/s, initial downward velocity
    real_time_factor: float
    publish_rate: float   # Hz
    frame_id: str
    publish_clock: bool
    sphere: cs.Material
    plate: cs.Material
    plate_radius: float   # m, inf = flat

    @property
    def fast(self):
        """True when the simulation runs as fast as possible (real_time_factor 0 or inf)."""
        return self.real_time_factor == 0.0 or math.isinf(self.real_time_factor)

    def summary(self):
        plate = 'flat plate' if math.isinf(self.plate_radius) \
            else f'sphere R2 = {self.plate_radius * 1e3:g} mm'
        return (f'{self.contact.law.name}: {self.sphere.name} sphere '
                f'R1 = {self.radius * 1e3:g} mm, '
                f'm = {self.mass * 1e3:.4g} g on {self.plate.name} {plate}; '
                f'k = {self.contact.stiffness:.4g} N/m^{self.contact.law.n:g}, '
                f'lambda = {self.contact.damping:.4g}; drop from {self.height:g} m at '
                f'{self.velocity:g} m/s, g = {self.gravity:g} m/s^2')


def _renamed(error, **names):
    """The library's ValueError text with its field names replaced by parameter names."""
    text = str(error)
    for old, new in names.items():
        text = re.sub(rf'\b{old}\b', new, text)
    return ValueError(text)


def _material(values, body):
    fields = ('youngs_modulus', 'poisson_ratio', 'density')
    try:
        custom = cs.Material(f'custom_{body}', *(values[f'{body}_{f}'] for f in fields))
    except ValueError as error:
        raise _renamed(error, **{f: f'{body}_{f}' for f in fields}) from None
    name = values[f'{body}_material']
    if name == 'custom':
        return custom
    try:
        return cs.get_material(name)
    except ValueError:
        raise ValueError(f'{body}_material = {name!r} is unknown: allowed one of {_MATERIALS} '
                         f'or custom (then {body}_youngs_modulus, {body}_poisson_ratio and '
                         f'{body}_density apply)') from None


def _contact(values, sphere, plate, radius, plate_radius):
    """The Contact: Hertz k and λ = λ* √R (eqs. 5, 6, 9, 10), unless overridden."""
    try:
        law = cs.get_law(values['contact_law'])
    except ValueError as error:
        raise _renamed(error, law='contact_law') from None
    damping_factor = require_nonnegative('damping_factor', values['damping_factor'])
    stiffness = require_nonnegative('stiffness', values['stiffness'])
    damping = require_nonnegative('damping', values['damping'])
    if law.n != 1.5 and stiffness == 0.0:
        raise ValueError(f'contact_law = {law.name!r} has n = {law.n:g}: Hertz stiffness needs '
                         'n = 1.5; set stiffness > 0 (N/m^n) to give k directly')
    try:
        # with a stiffness override any law goes: Hertz is then used for λ = λ* √R only
        hertz = cs.Contact.from_materials(law if law.n == 1.5 else cs.AZAD_FEATHERSTONE, sphere,
                                          plate, radius, plate_radius, damping_factor)
    except ValueError as error:
        raise _renamed(error, radius='sphere_radius') from None
    return cs.Contact(law, stiffness or hertz.stiffness, damping or hertz.damping)


def _build_model(values):
    """Validate parameter values (a dict name -> value) and build the Model.

    Raises ValueError naming the parameter, its value and the allowed range (the core library's
    messages, with its field names replaced by the parameter names).
    """
    radius = require_positive('sphere_radius', values['sphere_radius'])
    plate_radius = require_positive('plate_radius', values['plate_radius'], allow_inf=True)
    sphere = _material(values, 'sphere')
    plate = _material(values, 'plate')
    contact = _contact(values, sphere, plate, radius, plate_radius)
    mass = require_nonnegative('sphere_mass', values['sphere_mass'])
    if mass == 0.0:
        mass = cs.sphere_mass(sphere.density, radius)
    frame_id = values['frame_id']
    if not isinstance(frame_id, str) or not frame_id.strip():
        raise ValueError(f'frame_id = {frame_id!r} is invalid: allowed a non-empty string')
    model = Model(
        contact=contact, mass=mass, radius=radius,
        gravity=require_nonnegative('gravity', values['gravity']),
        height=require_nonnegative('initial_height', values['initial_height']),
        velocity=require_real('initial_velocity', values['initial_velocity']),
        real_time_factor=require_range('real_time_factor', values['real_time_factor'], 0.0,
                                       allow_inf=True),
        publish_rate=require_range('publish_rate', values['publish_rate'], 0.1, 10000.0),
        frame_id=frame_id, publish_clock=bool(values['publish_clock']),
        sphere=sphere, plate=plate, plate_radius=plate_radius)
    make_simulation(model)  # the engine's own checks, e.g. on mass, height and gravity
    require_shallow_contact(contact, radius, model, stiffness_given=values['stiffness'] > 0.0)
    return model


def require_shallow_contact(contact, radius, drop, stiffness_given, running=False):
    """Reject a contact so soft that a drop would sink the sphere deeper than its radius.

    ``drop`` has the drop's ``mass`` (kg), ``gravity`` (m/s²), ``height`` (m) and downward
    ``velocity`` (m/s): a Model, or the running DropSimulation (``running=True``). Hertz contact
    (and every law here) assumes z << R. Undamped, the first impact at speed
    v1 = sqrt(v0² + 2 g h) stops at the depth z where k z^(n+1)/(n+1) = m v1²/2 + m g z, so
    z <= R holds when k >= (n+1)(m v1²/2 + m g R) / R^(n+1). Damping only makes z smaller, so
    this bound is sufficient (and independent of λ). Without gravity a sphere thrown upwards or
    at rest never lands: nothing to check.
    """
    mass, gravity, height, velocity = drop.mass, drop.gravity, drop.height, drop.velocity
    if gravity == 0.0 and velocity <= 0.0:
        return
    n = contact.law.n
    speed_sq = velocity ** 2 + 2.0 * gravity * height
    minimum = (n + 1.0) * (0.5 * mass * speed_sq + mass * gravity * radius) / radius ** (n + 1.0)
    k = contact.stiffness
    if k >= minimum:
        return
    field = 'stiffness' if stiffness_given else \
        'the Hertz stiffness (from the materials\' moduli and Poisson ratios)'
    allowed = f'allowed stiffness >= {minimum:.4g} N/m^{n:g}'
    # or, with this k, the highest drop: m v1²/2 <= k R^(n+1)/(n+1) - m g R
    top_speed_sq = 2.0 * (k * radius ** (n + 1.0) / (n + 1.0) - mass * gravity * radius) / mass
    if not running and gravity > 0.0 and top_speed_sq > velocity ** 2:
        highest = (top_speed_sq - velocity ** 2) / (2.0 * gravity)
        allowed += f' or initial_height <= {highest:.4g} m'
    which = 'the running drop (until ~/reset)' if running else 'this drop'
    raise ValueError(
        f'{field} = {k:.4g} N/m^{n:g} is too small for {which}: a {mass:.4g} kg sphere '
        f'hitting at {math.sqrt(speed_sq):.4g} m/s would sink more than its radius '
        f'({radius:g} m) into the plate, where no contact law here applies; {allowed}')


def build_model(values):
    """``_build_model``, with arithmetic overflow from extreme values turned into a ValueError."""
    try:
        return _build_model(values)
    except ArithmeticError as error:
        def departure(name):   # orders of magnitude away from the default
            value, default = values[name], DEFAULTS[name]
            if isinstance(value, bool) or not isinstance(value, float) or not value > 0.0 \
                    or not isinstance(default, float) or not 0.0 < default < INF:
                return -1.0
            return abs(math.log10(value / default))
        name = max(DEFAULTS, key=departure)
        raise ValueError(f'{name} = {values[name]!r} overflows the model ({error}): allowed '
                         f'physically sensible magnitudes') from None


def make_simulation(model):
    """A fresh drop at t = 0 from the model's initial conditions."""
    return cs.DropSimulation(model.contact, model.mass, model.height, velocity=model.velocity,
                             gravity=model.gravity)


# --------------------------------------------------------------------------------------------
# ~/query_restitution: names -> answers (no ROS here either)
# --------------------------------------------------------------------------------------------

QUERY_QUANTITIES = ('restitution', 'contact_duration', 'peak_force', 'max_penetration')


def parse_query(name):
    """``'2.5'`` or ``'peak_force:2.5'`` -> (quantity, speed in m/s); ValueError says why not."""
    if not isinstance(name, str):
        raise ValueError(f'name = {name!r} is not a string')
    prefix, colon, text = name.rpartition(':')
    quantity = prefix.strip() if colon else 'restitution'
    if quantity not in QUERY_QUANTITIES:
        raise ValueError(f'prefix {quantity!r} is unknown: allowed none or one of '
                         f'{", ".join(q + ":" for q in QUERY_QUANTITIES)}')
    try:
        speed = float(text)
    except ValueError:
        raise ValueError(f'impact speed {text.strip()!r} is not a number (m/s, e.g. 2.5)') from None
    return quantity, require_positive('impact speed', speed)


def answer_queries(names, contact, mass):
    """Answer every name; returns [(value or None, reason or None)] in request order.

    Valid names are grouped by quantity and answered with one vectorised call of the library's
    fast path (``cs.restitution`` etc., zero gravity, one impact); if a group's call fails, its
    names are answered one by one so that only the failing ones go unanswered.
    """
    answers = [None] * len(names)
    groups = {}
    for i, name in enumerate(names):
        try:
            quantity, speed = parse_query(name)
        except ValueError as error:
            answers[i] = (None, str(error))
            continue
        groups.setdefault(quantity, []).append((i, speed))
    with np.errstate(all='ignore'):  # extreme speeds: every result is checked for finiteness
        _answer_groups(groups, answers, contact, mass)
    return answers


def _answer_groups(groups, answers, contact, mass):
    for quantity, items in groups.items():
        function = getattr(cs, quantity)
        speeds = np.array([speed for _, speed in items])
        try:
            values = np.asarray(function(contact, mass, speeds), dtype=float).reshape(-1)
            if values.shape != speeds.shape:
                raise ValueError(f'{quantity} returned {values.size} values for '
                                 f'{speeds.size} speeds')
        except Exception:  # isolate the failing speeds: answer one at a time
            values = []
            for i, speed in items:
                try:
                    values.append(float(function(contact, mass, speed)))
                except Exception as error:  # the engine's reason, reported per name
                    values.append(None)
                    answers[i] = (None, f'{quantity} at {speed:g} m/s failed: {error}')
        for (i, speed), value in zip(items, values):
            if answers[i] is not None:
                continue
            if value is None or not math.isfinite(value):
                answers[i] = (None, f'{quantity} at {speed:g} m/s is not finite')
            else:
                answers[i] = (float(value), None)


# --------------------------------------------------------------------------------------------
# Results -> messages (small pure functions; times are integer nanoseconds of simulated time)
# --------------------------------------------------------------------------------------------

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


def pose_msg(ns, radius, penetration, frame_id):
    """Sphere centre in the plate frame: z = R1 - penetration (height of the undeformed centre)."""
    msg = PoseStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    msg.pose.position.z = float(radius - penetration)
    msg.pose.orientation.w = 1.0
    return msg


def twist_msg(ns, penetration_rate, frame_id):
    """Sphere velocity in the plate frame: linear.z = -zdot (> 0 moving up)."""
    msg = TwistStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    msg.twist.linear.z = float(-penetration_rate)
    return msg


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
    for t, z, zdot, force in zip(np.asarray(samples.time, dtype=float),
                                 np.asarray(samples.penetration, dtype=float),
                                 np.asarray(samples.penetration_rate, dtype=float),
                                 np.asarray(samples.force, dtype=float)):
        if not _finite(t, z, zdot, force):
            dropped += 1
            continue
        ns = to_ns(offset + t)
        if ns <= after_ns:
            continue
        if out and ns == out[-1][0]:
            if force > out[-1][3]:
                out[-1] = (ns, float(z), float(zdot), float(force))
        else:
            out.append((ns, float(z), float(zdot), float(force)))
    return out, dropped


# --------------------------------------------------------------------------------------------
# The node
# --------------------------------------------------------------------------------------------

def _reliable(depth):
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)


SAMPLE_QOS = _reliable(10000)  # ~/wrench, ~/contact: a whole bouncing phase fits
# A writer keeps this many samples for reliable readers that lost some (a full shared-memory
# queue, say) and wait for the repair: 10 s of ticks at the default 100 Hz.
STATE_QOS = _reliable(1000)
IMPACT_QOS = _reliable(1000)
CLOCK_QOS = _reliable(1000)  # also matches rclpy's best-effort /clock subscribers


TICK_STEP_BUDGET = 5000  # integrator steps per tick at most, so services and Ctrl-C stay live


class StartupError(Exception):
    """The initial parameters are invalid: the node cannot start."""


class ContactSimNode(Node):
    """Simulates a sphere dropped on a plate and publishes its contact wrench, state and impacts."""

    def __init__(self, **kwargs):
        super().__init__(NODE_NAME, **kwargs)
        try:
            for spec in PARAMETERS:
                self.declare_parameter(spec.name, spec.default, descriptor(spec))
            self._model = build_model(self._values())
        except (ParameterException, ValueError) as error:
            raise StartupError(str(error)) from None
        self._warn_unknown_overrides()
        self._sim = make_simulation(self._model)
        self._offset = 0.0        # s: stamp = offset + simulator time; grows at each ~/reset
        self._last_sample_ns = -1
        self._last_state_ns = -1
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)  # pacing ignores use_sim_time

        self._frame_id = self._model.frame_id  # read-only
        self._wrench_pub = self.create_publisher(WrenchStamped, '~/wrench', SAMPLE_QOS)
        self._contact_pub = self.create_publisher(Vector3Stamped, '~/contact', SAMPLE_QOS)
        self._pose_pub = self.create_publisher(PoseStamped, '~/pose', STATE_QOS)
        self._twist_pub = self.create_publisher(TwistStamped, '~/twist', STATE_QOS)
        self._impact_pub = self.create_publisher(Float64MultiArray, '~/impact', IMPACT_QOS)
        self._clock_pub = (self.create_publisher(ClockMsg, '/clock', CLOCK_QOS)
                           if self._model.publish_clock else None)
        self.create_service(GetParameters, '~/query_restitution', self._on_query)
        self.create_service(Trigger, '~/reset', self._on_reset)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.add_post_set_parameters_callback(self._on_parameters_set)
        self._timer = None
        self._start_timer()
        self.get_logger().info(self._model.summary())

    # ---- parameters ------------------------------------------------------------------------

    def _values(self, changes=()):
        values = {name: self.get_parameter(name).value for name in PARAMETER_NAMES}
        values.update({p.name: p.value for p in changes})
        return values

    def _warn_unknown_overrides(self):
        unknown = sorted(name for name in getattr(self, '_parameter_overrides', {})
                         if not self.has_parameter(name))
        if unknown:
            self.get_logger().warning(f'ignoring unknown parameters: {", ".join(unknown)} '
                                      f'(known: {", ".join(PARAMETER_NAMES)})')

    def _on_set_parameters(self, parameters):
        """Validate a parameter change as a whole; nothing changes unless all of it is valid."""
        ours = [p for p in parameters if p.name in DEFAULTS]
        if not ours:
            return SetParametersResult(successful=True)
        try:
            values = self._values(ours)
            model = build_model(values)
            # a new contact acts from the next contact phase of the running drop
            require_shallow_contact(model.contact, model.radius, self._sim,
                                    values['stiffness'] > 0.0, running=True)
        except Exception as error:  # any failure rejects the change, never the node
            names = ', '.join(p.name for p in ours)
            return SetParametersResult(successful=False, reason=f'rejected {names}: {error}')
        return SetParametersResult(successful=True)

    def _on_parameters_set(self, parameters):
        """Apply an accepted change: the contact at once (engine: from the next contact)."""
        if not any(p.name in DEFAULTS for p in parameters):
            return
        old = self._model
        try:
            new = build_model(self._values())
        except Exception as error:  # validated already: should not happen; keep running
            self.get_logger().error(f'could not apply the accepted parameters: {error}')
            return
        self._model = new
        log = self.get_logger()
        if new.contact != old.contact:
            self._sim.set_contact(new.contact)
            log.info(f'contact changed, from the next contact phase: {new.summary()}')
        if (new.mass, new.gravity, new.height, new.velocity) != \
                (old.mass, old.gravity, old.height, old.velocity):
            log.info(f'mass, gravity or initial conditions changed, from the next ~/reset: '
                     f'{new.summary()}')
        if new.real_time_factor != old.real_time_factor:
            self._start_timer()
            log.info(f'real_time_factor = {new.real_time_factor:g}'
                     + (' (as fast as possible)' if new.fast else ''))

    # ---- simulation loop -------------------------------------------------------------------

    def _start_timer(self):
        """(Re)start the loop timer and re-anchor wall time to the current simulated time."""
        if self._timer is not None:
            self.destroy_timer(self._timer)
        model = self._model
        self._anchor = (time.monotonic(), self._sim.time)
        period = 0.0 if model.fast else 1.0 / model.publish_rate
        self._timer = self.create_timer(period, self._on_tick, clock=self._steady)

    def _target_time(self):
        model = self._model
        if model.fast:
            return self._sim.time + 1.0 / model.publish_rate
        wall0, sim0 = self._anchor
        return sim0 + model.real_time_factor * (time.monotonic() - wall0)

    def _on_tick(self):
        target = self._target_time()
        if not target > self._sim.time:
            return
        try:
            advance = self._sim.advance(target, max_steps=TICK_STEP_BUDGET)
        except Exception as error:  # keep the node alive and the last good state
            self.get_logger().error(f'simulation step to t = {target:.9f} s failed: {error}',
                                    throttle_duration_sec=5.0)
            return
        if self._sim.time < target:  # the budget ran out: go on at the next tick
            self.get_logger().warning(
                f'simulation is behind its target time ({self._sim.time:.6f} s < {target:.6f} s)'
                f': more than {TICK_STEP_BUDGET} integrator steps per tick',
                throttle_duration_sec=5.0)
        self._publish(advance)

    def _publish(self, advance):
        frame, offset = self._frame_id, self._offset
        samples, skipped = contact_samples(advance.samples, offset, self._last_sample_ns)
        for ns, z, zdot, force in samples:
            self._wrench_pub.publish(wrench_msg(ns, force, frame))
            self._contact_pub.publish(contact_msg(ns, z, zdot, force, frame))
            self._last_sample_ns = ns
        for record in advance.impacts:
            message = impact_msg(record, offset)
            if impact_ok(message):
                self._impact_pub.publish(message)
            else:
                skipped += 1
        state = self._sim.state
        ns = to_ns(offset + state.time)
        if not _finite(state.time, state.penetration, state.penetration_rate):
            skipped += 1
        elif ns > self._last_state_ns:
            self._last_state_ns = ns
            self._pose_pub.publish(pose_msg(ns, self._model.radius, state.penetration, frame))
            self._twist_pub.publish(twist_msg(ns, state.penetration_rate, frame))
            if self._clock_pub is not None:
                self._clock_pub.publish(clock_msg(ns))
        if skipped:
            self.get_logger().warning(f'skipped {skipped} non-finite values',
                                      throttle_duration_sec=5.0)

    # ---- services --------------------------------------------------------------------------

    def _on_query(self, request, response):
        model = self._model
        answers = answer_queries(list(request.names), model.contact, model.mass)
        values = []
        for name, (value, reason) in zip(request.names, answers):
            if value is None:
                self.get_logger().warning(f'query_restitution: cannot answer {name!r}: {reason}')
                values.append(ParameterValue(type=ParameterType.PARAMETER_NOT_SET))
            else:
                values.append(ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                             double_value=value))
        response.values = values
        return response

    def _on_reset(self, request, response):
        model = self._model
        try:
            sim = make_simulation(model)
        except Exception as error:
            response.success = False
            response.message = f'reset failed: {error}'
            return response
        self._offset += self._sim.time
        self._sim = sim
        self._anchor = (time.monotonic(), sim.time)
        response.success = True
        response.message = f'drop restarted at t = {self._offset:.9f} s: {model.summary()}'
        self.get_logger().info(response.message)
        return response


def spin_until_signal(node, stop_after=None, drain=None, drain_timeout=10.0):
    """Spin ``node`` until SIGINT or SIGTERM (or ``stop_after`` wall seconds), then return.

    The signals only set a flag, checked between executor turns, so a callback is never cut off
    and the context is shut down after spinning has stopped, not under the executor's feet.
    With ``drain`` (called once at the stop; it returns a predicate that is true when nothing
    more is needed), spinning goes on after the stop until that predicate holds, for at most
    ``drain_timeout`` wall seconds; a signal during it (a second one, after a signal) ends it at
    once. Returns whether the predicate held in the end (True without ``drain``). rclpy must be
    initialised with ``SignalHandlerOptions.NO``.
    """
    stop = []
    previous = {sig: signal.signal(sig, lambda *_: stop.append(True))
                for sig in (signal.SIGINT, signal.SIGTERM)}
    deadline = math.inf if stop_after is None else time.monotonic() + stop_after
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    drained = True
    try:
        while not stop and node.context.ok() and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.1)
        if drain is not None:
            done, limit, signals = drain(), time.monotonic() + drain_timeout, len(stop)
            while not (drained := done()) and len(stop) == signals and node.context.ok() \
                    and time.monotonic() < limit:
                executor.spin_once(timeout_sec=0.05)
    finally:
        executor.remove_node(node)
        executor.shutdown()
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    return drained


def main(args=None):
    """``contact_sim_node``: run until SIGINT/SIGTERM (exit code 0; 2 on bad parameters).

    ``args`` is a full argument vector like ``sys.argv`` (default: ``sys.argv``).
    """
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    code = 0
    try:
        node = ContactSimNode()
        spin_until_signal(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except StartupError as error:
        rclpy.logging.get_logger(NODE_NAME).fatal(f'invalid parameters: {error}')
        code = 2
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return code


# --------------------------------------------------------------------------------------------
# The recorder
# --------------------------------------------------------------------------------------------

RECORDED_TOPICS = (  # (suffix after the node name, type)
    ('wrench', WrenchStamped),
    ('contact', Vector3Stamped),
    ('pose', PoseStamped),
    ('twist', TwistStamped),
    ('impact', Float64MultiArray),
)
# A recorder that falls behind (a burst of contact samples, a busy machine) must not lose
# messages from its own queues: every topic gets a deep one.
RECORD_QOS = _reliable(10000)


def type_name(msg_type):
    """``geometry_msgs.msg.WrenchStamped`` -> ``'geometry_msgs/msg/WrenchStamped'``."""
    return f'{msg_type.__module__.split(".")[0]}/msg/{msg_type.__name__}'


_MAX_NS = 2 ** 63 - 1  # a bag timestamp is a signed 64-bit count of ns


def _bag_ns(seconds):
    """Seconds -> ns clamped to [0, 2^63 - 1]; NaN -> 0 (an impact array from any publisher)."""
    if not seconds > 0.0:
        return 0
    return _MAX_NS if seconds * 1e9 >= _MAX_NS else to_ns(seconds)


def message_time_ns(msg):
    """The simulated time a message belongs to, in ns: its header stamp, /clock's value, or an
    impact's ``time`` field."""
    if isinstance(msg, ClockMsg):
        stamp = msg.clock
    elif isinstance(msg, Float64MultiArray):
        return _bag_ns(msg.data[0]) if len(msg.data) else 0
    else:
        stamp = msg.header.stamp
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def covered_time_ns(msg):
    """How far in simulated time (ns) a message shows the simulation: its time, or for an
    impact the end of its contact (its start if the contact is permanent)."""
    if isinstance(msg, Float64MultiArray) and len(msg.data) >= 5 and math.isfinite(msg.data[4]):
        return _bag_ns(msg.data[0] + max(0.0, msg.data[4]))
    return message_time_ns(msg)


class Recorder(Node):
    """Subscribes to a contact_sim node's topics (and /clock) and writes them to a rosbag2 file.

    Each message is stored with its simulated time (message_time_ns) as the bag timestamp, so the
    bag's timeline is the simulation's even when the node runs faster than real time.
    """

    def __init__(self, output, storage='mcap', target=f'/{NODE_NAME}', clock=True, **kwargs):
        super().__init__('contact_sim_record', **kwargs)
        from .bag import BagWriter  # rosbags is needed only for recording
        self.bag = BagWriter(output, storage)
        target = '/' + target.strip('/')
        topics = [(f'{target}/{suffix}', msg_type) for suffix, msg_type in RECORDED_TOPICS]
        if clock:
            topics.append(('/clock', ClockMsg))
        for topic, msg_type in topics:
            events = SubscriptionEventCallbacks(matched=partial(self._on_matched, topic))
            self.create_subscription(msg_type, topic,
                                     partial(self._on_message, topic, type_name(msg_type)),
                                     RECORD_QOS, event_callbacks=events)
        self.topics = [topic for topic, _ in topics]
        self.covered_ns = {}   # topic -> simulated time (ns) its recorded messages reach
        self.publishers_matched = {}  # topic -> number of matched publishers
        self.cut_ns = None     # set at the stop: see cut()
        self.get_logger().info(f'recording {", ".join(self.topics)} to {self.bag.path} '
                               f'({storage})')

    def _on_matched(self, topic, status):
        self.publishers_matched[topic] = status.current_count
        if status.current_count_change > 0:
            self.get_logger().info(f'matched {topic}: {status.current_count} publisher(s)')

    def _on_message(self, topic, msgtype, msg):
        stamp, covered = message_time_ns(msg), covered_time_ns(msg)
        impact = isinstance(msg, Float64MultiArray)
        if impact and self.cut_ns is not None:  # stopping
            if stamp > self.cut_ns:
                return  # a contact that began after the stop
            self.cut_ns = max(self.cut_ns, covered)  # its whole contact goes in
        if topic not in self.bag.counts:
            self.get_logger().info(f'receiving {topic}')
        self.bag.write(topic, msgtype, stamp, serialize_message(msg))
        self.covered_ns[topic] = max(self.covered_ns.get(topic, 0), covered)
        if impact and len(msg.data):
            self.get_logger().debug(f'recorded the impact at t = {msg.data[0]:.9f} s')

    def cut(self):
        """At a stop: a predicate that holds once the bag is a consistent cut of the simulation.

        DDS delivers each topic in order but not in step with the others: when the stop comes,
        one topic can lag seconds behind (a backlog, or a lost sample waiting for its repair).
        The cut is the latest simulated time any of the node's topics has reached, an impact
        counting up to the end of its contact; it holds once every one of them with a matched
        publisher has reached it too, except the sparse ~/impact. An impact that arrives
        meanwhile and began before the cut moves it on to the end of its contact; one that
        began after it is not recorded. So every recorded impact has its whole wrench trace,
        and every continuous topic reaches the same simulated time. /clock, a global topic
        that another node may publish, neither sets the cut nor is waited for.
        """
        own = [ns for topic, ns in self.covered_ns.items() if topic != '/clock']
        if not own:
            return lambda: True
        self.cut_ns = max(own)
        behind = self.lagging()
        if behind:
            self.get_logger().info(f'stopping: waiting for {", ".join(behind)} to reach '
                                   f't = {self.cut_ns * 1e-9:.9f} s (Ctrl-C to stop now)')
        return lambda: not self.lagging()

    def lagging(self):
        """The continuous topics with a publisher whose messages do not reach the cut yet."""
        if self.cut_ns is None:
            return []
        return [topic for topic in self.topics if not topic.endswith('/impact')
                and topic != '/clock' and self.publishers_matched.get(topic, 0) > 0
                and self.covered_ns.get(topic, -1) < self.cut_ns]

    def close(self):
        self.bag.close()
        counts = ', '.join(f'{topic} {self.bag.counts.get(topic, 0)}' for topic in self.topics)
        self.get_logger().info(f'wrote {self.bag.path}: {counts}')


def record_parser():
    parser = argparse.ArgumentParser(
        prog='contact_sim_record',
        description='Record a contact_sim node\'s topics and /clock to a rosbag2 file (MCAP by '
                    'default) with the rosbags library; stop with Ctrl-C.')
    parser.add_argument('-o', '--output', default=None,
                        help='bag directory to create (default: contact_sim_YYYY_MM_DD-HH_MM_SS)')
    parser.add_argument('-s', '--storage', choices=('mcap', 'sqlite3'), default='mcap',
                        help='storage format (default: mcap)')
    parser.add_argument('--node', default=f'/{NODE_NAME}',
                        help='fully qualified name of the node to record (default: /contact_sim)')
    parser.add_argument('--no-clock', action='store_true', help='do not record /clock')
    parser.add_argument('--duration', type=float, default=None,
                        help='stop after this many wall-clock seconds (default: until Ctrl-C)')
    return parser


def record_main(args=None):
    """``contact_sim_record``: record until SIGINT/SIGTERM or --duration; exit code 0.

    ``args`` is a full argument vector like ``sys.argv`` (default: ``sys.argv``).
    """
    argv = sys.argv if args is None else args
    options = record_parser().parse_args(remove_ros_args(argv)[1:])
    output = options.output or time.strftime('contact_sim_%Y_%m_%d-%H_%M_%S')
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    recorder = None
    code = 0
    try:
        recorder = Recorder(output, options.storage, options.node, clock=not options.no_clock)
        if not spin_until_signal(recorder, stop_after=options.duration, drain=recorder.cut):
            recorder.get_logger().warning(
                f'stopped before {", ".join(recorder.lagging())} caught up: the bag ends '
                f'earlier on those topics')
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except ValueError as error:  # e.g. the output directory exists
        print(f'contact_sim_record: error: {error}', file=sys.stderr)
        code = 2
    finally:
        if recorder is not None:
            recorder.close()
            recorder.destroy_node()
        rclpy.try_shutdown()
    return code


if __name__ == '__main__':
    sys.exit(main())
