"""The coupling in MuJoCo: ``CoupledContacts(model, data, pairs).step()`` in place of ``mj_step``.

Each pair names a sphere geom and another geom (a plane, a box, a mesh or another sphere).  At
every step, between ``mj_step1`` (positions, velocities, MuJoCo's own collisions) and
``mj_step2`` (forces, constraints, the integrator):

* the gap along the normal from MuJoCo's geometry (``mj_geomDistance``); the normal is the
  plane's axis, the line of centres of two spheres, or from the other geom's nearest point to
  the sphere's centre;
* the contact point's relative velocity and its Jacobian (``mj_jac`` on both bodies); for free
  bodies the effective mass along the normal 1 / (n J M⁻¹ Jᵀ n) (``mj_solveM``) and the rest of
  the system's normal acceleration n J q̈_smooth (``mj_fwdActuation``, ``mj_fwdAcceleration``:
  gravity, actuators, passive and applied forces);
* for bodies whose kinematic trees bear on MuJoCo's own constraints (a constraint island:
  ``data.tree_island``) or carry damping the integrator takes implicitly, both measured on
  MuJoCo's own step instead: ``mj_step2`` run as a trial and the state put back
  (``mj_getState``/``mj_setState``), without the coupled forces (the acceleration, with the
  constraint forces and the implicit terms) and with a probe impulse along Jᵀ n (the effective
  mass), along the tangents too when the point slides and friction is on; joint damping is
  taken at the exact contact's rate, and over a contact as its exact impulse -c Δgap.  J̇q̇ is
  left out (measured worse with it: the semi-implicit host moves the gap along its curvature);
* ``contact_sim.coupling.NormalCoupling`` gives the normal impulse of the step, friction its
  tangential impulse (``friction_impulse``), and Jᵀ(impulse / dt) is added to ``qfrc_applied``
  for ``mj_step2`` (and taken off again after it: the user's own ``qfrc_applied`` stays).

MuJoCo's own contact of a coupled sphere is switched off by setting its geom's ``contype`` and
``conaffinity`` to 0: the sphere then collides in MuJoCo with nothing, and every geom it may
touch must be named in a pair.  The Euler, implicit and implicitfast integrators step positions
with the new velocities, as the coupling assumes; RK4 (which ``mj_step2`` does not run) is
refused.  Units: SI.
"""
import math

import mujoco
import numpy as np

from contact_sim.coupling.core import NormalCoupling
from contact_sim.coupling.mujoco_model import damped, moves, normal_damping, turns
from contact_sim.coupling.rows import (pair_rows, refuse_repeated, refuse_stack,
                                       refuse_tunnel, tangential_impulse, tangents)
from contact_sim.model import require_contact
from contact_sim.validation import InputError, require_nonnegative, require_positive

# a pair whose gap is beyond this (m) and that carries no state is not looked at further
REACH = 0.05
# an explicit contact pair's margin (m) that no distance falls below: the pair is switched off
_NEVER = -1e10
_SPHERE, _PLANE = int(mujoco.mjtGeom.mjGEOM_SPHERE), int(mujoco.mjtGeom.mjGEOM_PLANE)
# what a trial of MuJoCo's step changes and is restored after it
_STATE = int(mujoco.mjtState.mjSTATE_FULLPHYSICS | mujoco.mjtState.mjSTATE_WARMSTART)
# the smallest speed (m/s) whose impulse probes MuJoCo's response along a normal
_PROBE_SPEED = 1e-3
# a contact point sliding slower than this (m/s) on a measured pair gets no friction that step
# (its tangential response is not measured: two trials of MuJoCo's step saved)
_STILL = 1e-9
# the last step's push is applied along its own direction when that differs from this step's by
# more than this (relative): a centred sphere's stays on this step's
_TURNED = 1e-9
_SERVED = {int(mujoco.mjtIntegrator.mjINT_EULER), int(mujoco.mjtIntegrator.mjINT_IMPLICIT),
           int(mujoco.mjtIntegrator.mjINT_IMPLICITFAST)}


