"""The one list of texsynth's methods, which the command line, the demo gallery and the docs read.

Each :class:`Method` names a public function, its paper and its docs page, how
``texsynth NAME`` exposes it, and the gallery images ``texsynth demo`` makes of
it. Adding a method to the library is: its module in its family's folder, its
name in the family's ``__init__`` and in ``texsynth/__init__.py``, and one entry
here; then a docs page, tests, and a row of the table in ``docs/methods/index.md``,
which ``tests/test_registry.py`` holds against this list. See ``docs/architecture.md``.

One stem per algorithm: the module ``<family>/_X.py`` has its page
``docs/methods/X.md`` (``page="X"``), its tests ``tests/test_X.py`` (more:
``test_X_<topic>.py``) and its benchmark ``benchmarks/bench_X.py``; the command
is the function's name with dashes (``synthesize_pixels`` -> ``texsynth
synthesize-pixels``). ``tests/test_architecture.py`` holds the stems to it.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
from dataclasses import dataclass
from typing import Callable, NamedTuple

from . import data

__all__ = ["Method", "Demo", "METHODS", "SURFACE_DEMOS", "demos", "methods", "MethodEntry", "MethodList",
           "is_group", "group_fields", "option_holder", "group_options"]


def is_group(default):
    """True if a parameter's default is an option group: an instance of a dataclass (``search=Search()``)."""
    return dataclasses.is_dataclass(default) and not isinstance(default, type)


def group_fields(instance):
    """The fields of an option group that a caller sets by name: those its constructor takes."""
    return [f for f in dataclasses.fields(instance) if f.init and not f.name.startswith("_")]


def option_holder(params, name):
    """Where a function with ``params`` (its signature's parameters) takes the option ``name``: ``""`` (a
    parameter), the option group parameter that has it as a field, or None (nowhere)."""
    if name in params:
        return ""
    return next((pname for pname, param in params.items() if is_group(param.default)
                 and name in {field.name for field in group_fields(param.default)}), None)


def group_options(func, options):
    """Flat options ``{name: value}`` (a command line's, a manifest's) as ``func`` takes them: the fields of
    each option group rebuilt into it with :func:`dataclasses.replace`; a name ``func`` does not take is
    passed on, for its own error.

    >>> from texsynth.optimization import optimize_texture
    >>> group_options(optimize_texture, {"levels": 2, "rng": 0})
    {'rng': 0, 'schedule': Schedule(neighborhood_sizes='auto', levels=2, relative_grid_spacing=0.25, max_iterations=5, tolerance='auto')}
    """
    params = inspect.signature(func).parameters
    out, given = {}, {}
    for name, value in options.items():
        holder = option_holder(params, name)
        if holder:
            given.setdefault(holder, {})[name] = value
        else:
            out[name] = value
    out.update({holder: dataclasses.replace(params[holder].default, **fields) for holder, fields in given.items()})
    return out


@dataclass(frozen=True)
class Demo:
    """One image of the demo gallery: ``make(exemplar, seed)`` returns it.

    ``sample`` is the bundled texture it starts from (None for procedural
    entries); ``paper`` is shown under it.
    """

    slug: str
    title: str
    paper: str
    sample: str | None
    make: Callable


@dataclass(frozen=True)
class Method:
    """One method of the library: its function, paper and page, its command and its gallery images.

    Attributes
    ----------
    target : str
        ``"module:function"`` inside texsynth (e.g. ``"pixel:synthesize_pixels"``).
    summary : str
        One line for ``texsynth list``.
    paper : str
        The paper, with its DOI.
    page : str
        Its page under ``docs/methods`` (without ``.md``): the stem of the module
        of its algorithm (``"kwatra"`` for ``optimization/_kwatra.py``).
    inputs : str
        ``"image"`` (one input image), ``"images"`` (one or more),
        ``"frames"`` (a GIF, video or folder of frames), ``"pair"`` (two images)
        or ``"none"`` (procedural: no input).
    output : str
        ``"image"``, ``"volume"`` (.npy plus PNG slices) or ``"frames"``.
    size : str or None
        Name of the function's size argument if it takes one.
    files : tuple of str
        Parameters whose value on the command line may be an image path
        (numbers and other literals pass through).
    ramps : tuple of str
        Parameters for which the word ``ramp`` means a left-to-right ramp
        from 0 to 1 at the output size (a transition strip).
    flow : str or None
        Parameter that takes a flow field, given on the command line as
        ``KIND:AMOUNT`` (see :func:`texsynth.cli.parse_flow`) at the
        ``--size`` of the output.
    mixing : str or None
        Parameter that takes one weight per input, given on the command line
        as ``equal``, ``ramp`` or image files (see
        :func:`texsynth.cli.parse_weights`).
    maps : tuple of str
        Parameters whose value on the command line may be an image file read
        as one grey map ``(H, W)`` (colour channels averaged, an alpha channel
        ignored), e.g. masks.
    map_pairs : tuple of str
        Parameters that take two binary maps, given as ``--NAME FILE1 FILE2``.
    mask : str or None
        The one map of ``maps`` that ``--invert-mask`` inverts (``1 - map``
        as read from its file): the command's hole or mask, for masks drawn
        the other way round. A map named ``hole`` also gets
        ``--hole-channel a`` (the input's transparency as the hole).
    fields : tuple of str
        Orientation and magnification fields over the output
        (``orientation`` in radians, ``magnification`` factors of the
        elements): on the command line a number, a ``.npy`` array of the
        output's size, or a grey image file mapped by
        :func:`texsynth.cli.read_field` (grey 0..1 -> 0..2 pi for
        ``orientation``, 0.5..2 geometrically for ``magnification``).
    spatial : str or None
        Parameter that is a number or a map of numbers at the output size.
        Besides ``--NAME`` it gets ``--NAME-map FILE`` (a grey image of
        values; the output then has the image's size unless ``--size`` is
        given) and ``--transition`` (a left-to-right ramp from 0 to 1 at the
        output size). The three are mutually exclusive.
    skip : tuple of str
        Keyword parameters not exposed on the command line (arrays, callables).
    values : str
        The function's value range: ``"unit"`` ([0, 1]), ``"signed"``
        ([-1, 1]) or ``"positive"``; mapped to [0, 1] for saving.
    demos : tuple of Demo
        Its images in ``texsynth demo``.
    """

    target: str
    summary: str
    paper: str = ""
    page: str = ""
    inputs: str = "image"
    output: str = "image"
    size: str | None = "size"
    files: tuple = ()
    skip: tuple = ()
    values: tuple = (0.0, 1.0)  # the range the function's values lie in, mapped to [0, 1] for saving
    ramps: tuple = ()
    flow: str | None = None
    mixing: str | None = None
    maps: tuple = ()
    map_pairs: tuple = ()
    mask: str | None = None
    fields: tuple = ()
    spatial: str | None = None
    demos: tuple = ()

    def to_unit(self, result):
        """Map ``values``, the function's range, linearly to [0, 1] for saving (clipped).

        The range is known before the function runs, so a lazy (block by block) result is mapped
        block by block: no pass over the whole image to find its extremes first.
        """
        import numpy as np

        low, high = self.values
        if (low, high) == (0.0, 1.0):
            return result
        return np.clip((result - low) / (high - low), 0.0, 1.0)

    def function(self):
        """The public function (its family is imported now)."""
        module, name = self.target.split(":")
        return getattr(importlib.import_module(f"texsynth.{module}"), name)


