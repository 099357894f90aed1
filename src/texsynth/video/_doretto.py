"""Doretto et al.'s dynamic textures: a linear dynamical system learnt from a clip, then run.

Doretto, Chiuso, Wu & Soatto (2003) model the frames ``y(t)`` of a clip of a
stationary scene in motion (water, smoke, steam, foliage in wind), each frame
stacked as one vector of ``m`` values, as the output of a linear Gaussian
state-space model, an ARMA process (the paper's eq. 1, with ``v = B v'``)::

    x(t + 1) = A x(t) + B v(t),         v(t) ~ N(0, I_{n_v})    (state, n values)
    y(t)     = C x(t) + ybar + w(t),    w(t) ~ N(0, R)          (frame, m values)

with ``n << m``. The paper identifies ``A, B, C`` *sub-optimally, in closed
form*, from a principal component analysis of the frames:

1. ``Y = [y(1) - ybar, ..., y(T) - ybar]``, the frames minus their per-pixel
   mean ``ybar``; thin SVD ``Y = U S V^T``;
2. ``C = U_n`` (the first ``n`` columns) and ``X = S_n V_n^T``, the clip's
   states (``X = C^T Y``);
3. ``A = X_{2:T} X_{1:T-1}^+``, the least-squares one-step predictor;
4. ``V = X_{2:T} - A X_{1:T-1}``, its residuals, ``Q = V V^T / (T - 1)``,
   and ``B = U_v S_v / sqrt(T - 1)`` of rank ``n_v`` from the SVD of ``V``
   (``B B^T = Q`` for ``n_v = rank Q``);
5. ``R``, the variance of the measurement noise, from the residual
   ``Y - C X``.

Synthesis runs the state equation from the clip's first state ``x0 = X_{:,1}``
with Gaussian ``v(t)`` and writes ``C x(t) + ybar``: any number of frames at
almost no cost.

This module's departures and additions, each documented where it acts:
steps 3-4 by default in their Yule-Walker form (``A = S_1 S_0^-1``, ``Q =
S_0 - A S_0 A^T`` from the clip's state covariances; the paper's least
squares is ``estimator="least-squares"``), see :func:`learn_dynamic_texture`;
the automatic state dimension (:func:`resolve_state_dim`); the stabilisation
of ``A`` (:func:`stabilize`); frames of another size through one
source-coordinate map (:func:`_map_model`, :func:`dynamic_texture`).

Symbols follow the paper, except ``tau`` (the clip's length) written ``T``:
``n`` the state dimension, ``n_v`` the noise dimension, ``m = H W C`` the values
of a frame.

Not checked against the paper (it was not at hand; this follows its
abstract and the closed-form algorithm and code listing as reproduced in
course notes and later papers): the section and equation numbers beyond
eq. 1, the normalisations ``1 / (T - 1)`` of ``Q`` and ``1 / T`` of ``R``,
how (and whether) the paper estimates ``R``, whether its synthesis adds
``w(t)`` (the quoted code does not), its examples' state dimensions and any
remedy it gives for an unstable ``A``.

References
----------
.. [1] G. Doretto, A. Chiuso, Y. N. Wu and S. Soatto, "Dynamic textures",
   International Journal of Computer Vision 51(2), 2003, pp. 91-109.
   doi:10.1023/A:1021669406132
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import time

import numpy as np

from ..core._progress import Progress
from ..core._validate import (as_image, as_rng, as_size, check_bool, check_choice, check_memory, check_positive_int,
                              is_auto)

__all__ = ["DynamicTexture", "DynamicTextureInfo", "learn_dynamic_texture", "dynamic_texture"]

#: The share of the clip's variance (the energy of the singular values of the mean-free frames) that
#: ``state_dim="auto"`` keeps.
ENERGY = 0.95
#: An eigenvalue of a learnt ``A`` on or outside the unit circle (magnitude at least :data:`UNIT`, 1 less
#: rounding) is moved radially to this magnitude (:func:`stabilize`).
MAX_RADIUS = 0.99
UNIT = 1.0 - 1e-9
#: Singular values below this fraction of the largest are rounding noise of the Gram matrix (its
#: eigenvalues are the squares, exact to about 1e-16 of the largest): never a state dimension.
RANK_TOLERANCE = 1e-6
#: Values rendered at once, at least (whole frames; paces the progress report) ...
CHUNK_VALUES = 1 << 22
#: ... and at most, unless one frame is larger (bounds the temporaries of a block: a mask, the noise w(t)).
BLOCK_VALUES = 1 << 25


# --------------------------------------------------------------------------
# The model


@dataclasses.dataclass(frozen=True, eq=False)
class DynamicTexture:
    """A dynamic texture: the linear dynamical system learnt from a clip (Doretto et al. 2003, eq. 1).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> t, c = np.arange(24)[:, None, None], np.arange(16)[None, None, :]
    >>> clip = 0.5 + 0.4 * np.sin(0.5 * c - 0.3 * t) * np.ones((1, 12, 1))  # a wave moving right
    >>> model = texsynth.learn_dynamic_texture(clip, state_dim=2)
    >>> model.A.shape, model.C.shape, model.frame_shape
    ((2, 2), (192, 2), (12, 16))
    >>> model.synthesize(50, rng=0).shape
    (50, 12, 16)

    Made by :func:`learn_dynamic_texture`; :meth:`synthesize` runs it. The
    arrays are read-only.

    Attributes
    ----------
    A : numpy.ndarray
        ``(n, n)`` state transition, every eigenvalue inside the unit
        circle (:func:`stabilize`).
    B : numpy.ndarray
        ``(n, n_v)`` input matrix, ``B B^T = Q`` (the ``n_v`` strongest
        directions of ``Q``).
    C : numpy.ndarray
        ``(m, n)`` output matrix with orthonormal columns: the clip's first
        ``n`` principal components, ``m = H W C`` values per frame in C order
        of ``frame_shape``.
    mean : numpy.ndarray
        The mean frame ``ybar``, of ``frame_shape``.
    R : numpy.ndarray
        The variance of the measurement noise ``w(t)`` per value (the
        diagonal of the paper's ``R``), of ``frame_shape``.
    x0 : numpy.ndarray
        ``(n,)`` initial state: the clip's first state ``X_{:,1}``.
    states : numpy.ndarray
        ``(n, T)`` the clip's states ``X = S_n V_n^T``.
    singular_values : numpy.ndarray
        All ``min(T, m)`` singular values of the mean-free frames, largest
        first (0 below the numerical rank).
    eigenvalues : numpy.ndarray
        ``(n,)`` eigenvalues of the estimated ``A`` before stabilisation
        (compare ``np.linalg.eigvals(model.A)``).
    stabilized : bool
        Whether :func:`stabilize` moved any eigenvalue.
    estimator : str
        How ``A`` and ``Q`` were estimated: ``"yule-walker"`` or
        ``"least-squares"`` (see :func:`learn_dynamic_texture`).
    frame_shape : tuple
        ``(H, W)`` or ``(H, W, C)``, the clip's frame.
    dtype : numpy.dtype
        float32 for a float32 clip, float64 otherwise: the dtype of ``C``,
        ``mean``, ``R`` and of synthesised frames.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    mean: np.ndarray
    R: np.ndarray
    x0: np.ndarray
    states: np.ndarray
    singular_values: np.ndarray
    eigenvalues: np.ndarray
    stabilized: bool
    estimator: str
    frame_shape: tuple
    dtype: np.dtype

    def __post_init__(self):
        for name in ("A", "B", "C", "mean", "R", "x0", "states", "singular_values", "eigenvalues"):
            getattr(self, name).setflags(write=False)

    @property
    def state_dim(self):
        """``n``, the dimension of the state."""
        return self.A.shape[0]

    @property
    def noise_dim(self):
        """``n_v``, the dimension of the driving noise."""
        return self.B.shape[1]

    @property
    def Q(self):
        """``(n, n)`` covariance of the state noise ``B v(t)``: ``B B^T``."""
        return self.B @ self.B.T

    @property
    def spectral_radius(self):
        """The largest magnitude of an eigenvalue of ``A``: below 1."""
        return float(np.max(np.abs(np.linalg.eigvals(self.A)), initial=0.0))

    @property
    def modes(self):
        """The columns of ``C`` as images: ``(n,) + frame_shape``."""
        return self.C.T.reshape((self.state_dim,) + self.frame_shape)

    def synthesize(self, n_frames, *, size=None, output_noise=False, rng=None, return_info=False, progress=False):
        """Run the model for ``n_frames`` frames (Doretto et al. 2003, eq. 1).

        Examples
        --------
        >>> import numpy as np, texsynth
        >>> t, c = np.arange(24)[:, None, None], np.arange(16)[None, None, :]
        >>> clip = 0.5 + 0.4 * np.sin(0.5 * c - 0.3 * t) * np.ones((1, 12, 1))
        >>> model = texsynth.learn_dynamic_texture(clip, state_dim=2)
        >>> video = model.synthesize(100, rng=0)
        >>> video.shape, bool(np.allclose(video[0], model.mean + (model.C @ model.x0).reshape(12, 16)))
        ((100, 12, 16), True)

        ``x(1) = x0``, ``x(t + 1) = A x(t) + B v(t)`` with ``v(t)`` drawn
        from ``N(0, I)``, and frame ``t`` is ``C x(t) + ybar`` (plus
        ``w(t)`` with ``output_noise=True``), clipped to [0, 1].

        Parameters
        ----------
        n_frames : int
            Number of frames, any.
        size : None, int or (int, int)
            Output frame size ``(height, width)``. None (default): the
            clip's. Another size renders every frame through one
            source-coordinate map synthesised for it (see the Notes of
            :func:`dynamic_texture`).
        output_noise : bool
            Add the measurement noise ``w(t) ~ N(0, R)``, independent per
            value and frame. Default False, as the paper's synthesis (see
            Notes of :func:`dynamic_texture`).
        rng : None, int or numpy.random.Generator
            Random source of ``v(t)``, ``w(t)`` and the map; an int seed
            reproduces the output bit for bit.
        return_info : bool
            Also return a :class:`DynamicTextureInfo`.
        progress : bool or callable
            Report progress per block of rendered frames.

        Returns
        -------
        video : numpy.ndarray
            ``(n_frames, height, width[, C])`` in [0, 1], of :attr:`dtype`.
        info : DynamicTextureInfo
            Only with ``return_info=True``.

        Raises
        ------
        ValueError
            For ``n_frames < 1``, a bad ``size``, or an output that would not
            fit in memory.
        """
        start = time.perf_counter()
        N = check_positive_int(n_frames, "n_frames")
        out_shape = self.frame_shape if size is None else as_size(size) + self.frame_shape[2:]
        noise = check_bool(output_noise, "output_noise")
        gen = as_rng(rng)
        values = math.prod(out_shape)
        mapped = tuple(out_shape) != tuple(self.frame_shape)
        check_output_memory(N, out_shape, self.dtype, self.state_dim if mapped else None, self.state_dim)
        states = run_states(self.A, self.B, self.x0, N, gen)
        C, mean, deviation, map_info = self.C, self.mean.reshape(-1), np.sqrt(self.R).reshape(-1), None
        if mapped:
            C, mean, deviation, map_info = _map_model(self, out_shape[:2], gen)
        video = np.empty((N,) + tuple(out_shape), self.dtype)
        flat = video.reshape(N, -1)
        per_block = frames_per_block(N, values, self.state_dim)
        clipped = 0
        with Progress(progress, math.ceil(N / per_block), "dynamic_texture") as bar:
            for first in range(0, N, per_block):
                last = min(N, first + per_block)
                block = flat[first:last]  # eq. 1: y(t) = C x(t) + ybar (+ w(t)), written in place
                np.matmul(states[:, first:last].T.astype(self.dtype), C.T, out=block)
                block += mean
                if noise:
                    block += gen.standard_normal(block.shape).astype(self.dtype, copy=False) * deviation
                clipped += int(np.count_nonzero(block < 0)) + int(np.count_nonzero(block > 1))
                np.clip(block, 0.0, 1.0, out=block)
                bar.advance({"frame": last})
        if not return_info:
            return video
        return video, DynamicTextureInfo(
            model=self, states=states, coordinates=None if map_info is None else map_info.coordinates,
            weights=None if map_info is None else map_info.weights, map_info=map_info,
            clipped=clipped / float(video.size), seconds=time.perf_counter() - start)


@dataclasses.dataclass(frozen=True, eq=False)
class DynamicTextureInfo:
    """What :func:`dynamic_texture` (or :meth:`DynamicTexture.synthesize`) learnt and drew.

    Attributes
    ----------
    model : DynamicTexture
        The learnt system; ``model.synthesize(...)`` makes more frames.
    states : numpy.ndarray
        ``(n, n_frames)`` the synthesised states ``x(t)``.
    coordinates, weights : numpy.ndarray or None
        With a ``size`` other than the clip's: the source-coordinate map
        from the output frame into the clip's frame (``(H, W, K, 2)`` and
        ``(H, W, K)``), the same for every frame.
        ``texsynth.apply_coordinates(image, info)`` renders any image of the
        clip's frame size through it. None otherwise.
    map_info : object or None
        The info of the 2-D synthesis that made the map
        (:class:`~texsynth.patch.PatchSamplingInfo`).
    clipped : float
        Fraction of output values clipped to [0, 1].
    seconds : float
        Wall time of the call.
    """

    model: DynamicTexture
    states: np.ndarray
    coordinates: np.ndarray | None
    weights: np.ndarray | None
    map_info: object
    clipped: float
    seconds: float


# --------------------------------------------------------------------------
# Learning: the closed-form sub-optimal identification


def _check_clip(frames):
    video = as_image(frames, "frames", spatial_dims=3)
    if video.shape[0] < 3:
        raise ValueError(
            f"frames must hold at least 3 frames (T, H, W[, C]) to learn a dynamic texture, got {video.shape[0]}; "
            "A is fitted on T - 1 pairs of successive states"
        )
    return video


def _check_clip_memory(frames):
    """Refuse a clip whose data matrix (and its principal components) cannot fit, before converting it."""
    if not hasattr(frames, "shape") or len(frames.shape) < 3:
        return
    T = int(frames.shape[0])
    m = math.prod(int(s) for s in frames.shape[1:])
    itemsize = 4 if getattr(frames, "dtype", None) == np.float32 else 8
    # the converted clip, the mean-free data matrix Y and C (at most T columns)
    check_memory(3.0 * T * m * itemsize, tuple(frames.shape), name="frames",
                 what="the clip's data matrix and its principal components")


def _check_dims(state_dim, noise_dim):
    """Type and sign of ``state_dim`` and ``noise_dim``, before any work (their bounds need the clip)."""
    for name, value, minimum in (("state_dim", state_dim, 1), ("noise_dim", noise_dim, 0)):
        if isinstance(value, str):
            if not is_auto(value):
                raise ValueError(f"{name} must be an integer >= {minimum} or 'auto', got {value!r}")
        elif not isinstance(value, numbers.Integral) or isinstance(value, bool):
            raise TypeError(f"{name} must be an integer >= {minimum} or 'auto', got {type(value).__name__} {value!r}")
        elif value < minimum:
            raise ValueError(f"{name} must be an integer >= {minimum} or 'auto', got {value}")


def resolve_state_dim(state_dim, singular_values, T, rank):
    """``n``: the user's (at most ``T - 1``), or ``"auto"``: the fewest components holding :data:`ENERGY`
    of the variance, at most ``T // 4`` and the clip's numerical ``rank``, at least 1.

    ``T // 4``: ``A``'s ``n^2`` entries are estimated from ``T - 1`` pairs of states; as ``n`` nears ``T / 2``
    they describe the clip's one trajectory more than its dynamics, and the synthesis replays the clip
    (figures in :func:`learn_dynamic_texture`).
    """
    if is_auto(state_dim):
        energy = np.cumsum(singular_values.astype(np.float64) ** 2)
        if energy[-1] <= 0:
            return 1
        n = int(np.searchsorted(energy / energy[-1], ENERGY - 1e-12) + 1)
        return max(1, min(n, T // 4, rank))
    n = int(state_dim)
    most = min(T - 1, singular_values.size)
    if n > most:
        raise ValueError(
            f"state_dim={n} is more than the clip supports: at most T - 1 = {T - 1} for {T} frames "
            f"(and the {singular_values.size} values of a frame); pass state_dim <= {most} or 'auto'"
        )
    return n


def _principal_components(Y, n_max):
    """The thin SVD of the mean-free ``(m, T)`` data matrix through its Gram matrix: singular values
    (all ``min(m, T)``), ``U`` and ``V`` for the first ``n_max`` (the method of snapshots: ``Y^T Y =
    V S^2 V^T``, ``U = Y V S^-1``: the whole learning takes a quarter of the time of LAPACK's thin SVD of
    the tall matrix alone, ``benchmarks/bench_doretto.py``; exact for every component above
    :data:`RANK_TOLERANCE` of the largest)."""
    m, T = Y.shape
    if m >= T:
        if Y.dtype == np.float64:
            gram = Y.T @ Y
        else:  # float32 data, a float64 Gram matrix: row blocks bound the float64 copies
            gram = np.zeros((T, T))
            for first in range(0, m, 1 << 16):
                rows = Y[first:first + (1 << 16)].astype(np.float64)
                gram += rows.T @ rows
        w, V = np.linalg.eigh(gram)
        w, V = w[::-1], V[:, ::-1]
        s = np.sqrt(np.clip(w, 0, None))
        top = s[:n_max]
        safe = np.where(top > 0, top, 1.0)
        U = (Y @ V[:, :n_max].astype(Y.dtype)) / safe.astype(Y.dtype)
        return s, U, V[:, :n_max]
    U, s, Vt = np.linalg.svd(Y.astype(np.float64), full_matrices=False)  # few values per frame: small
    return s, U[:, :n_max].astype(Y.dtype), Vt[:n_max].T


def stabilize(A, max_radius=MAX_RADIUS):
    """``A`` with every eigenvalue on or outside the unit circle moved radially to magnitude ``max_radius``.

    In the real Schur form ``A = Z T Z^T`` (``Z`` orthogonal, ``T`` quasi-upper-triangular, whose
    1 x 1 and 2 x 2 diagonal blocks carry the real eigenvalues and the complex pairs), a 1 x 1 block
    ``lambda`` with ``|lambda| >= 1`` becomes ``sign(lambda) max_radius``, and a 2 x 2 block (a pair of
    magnitude ``sqrt(det)``) with ``sqrt(det) >= 1`` is multiplied by ``max_radius / sqrt(det)``: its pair
    keeps its angle (its frequency) and gets magnitude ``max_radius``. The other eigenvalues, ``Z``
    and the coupling above the diagonal stay; ``Z`` orthogonal keeps the arithmetic well conditioned
    where an eigendecomposition ``W Lambda W^-1`` of a non-normal ``A`` might not be.

    Returns ``(A', moved)``.

    Examples
    --------
    >>> A = np.array([[1.2, 0.0], [0.3, 0.5]])
    >>> B, moved = stabilize(A)
    >>> moved, np.round(np.sort(np.abs(np.linalg.eigvals(B))), 6).tolist()
    (True, [0.5, 0.99])
    >>> stabilize(np.array([[0.995]]))  # inside the unit circle: unchanged
    (array([[0.995]]), False)
    """
    from scipy.linalg import schur

    if A.size == 0:
        return A, False
    T, Z = schur(A, output="real")
    n, i, moved = T.shape[0], 0, False
    while i < n:
        if i + 1 < n and T[i + 1, i] != 0:  # a 2 x 2 block: a complex pair of magnitude sqrt(det)
            radius = math.sqrt(abs(T[i, i] * T[i + 1, i + 1] - T[i, i + 1] * T[i + 1, i]))
            if radius >= UNIT:
                T[i:i + 2, i:i + 2] *= max_radius / radius
                moved = True
            i += 2
        else:
            if abs(T[i, i]) >= UNIT:
                T[i, i] = math.copysign(max_radius, T[i, i])
                moved = True
            i += 1
    return (Z @ T @ Z.T, True) if moved else (A, False)


ESTIMATORS = ("yule-walker", "least-squares")


def learn_dynamic_texture(frames, *, state_dim="auto", noise_dim="auto", estimator="yule-walker"):
    """Learn a dynamic texture from a clip (Doretto et al. 2003: the closed-form identification).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> t, c = np.arange(24)[:, None, None], np.arange(16)[None, None, :]
    >>> clip = 0.5 + 0.4 * np.sin(0.5 * c - 0.3 * t) * np.ones((1, 12, 1))  # a wave moving right
    >>> model = texsynth.learn_dynamic_texture(clip)
    >>> model.state_dim, np.round(np.abs(np.angle(np.linalg.eigvals(model.A))), 2).tolist()
    (2, [0.3, 0.3])

    The moving wave is a rotation of two principal components by 0.3 rad
    per frame: the learnt ``A`` has eigenvalues close to ``e^{+-0.3i}``.

    Parameters
    ----------
    frames : array_like or str
        The clip, ``(T, H, W)`` or ``(T, H, W, C)`` with ``T >= 3`` (any
        accepted dtype, or frame files: :func:`texsynth.io.load_frames`).
        Colour frames are stacked as one vector of ``m = H W C`` values.
    state_dim : int or "auto"
        ``n``, the dimension of the state: how many principal components of
        the frames the model keeps. ``"auto"`` (default): the fewest that
        hold 95 % of the clip's variance about its mean frame, at most
        ``T // 4`` (see Notes). At most ``T - 1``.
    noise_dim : int or "auto"
        ``n_v <= n``, the dimension of the driving noise ``v(t)``.
        ``"auto"`` (default): the rank of ``Q``, so that ``B B^T = Q``;
        fewer keeps the ``n_v`` strongest directions of ``Q``. 0 makes the
        model deterministic (it decays to the mean frame).
    estimator : {"yule-walker", "least-squares"}
        How ``A`` and ``Q`` are estimated from the clip's states.
        ``"least-squares"``: the paper's closed form. ``"yule-walker"``
        (default): the same closed form with the clip's state covariance in
        place of the first ``T - 1`` states' Gram matrix, which makes the
        model keep the clip's variance and its correlation from one frame
        to the next (see Notes; a departure from the paper, for that
        reason).

    Returns
    -------
    DynamicTexture
        The model; its :meth:`~DynamicTexture.synthesize` makes frames.

    Raises
    ------
    ValueError
        For fewer than 3 frames, a ``state_dim`` above ``T - 1``, a
        ``noise_dim`` above ``state_dim``, an unknown ``estimator``, or a
        clip that does not fit in memory.
    TypeError
        For a non-integer ``state_dim`` or ``noise_dim``, or frames that are
        not an array.

    Notes
    -----
    The model (eq. 1 of the paper, with ``v(t) = B v'(t)``):

    .. math:: x(t+1) = A x(t) + B v(t), \\quad y(t) = C x(t) + \\bar y + w(t),
              \\quad v(t) \\sim N(0, I_{n_v}),\\ w(t) \\sim N(0, R).

    The paper's closed-form, sub-optimal identification (as its code
    listing of the learning is quoted): with ``Y`` the mean-free frames as
    columns and its thin SVD ``Y = U S V^T``,

    .. math:: C = U_n,\\quad X = S_n V_n^T,\\quad
              A = X_{2:T} X_{1:T-1}^{+},\\quad
              \\hat V = X_{2:T} - A X_{1:T-1},\\quad
              Q = \\frac{\\hat V \\hat V^T}{T - 1} = B B^T,

    ``B = U_v S_v / sqrt(T - 1)`` from the first ``n_v`` singular vectors and
    values of ``hat V``, and ``R`` the mean square over the clip of ``Y - C
    X`` per value (the diagonal of the paper's ``R``; ``C`` has orthonormal
    columns, so it is ``(sum_t Y^2 - sum_k C_k^2 s_k^2) / T``). The SVD is
    taken through the ``T x T`` Gram matrix ``Y^T Y`` (the same
    factorisation, far faster for ``m >> T``). ``estimator="least-squares"``
    is this.

    **Yule-Walker** (the default). With the clip's state covariance ``S_0 =
    X X^T / T = S_n^2 / T`` and its lag-1 covariance ``S_1 = X_{2:T}
    X_{1:T-1}^T / T``,

    .. math:: A = S_1 S_0^{-1}, \\qquad Q = S_0 - A S_0 A^T,

    the moment equations of the model's stationary state: its covariance
    ``P`` solves ``P = A P A^T + Q``, so ``P = S_0``, and its lag-1
    covariance is ``A P = S_1``. The synthesised states therefore have the
    clip's variance in every component and its correlation from frame to
    frame, and ``A`` has no eigenvalue outside the unit circle (``Q`` is
    the Schur complement of ``S_0`` in the block Toeplitz matrix of ``S_0``
    and ``S_1``, the Gram matrix of the zero-padded states and its shift,
    so positive semi-definite, and ``P = S_0`` is positive definite).

    The least-squares ``A`` differs in ``T - 1`` against ``T`` states and
    in that ``Q`` comes from its residuals; on a short clip it sits near
    or beyond the unit circle, ``Q`` is too small (the residuals
    of ``n^2`` parameters fitted to ``T - 1`` pairs) and the synthesised
    motion loses contrast. Measured on simulated water clips (128 x 128
    colour, 64 frames, dense and sparse drops, three seeds each;
    ``texsynth.data.clip("waves")`` and ``"rain"``) at the default ``n``
    (16), the stationary variance of the paper's model is 0.37-0.86 of the
    clip's, 0.21-0.65 of it in the four leading components and 0.94-2.3
    times it in the four last (0.16-3.5 over single components): the
    frames lose contrast and their fine detail takes over, a speckle that
    the clip does not show. Yule-Walker's is the clip's in every component.
    On long clips the two agree.

    **Choice of n** (``"auto"``). The paper chooses ``n`` by hand and
    reads from the singular values how much of the clip each state
    dimension explains. ``"auto"`` keeps the fewest components that hold
    95 % of the variance about the mean frame (99 % would mostly add the
    clip's fine detail and pixel noise, which the model then animates as
    if it were dynamics), at most ``T // 4``: ``A`` has ``n^2`` entries
    estimated from ``T - 1`` pairs of states, and as ``n`` nears ``T / 2``
    they describe the clip's one trajectory more than its dynamics, so the
    synthesis, which starts from the clip's first state, replays the clip.
    Measured on a 64-frame water clip (128 x 128 colour): the correlation
    of synthesised frame 63 with the clip's frame 63 (both about the mean
    frame) is 0.34 at ``n = 16``, 0.79 at ``n = 31`` (0.76 and 0.95 with
    least squares; at ``n = 63`` least squares replays the clip exactly).
    Larger ``n`` holds more detail (the spectrum distance of frames to the
    clip's falls from 0.41-0.51 at 16 to 0.27-0.34 at 31, three seeds):
    with a longer clip, the cap rises with it.

    **Stability.** An eigenvalue of ``A`` on or outside the unit circle
    would make the frames diverge (least squares on a short clip, or
    Yule-Walker's ``A`` at a singular ``Q``). Each one is moved radially
    to magnitude 0.99 (:func:`stabilize`, in the real Schur form: the other
    eigenvalues and each pair's angle, its frequency, stay);
    ``model.eigenvalues`` keeps the estimate's, ``model.stabilized`` says
    whether any moved. An ``A`` inside the unit circle is unchanged.

    Not checked against the paper (it was not at hand): the section and
    equation numbers beyond eq. 1, the normalisations ``1 / (T - 1)`` of
    ``Q`` (here the quoted code's) and ``1 / T`` of ``R``, how the paper
    estimates ``R`` (here its diagonal only: the full ``m x m`` matrix
    would not fit), and any remedy it gives for an unstable ``A``.

    References
    ----------
    .. [1] G. Doretto, A. Chiuso, Y. N. Wu and S. Soatto, "Dynamic
       textures", International Journal of Computer Vision 51(2), 2003,
       pp. 91-109. :doi:`10.1023/A:1021669406132`
    """
    _check_dims(state_dim, noise_dim)
    check_choice(estimator, "estimator", ESTIMATORS)
    _check_clip_memory(frames)
    video = _check_clip(frames)
    T = video.shape[0]
    frame_shape = tuple(video.shape[1:])
    dtype = video.dtype
    Y = video.reshape(T, -1).T  # (m, T): one column per frame (a view of the converted clip)
    mean = Y.mean(axis=1, dtype=np.float64)
    Y = Y - mean.astype(dtype)[:, None]  # the mean-free data matrix
    # step 1: the principal components; at most T - 1 (the mean-free columns sum to zero)
    n_max = min(T - 1, min(Y.shape)) if not is_auto(state_dim) else min(max(1, T // 4), min(Y.shape))
    s, U, V = _principal_components(Y, max(1, n_max))
    rank = int(np.count_nonzero(s > RANK_TOLERANCE * s[0])) if s[0] > 0 else 0
    s[rank:] = 0.0
    n = resolve_state_dim(state_dim, s, T, max(rank, 1))
    # step 2: C = U_n, X = S_n V_n^T (components beyond the rank are zero: X rows of 0)
    C = np.ascontiguousarray(U[:, :n])
    X = s[:n, None] * V[:, :n].T
    if rank < n:  # a state_dim beyond the clip's rank: the extra components are zero
        X[rank:] = 0.0
        C[:, rank:] = 0.0
    # steps 3 and 4: A and Q (then B with B B^T = Q)
    if estimator == "least-squares":
        A_fit, Q_factor, q_values = _least_squares(X)
    else:
        A_fit, Q_factor, q_values = _yule_walker(X)
    A, moved = stabilize(A_fit)
    q_rank = int(np.count_nonzero(q_values > 1e-10 * q_values[0])) if q_values.size and q_values[0] > 0 else 0
    n_v = q_rank if is_auto(noise_dim) else int(noise_dim)
    if n_v > n:
        raise ValueError(f"noise_dim must be at most state_dim ({n}), got {n_v}; pass noise_dim <= {n} or 'auto'")
    B = np.zeros((n, n_v))
    k = min(n_v, q_values.size)
    B[:, :k] = Q_factor[:, :k] * np.sqrt(q_values[:k])  # the n_v strongest directions of Q
    # step 5: R, the variance per value of the residual Y - C X
    total = np.einsum("ij,ij->i", Y, Y, dtype=np.float64) if Y.size else np.zeros(Y.shape[0])
    explained = (C.astype(np.float64) ** 2) @ (s[:n] ** 2)
    R = np.clip(total - explained, 0.0, None) / T
    return DynamicTexture(
        A=A, B=B, C=C.astype(dtype, copy=False), mean=mean.astype(dtype).reshape(frame_shape),
        R=R.astype(dtype).reshape(frame_shape), x0=X[:, 0].copy(), states=X, singular_values=s,
        eigenvalues=np.linalg.eigvals(A_fit), stabilized=moved, estimator=estimator, frame_shape=frame_shape,
        dtype=np.dtype(dtype))


def _least_squares(X):
    """The paper's steps 3 and 4: ``A = X_{2:T} X_{1:T-1}^+``, ``Q = hat V hat V^T / (T - 1)`` from the
    residuals ``hat V = X_{2:T} - A X_{1:T-1}``; ``Q``'s factor and values from the SVD of ``hat V``
    (``B = U_v S_v / sqrt(T - 1)``)."""
    past, future = X[:, :-1], X[:, 1:]
    A = future @ np.linalg.pinv(past)
    U, sv, _ = np.linalg.svd(future - A @ past, full_matrices=False)
    return A, U, sv**2 / (X.shape[1] - 1)


def _yule_walker(X):
    """The Yule-Walker estimate: ``A = S_1 S_0^-1``, ``Q = S_0 - A S_0 A^T`` with the clip's state
    covariance ``S_0 = X X^T / T`` (diagonal: ``S_n^2 / T``) and lag-1 covariance ``S_1 = X_{2:T}
    X_{1:T-1}^T / T``; ``Q``'s factor and values from its eigendecomposition (negative rounding
    clipped)."""
    n, T = X.shape
    variance = np.einsum("ij,ij->i", X, X) / T  # the diagonal of S_0
    lagged = X[:, 1:] @ X[:, :-1].T / T  # S_1
    safe = np.where(variance > 0, variance, 1.0)
    A = np.where(variance[None, :] > 0, lagged / safe[None, :], 0.0)  # S_1 S_0^-1, S_0 diagonal
    Q = np.diag(variance) - (A * variance[None, :]) @ A.T
    w, V = np.linalg.eigh((Q + Q.T) / 2)
    order = np.argsort(w)[::-1]
    return A, V[:, order], np.clip(w[order], 0.0, None)


# --------------------------------------------------------------------------
# Synthesis


def frames_per_block(n_frames, values, n):
    """Frames rendered at once: at least :data:`CHUNK_VALUES` values, and ``4 n`` frames so that ``C``
    (``n`` values per output value, read once per block) costs at most a quarter of the output's traffic,
    up to :data:`BLOCK_VALUES` values (which bound the temporaries)."""
    return max(1, min(n_frames, max(CHUNK_VALUES // values, min(4 * n, BLOCK_VALUES // values))))


def check_output_memory(n_frames, out_shape, dtype, mapped_modes=None, n=0):
    """Refuse ``n_frames`` frames of ``out_shape`` that cannot fit, before anything is allocated: the
    output, the temporaries of one block of frames (the noise ``w(t)`` in float64 and a mask) and, for a map
    (``mapped_modes``: ``n``), the modes, mean and deviation rendered at the output size."""
    values = math.prod(out_shape)
    block = frames_per_block(n_frames, values, max(n, mapped_modes or 0)) * float(values)
    need = float(n_frames) * values * np.dtype(dtype).itemsize + block * 9.0
    if mapped_modes is not None:
        need += float(values) * (mapped_modes + 2) * np.dtype(dtype).itemsize
    check_memory(need, tuple(out_shape[:2]), also={"n_frames": n_frames})


def run_states(A, B, x0, n_frames, gen):
    """``(n, n_frames)`` states: ``x(1) = x0``, ``x(t + 1) = A x(t) + B v(t)`` (eq. 1), ``v`` drawn at once."""
    n, n_v = B.shape
    v = gen.standard_normal((n_frames - 1, n_v)) if n_v else np.zeros((n_frames - 1, 0))
    drive = v @ B.T  # B v(t) for t = 1 .. n_frames - 1
    X = np.empty((n, n_frames))
    x = np.asarray(x0, np.float64)
    X[:, 0] = x
    for t in range(n_frames - 1):
        x = A @ x + drive[t]
        X[:, t + 1] = x
    return X


def _map_model(model, size, gen):
    """``C``, ``ybar`` and ``sqrt(R)`` rendered at the output size through one source-coordinate map
    (see the Notes of :func:`dynamic_texture`), and the info of the 2-D synthesis that made it.

    The map is synthesised once (patch-based sampling of the mean frame) and every mode (column of
    ``C``) goes through :func:`texsynth.apply_coordinates`: the map is linear in the image it renders,
    so ``map(C x) = map(C) x`` and every frame is rendered as if it went through the map itself."""
    from ..core.coordinates import apply_coordinates
    from ..patch import patch_sampling  # noqa: the video family's one use of another family (docs/architecture.md)

    _, info = patch_sampling(model.mean, size, rng=gen, return_info=True)  # the map, from the mean frame
    coordinates, weights = info.coordinates, info.weights
    if weights is None:
        coordinates, weights = coordinates[..., None, :], np.ones(coordinates.shape[:-1] + (1,))
    mean, deviation = apply_coordinates([model.mean, np.sqrt(model.R)], coordinates, weights)
    # the modes carry the motion about the mean frame: blended with Harrison's weights w / sqrt(sum w^2)
    # (patchwork's eq. 2), so a pixel of a boundary zone, which mixes clip pixels that move independently,
    # keeps their temporal variance instead of losing up to half of it to the plain average
    balanced = weights / np.sqrt(np.sum(np.square(weights), axis=-1, keepdims=True))
    modes = apply_coordinates(list(model.modes), coordinates, balanced) if model.state_dim else []
    flat = [np.asarray(r, model.dtype).reshape(-1) for r in [mean, deviation] + list(modes)]
    C = np.stack(flat[2:], axis=1) if model.state_dim else np.zeros((flat[0].size, 0), model.dtype)
    return C, flat[0], np.abs(flat[1]), info


def dynamic_texture(frames, n_frames, *, state_dim="auto", noise_dim="auto", estimator="yule-walker", size=None,
                    output_noise=False, rng=None, return_info=False, progress=False):
    """Learn a dynamic texture from a clip and synthesise frames (Doretto et al. 2003).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> t, c = np.arange(24)[:, None, None], np.arange(16)[None, None, :]
    >>> clip = 0.5 + 0.4 * np.sin(0.5 * c - 0.3 * t) * np.ones((1, 12, 1))  # a wave moving right
    >>> video, info = texsynth.dynamic_texture(clip, 100, rng=0, return_info=True)
    >>> video.shape, info.model.state_dim
    ((100, 12, 16), 2)

    Fits a linear dynamical system to the frames (:func:`learn_dynamic_texture`)
    and runs it with random input for any number of frames
    (:meth:`DynamicTexture.synthesize`). Suits clips of stationary,
    stochastic motion (water, steam, smoke, foliage in wind): the output
    has the clip's mean frame, principal components and their dynamics up
    to second order, and never repeats.

    Parameters
    ----------
    frames : array_like or str
        The clip, ``(T, H, W)`` or ``(T, H, W, C)`` with ``T >= 3``.
    n_frames : int
        Number of output frames, any.
    state_dim, noise_dim : int or "auto"
        ``n`` and ``n_v``; see :func:`learn_dynamic_texture`.
    estimator : {"yule-walker", "least-squares"}
        How ``A`` and ``Q`` are estimated: Yule-Walker (default), or the
        paper's least squares; see :func:`learn_dynamic_texture`.
    size : None, int or (int, int)
        Output frame size. None (default): the clip's. Another size (larger
        frames, typically): one source-coordinate map from the output frame
        into the clip's, synthesised once by patch-based sampling of the
        mean frame, renders every frame (see Notes).
    output_noise : bool
        Add the measurement noise ``w(t) ~ N(0, R)`` to every value
        (default False, as the paper's synthesis; see Notes).
    rng : None, int or numpy.random.Generator
        Random source; an int seed reproduces the output bit for bit.
    return_info : bool
        Also return a :class:`DynamicTextureInfo` (the model, the
        synthesised states, the map).
    progress : bool or callable
        Report progress per block of rendered frames.

    Returns
    -------
    video : numpy.ndarray
        ``(n_frames, height, width[, C])`` in [0, 1] (clipped), the clip's
        channel layout; float32 for a float32 clip, float64 otherwise.
    info : DynamicTextureInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        For fewer than 3 frames, a bad ``state_dim``, ``noise_dim``,
        ``estimator``, ``n_frames`` or ``size``, or an output (``n_frames`` frames of
        ``size``) that does not fit in memory: refused before anything is
        allocated.

    Notes
    -----
    Synthesis (the paper's "Matlab code" of the synthesis, as quoted): ``x(1)
    = x0``, the clip's first state, then

    .. math:: x(t+1) = A x(t) + B v(t), \\quad y(t) = C x(t) + \\bar y,
              \\quad v(t) \\sim N(0, I_{n_v}),

    so the first frame is the clip's first frame projected on the ``n``
    components. The quoted synthesis adds no measurement noise ``w(t)``:
    ``output_noise=False`` is the default; ``True`` adds ``w(t)``, white
    Gaussian noise with the variance ``R`` of each value (the clip's
    unexplained variance, mostly fine detail and pixel noise). Frames are
    clipped to [0, 1] (``info.clipped``: the fraction).

    **Larger frames.** The model's frame size is the clip's. For another
    ``size``, patch-based sampling (:func:`texsynth.patch_sampling`, its
    defaults: blocks a quarter of the clip's shorter side, boundary zones a
    sixth of a block) synthesises, once, an output-size image from the
    clip's mean frame and records where each output pixel came from: a
    source-coordinate map ``c_k(x)`` with convex weights ``w_k(x)`` (one
    source of weight 1 inside a patch, two to four in a boundary zone). Every
    frame is rendered through that one map, so the output is temporally
    coherent: each output pixel follows one clip pixel, or a fixed blend of
    a few. The mean frame ``ybar`` (and ``sqrt(R)``) go through the map as
    they are; the motion about it, the columns of ``C``, goes through it
    with the weights ``w_k / sqrt(sum_k w_k^2)`` (Harrison's
    variance-preserving blend, :func:`texsynth.patchwork`'s eq. 2, in
    :func:`texsynth.apply_coordinates`' rule ``sum_k w'_k I(c_k) + (1 -
    sum_k w'_k) mean(I)``): a plain average of two clip pixels that move
    independently would halve their temporal variance, and the boundary
    zones, a grid over the output, would look calmer than the patches. The
    map is linear, so the ``n`` columns of ``C`` are rendered once and
    frame ``t`` is ``map'(C) x(t) + map(ybar)``: the same as rendering
    ``C x(t)`` and ``ybar`` frame by frame, at the cost of ``n`` images
    instead of ``n_frames``. ``info.coordinates`` and ``info.weights`` are
    the map (the convex weights).

    References
    ----------
    .. [1] G. Doretto, A. Chiuso, Y. N. Wu and S. Soatto, "Dynamic
       textures", International Journal of Computer Vision 51(2), 2003,
       pp. 91-109. :doi:`10.1023/A:1021669406132`
    """
    N = check_positive_int(n_frames, "n_frames")
    out_size = None if size is None else as_size(size)
    check_bool(output_noise, "output_noise")
    as_rng(rng)  # type errors before the work; the generator itself is made once, below
    _check_dims(state_dim, noise_dim)
    check_choice(estimator, "estimator", ESTIMATORS)
    shape = getattr(frames, "shape", None)
    if shape is not None and len(shape) in (3, 4):  # the output's memory, before the clip is even converted
        frame = tuple(int(v) for v in shape[1:])
        out_shape = frame if out_size is None else out_size + frame[2:]
        dtype = np.float32 if getattr(frames, "dtype", None) == np.float32 else np.float64
        check_output_memory(N, out_shape, dtype, None if out_shape == frame else 0)
    model = learn_dynamic_texture(frames, state_dim=state_dim, noise_dim=noise_dim, estimator=estimator)
    return model.synthesize(N, size=size, output_noise=output_noise, rng=rng, return_info=return_info,
                            progress=progress)
