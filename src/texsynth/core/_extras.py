"""The command that installs an optional extra, for the ImportError of a feature that needs it.

texsynth is installed from a checkout (it is not on PyPI yet), so an install line naming the package with an extra
would fail as written; the packages of the extra, read from the installed metadata, install
anywhere.
"""

from __future__ import annotations

from importlib import metadata


def install_hint(extra):
    """``python -m pip install '<package>' ...`` for the packages of ``extra`` (from texsynth's metadata), or the
    checkout's ``python -m pip install '.[<extra>]'`` when texsynth runs uninstalled.

    Examples
    --------
    >>> install_hint("video")
    "python -m pip install 'imageio-ffmpeg' (texsynth's video extra)"
    """
    try:
        requires = metadata.requires("texsynth") or []
    except metadata.PackageNotFoundError:
        requires = []
    marker = f'extra == "{extra}"'
    packages = [r.split(";")[0].strip() for r in requires if ";" in r and marker in r.split(";", 1)[1]]
    if not packages:
        return f"python -m pip install '.[{extra}]' in a texsynth checkout"
    return "python -m pip install " + " ".join(f"'{p}'" for p in packages) + f" (texsynth's {extra} extra)"
