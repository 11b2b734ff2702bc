"""The node's parameters: their specs and descriptors, and the one place that turns parameter
values into the simulation's model (``build_model``).

``build_model(values)`` is the single entry point from parameter values (a dict name -> value) to
the validated ``Model`` the node runs; everything model-related the node does goes through it
(start-up, every set-parameters check, applying a change) and ``make_simulation``. The domain
rules it applies (contact from materials, mass from density, ``require_shallow_contact``, ranges)
are today's, kept here as they were in ``contact_sim/node.py``; switching them to the core
library's API is a change of this module only.

Flat plate: ``plate_radius`` 0.0 (the default) means a flat plate (R2 = inf); ``.inf`` is accepted
too, but 0.0 is what the node declares and dumps, because ``ros2 param dump`` writes ``.inf`` and
``ros2 param load`` then reads it back as a string.
"""
import math
import re
from dataclasses import dataclass

from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor

import contact_sim as cs
from contact_sim.validation import require_nonnegative, require_positive, require_range, \
    require_real

NODE_NAME = 'contact_sim'
INF = math.inf


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
    Spec('plate_radius', 0.0,
         f'Radius R2 of the body struck [m]: 0 = flat plate (R2 = inf), > 0 = a fixed second '
         f'sphere (1/R = 1/R1 + 1/R2, eq. 10); {_CONTACT_NOTE}', (0.0, INF),
         constraints='plate_radius = 0 (flat) or 0 < plate_radius'),
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
         'Simulated seconds per wall-clock second [-]; 0 (or .inf) = as fast as possible (each '
         'tick advances 1/publish_rate simulated seconds); takes effect at once',
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
    plate_radius = flat_or_radius(values['plate_radius'])
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


def flat_or_radius(value):
    """``plate_radius`` -> R2 in m: 0.0 (or inf) = a flat plate, inf; else a positive radius."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0.0:
        return INF
    return require_positive('plate_radius', value, allow_inf=True)


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


