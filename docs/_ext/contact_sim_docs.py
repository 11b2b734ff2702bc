"""Sphinx extension: the pages' generated parts, written into docs/_generated/ before reading.

- ``ros_parameters.md``, ``ros_topics.md``, ``ros_interfaces.md``: the node's tables, from
  ``contact_sim.ros.params.PARAMETERS``, ``contact_sim.ros.messages.TOPICS`` and a node built in
  this process (its own services and subscriptions), so they cannot drift from the code;
- ``transcripts/*.txt``: console transcripts, by ``scripts/transcripts.py``;
- ``figures/*.png``: the pictures, by ``scripts/docs_figures.py``.

The html builder writes them all each time; other builders (doctest) only what is missing.
Benchmark tables are not made here: the bench scripts write them (docs/benchmarks/, committed).
"""
import importlib.util
import math
import os
import re
import tempfile
import time
from pathlib import Path

from sphinx.util import logging

logger = logging.getLogger(__name__)

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
GENERATED = DOCS / '_generated'


def _script(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / 'scripts' / f'{name}.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _cell(value):
    text = str(value).replace('|', '\\|').replace('\n', ' ')
    return text


def _number(value):
    if isinstance(value, float):
        if math.isinf(value):
            return '.inf' if value > 0 else '-.inf'
        return repr(value)
    if isinstance(value, bool):
        return 'true' if value else 'false'
    return str(value)


def _type_of(value):
    return {bool: 'bool', float: 'double', int: 'integer', str: 'string'}.get(type(value), '?')


def parameters_table():
    """The node's parameters, one row a ``Spec`` of ``PARAMETERS``."""
    from contact_sim.ros.params import PARAMETERS
    rows = ['| parameter | type | default | range | changes | meaning (units) | rule |',
            '| --- | --- | --- | --- | --- | --- | --- |']
    for spec in PARAMETERS:
        rng = (f'{_number(float(spec.range[0]))} … {_number(float(spec.range[1]))}'
               if spec.range else '')
        rows.append(f'| `{spec.name}` | {_type_of(spec.default)} | `{_number(spec.default)}` | '
                    f'{rng} | {"read-only" if spec.read_only else "at run time"} | '
                    f'{_cell(spec.description)} | {_cell(spec.constraints)} |')
    return '\n'.join(rows) + '\n'


def _qos(qos):
    history = qos.history.name.lower().replace('keep_', 'keep ')
    depth = f' {qos.depth}' if 'last' in history else ''
    return f'{qos.reliability.name.lower()}, {qos.durability.name.lower()}, {history}{depth}'


def topics_table():
    """The node's published topics, one row a ``Topic`` of ``TOPICS``."""
    from contact_sim.ros.messages import TOPICS
    rows = ['| topic | type | published | QoS | fields filled |',
            '| --- | --- | --- | --- | --- |']
    when = {'sample': 'every contact point and each tick\'s end', 'state': 'once a tick',
            'impact': 'once a completed contact phase', 'clock': 'once a tick'}
    for topic in TOPICS:
        fields = ', '.join(f'`{f}`' for f in topic.fields)
        rows.append(f'| `{topic.name}` | `{topic.type_name}` | {when.get(topic.kind, topic.kind)} '
                    f'| {_qos(topic.qos)} | {fields} |')
    return '\n'.join(rows) + '\n'


def _type_path(cls):
    module = cls.__module__.split('.')
    return f'{module[0]}/{module[1]}/{cls.__name__}'


def _summary(callback):
    doc = getattr(callback, '__doc__', None) or ''
    text = ' '.join(doc.strip().split('\n\n')[0].split())
    name = getattr(callback, '__qualname__', '')
    return text or f'`{name}` (described below)'


def interfaces_table():
    """The node's own services and subscriptions, read from a node built in this process."""
    import rclpy
    from rclpy.context import Context

    from contact_sim.ros.node import ContactSimNode
    os.environ.setdefault('ROS_LOG_DIR', tempfile.mkdtemp(prefix='contact_sim_docs_'))
    context = Context()
    rclpy.init(context=context, args=[], domain_id=200 + os.getpid() % 30)
    try:
        node = ContactSimNode(context=context)
        prefix = '/' + node.get_name()
        rows = ['| kind | name | type | what the node does with it |',
                '| --- | --- | --- | --- |']
        for service in node.services:
            name = service.srv_name
            if not name.startswith('~/'):     # rclpy's parameter services
                continue
            rows.append(f'| service | `{name}` | `{_type_path(service.srv_type)}` | '
                        f'{_cell(_summary(service.callback))} |')
        for sub in node.subscriptions:
            name = sub.topic_name.replace(prefix + '/', '~/', 1)
            rows.append(f'| subscription | `{name}` | `{_type_path(sub.msg_type)}` | '
                        f'{_cell(_summary(sub.callback))} |')
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    return '\n'.join(rows) + '\n'


RANGE_EXAMPLES = (('gravity', -1.0), ('gravity', 1e7), ('stiffness', 1e308))


def range_refusals():
    """rclpy's own refusals of values outside a parameter's declared range, as the node gives
    them (a node built in this process, each value set on it and refused)."""
    import rclpy
    from rclpy.context import Context
    from rclpy.parameter import Parameter

    from contact_sim.ros.node import ContactSimNode
    os.environ.setdefault('ROS_LOG_DIR', tempfile.mkdtemp(prefix='contact_sim_docs_'))
    context = Context()
    rclpy.init(context=context, args=[], domain_id=200 + os.getpid() % 30)
    try:
        node = ContactSimNode(context=context)
        lines = []
        for name, value in RANGE_EXAMPLES:
            (result,) = node.set_parameters([Parameter(name, value=value)])
            assert not result.successful, (name, value)
            lines.append(f'- `{name}` = `{value!r}`: `{result.reason}`')
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    return '\n'.join(lines) + '\n'


def _write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def generate(app):
    everything = app.builder.name == 'html'
    started = time.perf_counter()
    tables = {'ros_parameters.md': parameters_table, 'ros_topics.md': topics_table,
              'ros_interfaces.md': interfaces_table, 'ros_range_refusals.md': range_refusals}
    for name, make in tables.items():
        if everything or not (GENERATED / name).exists():
            _write(GENERATED / name, make())
    transcripts = _script('transcripts')
    if everything or transcripts.missing(GENERATED / 'transcripts'):
        transcripts.write_all(GENERATED / 'transcripts', figures=GENERATED / 'figures')
    figures = _script('docs_figures')
    if everything or figures.missing(GENERATED / 'figures'):
        figures.write_all(GENERATED / 'figures')
    logger.info('contact_sim_docs: generated parts in %.1f s', time.perf_counter() - started)


_LITERAL = re.compile(r'(``.*?``|`[^`]*`_?)')
_STRONG = re.compile(r'(?<![*\w\\])\*\*(?=\w)(?![^*\n]*\*\*)')
_EMPHASIS = re.compile(r'(?<![*\w\\])\*(?=\w)(?![^*\n]*\*)')


def _escape(segment):
    segment = segment.replace('|', '\\|')
    return _EMPHASIS.sub(r'\\*', _STRONG.sub(r'\\*\\*', segment))


def escape_math_notation(app, what, name, obj, options, lines):
    """The docstrings write |x| for an absolute value and *args for a call's rest, as plain
    text; reST would read them as substitutions and emphasis. Escape them outside literals,
    doctest blocks (``>>>`` to the next blank line) and literal blocks (after ``::``)."""
    doctest = literal = False
    literal_indent = 0
    for i, line in enumerate(lines):
        stripped = line.strip()
        indent = len(line) - len(line.lstrip())
        if doctest:
            doctest = bool(stripped)
            continue
        if literal:
            if not stripped or indent > literal_indent:
                continue
            literal = False
        if stripped.startswith('>>>'):
            doctest = True
            continue
        if stripped.startswith(('+', '|')) and stripped.endswith(('+', '|')):   # a grid table
            continue
        parts = _LITERAL.split(line)
        lines[i] = ''.join(part if k % 2 else _escape(part) for k, part in enumerate(parts))
        if stripped.endswith('::'):
            literal, literal_indent = True, indent


def module_namespace_for_examples(app, what, name, obj, options, lines):
    """A docstring's examples run, as with ``pytest --doctest-modules``, in the namespace of the
    module that defines the object: a hidden ``testsetup`` on the page loads that module's
    globals (the doctest builder runs a page's examples in one namespace)."""
    if not any(line.lstrip().startswith('>>>') for line in lines):
        return
    module = getattr(obj, '__module__', None) if what != 'module' else name
    if not isinstance(module, str) or not module.startswith('contact_sim'):
        module = name.rsplit('.', 1)[0] if what != 'module' else name
    lines.extend(['', '.. testsetup::', '',
                  '   import importlib as _importlib',
                  f'   globals().update(vars(_importlib.import_module({module!r})))', ''])


def setup(app):
    app.connect('builder-inited', generate)
    app.connect('autodoc-process-docstring', escape_math_notation, priority=100)
    app.connect('autodoc-process-docstring', module_namespace_for_examples, priority=900)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
