"""The ``texsynth`` command.

::

    texsynth list
    texsynth demo [--out DIR] [--only NAME,...]
    texsynth batch INPUT_FOLDER_OR_MANIFEST -o FOLDER [--methods a,b] [--seeds N] [--scheduler tcp://HOST:PORT]
    texsynth METHOD INPUT [INPUT ...] -o OUTPUT [--size WxH|N|4x] [-s SEED] [--bits 8|16|32] [method options]
    texsynth inpaint photo.png --hole hole.png [--invert-mask] -o out.png   (or --hole-channel a)
    texsynth quilt albedo.png -o out.png --channels height.png,rough.png --normal-maps normal.png
    texsynth quilt albedo.png -o out.png --coordinates out_map.npz
    texsynth apply-coordinates out_map.npz height.png -o out_height.png [--normal-map]
    texsynth surface MESH EXEMPLAR -o out.ply [--mode vertex|lapped] [--n-vertices N | --pixel-size S] [--field F]
    texsynth surface MESH A.png -o out.ply --mode progressive --exemplar-b B.png --blend z
    texsynth geometry EXAMPLE.ply -o out.ply [--size N|WxHxD|2x] [--voxels N] [--block B] [--copy-elements]
    texsynth btf SAMPLE.npz -o out.npz [--size N] | --mesh MESH -o out.ply --light X,Y,Z   (SAMPLE: or stones)
    texsynth geometry-analogies A.npy A_PRIME.npy B.ply -o out.ply --field-a z --field-b around-z
    texsynth mesh-quilting SWATCH.ply SURFACE.obj -o out.ply [--unit-length L] [--thickness T]  (or: rivets bumpy)

The methods and how each is exposed come from :mod:`texsynth.registry`. A
method's command is its function's name with dashes (``texsynth
synthesize-pixels`` runs :func:`texsynth.synthesize_pixels`, ``texsynth
carve-seams`` :func:`texsynth.carve_seams`); ``texsynth surface`` runs one of the
two surface methods, chosen by ``--mode``, and ``texsynth geometry`` the geometry
synthesis of :func:`texsynth.geometry.synthesize_geometry`, ``texsynth mesh-quilting``
:func:`texsynth.geometry.mesh_quilting`, ``texsynth btf`` the BTF synthesis of
:func:`texsynth.pixel.synthesize_btf` and :func:`texsynth.surface.synthesize_btf_surface`. A mistyped command names the
likeliest ones ("did you mean 'synthesize-pixels'?"). Each
method's options are generated from the keyword-only parameters of its Python
function and their numpydoc descriptions, so the command and the API never
drift apart: ``--help`` shows the first sentence of each, ``METHOD --help-full``
the whole text. Bad input gives a one-line error and exit status 2; an error the
function raises names the flags (``levels must be`` -> ``--levels must be``,
:func:`_flags_in`), an option the command does not take names the likeliest
ones, and a warning is one ``texsynth: warning:`` line. Abbreviated options
are not accepted (``--scale`` would have been ``--scales`` of
``heeger-bergen``).

``--size`` is ``WIDTHxHEIGHT``, ``N`` or a factor of the input's size
(``4x``, ``1.5x``; :func:`parse_size`); ``-s`` is ``--seed``. A method's
main mask (:attr:`texsynth.registry.Method.mask`) is an image file, white =
its meaning (``--hole``: fill), and ``--invert-mask`` swaps black and white;
``inpaint`` also takes ``--hole-channel a``, the input's transparency.

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
allows (PNG up to 16 bits, TIFF and EXR up to 32-bit float, other formats 8),
unless ``--bits`` says otherwise. A float input outside [0, 1] (a height in
metres, HDR colour) is scaled into [0, 1] by its minimum and maximum for the
synthesis (:func:`texsynth.io.normalize_range`) and its range restored in a
float output (EXR, TIFF with ``--bits 32``); an 8/16-bit output keeps the
scaled values, and a note on stderr says what 0 and 1 stand for. Methods that
record where each output pixel came from
(:data:`texsynth.registry.COORDINATE_METHODS`) take ``--channels`` and
``--normal-maps``: more images of the input's size (height, roughness, normal
maps of the same material) rendered through the synthesis's source-coordinate
map (:func:`texsynth.apply_coordinates`) and written next to the output as
``OUTPUT-STEM_CHANNEL-STEM.SUFFIX``, all files or none, each in its own
file's format and depth (``--channel-format`` chooses another).
``--coordinates MAP.npz`` (or ``MAP.png``, ``.tif``, ``.exr``: an image for
a shader) saves the map itself (:func:`texsynth.io.save_coordinates`) with
the output, and ``texsynth apply-coordinates`` renders a channel through it
later. A ``.zarr`` output (methods with ``chunks``) records the method, its
options, the seed, the exemplar and texsynth's version as attributes;
``--zarr-format 2`` writes Zarr version 2.
"""

from __future__ import annotations

import argparse
import dataclasses
import inspect
import re
import shutil
import sys
import textwrap
from pathlib import Path

from .io._images import check_suffix
from ._cli_shapes import (add_btf_parser, add_geometry_analogies_parser, add_geometry_parser,
                          add_mesh_quilting_parser, add_surface_parser, run_btf, run_geometry,
                          run_geometry_analogies, run_mesh_quilting, run_surface)