# --------------------------------------------------------------------------- the gallery's images
# Sizes are small so that the whole gallery takes about a minute on 2 cores.
def _side_by_side(images, gap=4):
    """Images of one height next to each other, separated by white gaps."""
    import numpy as np

    white = np.ones((images[0].shape[0], gap) + images[0].shape[2:])
    parts = [images[0]]
    for image in images[1:]:
        parts += [white, image]
    return np.concatenate(parts, axis=1)


def _call(target, *args, crop=None, **options):
    """``make(exemplar, seed)``: the function on the (cropped) exemplar with these arguments."""

    def make(exemplar, seed):
        module, name = target.split(":")
        func = getattr(importlib.import_module(f"texsynth.{module}"), name)
        inputs = () if exemplar is None else (exemplar if crop is None else exemplar[:crop, :crop],)
        return func(*inputs, *args, **group_options(func, {"rng": seed, **options}))  # fields into their groups

    return make


def _mixture(exemplar, seed):
    import numpy as np

    from .pixel import mix_textures

    ramp = np.broadcast_to(np.linspace(0.0, 1.0, 192), (96, 192))
    other = data.load("bread")[:64, :64]
    return mix_textures([exemplar[:64, :64], other], (96, 192), weights=[1.0 - ramp, ramp], rng=seed)


def _solid(exemplar, seed):
    from .pixel import synthesize_solid

    volume = synthesize_solid(exemplar[:64, :64], 32, rng=seed)
    # three faces of the cube, one per axis: each should look like the exemplar
    return _side_by_side([volume[0], volume[:, 0], volume[:, :, 0]])


def _quilt_transfer(exemplar, seed):
    from skimage import data as skdata
    from skimage.transform import resize

    from .patch import quilt_transfer

    return quilt_transfer(exemplar, resize(skdata.camera(), (192, 192), anti_aliasing=True), block=16, rng=seed)


def _wang_tileable(exemplar, seed):
    import numpy as np

    from .patch import wang_texture

    return np.tile(wang_texture(exemplar, (120, 120), tile=40, tileable=True, rng=seed), (2, 2, 1))


def _quilt_channels(exemplar, seed):
    import numpy as np
    from scipy import ndimage

    from .core.coordinates import apply_coordinates
    from .patch import quilt

    height = -ndimage.gaussian_filter(exemplar.mean(-1), 0.7)  # a height channel of the same material
    height = (height - height.min()) / np.ptp(height)
    out, info = quilt(exemplar, (128, 128), block=24, rng=seed, return_info=True)
    rendered = apply_coordinates(height, info)  # the height through the albedo's source-coordinate map
    return _side_by_side([out, np.repeat(rendered[..., None], 3, -1)])


def _style_transfer(exemplar, seed):
    import numpy as np
    from skimage import data as skdata
    from skimage.transform import resize

    from .optimization import Guides, optimize_texture

    photo = resize(skdata.camera() / 255.0, (96, 96), anti_aliasing=True)
    texture = exemplar[:64, :64]
    lum = texture @ np.array([0.2125, 0.7154, 0.0721])
    # Hertzmann et al.'s luminance remapping (Sec. 3.4): the texture's luminance to the photo's mean and spread
    guide = np.clip((lum - lum.mean()) / lum.std() * photo.std() + photo.mean(), 0.0, 1.0)
    out = optimize_texture(texture, 96, guides=Guides(exemplar_guide=guide, output_guide=photo, guide_weight=4.0),
                           rng=seed)
    return _side_by_side([np.repeat(photo[..., None], 3, -1), out])


def _text_complete(exemplar, seed):
    from .optimization import Terms, optimize_texture

    return optimize_texture(exemplar[:96, :96], (144, 144), terms=Terms(completeness_weight=1.0, copy_limit=0.2),
                            rng=seed)


def _animate(exemplar, seed):
    from .core import flows
    from .optimization import animate_texture

    frames = animate_texture(exemplar[:96, :96], flows.rotation((96, 96), 0.06), n_frames=8, rng=seed)
    return _side_by_side([frames[0], frames[3], frames[7]])


def _controlled(exemplar, seed):
    import numpy as np

    from .pixel import synthesize_controlled

    def vortex(rows, cols):  # the texture turned along circles about the centre
        return np.arctan2(rows - 96.0, cols - 96.0) + np.pi / 2

    def grow(rows, cols):  # elements from 0.8x at the left to 2x at the right
        return 0.8 + 1.2 * cols / 192.0

    return synthesize_controlled(exemplar[:96, :96], 192, orientation=vortex, magnification=grow, rng=seed)


def _interpolate(exemplar, seed):
    from .optimization import InterpolationSchedule, interpolate_textures

    other = data.load("bumpy")[:64, :64]
    return interpolate_textures(exemplar[:64, :64], other, 0.5, size=(64, 64),
                                schedule=InterpolationSchedule(stages=((2, 17), (1, 17))), rng=seed)


def _seam_carve(exemplar, seed):
    from skimage import data as skdata

    from .patch import carve_seams

    photo = skdata.astronaut()[::4, ::4] / 255.0  # a photograph, not a texture: the sample is not used
    return _side_by_side([photo, carve_seams(photo, (128, 96)), carve_seams(photo, (128, 160))])


def _patchwork_video(exemplar, seed):
    import numpy as np

    from .patch import patchwork_video

    clip = np.stack([exemplar[:128, 4 * t:4 * t + 128] for t in range(16)])  # a window drifting over the photo
    video = patchwork_video(clip, (128, 128), 12, grid_spacing=32, rng=seed)
    return _side_by_side([video[0], video[5], video[11]])