class _Pair:
    """One coupled pair: the sphere geom, the other geom, their bodies and the coupling."""

    def __init__(self, model, sphere, other, contact, index):
        self.sphere, self.other = sphere, other
        self.body_s, self.body_o = int(model.geom_bodyid[sphere]), int(model.geom_bodyid[other])
        self.radius = float(model.geom_size[sphere, 0])
        self.other_type = int(model.geom_type[other])
        self.coupling = NormalCoupling(contact)
        self.index = index
        nv = model.nv
        self.jac_s, self.jac_o = np.zeros((3, nv)), np.zeros((3, nv))
        self.jacr = np.zeros((3, nv))
        self.response = np.zeros((3, nv))
        self.fromto = np.zeros(6)
        self.far = False            # out of reach at the last step
        self.trees = [int(model.body_treeid[b]) for b in (self.body_s, self.body_o)
                      if model.body_treeid[b] >= 0]
        self.damped = damped(model, self.trees)
        # whether the last step's push may be due along another direction than this step's
        self.turns = turns(model, sphere) or turns(model, other)
        self.damping = np.array([model.dof_damping[i] if int(model.dof_treeid[i]) in self.trees
                                 else 0.0 for i in range(nv)])
        self.exact_rate = None      # the exact gap rate at the step's start, m/s, if carried
        self.pending = 0.0          # the damping's correction of the gap rate due at lift-off
        self.along_normal = None    # (n J, n J M⁻¹, n J M⁻¹ Jᵀ n) of the step's push
        # (N·s, normal, the contact point's offsets from the bodies' centres of mass) the last
        # step's contact force leaves to this step, with the direction it had then
        self.held = None
        self.jac_held = np.zeros((3, nv))
        self.solved = np.zeros((1, nv))