from ._cli_text import HelpFull, did_you_mean, doc_params, group_heading, plain_text, short_help
from ._cli_values import (FIELD_GREY, SIZE_FORMS, CommandError, parse_flow, parse_keyframes, parse_size, parse_value,
                          parse_weights, ramp, read_field, read_grey_map)
from .registry import (COORDINATE_METHODS, METHODS, VIDEO_COORDINATE_METHODS, Method, group_fields, is_group,
                       option_holder)

__all__ = ["main", "METHODS", "Method"]


_ALWAYS_SKIPPED = {"rng", "progress", "return_info"}






















"""The forms ``--size`` takes, as its help and its errors say them."""




def _add_method_parser(sub, name, method):
    func = method.function()
    first_line = plain_text((inspect.getdoc(func) or method.summary).splitlines()[0])
    parser = sub.add_parser(name, help=method.summary, description=f"{method.summary}\n\n{first_line}",
                            formatter_class=argparse.RawDescriptionHelpFormatter, allow_abbrev=False)
    if method.inputs == "images":
        parser.add_argument("inputs", nargs="+", metavar="INPUT", help="input images")
    elif method.inputs == "pair":
        parser.add_argument("inputs", nargs=2, metavar="INPUT", help="the two input images")
    elif method.inputs in {"image", "frames"}:
        what = "input image" if method.inputs == "image" else "input frames: a GIF, video or folder of images"
        parser.add_argument("inputs", nargs=1, metavar="INPUT", help=what)
    parser.add_argument("-o", "--output", required=True, help="output file (or folder for frames)")
    if method.size or method.flow:
        parser.add_argument("--size", help=f"output size: {SIZE_FORMS}; default: the input's")
    parser.add_argument("-s", "--seed", type=int, default=None, help="random seed (same seed, same output)")
    parser.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    if method.output == "image":
        parser.add_argument("--bits", type=int, choices=(8, 16, 32), default=None,
                            help="bits per sample of the output file: 8, 16 (PNG, TIFF; EXR: half float) or 32 "
                                 "(float TIFF or EXR); default: the input file's, as far as the output format allows")
    if name in COORDINATE_METHODS:
        parser.add_argument("--channels", metavar="FILES",
                            help="comma-separated images of the input's size (height, roughness, ...) rendered "
                                 "through the synthesis's source-coordinate map and written next to OUTPUT as "
                                 "OUTPUT-STEM_CHANNEL-STEM.SUFFIX, each in its own format and bit depth (see "
                                 "--channel-format)")
        parser.add_argument("--normal-maps", metavar="FILES",
                            help="as --channels, for tangent-space normal maps: blended pixels are renormalised")
        parser.add_argument("--channel-format", choices=tuple(CHANNEL_FORMATS), default="same",
                            help="format of the --channels/--normal-maps outputs: 'same' (default) keeps each "
                                 "channel file's suffix and depth; 'output' takes OUTPUT's suffix and --bits; "
                                 "png8, png16, tif16, tif32 (float), exr16 (half), exr32 (float) force one")
        if method.inputs == "images":
            parser.description += ("\n\nWith several inputs, each --channels/--normal-maps entry is one file per "
                                   "input joined by '+', in the inputs' order: --channels ha.png+hb.png")
    if name in COORDINATE_METHODS or name in VIDEO_COORDINATE_METHODS:
        parser.add_argument("--coordinates", metavar="MAP",
                            help="also save the source-coordinate map to this file, written with OUTPUT as a set: "
                                 ".npz (every source and weight), or an image for a shader, .png (16-bit), .tif or "
                                 ".exr (float), R = (column + 0.5) / exemplar width, G = (row + 0.5) / height; "
                                 "'texsynth apply-coordinates MAP CHANNEL -o OUT' renders a channel (for a video: "
                                 "the channel's frames) through it later")
    if option_holder(inspect.signature(func).parameters, "chunks") is not None:
        parser.add_argument("--zarr-format", type=int, choices=(2, 3), default=None,
                            help="Zarr format version of a .zarr OUTPUT: 3 (default) or 2 for older readers")
    params = inspect.signature(func).parameters
    options = _options(method, params)
    shown = [option.name for option in options]
    help_text = doc_params(func, shown)
    full = {}  # an action or an option group's section -> its full text, which --help-full shows
    width = max(40, shutil.get_terminal_size().columns - 4)
    containers = {}  # an option group's parameter -> its section of the help

    def add(where, *names, describe, **kwargs):
        """add_argument with the help ``describe(first sentence)``; ``describe(whole text)`` for --help-full."""
        action = where.add_argument(*names, help=describe(short), **kwargs)
        full[action] = ("help", describe(long))
        return action

    for option in options:
        pname, default = option.name, option.default
        if option.group is None:
            container = parser
        elif option.group not in containers:
            group_text = plain_text(help_text.get(option.group, ""))
            tail = f" Each flag sets one field of {option.group}; the others keep their defaults."
            # wrapped here: the description formatter is raw
            containers[option.group] = container = parser.add_argument_group(
                group_heading(option.group, params[option.group].default),
                textwrap.fill((short_help(group_text) + tail).strip(), width))
            full[container] = ("description", textwrap.fill((group_text + tail).strip(), width))
        else:
            container = containers[option.group]
        flag = "--" + pname.replace("_", "-")
        flags = [flag]
        long = plain_text(help_text.get(pname, "")).replace("%", "%%")  # argparse %-formats help strings
        short = short_help(long)
        required = default is inspect.Parameter.empty
        if pname == method.spatial:
            # NAME (number | ramp | file), NAME-map FILE and --transition: one of them, at most
            group = container.add_mutually_exclusive_group(required=required)
            forms = ["a number"] + (["'ramp' (as --transition)"] if pname in method.ramps else []) + (
                ["a grey image file (as " + flag + "-map)"] if pname in method.maps else [])
            add(group, *flags, dest=pname, type=parse_value, default=None if required else default,
                describe=lambda d: f"{', '.join(forms[:-1])} or {forms[-1]}. {d}" if len(forms) > 1 else d)
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
        elif pname == method.flow:
            container.add_argument(*flags, dest=pname, metavar="KIND:AMOUNT", required=required,
                                   help="the flow at --size: sink:S, source:S or vortex:S (S pixels per frame), "
                                        "rotation:R (radians per frame) or translation:DX or translation:(DX, DY) "
                                        "(pixels per frame, x to the right, y down)")
        elif pname in method.map_pairs:
            add(container, *flags, dest=pname, nargs=2, metavar=("PATH1", "PATH2"), default=default,
                describe=lambda d: f"two image files, read as binary maps (grey, colour channels averaged, an alpha "
                                   f"channel ignored, threshold 0.5). {d}")
        elif pname == "hole" and pname in method.maps:  # an image file, or the input's transparency
            add(container, *flags, dest=pname, metavar="PATH", default=None if required else default,
                describe=lambda d: "image file, white (> 0.5) = fill (colour channels averaged, an alpha channel "
                                   "ignored); black = fill: add --invert-mask; or --hole-channel a instead."
                                   + ("" if d == short else f" {d}"))
            container.add_argument("--hole-channel", choices=("a",), default=None,
                                   help="a: the hole is the input's transparency (alpha < 1 = fill, the input "
                                        "laid over the fill by its alpha), as "
                                        "hole='alpha' in Python; the input must have an alpha channel")
        elif required:
            add(container, *flags, dest=pname, type=parse_value, required=True, describe=lambda d: d)
        elif pname in method.maps:
            add(container, *flags, dest=pname, metavar="PATH", default=default,
                describe=lambda d: f"grey image file (colour channels averaged, an alpha channel ignored). {d}")
        elif pname in method.fields:
            add(container, *flags, dest=pname, metavar="VALUE|PATH", default=default,
                describe=lambda d: f"a number, a .npy array of the output's size, or a grey image file (grey "
                                   f"{FIELD_GREY[pname][1]}). {d}")
        elif pname in method.files:
            add(container, *flags, dest=pname, metavar="PATH", default=default, describe=lambda d: f"image file. {d}")
        elif isinstance(default, bool):
            add(container, *flags, dest=pname, action=argparse.BooleanOptionalAction, default=default,
                describe=lambda d: f"{d} (default: {default})")
        else:  # a string default is a word of a closed vocabulary: no literal parsing ("none" stays "none"),
            # except "auto", which stands for a value chosen for the input (a number, a tuple or None)
            word = isinstance(default, str) and default != "auto"
            add(container, *flags, dest=pname, type=str if word else parse_value, default=default,
                describe=lambda d: f"{d} (default: {default!r})")
        if pname == method.mask:
            parser.add_argument("--invert-mask", action="store_true",
                                help=f"swap black and white of the {flag} file as read (1 - the map): for a mask "
                                     f"drawn the other way round (Embark marks a hole black)")
    parser.add_argument("--help-full", action=HelpFull, full=full,
                        help="show the full description of every option and exit")
    parser.epilog = textwrap.fill(
        f"Each option shows the first sentence of its description; 'texsynth {name} --help-full' shows them "
        f"whole, help(texsynth.{func.__name__}) in Python the function's documentation, and the docs' page "
        f"docs/methods/{method.page}.md the method.", width)
    parser.set_defaults(_method=name)
    return parser






















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