def _dynamic_texture(exemplar, seed):
    from .video import dynamic_texture

    clip = data.clip("waves", 64, 96, rng=0)
    video = dynamic_texture(clip, 96, rng=seed)
    return _side_by_side([clip[0], video[0], video[47], video[95]])


def _video_texture(exemplar, seed):
    from .video import video_texture

    clip = data.clip("flame", 150, 96, rng=0)
    loop = video_texture(clip, 60, loop=True, rng=seed)
    return _side_by_side([clip[0], loop[0], loop[20], loop[40]])


def _graphcut_video(exemplar, seed):
    from .video import graphcut_video

    clip = data.clip("waves", 24, 64, rng=0)
    video = graphcut_video(clip, 48, rng=seed)
    return _side_by_side([clip[0], video[0], video[23], video[47]])


def _stylize_video(exemplar, seed):
    import numpy as np

    from .video import stylize_video

    clip = data.clip("waves", 8, 64, rng=0)
    lum = clip[0].mean(-1)
    painting = np.where(lum[..., None] > np.median(lum), [0.95, 0.75, 0.3], [0.35, 0.1, 0.1])  # two colours
    video = stylize_video(clip, {0: painting}, rng=seed)
    return _side_by_side([clip[0], painting, video[3], video[7]])


def _inpaint(exemplar, seed):
    import numpy as np

    from .optimization import inpaint

    image = exemplar[:96, :96]
    rows, cols = np.mgrid[:96, :96]
    hole = (rows - 48) ** 2 + (cols - 48) ** 2 < 20**2
    shown = image.copy()
    shown[hole] = 1.0
    return _side_by_side([shown, inpaint(image, hole, rng=seed)])


def _feature_aligned_rings(exemplar, seed):
    import numpy as np

    from .optimization import feature_aligned_texture

    size = 160  # two rings drawn as the curves: the mortar follows them
    t = np.linspace(0, 2 * np.pi, 16 * size)
    curves = np.zeros((size, size), bool)
    for r in (0.2 * size, 0.4 * size):
        curves[np.rint(79.5 + r * np.sin(t)).astype(int), np.rint(79.5 + r * np.cos(t)).astype(int)] = True
    return _side_by_side([np.repeat(curves[..., None], 3, axis=-1).astype(float),
                          feature_aligned_texture(exemplar, curves, rng=seed)])


def _make_tileable(exemplar, seed):
    import numpy as np

    from .optimization import make_tileable

    image = exemplar[:96, :96]
    reps = (2, 2) + (1,) * (image.ndim - 2)
    return _side_by_side([np.tile(image, reps), np.tile(make_tileable(image, rng=seed), reps)])


# --------------------------------------------------------------------------- the methods
_XU = ("Xu, Cohen-Or, Ju, Liu, Zhang, Zhou & Xiong, \"Feature-aligned shape texturing\", SIGGRAPH Asia 2009, "
       "doi:10.1145/1618452.1618454")
_WEI_LEVOY = "Wei & Levoy, SIGGRAPH 2000, doi:10.1145/344779.345009"
_WEI = "Wei, \"Texture synthesis from multiple sources\", SIGGRAPH 2003 sketch, doi:10.1145/965400.965507"
_EFROS_LEUNG = "Efros & Leung, ICCV 1999, doi:10.1109/ICCV.1999.790383"
_EFROS_FREEMAN = "Efros & Freeman, SIGGRAPH 2001, doi:10.1145/383259.383296"
_KWATRA_2003 = "Kwatra, Schödl, Essa, Turk & Bobick, SIGGRAPH 2003, doi:10.1145/882262.882264"
_LIANG = "Liang, Liu, Xu, Guo & Shum, ACM TOG 2001, doi:10.1145/501786.501787"
_AVIDAN_SHAMIR = "Avidan & Shamir, SIGGRAPH 2007, doi:10.1145/1275808.1276390"
_COHEN = "Cohen, Shade, Hiller & Deussen, SIGGRAPH 2003, doi:10.1145/882262.882265"
_KWATRA = "Kwatra et al., SIGGRAPH 2005, doi:10.1145/1073204.1073263"
_RUITERS = "Ruiters, Schnabel & Klein, Computer Graphics Forum 2010, doi:10.1111/j.1467-8659.2010.01739.x"
_HARRISON = "Harrison, \"Patchwork texture synthesis\", Monash University technical report, 2002"
_HB = "Heeger & Bergen, SIGGRAPH 1995, doi:10.1145/218380.218446; Briand et al., IPOL 2014"
_PS = "Portilla & Simoncelli, IJCV 2000, doi:10.1023/A:1026553619983"
_GGM = "Galerne, Gousseau & Morel, IEEE TIP 2011, doi:10.1109/TIP.2010.2052822"
_HEITZ = "Heitz & Neyret, HPG 2018, doi:10.1145/3233304; Deliot & Heitz, GPU Zen 2, 2019"
_PERLIN = "Perlin, SIGGRAPH 1985 / 2002, doi:10.1145/325165.325247"
_TURK = "Turk, SIGGRAPH 1991, doi:10.1145/122718.122749"
_PEARSON = "Pearson, Science 1993, doi:10.1126/science.261.5118.189"
_ZHANG = "Zhang, Zhou, Velho, Guo & Shum, SIGGRAPH 2003, doi:10.1145/882262.882344"
_DORETTO = "Doretto, Chiuso, Wu & Soatto, IJCV 2003, doi:10.1023/A:1021669406132"
_SCHODL = "Schödl, Szeliski, Salesin & Essa, SIGGRAPH 2000, doi:10.1145/344779.345012"
_JAMRISKA = "in the spirit of Jamriška et al., SIGGRAPH 2019, doi:10.1145/3306346.3323006"


def _m(target, summary, paper, page, demos=(), **cli):
    """A Method whose demos ``(slug, title, sample, make)`` carry its paper."""
    return Method(target, summary, paper, page, demos=tuple(Demo(s, t, paper, sample, make)
                                                            for s, t, sample, make in demos), **cli)


_PROCEDURAL = dict(inputs="none", skip=("points", "offset", "dtype"))