class CoupledContacts:
    """MuJoCo stepped with the package's exact contacts between named geom pairs.

    Parameters
    ----------
    model : mujoco.MjModel
        The model (its coupled spheres' ``contype`` and ``conaffinity`` are set to 0).
    data : mujoco.MjData
        The data the steps advance.
    pairs : sequence of (str, str, Contact)
        (geom, geom, contact): one of the two a sphere geom, the other a plane, box, mesh or
        sphere geom, by name.
    friction : float, optional
        Coulomb's μ of every pair, >= 0 (default 0: frictionless).
    reach : float, optional
        A pair farther apart than this (m) and carrying no contact state costs one distance
        query a step; > 0 (default ``REACH``).  It must exceed the distance a body closes in
        one step.

    Raises
    ------
    InputError
        Keyed ``pairs`` (not a sequence of (name, name, Contact), a name of no geom, no sphere
        in a pair, both geoms on bodies without degrees of freedom, both on one body, a pair
        named twice), ``friction``, ``reach`` or ``integrator`` (RK4: the step this coupling
        cannot serve); at ``step``, keyed ``pairs`` when two pairs push at once on a body
        along lines that move each other's gap (a stack of balls).

    Examples
    --------
    >>> import mujoco
    >>> import contact_sim as cs
    >>> from contact_sim.coupling.mujoco import CoupledContacts
    >>> xml = '''<mujoco><option timestep="0.001"/><worldbody>
    ...   <geom name="floor" type="plane" size="1 1 0.1"/>
    ...   <body pos="0 0 0.1"><freejoint/><geom name="ball" type="sphere" size="0.0127"
    ...     mass="0.0669"/></body></worldbody></mujoco>'''
    >>> model = mujoco.MjModel.from_xml_string(xml)
    >>> data = mujoco.MjData(model)
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> coupled = CoupledContacts(model, data, [('ball', 'floor', contact)])
    >>> for _ in range(300):
    ...     coupled.step()
    >>> impact = coupled.impacts[0]
    >>> print(f"{impact.speed_in:.3f} m/s in, e = {impact.restitution:.3f}")
    1.309 m/s in, e = 0.726
    """

    def __init__(self, model, data, pairs, friction=0.0, reach=REACH):
        if int(model.opt.integrator) not in _SERVED:
            raise InputError('integrator', model.opt.integrator,
                             '{n[integrator]} = {value}: allowed Euler, implicit or implicitfast '
                             '(RK4 evaluates the forces four times a step; the coupling gives one '
                             'impulse a step)', value=str(mujoco.mjtIntegrator(model.opt.integrator)))
        self.model, self.data = model, data
        self.friction = require_nonnegative('friction', friction)
        self.reach = require_positive('reach', reach)
        rows = pair_rows(pairs, '(geom, geom, Contact)')
        self.pairs = [self._pair(row, i) for i, row in enumerate(rows)]
        refuse_repeated([frozenset((p.sphere, p.other)) for p in self.pairs], rows)
        spheres = {pair.sphere for pair in self.pairs}
        for pair in self.pairs:
            model.geom_contype[pair.sphere] = 0
            model.geom_conaffinity[pair.sphere] = 0
        for i in range(model.npair):    # explicit <contact><pair>s ignore contype: never within
            if {int(model.pair_geom1[i]), int(model.pair_geom2[i])} & spheres:   # this margin
                model.pair_margin[i] = _NEVER
        self._applied = np.zeros(model.nv)
        self._user_applied = np.zeros(model.nv)
        self._saved = np.empty(mujoco.mj_stateSize(model, _STATE))
        self._smooth = self._base = None
        self._damped = any(pair.damped for pair in self.pairs)

    def _pair(self, row, index):
        model = self.model
        if len(row) != 3:
            raise InputError('pairs', row, '{n[pairs]}[%d] = {value}: allowed a (geom, geom, '
                             'Contact) triple' % index)
        ids = []
        for name in row[:2]:
            gid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, str(name)) \
                if isinstance(name, str) else -1
            if gid < 0:
                raise InputError('pairs', name, '{n[pairs]}[%d] names {value}, which is no geom '
                                 'of the model: allowed the names of its geoms' % index)
            ids.append(gid)
        contact = require_contact(row[2], 'pairs')
        types = [int(model.geom_type[g]) for g in ids]
        if _SPHERE not in types:
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value} has no sphere geom: '
                             'allowed a sphere against a plane, box, mesh or sphere' % index)
        sphere, other = (ids[0], ids[1]) if types[0] == _SPHERE else (ids[1], ids[0])
        if types[0] == _SPHERE and types[1] == _SPHERE and model.body_dofnum[
                model.geom_bodyid[ids[0]]] == 0:
            sphere, other = ids[1], ids[0]
        dofs = [int(model.body_dofnum[model.geom_bodyid[g]]) for g in ids]
        moving = [moves(model, int(model.geom_bodyid[g])) for g in ids]
        if not any(moving):
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value}: neither geom\'s body '
                             'has a degree of freedom (body dofs %s): allowed a pair that can '
                             'move' % (index, dofs))
        if model.geom_bodyid[ids[0]] == model.geom_bodyid[ids[1]]:
            raise InputError('pairs', row[:2], '{n[pairs]}[%d] = {value}: both geoms are on the '
                             'same body: allowed geoms of two bodies' % index)
        return _Pair(model, sphere, other, contact, index)

    @property
    def impacts(self):
        """Every impact of every pair so far (``CoupledImpact``), in time order."""
        return sorted((i for p in self.pairs for i in p.coupling.impacts), key=lambda i: i.time)

    def step(self):
        """One MuJoCo step with the coupled contacts (in place of ``mujoco.mj_step``)."""
        m, d = self.model, self.data
        mujoco.mj_step1(m, d)
        near = []
        for pair in self.pairs:
            dist = mujoco.mj_geomDistance(m, d, pair.sphere, pair.other, self.reach,
                                          pair.fromto)
            if dist >= self.reach and not pair.coupling.carrying:
                pair.far, pair.held = True, None
                continue
            if pair.far and dist < 0.0:
                refuse_tunnel(pair.index, dist, self.reach)
            pair.far = False
            near.append((pair, dist))
        if not near:
            mujoco.mj_step2(m, d)
            return
        applied = self._applied
        applied[:] = 0.0
        if (self._damped or d.nefc) and any(self._measured(pair) for pair, _ in near):
            base = self._host_velocity()
        else:
            base = None
            self._smooth = self._smooth_acceleration()
        pushing = [pair for pair, dist in near if self._couple(pair, dist, base, applied)]
        if len(pushing) > 1:
            _refuse_coupled(pushing)
        d.qfrc_applied += applied
        try:
            mujoco.mj_step2(m, d)
        finally:
            d.qfrc_applied -= applied

    def _measured(self, pair):
        """Whether the pair's response is measured on MuJoCo's own step: its bodies bear on other
        constraints (their kinematic trees are in a constraint island) or velocity-dependent
        forces the integrator takes implicitly (damping, implicit actuators)."""
        if pair.damped:
            return True
        d = self.data
        if d.nefc == 0:
            return False
        if d.nisland == 0:          # islands off: any constraint may bear on the pair
            return True
        return any(d.tree_island[tree] >= 0 for tree in pair.trees)

    def _smooth_acceleration(self):
        """The unconstrained acceleration q̈_smooth (without the coupled forces)."""
        m, d = self.model, self.data
        mujoco.mj_fwdActuation(m, d)
        mujoco.mj_fwdAcceleration(m, d)
        return d.qacc_smooth.copy()

    def _host_velocity(self, force=None):
        """The velocities MuJoCo's own step (``mj_step2``: constraints, integrator) ends with,
        without the coupled forces and with the generalized ``force`` (N, N·m) added; the state
        is restored after it."""
        m, d = self.model, self.data
        if force is None:       # the first trial of the step: keep the state and the user's load
            mujoco.mj_getState(m, d, self._saved, _STATE)
            self._user_applied[:] = d.qfrc_applied
        else:
            d.qfrc_applied += force
        try:
            mujoco.mj_step2(m, d)
            return d.qvel.copy()
        finally:
            mujoco.mj_setState(m, d, self._saved, _STATE)
            d.qfrc_applied[:] = self._user_applied

    def _trial_response(self, row, impulse):
        """The change of MuJoCo's step-end velocities per unit impulse along ``row`` (J^T n, a
        generalized direction), measured with ``impulse`` (N·s) applied over the step."""
        dt = self.model.opt.timestep
        moved = self._host_velocity(row * (impulse / dt))
        return (moved - self._base) / impulse

    def _couple(self, pair, dist, base, applied):
        m, d = self.model, self.data
        dt = m.opt.timestep
        centre = d.geom_xpos[pair.sphere]
        normal = self._normal(pair, centre)
        point = centre - pair.radius * normal
        mujoco.mj_jac(m, d, pair.jac_s, pair.jacr, point, pair.body_s)
        if pair.body_o:         # the sphere's point relative to the other's
            mujoco.mj_jac(m, d, pair.jac_o, pair.jacr, point, pair.body_o)
            jac = pair.jac_s - pair.jac_o
        else:                   # the world does not move
            jac = pair.jac_s
        response = pair.response
        mujoco.mj_solveM(m, d, response, jac)      # M⁻¹ Jᵀ, row by row
        inverse = jac @ response.T                  # J M⁻¹ Jᵀ (3 x 3)
        along = inverse @ normal                    # the point's velocity per unit impulse
        w_n = float(normal @ along)
        if not w_n > 0.0:
            raise InputError('pairs', pair.index, '{n[pairs]}[{value}]: the contact point cannot '
                             'move along the normal (no degree of freedom): allowed a pair whose '
                             'bodies can move apart')
        velocity = jac @ d.qvel
        row = normal @ jac
        gap_rate = float(normal @ velocity)
        extra = 0.0             # N·s along the normal beside the contact's (damping, below)
        if base is None:        # free bodies: M⁻¹ and q̈_smooth
            acceleration = jac @ self._smooth
            moved = normal @ response
            gap_acceleration = float(normal @ acceleration)
        else:                   # measured on MuJoCo's own step (constraints, integrator)
            self._base = base
            acceleration = jac @ ((base - d.qvel) / dt)
            gap_acceleration = float(normal @ acceleration)
            probe = max(abs(gap_rate), abs(gap_acceleration) * dt, _PROBE_SPEED) / w_n
            damping = normal_damping(pair, normal @ response, w_n)
            moved = self._trial_response(row, probe)
            along = jac @ moved
            w_n = float(normal @ along)
            if not w_n > 0.0:
                raise InputError('pairs', pair.index, '{n[pairs]}[{value}]: the contact point '
                                 'does not move along the normal when pushed in MuJoCo\'s step '
                                 '(held by its constraints): allowed a pair whose bodies can '
                                 'move apart')
            if damping > 0.0:   # the host damps its own rate at the step's end; the exact
                end = gap_rate + gap_acceleration * dt      # contact's is damped instead
                mean = end if pair.exact_rate is None else pair.exact_rate
                shift = damping * (end - mean)
                gap_acceleration += shift
                extra = shift * dt / w_n
        step = pair.coupling.step(float(d.time), float(dist), gap_rate, 1.0 / w_n,
                                  gap_acceleration, dt)
        if base is not None:
            correction = 0.0
            if damping > 0.0 and step.touched:  # a damping ∝ the rate: -c Δgap over the step,
                pair.pending -= damping * (-step.penetration - dist - mean * dt)  # given at
                if not step.in_contact:                 # the lift-off (a kick of the host's
                    correction, pair.pending = pair.pending, 0.0    # gap inside a contact
                    extra += correction / w_n                       # would change its e)
            if pair.coupling.carrying:
                pair.exact_rate = -step.penetration_rate + correction
            else:
                pair.exact_rate, pair.pending = None, 0.0
        held, pair.held = pair.held, None
        if base is None and step.remainder > 0.0 and pair.turns:
            pair.held = (step.remainder, normal, point - d.xipos[pair.body_s],
                         point - d.xipos[pair.body_o])
        turned = None           # the last step's remainder along the direction it had then
        if held is not None and base is None and (step.impulse > 0.0 or not step.touched):
            turned = self._turned(pair, held, row, w_n, step, jac, along)
        if turned is None and step.impulse == 0.0 and extra == 0.0:
            return False
        pair.along_normal = (row, moved, w_n)
        impulse = (step.impulse + extra) * normal
        normal_impulse = step.impulse
        if turned is None:
            kick = step.impulse * along         # the contact point's velocity change
        else:
            push, kick, normal_impulse = turned
            impulse = np.zeros(3)
            applied += push / dt
        if self.friction > 0.0 and normal_impulse > 0.0:    # Coulomb's, from the velocity
            free = velocity + dt * acceleration + kick  # without friction
            if base is not None:
                slide = free - float(free @ normal) * normal
                sliding = float(slide @ slide) > _STILL * _STILL
                if sliding:     # else no friction, and no tangential trials
                    inverse = self._measured_inverse(jac, normal, along,
                                                     self.friction * step.impulse)
            if base is None or sliding:
                impulse = impulse + tangential_impulse(normal_impulse, free, normal, inverse,
                                                       self.friction)
        applied += jac.T @ (impulse / dt)
        return step.impulse > 0.0

    def _turned(self, pair, held, row, w_n, step, jac, along):
        """The step's normal push (a generalized impulse, N·s) and the contact point's velocity
        change when the part the last step's contact force leaves to it (``held``) is applied as
        the momentum it made then: the last step's force along its normal, at its contact
        point's offset from each body's centre of mass held in the world (a spinning body's
        Jacobian turns within a step); the rest along this step's n J, so the gap's change is
        the coupling's.  None when that direction is this step's (a centred sphere)."""
        m, d = self.model, self.data
        remainder, normal, offset_s, offset_o = held
        mujoco.mj_jac(m, d, pair.jac_held, None, d.xipos[pair.body_s] + offset_s, pair.body_s)
        direction = normal @ pair.jac_held
        if pair.body_o:
            mujoco.mj_jac(m, d, pair.jac_held, None, d.xipos[pair.body_o] + offset_o,
                          pair.body_o)
            direction = direction - normal @ pair.jac_held
        if not np.max(np.abs(direction - row)) > _TURNED * np.max(np.abs(row)):
            return None
        mujoco.mj_solveM(m, d, pair.solved, direction.reshape(1, -1))
        cross = float(row @ pair.solved[0])     # the gap's rate per unit held impulse
        if not cross > 0.0:
            return None
        kick = jac @ pair.solved[0]             # the point's velocity per unit held impulse
        if not step.touched:    # in flight all the step: the last impact's remainder alone (the
            return remainder * direction, remainder * kick, remainder   # gap's acceleration
        carried = min(remainder, step.impulse * w_n / cross)   # changed with the spin the
        fresh = step.impulse - cross * carried / w_n            # impact gave)
        return (carried * direction + fresh * row, carried * kick + fresh * along,
                step.impulse)

    def _measured_inverse(self, jac, normal, along, probe):
        """The contact point's 3 x 3 velocity per unit impulse (1/kg) on MuJoCo's own step, from
        ``along`` (the normal's, measured) and two trials along the tangents (``probe`` N·s)."""
        basis = np.vstack((normal, tangents(normal)))
        columns = [along] + [jac @ self._trial_response(t @ jac, probe) for t in basis[1:]]
        return np.column_stack(columns) @ basis

    def _normal(self, pair, centre):
        """The unit normal from the other geom to the sphere."""
        d = self.data
        if pair.other_type == _PLANE:
            return d.geom_xmat[pair.other].reshape(3, 3)[:, 2].copy()
        if pair.other_type == _SPHERE:
            n = centre - d.geom_xpos[pair.other]
        else:       # from the other geom's nearest point (fromto's second half: the sphere is
            n = centre - pair.fromto[3:]    # passed first) to the sphere's centre
        length = math.sqrt(float(n @ n))
        return n / length if length > 0.0 else np.array([0.0, 0.0, 1.0])


