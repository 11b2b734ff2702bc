"""``contact_sim_record``: records a contact_sim node's topics (the table in ``messages.TOPICS``) to
a rosbag2 directory with the ``rosbags`` library, for installs without rosbag2.

Lossless: every subscription is reliable and keep-all (``messages.RECORD_QOS``), and the recorder
acknowledges on ``~/recorded`` what it has recorded, so that a node running as fast as possible
waits for it instead of losing samples (the protocol: ``pacing``). Crash-safe: the
bag is flushed to disk at least every ``FLUSH_PERIOD`` s (``bag.BagWriter.flush``), so after a
SIGKILL at most the last second is lost, and ``contact_sim_record --recover BAG`` writes the
missing index and metadata (``bag.recover_bag``). A clean stop makes a consistent cut (``cut``).
"""
import sys
import time
from functools import partial

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from contact_sim.validation import InputError

from .messages import PROGRESS, RECORD_QOS, TOPICS, clock_msg
from .pacing import READY_NS
from .params import NODE_NAME
from .record_options import OPTION_NAMES, check_options, check_output, \
    record_parser  # noqa: F401  (record_parser: the command line, also reached from here)
from .startup import spin_until_signal

FLUSH_PERIOD = 0.5  # s of wall time between flushes of the bag to disk
REPORT_PERIOD = 0.02  # s of wall time between acknowledgements on ~/recorded, at least
ACK_EVERY = 64        # and one after this many messages on the paced topics (pacing.lead_messages)
TAKE_MESSAGES = 256   # messages taken from one reader in one wake-up, at most (then the timers run)