#: Every method, in the order ``texsynth list``, the gallery and the docs show them: the example-based
#: families first (pixel, optimization, patch, statistical), the procedural ones (no exemplar) last.
METHODS: dict[str, Method] = {
    "synthesize": Method(
        "_synthesize:synthesize", "The front door: analyses the exemplar (lattice, orientation, elements) and runs "
        "the method that suits it (--preset auto | fast | quality | a method's name)",
        "the methods it chooses: Liu, Lin & Hays, SIGGRAPH 2004, doi:10.1145/1015706.1015731; Kwatra et al., "
        "SIGGRAPH 2003, doi:10.1145/882262.882264; Kwatra et al., SIGGRAPH 2005, doi:10.1145/1073204.1073263; "
        "Liang et al., ACM TOG 2001, doi:10.1145/501786.501787 (preset fast)", page="synthesize",
        demos=(Demo("synthesize_brick", "texsynth.synthesize on the brick wall: a grid of mortar lines, so whole "
                    "cells placed on it (near-regular synthesis)",
                    "", "brick", _call("_synthesize:synthesize", (192, 192))),)),
    "synthesize-pixels": _m(
        "pixel:synthesize_pixels",
        "Wei-Levoy 2000: multi-resolution pixel synthesis (scanline or order-independent)", _WEI_LEVOY,
        "wei_levoy",
        demos=[("pixels_bread", "Wei-Levoy pixel synthesis (scanline, 3 levels, causal 5x5 neighbourhoods)",
                "bread", _call("pixel:synthesize_pixels", (160, 160), crop=64)),
               ("pixels_kcoherent_brick", "Wei-Levoy with k-coherent candidates (Ashikhmin's search, k=1): "
                "bricks copied in pieces", "brick", _call("pixel:synthesize_pixels", (192, 192),
                                                           candidates="k-coherent"))]),
    "mix-textures": _m(
        "pixel:mix_textures", "Wei 2002: mixture of two or more textures (--weights equal | ramp | w1.png,w2.png)",
        _WEI, "wei_2002", inputs="images", mixing="weights",
        demos=[("mix_brick_bread", "Wei texture mixture, ramp weights: brick (left) turning into bread (right)",
                "brick", _mixture)]),
    "synthesize-solid": _m(
        "pixel:synthesize_solid",
        "Wei 2002: solid texture from 1-3 views along z, y, x (.npy volume plus PNG slices)", _WEI,
        "wei_2002", inputs="images", output="volume",
        demos=[("solid_bread", "Wei solid texture from one 2-D view: three faces of a 32^3 cube (x, y and "
                "z slices)", "bread", _solid)]),
    "synthesize-controlled": _m(
        "pixel:synthesize_controlled",
        "Zhang et al. 2003: texton masks keep elements whole; --orientation and --magnification (a number, "
        "a .npy field or a grey image) turn and grow them; --exemplar-b B with --blend X | --blend-map "
        "M | --transition varies one into the other", _ZHANG, "texton", files=("exemplar_b",),
        maps=("blend",), ramps=("blend",), fields=("orientation", "magnification"), spatial="blend",
        demos=[("controlled_vortex_reptile", "Zhang et al. texton-mask synthesis with a vortex "
                "orientation field and a magnification growing from 0.8 (left) to 2.0 (right): the scales "
                "turn along circles and grow, whole", "reptile", _controlled)]),
    "efros-leung": _m("pixel:efros_leung",
                      "Efros-Leung 1999: non-parametric sampling, grown pixel by pixel from a seed; "
                      "--target/--mask for hole filling", _EFROS_LEUNG, "efros_leung", files=("target",),
                      maps=("mask", "exemplar_mask"), mask="mask",
                      demos=[("efros_leung_text", "Efros-Leung on text, 15x15 window (64x64 -> 96x96): words, "
                              "some copied whole from the exemplar", "text",
                              _call("pixel:efros_leung", (96, 96), crop=64, neighborhood_size=15))]),
    "optimize-texture": _m(
        "optimization:optimize_texture",
        "Kwatra 2005: texture optimization (EM + IRLS); --mask/--target for hole filling; "
        "--orientation/--magnification fields", _KWATRA,
        "kwatra", files=("target", "init"), maps=("mask", "exemplar_mask", "exemplar_guide", "output_guide"),
        mask="mask", fields=("orientation", "magnification"),
        demos=[("optimize_bread", "Kwatra texture optimization (EM + IRLS, 3 levels, sizes 32/16/8)",
                "bread", _call("optimization:optimize_texture", (128, 128))),
               ("optimize_text_complete", "Kwatra texture optimization with the completeness term of the "
                "bidirectional similarity and a copy limit (completeness_weight=1, copy_limit=0.2): all "
                "of the 96x96 exemplar, in pieces of at most a third of it", "text", _text_complete),
               ("style_transfer_water", "Style transfer as guided synthesis (Hertzmann et al. 2001, "
                "doi:10.1145/383259.383295): the photograph's luminance is the output guide, the "
                "water's (remapped) luminance the exemplar guide", "water", _style_transfer)]),
    "animate-texture": _m(
        "optimization:animate_texture",
        "Kwatra 2005: flow-guided animation, e.g. --flows sink:1.5 --n-frames 16 --size 128",
        f"{_KWATRA}, Section 4.1", "kwatra", output="frames", size=None, flow="flows",
        files=("first_frame",),
        demos=[("animate_bumpy", "Kwatra flow-guided animation, rotation 0.06 rad/frame: frames 1, 4 and 8 "
                "(elements follow the flow; they soften over the frames)", "bumpy", _animate)]),
    "inpaint": _m("optimization:inpaint", "Hole filling by texture optimization with hard constraints "
                  "(IMAGE --hole MASK, white = fill; or --hole-channel a)", _KWATRA, "completion", size=None,
                  maps=("hole", "sample_mask"), mask="hole",
                  demos=[("inpaint_bread", "Hole filling (a 40 px disc of the bread photo, filled from the rest)",
                          "bread", _inpaint)]),
    "make-tileable": _m("optimization:make_tileable", "Make a photo tile seamlessly: re-synthesise a band along "
                        "its edges on a toroidal canvas (IMAGE [--band N])", _KWATRA, "completion", size=None,
                        demos=[("make_tileable_brick", "Make tileable: the brick photo (77x96 px) tiled 2x2, before "
                                "and after (a 9 px band along its edges re-synthesised)", "brick", _make_tileable)]),
    "uncrop": _m("optimization:uncrop", "Uncrop: extend an image beyond its borders by texture optimization "
                 "(--size WxH or 1.5x)", _KWATRA, "completion", maps=("sample_mask",), mask="sample_mask",
                 skip=("position",),
                 demos=[("uncrop_bread", "Uncrop: the bread photo (64 px, centre) extended to 96 px",
                         "bread", _call("optimization:uncrop", (96, 96), crop=64))]),
    "interpolate-textures": _m(
        "optimization:interpolate_textures",
        "Ruiters 2010: texture interpolation (A B --alpha 0.5 | --transition | --alpha-map map.png; "
        "--features FA FB)", _RUITERS, "ruiters", inputs="pair", skip=("rpm_options",),
        maps=("alpha",), ramps=("alpha",), map_pairs=("features",), spatial="alpha",
        demos=[("interpolate_brick_bumpy", "Ruiters texture interpolation, alpha = 0.5: brick halfway "
                "to bumpy plaster (small: 64x64, stages (2, 17), (1, 17))", "brick", _interpolate)]),
    "feature-aligned-texture": _m("optimization:feature_aligned_texture",
                                  "After Xu et al. 2009: a texture whose direction follows drawn curves and whose "
                                  "feature lines (edges) lie on them (EXEMPLAR CURVES.png)", _XU, "feature_aligned",
                                  inputs="pair", size=None,
                                  demos=[("feature_aligned_rings_brick", "Feature-aligned texture: two drawn rings "
                                          "(left), the brick's mortar laid along them (right)", "brick",
                                          _feature_aligned_rings)]),
    "patchwork": _m("patch:patchwork", "Harrison 2002: Voronoi patchwork with invisible joins (fast, tileable)",
                    _HARRISON, "patchwork",
                    demos=[("patchwork_water", "Harrison patchwork, tileable (grid 64, f = 6)", "water",
                            _call("patch:patchwork", (256, 256), grid_spacing=64, tileable=True)),
                           ("patchwork_bread", "Harrison patchwork, tileable (grid 24, f = 6)", "bread",
                            _call("patch:patchwork", (256, 256), grid_spacing=24, tileable=True))]),
    "patchwork-video": _m("patch:patchwork_video",
                          "Harrison 2002: seamlessly looping video texture from a frame sequence", _HARRISON,
                          "patchwork", inputs="frames", output="frames",
                          demos=[("patchwork_video_water", "Harrison video patchwork: frames 1, 6 and 12 of a looping "
                                  "12-frame video from a 16-frame input clip (the water photograph drifting "
                                  "sideways: no video texture is bundled)", "water", _patchwork_video)]),
    "dynamic-texture": _m("video:dynamic_texture",
                          "Doretto et al. 2003: a linear dynamical system learnt from a clip plays new frames for ever "
                          "(--size larger than the clip's frames: through one source-coordinate map)", _DORETTO,
                          "doretto", inputs="frames", output="frames",
                          demos=[("dynamic_texture_waves", "Dynamic texture: a frame of the simulated water clip "
                                  "(texsynth.data.clip('waves'), 64 frames), then frames 1, 48 and 96 of the "
                                  "synthesis", None, _dynamic_texture)]),
    "video-texture": _m("video:video_texture",
                        "Schödl et al. 2000: the clip's frames replayed with jumps between similar frames, endless "
                        "(random play) or a seamless loop of N frames (--loop)", _SCHODL, "schodl", inputs="frames",
                        output="frames", size=None,
                        demos=[("video_texture_flame", "Video texture: a frame of the simulated candle clip "
                                "(texsynth.data.clip('flame'), 150 frames), then frames 1, 21 and 41 of a "
                                "60-frame seamless loop", None, _video_texture)]),
    "graphcut-video": _m("video:graphcut_video",
                         "Kwatra et al. 2003, Section 5: a clip extended in time (and space) by spatio-temporal "
                         "patches joined along 3-D minimum cuts (--loop: a clip that loops)", _KWATRA_2003,
                         "graphcut_video", inputs="frames", output="frames",
                         demos=[("graphcut_video_waves", "Graph-cut video: a frame of the simulated water clip "
                                 "(texsynth.data.clip('waves'), 24 frames), then frames 1, 24 and 48 of a 48-frame "
                                 "extension", None, _graphcut_video)]),
    "stylize-video": _m("video:stylize_video",
                        "After Jamriška et al. 2019 (ebsynth): every frame painted like its painted keyframes "
                        "(--keyframes 0=first.png,29=last.png), coherent along the frames' motion", _JAMRISKA,
                        "jamriska", inputs="frames", output="frames", size=None,
                        demos=[("stylize_video_waves", "Keyframe stylisation: a frame of the simulated water clip, "
                                "its two-colour painting (the keyframe), then frames 4 and 8 painted alike", None,
                                _stylize_video)]),
    "patchwork-transfer": _m("patch:patchwork_transfer",
                             "Harrison 2002: texture transfer onto a pattern image (TEXTURE PATTERN; a grey "
                             "pattern is repeated to the texture's channels)", _HARRISON, "patchwork", inputs="pair",
                             size=None),
    "quilt": _m("patch:quilt", "Efros-Freeman 2001: image quilting, blocks joined along minimum-error cuts (tileable)",
                _EFROS_FREEMAN, "quilting",
                demos=[("quilt_brick", "Image quilting (blocks of 19 px, overlap 3, tolerance 0.1)", "brick",
                        _call("patch:quilt", (256, 256))),
                       ("quilt_text", "Image quilting on text (blocks of 32 px): lines straight, most letters whole",
                        "text", _call("patch:quilt", (256, 256), crop=128, block=32)),
                       ("quilt_channels_bread", "One synthesis, two channels: the quilted albedo and a height map "
                        "(the bread's blurred, inverted luminance) rendered through its source-coordinate map "
                        "(texsynth.apply_coordinates): every crumb's height under its colour", "bread",
                        _quilt_channels)]),
    "quilt-transfer": _m("patch:quilt_transfer", "Efros-Freeman 2001: texture transfer onto a pattern image "
                         "(TEXTURE PATTERN)", f"{_EFROS_FREEMAN}, Section 3", "quilting", inputs="pair", size=None,
                         skip=("correspondence",),
                         demos=[("quilt_transfer_bread", "Quilting texture transfer: the camera in bread "
                                 "(3 passes, blocks 16/11/7)", "bread", _quilt_transfer)]),
    "graphcut-texture": _m(
        "patch:graphcut_texture", "Kwatra et al. 2003: graph-cut textures, patches matched and joined "
        "along min-cuts, seams refined (tileable)", _KWATRA_2003, "graphcut",
        demos=[("graphcut_brick", "Graph-cut textures (blocks of 48 px, entire patch matching, 2 "
                "refinement passes)", "brick", _call("patch:graphcut_texture", (192, 192), crop=96))]),
    "graphcut-merge": _m("patch:graphcut_merge", "Kwatra et al. 2003: interactive merging of two images along a "
                         "min-cut (A B --from-a MASK_A --from-b MASK_B)", _KWATRA_2003,
                         "graphcut", inputs="pair", size=None, maps=("from_a", "from_b")),
    "carve-seams": _m(
        "patch:carve_seams", "Avidan-Shamir 2007: seam carving, content-aware resizing (--size WxH) "
        "and object removal (--remove-mask MASK, --protect-mask MASK)", _AVIDAN_SHAMIR, "seam_carving",
        maps=("remove_mask", "protect_mask"), mask="remove_mask",
        demos=[("seam_carve_astronaut", "Seam carving a photograph (128 px): the input, 32 columns "
                "removed, 32 columns inserted", None, _seam_carve)]),
    "wang-texture": _m(
        "patch:wang_texture", "Cohen et al. 2003: Wang tiles quilted from diamonds, tiled at random "
        "to any --size (--tile, --colors)", _COHEN, "wang_tiles",
        demos=[("wang_tiles_bread", "Wang tiles: 8 tiles of 40 px (2 colours per direction) tiled at "
                "random", "bread", _call("patch:wang_texture", (240, 240), tile=40)),
               ("wang_tiles_tileable_bread", "Wang tiles, tileable=True: a 120 px toroidal tiling shown "
                "tiled 2x2 (no seam where the copies meet)", "bread", _wang_tileable)]),
    "patch-sampling": _m("patch:patch_sampling", "Liang et al. 2001: patch-based sampling, boundary zones feathered "
                         "(tileable)", _LIANG, "patch_sampling",
                         demos=[("patch_sampling_bread", "Patch-based sampling (patches of 25 px, zones of 4 px, "
                                 "eps 0.2)", "bread", _call("patch:patch_sampling", (256, 256)))]),
    "near-regular-texture": _m("patch:near_regular_texture", "After Liu, Lin & Hays 2004: whole cells of the "
                               "exemplar's lattice (tiles, bricks) placed on a lattice, quilted (tileable)",
                               "Liu, Lin & Hays, ACM TOG 2004 (SIGGRAPH), doi:10.1145/1015706.1015731",
                               "near_regular",
                               demos=[("near_regular_brick", "Near-regular texture: the running bond's cells "
                                       "placed on its lattice (14 x 20 px, found from the mortar lines)", "brick",
                                       _call("patch:near_regular_texture", (256, 256)))]),
    "heeger-bergen": _m("statistical:heeger_bergen",
                        "Heeger-Bergen 1995: steerable-pyramid histogram matching (stochastic textures)", _HB,
                        "heeger_bergen",
                        demos=[(f"heeger_bergen_{sample}", title, sample, _call("statistical:heeger_bergen", (192, 192)))
                               for sample, title in (("metal", "Heeger-Bergen: stochastic texture (works)"),
                                                     ("bread", "Heeger-Bergen: colour by PCA (works)"),
                                                     ("text", "Heeger-Bergen: structured texture (fails: no letters)"))]),
    "portilla-simoncelli": _m("statistical:portilla_simoncelli",
                              "Portilla-Simoncelli 2000: joint wavelet statistics by iterated projections", _PS,
                              "portilla_simoncelli",
                              demos=[(f"portilla_simoncelli_{sample}", title, sample,
                                      _call("statistical:portilla_simoncelli", (128, 128), iterations=30))
                                     for sample, title in (("reptile", "Portilla-Simoncelli: structured texture"),
                                                           ("text", "Portilla-Simoncelli: text (letter-like strokes, "
                                                                    "no words)"))]),
    "random-phase-noise": _m(
        "statistical:random_phase_noise",
        "Galerne et al. 2011: random phase noise / ADSN, micro-textures in one FFT (--process adsn)",
        _GGM, "random_phase",
        demos=[(f"random_phase_{sample}", title, sample,
                _call("statistical:random_phase_noise", (256, 256), **options))
               for sample, title, options in (
                   ("metal", "Random phase noise: micro-texture (works)", {}),
                   ("bread", "ADSN: the same colour noise for every channel (works)",
                    {"process": "adsn"}),
                   ("brick", "Random phase noise: structured texture (fails: edges are phases)", {}))]),
    "tile-and-blend": _m(
        "statistical:tile_and_blend",
        "Heitz-Neyret 2018: infinite by-example noise, tiling and histogram-preserving blending",
        _HEITZ, "tiling_blending",
        demos=[(f"tile_blend_{sample}", title, sample, _call("statistical:tile_and_blend", (384, 384)))
               for sample, title in (("bumpy", "Tiling and blending: stochastic texture (works)"),
                                     ("brick", "Tiling and blending: structured texture (fails: "
                                               "ghosted bricks)"))]),
    "perlin": _m("procedural:perlin", "Perlin gradient noise (2-D image, or 3-D volume with --size WxHxD)",
                 _PERLIN, "noise", values=(-1.0, 1.0), **_PROCEDURAL),
    "turbulence": _m("procedural:turbulence", "Perlin turbulence: sum of |noise| octaves to the band limit",
                     _PERLIN, "patterns", values=(0.0, 2.0), **_PROCEDURAL),
    "fbm": _m("procedural:fbm", "fractional Brownian motion: signed sum of noise octaves", _PERLIN, "patterns",
              values=(-1.0, 1.0), **_PROCEDURAL),
    "marble": _m("procedural:marble", "Perlin marble: sin(x + turbulence) through a colour map (2-D or 3-D)",
                 _PERLIN, "patterns", inputs="none", skip=("dtype",),
                 demos=[("marble", "Perlin marble: sin(x + turbulence) through a colour map", None,
                         _call("procedural:marble", (192, 192)))]),
    "wood": _m("procedural:wood", "wood rings: sin(radius + turbulence) through a colour map (2-D or 3-D)",
               _PERLIN, "patterns", inputs="none", skip=("dtype",),
               demos=[("wood", "Solid wood rings: sin(radius + turbulence)", None,
                       _call("procedural:wood", (192, 192)))]),
    "reaction-diffusion": _m(
        "procedural:reaction_diffusion", "Turk 1991 reaction-diffusion: spots or labyrinth stripes (two chemicals)",
        _TURK, "reaction_diffusion", inputs="none", skip=("dtype", "record_every"),
        demos=[("reaction_diffusion", "Turk reaction-diffusion spots", None,
                _call("procedural:reaction_diffusion", (192, 192), steps=6000)),
               ("reaction_diffusion_stripes", "Turk's two-chemical system far above the Turing threshold: stripes",
                None, _call("procedural:reaction_diffusion", (192, 192), preset="stripes", steps=10000))]),
    "meinhardt-stripes": _m("procedural:meinhardt_stripes",
                            "Meinhardt's five-chemical stripe system, as Turk's 1991 program used", _TURK,
                            "reaction_diffusion", inputs="none", skip=("dtype", "record_every")),
    "gray-scott": _m("procedural:gray_scott",
                     "Gray-Scott reaction-diffusion presets: spots, stripes, mazes, coral, mitosis, holes", _PEARSON,
                     "reaction_diffusion", inputs="none", skip=("dtype", "record_every", "seeds"),
                     demos=[("gray_scott_mazes", "Gray-Scott reaction-diffusion, 'mazes' preset", None,
                             _call("procedural:gray_scott", (192, 192), preset="mazes", steps=6000))]),
}

