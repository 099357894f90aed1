"""Reaction-diffusion textures: Turk's two-chemical system, Meinhardt's stripes, Gray-Scott.

Turk 1991 (the slide "Reaction Diffusion Based Method") grows spots with
Turing's two-chemical system, discretised on a grid of cells ``(i, j)``:

    (1)  Delta a_ij = s (16 - a_ij b_ij)          + D_a (a_i+1,j + a_i-1,j + a_i,j+1 + a_i,j-1 - 4 a_ij)
    (2)  Delta b_ij = s (a_ij b_ij - b_ij - beta_ij) + D_b (b_i+1,j + b_i-1,j + b_i,j+1 + b_i,j-1 - 4 b_ij)

with ``beta_ij`` random around 12, starting from the uniform steady state
``a = b = 4``; ``b`` is clamped at 0. Linearised at ``a = b = 4`` (b is the
self-enhancing chemical, a the fast-diffusing substrate), the uniform state is
Turing-unstable only if ``D_a / D_b > 4``; Turk's spot rates (1/8, 1/32) sit
exactly at that threshold. Far above it (``D_a / D_b >= 10``) the same
equations make labyrinthine stripes (``preset="stripes"``).

Turk's own stripes (his 1991 program ``spots.c``, option ``-x``) come from a
different system, Meinhardt's five-chemical "two-species balance" [4]_:
two mutually exclusive activators a and b, a common inhibitor c, and two
diffusing messengers d and e that let each activator support the other one
at a distance:

    (5)  Delta a = 0.01 r_ij a^2 e / c - p1 a + D1 lap(a)
    (6)  Delta b = 0.01 b^2 d / c      - p1 b + D1 lap(b)
    (7)  Delta c = 0.01 r_ij a^2 e + 0.01 b^2 d - p2 c
    (8)  Delta d = p3 (a - d) + D2 lap(d)
    (9)  Delta e = p3 (b - e) + D2 lap(e)

with ``r_ij`` random around 1 (:func:`meinhardt_stripes`). The Gray-Scott
model (Pearson 1993), the common modern alternative, is

    (3)  du/dt = D_u lap(u) - u v^2 + F (1 - u)
    (4)  dv/dt = D_v lap(v) + u v^2 - (F + k) v

(Pearson's feed rate ``F`` and kill rate ``k`` are the options ``feed`` and
``kill`` of :class:`GrayScottRates`; in texsynth ``k`` always counts
neighbours.)

Both are integrated with the explicit (forward Euler) scheme on a periodic
grid (the texture tiles) with the 5-point Laplacian. For pure diffusion that
scheme is stable only if ``4 D dt / h^2 <= 1`` (h = 1 pixel; von Neumann
analysis of the FTCS scheme in two dimensions: the Fourier mode
(pi, pi) is multiplied by ``1 - 8 D dt / h^2``, which must not fall below -1);
larger time steps raise a ValueError.

References
----------
.. [1] G. Turk, "Generating textures on arbitrary surfaces using
   reaction-diffusion", SIGGRAPH 1991, Computer Graphics 25(4), 289-298.
   https://doi.org/10.1145/122718.122749
.. [2] J. E. Pearson, "Complex patterns in a simple system", Science 261
   (1993), 189-192. https://doi.org/10.1126/science.261.5118.189
.. [3] W. H. Press, S. A. Teukolsky, W. T. Vetterling, B. P. Flannery,
   Numerical Recipes, 3rd ed. (2007), section 20.2, "Diffusive initial value
   problems" (stability of the forward-time centred-space scheme).
.. [4] H. Meinhardt, Models of Biological Pattern Formation, Academic Press,
   1982 (stripes by a two-species balance), as implemented by G. Turk in
   ``spots.c`` (1991), the program accompanying [1]_.
.. [5] M. G. Malheiros, H. Fensterseifer, M. Walter, "Pattern formation
   through minimalist biologically inspired cellular simulation", Graphics
   Interface 2017; experiment file ``basic-spots/spots-03-v-spots.pex`` of
   https://github.com/mgmalheiros/pattern-explorer (Turk's two-chemical
   equations with D_a = 0.15, D_b = 0.01, s = 0.01 give a "labyrinth").
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import as_rng, as_size, check_group, check_positive_int, is_auto
from ._noise import check_dtype, check_fits, check_float
from ._patterns import apply_colormap, colormap_function

__all__ = [
    "reaction_diffusion",
    "gray_scott",
    "meinhardt_stripes",
    "TurkRates",
    "GrayScottRates",
    "TURK_PRESETS",
    "GRAY_SCOTT_PRESETS",
    "ReactionDiffusionInfo",
    "stability_limit",
]

def _check_auto_rate(value, name):
    """A rate of a group: ``"auto"`` (the preset's) or a finite number >= 0."""
    return value if is_auto(value) else check_float(value, name, allow_zero=True)


class _Rates:
    """The behaviour shared by :class:`TurkRates` and :class:`GrayScottRates`."""

    def __post_init__(self):
        for f in dataclasses.fields(self):
            _check_auto_rate(getattr(self, f.name), f.name)

    def resolved(self, preset):
        """These rates with every ``"auto"`` field taken from ``preset`` (an instance of the same class)."""
        return dataclasses.replace(preset, **{f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                                              if not is_auto(getattr(self, f.name))})


@dataclass(frozen=True)
class TurkRates(_Rates):
    """The rates of Turk's two-chemical system (eqs. 1-2 of :func:`reaction_diffusion`).

    Examples
    --------
    >>> from texsynth.procedural import TURK_PRESETS, TurkRates
    >>> TurkRates(s=1 / 40).resolved(TURK_PRESETS["spots"]) == TURK_PRESETS["small-spots"]
    True

    One group of options, passed as ``rates=TurkRates(...)``; every field
    left ``"auto"`` (the default) takes its value from the ``preset``
    (:data:`TURK_PRESETS`, whose values are instances of this class). On the
    command line its fields are the flags ``--s``, ``--Da``, ``--Db``,
    ``--beta`` and ``--beta-spread``. The symbols are Turk's (1991).

    Parameters
    ----------
    s : float or "auto"
        Reaction rate; it sets the pattern scale (larger s, smaller spots or
        narrower stripes). Turk's spots: 1/80.
    Da, Db : float or "auto"
        Diffusion rates ``D_a``, ``D_b`` of a and b (per step, grid spacing
        1). The ratio decides the pattern: 4 (Turk's spots, 1/8 and 1/32) is
        the linear Turing threshold, spots appear near it, labyrinthine
        stripes from about 10 on.
    beta : float or "auto"
        Mean of the random substrate ``beta_ij`` (12 in Turk's system).
    beta_spread : float or "auto"
        ``beta_ij`` is uniform in ``beta +- beta_spread`` (Turk: 0.1).

    Raises
    ------
    ValueError, TypeError
        For a rate that is negative, not finite or not a number.
    """

    s: object = "auto"
    Da: object = "auto"
    Db: object = "auto"
    beta: object = "auto"
    beta_spread: object = "auto"


@dataclass(frozen=True)
class GrayScottRates(_Rates):
    """The rates of the Gray-Scott model (eqs. 3-4 of :func:`gray_scott`, Pearson 1993).

    Examples
    --------
    >>> from texsynth.procedural import GRAY_SCOTT_PRESETS, GrayScottRates
    >>> GrayScottRates(kill=0.06).resolved(GRAY_SCOTT_PRESETS["spots"])
    GrayScottRates(feed=0.035, kill=0.06, Du=0.16, Dv=0.08)

    One group of options, passed as ``rates=GrayScottRates(...)``; every
    field left ``"auto"`` (the default) takes its value from the ``preset``
    (:data:`GRAY_SCOTT_PRESETS`, whose values are instances of this class).
    On the command line its fields are the flags ``--feed``, ``--kill``,
    ``--Du`` and ``--Dv``.

    Parameters
    ----------
    feed : float or "auto"
        Feed rate ``F`` of u (Pearson's ``F``).
    kill : float or "auto"
        Kill rate of v (Pearson's ``k``: v decays at ``F + k``).
    Du, Dv : float or "auto"
        Diffusion rates ``D_u``, ``D_v`` (grid spacing 1); every preset has
        Pearson's 0.16 and 0.08 (his ``2 x 10^-5`` and ``10^-5`` on a
        2.5 x 2.5 domain of 256 cells).

    Raises
    ------
    ValueError, TypeError
        For a rate that is negative, not finite or not a number.
    """

    feed: object = "auto"
    kill: object = "auto"
    Du: object = "auto"
    Dv: object = "auto"


TURK_PRESETS = {
    # Turk's spot parameters (his code as ported: D_a = 1/8, D_b = 1/32,
    # s = 1/80 sets the spot size; beta = 12 +- 0.1; b clamped at 0).
    "spots": TurkRates(s=1 / 80, Da=1 / 8, Db=1 / 32, beta=12.0, beta_spread=0.1),
    # Smaller, denser spots: a larger reaction rate s (s scales the pattern).
    "small-spots": TurkRates(s=1 / 40, Da=1 / 8, Db=1 / 32, beta=12.0, beta_spread=0.1),
    # Larger spots: faster diffusion, same ratio D_a / D_b = 4 as Turk's 1-D
    # code (D_a = 0.25, D_b = 0.0625, scaled by 0.8 to stay inside the 2-D
    # stability bound 4 D dt <= 1).
    "large-spots": TurkRates(s=1 / 80, Da=0.2, Db=0.05, beta=12.0, beta_spread=0.1),
    # A wide substrate spread (beta = 12 +- 2): spots of varied size, some
    # fused into short worms (measured on this implementation, 96^2, 8000 steps).
    "irregular": TurkRates(s=1 / 80, Da=1 / 8, Db=1 / 32, beta=12.0, beta_spread=2.0),
    # Labyrinthine stripes: the same equations far above the Turing threshold
    # D_a / D_b = 4. D_a = 0.15, D_b = 0.01 (ratio 15) are Malheiros et al.'s
    # labyrinth rates (GI 2017); s = 1/200 instead of their 1/100 widens the
    # stripes to a period of about 9 px, close to the spacing of "spots".
    # Our sweep (128^2, Turk's start a = b = 4, beta = 12 +- 0.1): ratio 4
    # spots, 6-8 spots and worms, >= 10 labyrinths; without the clamp b >= 0
    # every run diverged.
    "stripes": TurkRates(s=1 / 200, Da=0.15, Db=0.01, beta=12.0, beta_spread=0.1),
}
"""Named rates of :func:`reaction_diffusion` (Turk's system), as :class:`TurkRates`.

``"stripes"`` gives labyrinthine stripes of the two-chemical system; Turk's
own stripes came from Meinhardt's five-chemical system,
:func:`meinhardt_stripes`.
"""

GRAY_SCOTT_PRESETS = {
    # (F, k) of Pearson's classification with D_u = 0.16, D_v = 0.08, dt = 1.
    "spots": GrayScottRates(feed=0.035, kill=0.065, Du=0.16, Dv=0.08),
    "mitosis": GrayScottRates(feed=0.0367, kill=0.0649, Du=0.16, Dv=0.08),
    "stripes": GrayScottRates(feed=0.022, kill=0.051, Du=0.16, Dv=0.08),
    "mazes": GrayScottRates(feed=0.029, kill=0.057, Du=0.16, Dv=0.08),
    "coral": GrayScottRates(feed=0.0545, kill=0.062, Du=0.16, Dv=0.08),
    "holes": GrayScottRates(feed=0.039, kill=0.058, Du=0.16, Dv=0.08),
}
"""Named rates of :func:`gray_scott`, as :class:`GrayScottRates`: Pearson's (F, k) with D_u = 0.16, D_v = 0.08."""

RD_COLORS = [(0.00, (0.96, 0.90, 0.76)), (0.45, (0.83, 0.62, 0.33)), (1.00, (0.22, 0.12, 0.05))]
"""Default colours: cream background, dark-brown pattern (high b or v)."""


@dataclass
class ReactionDiffusionInfo:
    """Extra results of :func:`reaction_diffusion` and :func:`gray_scott`.

    Attributes
    ----------
    concentrations : dict of str to numpy.ndarray
        Final concentrations by chemical name (``"a"``, ``"b"`` for Turk;
        ``"u"``, ``"v"`` for Gray-Scott), each ``(H, W)``.
    steps : int
        Number of time steps taken.
    parameters : dict
        The parameters used (after presets and defaults).
    frames : numpy.ndarray or None
        ``(T, H, W)`` snapshots of the pattern chemical (b or v) every
        ``record_every`` steps, if requested.
    beta : numpy.ndarray or None
        Turk's per-cell ``beta_ij`` (None for Gray-Scott).
    """

    concentrations: dict
    steps: int
    parameters: dict = field(default_factory=dict)
    frames: np.ndarray | None = None
    beta: np.ndarray | None = None


def stability_limit(diffusion, h=1.0):
    """Largest stable time step ``h^2 / (4 D)`` of forward Euler with the 5-point Laplacian.

    Parameters
    ----------
    diffusion : float
        Diffusion rate ``D`` (finite, >= 0).
    h : float, default 1.0
        Grid spacing (finite, > 0).

    Returns
    -------
    float
        ``h^2 / (4 D)``; ``inf`` for ``D = 0`` (no diffusion, no bound) or
        when the bound is beyond the float range.

    Raises
    ------
    ValueError
        For a negative, NaN or infinite diffusion, or a non-positive or
        non-finite ``h``.
    TypeError
        For a diffusion or ``h`` that is not a real number (e.g. a bool).

    Examples
    --------
    >>> stability_limit(0.25)
    1.0
    >>> stability_limit(0)
    inf
    """
    diffusion = check_float(diffusion, "diffusion", allow_zero=True)
    h = check_float(h, "h")
    if diffusion == 0:
        return math.inf
    try:
        return h * h / (4.0 * diffusion)
    except (OverflowError, ZeroDivisionError):  # pragma: no cover - float division gives inf here
        return math.inf


def _check_stable(dt, rates):
    for name, d in rates.items():
        if 4.0 * d * dt > 1.0:
            raise ValueError(
                f"{name}={d:g} with dt={dt:g} is unstable: the explicit scheme with the 5-point Laplacian needs "
                f"4 * {name} * dt / h^2 <= 1 (h = 1 pixel), here {4 * d * dt:.3g}; use dt <= "
                f"{stability_limit(d):.4g} or a smaller {name}"
            )


def _check_grid(size):
    """``(H, W)``, an int meaning a square."""
    if isinstance(size, (str, bytes)) or not isinstance(size, (numbers.Integral, tuple, list, np.ndarray)):
        raise TypeError(f"size must be an int or a tuple (height, width), got {size!r}")
    return as_size(size, "size", 2)


def _check_rate(value, name):
    return check_float(value, name, allow_zero=True)


def _check_choice(value, choices, name):
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"{name} must be one of {sorted(choices)}, got {value!r}")
    return value