# words after which a one-word option name is the parameter ("levels must be", "block <= 128", "band 8")
_AS_PARAMETER = r"(?=\s*(?:=|<|>|\d|(?:must|is|are|has|needs|contains|should|cannot|does|takes|gives|leaves)\b))"


def _calls(message):
    """The spans of ``name(...)`` calls in a message (a Python expression such as ``Search(k=2)``)."""
    spans, stack = [], []
    for i, char in enumerate(message):
        if char == "(":
            stack.append(i if i and (message[i - 1].isalnum() or message[i - 1] == "_") else None)
        elif char == ")" and stack:
            opened = stack.pop()
            if opened is not None:
                spans.append((opened, i))
    return spans


def _flags_in(message, names):
    """A function's error (or warning) message with the options of ``names`` it names as the command's flags.

    ``names`` are the options the command shows. A name with an underscore is a parameter wherever it stands
    (``neighborhood_sizes=(16, 8)`` -> ``--neighborhood-sizes=(16, 8)``); a one-word name only where the
    message uses it as one (``levels must be``, ``block <= 128``, ``k=3``, ``band 8``), so that ordinary words
    ("at all levels") stay. Names inside a Python call of the message (``Search(k=2)``) stay too.

    >>> _flags_in("pass block <= 128 or a larger image, not neighborhood_sizes=(64,)", ["block", "neighborhood_sizes"])
    'pass --block <= 128 or a larger image, not --neighborhood-sizes=(64,)'
    >>> _flags_in("levels must be >= 1 (at all levels); pass search=Search(k=2)", ["levels", "k"])
    '--levels must be >= 1 (at all levels); pass search=Search(k=2)'
    """
    for name in sorted(set(names), key=len, reverse=True):
        tail = "" if "_" in name else _AS_PARAMETER
        pattern = re.compile(rf"(?<![\w\-.'\"`]){re.escape(name)}(?![\w\-'\"`(]){tail}")
        calls = _calls(message)
        message = pattern.sub(lambda m: m.group(0) if any(a < m.start() < b for a, b in calls)
                              else "--" + name.replace("_", "-"), message)
    return message


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
        return ramp(shape)
    if pname in method.maps and isinstance(value, str):
        return read_grey_map(value, "--" + pname.replace("_", "-"))
    return value


