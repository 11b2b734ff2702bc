"""A sphere dropped on a plate, fixed or moving, until it rests: the steppable drop engine (an
explicit state machine: ``engine``, its modes ``mode_*``, its ``transitions`` table, its
``records`` and ``limits``), the plate's motions (``plate``), the vibrating-table studies and
sweeps.

The engine (``engine``) is event-driven and steppable.  The motion goes through modes, each an
object in its own module with one small interface (``mode.Mode``: its state, how far it goes
alone, ``advance`` until its next event):

* ``mode_flight.Flight`` (the clamped force is zero): in closed form with no integrator steps,
  the time at which the force switches on again planned by the plate (``plate.flights``):
  ballistic or with drag by the quadratic formula on the fixed plate, by the first root of the
  gap over a moving one; event ``touch``;
* ``mode_contact.InContact`` (a contact phase): integrated exactly (``phase.PhaseFactory``: compiled DOP853, or the
  reference ``phase.PhaseIntegrator`` where stiff), the plate's acceleration as forcing, up to
  the located lift-off; events ``lift_off``, ``knot`` (the plate's forcing changes), ``landed``
  (the contact became permanent: the same phase goes on), ``settled``, ``carried``;
* ``mode_rest.Rest`` (the fixed plate): once the energy above static equilibrium is too small
  for the force ever to vanish again (permanent contact) and the oscillation amplitude about the
  static deflection z₀ = (m g / k)^(1/n) has decayed below ``settle_tolerance * z₀``, the motion
  is the linearised damped oscillator about z₀, in closed form, so a resting sphere costs nothing
  to advance;
* ``mode_carried.Carried`` (a moving plate): quasi-static while the plate's acceleration is
  above -g/2; event ``released``.

The speed is in the compiled kernels each mode calls (a phase's integrator steps, a flight's
plan), not in a second machine: every bounce goes through these modes and the table.

What follows an event is looked up in one table, ``transitions.TRANSITIONS``, whose entries make
every successor (no mode builds the one that follows it) and write what the drop records of the
event to one ledger, ``records.Recorder`` (impacts, the landing for good, the rest, apexes and
integrator steps).  The fixed plate is the
plate motion that does not move (``plate.FixedPlate``), answering the modes' questions in closed
form: there is one machine for every plate.

To add a mode (two spheres, friction, a plate that is a robot's tool): write it in a new module
``mode_<name>.py`` as a ``mode.Mode`` (``state``, ``states``, ``until``, ``advance`` returning a
``mode.Move`` with the ``mode.Event`` that ends it, ``steps``, ``in_contact``, ``carried``), and
add its rows to ``transitions.TRANSITIONS``: the events that lead into it, from it (each entry
makes the next mode and records what the event adds to the ``Recorder``), and what the changes
from outside (``set_contact``, ``set_plate``) do to it.

``DropSimulation.advance(t)`` moves to time t and returns what happened on the way, so the same
engine serves a batch run (``simulate_drop``) and a real-time loop.  Units: SI; z > 0 is
penetration, ż > 0 is downward motion (approach), height above the plate is -z.
"""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``)
_EXPORTS = {
    'engine': ('DropSimulation',),
    'simulate': ('simulate_drop',),
    'limits': ('GRAVITY_MAX', 'HEIGHT_MAX', 'VELOCITY_MAX', 'check_drop'),
    'plate': ('FIXED', 'TABLE_ACCELERATION_MAX', 'TABLE_AMPLITUDE_MAX', 'TABLE_FREQUENCY_MAX',
              'TABLE_FREQUENCY_MIN', 'TABLE_PHASE_MAX', 'CommandedPlate', 'FixedPlate', 'PlateMotion',
              'SinusoidalPlate', 'SwitchedPlate', 'command_motion', 'sphere_motion', 'table_transition',
              'vibrating_table'),
    'records': ('AdvanceResult', 'DropResult', 'DropState', 'ImpactRecord', 'Recorder', 'Samples',
                'TickBatch'),
    'sweeps': ('bifurcation_diagram', 'sweep'),
    'table': ('VibratingTable', 'period_doubling_threshold', 'period_one_phase',
              'period_one_threshold'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['FIXED', 'GRAVITY_MAX', 'HEIGHT_MAX', 'TABLE_ACCELERATION_MAX', 'TABLE_AMPLITUDE_MAX',
           'TABLE_FREQUENCY_MAX', 'TABLE_FREQUENCY_MIN', 'TABLE_PHASE_MAX', 'VELOCITY_MAX',
           'AdvanceResult', 'CommandedPlate',
           'DropResult', 'DropSimulation', 'DropState', 'FixedPlate', 'ImpactRecord',
           'PlateMotion', 'Recorder', 'Samples',
           'SinusoidalPlate', 'SwitchedPlate', 'TickBatch', 'VibratingTable',
           'bifurcation_diagram', 'check_drop', 'command_motion', 'period_doubling_threshold',
           'period_one_phase', 'period_one_threshold', 'simulate_drop', 'sphere_motion', 'sweep',
           'table_transition', 'vibrating_table']
