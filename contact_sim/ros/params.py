"""The node's parameters: their specs and descriptors, and the one place that turns parameter
values into the simulation's model (``build_model``).

``build_model(values)`` is the single entry point from parameter values (a dict name -> value) to
the validated ``Model`` the node runs; everything model-related the node does goes through it
(start-up, every set-parameters check, applying a change) and ``make_simulation``. It applies no
domain rule of its own: the contact from materials or overrides (``cs.build_contact``), the mass
from density (``cs.build_mass``), the ranges of the drop and the depth check (``cs.check_drop``,
run by ``cs.DropSimulation``) are the core library's, the same ones the command line uses. The
core refuses with an ``InputError`` keyed by its own field names; ``PARAMETER_KEYS`` spells them
as this node's parameters, so a refusal names the parameter the user set.

Flat plate: ``plate_radius`` 0.0 (the default) means a flat plate (R2 = inf); ``.inf`` is accepted
too, but 0.0 is what the node declares and dumps, because ``ros2 param dump`` writes ``.inf`` and
``ros2 param load`` then reads it back as a string.
"""
import math
from dataclasses import dataclass

from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor

import contact_sim as cs
from contact_sim.drop import GRAVITY_MAX, HEIGHT_MAX, VELOCITY_MAX
from contact_sim.flight import AIR_DENSITY
from contact_sim.model import DEFAULT_CONTACT, DENSITY_MIN, MODULUS_MIN
from contact_sim.drop import (TABLE_ACCELERATION_MAX, TABLE_AMPLITUDE_MAX, TABLE_FREQUENCY_MAX,
                              TABLE_FREQUENCY_MIN, TABLE_PHASE_MAX, table_transition,
                              vibrating_table)
from contact_sim.validation import InputError, require_positive, require_range

NODE_NAME = 'contact_sim'
# The node's own bounds, beyond the core's: values past them overflow the engine's scales (a
# stiffness of 1e308 N/m^n leaves no length scale to a contact phase), the stamps (int32 seconds)
# or the tick arithmetic (real_time_factor 1e9 is 1e7 s of simulated time a tick). The damping
# needs none: the core bounds it by its damping group (zeta <= 1e8).
MODULUS_MAX = 1e13            # Pa: 10 TPa, eight times diamond's
DENSITY_MAX = 1e5             # kg/m^3: four times osmium's
RADIUS_MAX = 10.0             # m, the sphere
PLATE_RADIUS_MAX = 1e6        # m, the struck sphere (0 = flat)
STIFFNESS_MAX = 1e20          # N/m^n
REAL_TIME_FACTOR_MAX = 1000.0  # above it, 0 or .inf: as fast as possible
# The node's floors: the smallest magnitude other than 0 it takes (issue 34: 5e-324 stopped the
# simulated clock, or was refused in the engine's words, "speed ... Z and T", "math domain
# error"). Below them a tick, an impact speed or a table's period is no longer a number the
# engine or the stamps (int32 seconds, ns) can hold; 0 keeps its own meaning (flat out, no
# gravity, at rest on the plate, Hertz, the fixed plate).
REAL_TIME_FACTOR_MIN = 1e-4   # a tick of 10 ns at 10 kHz: stamps (ns) still apart
GRAVITY_MIN = 1e-6            # m/s^2
HEIGHT_MIN = 1e-9             # m, with VELOCITY_MIN: an impact speed of at least ~1e-8 m/s
VELOCITY_MIN = 1e-9           # m/s
STIFFNESS_MIN = 1e-300        # N/m^n: below it the depth check itself underflows
RADIUS_MIN = 1e-12            # m, either sphere
FREQUENCY_MIN = TABLE_FREQUENCY_MIN   # Hz: the core's (a table's period, 1000 s, is its bridge)


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
    return (spec('youngs_modulus', "Young's modulus E [Pa]", (MODULUS_MIN, MODULUS_MAX),
                 '%g <= {} <= %g' % (MODULUS_MIN, MODULUS_MAX)),
            spec('poisson_ratio', 'Poisson ratio nu [-]', (-1.0, 0.5), '-1 < {} < 0.5'),
            spec('density', 'Density rho [kg/m^3]' + density_note, (DENSITY_MIN, DENSITY_MAX),
                 '%g <= {} <= %g' % (DENSITY_MIN, DENSITY_MAX)))


