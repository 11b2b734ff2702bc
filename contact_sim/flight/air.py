"""The air a sphere flies through, by default: its density and a smooth sphere's drag coefficient.

Apart from ``drag`` (its root search imports scipy's solvers) so that the command line can show
the defaults in its help without importing them.
"""
AIR_DENSITY = 1.204          # kg/m³: dry air at 20 °C and 101.325 kPa
SPHERE_DRAG_COEFFICIENT = 0.47   # smooth sphere, subcritical Reynolds number (1e3 - 2e5)