def _load_inputs(method, paths):
    from .io import load_frames, load_image

    loader = load_frames if method.inputs == "frames" else load_image
    return [loader(p) for p in paths]


def _load_scaled(paths, what="input"):
    """Images of ``paths`` in [0, 1] and the ``(low, high)`` range they stand for: ``(0.0, 1.0)`` unless a float
    file (height, displacement, HDR) leaves [0, 1]; then all of them are scaled by one range, their joint
    minimum and maximum (:func:`texsynth.io.normalize_range`), so that they stay comparable."""
    from .io import load_image, normalize_range, restore_range

    loaded = [load_image(p, normalize=True) for p in paths]
    ranges = {value_range for _, value_range in loaded}
    if ranges <= {(0.0, 1.0)}:
        return [image for image, _ in loaded], (0.0, 1.0)
    joint = (min(lo for lo, _ in ranges), max(hi for _, hi in ranges))
    if len(loaded) == 1:
        return [loaded[0][0]], joint
    return [normalize_range(restore_range(image, r), joint)[0] for image, r in loaded], joint


def _restored(image, value_range, target, bits, what):
    """An output image in [0, 1] as it is written to ``target``: restored to ``value_range`` for a float format,
    else left in [0, 1] with a note on stderr saying what 0 and 1 stand for."""
    from .io import restore_range

    if value_range == (0.0, 1.0):
        return image
    lo, hi = value_range
    suffix = Path(target).suffix.lower()
    if hasattr(image, "dask"):  # a lazy output (chunks): restored block by block into float32 samples
        if bits == 32:
            return image * (hi - lo) + lo
    elif suffix == ".exr" or (suffix in {".tif", ".tiff"} and bits == 32):
        return restore_range(image, value_range)
    print(f"texsynth: note: {what} holds values in [{lo:.6g}, {hi:.6g}]; {Path(target).name} stores them scaled "
          f"into [0, 1] (0 is {lo:.6g}, 1 is {hi:.6g}): write .exr, or .tif with --bits 32, to keep the values",
          file=sys.stderr)
    return image


_MOST_BITS = {".png": 16, ".tif": 32, ".tiff": 32, ".npy": 32, ".exr": 32, ".zarr": 32}


def _output_bits(requested, source, path):
    """The bits of an output file: ``--bits`` if given, else the ``source`` file's (None: the format's default),
    as far as the format of ``path`` stores them (an EXR: half from a half-float EXR, else float32)."""
    if requested is not None:
        return requested
    if source is None:
        return None
    from .io import image_bits

    bits, suffix = image_bits(source), Path(path).suffix.lower()
    if suffix == ".exr":
        return 16 if bits == 16 and Path(source).suffix.lower() == ".exr" else 32
    return min(bits, _MOST_BITS.get(suffix, 8))


def _channel_bits(args, requested, source, target):
    """The bits of a --channels output, by --channel-format (see :data:`CHANNEL_FORMATS`)."""
    fmt = getattr(args, "channel_format", "same") or "same"
    if CHANNEL_FORMATS.get(fmt):
        return CHANNEL_FORMATS[fmt][1]
    return _output_bits(requested if fmt == "output" else None, source, target)


def _channel_suffix(args, source, output):
    """The suffix of a --channels output: the channel file's own ('same', the default), the output's ('output'),
    or --channel-format's; refused up front if texsynth cannot write it."""
    fmt = getattr(args, "channel_format", "same") or "same"
    suffix = source.suffix if fmt == "same" else output.suffix if fmt == "output" else CHANNEL_FORMATS[fmt][0]
    try:
        check_suffix(source.with_suffix(suffix))
    except ValueError:
        raise CommandError(f"--channels file {str(source)!r}: texsynth does not write {suffix or 'suffix-less'} "
                           "files; pass --channel-format png16 (or tif32, exr32, output)") from None
    return suffix


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
            pairs.append((paths, out.with_name(f"{out.stem}_{paths[0].stem}{_channel_suffix(args, paths[0], out)}"),
                          normal))
    targets = [out] + [t for _, t, _ in pairs]
    if len({t.resolve() for t in targets}) < len(targets):
        raise CommandError("two --channels files have the same name (or the output's); rename one of them")
    return pairs


