"""The ``texsynth`` command.

::

    texsynth list
    texsynth demo [--out DIR] [--only NAME,...]
    texsynth batch INPUT_FOLDER_OR_MANIFEST -o FOLDER [--methods a,b] [--seeds N] [--scheduler tcp://HOST:PORT]
    texsynth METHOD INPUT [INPUT ...] -o OUTPUT [--size WxH] [--seed N] [--bits 8|16|32] [method options]
    texsynth quilt albedo.png -o out.png --channels height.png,rough.png --normal-maps normal.png
    texsynth quilt albedo.png -o out.png --coordinates out_map.npz
    texsynth apply-coordinates out_map.npz height.png -o out_height.png [--normal-map]
    texsynth surface MESH EXEMPLAR -o out.ply [--mode vertex|lapped] [--n-vertices N | --pixel-size S] [--field F]

The methods and how each is exposed come from :mod:`texsynth.registry`; each
method's options are generated from the keyword-only parameters of its Python
function and their numpydoc descriptions, so the command and the API never
drift apart. Bad input gives a one-line error and exit status 2.

An option group, a parameter whose default is a frozen dataclass instance
(``search=Search()``), is flattened: each of its fields is a flag named after
the field (``--method``, ``--candidates``, ``--k``), with the field's value in
the default instance as its default and its help from the class's numpydoc
``Parameters``; the group's fields are listed under their own heading of
``--help``. The registry's lists (``files``, ``maps``, ``fields``, ``skip``,
...) name fields as they name parameters, with the same handling. The flags
given rebuild the group, ``dataclasses.replace(default, **given)``, and the
others keep the default's values; an error of the group's constructor names
the flag (``--k must be ...``). Field names are unique per function (a clash
fails when the parser is built).

The output keeps the bit depth of the (first) input file, as far as its format
allows (PNG up to 16 bits, TIFF up to 32-bit float, other formats 8), unless
``--bits`` says otherwise. Methods that record where each output pixel came
from (:data:`texsynth.registry.COORDINATE_METHODS`) take ``--channels`` and
``--normal-maps``: more images of the input's size (height, roughness, normal
maps of the same material) rendered through the synthesis's source-coordinate
map (:func:`texsynth.apply_coordinates`) and written next to the output as
``OUTPUT-STEM_CHANNEL-STEM.SUFFIX``, all files or none. ``--coordinates MAP.npz``
saves the map itself (:func:`texsynth.io.save_coordinates`) with the output,
and ``texsynth apply-coordinates`` renders a channel through it later.
"""

from __future__ import annotations

import argparse
import ast
import dataclasses
import importlib
import inspect
import re
import shutil
import sys
import textwrap
from pathlib import Path

from .io import check_suffix
from .registry import (COORDINATE_METHODS, METHODS, VIDEO_COORDINATE_METHODS, Method, group_fields, group_options,
                       is_group, option_holder)

__all__ = ["main", "METHODS", "Method"]


_ALWAYS_SKIPPED = {"rng", "progress", "return_info"}


class CommandError(Exception):
    """A user error on the command line: printed on one line, exit status 2."""


def _doc_entries(func):
    """The Parameters section of a numpydoc docstring as [(names, description)], one per entry."""
    doc = inspect.getdoc(func) or ""
    match = re.search(r"^Parameters\n-+\n(.*?)(?:^\w[\w ]*\n-+\n|\Z)", doc, re.S | re.M)
    entries = []
    if not match:
        return entries
    for line in match.group(1).splitlines():
        if line and not line.startswith(" "):
            names = line.split(":")[0]
            entries.append(([n.strip() for n in names.split(",") if n.strip()], ""))
        elif entries and line.strip():
            names, text = entries[-1]
            entries[-1] = (names, (text + " " + line.strip()).strip())
    return entries


_REFERENCE = re.compile(r"^As in :(?:func|meth):`~?([\w.]+)`")
_ONLY_REFERENCE = re.compile(r"^As in :(?:func|meth):`~?[\w.]+`\.?$")  # nothing but the pointer


def _referenced_function(func, text):
    """The function a description such as "As in :func:`optimize_texture`, ..." refers to, or None.

    A bare name is looked up in the module of ``func``, then among texsynth's public names.
    """
    match = _REFERENCE.match(text)
    if not match:
        return None
    module_name, _, name = match.group(1).rpartition(".")
    try:
        module = importlib.import_module(module_name) if module_name else sys.modules[func.__module__]
    except (ImportError, KeyError):
        return None
    other = getattr(module, name, None)
    if other is None and not module_name:
        try:
            other = getattr(importlib.import_module("texsynth"), name, None)
        except ImportError:
            return None
    return other if callable(other) and other is not func else None


def _doc_sources(obj):
    """The Parameters entries of ``obj``'s docstring and, for a function, those of its option groups' classes."""
    entries = list(_doc_entries(obj))
    for param in _parameters(obj).values():
        if is_group(param.default):
            entries += _doc_entries(type(param.default))
    return entries


def _parameters(obj):
    """The parameters of a function's signature ({} for a class or what has no signature)."""
    if isinstance(obj, type):
        return {}
    try:
        return inspect.signature(obj).parameters
    except (TypeError, ValueError):
        return {}


def _group_heading(pname, default):
    """The --help heading of an option group's flags: ``search=Search(...)``."""
    return f"{pname}={type(default).__name__}(...)"


def _full_doc(obj, seen=()):
    """{name: description} of ``obj``'s parameters (and its groups' fields), each complete on its own.

    A grouped entry's description goes to each of its names, after the name's
    own description from the function the entry refers to ("As in
    :func:`inpaint`"), itself complete; a bare "As in ..." is dropped where
    the name has its own. No description points to another option: these
    are what another function's grouped entry borrows.
    """
    out = {}
    for names, text in _doc_sources(obj):
        other = _referenced_function(obj, text)
        own = _full_doc(other, seen + (obj,)) if other is not None and other not in seen else {}
        for n in names:
            mine = own.get(n, "")
            out[n] = mine if mine and _ONLY_REFERENCE.match(text) else f"{mine} {text}".strip()
    return out


