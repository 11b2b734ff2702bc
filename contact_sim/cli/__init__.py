"""The ``contact-sim`` command line: one module per subcommand over the core library."""
from contact_sim.cli.app import main

__all__ = ['main']