DEFAULT_CHUNKS = 1024
"""Block side of ``--chunks`` when a .zarr output asks for blocks without giving their size (1024: a 2048 x 2048
output is four blocks, written on as many threads)."""

CHANNEL_FORMATS = {"same": None, "output": None, "png8": (".png", 8), "png16": (".png", 16), "tif16": (".tif", 16),
                   "tif32": (".tif", 32), "exr16": (".exr", 16), "exr32": (".exr", 32)}
"""``--channel-format``: ``(suffix, bits)`` of the channel outputs; 'same' keeps each channel file's suffix and
depth, 'output' takes the output's suffix (and ``--bits``)."""


def _write(method, result, output, overwrite, bits=None, extra=None, chunked_options=None):
    """Write the result (and ``extra``: {path: (image or writer, bits)} as one set); ``chunked_options`` are
    :func:`texsynth.io.save_chunked`'s ``attributes`` and ``zarr_format`` for a lazy result."""
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

        save_chunked(out, result, bits=bits, overwrite=overwrite, progress=sys.stderr.isatty(),
                     **(chunked_options or {}))
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
    if requested_bits == 32 and out.suffix.lower() not in {".tif", ".tiff", ".npy", ".exr", ".zarr"}:
        raise CommandError(f"--bits 32 (float samples) needs a .tif or .exr output, got {args.output!r}")
    if requested_bits == 16 and out.suffix.lower() not in {".png", ".tif", ".tiff", ".npy", ".exr", ".zarr"}:
        raise CommandError(f"--bits 16 needs a .png, .tif or .exr output, got {args.output!r}")
    if requested_bits == 8 and out.suffix.lower() == ".exr":
        raise CommandError(f"--bits 8 cannot be stored in an .exr output (half or float samples: --bits 16 or 32), "
                           f"got {args.output!r}")
    if getattr(args, "zarr_format", None) is not None and out.suffix.lower() != ".zarr":
        raise CommandError(f"--zarr-format is for a .zarr output, got {args.output!r}")
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
    map_file = _coordinates_file(args, out, paths, channel_files, method)
    if method.inputs == "frames":
        inputs, value_range = _load_inputs(method, paths), (0.0, 1.0)
    else:  # float files outside [0, 1] (heights, HDR) scaled in, and their range restored on output
        inputs, value_range = _load_scaled(paths)
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
    input_size = None if not inputs else inputs[0].shape[:2] if method.inputs != "frames" else inputs[0].shape[1:3]
    given_size = None if getattr(args, "size", None) is None else parse_size(args.size, input_size)
    size = None
    if method.size:
        if given_size is not None:
            size = given_size
        elif inputs:
            size = input_size
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
            value = parse_flow(value, given_size)
        elif pname in method.map_pairs and value is not None:
            value = tuple(read_grey_map(path, "--" + pname.replace("_", "-")) > 0.5 for path in value)
        elif pname in method.ramps and value == "ramp":
            value = ramp(size if method.size else inputs[0].shape[:2])
        elif pname == "hole" and pname in method.maps:
            value = _hole_value(args, value, inputs[0], pname == method.mask)
        elif pname in method.maps and isinstance(value, str):
            value = read_grey_map(value, "--" + pname.replace("_", "-"))
            if pname == method.mask and args.invert_mask:
                value = 1.0 - value
        elif pname in method.fields and isinstance(value, str):
            value = read_field(value, pname)
        elif pname == "keyframes" and isinstance(value, str):
            value = parse_keyframes(value)
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
    if getattr(args, "invert_mask", False) and not isinstance(getattr(args, method.mask), str) and not (
            method.mask == "hole" and args.hole_channel):
        flag = "--" + method.mask.replace("_", "-")
        raise CommandError(f"--invert-mask inverts the {flag} file; pass {flag} FILE too")
    result = _call(func, positional, kwargs, [option.name for option in _options(method, params)])
    info = None
    if isinstance(result, tuple):
        result, info = result[0], result[1]
    result = method.to_unit(result)
    source = paths[0] if paths and method.inputs != "frames" else None
    bits = _output_bits(requested_bits, source, out) if method.output == "image" else None
    names = " and ".join(Path(p).name for p in paths)
    if method.output == "image":
        result = _restored(result, value_range, out, bits, names)
    else:  # a volume (.npy and PNG slices, one set): kept in [0, 1], with the note
        _restored(result, value_range, out.with_suffix(".png"), None, names)
    extra = None
    if channels:
        from .core.coordinates import apply_coordinates

        several = getattr(info, "source_index", None) is not None  # one image per source, else the first's
        images = apply_coordinates([group if several else group[0] for group, _, _ in channels], info,
                                   normals=[normal for _, normal, _ in channels])
        extra = {}
        for (group, target, _), (_, _, channel_range), image in zip(channel_files, channels, images):
            channel_bits = _channel_bits(args, requested_bits, group[0], target)
            extra[target] = (_restored(np.clip(image, 0.0, 1.0), channel_range, target, channel_bits,
                                       " and ".join(p.name for p in group)), channel_bits)
    if map_file:
        from .io import save_coordinates

        extra = dict(extra or {})
        exemplar_size = inputs[0].shape[:2] if method.inputs != "frames" else None
        extra[map_file] = (lambda path, overwrite: save_coordinates(
            path, info, overwrite=overwrite,
            exemplar_size=exemplar_size if path.suffix.lower() != ".npz" else None), None)
    chunked_options = None
    if chunked:
        chunked_options = {"zarr_format": getattr(args, "zarr_format", None),
                           "attributes": _provenance(args, paths, kwargs, value_range if bits != 32 else (0.0, 1.0))}
    return _write(method, result, args.output, args.overwrite, bits, extra, chunked_options)