_LAWS = ', '.join(sorted(cs.LAWS))
_MATERIALS = ', '.join(sorted(cs.MATERIALS))
_DEFAULT = DEFAULT_CONTACT   # the core's default contact: the command line's too
_STEEL, _IRON = cs.MATERIALS[_DEFAULT.sphere], cs.MATERIALS[_DEFAULT.plate]   # the default pair
_CONTACT_NOTE = 'takes effect from the next contact phase'
_RESET_NOTE = 'takes effect at the next ~/reset'

PARAMETERS = (
    Spec('contact_law', _DEFAULT.law,
         f'Normal-force law F = k z^n + lambda z^p zdot^q (paper eq. 1); {_CONTACT_NOTE}',
         constraints=f'one of: {_LAWS}'),
    Spec('sphere_material', _DEFAULT.sphere,
         f'Material of the falling sphere: a library name or custom; elastic constants '
         f'{_CONTACT_NOTE}, a density-derived mass at the next ~/reset',
         constraints=f'one of: {_MATERIALS}, custom'),
    *_custom_material('sphere', _STEEL),
    Spec('sphere_radius', _DEFAULT.radius,
         f'Sphere radius R1 [m]; the Hertz stiffness {_CONTACT_NOTE}, a density-derived mass at '
         'the next ~/reset', (0.0, RADIUS_MAX),
         constraints=f'{RADIUS_MIN:g} <= sphere_radius <= {RADIUS_MAX:g}'),
    Spec('sphere_mass', 0.0,
         f'Sphere mass [kg]; 0 = from sphere density and radius, (4/3) pi R1^3 rho; {_RESET_NOTE}',
         (0.0, math.inf), constraints='0 <= sphere_mass < inf'),
    Spec('plate_material', _DEFAULT.plate,
         f'Material of the plate (or of the lower sphere); {_CONTACT_NOTE}',
         constraints=f'one of: {_MATERIALS}, custom'),
    *_custom_material('plate', _IRON, ' (the plate is immovable: its mass never enters)'),
    Spec('plate_radius', 0.0,
         f'Radius R2 of the body struck [m]: 0 = flat plate (R2 = inf), > 0 = a fixed second '
         f'sphere (1/R = 1/R1 + 1/R2, eq. 10); {_CONTACT_NOTE}', (0.0, PLATE_RADIUS_MAX),
         constraints=f'plate_radius = 0 (flat), or {RADIUS_MIN:g} <= plate_radius <= '
                     f'{PLATE_RADIUS_MAX:g}'),
    Spec('stiffness', 0.0,
         f'Stiffness override k [N/m^n]; 0 = Hertz, k = (4/3) E* sqrt(R) (eqs. 5, 6); '
         f'{_CONTACT_NOTE}', (0.0, STIFFNESS_MAX),
         constraints=f'stiffness = 0 (Hertz), or {STIFFNESS_MIN:g} <= stiffness <= '
                     f'{STIFFNESS_MAX:g}'),
    Spec('damping', 0.0,
         f'Damping override lambda [N s^q/m^(p+q)]; 0 = lambda* sqrt(R) (eq. 9); '
         f'{_CONTACT_NOTE}', (0.0, math.inf), constraints='0 <= damping < inf'),
    Spec('damping_factor', _DEFAULT.damping_factor,
         f'Damping factor lambda* [N s/m^(p+q+1/2)], N s/m^2 for azad_featherstone; used when '
         f'damping is 0; {_CONTACT_NOTE}', (0.0, math.inf),
         constraints='0 <= damping_factor < inf'),
    Spec('gravity', 9.81, f'Gravitational acceleration g, pulling the sphere down [m/s^2]; '
         f'{_RESET_NOTE}', (0.0, GRAVITY_MAX), constraints=f'gravity = 0, or {GRAVITY_MIN:g} <= gravity <= '
                                           f'{GRAVITY_MAX:g}'),
    Spec('initial_height', 1.0,
         f'Initial height of the sphere\'s lowest point above the plate [m]; {_RESET_NOTE}',
         (0.0, HEIGHT_MAX), constraints=f'initial_height = 0, or {HEIGHT_MIN:g} <= '
                                        f'initial_height <= {HEIGHT_MAX:g}'),
    Spec('initial_velocity', 0.0,
         f'Initial downward velocity [m/s] (> 0 = towards the plate); {_RESET_NOTE}',
         (-VELOCITY_MAX, VELOCITY_MAX),
         constraints=f'initial_velocity = 0, or {VELOCITY_MIN:g} <= |initial_velocity| <= '
                     f'{VELOCITY_MAX:g}'),
    Spec('air_density', AIR_DENSITY,
         f'Air density rho_air [kg/m^3] for the drag in flight (used when drag_coefficient > 0); '
         f'{_RESET_NOTE}', (0.0, 100.0), constraints='0 <= air_density <= 100'),
    Spec('drag_coefficient', 0.0,
         f'Drag coefficient C_d of the sphere [-]: quadratic air drag 1/2 rho_air C_d pi R1^2 v^2 '
         f'in flight (closed form; neglected during contact); 0 = vacuum; {_RESET_NOTE}',
         (0.0, 10.0), constraints='0 <= drag_coefficient <= 10'),
    Spec('plate_amplitude', 0.0,
         'Amplitude a of the vibrating table, p(t) = a sin(2 pi f t + phi), t the simulated '
         'time since the last ~/reset [m]; 0 = the fixed plate; takes effect at once (a C1 '
         'bridge over one period or longer, see README); > 0 (with plate_frequency > 0) takes '
         'the plate over from ~/plate_command',
         (0.0, TABLE_AMPLITUDE_MAX),
         constraints=f'0 <= plate_amplitude <= {TABLE_AMPLITUDE_MAX:g}, and plate_amplitude '
                     f'(2 pi plate_frequency)^2 <= {TABLE_ACCELERATION_MAX:g} m/s^2'),
    Spec('plate_frequency', 0.0, 'Frequency f of the vibrating table [Hz]; 0 = the fixed '
         'plate (as plate_amplitude 0); takes effect at once',
         (0.0, TABLE_FREQUENCY_MAX),
         constraints=f'plate_frequency = 0, or {FREQUENCY_MIN:g} <= plate_frequency <= '
                     f'{TABLE_FREQUENCY_MAX:g}'),
    Spec('plate_phase', 0.0, 'Phase phi of the vibrating table [rad]; takes effect at once',
         (-TABLE_PHASE_MAX, TABLE_PHASE_MAX),
         constraints='-2 pi <= plate_phase <= 2 pi'),
    Spec('publish_rate', 100.0,
         'Publish ticks per second [Hz]: wall-clock rate at a finite real_time_factor, simulated '
         'ticks per simulated second when real_time_factor is 0 or .inf',
         (0.1, 10000.0), read_only=True, constraints='0.1 <= publish_rate <= 10000'),
    Spec('real_time_factor', 1.0,
         'Simulated seconds per wall-clock second [-]; 0 (or .inf) = as fast as possible (each '
         'tick advances 1/publish_rate simulated seconds); takes effect at once',
         (0.0, math.inf), constraints=f'real_time_factor = 0 or .inf (as fast as possible), or '
                                 f'{REAL_TIME_FACTOR_MIN:g} <= real_time_factor <= '
                                 f'{REAL_TIME_FACTOR_MAX:g}'),
    Spec('frame_id', 'plate', 'frame_id of every stamped message: the plate frame, z up, the '
         'plate surface at z = 0', read_only=True, constraints='non-empty'),
    Spec('publish_clock', True, 'Publish the simulated time on /clock (rosgraph_msgs/Clock)',
         read_only=True),
)
PARAMETER_NAMES = tuple(spec.name for spec in PARAMETERS)
# the parameters with one of the node's own caps (MODULUS_MAX ...), which build_model checks (at
# start-up rclpy checks only the declared default)
_CAPS = (MODULUS_MAX, DENSITY_MAX, RADIUS_MAX, PLATE_RADIUS_MAX, STIFFNESS_MAX)
_CAPPED = tuple(spec for spec in PARAMETERS if spec.range is not None and spec.range[1] in _CAPS)


