"""The ROS domains of a test run: each one claimed for this process alone, never the caller's.

A test run must not reach outside itself (issue 33, item 2): a user's node on this machine in the
same domain discovers the tests' nodes even with localhost-only discovery, and then the tests
would set its parameters and read its topics (and it theirs). So every domain a test uses is

* not the caller's (``ROS_DOMAIN_ID`` as it was when pytest started, 0 when unset);
* not in use on this machine: no UDP port of the domain's range is bound (a DDS participant of
  domain d binds ports 7400 + 250 d ... + 249, Fast DDS's and the RTPS standard's well-known
  ports; ``/proc/net/udp`` and ``udp6``), whoever runs it;
* not claimed by another test process: each id has a lock file in the temporary directory,
  locked (``fcntl.flock``) by the process that claimed it until that process ends, so xdist
  workers and concurrent runs (other checkouts too) take different ids, and a killed run leaves
  no stale claim.

Ids come from the ranges ROS 2 documents as safe on Linux (1-101, 215-232; see "The ROS_DOMAIN_ID"
in the ROS 2 docs). ``isolated_env`` adds localhost-only discovery, no static peers, and drops
the variables that would send discovery elsewhere (a discovery server, an XML profile).
"""
import fcntl
import os
import random
import tempfile
from pathlib import Path

CALLER_ENV = dict(os.environ)   # at the first import, before any fixture changes os.environ
POOL = (*range(1, 102), *range(215, 233))
LOCK_DIR = Path(tempfile.gettempdir()) / 'contact_sim_test_domains'
PORT_BASE, DOMAIN_GAIN = 7400, 250   # RTPS well-known ports: PB + DG * domain + offsets
# variables that would make a test's participant discover or be discovered beyond this machine
# or this domain: a discovery server, a super client, XML profiles with their own peers
DROPPED = ('ROS_DISCOVERY_SERVER', 'ROS_SUPER_CLIENT', 'FASTRTPS_DEFAULT_PROFILES_FILE',
           'FASTDDS_DEFAULT_PROFILES_FILE', 'RMW_FASTRTPS_USE_QOS_FROM_XML', 'CYCLONEDDS_URI',
           'ROS_LOCALHOST_ONLY')
_held = {}   # domain id -> open lock file, for the life of this process


def callers_domain(environ=None):
    """The caller's domain id (an int): its ``ROS_DOMAIN_ID``, or 0 (ROS's default) unset."""
    value = (CALLER_ENV if environ is None else environ).get('ROS_DOMAIN_ID', '').strip()
    return int(value) if value.isdigit() else 0


def bound_udp_ports():
    """The UDP ports bound on this machine (IPv4 and IPv6), from ``/proc/net``."""
    ports = set()
    for name in ('udp', 'udp6'):
        try:
            lines = Path('/proc/net', name).read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            local = line.split()[1]
            ports.add(int(local.rsplit(':', 1)[1], 16))
    return ports


def in_use(domain, ports=None):
    """Whether a DDS participant on this machine has bound a port of ``domain``'s range."""
    ports = bound_udp_ports() if ports is None else ports
    low = PORT_BASE + DOMAIN_GAIN * domain
    return any(low <= port < low + DOMAIN_GAIN for port in ports)


def claim_domain(exclude=()):
    """A domain id for this process alone (see the module's docstring), held until it ends.

    Parameters
    ----------
    exclude : iterable of int
        Ids not to take besides the caller's.

    Returns
    -------
    int
    """
    LOCK_DIR.mkdir(exist_ok=True)
    skip = {callers_domain(), *exclude}
    ports = bound_udp_ports()
    start = random.Random(os.getpid()).randrange(len(POOL))
    for domain in POOL[start:] + POOL[:start]:
        if domain in skip or domain in _held or in_use(domain, ports):
            continue
        lock = open(LOCK_DIR / f'{domain}.lock', 'a')
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            lock.close()
            continue
        if in_use(domain):   # taken meanwhile by a process that takes no lock
            lock.close()
            continue
        _held[domain] = lock
        return domain
    raise RuntimeError(f'no free ROS domain among {len(POOL)} (all in use or claimed)')


def isolated_env(domain, base):
    """``base`` with ``ROS_DOMAIN_ID`` = ``domain``, localhost-only discovery and no static
    peers, and without the variables of ``DROPPED``."""
    env = {key: value for key, value in base.items() if key not in DROPPED}
    env.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST',
               ROS_STATIC_PEERS='')
    return env
