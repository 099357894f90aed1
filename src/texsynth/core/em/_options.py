"""The option groups of the methods built on the EM parts: a schedule, the energy's terms, constraints, guides, fields.

Each group is a frozen dataclass passed as one option (``schedule=Schedule(levels=1)``); its fields keep
the names the command line shows as flags (``--levels``). ``"auto"`` means "chosen by the method's
preset". :class:`texsynth.core.search.Search` is the search's group.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Schedule", "Terms", "Constraints", "Guides", "Fields", "Animation"]


@dataclass(frozen=True)
class Schedule:
    """Coarse to fine and when to stop: the stages of an EM synthesis (Kwatra et al. 2005, Section 3.2).

    Examples
    --------
    >>> import texsynth
    >>> texsynth.Schedule(neighborhood_sizes=(16, 8), levels=2)
    Schedule(neighborhood_sizes=(16, 8), levels=2, relative_grid_spacing=0.25, max_iterations=5, tolerance='auto')

    Parameters
    ----------
    neighborhood_sizes : sequence of int or "auto"
        Neighbourhood widths ``w``, used largest first at every level; at
        each level only the sizes that fit the sub-sampled exemplar are used
        (see Notes). ``"auto"``: preset ``"default"`` chooses them from
        the exemplar's feature scale (:func:`~texsynth.optimize_texture`,
        Notes), ``"paper"`` takes ``(32, 16, 8)``.
    levels : int or "auto"
        Resolution levels; 1 synthesises at full resolution only. ``"auto"``:
        as many as keep the coarsest exemplar 32 pixels or more (preset
        ``"default"``), 3 (``"paper"``).
    relative_grid_spacing : float
        Spacing of the neighbourhood centres as a fraction of the
        neighbourhood width (default 1/4). The paper's centres ``X†`` are
        "w/4 pixels apart".
    max_iterations : int
        EM iterations per (level, size) stage at most; a stage also stops when
        the matched exemplar neighbourhoods no longer change. They are the
        paper's ``{z_p}``; default 5 ("usually 3-5 iterations per
        resolution/scale level were found to be enough", Section 5).
    tolerance : float or "auto"
        A stage also stops when one iteration lowers the energy by less than
        this fraction (an addition to the paper's test, which rarely fires
        with thousands of neighbourhoods). 0 keeps only the paper's
        criterion. Not used with ``occurrence_weight > 0`` or
        ``copy_limit``, whose penalties raise the energy on purpose.
        ``"auto"``: 5e-3 (preset ``"default"``), 0 (``"paper"``).

    Notes
    -----

    Neighbourhood sizes per level: at full resolution every size not larger
    than the exemplar is used; at a level sub-sampled ``2^l`` times only
    sizes up to half the sub-sampled exemplar's smaller side, so the coarse
    search has a choice of neighbourhoods (a 128-pixel exemplar gives
    (16, 8) at 1/4, (32, 16, 8) at 1/2 and at full resolution).
    """

    neighborhood_sizes: object = "auto"
    levels: object = "auto"
    relative_grid_spacing: float = 0.25
    max_iterations: int = 5
    tolerance: object = "auto"


@dataclass(frozen=True)
class Terms:
    """The terms of the energy an EM synthesis minimises, besides constraints and guides.

    Examples
    --------
    >>> import texsynth
    >>> terms = texsynth.Terms(gradient_weight=10.0)  # the paper's gradient term
    >>> terms.irls_exponent
    0.8

    Parameters
    ----------
    irls_exponent : float
        Exponent of the robust energy, in (0, 2]; default 0.8 (Section 3.1).
        It is ``r`` of ``||x_p - z_p||^r``; ``r = 2`` is the plain
        least-squares eq. 1.
    gradient_weight : float
        Weight of the gradient energy, which matches the exemplar's gradients
        too (Section 3). It is ``μ`` of ``μ sum_p ||D x_p - D z_p||^2``.
        Default 0 (off): the paper's Algorithm 1, its robust
        optimisation and its results are stated for the colour energy (1);
        the gradient term is offered as a generalisation ("we can
        generalize...") with ``μ = 10`` "in our experiments". Pass 10 to use
        it; the E-step then solves a Poisson-like linear system.
    falloff : bool
        Weight each neighbourhood's pixels by a Gaussian fall-off (σ = w/4)
        in both steps (Section 3.1). Default True.
    occurrence_weight : float
        Weight of the occurrence penalty of Kaspar et al. 2015 [1]_, ``>= 0``:
        it favours exemplar parts the output uses little. It is ``λ_occ``:
        the M-step ranks candidates by
        ``ρ_p + λ_occ · scale · o(z) / ω``, where ``o(z)`` is how much the
        current ``z_p`` already cover the exemplar pixels of ``z`` (fall-off
        weighted), ``ω`` the value of an even use of the whole exemplar and
        ``scale`` the exemplar's variance times the summed weights of a
        neighbourhood; the kd-tree's 4 nearest and the 4 coherent candidates
        (the grid neighbours' ``z`` shifted) compete. It spreads the output
        over more of the exemplar (completeness) but does not limit verbatim
        copies. Default 0 (off, the paper's M-step). With
        ``occurrence_weight > 0`` or ``copy_limit``, the energy is no longer
        guaranteed to fall within a stage (the M-step minimises another
        criterion), and a stage ends only by the paper's test or
        ``max_iterations``.
    copy_limit : float in (0, 1], None or "auto"
        Largest verbatim copy, as a fraction of the exemplar's area. A
        penalty grows on every exemplar offset (exemplar position minus
        output position of ``z_p``) shared by more neighbourhood centres than
        a copied region covering ``copy_limit`` of the exemplar's area has
        (see Notes). None: off (the
        paper's M-step). Paired with ``completeness_weight`` it also
        withholds the completeness votes of over-limit offsets. ``"auto"``:
        0.25 (preset ``"default"``; when the finest level has no
        completeness term, 0.3 there, as it refines the coarser levels'
        arrangement: only outlying copies are cut there, not elements), None
        (``"paper"``).
    completeness_weight : float or "auto"
        Weight of completeness, ``>= 0``: how strongly every part of the
        exemplar must appear in the output. It is ``λ_b`` of the completeness
        half of the bidirectional similarity of Simakov et al. 2008 [2]_,
        added to the energy: every exemplar
        neighbourhood ``q_j`` on the ``w/4`` grid must appear somewhere in
        the output, ``λ_b (|X†| / |J|) sum_j ||x_p(j) - q_j||^r`` with
        ``x_p(j)`` its nearest output neighbourhood on ``X†``. The M-step
        also finds ``p(j)``, and the E-step averages ``q_j`` at ``p(j)``
        with the ``z_p`` (Simakov et al.'s update rule); 1 weighs both
        directions equally per neighbourhood; 0 is off (the paper's eq. 1).
        Alone it makes the output contain the whole exemplar
        verbatim, so use it with ``copy_limit``: ``completeness_weight=1,
        copy_limit=0.2`` brings all of the exemplar without large copies, at
        about twice the time (docs/methods/kwatra.md measures it).
        Without ``copy_limit`` the energy never rises within a stage, as for
        eq. 1. ``"auto"``: 1 (preset ``"default"``), on every level when
        the output has less than 4 times the exemplar's area and on every
        level but the finest from there on (the coarse levels choose which
        parts of the exemplar appear; on the finest level the votes would
        blur large flat areas); 0 (``"paper"``). An explicit value holds on
        every level. :attr:`StageInfo.completeness_weight` gives the weight
        each stage used.
    histogram_matching : bool or "auto"
        After every E-step, give each colour channel of the output the
        exemplar's histogram (exact quantile assignment,
        :mod:`texsynth.core.histogram`): a simple form of the histogram
        matching Kopf et al. 2007 [3]_ build into texture optimization (they
        re-weight the neighbourhoods' votes; here the output is remapped,
        which we could not compare with theirs). The E-step averages overlapping
        neighbourhoods, the average matches the exemplar's flattest ones
        best, and at large enlargements the output can wash out into one
        flat region; restoring the histogram breaks that loop. Not applied
        with soft constraints (``target``); with hard ones
        (``constraint_weight=inf``) only the unconstrained pixels are
        matched. With label guides (``exemplar_guide``/``output_guide`` of
        at most 32 distinct values, every output value also in the
        exemplar's) each output label region is matched to the exemplar
        pixels of the same label, so regions covering other proportions
        than in the exemplar keep their own colours; other guides: the
        whole exemplar. The energy may then rise within a stage.
        ``"auto"``: True (preset ``"default"``), False (``"paper"``).

    Notes
    -----

    Copy limit: with ``copy_limit = c``, an exemplar offset shared by ``n``
    centres of the ``w/4`` grid costs every candidate that uses it
    ``3 · scale · max(0, n / n_c - 1)`` with ``n_c = c · h · w / spacing²``
    (the centres of a copied region covering ``c`` of the ``h x w``
    exemplar) and ``scale`` as for ``occurrence_weight``: the penalty grows
    with the excess, so a region sheds first the neighbourhoods with the
    closest alternatives, at its rim. This is our addition, not in the
    papers: eq. 1 rewards copies (a verbatim copy has zero energy), and the
    occurrence penalty does not limit them either (a region copied once uses
    its exemplar pixels less than an even spread of a larger output does).

    References
    ----------
    .. [1] A. Kaspar, B. Neubert, D. Lischinski, M. Pauly and J. Kopf, "Self
       tuning texture optimization", Computer Graphics Forum (Eurographics
       2015) 34(2), pp. 349-359. :doi:`10.1111/cgf.12565`
    .. [2] D. Simakov, Y. Caspi, E. Shechtman and M. Irani, "Summarizing visual
       data using bidirectional similarity", CVPR 2008.
       :doi:`10.1109/CVPR.2008.4587842`
    .. [3] J. Kopf, C.-W. Fu, D. Cohen-Or, O. Deussen, D. Lischinski and
       T.-T. Wong, "Solid texture synthesis from 2D exemplars", ACM
       Transactions on Graphics (SIGGRAPH 2007) 26(3).
       :doi:`10.1145/1276377.1276380`
    """

    irls_exponent: float = 0.8
    gradient_weight: float = 0.0
    falloff: bool = True
    occurrence_weight: float = 0.0
    copy_limit: object = "auto"
    completeness_weight: object = "auto"
    histogram_matching: object = "auto"


@dataclass(frozen=True, eq=False)
class Constraints:
    """Soft or hard constraints on the output (Kwatra et al. 2005, eq. 2) and the exemplar pixels that may be copied.

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> hole = np.zeros((64, 64), bool); hole[24:40, 24:40] = True
    >>> keep = texsynth.Constraints(mask=~hole, target=np.zeros((64, 64, 3)), constraint_weight=float("inf"))
    >>> keep.confidence is None
    True

    Parameters
    ----------
    mask : array_like, optional
        Which output pixels are held to ``target``: ``(H, W)`` bool (white,
        True = held), or weights in [0, 1] (soft masks). The paper's ``C``
        of eq. 2; requires ``target``.
    target : array_like, optional
        The wanted output: an image of the output's size. Alone (no mask)
        it constrains every pixel; the paper's ``x^c``.
    constraint_weight : float
        How strongly the output keeps ``target``, ``>= 0`` (default 1;
        ``float("inf")``: exactly). It is ``λ``, the weight of ``E_c``
        against the texture energy. With the default sizes and ``r``, the texture term weighs a pixel
        by roughly 1-10, so λ = 1 is a gentle pull and λ = 100 nearly hard.
        ``float("inf")``: hard constraints, the limit λ → ∞ (as in Wexler
        et al.'s and PatchMatch's hole filling): every E-step sets the
        masked pixels to ``target`` (blended by the mask where a coarse
        pixel is partly masked), so each ``x_p`` already holds them and the
        M-step is the plain nearest-neighbour search (PatchMatch on large
        stages, not Algorithm 2's index query of every constrained
        neighbourhood): how :func:`texsynth.inpaint` and
        :func:`texsynth.uncrop` fill large images. Only the neighbourhoods
        that touch an unconstrained pixel, and the ring one grid step around
        them (whose matches PatchMatch propagates across the border), are
        searched and averaged: the others vote only for pixels the E-step
        puts back, so the work follows the free pixels, not the output. The
        source-coordinate map of a pixel no such neighbourhood covers
        continues that of the nearest covered pixel.
    confidence : None or float
        With hard constraints, weigh the fill's neighbourhoods by their
        distance to the known pixels (Wexler et al.: 1.3). It is Wexler,
        Shechtman & Irani's confidence base ``γ`` (their value: 1.3,
        :data:`WEXLER_CONFIDENCE`), used with
        ``constraint_weight=float("inf")``. A filled pixel at distance ``d`` from the
        nearest known pixel has confidence ``γ^-d`` (a known pixel 1), and in
        the E-step each neighbourhood weighs by the mean confidence of its
        pixels, so near the boundary the neighbourhoods lying on known pixels
        decide and the fill continues them (2007, Sec. 3.2; TPAMI
        doi:10.1109/TPAMI.2007.60). Default None: all neighbourhoods alike,
        as in Kwatra et al. :func:`~texsynth.inpaint` and
        :func:`~texsynth.uncrop` use 1.3; :func:`~texsynth.make_tileable`
        does not, since there the two sides of its band meet in the middle,
        and the confidence made that meeting a seam (measured in
        ``docs/methods/completion.md``).
    exemplar_mask : array_like, optional
        Exemplar pixels that may be copied: ``(h, w)`` bool (white, True =
        may be copied). Neighbourhoods
        touching a False pixel are never used (e.g. the hole when the
        exemplar is the image being filled).
    """

    mask: object = None
    target: object = None
    constraint_weight: float = 1.0
    confidence: object = None
    exemplar_mask: object = None


@dataclass(frozen=True, eq=False)
class Guides:
    """Guide maps of the exemplar and the output: guided synthesis, "texture by numbers".

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> labels = texsynth.Guides(np.zeros((32, 32)), np.ones((48, 48)), guide_weight=4.0)
    >>> labels.guide_weight
    4.0

    Parameters
    ----------
    exemplar_guide, output_guide : array_like, optional
        Guided synthesis ("texture by numbers", Hertzmann et al. 2001 [1]_):
        ``(h, w)`` or ``(h, w, G)`` guide maps of the exemplar and ``(H, W)``
        or ``(H, W, G)`` of the output (the same ``G``), values in [0, 1]
        (any accepted dtype), e.g. a label map painted over each. Both or
        neither. The guides become ``G`` extra channels of the exemplar and
        of the output, multiplied by ``sqrt(guide_weight)``, so every
        neighbourhood distance (M-step, energy) compares the guides too;
        their Gaussian pyramids are built like the images'. The output's
        guide channels are given, not synthesised: every E-step (and each
        stage's start, after up-sampling) resets them to ``output_guide``;
        histogram matching leaves them out; they are stripped from the
        result.
    guide_weight : float
        Weight of the guide channels against the colours, ``>= 0`` (default
        1): a guide difference of 1 costs as much as a colour difference of
        ``sqrt(guide_weight)`` in one channel, in the colours' [0, 1] units.
        0 ignores the guides (the unguided result, bit for bit).

    Notes
    -----
    Not checked against Hertzmann et al.'s paper [1]_ (it is not in our
    papers folder): its texture by numbers matches neighbourhoods of the
    label images A, B together with those of A' (its own weights and
    search); here the labels are extra channels of Kwatra's neighbourhood
    distance, with our ``guide_weight``, and we could not compare results
    with the paper's figures.

    References
    ----------
    .. [1] A. Hertzmann, C. E. Jacobs, N. Oliver, B. Curless and D. H. Salesin,
       "Image analogies", SIGGRAPH 2001, pp. 327-340.
       :doi:`10.1145/383259.383295`
    """

    exemplar_guide: object = None
    output_guide: object = None
    guide_weight: float = 1.0


@dataclass(frozen=True, eq=False)
class Fields:
    """Orientation and magnification fields over the output: the texture turned and magnified locally.

    Examples
    --------
    >>> import texsynth
    >>> fields = texsynth.Fields(orientation=0.5)  # turned by 0.5 rad everywhere
    >>> fields.magnification is None
    True

    Parameters
    ----------
    orientation : None, float, array_like or callable
        The angle in radians, counter-clockwise as the image is shown, by
        which the texture is turned at each output pixel (the field
        ``theta``, as in :func:`~texsynth.synthesize_controlled`): a number, an
        ``(H, W)`` array, or a callable ``orientation(rows, cols)`` of float
        arrays of output pixel coordinates. None (default): not turned, and
        the synthesis is exactly the one without fields.
    magnification : None, float, array_like or callable
        How much larger the texture's elements appear at each output pixel
        (2: twice as large; the output's size is ``size``, not this): the
        field ``S``, same forms; finite, in [0.001, 1000].
        With either field every output neighbourhood ``x_p`` is sampled on
        a grid turned and scaled around its centre (see Notes); the M-step
        then uses the index (PatchMatch compares unrotated patches), and
        ``gradient_weight > 0`` and soft constraints are refused. Fields
        wrap with ``tileable=True``.

    Notes
    -----

    Orientation and magnification fields (Kwatra et al. have none; this
    follows the local frames of Zhang et al. 2003 [1]_ and the lecture's
    "Synthesis with Local Size/Vector Field Control"): the neighbourhood of centre ``p`` is
    the output sampled bilinearly at ``p + A(p) d``, ``A = S R(theta)``, for
    the offsets ``d`` of a ``w x w`` patch (M-step: compared with the
    exemplar's plain neighbourhoods, fall-off ``g(d)``), and the E-step adds
    every value ``z_p(d)`` back at ``p + A(p) d`` with the same bilinear
    weights times ``ω_p g(d)`` (the adjoint of the sampling,
    :func:`texsynth.core.fields.splat`), normalised by the summed weights.
    That average is not the exact least-squares solution of the bilinear
    sampling (it is where ``A`` is a whole-pixel shift), so the guarantee
    that ``E`` never rises within a stage does not hold with fields. The
    fields are read at each level at the output pixels it samples; the
    coherent candidates of the copy limit follow the frames (the grid
    neighbour's ``z`` shifted by ``A^{-1} e``), while the copy limit's
    offsets stay unrotated, so it rarely fires where the field turns.

    References
    ----------
    .. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
       progressively-variant textures on arbitrary surfaces", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 295-302. :doi:`10.1145/882262.882344` (not at
       hand; its orientation and scale control as summarised in
       :func:`~texsynth.synthesize_controlled`).
    """

    orientation: object = None
    magnification: object = None


@dataclass(frozen=True)
class Animation:
    """How :func:`animate_texture` synthesises frames 2..L (Kwatra et al. 2005, Section 4.1).

    Examples
    --------
    >>> import texsynth
    >>> animation = texsynth.Animation(constraint_weight=5.0, max_frame_iterations=1)
    >>> animation.frame_sizes
    'auto'

    Parameters
    ----------
    frame_sizes : sequence of int or "auto"
        Neighbourhood sizes of the single-resolution synthesis of frames
        2..L; ``"auto"`` (default): the last two of the schedule's
        ``neighborhood_sizes`` (16, 8): the warped frame is already a good
        texture, so the large size, which rearranges whole elements, is not
        needed to repair it.
    max_frame_iterations : int
        EM iterations per size for frames 2..L at most (default 3); a size
        also stops when the matches no longer change or the energy falls by
        less than the schedule's ``tolerance``. The matches are the paper's
        ``{z_p}``.
    constraint_weight : float
        How strongly a frame keeps the warped previous frame (default 3).
        It is ``λ`` of the flow term; the paper gives no value, and λ = 1
        lets the texture wash out into flat regions (docs/methods/kwatra.md).
    warp_order : int
        Spline order of the warp (default 3, cubic): a bilinear warp blurs a
        little at every frame and the blur accumulates over the sequence.
    frame_falloff : float or None
        Width of the fall-off with which frames 2..L average overlapping
        neighbourhoods, in grid spacings (default 0.25). It is ``σ`` of the
        Gaussian with which the E-step averages the overlapping ``z_p``, in
        units of the grid spacing ``w/4``. Default 0.25: each pixel comes mostly from the ``z_p``
        centred nearest to it, so neighbourhoods that disagree by a pixel
        (inevitable when the texture moves by fractions of a pixel) are not
        averaged into blur. ``None`` uses the M-step's fall-off (σ = w/4),
        the plain Algorithm 2, with which the frames wash out into flat
        smeared regions; the paper gives no σ.
    """

    frame_sizes: object = "auto"
    max_frame_iterations: int = 3
    constraint_weight: float = 3.0
    warp_order: int = 3
    frame_falloff: object = 0.25
