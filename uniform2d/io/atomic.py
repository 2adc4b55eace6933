"""Atomic file output: a file is either written completely or not at all.

Every writer in :mod:`uniform2d.io` goes through :func:`atomic_write`: the
content is produced in a temporary file in the destination's directory, which
then replaces the destination with :func:`os.replace` (atomic on POSIX and on
Windows for files on the same volume).  If the writer fails, the temporary
file is removed and a file that already existed at the destination is left
untouched.

Examples
--------
>>> import os, tempfile
>>> from uniform2d.io.atomic import atomic_write
>>> d = tempfile.mkdtemp()
>>> target = os.path.join(d, "hello.txt")
>>> def write(tmp):
...     with open(tmp, "w") as f:
...         f.write("hello")
>>> atomic_write(target, write, extension=".txt")
>>> open(target).read()
'hello'
>>> def fail(tmp):
...     with open(tmp, "w") as f:
...         f.write("half of it")
...     raise RuntimeError("disk on fire")
>>> atomic_write(target, fail, extension=".txt")
Traceback (most recent call last):
    ...
RuntimeError: disk on fire
>>> open(target).read(), sorted(os.listdir(d))
('hello', ['hello.txt'])
"""

from __future__ import annotations

import os
import secrets
from pathlib import Path
from typing import Callable

__all__ = ["atomic_write", "named_for"]


def atomic_write(path, write: Callable[[Path], object], *, extension: str = "") -> None:
    """Call ``write(tmp_path)`` and move the result to `path` only if it succeeds.

    Parameters
    ----------
    path : str or os.PathLike
        Destination file.  Its directory must exist.
    write : callable
        Called with the temporary :class:`~pathlib.Path` to write to (the file
        already exists, empty, so writers may open it by name).
    extension : str, optional
        The (possibly compound) extension of `path`, e.g. ``".vol.gz"``.  The
        temporary file keeps it, for writers that look at the file name.

    Raises
    ------
    FileNotFoundError
        If the destination directory does not exist.
    NotADirectoryError
        If the destination's parent is a file.
    Exception
        Whatever `write` raises; nothing is left behind in that case.
    """
    path = Path(path)
    directory = path.parent if str(path.parent) else Path(".")
    if directory.exists() and not directory.is_dir():
        raise NotADirectoryError(f"cannot write '{path}': '{directory}' is a file, not a directory")
    if not directory.is_dir():
        raise FileNotFoundError(
            f"cannot write '{path}': directory '{directory}' does not exist"
        )
    name = path.name
    stem = name[: len(name) - len(extension)] if extension and name.lower().endswith(
        extension.lower()
    ) else name
    while True:
        tmp = directory / f".{stem}.tmp-{secrets.token_hex(4)}{extension}"
        try:
            # 0o666 filtered by the umask: the same permissions as a plain open().
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:  # pragma: no cover - 32 random bits collided
            continue
        except OSError as exc:  # e.g. a read-only directory: name the user's file
            raise named_for(exc, tmp, path) from None
        os.close(fd)
        break
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:  # pragma: no cover
            pass
        if isinstance(exc, OSError):
            raise named_for(exc, tmp, path) from None
        raise


def named_for(exc: OSError, tmp: Path, path: Path) -> OSError:
    """``exc`` about the hidden temporary file (or about no file: a full disk while
    writing), retold about the user's ``path``."""
    if exc.errno is not None and (exc.filename is None or Path(exc.filename) == tmp):
        return type(exc)(exc.errno, exc.strerror, str(path))
    return exc