#: Methods whose ``info.coordinates`` is a source-coordinate map (``texsynth.apply_coordinates``):
#: the command line offers them ``--channels`` (extra channels rendered through the synthesis).
COORDINATE_METHODS = ("synthesize", "synthesize-pixels", "mix-textures", "efros-leung", "optimize-texture", "patchwork", "quilt",
                      "quilt-transfer", "graphcut-texture", "wang-texture", "patch-sampling", "near-regular-texture",
                      "carve-seams")

#: Methods that record a video map (one map per output frame, the input frames as sources): their command takes
#: ``--coordinates`` (``texsynth apply-coordinates`` renders a channel's frames through it), not ``--channels``.
VIDEO_COORDINATE_METHODS = ("patchwork-video",)


def _surface_demo(mode):
    """``make(exemplar, seed)``: a preview (two views) of ``mode`` ("vertex" or "lapped") on a test shape."""

    def make(exemplar, seed):
        import numpy as np

        from .surface import lapped_textures, render_mesh, sphere, synthesize_surface, torus

        if mode == "lapped":
            mesh = lapped_textures(torus(), exemplar, rng=seed)
        else:  # courses along the latitudes: the field turns about the vertical axis
            mesh = synthesize_surface(sphere(2562), exemplar[:96, :96], n_vertices=8000, rng=seed,
                                      field=lambda p: np.stack([-p[:, 1], p[:, 0], np.zeros(len(p))], axis=1))
        return render_mesh(mesh, 384, views=2)

    return make