def _refuse_coupled(pushing):
    """Refuse two pairs pushing in one step whose normal impulses move each other's gap: each
    is integrated alone, and together they would pump energy in (a stack of balls)."""
    for k, first in enumerate(pushing):
        row, _, w_first = first.along_normal
        for second in pushing[k + 1:]:
            _, moved, w_second = second.along_normal
            refuse_stack(first.index, second.index, float(row @ moved), w_first, w_second)


def coupled_restitution(contact, radius, mass, speeds, timestep, integrator='implicitfast'):
    """The e(v) the coupling gives in MuJoCo: a free sphere thrown at a plane, gravity off, one
    throw a speed (``contact-sim audit mujoco ... --coupled``).

    Parameters
    ----------
    contact : Contact
        The contact coupled in.
    radius, mass : float
        The sphere's radius (m) and mass (kg), > 0.
    speeds : array_like of float
        Impact speeds, m/s, > 0.
    timestep : float
        MuJoCo's step, s, > 0.
    integrator : str, optional
        'Euler', 'implicit' or 'implicitfast' (default).

    Returns
    -------
    numpy.ndarray
        e at each speed: the rebound speed over the impact speed, read from MuJoCo's velocity a
        whole step after the impact.

    Examples
    --------
    >>> import contact_sim as cs
    >>> from contact_sim.coupling.mujoco import coupled_restitution
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> e = coupled_restitution(contact, 0.0127, 0.0674, [0.1, 1.0], 1e-3)
    >>> print(f"{e[0]:.4f} {e[1]:.4f}")
    0.8220 0.7381
    """
    radius, mass = require_positive('radius', radius), require_positive('mass', mass)
    timestep = require_positive('timestep', timestep)
    out = []
    for speed in np.atleast_1d(np.asarray(speeds, dtype=float)).tolist():
        speed = require_positive('speeds', speed)
        xml = (f'<mujoco><option timestep="{timestep!r}" gravity="0 0 0" integrator='
               f'"{integrator}"/><worldbody><geom name="floor" type="plane" size="1 1 0.1"/>'
               f'<body pos="0 0 {radius + 3.5 * speed * timestep!r}"><freejoint/><geom '
               f'name="ball" type="sphere" size="{radius!r}" mass="{mass!r}"/></body>'
               '</worldbody></mujoco>')
        model = mujoco.MjModel.from_xml_string(xml)
        data = mujoco.MjData(model)
        data.qvel[2] = -speed
        coupled = CoupledContacts(model, data, [('ball', 'floor', contact)])
        for _ in range(1_000_000):
            coupled.step()
            if coupled.pairs[0].coupling.impacts:
                break
        coupled.step()          # a whole step of flight: MuJoCo's velocity is the exact one
        out.append(data.qvel[2] / speed)
    return np.array(out)