def _doc_params(func, shown=None):
    """Option descriptions from a numpydoc docstring: {name: description}.

    The function's Parameters section, and for each option group (a
    parameter whose default is a dataclass instance) the Parameters section
    of the group's class, one entry per field. A grouped entry (``a, b, c :
    type`` with one description for all) gives its description to the
    first of its names that is ``shown`` as an option; the others get "see
    --first" instead of a copy of the same sentence. When the description
    refers to another function ("As in :func:`optimize_texture`, ..."),
    every name also gets its own, complete description from that function's
    docstring (a bare "As in ..." is then left out); a name whose
    description is the same as an option shown before it gets "See
    --that-option." instead of a copy.
    """
    out = {}
    carrier = {}  # a borrowed description -> the shown option that carries it
    groups = {pname: _group_heading(pname, param.default) for pname, param in _parameters(func).items()
              if is_group(param.default) and (shown is None or any(
                  field.name in shown for field in group_fields(param.default)))}  # the headings of their flags

    def flag(name):
        return groups.get(name) or "--" + name.replace("_", "-")

    for names, text in _doc_sources(func):
        other = _referenced_function(func, text)
        own = _full_doc(other, (func,)) if other is not None else {}
        visible = [n for n in names if shown is None or n in shown or n in groups]
        first = (visible or names)[0]
        bare = bool(_ONLY_REFERENCE.match(text))
        for n in names:
            mine = own.get(n, "")
            if mine in carrier:
                out[n] = f"See {flag(carrier[mine])}."
                continue
            if mine and n in visible:
                carrier[mine] = n
            if n == first:
                out[n] = mine if mine and bare else f"{mine} {text}".strip()
            elif mine and bare:  # its own description says it all
                out[n] = mine
            else:
                out[n] = f"{mine} (see {flag(first)})" if mine else f"See {flag(first)}."
    return out


def _plain(text):
    """numpydoc markup to plain help text: ``x`` -> x, :func:`~a.f` -> f()."""
    text = re.sub(r":(?:func|meth):`~?(?:[\w]+\.)*(\w+)`", r"\1()", text)
    text = re.sub(r":\w+:`~?([^`]+)`", r"\1", text)
    text = re.sub(r"\s*\[\d+\]_", "", text)  # citations of the References section: [2]_
    return text.replace("``", "")


def _parse_value(text):
    """Command-line text to a Python value: numbers, tuples, None, else the string."""
    if text.lower() in {"none", "null"}:
        return None
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text


def parse_size(text):
    """``"WxH"`` or ``"N"`` to ``(height, width)``.

    >>> parse_size("320x200"), parse_size("64")
    ((200, 320), (64, 64))
    """
    parts = text.lower().split("x")
    try:
        numbers = [int(p) for p in parts]
    except ValueError:
        raise CommandError(f"--size must look like WIDTHxHEIGHT (e.g. 256x256) or one number, got {text!r}") from None
    if len(numbers) == 1:
        numbers = numbers * 2
    if len(numbers) == 3:  # volumes: WxHxD
        width, height, depth = numbers
        return depth, height, width
    if len(numbers) != 2 or min(numbers) < 1:
        raise CommandError(f"--size must be positive WIDTHxHEIGHT, got {text!r}")
    width, height = numbers
    return height, width


