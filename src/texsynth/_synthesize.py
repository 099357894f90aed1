"""The front door: :func:`texsynth.synthesize` looks at an exemplar, picks the method and runs it.

The analysis (:func:`analyze_exemplar`) measures what decides between the methods: a lattice or
courses (bricks, tiles, shingles, a weave), a dominant orientation (grain, roots, strata), and the
size of the elements. The choice rules (:func:`choose_method`) are written down in
docs/methods/synthesize.md, and docs/front_door.md evaluates them (benchmarks/eval_front_door.py, a
tuning half of the photographs and a reporting half).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from .core._validate import as_image, as_size, check_bool, check_choice

__all__ = ["synthesize", "analyze_exemplar", "choose_method", "ExemplarAnalysis", "SynthesisChoice", "PRESETS",
           "METHODS", "RULES"]

#: ``preset`` values besides a method's name: ``"auto"`` (the analysis decides), ``"fast"`` and ``"quality"``.
PRESETS = ("auto", "fast", "quality")
#: The methods the front door chooses from (and ``preset`` may name), by their function's name.
METHODS = ("near_regular_texture", "patch_sampling", "quilt", "graphcut_texture", "optimize_texture", "patchwork")

#: A dominant orientation (:func:`texsynth.metrics.dominant_orientation`) at least this strong makes an
#: exemplar directional: wood grain 0.81, stone strata 0.62, bricks' courses 0.52, gravel 0.30 and below
#: for stochastic photos (benchmarks/photos, 256 px crops).
DIRECTIONAL = 0.45
#: Courses: the autocorrelation of the edge map's mean along rows (or columns) at its first peak. Brick
#: courses and a weave reach 0.8, shingles 0.71; photos without courses stay below 0.45 (moss 0.42, bark
#: 0.43 on 256 px crops that hold two of their blotches).
COURSES = 0.6
#: An orientation at least this strong is grain: wood 0.81 and sand ripples 0.86 on the tuning photographs;
#: stucco 0.52 and stone courses 0.47 are not, nor the bundled bread (0.60) and reptile skin (0.64).
GRAIN = 0.7
#: Pixels: elements at least this large (:func:`texsynth.metrics.correlation_length`) stay whole in graph
#: cuts' large patches: charred bark 66, planks 68, ice cells 98 on the tuning photographs, where graph cuts
#: is the best single method (pebbles 37, stone courses 21, gravel and moss 5, on 256 px crops).
LARGE_ELEMENTS = 48


@dataclass(frozen=True)
class ExemplarAnalysis:
    """What :func:`analyze_exemplar` measured on an exemplar.

    Attributes
    ----------
    lattice : texsynth.metrics.Lattice
        Period vectors of the exemplar's autocorrelation (none for most photographs).
    courses : tuple of (int, float)
        ``((period, strength), (period, strength))``: the period in pixels of the edges' mean profile
        down the rows (horizontal courses: bricks, shingles) and across the columns, and the
        autocorrelation of that profile there (1 for perfect courses).
    orientation : float
        The dominant orientation, degrees counter-clockwise from the horizontal (90: vertical roots).
    anisotropy : float
        Its strength in [0, 1] (0: no dominant orientation).
    element_size : float
        Pixels: the diameter of the autocorrelation's central lobe
        (:func:`texsynth.metrics.correlation_length`).
    grid : tuple or None
        The axis-aligned grid of full-length lines ``(period_rows, period_cols, origin_row, origin_col)``
        that :func:`texsynth.near_regular_texture` places whole cells on
        (:func:`texsynth.patch.find_lattice`), or None.
    shape : (int, int)
        The exemplar's ``(height, width)``.
    seconds : float
        Time the analysis took.
    """

    lattice: object
    courses: tuple
    orientation: float
    anisotropy: float
    element_size: float
    grid: tuple | None
    shape: tuple
    seconds: float = 0.0

    @property
    def regular(self):
        """Whether the exemplar has a lattice or courses that a synthesis must keep aligned."""
        return (self.grid is not None or len(self.lattice.vectors) > 0
                or max(strength for _, strength in self.courses) >= COURSES)

    @property
    def period(self):
        """Pixels: the longest period of the lattice or of the courses (0 when there is none)."""
        lengths = [float(np.hypot(*v)) for v in self.lattice.vectors.tolist()]
        lengths += [float(period) for period, strength in self.courses if strength >= COURSES]
        return max(lengths, default=0.0)

    @property
    def directional(self):
        """Whether the exemplar has a dominant orientation a synthesis must keep."""
        return self.anisotropy >= DIRECTIONAL

    @property
    def kind(self):
        """``"regular"``, ``"directional"`` or ``"stochastic"`` (in that order of precedence)."""
        return "regular" if self.regular else "directional" if self.directional else "stochastic"

    def describe(self):
        """One sentence on what was measured, for :attr:`SynthesisChoice.choice`."""
        if self.regular:
            (rows, rs), (cols, cs) = self.courses
            if self.grid is not None:
                what = f"a grid of lines every {self.grid[0]:.0f} x {self.grid[1]:.0f} px"
            elif len(self.lattice.vectors):
                what = "a lattice (period vectors " + ", ".join(f"{tuple(v)}" for v in self.lattice.vectors.tolist())
                what += " px)"
            else:
                what = f"courses every {rows if rs >= cs else cols} px " + ("down the rows" if rs >= cs else
                                                                            "across the columns")
            return f"the exemplar is regular: {what}"
        if self.directional:
            return (f"the exemplar is directional: its structure runs at {self.orientation:.0f} degrees "
                    f"(strength {self.anisotropy:.2f})")
        return f"the exemplar is stochastic: no lattice, no dominant orientation, elements of about " \
               f"{self.element_size:.0f} px"


@dataclass(frozen=True)
class SynthesisChoice:
    """What :func:`synthesize` chose and why (its ``info`` with ``return_info=True``).

    Attributes
    ----------
    method : str
        The function called, e.g. ``"patch_sampling"`` (``texsynth.patch_sampling``).
    options : dict
        The options it was called with besides the exemplar, size and seed.
    choice : str
        One sentence: what the analysis found and why that method.
    analysis : ExemplarAnalysis or None
        The analysis (None when ``preset`` named the method).
    method_info : object
        The chosen method's own info.
    seconds : float
        Wall time of the whole call, the analysis included.
    coordinates, weights, source_index
        The chosen method's source-coordinate map, so that this info renders the other channels of a
        material (:func:`texsynth.apply_coordinates`) as the method's own does.
    """

    method: str
    options: dict
    choice: str
    analysis: ExemplarAnalysis | None
    method_info: object = field(repr=False, default=None)
    seconds: float = 0.0

    @property
    def coordinates(self):
        """The chosen method's source-coordinate map (:func:`texsynth.apply_coordinates` takes this info too)."""
        return self.method_info.coordinates

    @property
    def weights(self):
        """The chosen method's blending weights of the map, or None."""
        return getattr(self.method_info, "weights", None)

    @property
    def source_index(self):
        """The chosen method's sources of the map, or None (one exemplar)."""
        return getattr(self.method_info, "source_index", None)