def _shape_demo(kind):
    """``make(exemplar, seed)``: a preview (two views) of one of the mesh and geometry methods on a test shape."""

    def make(exemplar, seed):
        import numpy as np

        from . import geometry, surface

        if kind == "feature_aligned":  # a sphere with four sharp crests along its meridians
            ball = surface.sphere(2562)
            v = ball.vertices
            phi = np.arctan2(v[:, 1], v[:, 0])
            v = v * (1 + 0.25 * (1 - np.abs(np.sin(2 * phi))) * np.sqrt(np.clip(1 - v[:, 2] ** 2, 0, 1)))[:, None]
            mesh = surface.feature_aligned_surface(surface.Mesh(v * [1, 1, 0.7], ball.faces), exemplar,
                                                   n_vertices=6000, rng=seed)
        elif kind == "btf":  # a BTF sample of stones over a torus, lit from above and a little from the left
            covered = surface.synthesize_btf_surface(surface.torus(), data.btf("stones", 96, n_lights=32),
                                                     n_vertices=12000, n_textons=32, rng=seed)
            return surface.render_mesh(surface.render_btf_surface(covered, (-0.4, 0.2, 1.0)), 384, views=2,
                                       ambient=1.0)
        elif kind == "mesh_quilting":
            ball = surface.bumpy(10242, rng=0)
            elements, faces = geometry.mesh_quilting(data.swatch("rivets"), ball, unit_length=0.13, rng=seed)
            mesh = (np.concatenate([ball.vertices, elements]), np.concatenate([ball.faces, faces + len(ball.vertices)]))
        else:  # geometry synthesis: the pebbles volume, larger
            mesh = geometry.sdf_to_mesh(geometry.synthesize_geometry(data.volume("pebbles"), 64, rng=seed))
        return surface.render_mesh(mesh, 384, views=2)

    return make


