"""The plate under the sphere: its motions (``motions``: the protocol, the fixed plate, the
vibrating table and its settings, a switch, the sphere's absolute motion over the plate;
``commanded``: set-points), the changes of motion at a time (``commands``: the table's bridge,
trajectory commands), the flights over it (``flights``) and the root searches they use
(``roots``; ``compiled_flight``: the same searches in numba for the vibrating table, a commanded
plate and the fixed plate)."""
from contact_sim.drop.plate.commanded import CommandedPlate
from contact_sim.drop.plate.commands import (BRIDGE_SPEED_MAX, BRIDGE_TIME, COMMAND_ACCELERATION_MAX,
                                             COMMAND_HORIZON, COMMAND_POSITION_MAX,
                                             COMMAND_STOP_TIME, COMMAND_VELOCITY_MAX, Command,
                                             bridge_time, command_motion, table_transition)
from contact_sim.drop.plate.flights import touch_time
from contact_sim.drop.plate.motions import (FIXED, TABLE_ACCELERATION_MAX, TABLE_AMPLITUDE_MAX,
                                            TABLE_FREQUENCY_MAX, TABLE_FREQUENCY_MIN,
                                            TABLE_PHASE_MAX, FixedPlate, PlateMotion,
                                            SinusoidalPlate, SwitchedPlate, as_plate,
                                            sphere_motion, vibrating_table)
from contact_sim.drop.plate.roots import EPS, first_gap_root, first_upward_root

__all__ = ['BRIDGE_SPEED_MAX', 'BRIDGE_TIME', 'COMMAND_ACCELERATION_MAX', 'COMMAND_HORIZON',
           'COMMAND_POSITION_MAX', 'COMMAND_STOP_TIME', 'COMMAND_VELOCITY_MAX', 'EPS', 'FIXED',
           'TABLE_ACCELERATION_MAX', 'TABLE_AMPLITUDE_MAX', 'TABLE_FREQUENCY_MAX',
           'TABLE_FREQUENCY_MIN', 'TABLE_PHASE_MAX', 'Command', 'CommandedPlate', 'FixedPlate', 'PlateMotion',
           'SinusoidalPlate', 'SwitchedPlate', 'as_plate', 'bridge_time', 'command_motion',
           'first_gap_root', 'first_upward_root', 'sphere_motion', 'table_transition',
           'touch_time', 'vibrating_table']