def _add_method_parser(sub, name, method):
    func = method.function()
    first_line = (inspect.getdoc(func) or method.summary).splitlines()[0]
    parser = sub.add_parser(name, help=method.summary, description=f"{method.summary}\n\n{first_line}",
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    if method.inputs == "images":
        parser.add_argument("inputs", nargs="+", metavar="INPUT", help="input images")
    elif method.inputs == "pair":
        parser.add_argument("inputs", nargs=2, metavar="INPUT", help="the two input images")
    elif method.inputs in {"image", "frames"}:
        what = "input image" if method.inputs == "image" else "input frames: a GIF, video or folder of images"
        parser.add_argument("inputs", nargs=1, metavar="INPUT", help=what)
    parser.add_argument("-o", "--output", required=True, help="output file (or folder for frames)")
    if method.size or method.flow:
        parser.add_argument("--size", help="output size WIDTHxHEIGHT (WxHxD for volumes); default: the input's")
    parser.add_argument("--seed", type=int, default=None, help="random seed (same seed, same output)")
    parser.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    if method.output == "image":
        parser.add_argument("--bits", type=int, choices=(8, 16, 32), default=None,
                            help="bits per sample of the output file: 8, 16 (PNG, TIFF) or 32 (float TIFF); "
                                 "default: the input file's, as far as the output format allows")
    if name in COORDINATE_METHODS:
        parser.add_argument("--channels", metavar="FILES",
                            help="comma-separated images of the input's size (height, roughness, ...) rendered "
                                 "through the synthesis's source-coordinate map and written next to OUTPUT as "
                                 "OUTPUT-STEM_CHANNEL-STEM (each keeps its own bit depth unless --bits is given)")
        parser.add_argument("--normal-maps", metavar="FILES",
                            help="as --channels, for tangent-space normal maps: blended pixels are renormalised")
        if method.inputs == "images":
            parser.description += ("\n\nWith several inputs, each --channels/--normal-maps entry is one file per "
                                   "input joined by '+', in the inputs' order: --channels ha.png+hb.png")
    if name in COORDINATE_METHODS or name in VIDEO_COORDINATE_METHODS:
        parser.add_argument("--coordinates", metavar="MAP.npz",
                            help="also save the source-coordinate map (coordinates, weights, source_index) to this "
                                 ".npz file, written with OUTPUT as a set; 'texsynth apply-coordinates MAP.npz "
                                 "CHANNEL -o OUT' renders a channel (for a video: the channel's frames) through it "
                                 "later")
    params = inspect.signature(func).parameters
    options = _options(method, params)
    shown = [option.name for option in options]
    help_text = _doc_params(func, shown)
    containers = {}  # an option group's parameter -> its section of the help
    for option in options:
        pname, default = option.name, option.default
        if option.group is None:
            container = parser
        elif option.group not in containers:
            group_doc = f"{_plain(help_text.get(option.group, ''))} Each flag sets one field of {option.group}; " \
                        f"the others keep their defaults."  # wrapped here: the description formatter is raw
            width = max(40, shutil.get_terminal_size().columns - 4)
            containers[option.group] = container = parser.add_argument_group(
                _group_heading(option.group, params[option.group].default),
                textwrap.fill(group_doc.strip(), width))
        else:
            container = containers[option.group]
        flag = "--" + pname.replace("_", "-")
        flags = [flag]
        desc = _plain(help_text.get(pname, "")).replace("%", "%%")  # argparse %-formats help strings
        required = default is inspect.Parameter.empty
        if pname == method.spatial:
            # NAME (number | ramp | file), NAME-map FILE and --transition: one of them, at most
            group = container.add_mutually_exclusive_group(required=required)
            forms = ["a number"] + (["'ramp' (as --transition)"] if pname in method.ramps else []) + (
                ["a grey image file (as " + flag + "-map)"] if pname in method.maps else [])
            group.add_argument(*flags, dest=pname, type=_parse_value, default=None if required else default,
                               help=f"{', '.join(forms[:-1])} or {forms[-1]}. {desc}" if len(forms) > 1 else desc)
            group.add_argument(flag + "-map", dest=f"_{pname}_map", metavar="PATH",
                               help=f"grey image file of {pname} values in [0, 1] (colour channels averaged, an "
                                    f"alpha channel ignored); the output has its size unless --size is given")
            group.add_argument("--transition", dest=f"_{pname}_transition", action="store_true",
                               help=f"a transition strip: {pname} rising from 0 at the left edge to 1 at the "
                                    f"right edge of the output (--size, default the first input's size)")
        elif pname == method.mixing:
            container.add_argument(*flags, dest=pname, default="equal",
                                   help="one weight per input: 'equal', 'ramp' (first input at the left edge to "
                                        "the last at the right) or grey weight images, comma-separated (one per "
                                        "input, or one file m for two inputs: weights 1-m and m) (default: 'equal')")
        elif pname in method.map_pairs:
            container.add_argument(*flags, dest=pname, nargs=2, metavar=("PATH1", "PATH2"), default=default,
                                   help=f"two image files, read as binary maps (grey, colour channels averaged, "
                                        f"an alpha channel ignored, threshold 0.5). {desc}")
        elif required:
            container.add_argument(*flags, dest=pname, type=_parse_value, required=True, help=desc)
        elif pname in method.maps:
            container.add_argument(*flags, dest=pname, metavar="PATH", default=default,
                                   help=f"grey image file (colour channels averaged, an alpha channel ignored). "
                                        f"{desc}")
        elif pname in method.fields:
            container.add_argument(*flags, dest=pname, metavar="VALUE|PATH", default=default,
                                   help=f"a number, a .npy array of the output's size, or a grey image file (grey "
                                        f"{_FIELD_GREY[pname][1]}). {desc}")
        elif pname in method.files:
            container.add_argument(*flags, dest=pname, metavar="PATH", default=default, help=f"image file. {desc}")
        elif isinstance(default, bool):
            container.add_argument(*flags, dest=pname, action=argparse.BooleanOptionalAction, default=default,
                                   help=f"{desc} (default: {default})")
        else:  # a string default is a word of a closed vocabulary: no literal parsing ("none" stays "none"),
            # except "auto", which stands for a value chosen for the input (a number, a tuple or None)
            word = isinstance(default, str) and default != "auto"
            container.add_argument(*flags, dest=pname, type=str if word else _parse_value,
                                   default=default, help=f"{desc} (default: {default!r})")
    parser.set_defaults(_method=name)
    return parser


def parse_flow(text, shape):
    """``KIND:AMOUNT`` to a flow field of the given shape (texsynth.core.flows).

    KIND is ``sink``, ``source``, ``vortex`` (AMOUNT: speed in pixels per
    frame), ``rotation`` (radians per frame) or ``translation`` (AMOUNT: one
    number for a horizontal shift, or ``(dx, dy)``).

    >>> parse_flow("translation:(1, 0)", (4, 6)).shape
    (4, 6, 2)
    """
    from .core import flows

    kinds = {"sink": flows.sink, "source": flows.source, "vortex": flows.vortex, "rotation": flows.rotation,
             "translation": flows.translation}
    kind, _, amount = str(text).partition(":")
    if kind not in kinds or not amount:
        raise CommandError(f"--flows must be KIND:AMOUNT with KIND one of {', '.join(kinds)}, got {text!r}")
    value = _parse_value(amount)
    if kind == "translation" and not isinstance(value, tuple):
        value = (value, 0.0)
    return kinds[kind](tuple(shape), value)


def _ramp(shape):
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
        t = _ramp(shape) * (n - 1)
        return [np.clip(1.0 - np.abs(t - i), 0.0, 1.0) for i in range(n)]
    paths = str(text).split(",")
    if len(paths) not in {n, 1} or (len(paths) == 1 and n != 2):
        raise CommandError(f"--weights needs 'equal', 'ramp', one image file per input ({n}) "
                           f"or, for two inputs, one file; got {text!r}")
    maps = [read_grey_map(path, "--weights") for path in paths]
    return [1.0 - maps[0], maps[0]] if len(paths) == 1 else maps


# grey 0..1 of a field image -> the field's values, and the mapping in words
_FIELD_GREY = {"orientation": (lambda g: 2.0 * 3.141592653589793 * g, "0..1 -> angle 0..2 pi, counter-clockwise"),
               "scale": (lambda g: 2.0 ** (2.0 * g - 1.0), "0..1 -> scale 0.5..2 geometrically, 0.5 -> 1")}


def read_field(text, name):
    """``--orientation``/``--scale`` text to a field: a number, a ``.npy`` array or a grey image file.

    A number is the field everywhere; a ``.npy`` file holds the values
    themselves (radians; scale factors) at the output's size; any other path
    is an image read by :func:`read_grey_map` whose grey ``g`` in [0, 1]
    maps to ``2 pi g`` radians (orientation) or the scale ``2^(2g - 1)``
    (0.5 at black, 1 at mid-grey, 2 at white). A callable is API-only.

    >>> read_field("1.5", "scale")
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
    return _FIELD_GREY[name][0](read_grey_map(text, option))


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


class _Option:
    """One method option on the command line: a parameter, or a field of an option group.

    ``group`` is the parameter whose dataclass instance holds the field
    (None for a parameter); ``default`` is the parameter's default or the
    field's value in that instance (``inspect.Parameter.empty``: required).
    """

    __slots__ = ("name", "default", "group")

    def __init__(self, name, default, group=None):
        self.name, self.default, self.group = name, default, group


def _options(method, params):
    """The method's --options in signature order: keyword-only parameters, and positional ones after the inputs
    and size; an option group (a parameter whose default is a dataclass instance) gives one option per field.

    Every name in the registry's lists (``files``, ``maps``, ``skip``, ...) may be a parameter or a field.
    Field names are unique across the function's groups and parameters (they are the flags): a clash is a
    TypeError here, when the parser is built.
    """
    consumed = {"image": 1, "images": 1, "frames": 1, "pair": 2, "none": 0}[method.inputs]
    if method.size and params[method.size].kind is not inspect.Parameter.KEYWORD_ONLY:
        consumed += 1
    owners = {pname: None for pname in params}  # a name -> the group that holds it (None: a parameter)
    options = []
    for position, (pname, param) in enumerate(params.items()):
        if is_group(param.default):
            for field in group_fields(param.default):
                if field.name in owners and field.name != pname:
                    other = owners[field.name]
                    where = f"a field of {other}= too" if other else "also a parameter"
                    raise TypeError(f"{method.target}: {field.name!r} is a field of {pname}="
                                    f"{type(param.default).__name__}(...) and {where}; the command line makes one "
                                    f"flag of each name, so field names must be unique per function: rename one")
                owners[field.name] = pname
        if pname in _ALWAYS_SKIPPED or pname in method.skip or pname == method.size:
            continue
        if param.kind is inspect.Parameter.KEYWORD_ONLY or (
                param.kind is inspect.Parameter.POSITIONAL_OR_KEYWORD and position >= consumed):
            if not is_group(param.default):
                options.append(_Option(pname, param.default))
                continue
            options += [_Option(field.name, getattr(param.default, field.name), pname)
                        for field in group_fields(param.default)
                        if field.name not in _ALWAYS_SKIPPED and field.name not in method.skip]
    return options


def _option_names(method, params):
    """The names of the method's --options: parameters and option groups' fields (see :func:`_options`)."""
    return [option.name for option in _options(method, params)]


def _flag_message(message, names):
    """An option group's error message with the fields it names as flags ("k must be" -> "--k must be"); if it
    names none of ``names`` (the fields given), they are put in front."""
    named = False
    for name in sorted(names, key=len, reverse=True):
        message, n = re.subn(rf"(?<![\w\-.'\"`]){re.escape(name)}(?![\w\-'\"`(])",
                             "--" + name.replace("_", "-"), message)
        named = named or n > 0
    return message if named else ", ".join("--" + n.replace("_", "-") for n in names) + ": " + message


def _rebuild_group(default, given):
    """The option group ``default`` with the fields the command line ``given`` ({field: value}) replaced."""
    try:
        return dataclasses.replace(default, **given)
    except (ValueError, TypeError) as error:
        message = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise CommandError(_flag_message(message, list(given))) from None


def _match_channels(first, second):
    """On the command line a grey image paired with a colour one is repeated to the colour one's channels."""
    import numpy as np

    def channels(image):
        return 1 if image.ndim == 2 else image.shape[-1]

    def widen(image, c):
        grey = image if image.ndim == 2 else image[..., 0]
        return np.repeat(grey[..., None], c, axis=-1)

    if channels(first) == 1 and channels(second) > 1:
        first = widen(first, channels(second))
    elif channels(second) == 1 and channels(first) > 1:
        second = widen(second, channels(first))
    return first, second


def _spatial_value(method, args, pname, value, shape):
    """The value of a ``Method.spatial`` parameter from NAME, NAME-map or --transition (exclusive)."""
    map_path = getattr(args, f"_{pname}_map")
    if map_path is not None:
        return read_grey_map(map_path, "--" + pname.replace("_", "-") + "-map")
    if getattr(args, f"_{pname}_transition") or (pname in method.ramps and value == "ramp"):
        return _ramp(shape)
    if pname in method.maps and isinstance(value, str):
        return read_grey_map(value, "--" + pname.replace("_", "-"))
    return value


def _load_inputs(method, paths):
    from .io import load_frames, load_image

    loader = load_frames if method.inputs == "frames" else load_image
    return [loader(p) for p in paths]


_MOST_BITS = {".png": 16, ".tif": 32, ".tiff": 32, ".npy": 32}


def _output_bits(requested, source, path):
    """The bits of an output file: ``--bits`` if given, else the ``source`` file's (None: the format's default),
    as far as the format of ``path`` stores them."""
    if requested is not None:
        return requested
    if source is None:
        return None
    from .io import image_bits

    return min(image_bits(source), _MOST_BITS.get(Path(path).suffix.lower(), 8))


def _channel_files(args, output, n_inputs=1):
    """``[(channel paths, output path, is a normal map)]`` of --channels and --normal-maps: one path per input
    (``a.png+b.png`` with several inputs), the output named after the first."""
    out = Path(output)
    pairs = []
    for option, normal in (("channels", False), ("normal_maps", True)):
        text = getattr(args, option, None)
        for part in (text.split(",") if text else []):
            paths = [Path(p.strip()) for p in part.split("+")] if n_inputs > 1 else [Path(part.strip())]
            if not part.strip() or not all(str(p) != "." for p in paths):
                raise CommandError(f"--{option.replace('_', '-')} has an empty file name in {text!r}; pass "
                                   "comma-separated image files")
            if len(paths) != n_inputs:
                raise CommandError(f"--{option.replace('_', '-')} entry {part!r} has {len(paths)} file(s) for "
                                   f"{n_inputs} inputs; join one file per input with '+', e.g. ha.png+hb.png")
            pairs.append((paths, out.with_name(f"{out.stem}_{paths[0].stem}{out.suffix}"), normal))
    targets = [out] + [t for _, t, _ in pairs]
    if len({t.resolve() for t in targets}) < len(targets):
        raise CommandError("two --channels files have the same name (or the output's); rename one of them")
    return pairs


DEFAULT_CHUNKS = 2048
"""Block side of ``--chunks`` when a .zarr output asks for blocks without giving their size."""


def _write(method, result, output, overwrite, bits=None, extra=None):
    import numpy as np

    from .io import save_frames, save_image

    out = Path(output)
    if method.output == "frames":
        if extra:  # a video's --coordinates map and the frames, both or neither (the frames last)
            return _write_set({**{path: writer for path, (writer, _) in extra.items()},
                               out: lambda path, replace: save_frames(path, result, overwrite=replace)}, overwrite)
        save_frames(out, result, overwrite=overwrite)
        return [out]
    if hasattr(result, "dask"):  # a lazy image (chunks): block by block, never whole in memory
        from .io import save_chunked

        save_chunked(out, result, bits=bits, overwrite=overwrite, progress=sys.stderr.isatty())
        return [out]
    if extra:  # the output and the channels rendered through its map: all files or none
        return _write_set({out: result, **{path: image for path, (image, _) in extra.items()}}, overwrite,
                          {out: bits, **{path: b for path, (_, b) in extra.items()}})
    if method.output == "volume" or (method.inputs == "none" and np.ndim(result) >= 3
                                     and (np.ndim(result) == 4 or np.shape(result)[-1] > 4)):
        volume = np.asarray(result)
        files = {out.with_suffix(".npy"): volume}
        for axis, label in enumerate("zyx"):
            files[out.with_name(f"{out.stem}_slice_{label}.png")] = np.take(volume, volume.shape[axis] // 2, axis=axis)
        return _write_set(files, overwrite)
    save_image(out, result, overwrite=overwrite, bits=bits)
    return [out]


def _write_set(files, overwrite, bits=None):
    """Write ``{path: image}`` as a set: every target is checked first, and a failure part-way
    removes the files this call created (each file is written atomically by save_image, or by
    ``image(path, overwrite)`` when the value is a writer: the --coordinates map).
    ``bits`` is ``{path: bits}`` (None or missing: save_image's default)."""
    from .io import save_image

    bits = bits or {}

    for path in files:
        if path.exists() and not overwrite:
            raise CommandError(f"output {str(path)!r} exists; pass --overwrite to replace it (nothing was written)")
    created = []
    try:
        for path, image in files.items():
            existed = path.exists()
            if callable(image):  # a file that is not an image (the --coordinates map): its own writer
                image(path, overwrite)
            else:
                save_image(path, image, overwrite=overwrite, bits=bits.get(path))
            if not existed:
                created.append(path)
    except BaseException:
        for path in created:
            path.unlink(missing_ok=True)
        raise
    return list(files)


def _run_method(args):
    import numpy as np

    method = METHODS[args._method]
    func = method.function()
    paths = list(getattr(args, "inputs", []) or [])
    out = Path(args.output).resolve()
    for p in paths:
        if Path(p).resolve() == out:
            raise CommandError(f"output {args.output!r} is also an input; choose another output path")
    if out.exists() and not args.overwrite:
        raise CommandError(f"output {args.output!r} exists; pass --overwrite to replace it")
    # chunks: written block by block to a Zarr store or a tiled BigTIFF (the methods with a chunks= option)
    chunks_holder = option_holder(inspect.signature(func).parameters, "chunks")
    chunked = chunks_holder is not None and (
        out.suffix.lower() == ".zarr" or getattr(args, "chunks", None) is not None)
    if chunked and out.suffix.lower() not in {".zarr", ".tif", ".tiff"}:
        raise CommandError(f"--chunks writes block by block to a .zarr store or a .tif file, got {args.output!r}")
    if method.output != "volume" and not chunked:  # refuse a format that cannot be written before the synthesis runs
        check_suffix(out, frames=method.output == "frames")
    requested_bits = getattr(args, "bits", None)
    if requested_bits == 32 and out.suffix.lower() not in {".tif", ".tiff", ".npy"}:
        raise CommandError(f"--bits 32 (float samples) needs a .tif output, got {args.output!r}")
    if requested_bits == 16 and out.suffix.lower() not in {".png", ".tif", ".tiff", ".npy"}:
        raise CommandError(f"--bits 16 needs a .png or .tif output, got {args.output!r}")
    channel_files = _channel_files(args, args.output, len(paths) if method.inputs == "images" else 1)
    channel_sources = {Path(c).resolve() for group, _, _ in channel_files for c in group}
    for group, target, _ in channel_files:
        for source in group:
            if source.resolve() in {out, *(Path(p).resolve() for p in paths)} or target.resolve() in {
                    Path(p).resolve() for p in paths} | channel_sources:
                raise CommandError(f"--channels file {str(source)!r} is also an input or an output; choose other "
                                   "paths")
        if target.exists() and not args.overwrite:
            raise CommandError(f"output {str(target)!r} (of --channels {str(group[0])!r}) exists; pass --overwrite "
                               "to replace it (nothing was written)")
    map_file = _coordinates_file(args, out, paths, channel_files)
    inputs = _load_inputs(method, paths)
    channels = _load_channels(channel_files, [image.shape[:2] for image in inputs])
    if method.inputs == "pair":
        inputs = _match_channels(*inputs)
    params = inspect.signature(func).parameters
    kwargs = {}
    if "rng" in params:
        kwargs["rng"] = args.seed
    if "progress" in params:
        kwargs["progress"] = not args.no_progress and sys.stderr.isatty()
    positional = list(inputs) if method.inputs != "images" else [inputs]
    size = None
    if method.size:
        if args.size is not None:
            size = parse_size(args.size)
        elif inputs:
            size = inputs[0].shape[:2] if method.inputs != "frames" else inputs[0].shape[1:3]
        else:
            raise CommandError("--size is required for this method")
        if method.output == "volume" and len(size) == 2:  # a volume as deep as it is high
            size = (size[0],) + tuple(size)
    given = {}  # an option group's parameter -> {field: value} of the flags given
    for option in _options(method, params):
        pname = option.name
        value = getattr(args, pname)
        if pname == method.spatial:
            value = _spatial_value(method, args, pname, value, size if method.size else inputs[0].shape[:2])
            if args.size is None and method.size and isinstance(value, np.ndarray):
                size = value.shape[:2]  # a map from a file: the output has its size
        elif pname == method.mixing:
            value = parse_weights(value, len(inputs), size)
        elif pname == method.flow:
            if args.size is None:
                raise CommandError("--size is required for an animation (the flow field's size)")
            value = parse_flow(value, parse_size(args.size))
        elif pname in method.map_pairs and value is not None:
            value = tuple(read_grey_map(path, "--" + pname.replace("_", "-")) > 0.5 for path in value)
        elif pname in method.ramps and value == "ramp":
            value = _ramp(size if method.size else inputs[0].shape[:2])
        elif pname in method.maps and isinstance(value, str):
            value = read_grey_map(value, "--" + pname.replace("_", "-"))
        elif pname in method.fields and isinstance(value, str):
            value = read_field(value, pname)
        elif pname in method.files and isinstance(value, str):
            value = _load_inputs(Method(target="", summary="", inputs="image"), [value])[0]
        if value is not option.default:
            (kwargs if option.group is None else given.setdefault(option.group, {}))[pname] = value
    if chunked:
        (given.setdefault(chunks_holder, {}) if chunks_holder else kwargs).setdefault("chunks", DEFAULT_CHUNKS)
        kwargs.pop("progress", None)  # the writer reports progress, per row of blocks
    for group, fields in given.items():  # each group rebuilt from its default with the flags given
        kwargs[group] = _rebuild_group(params[group].default, fields)
    if method.size:
        if params[method.size].kind is inspect.Parameter.KEYWORD_ONLY:
            kwargs[method.size] = size
        else:
            positional.append(size)
    if channels or map_file:
        kwargs["return_info"] = True
    result = func(*positional, **kwargs)
    info = None
    if isinstance(result, tuple):
        result, info = result[0], result[1]
    result = method.to_unit(result)
    source = paths[0] if paths and method.inputs != "frames" else None
    bits = _output_bits(requested_bits, source, out) if method.output == "image" else None
    extra = None
    if channels:
        from .core.coordinates import apply_coordinates

        several = getattr(info, "source_index", None) is not None  # one image per source, else the first's
        images = apply_coordinates([group if several else group[0] for group, _ in channels], info,
                                   normals=[normal for _, normal in channels])
        extra = {target: (np.clip(image, 0.0, 1.0), _output_bits(requested_bits, group[0], target))
                 for (group, target, _), image in zip(channel_files, images)}
    if map_file:
        from .io import save_coordinates

        extra = dict(extra or {})
        extra[map_file] = (lambda path, overwrite: save_coordinates(path, info, overwrite=overwrite), None)
    return _write(method, result, args.output, args.overwrite, bits, extra)


def _coordinates_file(args, out, paths, channel_files):
    """The ``--coordinates`` target (a .npz that is neither an input nor another output), or None."""
    text = getattr(args, "coordinates", None)
    if not text:
        return None
    target = Path(text)
    if target.suffix.lower() != ".npz":
        raise CommandError(f"--coordinates must be a .npz file, got {text!r}")
    taken = {out, *(Path(p).resolve() for p in paths)} | {t.resolve() for _, t, _ in channel_files}
    if target.resolve() in taken:
        raise CommandError(f"--coordinates {text!r} is also an input or an output; choose another path")
    if target.exists() and not args.overwrite:
        raise CommandError(f"output {text!r} (of --coordinates) exists; pass --overwrite to replace it "
                           "(nothing was written)")
    return target


def _load_channels(channel_files, shapes):
    """The --channels images as ``[(images, is a normal map)]``, one image per input, each of its input's shape
    (``shapes`` None: not checked)."""
    from .io import load_image

    out = []
    for group, _, normal in channel_files:
        images = []
        for path, shape in zip(group, shapes or [None] * len(group)):
            image = load_image(path)
            if shape is not None and image.shape[:2] != tuple(shape):
                raise CommandError(f"--channels file {str(path)!r} is {image.shape[1]}x{image.shape[0]} but its input "
                                   f"is {shape[1]}x{shape[0]}; pass channels of the input's size")
            if normal and (image.ndim != 3 or image.shape[-1] < 3):
                raise CommandError(f"--normal-maps file {str(path)!r} has "
                                   f"{1 if image.ndim == 2 else image.shape[-1]} channel(s); a normal map is RGB "
                                   "(x, y, z encoded in [0, 1])")
            images.append(image)
        if len({(im.dtype, im.shape[2:]) for im in images}) > 1:
            raise CommandError(f"--channels files {', '.join(map(str, group))} differ in channels; give every input's "
                               "file of one channel the same layout (all grey or all RGB)")
        out.append((images, normal))
    return out


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error message (exit status 2, as argparse uses)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def build_parser():
    """The full argument parser (methods that are registered)."""
    parser = _Parser(
        prog="texsynth",
        description="Example-based texture synthesis. 'texsynth list' shows the methods; "
                    "'texsynth METHOD --help' shows a method's options.",
    )
    from . import __version__

    parser.add_argument("--version", action="version", version=f"texsynth {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.add_parser("list", help="list the methods with one line each")
    demo = sub.add_parser("demo", help="write a gallery of every method on bundled sample textures")
    demo.add_argument("--out", default="texsynth-demo", help="gallery folder (default: texsynth-demo)")
    demo.add_argument("--seed", type=int, default=0, help="random seed")
    demo.add_argument("--only", metavar="NAME[,NAME...]",
                      help="only these gallery images, by the names the demo prints (e.g. optimize_bread,quilt_brick)")
    _add_batch_parser(sub)
    _add_apply_coordinates_parser(sub)
    _add_surface_parser(sub)
    for name, method in METHODS.items():
        _add_method_parser(sub, name, method)
    return parser


def _add_apply_coordinates_parser(sub):
    apply = sub.add_parser("apply-coordinates", help="render a channel (height, normal, roughness) through a map "
                                                     "saved by METHOD ... --coordinates MAP.npz",
                           description="Render an image of the exemplar's size through a saved source-coordinate "
                                       "map (texsynth.apply_coordinates), so that it lines up with the synthesis.")
    apply.add_argument("map", metavar="MAP.npz", help="the map, saved with --coordinates")
    apply.add_argument("inputs", nargs="+", metavar="CHANNEL",
                       help="the channel: an image of the exemplar's size (with a map of several inputs, as from "
                            "'mix', one file per input in their order)")
    apply.add_argument("-o", "--output", required=True, help="output image")
    apply.add_argument("--normal-map", action="store_true",
                       help="the channel is a tangent-space normal map: blended pixels are renormalised")
    apply.add_argument("--bits", type=int, choices=(8, 16, 32), default=None,
                       help="bits per sample of the output: 8, 16 (PNG, TIFF) or 32 (float TIFF); default: the "
                            "channel file's, as far as the output format allows")
    apply.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")


def _run_apply_coordinates(args):
    import numpy as np

    from .core.coordinates import apply_coordinates
    from .io import load_coordinates, load_frames, save_frames, save_image

    out = Path(args.output)
    if out.resolve() in {Path(p).resolve() for p in [args.map, *args.inputs]}:
        raise CommandError(f"output {args.output!r} is also an input; choose another output path")
    if out.exists() and not args.overwrite:
        raise CommandError(f"output {args.output!r} exists; pass --overwrite to replace it")
    saved = load_coordinates(args.map)
    if saved.coordinates.ndim == 5:  # a video map (patchwork_video): the channel is a frame sequence
        if len(args.inputs) != 1:
            raise CommandError(f"{args.map!r} is a video map; pass the channel's frames as one GIF, video or folder "
                               f"of images (the input frames' order), got {len(args.inputs)} files")
        check_suffix(out, frames=True)
        frames = load_frames(args.inputs[0])
        rendered = apply_coordinates(list(frames), saved, normals=args.normal_map)
        save_frames(out, np.clip(rendered, 0.0, 1.0), overwrite=args.overwrite)
        return [out]
    check_suffix(out)
    images = _load_channels([([Path(p) for p in args.inputs], out, args.normal_map)], None)[0][0]
    several = saved.source_index is not None
    if not several and len(images) > 1:
        raise CommandError(f"{args.map!r} maps one exemplar but {len(images)} channel files were given; pass one")
    rendered = apply_coordinates(images if several else images[0], saved, normals=args.normal_map)
    bits = _output_bits(args.bits, args.inputs[0], out)
    save_image(out, np.clip(rendered, 0.0, 1.0), overwrite=args.overwrite, bits=bits)
    return [out]


def _add_surface_parser(sub):
    surface = sub.add_parser("surface", help="texture a mesh: vertex synthesis (Turk; Wei & Levoy) or lapped "
                                             "textures (Praun et al.)",
                             description="Synthesise a texture over a triangle mesh (texsynth.synthesize_surface) "
                                         "or paste lapped textures (texsynth.lapped_textures); docs/methods/"
                                         "surfaces.md.")
    surface.add_argument("mesh", metavar="MESH", help="the surface: .obj or .ply (others with texsynth[mesh])")
    surface.add_argument("exemplar", metavar="EXEMPLAR", help="the texture image")
    surface.add_argument("-o", "--output", required=True, help="output mesh (.ply or .obj; a texture goes beside it)")
    surface.add_argument("--mode", choices=("vertex", "lapped"), default="vertex",
                         help="vertex: colour retiled vertices (default); lapped: paste patches into a texture atlas")
    surface.add_argument("--n-vertices", type=int, help="vertex mode: retile to about this many vertices")
    surface.add_argument("--pixel-size", type=float,
                         help="surface length of one exemplar pixel; vertex mode: sets the density instead of "
                              "--n-vertices (neither: the mesh's own vertices); lapped mode: default a quarter of "
                              "the square root of the area per exemplar side")
    surface.add_argument("--field", default="smooth",
                         help="texture orientation: smooth (default), random, latitude or meridian (about the z "
                              "axis through the mesh's centre), or an .npy file of one (x, y, z) vector per vertex")
    surface.add_argument("--symmetry", type=int, choices=(1, 2, 4), default=1,
                         help="rotational symmetry of the texture, for the smooth field (default 1)")
    surface.add_argument("--levels", type=int, help="vertex mode: hierarchy levels (default 3)")
    surface.add_argument("--preset", choices=("default", "paper"), default="default", help="vertex mode: defaults")
    surface.add_argument("--order", choices=("independent", "sweep"),
                         help="vertex mode: all vertices of a level at once per pass (independent, the default "
                              "preset's) or one at a time along Turk's sweep (the paper preset's)")
    surface.add_argument("--seed", type=int, default=None, help="random seed")
    surface.add_argument("--preview", help="also write a rendered preview image (PNG)")
    surface.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")
    surface.add_argument("--allow-outside", action="store_true",
                         help="follow the files MESH names (mtllib, map_Kd, TextureFile) even outside the mesh's "
                              "folder; off by default, so a mesh from elsewhere cannot read other files")


def _surface_field(text, mesh):
    """The --field value: a name, a latitude/meridian callable about the mesh's vertical axis, or a .npy file."""
    import numpy as np

    center = mesh.vertices.mean(axis=0) * np.array([1.0, 1.0, 0.0])

    def latitude(p):
        return np.cross([0.0, 0.0, 1.0], p - center)

    if text in ("smooth", "random"):
        return text
    if text == "latitude":
        return latitude
    if text == "meridian":
        return lambda p: np.cross(p - center, latitude(p))
    if not text.endswith(".npy"):
        raise CommandError(f"--field must be smooth, random, latitude, meridian or an .npy file, got {text!r}")
    return np.load(text, allow_pickle=False)


def _run_surface(args):
    from .io import load_image, save_image
    from .surface import lapped_textures, read_mesh, render_mesh, synthesize_surface, write_mesh

    out = Path(args.output)
    if out.resolve() in {Path(args.mesh).resolve(), Path(args.exemplar).resolve()}:
        raise CommandError(f"output {args.output!r} is also an input; choose another output path")
    if out.exists() and not args.overwrite:
        raise CommandError(f"output {args.output!r} exists; pass --overwrite to replace it")
    mesh = read_mesh(args.mesh, allow_outside=args.allow_outside)
    exemplar = load_image(args.exemplar)
    field = _surface_field(args.field, mesh)
    if args.mode == "lapped":
        if args.n_vertices is not None or args.levels is not None or args.order is not None:
            raise CommandError("--n-vertices, --levels and --order belong to --mode vertex; lapped textures keep "
                               "the mesh")
        result = lapped_textures(mesh, exemplar, pixel_size=args.pixel_size, field=field, symmetry=args.symmetry,
                                 rng=args.seed)
    else:
        options = group_options(synthesize_surface, {
            "n_vertices": args.n_vertices, "pixel_size": args.pixel_size, "field": field, "symmetry": args.symmetry,
            "preset": args.preset, "rng": args.seed,
            **{name: value for name, value in (("levels", args.levels), ("order", args.order)) if value is not None}})
        result = synthesize_surface(mesh, exemplar[..., :3] if exemplar.ndim == 3 and exemplar.shape[2] == 4
                                    else exemplar, **options)
    written = [write_mesh(out, result, overwrite=args.overwrite)]
    if args.preview:
        save_image(args.preview, render_mesh(result, 768), overwrite=args.overwrite)
        written.append(Path(args.preview))
    return written


def _add_batch_parser(sub):
    batch = sub.add_parser("batch", help="exemplars x methods x options x seeds -> a folder, on Dask (docs/scaling.md)")
    batch.add_argument("inputs", metavar="INPUT", help="a folder of exemplar images or a .csv/.json manifest "
                                                       "(columns exemplar, method, options as JSON, seed(s), size)")
    batch.add_argument("-o", "--output", required=True, help="output folder (outputs, summary.json, summary.csv)")
    batch.add_argument("--methods", default="patchwork", help="comma-separated method names (default: patchwork)")
    batch.add_argument("--options", default=None, help="method options as JSON: an object or a list of objects")
    batch.add_argument("--seeds", default="1", help="a count of seeds (default 1) or a JSON list of seed indices")
    batch.add_argument("--size", help="output size WIDTHxHEIGHT; default: the manifest's, else the exemplar's")
    batch.add_argument("--scheduler", help="address of a running Dask scheduler, tcp://HOST:PORT "
                                           "(default: a local cluster on this machine)")
    batch.add_argument("--workers", type=int, default=None, help="local workers (default: one per core)")
    batch.add_argument("--threads", action="store_true", help="local workers are threads, not processes")
    batch.add_argument("--overwrite", action="store_true", help="recompute items whose output exists "
                                                                "(default: skip them, i.e. resume)")
    batch.add_argument("--no-progress", action="store_true", help="no progress bar")


def _run_batch(args):
    import json

    from ._batch import batch

    try:
        options = json.loads(args.options) if args.options else None
        seeds = json.loads(args.seeds)
    except json.JSONDecodeError as exc:
        raise CommandError(f"--options and --seeds must be JSON: {exc}") from None
    size = parse_size(args.size) if args.size else None
    summary = batch(args.inputs, args.output, methods=[m for m in args.methods.split(",") if m], options=options,
                    seeds=seeds, size=size, scheduler=args.scheduler, n_workers=args.workers,
                    processes=not args.threads, overwrite=args.overwrite,
                    progress=not args.no_progress and sys.stderr.isatty())
    print(f"{summary.count('done')} done, {summary.count('skipped')} skipped (output existed), "
          f"{summary.count('failed')} failed in {summary.seconds:.1f} s; see {Path(args.output) / 'summary.csv'}")
    for item in summary.failed:
        print(f"texsynth: failed: {item['exemplar']} {item['method']} seed {item['seed_index']}: "
              f"{item['error'].splitlines()[0]}", file=sys.stderr)
    return 1 if summary.failed else 0


def main(argv=None):
    """Entry point of the ``texsynth`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        if args.command is None:
            parser.print_help()
            return 0
        if args.command == "list":
            width = max((len(n) for n in METHODS), default=4)
            print(f"{'demo':<{width}}  gallery of every method on bundled sample textures")
            print(f"{'batch':<{width}}  many exemplars x methods x seeds into a folder, on Dask (pip install texsynth[dask])")
            print(f"{'apply-coordinates':<{width}}  render a channel through a map saved with --coordinates")
            print(f"{'surface':<{width}}  texture a mesh: vertex synthesis or lapped textures")
            for name, method in METHODS.items():
                print(f"{name:<{width}}  {method.summary}")
            return 0
        if args.command == "demo":
            from .demo import run_demo, select_entries

            entries = None if args.only is None else select_entries(args.only.split(","))
            index = run_demo(args.out, seed=args.seed, entries=entries, log=print)
            print(f"gallery written: {index}")
            return 0
        if args.command == "batch":
            return _run_batch(args)
        if args.command == "apply-coordinates":
            print("wrote " + ", ".join(str(p) for p in _run_apply_coordinates(args)))
            return 0
        if args.command == "surface":
            print("wrote " + ", ".join(str(p) for p in _run_surface(args)))
            return 0
        written = _run_method(args)
        print("wrote " + ", ".join(str(p) for p in written))
        return 0
    except (CommandError, ValueError, TypeError, OSError, MemoryError, ImportError) as exc:
        # bad input, a file that cannot be read or written (missing, a folder, read-only, a full disk):
        # one line, exit status 2, and save_image has left nothing half-written
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        if isinstance(exc, OSError) and exc.filename and str(exc.filename) not in message:
            message = f"{message}: {exc.filename}"
        print(f"texsynth: error: {message}", file=sys.stderr)
        return 2
