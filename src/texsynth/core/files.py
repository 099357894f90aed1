"""Writing files atomically: the one place where texsynth writes a file or a folder.

Every writer of the library (:mod:`texsynth.io`'s images, frames, chunked
stores and coordinate maps, :func:`texsynth.surface.save_mesh`, the batch
summaries, the demo's index page) goes through this module:

:func:`prepare_target`
    Refuse to replace an existing file unless ``overwrite``, a folder by a
    file, or a target whose folder does not exist, before any work is done.
:func:`atomic_write`
    Fill a hidden temporary file beside the target, then rename it over the
    target, so a file is never half-written.
:func:`swap_folder`
    The same for a folder (a Zarr store, a folder of frames).
:func:`as_path`
    A path argument as a :class:`pathlib.Path`, or an error naming it.

The temporary file (or folder) is removed when the write fails or the process
is interrupted, by Ctrl-C (SIGINT) or by SIGTERM (``kill``, ``timeout``, a job
scheduler); what a killed writer (SIGKILL) left is removed by the next write
of the same target. New files get the permissions the umask gives, as any
other program's output; a replaced file keeps its permission bits.

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> with tempfile.TemporaryDirectory() as d:
...     target = prepare_target(Path(d) / "notes.txt", overwrite=False)
...     atomic_write(target, lambda tmp: Path(tmp).write_text("done"))
...     print(target.read_text(), sorted(p.name for p in Path(d).iterdir()))
done ['notes.txt']
"""

from __future__ import annotations

import contextlib
import glob
import os
import re
import reprlib
import secrets
import shutil
import signal
import stat
import threading
from pathlib import Path

__all__ = ["as_path", "prepare_target", "atomic_write", "swap_folder"]

_short = reprlib.Repr()
_short.maxstring = _short.maxother = 60


# --------------------------------------------------------------------------- #
# paths
# --------------------------------------------------------------------------- #
def as_path(path, name="path"):
    """``path`` as a :class:`pathlib.Path`, or a TypeError/ValueError naming ``name``.

    Parameters
    ----------
    path : str, bytes or os.PathLike
        A file name.
    name : str
        The argument's name in error messages.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    TypeError
        If ``path`` is not a str, bytes or os.PathLike.
    ValueError
        If ``path`` is empty or contains a NUL character.

    Examples
    --------
    >>> as_path(b"out.png").name
    'out.png'
    """
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(
            f"{name} must be a str or os.PathLike (e.g. pathlib.Path) naming a file, "
            f"got {type(path).__name__} {_short.repr(path)}"
        )
    try:
        text = os.fsdecode(os.fspath(path))
    except TypeError as exc:
        raise TypeError(f"{name} must be a str or os.PathLike naming a file: {exc}") from None
    if text == "":
        raise ValueError(f"{name} is an empty string; pass a file name such as 'out.png'")
    if "\x00" in text:
        raise ValueError(f"{name} contains a NUL character ({_short.repr(text)}); pass a valid file name")
    return Path(text)


# --------------------------------------------------------------------------- #
# atomic writes of files
# --------------------------------------------------------------------------- #
class _Terminated(SystemExit):
    """Raised by the temporary SIGTERM handler of a write, so that its clean-up runs."""


class _CleanUpOnSigterm:
    """Turn SIGTERM into an exception for the duration of a write, then end the process as SIGTERM would.

    Python unwinds (and so removes temporary files) on SIGINT, but SIGTERM's
    default action ends the process at once. While the block runs, on the main
    thread and only if SIGTERM has its default action, a handler raises
    :class:`_Terminated` so the write's ``except`` clauses remove what they
    made; on leaving the block the default action is restored and the signal
    re-delivered, so the process still terminates by SIGTERM (exit status 143
    in a shell). A handler the program installed itself is left alone: its
    exception, if any, unwinds through the clean-up in the same way. A SIGTERM
    that arrives when no clean-up can follow (a second one, or one after the
    block) gets the default action at once.
    """

    def __enter__(self):
        self._installed = self._active = self._received = False
        sig = getattr(signal, "SIGTERM", None)
        if sig is None or threading.current_thread() is not threading.main_thread():
            return self
        try:
            if signal.getsignal(sig) is not signal.SIG_DFL:
                return self
            signal.signal(sig, self._handle)
        except (ValueError, OSError):  # pragma: no cover - e.g. signals unavailable in an embedded interpreter
            return self
        self._installed = self._active = True
        return self

    def _handle(self, signum, frame):
        if self._active and not self._received:
            self._received = True
            raise _Terminated(128 + signum)
        signal.signal(signum, signal.SIG_DFL)
        signal.raise_signal(signum)

    def __exit__(self, *exc):
        self._active = False
        if self._installed:
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            if self._received:
                signal.raise_signal(signal.SIGTERM)
        return False