_FLOORS = {'gravity': GRAVITY_MIN, 'initial_height': HEIGHT_MIN, 'initial_velocity': VELOCITY_MIN,
           'stiffness': STIFFNESS_MIN, 'sphere_radius': RADIUS_MIN, 'plate_radius': RADIUS_MIN,
           'plate_frequency': FREQUENCY_MIN}
_FLOORED = tuple(spec for spec in PARAMETERS if spec.name in _FLOORS)


def _require_floor(spec, value):
    """Refuse a number other than 0 below the node's floor of ``spec`` (``_FLOORS``), naming
    the parameter's whole range (the core checks the rest)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) \
            and 0.0 < abs(value) < _FLOORS[spec.name]:
        raise InputError(spec.name, value, '{n[%s]} = {value} is out of range: allowed %s'
                         % (spec.name, spec.constraints), value=repr(value))


def _require_cap(spec, value):
    """Refuse a finite number above the cap of ``spec`` (the core checks the rest: type, sign,
    finiteness; ``plate_radius`` .inf is a flat plate), naming the parameter's whole range."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) \
            and spec.range[1] < value < math.inf:
        raise InputError(spec.name, value, '{n[%s]} = {value} is out of range: allowed %s'
                         % (spec.name, spec.constraints), value=repr(value))
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
    frame_id: str
    publish_clock: bool
    sphere: cs.Material
    plate: cs.Material
    plate_radius: float   # m, inf = flat
    drag: cs.AirDrag = None   # None = vacuum
    table: object = None      # the vibrating table (plate.SinusoidalPlate), None = fixed plate
    hertz: bool = True        # k from the materials (False: stiffness given, moduli unused)

    def summary(self):
        plate = 'flat plate' if math.isinf(self.plate_radius) \
            else f'sphere R2 = {self.plate_radius * 1e3:g} mm'
        drag = '' if self.drag is None else f', air drag C_d = {self.drag.drag_coefficient:g}'
        if self.table is not None:
            t = self.table
            drag += (f'; table a = {t.amplitude:g} m, f = {t.frequency:g} Hz, '
                     f'phi = {t.phase:g} rad (Gamma = {t.peak_acceleration_ratio(self.gravity or 9.81):.3g})')
        sphere = _named(self.sphere, self.hertz, self.mass, self.radius)
        return (f'{self.contact.law.name}: {sphere} sphere '
                f'R1 = {self.radius * 1e3:g} mm, '
                f'm = {self.mass * 1e3:.4g} g on {_named(self.plate, self.hertz)} {plate}; '
                f'k = {self.contact.stiffness:.4g} N/m^{self.contact.law.n:g}, '
                f'lambda = {self.contact.damping:.4g}; drop from {self.height:g} m at '
                f'{self.velocity:g} m/s, g = {self.gravity:g} m/s^2{drag}')