def _provenance(args, paths, kwargs, value_range):
    """What a chunked output records about how it was made (Zarr attributes, a TIFF's description)."""
    attributes = {"method": args._method, "options": _jsonable({k: v for k, v in kwargs.items() if k != "rng"}),
                  "seed": args.seed, "exemplar": [Path(p).name for p in paths] if len(paths) > 1 else
                  (Path(paths[0]).name if paths else None)}
    if value_range != (0.0, 1.0):
        attributes["value_range"] = list(value_range)  # what 0 and 1 stand for, where the store keeps [0, 1]
    return attributes


def _jsonable(value):
    """``value`` as JSON values: option groups as dicts of their fields, arrays by their shape, tuples as lists."""
    import numpy as np

    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return f"array of shape {value.shape}"
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return repr(value)  # JSON has no inf or nan
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return repr(value)


def _hole_value(args, value, image, invertible):
    """``--hole FILE`` (white = fill) or ``--hole-channel a`` (the input's alpha < 1) as the function's ``hole``,
    inverted by ``--invert-mask``."""
    channel = getattr(args, "hole_channel", None)
    invert = invertible and getattr(args, "invert_mask", False)
    if channel is not None:
        if value is not None:
            raise CommandError("pass --hole FILE or --hole-channel a, not both")
        if image.ndim != 3 or image.shape[-1] not in (2, 4):
            channels = 1 if image.ndim == 2 else image.shape[-1]
            raise CommandError(f"--hole-channel a takes the hole from the input's alpha channel, but the input has "
                               f"{channels} channel(s) and no alpha; pass an RGBA (or grey + alpha) image, or "
                               f"--hole FILE (white = fill)")
        return image[..., -1] >= 1.0 if invert else "alpha"  # inverted: the opaque pixels are filled
    if value is None:
        raise CommandError("the hole is missing: pass --hole FILE (an image, white = fill) or --hole-channel a "
                           "(the input's transparency)")
    hole = read_grey_map(value, "--hole")
    return 1.0 - hole if invert else hole


