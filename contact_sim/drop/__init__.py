"""A sphere dropped on a plate, fixed or moving, until it rests: the steppable drop engine, the
plate's motions, the vibrating-table studies and sweeps."""
from contact_sim.drop.engine import (GRAVITY_MAX, HEIGHT_MAX, VELOCITY_MAX, Advance, DropResult,
                                     DropSimulation, DropState, ImpactRecord, Samples, TickBatch,
                                     check_drop, simulate_drop)
from contact_sim.drop.plate import (TABLE_ACCELERATION_MAX, TABLE_AMPLITUDE_MAX,
                                    TABLE_FREQUENCY_MAX, TABLE_PHASE_MAX, CommandedPlate,
                                    PlateMotion, SinusoidalPlate, SwitchedPlate, command_motion,
                                    sphere_motion, table_transition, vibrating_table)
from contact_sim.drop.sweep import bifurcation_diagram, sweep
from contact_sim.drop.table import (VibratingTable, period_doubling_threshold, period_one_phase,
                                    period_one_threshold)

__all__ = ['GRAVITY_MAX', 'HEIGHT_MAX', 'TABLE_ACCELERATION_MAX', 'TABLE_AMPLITUDE_MAX',
           'TABLE_FREQUENCY_MAX', 'TABLE_PHASE_MAX', 'VELOCITY_MAX', 'Advance', 'CommandedPlate',
           'DropResult', 'DropSimulation', 'DropState', 'ImpactRecord', 'PlateMotion', 'Samples',
           'SinusoidalPlate', 'SwitchedPlate', 'TickBatch', 'VibratingTable',
           'bifurcation_diagram', 'check_drop', 'command_motion', 'period_doubling_threshold',
           'period_one_phase', 'period_one_threshold', 'simulate_drop', 'sphere_motion', 'sweep',
           'table_transition', 'vibrating_table']
