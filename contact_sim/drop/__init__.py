"""A sphere dropped on a plate, fixed or moving, until it rests: the steppable drop engine (an
explicit state machine: ``engine``, its modes ``mode_*``, its ``transitions`` table, its
``records`` and ``limits``), the plate's motions (``plate``), the vibrating-table studies and
sweeps."""
from contact_sim.drop.engine import DropSimulation, simulate_drop
from contact_sim.drop.limits import GRAVITY_MAX, HEIGHT_MAX, VELOCITY_MAX, check_drop
from contact_sim.drop.plate import (FIXED, TABLE_ACCELERATION_MAX, TABLE_AMPLITUDE_MAX,
                                    TABLE_FREQUENCY_MAX, TABLE_PHASE_MAX, CommandedPlate,
                                    FixedPlate, PlateMotion, SinusoidalPlate, SwitchedPlate,
                                    command_motion, sphere_motion, table_transition,
                                    vibrating_table)
from contact_sim.drop.records import (Advance, DropResult, DropState, ImpactRecord, Recorder,
                                      Samples, TickBatch)
from contact_sim.drop.sweep import bifurcation_diagram, sweep
from contact_sim.drop.table import (VibratingTable, period_doubling_threshold, period_one_phase,
                                    period_one_threshold)

__all__ = ['FIXED', 'GRAVITY_MAX', 'HEIGHT_MAX', 'TABLE_ACCELERATION_MAX', 'TABLE_AMPLITUDE_MAX',
           'TABLE_FREQUENCY_MAX', 'TABLE_PHASE_MAX', 'VELOCITY_MAX', 'Advance', 'CommandedPlate',
           'DropResult', 'DropSimulation', 'DropState', 'FixedPlate', 'ImpactRecord',
           'PlateMotion', 'Recorder', 'Samples',
           'SinusoidalPlate', 'SwitchedPlate', 'TickBatch', 'VibratingTable',
           'bifurcation_diagram', 'check_drop', 'command_motion', 'period_doubling_threshold',
           'period_one_phase', 'period_one_threshold', 'simulate_drop', 'sphere_motion', 'sweep',
           'table_transition', 'vibrating_table']
