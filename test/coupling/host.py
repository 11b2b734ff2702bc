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


def run_continuous_host(coupling, mass, gap, gap_rate, acceleration, dt, steps, t0=0.0):
    """As ``run_host`` for a host that integrates the step's force exactly: the force
    impulse / dt + force_rate (t - t₀ - dt/2) under the constant acceleration, in closed form."""
    out = np.empty((4, steps))
    y, v, t = float(gap), float(gap_rate), float(t0)
    for i in range(steps):
        step = coupling.step(t, y, v, mass, acceleration, dt)
        mean, rate = step.impulse / dt / mass, step.force_rate / mass
        # y'' = acceleration + mean + rate (s - dt/2), s from 0 to dt (the force pushes +gap)
        y = y + v * dt + 0.5 * (acceleration + mean) * dt * dt + rate * dt ** 3 * (1 / 6 - 1 / 4)
        v = v + (acceleration + mean) * dt
        t = t0 + (i + 1) * dt
        out[:, i] = t, y, v, step.impulse
    return out