@dataclass(frozen=True)
class LoopSettings:
    """How the node's loop runs, apart from the physics: ``publish_rate`` (Hz) and
    ``real_time_factor`` (0 or inf: as fast as possible), validated by ``loop_settings``."""

    publish_rate: float
    real_time_factor: float

    @property
    def fast(self):
        """True when the simulation runs as fast as possible (real_time_factor 0 or inf)."""
        return self.real_time_factor == 0.0 or math.isinf(self.real_time_factor)

    @property
    def dt(self):
        """s of simulated time a tick: real_time_factor / publish_rate (1 / publish_rate when
        running as fast as possible)."""
        return (1.0 if self.fast else self.real_time_factor) / self.publish_rate


LOOP_PARAMETERS = ('publish_rate', 'real_time_factor')


def loop_settings(values):
    """The ``LoopSettings`` of parameter values (a dict name -> value); a refusal is a
    ValueError naming the parameter and its range, as ``build_model``'s."""
    try:
        return LoopSettings(
            publish_rate=require_range('publish_rate', values['publish_rate'], 0.1, 10000.0),
            real_time_factor=real_time_factor(values['real_time_factor']))
    except InputError as error:
        raise ValueError(refusal(error, values)) from None


def _named(material, hertz, mass=None, radius=None):
    """A material as the log names it: a library name, or a custom one with the constants the
    model used (its moduli only where the stiffness is Hertz's, ``hertz``)."""
    if material.name in cs.MATERIALS:
        return material.name
    density = f'density {material.density:.4g}' if mass is None else \
        f'mean density {mass / (4.0 / 3.0 * math.pi * radius ** 3):.4g}'
    moduli = (f'E = {material.youngs_modulus:.3g} Pa, nu = {material.poisson_ratio:g}, '
              if hertz else '')
    return f'custom ({moduli}{density} kg/m^3)'



# The core's field keys (cs.InputError.field) as this node's parameters spell them; keys that are
# parameter names already (stiffness, damping, damping_factor, gravity, plate_radius, ...) need
# no entry.
PARAMETER_KEYS = {'law': 'contact_law', 'sphere': 'sphere_material', 'plate': 'plate_material',
                  'radius': 'sphere_radius', 'mass': 'sphere_mass', 'height': 'initial_height',
                  'velocity': 'initial_velocity', 'amplitude': 'plate_amplitude',
                  'frequency': 'plate_frequency', 'phase': 'plate_phase'}
_MATERIAL_FIELDS = ('youngs_modulus', 'poisson_ratio', 'density')


