"""The audit of a user's MuJoCo model: the contact a sphere geom makes with the model's floor,
read as the model has it (both geoms' solref, solimp, solmix, priority, margin and gap, the
model's time step and integrator), and the e(v) MuJoCo gives it: the ball thrown at a plane
carrying the floor's own contact attributes, gravity off, so that MuJoCo applies its own
combination rules (``combined`` states them: a higher priority wins whole; at equal priority
solimp is mixed by solmix, solref too in the standard form, the smaller element-wise in the
direct form; margin and gap are the larger)."""
from dataclasses import dataclass


from contact_sim.export import mujoco_engine
from contact_sim.validation import InputError

# MuJoCo's integrator enum -> its MJCF name
INTEGRATORS = {'mjINT_EULER': 'Euler', 'mjINT_RK4': 'RK4', 'mjINT_IMPLICIT': 'implicit',
               'mjINT_IMPLICITFAST': 'implicitfast'}
# a geom's contact attributes, as the audit's throw copies them
ATTRIBUTES = ('solref', 'solimp', 'solmix', 'priority', 'margin', 'gap')
DEFAULT_FLOOR = {'solref': (0.02, 1.0), 'solimp': (0.9, 0.95, 0.001, 0.5, 2.0), 'solmix': 1.0,
                 'priority': 0, 'margin': 0.0, 'gap': 0.0}   # MuJoCo's defaults


@dataclass(frozen=True)
class GeomContact:
    """What a user's MuJoCo model gives a sphere geom's contact: its radius (m), its body's mass
    (kg), ``solref``, ``solimp``, the model's time step (s) and integrator, the ball's and the
    floor's contact attributes (dicts keyed as ``ATTRIBUTES``) and the floor's name (None: no
    plane on the world body, MuJoCo's default floor is used)."""

    radius: float
    mass: float
    solref: tuple
    solimp: tuple
    timestep: float
    integrator: str
    ball: dict = None
    floor: dict = None
    floor_name: object = None

    def combined(self):
        """(solref, solimp, margin, gap) of the pair by MuJoCo's rules (mj_contactParam)."""
        ball, floor = self.ball or self.attributes(), self.floor or DEFAULT_FLOOR
        margin, gap = max(ball['margin'], floor['margin']), max(ball['gap'], floor['gap'])
        if ball['priority'] != floor['priority']:
            win = ball if ball['priority'] > floor['priority'] else floor
            return tuple(win['solref']), tuple(win['solimp']), margin, gap
        m1, m2 = ball['solmix'], floor['solmix']
        tiny = 1e-15   # MuJoCo's mjMINVAL
        mix = (m1 / (m1 + m2) if m1 >= tiny and m2 >= tiny else 0.5 if m1 < tiny and m2 < tiny
               else 0.0 if m1 < tiny else 1.0)
        if ball['solref'][0] > 0 and floor['solref'][0] > 0:
            solref = tuple(mix * a + (1 - mix) * b for a, b in zip(ball['solref'], floor['solref']))
        else:
            solref = tuple(min(a, b) for a, b in zip(ball['solref'], floor['solref']))
        solimp = tuple(mix * a + (1 - mix) * b for a, b in zip(ball['solimp'], floor['solimp']))
        return solref, solimp, margin, gap

    def attributes(self):
        """The ball's contact attributes (MuJoCo's defaults where the audit has none)."""
        return {**DEFAULT_FLOOR, 'solref': self.solref, 'solimp': self.solimp}

    def describe(self):
        """Lines: the geom's and the floor's contact as MuJoCo reads them, and the pair's."""
        solref, solimp, margin, gap = self.combined()
        floor = (f'floor {self.floor_name!r} (the first plane on the world body)'
                 if self.floor_name is not None else
                 "floor: none in the model (no plane on the world body): MuJoCo's default plane")
        return [f'ball: {_text(self.ball or self.attributes())}, timestep = {self.timestep:g} s, '
                f'integrator {self.integrator}, R = {self.radius:g} m, m = {self.mass:.6g} kg',
                f'{floor}: {_text(self.floor or DEFAULT_FLOOR)}',
                f'the pair, by MuJoCo\'s rules: solref = {_numbers(solref)}, solimp = '
                f'{_numbers(solimp)}, margin = {margin:g} m, gap = {gap:g} m']