def _temp_parts(path, folder):
    """``(stem, suffix)``: the parts of ``path``'s name around a temporary's ``-PID-TOKEN`` (a file keeps its
    suffix last, since writers choose the format by it)."""
    return (path.name, "") if folder else (path.stem, path.suffix)


def _temp_name(path, *, folder=False):
    """A new hidden name beside ``path`` for the temporary file (or ``folder``) a write fills before renaming:
    ``.noise-PID-TOKEN.png``, ``.big.zarr-PID-TOKEN``. The writer's pid lets a later write tell the
    leftover of a killed writer from the work of a running one (:func:`_stale_temp_files`)."""
    stem, suffix = _temp_parts(path, folder)
    return path.parent / f".{stem}-{os.getpid()}-{secrets.token_hex(4)}{suffix}"


def _running(pid):
    """Whether process ``pid`` runs on this machine; True when that cannot be told."""
    if os.name != "posix":  # os.kill(pid, 0) would end the process on Windows
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (OSError, OverflowError):  # another user's process, or no valid pid
        return True
    return True


def _stale_temp_files(path, *, folder=False):
    """The temporaries of ``path`` that a killed write left (``kill -9`` allows no clean-up): the files (or,
    with ``folder``, the folders) named exactly as :func:`_temp_name` names them whose writer has ended."""
    path = Path(path)
    stem, suffix = _temp_parts(path, folder)
    pattern = re.compile(rf"\.{re.escape(stem)}-([0-9]+)-[0-9a-f]{{8}}{re.escape(suffix)}")
    stale = []
    for p in path.parent.glob(f".{glob.escape(stem)}-*"):
        match = pattern.fullmatch(p.name)
        kind = (p.is_dir() and not p.is_symlink()) if folder else p.is_file()
        if match and kind and not _running(int(match[1])):
            stale.append(p)
    return stale