def refusal(error, values):
    """The core's refusal in this node's words: the parameter names, and what a 0 means here."""
    text = error.render(PARAMETER_KEYS)
    field = error.field
    if field == 'mass':
        text += (', or sphere_mass = 0 for the mass from sphere density and radius'
                 if values.get('sphere_mass') != 0.0 else
                 ' (sphere_mass = 0: the mass is (4/3) pi R1^3 rho from sphere_radius and the '
                 'sphere density)')
    elif field == 'stiffness' and values.get('stiffness') == 0.0:
        text += (" (stiffness = 0: k is the Hertz stiffness from the materials' moduli and "
                 'Poisson ratios and the radii)')
    elif field == 'damping' and values.get('damping') == 0.0:
        text += ' (damping = 0: lambda = damping_factor sqrt(R), eq. 9)'
    elif field == 'plate_radius':
        text += ', or plate_radius = 0 for a flat plate'
    elif field == 'gravity' and values.get('drag_coefficient', 0.0) > 0.0:
        text += '; drag_coefficient = 0 turns the air drag off'
    elif field == 'gravity' and values.get('plate_amplitude', 0.0) > 0.0:
        text += '; plate_amplitude = 0 stops the vibrating table'
    return text


def _material(values, body):
    """The ``body`` material; its custom constants are checked even when a library one is used."""
    try:
        custom = cs.Material(f'custom_{body}', *(values[f'{body}_{f}'] for f in _MATERIAL_FIELDS))
    except InputError as error:
        raise (error.rekeyed(f'{body}_{error.field}') if error.field in _MATERIAL_FIELDS
               else error) from None
    name = values[f'{body}_material']
    if name == 'custom':
        return custom
    if name not in cs.MATERIALS:
        key = f'{body}_material'
        raise InputError(key, name, '{n[%s]} = {value} is unknown: allowed one of %s or custom '
                         '(then %s_youngs_modulus, %s_poisson_ratio and %s_density apply)'
                         % (key, _MATERIALS, body, body, body), value=repr(name))
    return cs.MATERIALS[name]


def _drag(values, radius):
    """The air drag of the flights (``cs.AirDrag``), or None for the vacuum (C_d = 0)."""
    drag = cs.AirDrag(values['air_density'], values['drag_coefficient'], radius)
    return drag if drag.active else None


def _build_model(values):
    """Validate parameter values (a dict name -> value) and build the Model (InputError keyed by
    the core's field names on a refusal)."""
    for spec in _CAPPED:
        _require_cap(spec, values[spec.name])
    for spec in _FLOORED:
        _require_floor(spec, values[spec.name])
    radius = require_positive('radius', values['sphere_radius'])
    plate_radius = flat_or_radius(values['plate_radius'])
    sphere = _material(values, 'sphere')
    plate = _material(values, 'plate')
    damping = values['damping']
    contact = cs.build_contact(
        values['contact_law'], stiffness=values['stiffness'] or None,      # 0 = Hertz
        damping=damping or None, damping_factor=None if damping else values['damping_factor'],
        sphere=sphere, plate=plate, radius=radius, plate_radius=plate_radius)
    frame_id = values['frame_id']
    if not isinstance(frame_id, str) or not frame_id.strip():
        raise InputError('frame_id', frame_id, '{n[frame_id]} = {value} is invalid: allowed a '
                         'non-empty string', value=repr(frame_id))
    model = Model(
        contact=contact, mass=cs.build_mass(values['sphere_mass'] or None, sphere, radius),
        radius=radius, gravity=values['gravity'], height=values['initial_height'],
        velocity=values['initial_velocity'], frame_id=frame_id, publish_clock=bool(values['publish_clock']),
        sphere=sphere, plate=plate, plate_radius=plate_radius, drag=_drag(values, radius),
        table=vibrating_table(values['plate_amplitude'], values['plate_frequency'],
                              values['plate_phase']),
        hertz=not values['stiffness'])
    # the engine's checks (ranges of the drop, the depth check) build the drop: it is kept, to
    # run from the next ~/reset (or at once, at the start)
    return model, make_simulation(model)