def _numbers(values):
    return '[' + ', '.join(f'{x:.6g}' for x in values) + ']'


def _text(attributes):
    return ', '.join(f'{key} = {_numbers(value) if isinstance(value, tuple) else f"{value:g}"}'
                     for key, value in attributes.items())


def _geom_attributes(model, index):
    """A geom's contact attributes (``ATTRIBUTES``) as the compiled ``model`` has them."""
    return {'solref': tuple(map(float, model.geom_solref[index])),
            'solimp': tuple(map(float, model.geom_solimp[index])),
            'solmix': float(model.geom_solmix[index]),
            'priority': int(model.geom_priority[index]),
            'margin': float(model.geom_margin[index]), 'gap': float(model.geom_gap[index])}


def mjcf(attributes):
    """The MJCF attributes of a geom's contact."""
    return ' '.join(f'{key}="{" ".join(f"{x!r}" for x in value)}"' if isinstance(value, tuple)
                    else f'{key}="{value!r}"' for key, value in attributes.items())


def geom_contact(path, geom):
    """The contact of the sphere ``geom`` (a name) on a free body in the MJCF file ``path``,
    with the floor it falls on: the first plane geom on the world body.

    Raises
    ------
    InputError
        Keyed ``model`` if the file does not load, ``geom`` if the geom is not a sphere of it
        or its body is not free (welded to the world or jointed).
    """
    mujoco = mujoco_engine._mujoco()
    mujoco_engine.quiet()
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as error:   # MuJoCo's parse and compile errors
        raise InputError('model', path, '{n[model]} = {value} does not load in MuJoCo: '
                         f'{str(error).strip()}', value=repr(str(path))) from None
    index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    if index < 0 or model.geom_type[index] != mujoco.mjtGeom.mjGEOM_SPHERE:
        raise InputError('geom', geom, '{n[geom]} = {value} is not a sphere geom of the model: '
                         'allowed the name of a sphere geom on a free body', value=repr(geom))
    body = int(model.geom_bodyid[index])
    joint = int(model.body_jntadr[body])
    if model.body_jntnum[body] != 1 or model.jnt_type[joint] != mujoco.mjtJoint.mjJNT_FREE:
        raise InputError('geom', geom, '{n[geom]} = {value} is on a body without a free joint '
                         '(welded to the world or to another body, or jointed): it cannot be '
                         'thrown; allowed the name of a sphere geom on a body with a '
                         '<freejoint/>', value=repr(geom))
    integrator = mujoco.mjtIntegrator(model.opt.integrator).name
    if integrator not in INTEGRATORS:
        raise InputError('model', path, '{n[model]} = {value} uses the integrator '
                         f'{integrator}: allowed ' + ', '.join(INTEGRATORS.values()),
                         value=repr(str(path)))
    planes = [g for g in range(model.ngeom) if model.geom_bodyid[g] == 0
              and model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE]
    floor = _geom_attributes(model, planes[0]) if planes else None
    floor_name = (mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, planes[0]) or
                  f'#{planes[0]} (unnamed)') if planes else None
    ball = _geom_attributes(model, index)
    return GeomContact(float(model.geom_size[index][0]), float(model.body_mass[body]),
                       ball['solref'], ball['solimp'], float(model.opt.timestep),
                       INTEGRATORS[integrator], ball, floor, floor_name)


def audit(contact, speeds):
    """MuJoCo's e at ``speeds`` (m/s) of a ``GeomContact``: the ball, with its own contact
    attributes, thrown at a plane with the floor's (MuJoCo's defaults if the model has no
    floor), gravity off, as ``mujoco_engine.measure``: the throw starts and ends beyond the
    pair's margin."""
    ball = mjcf(contact.ball or contact.attributes())
    floor = mjcf(contact.floor) if contact.floor is not None else ''
    return mujoco_engine.measure(contact.radius, contact.mass, speeds, contact.timestep, ball,
                                 contact.integrator, floor, margin=contact.combined()[2])
