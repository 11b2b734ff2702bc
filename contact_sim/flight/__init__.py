"""Flights between contacts, in closed form: ballistic, and with linear and quadratic air drag."""
from contact_sim.flight.drag import (AIR_DENSITY, SPHERE_DRAG_COEFFICIENT, AirDrag, FlightPath,
                                     contact_drag_impulse_ratio, fall_time, flight_to_plate)

__all__ = ['AIR_DENSITY', 'SPHERE_DRAG_COEFFICIENT', 'AirDrag', 'FlightPath',
           'contact_drag_impulse_ratio', 'fall_time', 'flight_to_plate']