def real_time_factor(value):
    """``real_time_factor``: 0 or inf (as fast as possible), or REAL_TIME_FACTOR_MIN <= value
    <= REAL_TIME_FACTOR_MAX."""
    if isinstance(value, float) and value in (0.0, math.inf):
        return value
    if isinstance(value, (int, float)) and not isinstance(value, bool) \
            and (REAL_TIME_FACTOR_MAX < value < math.inf or 0.0 < value < REAL_TIME_FACTOR_MIN):
        raise InputError('real_time_factor', value, '{n[real_time_factor]} = {value} is out of '
                         f'range: allowed {REAL_TIME_FACTOR_MIN:g} <= real_time_factor <= '
                         f'{REAL_TIME_FACTOR_MAX:g}, or 0 or .inf (as fast as possible)',
                         value=repr(value))
    return require_range('real_time_factor', value, 0.0, REAL_TIME_FACTOR_MAX)


def flat_or_radius(value):
    """``plate_radius`` -> R2 in m: 0.0 (or inf) = a flat plate, inf; else a positive radius."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0.0:
        return math.inf
    return require_positive('plate_radius', value, allow_inf=True)


def build_model(values):
    """The validated ``Model`` of parameter values (``build``'s, without its drop)."""
    return build(values)[0]


def build(values):
    """Validate parameter values (a dict name -> value) once and build what they make: the
    ``Model`` and a fresh drop from it (``make_simulation``: the engine's own checks), which the
    node keeps to run from its next ~/reset (at the start, at once). A refusal is a ValueError
    naming the parameter, its value and the allowed range (the core's message, see
    ``refusal``). The loop's settings (``LOOP_PARAMETERS``) are ``loop_settings``'."""
    try:
        return _build_model(values)
    except InputError as error:
        raise ValueError(refusal(error, values)) from None
    except ArithmeticError as error:
        def departure(name):   # orders of magnitude away from the default
            value, default = values[name], DEFAULTS[name]
            if isinstance(value, bool) or not isinstance(value, float) or not value > 0.0 \
                    or not isinstance(default, float) or not 0.0 < default < math.inf:
                return -1.0
            return abs(math.log10(value / default))
        name = max(DEFAULTS, key=departure)
        raise ValueError(f'{name} = {values[name]!r} overflows the model ({error}): allowed '
                         f'physically sensible magnitudes') from None


def awaiting_stiffness(values, running):
    """A law without a Hertz stiffness (``linear``, n = 1) set while ``stiffness`` is 0: the
    values to validate (the law of ``running``, the ``Model`` running, in its place) and the
    note saying so; else ``(values, None)``.

    ``ros2 param load`` sets a dump's parameters one at a time in alphabetical order, so a
    linear contact's ``contact_law`` comes before its ``stiffness``: taken alone it is refused
    ("stiffness is missing"), and the load went on with the wrong law. The law is accepted
    and waits for its stiffness; every other parameter is checked meanwhile with the law
    running.
    """
    law = cs.LAWS.get(values['contact_law']) if isinstance(values['contact_law'], str) else None
    if law is None or law.hertz or values['stiffness'] != 0.0 \
            or law == running.contact.law:
        return values, None
    note = (f'contact_law = {law.name!r} waits for its stiffness (n = {law.n:g} has no Hertz '
            f'stiffness; stiffness = 0): the contact stays {running.contact.law.name} until '
            'stiffness is set')
    return {**values, 'contact_law': running.contact.law.name}, note


def check_running(sim, model, values, previous):
    """Check ``model`` against the running drop ``sim`` (its initial conditions bound the energy
    until the next ~/reset), ``previous`` being the Model running: the new contact over the plate
    as it will move (``table_motion``, bridge included, if the table changes), as
    ``sim.set_contact`` will take it, and a changed table with the contacts the drop has now, as
    ``sim.set_plate`` will; ValueError as build_model."""
    try:
        changed = model.table != previous.table
        plate = table_motion(sim, previous.table, model.table) if changed else sim.plate
        sim.check(model.contact, plate=plate)
        if changed:
            sim.check_plate(plate)
    except InputError as error:
        raise ValueError('the running drop (until ~/reset) refuses it: '
                         f'{refusal(error, values)}') from None


def table_motion(sim, old, new):
    """The plate's motion from now on when the table changes from ``old`` to ``new``
    (``SinusoidalPlate`` or ``None``): the running plate bridged to the new table
    (``plate.table_transition``)."""
    return table_transition(sim.time, sim.plate, new, old.frequency if old is not None else 0.0)


def make_simulation(model):
    """A fresh drop at t = 0 from the model's initial conditions (the engine checks them)."""
    return cs.DropSimulation(model.contact, model.mass, model.height, velocity=model.velocity,
                             gravity=model.gravity, radius=model.radius, drag=model.drag,
                             plate=model.table)


