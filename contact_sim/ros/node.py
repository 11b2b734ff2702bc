"""``contact_sim_node``: simulates a sphere dropped on a plate and publishes its contact wrench, state
and impacts, stamped with simulated time.

Data flows one way:

    parameters --params.build--> Model and its drop (cs.DropSimulation), once a change
        --loop.TickLoop: advance--> samples and impact records --messages.TOPICS encoders-->
        topics

A change of parameters is validated once (``_on_set_parameters``); what the validation built is
applied (``_on_parameters_set``): the model at once, its fresh drop from the next ~/reset. The
loop's settings (``params.LoopSettings``: publish_rate, real_time_factor) are apart from the
physics: a change of real_time_factor builds no model.

Frames and signs (REP 103, SI units): the plate frame (``frame_id``, default ``plate``) has z up
and the plate's surface (the top of the lower sphere, for two spheres) at z = 0. The sphere moves
along that z axis only. Penetration z > 0 means the undeformed bodies overlap; its rate ż > 0 means
approach. README.md documents every topic, service and parameter.

The plate. ``plate_amplitude`` and ``plate_frequency`` > 0 vibrate it
(``plate.table_transition`` bridges every change); ``~/plate_command``
(trajectory_msgs/JointTrajectory, joint ``plate_z``) drives it otherwise: the node only
translates the message (``read_plate_command``), the rules are ``plate.command_motion``'s;
both go to the engine through ``DropSimulation.set_plate``. ~/pose and ~/twist are absolute
(p + R1 - z, pdot - zdot); ~/plate_pose, ~/plate_twist (once per tick) and ~/plate_wrench (-F, at
every contact sample) show the plate.

The node's jobs are split by module: this one holds the node (parameters, the plate, services)
and ``main``; ``parameter_services`` the parameter services (no request stops the node);
``loop`` the tick loop (``TickLoop``: pacing, budgets, a recorder's pace), given the drop, the
settings, the model and the stamp offset it runs;
``outbox`` the publishers and the wait for readers (``Outbox``); ``pacing`` the pace a recorder
sets; ``view`` ~/markers and /diagnostics; ``plate_command`` the translation of ~/plate_command
(``read_plate_command``).
"""
import signal
import sys
from dataclasses import replace

import rclpy
import rclpy.logging
from rcl_interfaces.msg import ParameterType, ParameterValue, SetParametersResult
from rcl_interfaces.srv import GetParameters
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import Trigger
from trajectory_msgs.msg import JointTrajectory

from contact_sim.drop import command_motion
from contact_sim.validation import InputError

from .clock import CHECK_PERIOD, clock_to_yield_to
from .loop import TickLoop
from .outbox import Outbox
from .params import DEFAULTS, LOOP_PARAMETERS, NODE_NAME, PARAMETER_NAMES, PARAMETERS, \
    awaiting_stiffness, build, check_running, descriptor, loop_settings, make_simulation, \
    refusal, table_motion
from .plate_command import COMMAND_FIELDS, read_plate_command
from .query import MAX_NAMES, answer_queries
from .rclpy_private import parameter_overrides
from .parameter_services import ParameterServices
from .refusals import REFUSAL_PERIOD, RefusalLog, guarded, shorten
from .startup import ArgumentError, node_arguments, print_usage, publication_mode, \
    spin_until_signal


class StartupError(Exception):
    """The initial parameters are invalid: the node cannot start.

    ``str(error)`` is the refusal, naming the parameter and its allowed range; ``main`` logs it
    as one ``[FATAL]`` line and exits with code 2.
    """