_TURK = ("Turk, SIGGRAPH 2001, doi:10.1145/383259.383297; Wei & Levoy, SIGGRAPH 2001, "
         "doi:10.1145/383259.383298")
_PRAUN = "Praun, Finkelstein & Hoppe, SIGGRAPH 2000, doi:10.1145/344779.344987"
_ZHANG_SURFACE = "Zhang, Zhou, Velho, Guo & Shum, SIGGRAPH 2003, doi:10.1145/882262.882344"
_LAGAE = ("Lagae, Dumont & Dutré, \"Geometry synthesis by example\", Shape Modeling International 2005, "
          "doi:10.1109/SMI.2005.19")
_TONG_2002 = ("Tong, Zhang, Liu, Wang, Guo & Shum, \"Synthesis of bidirectional texture functions on arbitrary "
              "surfaces\", SIGGRAPH 2002, doi:10.1145/566654.566634")
_ZHOU_2006 = ("Zhou, Huang, Wang, Tong, Desbrun, Guo & Shum, \"Mesh quilting for geometric texture synthesis\", "
              "SIGGRAPH 2006, doi:10.1145/1141911.1141921")
_BHAT = ("Bhat, Ingram & Turk, \"Geometric texture synthesis by example\", Eurographics Symposium on Geometry "
         "Processing 2004, doi:10.2312/SGP/SGP04/041-044")

SURFACE_DEMOS = [
    Demo("surface_vertex_brick", "vertex synthesis on a sphere, courses along the latitudes (texsynth surface)",
         _TURK, "brick", _surface_demo("vertex")),
    Demo("surface_lapped_brick", "lapped textures on a torus (texsynth surface --mode lapped)", _PRAUN, "brick",
         _surface_demo("lapped")),
    Demo("surface_feature_aligned_brick", "feature-aligned texturing: mortar along the four crests of a sphere "
         "(texsynth surface --mode feature-aligned)", _XU, "brick", _shape_demo("feature_aligned")),
    Demo("btf_stones_torus", "BTF synthesis: a rendered BTF of stones over a torus, lit from above "
         "(texsynth btf stones --mesh)", _TONG_2002, None, _shape_demo("btf")),
    Demo("geometry_pebbles", "geometry synthesis: a 64³ volume of pebbles from the 48³ example (texsynth geometry)",
         _LAGAE, None, _shape_demo("geometry")),
    Demo("mesh_quilting_rivets", "mesh quilting: rivets over a bumpy sphere (texsynth mesh-quilting)", _ZHOU_2006,
         None, _shape_demo("mesh_quilting")),
]
"""The gallery's previews of the methods whose commands are not registry methods: on meshes (``texsynth surface``,
``texsynth btf``) and of geometry (``texsynth geometry``, ``texsynth mesh-quilting``)."""


