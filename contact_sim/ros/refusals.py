"""Refusals logged at most once a period, the ones held back counted: a burst of bad inputs
gives one warning and then "3 more refused in the last second", never silence."""
import time

REFUSAL_PERIOD = 1.0   # s of wall time between two refusal warnings of one kind
SHORT = 200            # characters of a client's text quoted in a refusal


def shorten(text, limit=SHORT):
    """``text`` cut to ``limit`` characters, saying how long it was (a client's text in a log).

    Examples
    --------
    >>> from contact_sim.ros.refusals import shorten
    >>> shorten('abc')
    'abc'
    >>> shorten('x' * 1000, 10)
    'xxxxxxxxxx... (1000 characters)'
    """
    text = str(text)
    return text if len(text) <= limit else f'{text[:limit]}... ({len(text)} characters)'


class ClientError(ValueError):
    """A client's input the node cannot take, its message naming the field and the limit: a
    refusal quotes it as it is (any other error is quoted with its type)."""


def reason(error):
    """The refusal's text for ``error``, shortened (``shorten``).

    Examples
    --------
    >>> from contact_sim.ros.refusals import ClientError, reason
    >>> reason(ClientError('names has 2000 entries: allowed at most 1000 a request'))
    'names has 2000 entries: allowed at most 1000 a request'
    >>> reason(ZeroDivisionError('division by zero'))
    'ZeroDivisionError: division by zero'
    """
    return shorten(str(error) if isinstance(error, ClientError)
                   else f'{type(error).__name__}: {error}')


def guarded(callback, refusals, what, fallback=None):
    """``callback`` made safe for input from other processes: an exception it raises is refused
    (``refusals.refused``, naming ``what`` and the error) instead of ending the node's spin.

    Parameters
    ----------
    callback : callable
        A subscription's or service's callback.
    refusals : RefusalLog
        Where a refusal is logged.
    what : str
        What is refused (``'~/plate_command'``).
    fallback : callable, optional
        Called with the callback's arguments and the refusal's text (``reason``) after a
        refusal; its result is returned (a service's response). Default: None is returned.

    Returns
    -------
    callable

    Examples
    --------
    >>> from contact_sim.ros.refusals import RefusalLog, guarded
    >>> class Out:
    ...     def warning(self, text): print(text)
    >>> safe = guarded(lambda msg: 1 / msg, RefusalLog(Out(), 'x'), 'x')
    >>> safe(0)
    x refused: ZeroDivisionError: division by zero
    """
    def safe(*args):
        try:
            return callback(*args)
        except Exception as error:  # noqa: BLE001 - nothing a client sends may stop the node
            text = reason(error)
            refusals.refused(f'{what} refused: {text}')
            return None if fallback is None else fallback(*args, text)
    return safe


class RefusalLog:
    """Warnings of one kind of refusal, at most one per ``period``; the rest counted.

    Parameters
    ----------
    logger : object
        Has ``warning(text)`` (an rclpy logger).
    what : str
        What is refused, for the count line (``'~/plate_command'``).
    period : float
        Seconds of wall time between two warnings.
    clock : callable
        Wall time in s (default ``time.monotonic``).

    Examples
    --------
    >>> from contact_sim.ros.refusals import RefusalLog
    >>> class Out:
    ...     def warning(self, text): print(text)
    >>> log = RefusalLog(Out(), 'x', clock=lambda: 0.0)
    >>> log.refused('x refused: bad'); log.refused('x refused: worse')
    x refused: bad
    """

    def __init__(self, logger, what, period=REFUSAL_PERIOD, clock=time.monotonic):
        self._logger, self._what, self._period, self._clock = logger, what, period, clock
        self._last = -float('inf')
        self._held = 0

    def refused(self, text):
        """Log ``text`` if the period since the last warning is over, else count it."""
        now = self._clock()
        if now - self._last < self._period:
            self._held += 1
            return
        self._logger.warning(text + self._held_text())
        self._last, self._held = now, 0

    def flush(self):
        """Log the count of refusals held back once the period is over (call it periodically)."""
        now = self._clock()
        if self._held and now - self._last >= self._period:
            self._logger.warning(f'{self._what}: {self._held} more refused in the last '
                                 f'{self._period:g} s')
            self._last, self._held = now, 0

    def _held_text(self):
        return (f' ({self._held} more {self._what} refused in the last {self._period:g} s)'
                if self._held else '')
