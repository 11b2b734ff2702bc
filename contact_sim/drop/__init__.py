"""A sphere dropped on a plate, fixed or moving, until it rests: the steppable drop engine, the
plate's motions, the vibrating-table studies and sweeps."""
from contact_sim.drop.engine import (Advance, DropResult, DropSimulation, DropState, ImpactRecord,
                                     Samples, TickBatch, check_drop, simulate_drop)
from contact_sim.drop.plate import CommandedPlate, PlateMotion, SinusoidalPlate, SwitchedPlate
from contact_sim.drop.sweep import bifurcation_diagram, sweep
from contact_sim.drop.table import (VibratingTable, period_doubling_threshold, period_one_phase,
                                    period_one_threshold)

__all__ = ['Advance', 'CommandedPlate', 'DropResult', 'DropSimulation', 'DropState',
           'ImpactRecord', 'PlateMotion', 'Samples', 'SinusoidalPlate', 'SwitchedPlate',
           'TickBatch', 'VibratingTable', 'bifurcation_diagram', 'check_drop',
           'period_doubling_threshold', 'period_one_phase', 'period_one_threshold',
           'simulate_drop', 'sweep']
