"""Values from the command line: sizes, flows, weights, fields and grey maps (:mod:`texsynth.cli`)."""

from __future__ import annotations

import ast
import math
import re
from pathlib import Path

__all__ = ["CommandError", "parse_value", "parse_size", "parse_flow", "parse_weights", "parse_keyframes", "ramp",
           "read_field", "read_grey_map", "SIZE_FORMS", "FIELD_GREY"]


class CommandError(Exception):
    """A user error on the command line: printed on one line, exit status 2."""


def parse_value(text):
    """Command-line text to a Python value: numbers, tuples, None, else the string."""
    if text.lower() in {"none", "null"}:
        return None
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text


SIZE_FORMS = ("WIDTHxHEIGHT (e.g. 512x256; WxHxD for volumes), one number N (NxN) or a factor of the input's size "
              "(4x, 1.5x)")


def parse_size(text, input_size=None):
    """``--size`` to ``(height, width)``: ``"WxH"``, ``"N"``, or a factor ``"4x"`` of ``input_size``.

    ``input_size`` is the input's ``(height, width)`` (None: the command has
    no input, and a factor is refused). A factor's sides are rounded to the
    nearest pixel.

    >>> parse_size("320x200"), parse_size("64"), parse_size("4x", (96, 128)), parse_size("1.5x", (77, 96))
    ((200, 320), (64, 64), (384, 512), (116, 144))
    """
    text = str(text).strip()
    factor = re.fullmatch(r"(\d+(?:\.\d*)?|\.\d+)[xX]", text)
    if factor:
        value = float(factor.group(1))
        if input_size is None:
            raise CommandError(f"--size {text} is a factor of the input's size, but this command has no input "
                               f"image; pass WIDTHxHEIGHT (e.g. 512x256) or one number N")
        size = tuple(int(math.floor(side * value + 0.5)) for side in input_size[:2])
        if min(size) < 1:
            raise CommandError(f"--size {text} makes the {input_size[1]}x{input_size[0]} input smaller than a pixel; "
                               f"pass a larger factor, WIDTHxHEIGHT or N")
        return size
    parts = text.lower().split("x")
    try:
        numbers = [int(p) for p in parts]
    except ValueError:
        raise CommandError(f"--size must be {SIZE_FORMS}; got {text!r}") from None
    if len(numbers) == 1:
        numbers = numbers * 2
    if len(numbers) not in (2, 3):
        raise CommandError(f"--size must be {SIZE_FORMS}; got {text!r}")
    if min(numbers) < 1:
        raise CommandError(f"--size must be {SIZE_FORMS}, with sides of at least 1 pixel; got {text!r}")
    if len(numbers) == 3:  # volumes: WxHxD
        width, height, depth = numbers
        return depth, height, width
    width, height = numbers
    return height, width


def parse_flow(text, shape):
    """``KIND:AMOUNT`` to a flow field of the given shape (texsynth.core.flows).

    KIND is ``sink``, ``source``, ``vortex`` (AMOUNT: speed in pixels per
    frame), ``rotation`` (radians per frame) or ``translation`` (AMOUNT: one
    number for a shift to the right, or ``(dx, dy)``: x to the right, y down,
    in pixels per frame).

    >>> parse_flow("translation:(1, 0)", (4, 6)).shape
    (4, 6, 2)
    >>> parse_flow("translation:2", (4, 6))[0, 0].tolist()  # (rows, columns): 2 columns to the right
    [0.0, 2.0]
    """
    from .core import flows

    kinds = {"sink": flows.sink, "source": flows.source, "vortex": flows.vortex, "rotation": flows.rotation,
             "translation": flows.translation}
    kind, _, amount = str(text).partition(":")
    if kind not in kinds or not amount:
        raise CommandError(f"--flows must be KIND:AMOUNT with KIND one of {', '.join(kinds)}, got {text!r}")
    value = parse_value(amount)
    if kind == "translation":  # (dx, dy) on the command line; flows take (d_row, d_col)
        if isinstance(value, tuple) and len(value) != 2:
            raise CommandError(f"--flows translation takes one number (dx) or (dx, dy), got {amount!r}")
        dx, dy = value if isinstance(value, tuple) else (value, 0.0)
        value = (dy, dx)
    return kinds[kind](tuple(shape), value)


def ramp(shape):
    import numpy as np

    return np.broadcast_to(np.linspace(0.0, 1.0, shape[1]), tuple(shape[:2])).copy()


