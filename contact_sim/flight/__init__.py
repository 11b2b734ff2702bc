"""Flights between contacts, in closed form: ballistic, and with linear and quadratic air drag."""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``): ``air`` holds the
# defaults the command line shows, ``drag`` the flights (scipy's root search)
_EXPORTS = {
    'air': ('AIR_DENSITY', 'SPHERE_DRAG_COEFFICIENT'),
    'drag': ('AirDrag', 'FlightPath', 'contact_drag_impulse_ratio', 'fall_time',
             'flight_to_plate'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['AIR_DENSITY', 'SPHERE_DRAG_COEFFICIENT', 'AirDrag', 'FlightPath',
           'contact_drag_impulse_ratio', 'fall_time', 'flight_to_plate']