class Recorder(Node):
    """Subscribes to a contact_sim node's topics (and /clock) and writes them to a rosbag2 file.

    Each message is stored with its simulated time (message_time_ns) as the bag timestamp, so the
    bag's timeline is the simulation's even when the node runs faster than real time.  It also
    acknowledges on the node's ``~/recorded`` what it has recorded, which paces a node running
    as fast as possible (``loop``).

    Parameters
    ----------
    output : str or path-like
        The bag directory to create (it must not exist).
    storage : {'mcap', 'sqlite3'}, optional
        The rosbag2 storage format (default ``'mcap'``).
    target : str, optional
        The fully qualified name of the node recorded (default ``'/contact_sim'``).
    clock : bool, optional
        Record ``/clock`` too (default True).
    **kwargs
        Passed to ``rclpy.node.Node`` (e.g. ``context``).

    Raises
    ------
    ValueError
        The output directory exists, or the storage is unknown.

    See Also
    --------
    record_main : The ``contact_sim_record`` executable.

    Examples
    --------
    In a process of its own, beside a running node (not run as a doctest: it needs a ROS
    graph with the node on it):

    .. code-block:: python

        import rclpy
        from contact_sim.ros.recorder import Recorder

        rclpy.init()
        recorder = Recorder('drop_bag')
        try:
            rclpy.spin(recorder)
        except KeyboardInterrupt:
            pass
        finally:
            recorder.close()
            recorder.destroy_node()
            rclpy.try_shutdown()
    """

    def __init__(self, output, storage='mcap', target=f'/{NODE_NAME}', clock=True, **kwargs):
        super().__init__('contact_sim_record', **kwargs)
        from .bag import BagWriter  # rosbags is needed only for recording
        self.bag = BagWriter(output, storage)
        self._topics = {}  # full name -> Topic
        self._readers = {}
        for topic in TOPICS:
            if topic.kind == 'clock' and not clock:
                continue
            name = topic.resolve(target)
            self._topics[name] = topic
            self._readers[name] = self.create_subscription(
                topic.msg_type, name, partial(self._on_message, name, topic.type_name),
                RECORD_QOS, raw=True)
        self.topics = list(self._topics)
        self._taken = ()       # subscriptions taken by take(), not by an executor (taker())
        self.covered_ns = {}   # topic -> simulated time (ns) its recorded messages reach
        self.publishers_matched = {}  # topic -> number of matched publishers
        self.cut_ns = None     # set at the stop: see cut()
        self._held = []        # at the stop: (topic, type, stamp, data) past the cut, in order
        self._flushed = time.monotonic()
        self.create_timer(FLUSH_PERIOD, self._on_flush_timer)
        # the acknowledgement that paces a node running as fast as possible (node.py)
        self._progress = self.create_publisher(PROGRESS.msg_type, PROGRESS.resolve(target),
                                               PROGRESS.qos)
        self._reported_ns = -1
        self._unacked = 0       # paced messages recorded since the last acknowledgement
        self._stopping = False
        self._pacing = 0        # nodes matched on the acknowledgement
        self.create_timer(REPORT_PERIOD, self.report)
        self.get_logger().info(f'recording {", ".join(self.topics)} to {self.bag.path} '
                               f'({storage})')

    @property
    def subscriptions(self):
        """The subscriptions an executor serves: after ``taker()``, not the recorded topics'."""
        return [s for s in super().subscriptions if s not in self._taken]

    def taker(self):
        """Take the recorded topics' messages directly (call before adding the node to an
        executor, which then no longer serves them): a wait set of their subscriptions, and at
        each wake-up every message waiting on each of them taken in one go, without a callback
        from an executor a message (measured with ``bench/bench_dds_floor.py --take``).

        Returns
        -------
        callable
            ``take(timeout)``: wait at most ``timeout`` s for a message, record everything
            waiting; the number of messages recorded.
        """
        readers = [(name, self._topics[name].msg_type, self._topics[name].type_name,
                    subscription.handle, subscription.handle.pointer)
                   for name, subscription in self._readers.items()]
        self._taken = tuple(self._readers.values())
        wait_set = _rclpy.WaitSet(len(readers), 0, 0, 0, 0, 0, self.context.handle)
        on_message = self._on_message

        def take(timeout):
            wait_set.clear_entities()
            for reader in readers:
                wait_set.add_subscription(reader[3])
            wait_set.wait(int(timeout * 1e9))
            ready = wait_set.get_ready_entities('subscription')
            count = 0
            for name, msg_type, type_name, handle, pointer in readers:
                if pointer not in ready:
                    continue
                # at most TAKE_MESSAGES a reader a call: a node that refills the reader while
                # it is read must not keep the timers, the stop and the signals waiting
                for _ in range(TAKE_MESSAGES):
                    taken = handle.take_message(msg_type, True)
                    if taken is None:
                        break
                    on_message(name, type_name, taken[0])
                    count += 1
            return count
        return take

    def recorded_ns(self):
        """The simulated time up to which every per-tick topic with a matched publisher is recorded.

        ``Topic.paced`` topics count: /clock too, its latest stamp from any publisher, so a
        foreign /clock never holds the node back.

        Returns
        -------
        int or None
            Simulated time, ns; ``None`` while one of them has delivered nothing (or none has a
            publisher).
        """
        reached = []
        for topic, spec in self._topics.items():
            if spec.paced and self.publishers_matched.get(topic, 0):
                ns = self.covered_ns.get(topic)
                if ns is None:
                    return None
                reached.append(ns)
        return min(reached) if reached else None

    def ready(self):
        """Whether every per-tick topic subscribed to has a matched publisher.

        Returns
        -------
        bool
            True once each continuous topic has at least one matched publisher.
        """
        return all(self.publishers_matched.get(topic, 0) for topic, spec in self._topics.items()
                   if spec.continuous)

    def report(self):
        """Acknowledge on ~/recorded what is recorded, if it moved on, or ``READY_NS`` while
        ready with nothing recorded (the protocol: ``pacing``); nothing while stopping."""
        self._unacked = 0
        if self._stopping:
            return
        ns = self.recorded_ns()
        if ns is None:
            self.poll_matches(only_new=True)
            if self._reported_ns <= READY_NS and self.ready() and self._say(READY_NS):
                self._reported_ns = READY_NS
        elif ns > self._reported_ns and self._say(ns):
            self._reported_ns = ns

    def _say(self, ns):
        """Publish the acknowledgement ``ns``; False if the middleware refused it (an
        asynchronous writer whose one sample is still being sent: it is said again at the next
        report)."""
        try:
            self._progress.publish(clock_msg(ns))
        except _rclpy.RCLError:
            if not self.context.ok():
                raise
            return False
        return True

    def flush(self):
        """Put what has been recorded on disk (at most every FLUSH_PERIOD s, and by the timer)."""
        self._flushed = time.monotonic()
        self.bag.flush()

    def _on_flush_timer(self):
        self.flush()
        self.poll_matches()

    def poll_matches(self, only_new=False):
        """Note (and log) the publishers matched on each topic.

        Polled: the events executor does not deliver a match that happened before the node was
        added to it.

        Parameters
        ----------
        only_new : bool, optional
            Only raise the counts (default False: set them to what is matched now).
        """
        for topic, subscription in self._readers.items():
            count, before = subscription.get_publisher_count(), self.publishers_matched.get(topic, 0)
            if count > before:
                self.get_logger().info(f'matched {topic}: {count} publisher(s)')
            self.publishers_matched[topic] = max(count, before) if only_new else count
        pacing = self._progress.get_subscription_count()
        if pacing != self._pacing:
            self._pacing = pacing
            self.get_logger().info(f'pacing {pacing} node(s) through {self._progress.topic_name}'
                                   ' (a node running as fast as possible waits for this recorder)'
                                   if pacing else f'pacing no node through '
                                   f'{self._progress.topic_name}')

    def _on_message(self, topic, msgtype, data):
        """One serialized message (bytes, as received: the recorder never deserializes the
        continuous topics)."""
        spec = self._topics[topic]
        stamp, covered = spec.times_of_cdr(data)
        impact = spec.kind == 'impact'
        if self.cut_ns is not None:  # stopping
            if stamp > self.cut_ns and (impact or spec.continuous):
                # past the cut: a contact that began after it, or a continuous topic that is
                # ahead of the others (it has reached the cut: it is not waited for any more);
                # the latter is held, in case an impact that began before the cut moves it on
                self.covered_ns[topic] = max(self.covered_ns.get(topic, 0), covered)
                if not impact:
                    self._held.append((topic, msgtype, stamp, data))
                return
            if impact:
                self.cut_ns = max(self.cut_ns, covered)  # its whole contact goes in
                self._write_held()
        if topic not in self.bag.counts:
            self.poll_matches(only_new=True)
            self.get_logger().info(f'receiving {topic}')
        self.bag.write(topic, msgtype, stamp, data)
        self.covered_ns[topic] = max(self.covered_ns.get(topic, 0), covered)
        if spec.paced:
            self._unacked += 1
            if self._unacked >= ACK_EVERY:
                self.report()
        if impact:
            self.get_logger().debug(f'recorded the impact at t = {stamp * 1e-9:.9f} s')
        if time.monotonic() - self._flushed > FLUSH_PERIOD:
            self.flush()

    def _write_held(self):
        """Write the held messages (past the cut when they came) that the cut now reaches, in the
        order they came (each topic's own order)."""
        held, self._held = self._held, []
        for item in held:
            if item[2] <= self.cut_ns:
                self.bag.write(*item)
            else:
                self._held.append(item)

    def cut(self):
        """At a stop: a predicate that holds once the bag is a consistent cut of the simulation.

        DDS delivers each topic in order but not in step with the others: when the stop comes,
        one topic can lag seconds behind (a backlog, or a lost sample waiting for its repair).
        The cut is the latest simulated time any of the node's topics has reached, an impact
        counting up to the end of its contact; it holds once every one of them with a matched
        publisher has reached it too, except the sparse ~/impact. An impact that arrives
        meanwhile and began before the cut moves it on to the end of its contact (its samples
        that came first, past the cut then, were held and go in); one that
        began after it is not recorded. So every recorded impact has its whole wrench trace,
        and every continuous topic reaches the same simulated time. /clock, a global topic
        that another node may publish, neither sets the cut nor is waited for.

        Returns
        -------
        callable
            A function of no arguments, True once the cut is reached.
        """
        # stopping: the acknowledgement stops moving but its publisher stays until the recorder
        # is gone, so the node stays within its lead (pacing.lead_messages) of it while the
        # lagging topics drain (a node let loose here outruns its writers' histories and the
        # drain loses samples)
        self._stopping = True
        own = [ns for topic, ns in self.covered_ns.items()
               if self._topics[topic].kind != 'clock']
        if not own:
            return lambda: True
        self.cut_ns = max(own)
        behind = self.lagging()
        if behind:
            self.get_logger().info(f'stopping: waiting for {", ".join(behind)} to reach '
                                   f't = {self.cut_ns * 1e-9:.9f} s (Ctrl-C to stop now)')
        return lambda: not self.lagging()

    def lagging(self):
        """The continuous topics with a publisher whose messages do not reach the cut yet.

        Returns
        -------
        list of str
            The topics' full names (empty before ``cut`` or once every topic reaches it).
        """
        if self.cut_ns is None:
            return []
        return [topic for topic in self.topics if self._topics[topic].continuous
                and self.publishers_matched.get(topic, 0) > 0
                and self.covered_ns.get(topic, -1) < self.cut_ns]

    def close(self):
        """Close the bag (its index and ``metadata.yaml`` written) and log its message counts."""
        self.bag.close()
        counts = ', '.join(f'{topic} {self.bag.counts.get(topic, 0)}' for topic in self.topics)
        self.get_logger().info(f'wrote {self.bag.path}: {counts}')