def _call(func, positional, kwargs, names):
    """``func(*positional, **kwargs)``: its errors, one line naming the command's flags (``names``: the options
    shown), and its warnings printed as ``texsynth: warning: ...``."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", UserWarning)
        try:
            result = func(*positional, **kwargs)
        except (ValueError, TypeError) as error:
            message = str(error).splitlines()[0] if str(error) else type(error).__name__
            raise CommandError(_flags_in(message, names)) from None
    for warning in caught:
        print(f"texsynth: warning: {_flags_in(str(warning.message), names)}", file=sys.stderr)
    return result


def _coordinates_file(args, out, paths, channel_files, method=None):
    """The ``--coordinates`` target (a .npz, or an image: .png, .tif, .exr, that is neither an input nor another
    output), or None."""
    text = getattr(args, "coordinates", None)
    if not text:
        return None
    target = Path(text)
    suffix = target.suffix.lower()
    if suffix not in {".npz", ".png", ".tif", ".tiff", ".exr"}:
        raise CommandError(f"--coordinates must be a .npz file, or an image (.png, .tif, .exr), got {text!r}")
    if suffix != ".npz" and method is not None and (method.inputs == "frames" or len(paths) > 1):
        what = "a video map" if method.inputs == "frames" else "a map of several inputs"
        raise CommandError(f"--coordinates {text!r}: {what} cannot be saved as an image, which holds one "
                           "exemplar's coordinates; pass a .npz file")
    if suffix == ".exr":
        check_suffix(target)  # an ImportError naming the exr extra, before the synthesis
    taken = {out, *(Path(p).resolve() for p in paths)} | {t.resolve() for _, t, _ in channel_files}
    if target.resolve() in taken:
        raise CommandError(f"--coordinates {text!r} is also an input or an output; choose another path")
    if target.exists() and not args.overwrite:
        raise CommandError(f"output {text!r} (of --coordinates) exists; pass --overwrite to replace it "
                           "(nothing was written)")
    return target


def _load_channels(channel_files, shapes):
    """The --channels images as ``[(images, is a normal map, value range)]``, one image per input, each of its
    input's shape (``shapes`` None: not checked), in [0, 1]: float files outside it scaled by their joint range
    (normal maps stored as vectors in [-1, 1] by that range, which is their usual encoding)."""
    import numpy as np

    from .io import normalize_range, restore_range

    out = []
    for group, _, normal in channel_files:
        images, value_range = _load_scaled(group)
        if normal and value_range != (0.0, 1.0):
            if value_range[0] < -1 - 1e-6 or value_range[1] > 1 + 1e-6:
                raise CommandError(f"--normal-maps file(s) {', '.join(map(str, group))} hold values in "
                                   f"[{value_range[0]:.4g}, {value_range[1]:.4g}]; a normal map is encoded in [0, 1] "
                                   "or holds unit vectors in [-1, 1]")
            images = [normalize_range(restore_range(im, value_range), (-1.0, 1.0))[0] for im in images]
            value_range = (-1.0, 1.0)
        for path, image, shape in zip(group, images, shapes or [None] * len(group)):
            if shape is not None and image.shape[:2] != tuple(shape):
                raise CommandError(f"--channels file {str(path)!r} is {image.shape[1]}x{image.shape[0]} but its input "
                                   f"is {shape[1]}x{shape[0]}; pass channels of the input's size")
            if normal and (image.ndim != 3 or image.shape[-1] < 3):
                raise CommandError(f"--normal-maps file {str(path)!r} has "
                                   f"{1 if image.ndim == 2 else image.shape[-1]} channel(s); a normal map is RGB "
                                   "(x, y, z encoded in [0, 1])")
        if len({im.shape[2:] for im in images}) > 1:
            raise CommandError(f"--channels files {', '.join(map(str, group))} differ in channels; give every input's "
                               "file of one channel the same layout (all grey or all RGB)")
        common = np.result_type(*images)
        out.append(([im.astype(common, copy=False) for im in images], normal, value_range))
    return out


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error message (exit status 2, as argparse uses)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {did_you_mean(message)} (see '{self.prog} --help')\n")


def _refuse_unknown(parser, command, unknown):
    """Exit 2 on options the command does not take, naming the likeliest ones (the command's own parser's
    message); ``--scale`` also says which option sizes the output and which the elements."""
    import difflib

    sub = next((a for a in parser._actions if isinstance(a, argparse._SubParsersAction)), None)
    target = sub.choices.get(command, parser) if sub is not None and command else parser
    known = [o for action in target._actions for o in action.option_strings if o.startswith("--")]
    hints = []
    for given in (u.split("=")[0] for u in unknown if u.startswith("--")):
        close = [c for c in known if c.startswith(given) and c != given][:3] or [  # what an abbreviation meant
            c for c in difflib.get_close_matches(given, known, 3, 0.75) if c != given]
        if given in ("--scale", "--zoom", "--upscale", "--factor") and "--size" in known:
            sizes = "--size 4x makes the output four times the input's size"
            hints.append(sizes + ("; --magnification makes the elements larger" if "--magnification" in known
                                  else "") + (f"; or did you mean {' or '.join(close)}?" if close else ""))
        elif close:
            hints.append(f"{given}: did you mean {' or '.join(close)}?")
    target.error(f"unrecognized arguments: {' '.join(unknown)}" + ("; " + "; ".join(hints) if hints else ""))


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
    demo.add_argument("-s", "--seed", type=int, default=0, help="random seed")
    demo.add_argument("--only", metavar="NAME[,NAME...]",
                      help="only these gallery images, by the names the demo prints (e.g. optimize_bread,quilt_brick)")
    _add_batch_parser(sub)
    _add_apply_coordinates_parser(sub)
    add_surface_parser(sub)
    add_geometry_parser(sub)
    add_geometry_analogies_parser(sub)
    add_mesh_quilting_parser(sub)
    add_btf_parser(sub)
    for name, method in METHODS.items():
        _add_method_parser(sub, name, method)
    return parser


def _add_apply_coordinates_parser(sub):
    apply = sub.add_parser("apply-coordinates", help="render a channel (height, normal, roughness) through a map "
                                                     "saved by METHOD ... --coordinates MAP.npz",
                           description="Render an image of the exemplar's size through a saved source-coordinate "
                                       "map (texsynth.apply_coordinates), so that it lines up with the synthesis. "
                                       "Float channels outside [0, 1] (heights in metres) keep their values in a "
                                       "float output (.exr, .tif with --bits 32).")
    apply.add_argument("map", metavar="MAP",
                       help="the map, saved with --coordinates: .npz, or an image map (.png, .tif, .exr; one "
                            "without texsynth's note of the exemplar size is read at the channel's size)")
    apply.add_argument("inputs", nargs="+", metavar="CHANNEL",
                       help="the channel: an image of the exemplar's size (with a map of several inputs, as from "
                            "'mix-textures', one file per input in their order)")
    apply.add_argument("-o", "--output", required=True, help="output image")
    apply.add_argument("--normal-map", action="store_true",
                       help="the channel is a tangent-space normal map: blended pixels are renormalised")
    apply.add_argument("--bits", type=int, choices=(8, 16, 32), default=None,
                       help="bits per sample of the output: 8, 16 (PNG, TIFF; EXR: half float) or 32 (float TIFF "
                            "or EXR); default: the channel file's, as far as the output format allows")
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
    image_map = Path(args.map).suffix.lower() in {".png", ".tif", ".tiff", ".exr"}
    saved = None if image_map else load_coordinates(args.map)
    if saved is not None and saved.coordinates.ndim == 5:  # a video map (patchwork_video): the channel is frames
        if len(args.inputs) != 1:
            raise CommandError(f"{args.map!r} is a video map; pass the channel's frames as one GIF, video or folder "
                               f"of images (the input frames' order), got {len(args.inputs)} files")
        check_suffix(out, frames=True)
        frames = load_frames(args.inputs[0])
        rendered = apply_coordinates(list(frames), saved, normals=args.normal_map)
        save_frames(out, np.clip(rendered, 0.0, 1.0), overwrite=args.overwrite)
        return [out]
    check_suffix(out)
    suffix = out.suffix.lower()
    if (args.bits == 8 and suffix == ".exr") or (args.bits == 16 and suffix not in {".png", ".tif", ".tiff", ".exr"}) \
            or (args.bits == 32 and suffix not in {".tif", ".tiff", ".exr"}):
        raise CommandError(f"--bits {args.bits} cannot be stored in a {suffix} output; 8: PNG, TIFF, JPEG...; 16: "
                           "PNG, TIFF, EXR (half); 32: TIFF, EXR")
    images, _, value_range = _load_channels([([Path(p) for p in args.inputs], out, args.normal_map)], None)[0]
    if image_map:  # an image map holds coordinates divided by the exemplar's size: the channel's, unless recorded
        saved = load_coordinates(args.map, exemplar_size=images[0].shape[:2])
    several = saved.source_index is not None
    if not several and len(images) > 1:
        raise CommandError(f"{args.map!r} maps one exemplar but {len(images)} channel files were given; pass one")
    rendered = apply_coordinates(images if several else images[0], saved, normals=args.normal_map)
    bits = _output_bits(args.bits, args.inputs[0], out)
    rendered = _restored(np.clip(rendered, 0.0, 1.0), value_range, out, bits, " and ".join(args.inputs))
    save_image(out, rendered, overwrite=args.overwrite, bits=bits)
    return [out]


def _add_batch_parser(sub):
    batch = sub.add_parser("batch", help="exemplars x methods x options x seeds -> a folder, on Dask (docs/scaling.md)")
    batch.add_argument("inputs", metavar="INPUT", help="a folder of exemplar images or a .csv/.json manifest "
                                                       "(columns exemplar, method, options as JSON, seed(s), size)")
    batch.add_argument("-o", "--output", required=True, help="output folder (outputs, summary.json, summary.csv)")
    batch.add_argument("--methods", default="patchwork", help="comma-separated method names (default: patchwork)")
    batch.add_argument("--options", default=None, help="method options as JSON: an object or a list of objects")
    batch.add_argument("--seeds", default="1", help="a count of seeds (default 1) or a JSON list of seed indices")
    batch.add_argument("--size", help="output size WIDTHxHEIGHT, N, or a factor of each exemplar's size (4x); "
                                      "default: the manifest's, else the exemplar's")
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
    factor = args.size and re.fullmatch(r"[\d.]+[xX]", args.size.strip())
    size = args.size.strip() if factor else parse_size(args.size) if args.size else None  # a factor: per exemplar
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
    args, unknown = parser.parse_known_args(argv)
    if unknown:
        _refuse_unknown(parser, getattr(args, "command", None), unknown)
    try:
        if args.command is None:
            parser.print_help()
            return 0
        if args.command == "list":
            width = max((len(n) for n in METHODS), default=4)
            print(f"{'demo':<{width}}  gallery of every method on bundled sample textures")
            print(f"{'batch':<{width}}  many exemplars x methods x seeds into a folder, on Dask (the dask extra)")
            print(f"{'apply-coordinates':<{width}}  render a channel through a map saved with --coordinates")
            print(f"{'surface':<{width}}  texture a mesh: vertex synthesis or lapped textures")
            print(f"{'geometry':<{width}}  a larger shape like an example mesh or volume (Lagae et al. 2005)")
            print(f"{'geometry-analogies':<{width}}  a geometric texture carried to another shape (Bhat et al. 2004)")
            print(f"{'mesh-quilting':<{width}}  a swatch of geometry elements quilted over a surface (Zhou et al. 2006)")
            print(f"{'btf':<{width}}  a BTF (images under many lights) larger or over a mesh (Tong et al. 2002)")
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
        commands = {"apply-coordinates": _run_apply_coordinates, "surface": run_surface, "geometry": run_geometry,
                    "geometry-analogies": run_geometry_analogies, "btf": run_btf, "mesh-quilting": run_mesh_quilting}
        written = commands[args.command](args) if args.command in commands else _run_method(args)
        print("wrote " + ", ".join(str(p) for p in written))
        return 0
    except (CommandError, ValueError, TypeError, OSError, MemoryError, ImportError) as exc:
        # bad input, a file that cannot be read or written (missing, a folder, read-only, a full disk):
        # one line, exit status 2, and save_image has left nothing half-written
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        message = message.replace("pass overwrite=True", "pass --overwrite")  # the library's words for a file
        if isinstance(exc, OSError) and exc.filename and str(exc.filename) not in message:
            message = f"{message}: {exc.filename}"
        print(f"texsynth: error: {message}", file=sys.stderr)
        return 2
