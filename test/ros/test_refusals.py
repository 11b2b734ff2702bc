"""``RefusalLog`` without ROS: a burst of refusals is one warning and then the count of the rest
(issue 22: a second bad trajectory within a second was dropped without a log line)."""
from contact_sim.ros.refusals import RefusalLog


class Lines:
    def __init__(self):
        self.lines = []

    def warning(self, text):
        self.lines.append(text)


def test_refusals_held_back_are_counted_in_the_log():
    now, out = [0.0], Lines()
    log = RefusalLog(out, '~/plate_command', clock=lambda: now[0])
    for _ in range(4):
        log.refused('~/plate_command refused: bad')
    assert out.lines == ['~/plate_command refused: bad']
    log.flush()                       # the period is not over: nothing yet
    now[0] = 1.0
    log.flush()
    assert out.lines[1] == '~/plate_command: 3 more refused in the last 1 s'
    log.flush()                       # counted once
    assert len(out.lines) == 2
    log.refused('~/plate_command refused: a')     # within the period of the count line
    now[0] = 2.5
    log.refused('~/plate_command refused: b')
    log.refused('~/plate_command refused: c')
    now[0] = 3.5
    log.refused('~/plate_command refused: d')
    held = ' (1 more ~/plate_command refused in the last 1 s)'
    assert out.lines[2:] == ['~/plate_command refused: b' + held,
                             '~/plate_command refused: d' + held]