def record_main(args=None):
    """Run the ``contact_sim_record`` executable: record until SIGINT/SIGTERM or ``--duration``.

    Parameters
    ----------
    args : list of str, optional
        A full argument vector like ``sys.argv`` (program name first; options of
        ``record_options.record_parser``, then any ``--ros-args``); default: ``sys.argv``.

    Returns
    -------
    int
        The exit code: 0, or 2 with one line naming the problem (e.g. the output exists).

    Examples
    --------
    From a shell, beside a running ``contact_sim_node`` (not run as a doctest: it needs the
    node on the ROS graph):

    .. code-block:: console

        $ contact_sim_record -o drop_bag --duration 10
        $ contact_sim_record --recover drop_bag    # a bag a killed recorder left
    """
    argv = sys.argv if args is None else args
    options = record_parser().parse_args(remove_ros_args(argv)[1:])
    if options.recover is not None:
        return recover_main(options.recover)
    try:   # every option checked before ROS starts and before a bag is made
        check_options(options)
        output = check_output(time.strftime('contact_sim_%Y_%m_%d-%H_%M_%S')
                              if options.output is None else options.output)
    except InputError as error:
        print(f'contact_sim_record: error: {error.render(OPTION_NAMES)}', file=sys.stderr)
        return 2
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    recorder = None
    code = 0
    try:
        recorder = Recorder(output, options.storage, options.node, clock=not options.no_clock)
        if not spin_until_signal(recorder, stop_after=options.duration, drain=recorder.cut,
                                 take=recorder.taker()):
            recorder.get_logger().warning(
                f'stopped before {", ".join(recorder.lagging())} caught up: the bag ends '
                f'earlier on those topics')
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except (OSError, ValueError) as error:  # e.g. the output directory made meanwhile
        print(f'contact_sim_record: error: {error}', file=sys.stderr)
        code = 2
    finally:
        if recorder is not None:
            recorder.close()
            recorder.destroy_node()
        rclpy.try_shutdown()
    return code


def recover_main(path):
    """Run ``contact_sim_record --recover BAG``: make a bag a killed recorder left readable.

    Parameters
    ----------
    path : str or path-like
        The bag directory.

    Returns
    -------
    int
        The exit code: 0 (the messages recovered are printed), or 2 with one line naming the
        problem.

    Examples
    --------
    From Python, on a bag directory a killed recorder left (no ROS graph needed):

    .. code-block:: python

        from contact_sim.ros.recorder import recover_main

        code = recover_main('drop_bag')     # prints: recovered drop_bag: N messages (...)
    """
    from .bag import recover_bag
    try:
        counts = recover_bag(path)
    except (OSError, ValueError) as error:
        print(f'contact_sim_record: error: {error}', file=sys.stderr)
        return 2
    total = sum(counts.values())
    listing = ', '.join(f'{topic} {count}' for topic, count in counts.items())
    print(f'recovered {path}: {total} messages ({listing})')
    return 0


if __name__ == '__main__':
    sys.exit(record_main())
