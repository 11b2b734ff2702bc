"""The calibration's defaults that the command line shows in its help.

Apart from ``glitches`` (which imports the bounce model, hence the impact engine) so that the
command line can build its parsers without importing the engine.
"""
MICRO_BOUNCE_RATIO = 0.016   # contact time / flight time beyond which clicks are left out