def _courses(grey):
    """``((period, strength), (period, strength))`` of the edge map's mean profile down the rows and across
    the columns: the first maximum of its autocorrelation after the first negative lag."""
    edges = ndimage.gaussian_gradient_magnitude(grey, 1.5)
    found = []
    for axis in (1, 0):
        profile = edges.mean(axis=axis)
        profile = profile - profile.mean()
        n, power = len(profile), float(np.mean(profile * profile))
        lags = np.arange(n // 2 + 1)
        corr = np.correlate(profile, profile, "full")[n - 1:n - 1 + len(lags)] / ((n - lags) * power) \
            if power > 0 else np.zeros(len(lags))
        negative = np.flatnonzero(corr < 0)
        if not len(negative):
            found.append((0, 0.0))
            continue
        peak = negative[0] + int(np.argmax(corr[negative[0]:]))
        found.append((int(peak), float(corr[peak])))
    return tuple(found)


def analyze_exemplar(exemplar):
    """Measure what decides the method for an exemplar: lattice or courses, orientation, element size.

    Examples
    --------
    >>> import texsynth
    >>> texsynth.analyze_exemplar(texsynth.data.load("brick")).kind
    'regular'
    >>> texsynth.analyze_exemplar(texsynth.data.load("bumpy")).kind
    'stochastic'

    Parameters
    ----------
    exemplar : array_like, str or os.PathLike
        ``(H, W)`` or ``(H, W, C)`` image in [0, 1] (or its file), sides of at least 16 pixels.

    Returns
    -------
    ExemplarAnalysis
        Its ``kind`` (``"regular"``, ``"directional"`` or ``"stochastic"``) and the measurements behind it.

    Notes
    -----
    All on the luminance: the lattice of the autocorrelation
    (:func:`texsynth.metrics.lattice`), courses from the autocorrelation of the edge map's mean along
    rows and columns (a brick wall's mortar lines are periodic down the rows even where its 2-D
    lattice is too weak to detect, as on a 256 px crop holding two tiles), the dominant orientation
    over the Gaussian pyramid (:func:`texsynth.metrics.dominant_orientation`) and the element size
    (:func:`texsynth.metrics.correlation_length`). About 0.03 s for 256 px, 0.1 s for 512 px.
    """
    from .metrics import correlation_length, dominant_orientation, lattice
    from .patch import find_lattice

    start = time.perf_counter()
    image = as_image(exemplar, "exemplar", min_size=16)
    grey = image if image.ndim == 2 else image[..., :3 if image.shape[-1] >= 3 else 1].mean(axis=-1)
    angle, strength = dominant_orientation(grey)
    try:
        grid = find_lattice(grey[..., None])[0]
    except ValueError:  # no grid of lines
        grid = None
    return ExemplarAnalysis(lattice=lattice(grey), courses=_courses(grey), orientation=angle, anisotropy=strength,
                            element_size=correlation_length(grey), grid=grid, shape=grey.shape,
                            seconds=time.perf_counter() - start)


#: The rules of ``preset="auto"``, first match wins: ``(name, test, method, reason)``. Chosen on the tuning
#: half of benchmarks/photos (docs/front_door.md): texture optimization is the best single method there on
#: most photographs; graph cuts is on those with large elements (charred bark, ice cells, wide planks) and
#: strong grain (wood, sand ripples), which texture optimization breaks into blotches.
RULES = (
    ("grid", lambda a: a.grid is not None, "near_regular_texture",
     "near-regular synthesis places whole cells on the grid, so the grid stays unbroken and its cells whole"),
    ("grain", lambda a: a.anisotropy >= GRAIN, "graphcut_texture",
     "graph-cut textures copies large patches along minimum cuts, so grain and strata run on unbroken"),
    ("large elements", lambda a: a.element_size >= LARGE_ELEMENTS, "graphcut_texture",
     "graph-cut textures copies large patches along minimum cuts, so elements this large stay whole"),
    ("otherwise", lambda a: True, "optimize_texture",
     "texture optimization scores best on such textures, the most coherent and complete (docs/front_door.md)"),
)
_PRESET_METHODS = {"fast": ("patch_sampling", "preset='fast': patch-based sampling, seamless in a fraction of a "
                            "second"),
                   "quality": ("graphcut_texture", "preset='quality': graph-cut textures, the most coherent "
                               "patches of the library's methods, and the slowest")}


def choose_method(analysis, preset="auto"):
    """The method, its options and the reason for an exemplar's :class:`ExemplarAnalysis`.

    Examples
    --------
    >>> import texsynth
    >>> method, options, reason = texsynth.choose_method(texsynth.analyze_exemplar(texsynth.data.load("brick")))
    >>> method
    'near_regular_texture'

    Parameters
    ----------
    analysis : ExemplarAnalysis
        From :func:`analyze_exemplar`.
    preset : str
        ``"auto"`` (the rules of docs/methods/synthesize.md), ``"fast"``, ``"quality"`` or one of :data:`METHODS`.

    Returns
    -------
    method : str
        A name of :data:`METHODS`.
    options : dict
        Options for it (besides exemplar, size and seed).
    reason : str
        One sentence a user understands.
    """
    if not isinstance(preset, str):
        raise TypeError(f"preset must be a str: one of {', '.join(map(repr, PRESETS + METHODS))}, got "
                        f"{type(preset).__name__} {preset!r}")
    preset = check_choice(preset.replace("-", "_"), "preset", PRESETS + METHODS)
    if preset in METHODS:
        return preset, {}, f"preset={preset!r}: texsynth.{preset}"
    if preset in _PRESET_METHODS:
        method, reason = _PRESET_METHODS[preset]
        return method, {}, reason
    method, why = next((method, why) for _, test, method, why in RULES if test(analysis))  # the first that holds
    options = {"lattice": analysis.grid} if method == "near_regular_texture" else {}
    return method, options, f"{analysis.describe()}; {why}"


def synthesize(exemplar, size, *, preset="auto", tileable=False, rng=None, progress=False, return_info=False):
    """Synthesise a texture like ``exemplar`` at ``size``, with the method that suits it.

    Examples
    --------
    >>> import texsynth
    >>> out, info = texsynth.synthesize(texsynth.data.load("brick"), 128, rng=0, return_info=True)
    >>> out.shape, info.method
    ((128, 128, 3), 'near_regular_texture')
    >>> print(info.choice)  # doctest: +ELLIPSIS
    the exemplar is regular: a grid of lines every 14 x 21 px; near-regular synthesis places whole cells ...

    Parameters
    ----------
    exemplar : array_like, str or os.PathLike
        ``(H, W)`` or ``(H, W, C)`` image in [0, 1], or its file.
    size : int or (int, int)
        Output ``(height, width)``.
    preset : str
        ``"auto"`` (default): the method the analysis of the exemplar picks (:func:`analyze_exemplar`,
        :func:`choose_method`); ``"fast"``; ``"quality"``; or a method's name (:data:`METHODS`, e.g.
        ``"quilt"``), called with its own defaults.
    tileable : bool
        Make the output tile seamlessly (every method of :data:`METHODS` can).
    rng : None, int or numpy.random.Generator
        Seed or generator, passed to the method.
    progress : bool or callable
        Passed to the method.
    return_info : bool
        Also return a :class:`SynthesisChoice`: the method, its options, the one-sentence ``choice``,
        the analysis and the method's own info.

    Returns
    -------
    numpy.ndarray or (numpy.ndarray, SynthesisChoice)
        The texture, as the chosen method returns it.

    Raises
    ------
    TypeError, ValueError
        For a bad ``exemplar``, ``size`` or ``preset``, before any work; the chosen method's own errors
        (an output too large for memory is refused before anything is allocated).
    """
    import texsynth

    start = time.perf_counter()
    image = as_image(exemplar, "exemplar", min_size=16)
    size = as_size(size)
    tileable = check_bool(tileable, "tileable")
    return_info = check_bool(return_info, "return_info")
    named = isinstance(preset, str) and preset.replace("-", "_") in METHODS
    analysis = None if named else analyze_exemplar(image)
    method, options, reason = choose_method(analysis, preset)
    result = getattr(texsynth, method)(image, size, tileable=tileable, rng=rng, progress=progress,
                                       return_info=return_info, **options)  # the method's info costs time
    if not return_info:
        return result
    out, method_info = result
    return out, SynthesisChoice(method, options, reason, analysis, method_info, time.perf_counter() - start)