class ContactSimNode(Node):
    """Simulates a sphere dropped on a plate and publishes its contact wrench, state and impacts.

    The node ``contact_sim`` declares the parameters of ``params.PARAMETERS`` (materials,
    radii in m, stiffness in N/m^n, damping, drop height in m, plate motion, ``publish_rate``
    in Hz, ``real_time_factor``, ``frame_id``, ``publish_clock``), validates every change as a
    whole in its set-parameters callback (a refusal names the parameter and its range), and
    publishes the topics of ``messages.TOPICS`` stamped with simulated time.  It serves
    ``~/query_restitution`` (``rcl_interfaces/srv/GetParameters``: names such as ``'2.5'``
    or ``'peak_force:2.5'``, a quantity at an impact speed in m/s, in; the answers out) and ``~/reset``
    (``std_srvs/srv/Trigger``), and follows ``~/plate_command``
    (``trajectory_msgs/msg/JointTrajectory``, joint ``plate_z``).

    Parameters
    ----------
    **kwargs
        Passed to ``rclpy.node.Node`` (e.g. ``parameter_overrides``, a list of
        ``rclpy.parameter.Parameter``; ``context``; ``namespace``).

    Raises
    ------
    StartupError
        The initial parameters are invalid (the message names the parameter and its range).

    See Also
    --------
    main : The ``contact_sim_node`` executable.

    Examples
    --------
    In a process of its own (it needs ``rclpy.init``; not run as a doctest, since it spins a
    ROS node until Ctrl-C):

    .. code-block:: python

        import rclpy
        from rclpy.parameter import Parameter
        from contact_sim.ros.node import ContactSimNode

        rclpy.init()
        node = ContactSimNode(parameter_overrides=[Parameter('initial_height', value=0.2)])
        try:
            rclpy.spin(node)
        except KeyboardInterrupt:
            pass
        finally:
            node.destroy_node()
            rclpy.try_shutdown()
    """

    def __init__(self, **kwargs):
        # the parameter services are the node's own (parameter_services: no request stops it)
        super().__init__(NODE_NAME, **{**kwargs, 'start_parameter_services': False})
        try:
            for spec in PARAMETERS:
                self.declare_parameter(spec.name, spec.default, descriptor(spec))
            values = self._values()
            self._settings = loop_settings(values)   # publish_rate, real_time_factor
            self._model, self._sim = build(values)   # one model; its drop runs from now
        except (ParameterException, ValueError) as error:
            self.destroy_node()   # the node rcl made: nothing of it is left for the exit
            raise StartupError(str(error)) from None
        self._warn_unknown_overrides()
        self._fresh = None        # the drop a change's validation built, for the next ~/reset
        self._pending = None      # the change validated last: (values, model, drop, settings, note)
        self._waiting = None      # the note of a law waiting for its stiffness, once said
        self._offset = 0.0        # s: stamp = offset + simulator time; grows at each ~/reset
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)  # pacing ignores use_sim_time
        # frame_id and publish_clock are read-only
        self._out = Outbox(self, self._model.frame_id, self._model.publish_clock)
        # one log a kind of refusal, each at most once a second, the rest counted
        self._refusals = {kind: RefusalLog(self.get_logger(), what) for kind, what in (
            ('field', '~/plate_command'), ('command', '~/plate_command'),
            ('drop', '~/plate_command'), ('query', '~/query_restitution'),
            ('answers', '~/query_restitution'),
            ('parameters', 'parameter requests'), ('reset', '~/reset'))}
        ParameterServices(self, self._refusals['parameters'])
        # every callback a client reaches is guarded: what it raises is refused, never the node
        self.create_service(GetParameters, '~/query_restitution', guarded(
            self._on_query, self._refusals['query'], '~/query_restitution',
            lambda *_: GetParameters.Response()))
        self.create_service(Trigger, '~/reset', guarded(
            self._on_reset, self._refusals['reset'], '~/reset',
            lambda *_: Trigger.Response(success=False, message='reset failed')))
        self._commanded = False   # the plate follows ~/plate_command (until ~/reset or a table)
        self.create_subscription(JointTrajectory, '~/plate_command', guarded(
            self._on_plate_command, self._refusals['command'], '~/plate_command'), 10)
        self.create_timer(REFUSAL_PERIOD, self._flush_refusals, clock=self._steady)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.add_post_set_parameters_callback(self._on_parameters_set)
        self._clock_seen = {}       # other publishers of /clock: when first seen (s)
        if self._out.publishes_clock:
            self._clock_check = self.create_timer(CHECK_PERIOD, self._check_clock,
                                                  clock=self._steady)
        self._loop = TickLoop(self, self._out, self._steady)   # with ~/markers, /diagnostics
        self._loop.start(self._sim, self._settings, self._model, self._offset)
        self.get_logger().info(self._model.summary())

    def drain(self):
        """At a stop: tick no more and wait for what was published (``loop.TickLoop.drain``,
        ``startup.spin_until_signal``'s ``drain``).

        Returns
        -------
        callable
            A predicate that holds once everything published is out and a recorder has it.
        """
        return self._loop.drain()

    def _check_clock(self):
        """Yield /clock to another publisher of it (``clock.clock_to_yield_to``), once."""
        if not self._out.publishes_clock:
            return     # a turn of the timer queued before it was destroyed
        other = clock_to_yield_to(self, self._clock_seen,
                                  self._steady.now().nanoseconds * 1e-9)
        if other is None:
            return
        self._clock_check.cancel()
        self._out.stop_clock(self)
        self.get_logger().warning(f'{other} publishes /clock already: this node does not (one '
                                  'clock for use_sim_time; publish_clock:=false says so at '
                                  'start-up)')

    # ---- parameters ------------------------------------------------------------------------

    def _values(self, changes=()):
        values = {name: self.get_parameter(name).value for name in PARAMETER_NAMES}
        values.update({p.name: p.value for p in changes})
        return values

    def _warn_unknown_overrides(self):
        unknown = sorted(name for name in parameter_overrides(self)
                         if not self.has_parameter(name))
        if unknown:
            self.get_logger().warning(f'ignoring unknown parameters: {", ".join(unknown)} '
                                      f'(known: {", ".join(PARAMETER_NAMES)})')

    def _on_set_parameters(self, parameters):
        """Validate a parameter change as a whole, once; nothing changes unless all of it is
        valid. What the validation built (the model and its fresh drop, the loop's settings) is
        kept for ``_on_parameters_set`` to apply; a change of the loop's settings alone
        (``real_time_factor``) builds no model."""
        self._pending = None
        ours = [p for p in parameters if p.name in DEFAULTS]
        if not ours:
            return SetParametersResult(successful=True)
        try:
            values = self._values(ours)
            model, drop, settings, note = self._built(
                values, physics=any(p.name not in LOOP_PARAMETERS for p in ours))
            if model is not None:
                # a new contact acts from the next contact phase of the running drop; one the
                # running drop refuses waits for the next ~/reset (set one by one, as `ros2
                # param load` does, a dump's stiffness comes before the drop it suits), unless
                # a changed table needs it
                try:
                    check_running(self._sim, model, values, self._model)
                except ValueError:
                    check_running(self._sim, replace(model, contact=self._sim.contact), values,
                                  self._model)
        except Exception as error:  # any failure rejects the change, never the node
            names = ', '.join(p.name for p in ours)
            return SetParametersResult(successful=False, reason=f'rejected {names}: {error}')
        self._pending = (values, model, drop, settings, note)
        return SetParametersResult(successful=True, reason=note or '')

    def _built(self, values, physics=True):
        """``(model, drop, settings, note)`` of ``values``: ``params.build``'s (None, None unless
        ``physics``), the loop's settings, ``params.awaiting_stiffness``'s note; ValueError."""
        model = drop = note = None
        if physics:
            checked, note = awaiting_stiffness(values, self._model)
            model, drop = build(checked)
        return model, drop, loop_settings(values), note

    def _on_parameters_set(self, parameters):
        """Apply an accepted change with what its validation built: the contact at once
        (engine: from the next contact phase), the drop at the next ~/reset, the loop's
        settings at once."""
        if not any(p.name in DEFAULTS for p in parameters):
            return
        values, pending, self._pending = self._values(), self._pending, None
        if pending is not None and pending[0] == values:
            _, model, drop, settings, note = pending
        else:   # not the change validated last (should not happen): validate it again
            try:
                model, drop, settings, note = self._built(values)
            except Exception as error:  # noqa: BLE001 - keep running
                self.get_logger().error(f'could not apply the accepted parameters: {error}')
                return
        if model is not None:
            if note is not None and note != self._waiting:   # said once while the law waits
                self.get_logger().warning(note)
            self._waiting = note
            self._apply_model(model, drop)
        if settings != self._settings:
            self._settings = settings
            self._loop.start(self._sim, settings, self._model, self._offset)
            self.get_logger().info(f'real_time_factor = {settings.real_time_factor:g}'
                                   + (' (as fast as possible)' if settings.fast else ''))

    def _apply_model(self, new, drop):
        """The physics changed: the new model from now (the table and the contact at once, the
        rest from the next ~/reset, which runs ``drop``)."""
        old, self._model, self._fresh = self._model, new, drop
        self._loop.model = new
        if new.table != old.table:
            self._set_table(old.table, new.table)
        if new.contact != old.contact:
            self._set_contact(new)
        if (new.mass, new.gravity, new.height, new.velocity, new.drag) != \
                (old.mass, old.gravity, old.height, old.velocity, old.drag):
            self.get_logger().info(f'mass, gravity, drag or initial conditions changed, from '
                                   f'the next ~/reset: {new.summary()}')

    def _set_contact(self, model):
        """The contact changed: from the next contact phase, or, if the running drop refuses it
        (it would sink deeper than the sphere's radius from the drop's initial conditions), from
        the next ~/reset, the running drop going on with the contact it has."""
        log = self.get_logger()
        try:
            self._sim.set_contact(model.contact)
        except InputError as error:
            log.warning(f'contact changed, from the next ~/reset: the running drop (from '
                        f'{self._sim.height:g} m) refuses it: {refusal(error, self._values())}')
            return
        log.info(f'contact changed, from the next contact phase: {model.summary()}')

    # ---- the plate: vibrating table, ~/plate_command -----------------------------------------

    def _set_table(self, old, new):
        """The table's parameters changed: bridge the plate from where it is (C1, one period;
        ``plate.table_transition``, one period or longer); a running table takes the plate over
        from ~/plate_command."""
        sim, log = self._sim, self.get_logger()
        try:
            sim.set_plate(table_motion(sim, old, new))
        except ValueError as error:  # validated already (check_running): keep running
            log.error(f'could not change the vibrating table: {error}')
            return
        if new is not None and self._commanded:
            self._commanded = False
            log.info('the vibrating table takes the plate over from ~/plate_command')
        log.info('vibrating table ' + (f'a = {new.amplitude:g} m, f = {new.frequency:g} Hz, '
                                       f'phi = {new.phase:g} rad' if new is not None
                                       else 'stopped (the plate comes to rest at p = 0)')
                 + f' from t = {self._offset + sim.time:.6f} s, bridged C1')

    def _on_plate_command(self, msg):
        """A trajectory for the plate (README, "Commanded plate"): translated here, the rules are
        ``plate.command_motion``'s; a refusal is a warning and changes nothing."""
        log, sim = self.get_logger(), self._sim
        table = self._model.table
        if table is not None:
            log.warning(f'~/plate_command refused: the vibrating table runs (plate_amplitude = '
                        f'{table.amplitude:g}, plate_frequency = {table.frequency:g} > 0); '
                        'allowed only with plate_amplitude = 0 or plate_frequency = 0',
                        throttle_duration_sec=5.0)
            return
        try:
            times, positions, velocities = read_plate_command(msg, sim.time, self._offset)
            state = sim.state
            command = command_motion(sim.time, state.plate_position, state.plate_velocity,
                                     times, positions, velocities)
            if command.dropped:
                log.warning(f'~/plate_command: dropped {command.dropped} point(s) at or before '
                            f'now (t = {self._offset + sim.time:.6f} s)',
                            throttle_duration_sec=5.0)
            if command.motion is None:
                log.warning('~/plate_command ignored: no point after now (t = '
                            f'{self._offset + sim.time:.6f} s)', throttle_duration_sec=5.0)
                return
        except InputError as error:
            self._refusals['field'].refused(
                f'~/plate_command refused: {error.render(COMMAND_FIELDS)}')
            return
        except ValueError as error:
            self._refusals['command'].refused(f'~/plate_command refused: {error}')
            return
        try:
            sim.set_plate(command.motion)
        except InputError as error:   # the drop's own limits (the depth check, gravity)
            why = refusal(error, self._values())
            if error.field in ('stiffness', 'damping'):
                why = ('the commanded motion (points[].velocities, peak plate speed '
                       f'{command.motion.speed_bound():.6g} m/s) is too fast for the running '
                       f'drop: {why}')
            self._refusals['drop'].refused(f'~/plate_command refused: {why}')
            return
        self._commanded = True

    # ---- services --------------------------------------------------------------------------

    def _flush_refusals(self):
        for refusals in self._refusals.values():
            refusals.flush()

    def _on_query(self, request, response):
        model = self._model
        if len(request.names) > MAX_NAMES:
            self._refusals['query'].refused(
                f'~/query_restitution refused: names has {len(request.names)} names: allowed at '
                f'most {MAX_NAMES} a request (no values returned)')
            response.values = []
            return response
        answers = answer_queries(list(request.names), model.contact, model.mass)
        values, unanswered = [], []
        for name, (value, reason) in zip(request.names, answers):
            if value is None:
                unanswered.append(f'{shorten(repr(name), 40)}: {shorten(reason, 80)}')
                values.append(ParameterValue(type=ParameterType.PARAMETER_NOT_SET))
            else:
                values.append(ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                             double_value=value))
        if unanswered:   # one warning a request (at most one a second), naming 10 at most
            more = f'; and {len(unanswered) - 10} more' if len(unanswered) > 10 else ''
            self._refusals['answers'].refused(
                f'~/query_restitution: cannot answer {len(unanswered)} of {len(values)} names: '
                + '; '.join(unanswered[:10]) + more)
        response.values = values
        return response

    def _on_reset(self, request, response):
        model = self._model
        sim, self._fresh = self._fresh, None   # the drop the last change built, if unused
        if sim is None:
            try:
                sim = make_simulation(model)
            except Exception as error:  # noqa: BLE001 - validated already: keep running
                response.success = False
                response.message = f'reset failed: {error}'
                return response
        self._offset += self._loop.reached_on_grid()
        self._loop.view.reset(self._sim)
        self._sim = sim
        self._commanded = False     # the new drop's plate: the table's, or fixed
        self._loop.start(sim, self._settings, model, self._offset)
        response.success = True
        response.message = f'drop restarted at t = {self._offset:.9f} s: {model.summary()}'
        self.get_logger().info(response.message)
        return response