def _remove_stale_temps(path, *, folder=False):
    """Remove what killed writes of ``path`` left (best effort: a write never fails for them)."""
    for p in _stale_temp_files(path, folder=folder):
        if folder:
            shutil.rmtree(p, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                p.unlink()


def _new_temp_file(path):
    """Create an empty hidden file beside ``path`` with the mode the umask gives; return (name, mode)."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):
        tmp = _temp_name(path)
        try:
            fd = os.open(tmp, flags, 0o666)  # the umask (and default ACLs) apply, as for any new file
        except FileExistsError:  # pragma: no cover - 32 random bits
            continue
        try:
            mode = stat.S_IMODE(os.fstat(fd).st_mode)
        finally:
            os.close(fd)
        return tmp, mode
    raise FileExistsError(f"cannot create a temporary file beside {str(path)!r}")  # pragma: no cover


def _new_temp_dir(path):
    """Create a hidden folder beside ``path`` with the mode the umask gives."""
    for _ in range(100):
        tmp = _temp_name(path, folder=True)
        try:
            os.mkdir(tmp, 0o777)
        except FileExistsError:  # pragma: no cover
            continue
        return tmp
    raise FileExistsError(f"cannot create a temporary folder beside {str(path)!r}")  # pragma: no cover


def _keep_mode(tmp, target, default):
    """Give ``tmp`` the permission bits of the file it replaces (or ``default`` for a new file)."""
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        mode = default
    if stat.S_IMODE(os.stat(tmp).st_mode) != mode:
        os.chmod(tmp, mode)


def atomic_write(path, write):
    """Call ``write(tmp_path)`` on a temporary file beside ``path``, then rename it over ``path``.

    The temporary file is created with the permissions the umask gives (a
    replaced file's mode is kept) and removed if anything fails or the
    process is interrupted (SIGINT, SIGTERM) before the rename; what killed
    writes of ``path`` left (SIGKILL) is removed first. It does not check
    whether ``path`` may be replaced: call :func:`prepare_target` first.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    write : callable
        ``write(tmp)`` writes the whole file to the path ``tmp`` (a str), a
        hidden name beside ``path`` with the same suffix.

    Raises
    ------
    Exception
        Whatever ``write`` raises (nothing is left behind then).
    """
    path = Path(path)
    _remove_stale_temps(path)
    with _CleanUpOnSigterm():
        tmp = None
        try:
            tmp, mode = _new_temp_file(path)
            write(str(tmp))
            _keep_mode(tmp, path, mode)
            os.replace(tmp, path)
            tmp = None
        except BaseException:
            if tmp is not None:
                try:
                    os.remove(tmp)
                except FileNotFoundError:
                    pass
            raise


def prepare_target(path, overwrite, *, folder=False):
    """Refuse to replace an existing target unless ``overwrite``, a folder by a file, or a missing parent.

    Parameters
    ----------
    path : pathlib.Path
        The file (or, with ``folder``, the folder) a writer will write.
    overwrite : bool
        Whether an existing target may be replaced.
    folder : bool
        The target is a folder (written by :func:`swap_folder`).

    Returns
    -------
    pathlib.Path
        ``path`` itself.

    Raises
    ------
    FileExistsError
        If ``path`` exists and ``overwrite`` is False, or ``path`` is a
        folder and ``folder`` is False.
    FileNotFoundError
        If the folder that would hold ``path`` does not exist.
    """
    if path.is_dir() and not folder:
        example = path / f"out{path.suffix or '.png'}"
        raise FileExistsError(f"{str(path)!r} is a folder; pass the path of a file, e.g. {str(example)!r}")
    if path.exists() and not overwrite:
        raise FileExistsError(f"{str(path)!r} already exists; pass overwrite=True to replace it")
    if not path.parent.exists():
        raise FileNotFoundError(f"folder {str(path.parent)!r} does not exist; create it first")
    return path


# --------------------------------------------------------------------------- #
# atomic writes of folders
# --------------------------------------------------------------------------- #
def swap_folder(path, write):
    """Call ``write(tmp)`` on a new hidden folder beside ``path``, then swap it in for ``path``.

    The new folder gets the permissions the umask gives, or the mode of the folder it replaces;
    the temporary folder is removed if anything fails or the process is interrupted, and what killed
    writes of ``path`` left (SIGKILL) is removed first. An existing folder at ``path`` is replaced
    whole: call :func:`prepare_target` with ``folder=True`` first.

    Parameters
    ----------
    path : pathlib.Path
        The folder to write.
    write : callable
        ``write(tmp)`` fills the new folder ``tmp`` (a :class:`pathlib.Path`).

    Raises
    ------
    Exception
        Whatever ``write`` raises (the old folder is kept, the new one removed).
    """
    _remove_stale_temps(path, folder=True)
    with _CleanUpOnSigterm():
        tmp = old = None
        try:
            tmp = _new_temp_dir(path)
            if path.is_dir():
                os.chmod(tmp, stat.S_IMODE(path.stat().st_mode))
            write(tmp)
            if path.exists():
                old = _new_temp_dir(path)  # a temporary too: removed by a later write if a kill leaves it
                os.replace(path, old / path.name)
            os.replace(tmp, path)
            tmp = None
        except BaseException:
            if old is not None and not path.exists():
                os.replace(old / path.name, path)
            if tmp is not None:
                shutil.rmtree(tmp, ignore_errors=True)
            raise
        finally:
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