def demos():
    """Every gallery image, in the order of :data:`METHODS`, then the surface previews."""
    return [d for method in METHODS.values() for d in method.demos] + SURFACE_DEMOS


# --------------------------------------------------------------------------- texsynth.methods()
class MethodEntry(NamedTuple):
    """One method as :func:`texsynth.methods` lists it."""

    function: str
    """The Python function, e.g. ``"texsynth.optimize_texture"``."""
    command: str
    """Its command line, e.g. ``"texsynth optimize-texture"``."""
    summary: str
    """What it does, in one line."""
    paper: str
    """The paper it implements, with its DOI."""


class MethodList(list):
    """A list of :class:`MethodEntry` that prints as a table (one line per method), and as an HTML table
    in Jupyter."""

    def __str__(self):
        if not self:
            return "(no methods)"
        widths = [max(len(row[i]) for row in self) for i in (0, 1)]
        return "\n".join(f"{e.function:<{widths[0]}}  {e.command:<{widths[1]}}  {e.summary} "
                         f"({_short_paper(e.paper)})" for e in self)

    __repr__ = __str__

    def _repr_html_(self):
        import html

        head = "".join(f"<th>{name}</th>" for name in MethodEntry._fields)
        rows = "".join("<tr>" + "".join(f"<td>{html.escape(value)}</td>" for value in entry) + "</tr>"
                       for entry in self)
        return f"<table><tr>{head}</tr>{rows}</table>"


def _short_paper(paper):
    """``"Kwatra et al., SIGGRAPH 2005"`` from ``"Kwatra et al., SIGGRAPH 2005, doi:..."`` (the first paper)."""
    return paper.split(";")[0].split(", doi:")[0]


def _short_summary(summary):
    """A registry summary without its command-line details and its "Author YEAR: " prefix (the paper says it)."""
    import re

    text = re.sub(r"\s*\([^()]*(--|IMAGE|TEXTURE|\bA B\b)[^()]*\)", "", summary)  # "(IMAGE --hole MASK)"
    text = re.split(r"; |, e\.g\. --", text)[0].replace("any --size", "any size")
    text = re.sub(r"^[A-Z][\w.&\- ]{0,40}\b(19|20)\d\d: ", "", text)  # "Kwatra 2005: " -> ""
    return text[:1].upper() + text[1:]


_SURFACE_METHODS = (
    MethodEntry("texsynth.synthesize_surface", "texsynth surface",
                "Texture synthesis on a mesh: vertex colours matched over a retiled mesh hierarchy, along a "
                "tangent field", _TURK),
    MethodEntry("texsynth.lapped_textures", "texsynth surface --mode lapped",
                "Lapped textures: patches of the exemplar pasted over a mesh along a tangent field, baked into "
                "an atlas", _PRAUN),
    MethodEntry("texsynth.feature_aligned_surface", "texsynth surface --mode feature-aligned",
                "Feature-aligned texturing of a mesh: the texture along its ridges and valleys, the exemplar's edges "
                "laid on them", _XU),
    MethodEntry("texsynth.progressive_surface", "texsynth surface --mode progressive",
                "Progressively-variant texture on a mesh: a texton mask, then the texture, varying between two "
                "exemplars along a per-vertex transition function", _ZHANG_SURFACE),
)


_BTF_METHODS = (
    MethodEntry("texsynth.pixel.synthesize_btf", "texsynth btf",
                "BTF synthesis on the plane: one k-coherent synthesis of the sample's 3-D textons, every light's "
                "image copied through its source-coordinate map", _TONG_2002),
    MethodEntry("texsynth.surface.synthesize_btf_surface", "texsynth btf --mesh",
                "BTF synthesis on a mesh: a sample position per vertex from the 3-D textons, rendered for any light "
                "and view", _TONG_2002),
)
_GEOMETRY_METHODS = (
    MethodEntry("texsynth.geometry.synthesize_geometry", "texsynth geometry",
                "Geometry synthesis: an example shape (a closed mesh or a distance volume) quilted into a larger one "
                "block by block along 3-D minimum cuts", _LAGAE),
    MethodEntry("texsynth.geometry.geometry_analogies", "texsynth geometry-analogies",
                "Geometric texture analogies: a : a' :: b : b' on volumes, the texture laid along a vector field "
                "on b", _BHAT),
    MethodEntry("texsynth.geometry.mesh_quilting", "texsynth mesh-quilting",
                "Mesh quilting: a swatch of separate geometry elements quilted over a surface inside a thin shell, "
                "patches matched by their elements in the overlap", _ZHOU_2006),
)


def methods():
    """The methods of texsynth, one line each: function, command, summary and paper.

    Examples
    --------
    >>> import texsynth
    >>> found = texsynth.methods()           # print(found): a table, one line per method
    >>> [m.function for m in found if m.command == "texsynth quilt"]
    ['texsynth.quilt']
    >>> found[0].function, found[1].paper    # the front door first, then the methods by family
    ('texsynth.synthesize', 'Wei & Levoy, SIGGRAPH 2000, doi:10.1145/344779.345009')

    The same list as ``texsynth list`` on the command line, read from
    :data:`texsynth.registry.METHODS`: example-based methods first,
    procedural ones last, then the methods on meshes and the geometry methods.

    Returns
    -------
    MethodList
        A list of :class:`MethodEntry` named tuples ``(function, command,
        summary, paper)``. It prints as a table of one line per method
        (``print(texsynth.methods())``) and shows as an HTML table in Jupyter.

    See Also
    --------
    texsynth.demo.run_demo : ``texsynth demo``, each method on a bundled sample.
    """
    top_level = set(importlib.import_module("texsynth").__all__)
    entries = MethodList()
    for name, method in METHODS.items():
        module, function = method.target.split(":")
        where = "texsynth" if function in top_level else f"texsynth.{module}"
        entries.append(MethodEntry(f"{where}.{function}", f"texsynth {name}", _short_summary(method.summary),
                                   method.paper))
    entries.extend(_SURFACE_METHODS)
    entries.extend(_BTF_METHODS)
    entries.extend(_GEOMETRY_METHODS)
    return entries
