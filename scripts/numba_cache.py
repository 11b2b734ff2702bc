"""numba's on-disk cache of contact_sim's kernels (``*.nbi``, ``*.nbc`` in ``__pycache__``), kept
from going stale.

numba checks a cached kernel against its own file's time stamp only: a kernel that calls a
function of another file, or reads a constant from one, is loaded from the cache unchanged after
an edit there (issue 33). So the cache is stamped with a digest of every source that numba
compiles from (each ``contact_sim`` module that uses numba, and every ``contact_sim`` module
those import, transitively), and cleared when that digest changes.

    python scripts/numba_cache.py           # clear the cache if stale, then stamp it
    python scripts/numba_cache.py --clear   # clear it whatever the stamp (CI: .ci/run)

``scripts/setup.sh`` runs the first before it compiles the kernels; ``test/conftest.py`` calls
``clear_if_stale`` before a test session.
"""
import hashlib
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / 'contact_sim'
STAMP = PACKAGE / '__pycache__' / 'numba_sources.sha256'
IMPORT = re.compile(r'^\s*(?:from\s+(\.*[\w.]*)\s+import|import\s+(contact_sim[\w.]*))', re.M)


def _module_file(name, importer):
    """The file of module ``name`` (absolute, or relative to ``importer``), or None."""
    if name.startswith('.'):
        dots = len(name) - len(name.lstrip('.'))
        base = importer.parent
        for _ in range(dots - 1):
            base = base.parent
        parts = [p for p in name.lstrip('.').split('.') if p]
    elif name.split('.')[0] == 'contact_sim':
        base, parts = ROOT, name.split('.')
    else:
        return None
    path = base.joinpath(*parts)
    for candidate in (path.with_suffix('.py'), path / '__init__.py'):
        if candidate.is_file():
            return candidate
    return None


def compiled_sources():
    """Every source numba compiles from: the modules that use numba and what they import from
    contact_sim, transitively (sorted paths)."""
    todo = [p for p in PACKAGE.rglob('*.py') if re.search(r'\bnumba\b|\bnjit\b', p.read_text())]
    seen = set()
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        for match in IMPORT.finditer(path.read_text()):
            found = _module_file(match.group(1) or match.group(2), path)
            if found is not None and found not in seen:
                todo.append(found)
    return sorted(seen)


def digest():
    """sha256 of the compiled sources' paths and contents."""
    h = hashlib.sha256()
    for path in compiled_sources():
        h.update(str(path.relative_to(ROOT)).encode() + b'\0' + path.read_bytes() + b'\0')
    return h.hexdigest()


def clear():
    """Delete every cached kernel of the package and its stamp; the number of files deleted."""
    files = [*PACKAGE.rglob('*.nbi'), *PACKAGE.rglob('*.nbc')]
    for path in files:
        path.unlink(missing_ok=True)
    STAMP.unlink(missing_ok=True)
    return len(files)


def clear_if_stale():
    """Clear the cache if its stamp is not the sources' digest, then stamp it; the number of
    files deleted (0 when it was current)."""
    now = digest()
    if STAMP.is_file() and STAMP.read_text().strip() == now:
        return 0
    deleted = clear()
    STAMP.parent.mkdir(exist_ok=True)
    STAMP.write_text(now + '\n')
    return deleted


if __name__ == '__main__':
    count = clear() if sys.argv[1:] == ['--clear'] else clear_if_stale()
    print(f'numba cache: {count} stale file(s) deleted' if count else 'numba cache: current')
