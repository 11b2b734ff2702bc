"""The output files of every `contact-sim` subcommand, checked before any work starts.

Each output option (``--plot``, ``--save-params``, ``--output``) must name a file that can be
written: not empty, not a directory or a device, in a directory that exists and is writable, and
neither one of the subcommand's input files (``data``, ``--params-file``, ``MODEL.xml``) nor
another output of the same run.  Paths are compared after resolving links (``os.path.samefile``
where both exist), so ``./x.csv`` and ``x.csv`` are the same file.
"""
import os

from contact_sim.validation import InputError

# args attribute -> the option a user typed
OUTPUTS = {'plot': '--plot', 'save_params': '--save-params', 'output': '--output'}
INPUTS = {'data': 'data', 'params_file': '--params-file', 'model': 'MODEL.xml'}


def _given(args, table):
    """(option, path) of each attribute of ``table`` that ``args`` has and is not None."""
    found = []
    for attribute, option in table.items():
        value = getattr(args, attribute, None)
        for path in (value if isinstance(value, (list, tuple)) else [value]):
            if path is not None:
                found.append((option, path))
    return found


def _same(a, b):
    """True when the paths ``a`` and ``b`` name one file (existing or to be created)."""
    try:
        if os.path.exists(a) and os.path.exists(b):
            return os.path.samefile(a, b)
    except OSError:
        pass
    return os.path.realpath(a) == os.path.realpath(b)


def _refuse(option, path, reason):
    raise InputError(option, path, '%s = {value} cannot be written: %s' % (option, reason),
                     value=repr(str(path)))


def check_output(option, path):
    """Refuse an output ``path`` (of ``option``) that cannot be written as a regular file."""
    if not isinstance(path, str) or not path.strip():
        _refuse(option, path, 'the path is empty; allowed a file name, e.g. out.png')
    full = os.path.abspath(os.path.expanduser(path))
    if os.path.isdir(full):
        _refuse(option, path, 'it is a directory; allowed a file name inside it')
    if os.path.exists(full):
        if not os.path.isfile(full):
            _refuse(option, path, 'it is not a regular file (a device or a pipe); allowed a '
                                  'regular file')
        if not os.access(full, os.W_OK):
            _refuse(option, path, 'the file is not writable (permission denied)')
        return
    parent = os.path.dirname(full)
    if not os.path.isdir(parent):
        _refuse(option, path, f'directory {parent!r} does not exist; allowed a file in an '
                              'existing directory')
    if not os.access(parent, os.W_OK | os.X_OK):
        _refuse(option, path, f'directory {parent!r} is not writable (permission denied)')
    _probe(option, path, full)


def _probe(option, path, full):
    """Create ``full`` and remove it again: the only test that /proc, a read-only mount or a
    full quota refuses before the work rather than after it."""
    try:
        fd = os.open(full, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
    except FileExistsError:   # made meanwhile: the checks above apply to it next time
        return
    except OSError as error:
        _refuse(option, path, f'{error.strerror or error} (a file cannot be created there); '
                              'allowed a file in a writable directory')
    os.close(fd)
    os.unlink(full)


def check_outputs(args):
    """Check every output option of ``args`` before the work: each writable
    (``check_output``), none equal to an input file or to another output.

    Raises
    ------
    InputError
        Keyed by the option (e.g. ``--plot``), saying why the path cannot be used.
    """
    outputs = _given(args, OUTPUTS)
    inputs = [(option, path) for option, path in _given(args, INPUTS)
              if isinstance(path, str) and path != '-']
    for i, (option, path) in enumerate(outputs):
        check_output(option, path)
        for other, source in inputs:
            if _same(path, source):
                _refuse(option, path, f'it is the input file of {other} ({source!r}), which '
                                      'would be overwritten; allowed a different file')
        for other, earlier in outputs[:i]:
            if _same(path, earlier):
                _refuse(option, path, f'{other} writes to the same file; allowed a different '
                                      'file for each output')