def main(args=None):
    """Run the ``contact_sim_node`` executable until SIGINT/SIGTERM.

    ``--help`` prints the usage (ROS not started); an invalid argument, parameter or parameter
    file is one ``[FATAL]`` line naming it.

    Parameters
    ----------
    args : list of str, optional
        A full argument vector like ``sys.argv`` (program name first, then ``--ros-args``
        and its ``-p name:=value`` or ``--params-file`` arguments); default: ``sys.argv``.

    Returns
    -------
    int
        The exit code: 0 after SIGINT/SIGTERM or ``--help``, 2 for an invalid argument,
        parameter or parameter file.

    Examples
    --------
    From a shell, a vibrating plate (not run as a doctest: the node runs until Ctrl-C):

    .. code-block:: console

        $ contact_sim_node --ros-args -p plate_amplitude:=0.001 -p plate_frequency:=20.0

    The same from Python:

    .. code-block:: python

        import sys
        from contact_sim.ros.node import main

        sys.exit(main(['contact_sim_node', '--ros-args', '-p', 'initial_height:=0.2']))
    """
    argv = sys.argv if args is None else list(args)
    log = rclpy.logging.get_logger(NODE_NAME)
    # SIGINT and SIGTERM stop the start at any stage, quietly (spin_until_signal takes them over
    # once the node spins, and puts these back)
    previous = {sig: signal.signal(sig, _interrupt) for sig in (signal.SIGINT, signal.SIGTERM)}
    node = None
    try:
        if node_arguments(argv) == 'help':
            print_usage(sys.stdout)
            return 0
        publication_mode()
        rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
        node = ContactSimNode()
        spin_until_signal(node, drain=node.drain)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except ArgumentError as error:
        log.fatal(str(error))
        return 2
    except StartupError as error:
        log.fatal(f'invalid parameters: {error}')
        return 2
    finally:
        # the node stops: a signal now (Ctrl-C pressed again) is ignored, not a traceback
        for sig in previous:
            signal.signal(sig, signal.SIG_IGN)
        try:
            if node is not None:
                node.destroy_node()
            rclpy.try_shutdown()
        finally:
            if args is not None:   # a caller that goes on gets its handlers back; the console
                for sig, handler in previous.items():   # script exits next, ignoring signals
                    signal.signal(sig, handler)
    return 0


def _interrupt(signum, frame):
    """SIGINT or SIGTERM during the start: stop it (``main`` exits with code 0)."""
    raise KeyboardInterrupt


if __name__ == '__main__':
    sys.exit(main())