def parse_weights(text, n, shape):
    """``--weights`` to one weight per input: ``equal``, ``ramp`` or comma-separated image files.

    ``equal`` gives every input the weight 1. ``ramp`` goes from the first
    input at the left edge to the last at the right edge (piecewise-linear
    hat functions; for two inputs the weights ``1 - t`` and ``t``). Files
    are grey weight images of the output size: one per input, or a single
    one ``m`` for two inputs (weights ``1 - m`` and ``m``).

    >>> [w.round(2).tolist() for w in parse_weights("ramp", 3, (1, 5))]
    [[[1.0, 0.5, 0.0, 0.0, 0.0]], [[0.0, 0.5, 1.0, 0.5, 0.0]], [[0.0, 0.0, 0.0, 0.5, 1.0]]]
    """
    import numpy as np

    if text in (None, "equal"):
        return None
    if text == "ramp":
        t = ramp(shape) * (n - 1)
        return [np.clip(1.0 - np.abs(t - i), 0.0, 1.0) for i in range(n)]
    paths = str(text).split(",")
    if len(paths) not in {n, 1} or (len(paths) == 1 and n != 2):
        raise CommandError(f"--weights needs 'equal', 'ramp', one image file per input ({n}) "
                           f"or, for two inputs, one file; got {text!r}")
    maps = [read_grey_map(path, "--weights") for path in paths]
    return [1.0 - maps[0], maps[0]] if len(paths) == 1 else maps


# grey 0..1 of a field image -> the field's values, and the mapping in words
FIELD_GREY = {"orientation": (lambda g: 2.0 * 3.141592653589793 * g, "0..1 -> angle 0..2 pi, counter-clockwise"),
               "magnification": (lambda g: 2.0 ** (2.0 * g - 1.0),
                                 "0..1 -> magnification 0.5..2 geometrically, 0.5 -> 1")}


def parse_keyframes(text):
    """``--keyframes 0=first.png,29=last.png`` to ``{0: image, 29: image}``: painted frames by their index.

    >>> parse_keyframes("0=a.png, 29=b.png".replace("a.png", "missing.png"))  # doctest: +IGNORE_EXCEPTION_DETAIL
    Traceback (most recent call last):
    CommandError: --keyframes: cannot read missing.png ...
    """
    from .io import load_image

    keyframes = {}
    for item in str(text).split(","):
        index, sep, path = item.strip().partition("=")
        if not sep or not index.strip().lstrip("-").isdigit() or not path.strip():
            raise CommandError(f"--keyframes takes INDEX=FILE pairs separated by commas (e.g. "
                               f"'0=first.png,29=last.png', frame indices from 0), got {item.strip()!r}")
        try:
            keyframes[int(index)] = load_image(path.strip())
        except (OSError, ValueError) as error:
            raise CommandError(f"--keyframes: cannot read {path.strip()} ({error})") from None
    return keyframes


def read_field(text, name):
    """``--orientation``/``--magnification`` text to a field: a number, a ``.npy`` array or a grey image file.

    A number is the field everywhere; a ``.npy`` file holds the values
    themselves (radians; magnification factors) at the output's size; any
    other path is an image read by :func:`read_grey_map` whose grey ``g`` in
    [0, 1] maps to ``2 pi g`` radians (orientation) or the magnification
    ``2^(2g - 1)`` (0.5 at black, 1 at mid-grey, 2 at white). A callable is
    API-only.

    >>> read_field("1.5", "magnification")
    1.5
    """
    import numpy as np

    option = "--" + name.replace("_", "-")
    try:
        return float(text)
    except ValueError:
        pass
    if not Path(text).is_file():
        raise CommandError(f"{option} must be a number, a .npy file or an image file, got {text!r} (no such file)")
    if text.lower().endswith(".npy"):
        try:
            return np.load(text, allow_pickle=False)
        except ValueError as error:
            raise CommandError(f"{option}: could not read {text!r} as a numeric .npy array ({error})") from None
    return FIELD_GREY[name][0](read_grey_map(text, option))


def read_grey_map(path, option):
    """Read an image file as one grey map ``(H, W)`` of floats in [0, 1].

    The one reader of every map given on the command line (mixing weights,
    masks, alpha maps, feature maps), so that a map saved as grey, grey with
    alpha, RGB or RGBA (any bit depth ``load_image`` reads) means the same:
    the colour channels are averaged and an alpha channel is ignored.
    ``option`` names the option in error messages.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from texsynth.io import save_image
    >>> rgba = np.zeros((2, 3, 4)); rgba[..., :3] = 1.0  # white, fully transparent
    >>> with tempfile.TemporaryDirectory() as d:
    ...     read_grey_map(save_image(d + "/m.png", rgba), "--mask").tolist()
    [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]
    """
    from .io import load_image

    image = load_image(path)
    if image.ndim == 3:
        channels = image.shape[-1]
        image = image[..., 0] if channels <= 2 else image[..., :3].mean(axis=-1)  # (grey | RGB) [+ alpha]
    if image.ndim != 2:
        raise CommandError(f"{option} {str(path)!r} is not a 2-D image (shape {image.shape}); pass a grey or RGB image")
    return image
