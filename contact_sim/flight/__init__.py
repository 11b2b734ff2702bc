"""Flights between contacts, in closed form: ballistic, and with linear and quadratic air drag."""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``): ``drag`` (numpy
# only) holds the flights and the air's defaults the command line shows
_EXPORTS = {
    'drag': ('AIR_DENSITY', 'SPHERE_DRAG_COEFFICIENT', 'AirDrag', 'FlightPath',
             'contact_drag_impulse_ratio', 'fall_time', 'flight_to_plate'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['AIR_DENSITY', 'SPHERE_DRAG_COEFFICIENT', 'AirDrag', 'FlightPath',
           'contact_drag_impulse_ratio', 'fall_time', 'flight_to_plate']
