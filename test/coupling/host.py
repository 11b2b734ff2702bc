"""A minimal host for the coupling's tests: one body along the normal, stepped as MuJoCo's Euler,
PyBullet and Drake's discrete plant step it (semi-implicit Euler: the new velocity moves the
position), the coupling's impulse applied as impulse / dt over the step."""
import numpy as np


def run_host(coupling, mass, gap, gap_rate, acceleration, dt, steps, t0=0.0):
    """Step the host ``steps`` times from the gap (m) and its rate (m/s) under a constant
    ``acceleration`` of the gap (m/s²); returns (times, gaps, rates, impulses) after each step."""
    out = np.empty((4, steps))
    y, v, t = float(gap), float(gap_rate), float(t0)
    for i in range(steps):
        step = coupling.step(t, y, v, mass, acceleration, dt)
        v = v + acceleration * dt + step.impulse / mass
        y = y + dt * v
        t = t0 + (i + 1) * dt
        out[:, i] = t, y, v, step.impulse
    return out


def apexes(times, gaps, impacts, count):
    """The highest gap between successive impacts (m), for the first ``count`` of them."""
    touch = [i.time for i in impacts]
    return [float(gaps[(times > touch[k]) & (times < touch[k + 1])].max()) for k in range(count)]