def _rates_text(rates):
    return ", ".join(f"{k}={v:g}" for k, v in rates.items())


class _PeriodicGrid:
    """Diffusing chemicals on a periodic grid, with a fast 5-point Laplacian.

    ``inner`` is a C-contiguous (K, H, W) array (the K chemicals). The
    Laplacian is built from whole-array shifted slices: rows above/below as
    slices along axis 1, left/right neighbours as the flat array shifted by
    one element, after which only the first and last columns (where the flat
    shift crossed a row end) are recomputed with the periodic neighbour.
    Contiguous operations were measured 3-5x faster than the same operations
    on the interior view of a padded buffer.
    """

    def __init__(self, fields, dtype):
        k = len(fields)
        h, w = fields[0].shape
        self.inner = np.empty((k, h, w), dtype=dtype)
        for i, f in enumerate(fields):
            self.inner[i] = f
        self.lap = np.empty((k, h, w), dtype=dtype)
        self.center = np.empty((k, h, w), dtype=dtype)
        self.tmp = np.empty((h, w), dtype=dtype)

    def linear_part(self, diffusion, decay):
        """``self.lap = D * lap(c) - decay * c`` for every chemical (D, decay: (K, 1, 1)).

        ``D lap(c) = D (c_N + c_S + c_E + c_W) - 4 D c``; the ``-4 D c`` and a
        reaction's linear loss ``-decay' c`` are applied in one pass, with
        ``decay = 4 D + decay'``.
        """
        x, lap = self.inner, self.lap
        h = x.shape[1]
        if h > 1:
            np.add(x[:, :-2], x[:, 2:], out=lap[:, 1:-1])  # north + south, interior rows
            np.add(x[:, -1], x[:, 1 % h], out=lap[:, 0])  # periodic first row
            np.add(x[:, -2], x[:, 0], out=lap[:, -1])  # periodic last row
        else:
            np.multiply(x, 2, out=lap)
        w = x.shape[2]
        vertical = lap[:, :, [0, w - 1]]  # copies of the edge columns' north + south
        flat, lflat = x.reshape(-1), lap.reshape(-1)
        lflat[:-1] += flat[1:]  # east (wrong in the last column)
        lflat[1:] += flat[:-1]  # west (wrong in the first column)
        for i, col in enumerate((0, w - 1)):
            # recompute the edge columns with their periodic east/west neighbours
            lap[:, :, col] = vertical[:, :, i] + x[:, :, (col + 1) % w] + x[:, :, (col - 1) % w]
        lap *= diffusion
        lap -= np.multiply(x, decay, out=self.center)
        return lap


def _run(grid, step, steps, progress, desc, record_every, pattern_index, rates):
    frames = []
    chunk = max(1, steps // 100)
    with Progress(progress, steps, desc) as bar, np.errstate(over="ignore", invalid="ignore"):
        done = 0
        while done < steps:
            n = min(chunk, steps - done)
            for i in range(n):
                step()
                if record_every and (done + i + 1) % record_every == 0:
                    frames.append(grid.inner[pattern_index].copy())
            done += n
            rows = grid.inner[:, 0, :] if done < steps else grid.inner  # all of it at the end
            if not np.isfinite(rows).all():
                raise ValueError(
                    f"{desc} diverged after {done} steps (non-finite concentrations) with {_rates_text(rates)}: "
                    "the reaction terms are unstable at this time step; reduce dt or the reaction rates")
            bar.advance(n=n)
    return np.stack(frames) if frames else None


def _colour(field, colormap):
    lo, hi = float(field.min()), float(field.max())
    t = (field - lo) / (hi - lo) if hi > lo else np.zeros_like(field)
    return apply_colormap(t, colormap, default=RD_COLORS)


def _check_memory(size, dtype, copies, steps, record_every):
    """Refuse a grid, or recorded frames, that cannot fit in memory (before allocating)."""
    check_fits(size, max(dtype.itemsize, 8), copies)  # the chemicals, buffers and float64 set-up
    if record_every:
        check_fits((steps // record_every,) + tuple(size), dtype.itemsize, 1, "record_every", record_every)


def _check_record(record_every):
    if record_every is None:
        return None
    return check_positive_int(record_every, "record_every")


def reaction_diffusion(size, *, steps=10000, preset="spots", rates=TurkRates(), dt=1.0, cascade=None, colormap=None,
                       record_every=None, rng=None, dtype=np.float32, progress=False, return_info=False):
    """Turk's reaction-diffusion texture: spots or stripes from Turing's two-chemical system.

    Examples
    --------
    >>> import texsynth
    >>> img, info = texsynth.procedural.reaction_diffusion((24, 24), steps=200, rng=0, return_info=True)
    >>> img.shape, sorted(info.concentrations)
    ((24, 24, 3), ['a', 'b'])

    Two chemicals react and diffuse on a grid, ``a`` faster than ``b``, so
    small random differences grow into spots (or stripes) of one
    characteristic size, which are coloured (Turk 1991 [1]_).

    Parameters
    ----------
    size : int or (int, int)
        Grid size ``(H, W)`` (an int means a square); the result tiles
        (periodic boundary).
    steps : int, default 10000
        Time steps. With the "spots" preset the spots have formed after about
        4,000-6,000 steps and then only shift slightly; "stripes" has joined
        into a labyrinth after about 3,000-6,000 steps and then slowly
        straightens (measured at 128^2, ``examples/plot_reaction_diffusion.py``).
    preset : {"spots", "small-spots", "large-spots", "irregular", "stripes"}, default "spots"
        Preset of :data:`TURK_PRESETS` supplying the rates left ``"auto"``.
        "stripes" (``D_a / D_b = 15``) gives labyrinthine stripes; Turk's own
        stripes used Meinhardt's system, :func:`meinhardt_stripes`.
    rates : TurkRates
        The reaction rate ``s``, the diffusion rates ``Da``, ``Db`` and the
        substrate ``beta +- beta_spread``; a field left ``"auto"`` (the
        default: all of them) is the preset's. See :class:`TurkRates`.
    dt : float, default 1.0
        Time step; Turk's equations (1)-(2) are the increments for dt = 1.
        Must satisfy ``4 max(Da, Db) dt <= 1``.
    cascade : sequence of (float, int), optional
        Turk's cascade: after the first ``steps`` with ``s``, run each
        ``(s_k, steps_k)`` in turn, starting from the previous pattern and
        freezing the cells of its spots (``b`` above the midpoint of its
        range), so that smaller spots fill the space between larger ones.
    colormap : None or colour map
        Transfer function from normalised ``b`` to RGB (see
        :func:`~texsynth.procedural.apply_colormap`); default dark-brown spots
        on cream.
    record_every : int, optional
        Keep a snapshot of ``b`` every this many steps (``info.frames``).
    rng : None, int or numpy.random.Generator
        Seeds ``beta_ij``.
    dtype : numpy.float32 or numpy.float64, default float32
        float32 runs about 3x faster; the final pattern then depends on
        rounding (the instability amplifies it) but its statistics do not.
    progress : bool or callable, default False
        Progress bar or callback ``(step, total, info)``.
    return_info : bool, default False
        Also return a :class:`ReactionDiffusionInfo` with ``a``, ``b``, beta
        and the frames.

    Returns
    -------
    image : numpy.ndarray
        ``(H, W, 3)`` RGB in [0, 1]: ``b`` normalised to [0, 1] and coloured.
    info : ReactionDiffusionInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        Non-positive size or steps, an unknown preset, negative or
        non-finite rates, a malformed cascade, a time step above the
        stability bound ``dt <= 1 / (4 max(Da, Db))``, a run that diverges,
        or a size (or recorded frames) larger than this machine's memory.
    TypeError
        For arguments of the wrong type (a bool or string as a number, a
        float ``steps``, a dtype other than float32/float64).

    Notes
    -----
    Equations (1)-(2) of the module docstring, the slide "Reaction Diffusion
    Based Method" of Turk [1]_, with periodic boundaries and ``b >= 0``.
    The uniform state ``a = b = 4`` is the steady state for ``beta = 12``;
    the random ``beta_ij`` break the symmetry, and because ``a`` diffuses
    faster than ``b`` (Turing's condition) the perturbations grow into spots
    of a characteristic size.

    Linearising (1)-(2) at ``a = b = 4`` gives the Jacobian
    ``s [[-4, -4], [4, 3]]``; a Fourier mode of Laplacian eigenvalue ``-q``
    grows when ``Da Db q^2 - s (3 Da - 4 Db) q + 4 s^2 < 0`` for some q,
    i.e. when ``3 r - 4 > 4 sqrt(r)`` with ``r = Da / Db``: ``r > 4``.
    Turk's spot rates (r = 4) lie on the threshold, where spots form; well
    above it the stripe (labyrinth) state wins. Measured at 128^2 after
    8,000 steps (s = 0.01, D_b = 0.01, Turk's start): r = 4 gave 442 separate
    spots, r = 6 and 8 a mix of spots and short worms (349 and 226 pieces),
    r = 10 to 20 labyrinths (16-135 connected pieces). The clamp
    ``b >= 0`` is essential: without it every run of the sweep diverged.

    Too large a diffusion rate for the time step is refused:

    >>> texsynth.procedural.reaction_diffusion((8, 8), steps=1, rates=texsynth.procedural.TurkRates(Da=0.5))
    Traceback (most recent call last):
    ...
    ValueError: Da=0.5 with dt=1 is unstable: the explicit scheme with the 5-point Laplacian needs 4 * Da * dt / h^2 <= 1 (h = 1 pixel), here 2; use dt <= 0.5 or a smaller Da

    References
    ----------
    .. [1] G. Turk, "Generating textures on arbitrary surfaces using
       reaction-diffusion", SIGGRAPH 1991. https://doi.org/10.1145/122718.122749
    .. [2] M. G. Malheiros, H. Fensterseifer, M. Walter, "Pattern formation
       through minimalist biologically inspired cellular simulation", Graphics
       Interface 2017 (the labyrinth rates of the "stripes" preset).
    """
    size = _check_grid(size)
    steps = check_positive_int(steps, "steps")
    _check_choice(preset, TURK_PRESETS, "preset")
    params = dataclasses.asdict(check_group(rates, TurkRates, "rates").resolved(TURK_PRESETS[preset]))
    for name in ("s", "Da", "Db", "beta", "beta_spread"):
        params[name] = _check_rate(params[name], name)
    dt = check_float(dt, "dt")
    _check_stable(dt, {"Da": params["Da"], "Db": params["Db"]})
    stages = [(params["s"], steps)]
    if cascade is not None and not isinstance(cascade, (tuple, list)):
        raise TypeError(f"cascade must be a list of (s, steps) pairs, got {type(cascade).__name__}")
    for item in cascade or ():
        if not isinstance(item, (tuple, list)) or len(item) != 2:
            raise ValueError(f"cascade must be a sequence of (s, steps) pairs, got {cascade!r}")
        stages.append((_check_rate(item[0], "cascade s"), check_positive_int(item[1], "cascade steps")))
    record_every = _check_record(record_every)
    dt_ = check_dtype(dtype)
    if colormap is not None:
        colormap_function(colormap)
    _check_memory(size, dt_, 10, sum(n for _, n in stages), record_every)
    gen = as_rng(rng)

    # extreme (finite) rates overflow the dtype: that shows as divergence, checked in _run
    with np.errstate(over="ignore", invalid="ignore"):
        beta_ij = params["beta"] + gen.uniform(-params["beta_spread"], params["beta_spread"], size)
        grid = _PeriodicGrid([np.full(size, 4.0), np.full(size, 4.0)], dt_)
        a, b = grid.inner[0], grid.inner[1]
        diffusion = np.array([params["Da"], params["Db"]], dtype=dt_).reshape(2, 1, 1) * dt_.type(dt)
        frozen = None
        all_frames = []
        for stage, (s_k, n_k) in enumerate(stages):
            rate = dt_.type(s_k * dt)
            # linear terms: -4 D a ; -4 D b - s b     constant terms: s 16 ; -s beta_ij
            decay = (4 * diffusion + np.array([0, rate], dtype=dt_).reshape(2, 1, 1)).astype(dt_)
            constant = np.stack([np.full(size, 16 * s_k * dt), -beta_ij * (s_k * dt)]).astype(dt_)
            if stage > 0:
                lo, hi = float(b.min()), float(b.max())
                spots = b < (lo + hi) / 2  # Turk's spots are the cells where b is depleted
                frozen = spots if frozen is None else (frozen | spots)
                keep = (~frozen).astype(dt_)

            def step():
                lap = grid.linear_part(diffusion, decay)  # D lap(.) - s b
                lap += constant  # + s 16 ; - s beta
                ab = np.multiply(a, b, out=grid.tmp)
                ab *= rate  # s a b
                lap[0] -= ab  # eq. (1): s (16 - a b) + D_a lap(a)
                lap[1] += ab  # eq. (2): s (a b - b - beta) + D_b lap(b)
                if frozen is not None:
                    lap *= keep
                grid.inner += lap
                np.maximum(b, 0, out=b)  # Turk: b is never negative

            frames = _run(grid, step, n_k, progress, "reaction-diffusion", record_every, 1,
                          {"s": s_k, "Da": params["Da"], "Db": params["Db"], "beta": params["beta"],
                           "beta_spread": params["beta_spread"], "dt": dt})
            if frames is not None:
                all_frames.append(frames)
    image = _colour(-b, colormap)  # spots (b depleted) dark
    if not return_info:
        return image
    params["dt"] = dt
    if cascade:
        params["cascade"] = list(stages[1:])
    info = ReactionDiffusionInfo(
        concentrations={"a": a.copy(), "b": b.copy()},
        steps=sum(n for _, n in stages),
        parameters=params,
        frames=np.concatenate(all_frames) if all_frames else None,
        beta=beta_ij,
    )
    return image, info


def meinhardt_stripes(size, *, steps=4000, p1=0.04, p2=0.06, p3=0.04, diff1=0.009, diff2=0.2, arand=0.02,
                      colormap=None, record_every=None, rng=None, dtype=np.float32, progress=False,
                      return_info=False):
    """Turk's stripes: Meinhardt's five-chemical two-species balance.

    Examples
    --------
    >>> import texsynth
    >>> img, info = texsynth.procedural.meinhardt_stripes((24, 24), steps=100, rng=0, return_info=True)
    >>> img.shape, sorted(info.concentrations)
    ((24, 24, 3), ['a', 'b', 'c', 'd', 'e'])

    Two activators that exclude each other locally but support each other
    at a distance form alternating bands: the stripes of Turk's 1991
    program [2]_, after Meinhardt [1]_.

    Parameters
    ----------
    size : int or (int, int)
        Grid size ``(H, W)`` (an int means a square); periodic boundary (the
        result tiles).
    steps : int, default 4000
        Time steps (dt = 1, as Turk). Stripes have joined into a labyrinth of
        period about 7 px after 2,000 steps at 128^2; the system never
        settles: later on, single bursts of ``a`` (up to 4x the stripe
        height) appear and fade, re-routing stripes around them (measured
        to 16,000 steps, float32 and float64 alike).
    p1, p2, p3 : float, default 0.04, 0.06, 0.04
        Decay rate of the activators a and b, decay rate of their common
        inhibitor c, and the exchange rate of the messengers d and e.
    diff1, diff2 : float, default 0.009, 0.2
        Diffusion rates of a, b and of d, e (c does not diffuse).
    arand : float, default 0.02
        ``r_ij`` is uniform in ``1 +- arand / 2``: the random differences in
        a's autocatalysis that break the symmetry.
    colormap, record_every, rng, dtype, progress, return_info
        As in :func:`reaction_diffusion`; the pattern chemical is ``a``
        (shown dark), frames record ``a``.

    Returns
    -------
    image : numpy.ndarray
        ``(H, W, 3)`` RGB in [0, 1], ``a`` normalised and coloured.
    info : ReactionDiffusionInfo
        Only with ``return_info=True``: ``a`` to ``e``, ``r_ij`` (as
        ``info.beta``), frames.

    Raises
    ------
    ValueError
        Non-positive size or steps, negative or non-finite rates, p1 = 0 or
        p2 = 0 (no steady state), a steady state ``p2 / (2 p1)`` beyond the
        range of the dtype, diffusion rates above the stability bound
        ``4 D <= 1``, a run that diverges, or a size larger than this
        machine's memory.
    TypeError
        For arguments of the wrong type (see :func:`reaction_diffusion`).

    Notes
    -----

    Equations (5)-(9) of the module docstring, exactly as Turk's 1991 program
    ``spots.c`` (routine ``multiplicative_help``, "what Hans Meinhardt calls a
    two-species balance") with his parameters ``do_stripes``. Start: the
    uniform steady state ``a = b = d = e = p2 / (2 p1)``,
    ``c = 0.02 a^3 / p2``. a and b exclude each other locally (both feed the
    inhibitor c) but support each other at a distance (b makes d, which
    feeds a's autocatalysis, and vice versa), so bands of a alternate with
    bands of b. Forward Euler, 5-point periodic Laplacian.

    References
    ----------
    .. [1] H. Meinhardt, Models of Biological Pattern Formation, Academic
       Press, 1982.
    .. [2] G. Turk, "Generating textures on arbitrary surfaces using
       reaction-diffusion", SIGGRAPH 1991, and its program ``spots.c``
       ("The stripe-formation system is described in the book: Models of
       Biological Pattern Formation, Hans Meinhardt").
       https://doi.org/10.1145/122718.122749
    """
    size = _check_grid(size)
    steps = check_positive_int(steps, "steps")
    p1 = check_float(p1, "p1")
    p2 = check_float(p2, "p2")
    p3 = _check_rate(p3, "p3")
    diff1 = _check_rate(diff1, "diff1")
    diff2 = _check_rate(diff2, "diff2")
    arand = _check_rate(arand, "arand")
    _check_stable(1.0, {"diff1": diff1, "diff2": diff2})
    record_every = _check_record(record_every)
    dt_ = check_dtype(dtype)
    a0 = p2 / (2 * p1)  # semi-stable equilibrium (Turk's semi_equilibria)
    try:
        c0 = 0.02 * a0 ** 3 / p2
    except OverflowError:
        c0 = math.inf
    if not max(a0, c0) < float(np.finfo(dt_).max) / 1e6:
        raise ValueError(f"p1={p1:g} and p2={p2:g} put the steady state at a = p2 / (2 p1) = {a0:.3g}, "
                         f"c = 0.02 a^3 / p2 = {c0:.3g}, beyond the range of {dt_.name}; use a larger p1")
    if colormap is not None:
        colormap_function(colormap)
    _check_memory(size, dt_, 16, steps, record_every)
    gen = as_rng(rng)

    # extreme (finite) rates overflow the dtype: that shows as divergence, checked in _run
    with np.errstate(over="ignore", invalid="ignore"):
        r_ij = (1 + gen.uniform(-0.5 * arand, 0.5 * arand, size)).astype(dt_)
        grid = _PeriodicGrid([np.full(size, a0)] * 4, dt_)  # a, b, d, e diffuse
        a, b, d, e = grid.inner
        c = np.full(size, 0.02 * a0 ** 3 / p2, dtype=dt_)
        diffusion = np.array([diff1, diff1, diff2, diff2], dtype=dt_).reshape(4, 1, 1)
        decay = (4 * diffusion + np.array([p1, p1, p3, p3], dtype=dt_).reshape(4, 1, 1)).astype(dt_)
        buffers = np.empty((2,) + size, dtype=dt_)
        p2_, p3_ = dt_.type(p2), dt_.type(p3)

        def step():
            fa, fb = buffers
            lap = grid.linear_part(diffusion, decay)  # D lap(x) - p x
            np.multiply(a, a, out=fa)
            fa *= e
            fa *= r_ij
            fa *= 0.01  # 0.01 r a^2 e
            np.multiply(b, b, out=fb)
            fb *= d
            fb *= 0.01  # 0.01 b^2 d
            lap[0] += fa / c  # eq. (5)
            lap[1] += fb / c  # eq. (6)
            lap[2] += p3_ * a  # eq. (8): p3 (a - d) + D2 lap(d)
            lap[3] += p3_ * b  # eq. (9)
            fa += fb
            fa -= p2_ * c  # eq. (7), from the old c
            grid.inner += lap
            np.add(c, fa, out=c)  # c += eq. (7)

        frames = _run(grid, step, steps, progress, "meinhardt-stripes", record_every, 0,
                      {"p1": p1, "p2": p2, "p3": p3, "diff1": diff1, "diff2": diff2, "arand": arand})
    image = _colour(a, colormap)  # high a dark (the default colours put high values dark)
    if not return_info:
        return image
    info = ReactionDiffusionInfo(
        concentrations={"a": a.copy(), "b": b.copy(), "c": c.copy(), "d": d.copy(), "e": e.copy()},
        steps=steps,
        parameters=dict(p1=p1, p2=p2, p3=p3, diff1=diff1, diff2=diff2, arand=arand, dt=1.0),
        frames=frames,
        beta=r_ij,
    )
    return image, info


def gray_scott(size, *, preset="spots", rates=GrayScottRates(), dt=1.0, steps=10000, seeds="auto", colormap=None,
               record_every=None, rng=None, dtype=np.float32, progress=False, return_info=False):
    """Gray-Scott reaction-diffusion: spots, stripes, mazes, coral... from the feed and kill rates.

    Examples
    --------
    >>> import texsynth
    >>> img, info = texsynth.procedural.gray_scott((32, 32), steps=100, rng=0, return_info=True)
    >>> img.shape, sorted(info.concentrations)
    ((32, 32, 3), ['u', 'v'])

    Two chemicals react (``u + 2v -> 3v``) and diffuse from random seeds of
    ``v``, ``u`` fed at the rate ``feed`` and ``v`` removed at ``feed +
    kill``; the two rates select the pattern (Pearson 1993 [1]_).

    Parameters
    ----------
    size : int or (int, int)
        Grid size ``(H, W)`` (an int means a square); periodic boundary (the
        result tiles).
    preset : str, default "spots"
        A name of :data:`GRAY_SCOTT_PRESETS` supplying the rates left ``"auto"``.
    rates : GrayScottRates
        The feed rate ``feed`` (Pearson's F) of u, the kill rate ``kill``
        (his k) of v and the diffusion rates ``Du``, ``Dv`` (0.16, 0.08 in
        every preset); a field left ``"auto"`` (the default: all of them) is
        the preset's. See :class:`GrayScottRates`.
    dt : float, default 1.0
        Time step; must satisfy ``4 max(Du, Dv) dt <= 1``.
    steps : int, default 10000
        Time steps.
    seeds : int or "auto"
        Number of random square seeds of ``v = 0.5`` (``u = 0.25``) in the
        trivial state ``u = 1, v = 0``; ``"auto"`` (default): one per 1000
        pixels (at least 1). At most one per pixel.
    colormap, record_every, rng, dtype, progress, return_info
        As in :func:`reaction_diffusion` (the pattern chemical is ``v``).

    Returns
    -------
    image : numpy.ndarray
        ``(H, W, 3)`` RGB in [0, 1], ``v`` normalised and coloured.
    info : ReactionDiffusionInfo
        Only with ``return_info=True``: ``u``, ``v``, frames.

    Raises
    ------
    ValueError
        Unknown preset, non-positive sizes or steps, negative or non-finite
        rates, ``dt`` above the stability bound, more seeds than pixels, a
        run that diverges, or a size larger than this machine's memory.
    TypeError
        For arguments of the wrong type (see :func:`reaction_diffusion`).

    Notes
    -----

    Equations (3)-(4) of the module docstring (Pearson [1]_, eq. 1), forward
    Euler with the 5-point Laplacian, 1 % noise added to the seeds.

    References
    ----------
    .. [1] J. E. Pearson, "Complex patterns in a simple system", Science 261
       (1993), 189-192. https://doi.org/10.1126/science.261.5118.189
    """
    size = _check_grid(size)
    steps = check_positive_int(steps, "steps")
    _check_choice(preset, GRAY_SCOTT_PRESETS, "preset")
    params = dataclasses.asdict(check_group(rates, GrayScottRates, "rates").resolved(GRAY_SCOTT_PRESETS[preset]))
    params["feed"] = _check_rate(params["feed"], "feed")
    params["kill"] = _check_rate(params["kill"], "kill")
    Du = _check_rate(params.pop("Du"), "Du")
    Dv = _check_rate(params.pop("Dv"), "Dv")
    dt = check_float(dt, "dt")
    _check_stable(dt, {"Du": Du, "Dv": Dv})
    record_every = _check_record(record_every)
    dt_ = check_dtype(dtype)
    h, w = size
    if is_auto(seeds):
        seeds = max(1, (h * w) // 1000)
    seeds = check_positive_int(seeds, "seeds")
    if seeds > h * w:
        raise ValueError(f"seeds must be at most the number of pixels ({h * w}), got {seeds}")
    if colormap is not None:
        colormap_function(colormap)
    _check_memory(size, dt_, 10, steps, record_every)
    gen = as_rng(rng)

    u = np.ones(size)
    v = np.zeros(size)
    half = max(1, min(h, w) // 32)
    for r, c in zip(gen.integers(0, h, seeds), gen.integers(0, w, seeds)):
        rows = np.arange(r - half, r + half + 1) % h
        cols = np.arange(c - half, c + half + 1) % w
        u[np.ix_(rows, cols)] = 0.25
        v[np.ix_(rows, cols)] = 0.5
    u += 0.01 * gen.standard_normal(size)
    v += 0.01 * gen.standard_normal(size)
    np.clip(v, 0, None, out=v)
    # extreme (finite) rates overflow the dtype: that shows as divergence, checked in _run
    with np.errstate(over="ignore", invalid="ignore"):
        grid = _PeriodicGrid([u, v], dt_)
        uu, vv = grid.inner[0], grid.inner[1]
        diffusion = np.array([Du, Dv], dtype=dt_).reshape(2, 1, 1) * dt_.type(dt)
        # linear terms: -4 Du u - F u ; -4 Dv v - (F + k) v    constant: + F (for u)   (F: feed, k: kill)
        decay = (4 * diffusion + np.array([params["feed"], params["feed"] + params["kill"]]).reshape(2, 1, 1)
                 * dt).astype(dt_)
        feed = dt_.type(params["feed"] * dt)
        step_dt = dt_.type(dt)

        def step():
            lap = grid.linear_part(diffusion, decay)
            lap[0] += feed  # eq. (3): D_u lap(u) - u v^2 + F (1 - u)
            uvv = np.multiply(vv, vv, out=grid.tmp)
            uvv *= uu
            if dt != 1.0:
                uvv *= step_dt
            lap[0] -= uvv
            lap[1] += uvv  # eq. (4): D_v lap(v) + u v^2 - (F + k) v
            grid.inner += lap

        frames = _run(grid, step, steps, progress, "gray-scott", record_every, 1,
                      {"feed": params["feed"], "kill": params["kill"], "Du": Du, "Dv": Dv, "dt": dt})
    image = _colour(vv, colormap)
    if not return_info:
        return image
    params.update(Du=Du, Dv=Dv, dt=dt, seeds=seeds)
    info = ReactionDiffusionInfo(concentrations={"u": uu.copy(), "v": vv.copy()}, steps=steps,
                                 parameters=params, frames=frames)
    return image, info
