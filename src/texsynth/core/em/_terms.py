"""The energy's terms besides eq. 1: penalties, completeness, confidence, histograms.

:class:`Occurrence` (Kaspar et al. 2015's occurrence penalty, and our copy limit), :class:`Completeness`
(the completeness half of Simakov et al. 2008's bidirectional similarity), :func:`confidence_weights`
(Wexler, Shechtman & Irani 2007's confidence under hard constraints), :func:`touching_free` (which
neighbourhoods hard constraints leave to the synthesis), :func:`histogram_groups` and
:func:`match_channel` (histogram matching after the E-step, after Kopf et al. 2007) and
:func:`robust_energy` (the robust eq. 1 plus the soft constraint, eq. 2).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ..convolve import fft_convolve
from ..histogram import match_to_targets, quantile_targets
from ..neighborhood import patches_within
from ..search import PatchIndex, nearest, patchmatch_features
from ._patches import distances_at, output_patches, patch_features, unwrap_centers

__all__ = ["Occurrence", "Completeness", "confidence_weights", "touching_free", "robust_energy", "nearest_label",
           "histogram_groups", "match_channel", "WEXLER_CONFIDENCE"]


# copy_limit: penalty per unit of excess (offset count / limit - 1), in units of the
# occurrence scale (exemplar variance x summed weights of a neighbourhood)
_COPY_PENALTY = 3.0


WEXLER_CONFIDENCE = 1.3


"""γ of Wexler, Shechtman & Irani 2007 (Sec. 3.2): a filled pixel's confidence is γ^-(its distance to the
known pixels); :func:`~texsynth.inpaint` and :func:`~texsynth.uncrop` use it."""


def confidence_weights(mask, centers, patch_size, mode, confidence):
    """Each neighbourhood's confidence under hard constraints (Wexler, Shechtman & Irani 2007, Sec. 3.2).

    The mean over its pixels of 1 where the pixel is known (``mask``, fractional where a coarse pixel
    is partly known) and ``γ^-d`` elsewhere, ``d`` the distance to the nearest known pixel: in the
    E-step the neighbourhoods that lie mostly on known pixels outweigh the others near the
    boundary, so the fill continues what is known rather than meeting it along a seam.
    """
    known = mask >= 0.5
    if not known.any():
        return None
    h, w_ = mask.shape
    if mode == "wrap":  # distances round the torus
        d = ndimage.distance_transform_edt(np.tile(~known, (3, 3)))[h : 2 * h, w_ : 2 * w_]
    else:
        d = ndimage.distance_transform_edt(~known)
    conf = np.maximum(np.maximum(mask, confidence**-d), 1e-100)  # floored: far inside a hole only the ratios matter
    mean = ndimage.uniform_filter(conf, size=patch_size, mode="wrap" if mode == "wrap" else "nearest")
    return np.maximum(mean[centers[:, 0], centers[:, 1]], 1e-100)  # a running sum can round below 0


def touching_free(mask, centers, patch_size, spacing, mode):
    """Which neighbourhoods at ``centers`` take part under hard constraints: those that hold a pixel not
    wholly constrained (``mask`` below 1), and the ring of grid neighbours one ``spacing`` further out.

    The others hold nothing but target pixels, which every E-step puts back whatever they vote, so they
    are neither searched nor averaged: the work follows the hole (or the border of an uncrop), not the
    image. The ring holds known pixels only, but PatchMatch propagates its matches into the
    neighbourhoods across the border: without it the uncrop seams of bark_1 rose from 1.93 to 2.26
    (``benchmarks/bench_completion.py``, two seeds; docs/methods/completion.md). A coarse pixel within
    1e-6 of 1 counts as constrained, as :func:`pyramids` rounds the exemplar's valid mask.
    """
    reach = patch_size + 2 * spacing  # the neighbourhood and the ring around it
    known = mask > 1 - 1e-6
    if mode == "wrap":  # neighbourhoods that cross the edge read the other side
        known = np.pad(known, ((0, reach - 1), (0, reach - 1)), mode="wrap")
        corner = (centers - reach // 2) % mask.shape
    else:  # beyond the output counts as constrained
        known = np.pad(known, spacing, constant_values=True)
        corner = centers - patch_size // 2
    return ~patches_within(known, reach)[corner[:, 0], corner[:, 1]]


class Occurrence:
    """Occurrence penalty (Kaspar et al. 2015) and copy limit of one stage's M-step.

    ``count[c]`` is the number of ``z_p`` with top-left corner ``c``. The
    occurrence of an exemplar pixel is the fall-off weight with which the
    ``z_p`` cover it, and the occurrence of a neighbourhood the fall-off
    weighted mean of its pixels' occurrences: ``o = count * A`` with ``A``
    the autocorrelation of the fall-off divided by its sum (one FFT
    convolution). ``ω`` is the occurrence every neighbourhood would have if
    the ``z_p`` were spread evenly over the exemplar; the penalty added to
    ``ρ`` of a candidate is ``weight * scale * o / ω``, with ``scale`` the
    exemplar's variance times the summed weights of a neighbourhood (the
    expected half-distance of two random neighbourhoods), so ``weight`` is
    free of units and image size.

    Copy limit: the *offset* of ``z_p`` is its exemplar corner minus its
    output corner; ``n(o)`` centres sharing one offset are a region copied
    verbatim. With ``limit`` = ``copy_limit`` x exemplar area / spacing² (the
    number of grid centres of a copied region covering that fraction of the
    exemplar), a candidate whose offset is shared by ``n > limit`` centres
    pays ``_COPY_PENALTY * scale * (n / limit - 1)``: the penalty grows with
    the excess, so the members with the closest alternatives (at the region's
    rim) leave first and the region shrinks from its edges.
    """

    def __init__(self, exemplar, centers, occurrence_weight, copy_limit):
        n = len(centers)
        g = exemplar.g / exemplar.g.sum()
        self.kernel = fft_convolve(exemplar.g, g[::-1, ::-1])  # correlation, (2w-1, 2w-1), A(0) = sum g^2 / sum g
        self.self_weight = float(self.kernel[exemplar.size - 1, exemplar.size - 1])
        self.shape = exemplar.view.shape[:2]
        omega = n * float(exemplar.g.sum()) / len(exemplar)
        own = exemplar.original  # the exemplar itself (not its augmented copies): its variance, its area
        variance = float(own.reshape(-1, own.shape[-1]).var(axis=0).mean())
        self.factor = occurrence_weight * variance * float(exemplar.weights.sum()) / omega
        self.penalty = np.zeros(len(exemplar))
        self.own = 0.0
        self.offsets = None
        self.centers = centers
        self.span = int(max(exemplar.image.shape[:2]) + centers.max() + exemplar.size + 2)
        spacing = max(1, int(np.diff(np.unique(centers[:, 1]))[:1].max(initial=1)))
        self.copy_limit = None
        if copy_limit is not None:  # the limit as a number of grid centres sharing one offset
            self.copy_limit = max(1.0, copy_limit * own.shape[0] * own.shape[1] / spacing**2)
        self.copy_factor = _COPY_PENALTY * variance * float(exemplar.weights.sum())

    def update(self, exemplar, matches):
        count = np.zeros(self.shape)
        np.add.at(count, (exemplar.corner[matches, 0], exemplar.corner[matches, 1]), 1.0)
        occ = fft_convolve(count, self.kernel, mode="same")
        self.penalty = self.factor * np.maximum(occ[exemplar.corner[:, 0], exemplar.corner[:, 1]], 0.0)
        self.own = self.factor * self.self_weight  # a z_p's own share of its occurrence
        self.offsets = None
        if self.copy_limit is not None:
            key = self.offset_key(exemplar, matches, self.centers)
            offsets, counts = np.unique(key, return_counts=True)
            over = counts > self.copy_limit  # only the offsets over the limit pay: the others' penalty is 0
            if over.any():
                self.offsets = offsets[over]
                self.excess = self.copy_factor * (counts[over] / self.copy_limit - 1.0)

    @property
    def binding(self):
        """Whether any candidate can pay: an occurrence penalty, or an offset over the copy limit."""
        return self.factor > 0 or self.offsets is not None

    def offset_key(self, exemplar, cand, at):
        """One integer per (exemplar neighbourhood ``cand``, output centre ``at``) pair: its offset."""
        off = exemplar.corner[cand] - (at - exemplar.size // 2) + self.span
        return off[:, 0] * (4 * self.span) + off[:, 1]

    def copy_penalty(self, exemplar, cand, at):
        """The copy limit's penalty of taking neighbourhoods ``cand`` at output centres ``at``."""
        if self.offsets is None:
            return 0.0
        key = self.offset_key(exemplar, cand, at)
        k = np.clip(np.searchsorted(self.offsets, key), 0, len(self.offsets) - 1)
        return np.where(self.offsets[k] == key, self.excess[k], 0.0)


class Completeness:
    """The completeness term of the bidirectional similarity (Simakov et al. 2008) for one stage.

    Every exemplar neighbourhood ``q_j`` whose corner lies on a grid of the
    stage's spacing (of the exemplar itself, not of its augmented copies) is matched to its nearest output neighbourhood ``x_p(j)``;
    the term is ``scale * sum_j (||x_p(j) - q_j||^2 + ε²)^(r/2)`` with
    ``scale = weight * |X†| / |J|``, so that ``weight = 1`` gives the two
    directions equal weight per neighbourhood, as in Simakov et al.'s
    ``d = d_complete / N_S + d_cohere / N_T`` multiplied by ``N_T``.
    In the E-step ``q_j`` is one more neighbourhood averaged at the centre
    ``p(j)`` (their update rule: every pixel the weighted mean of the colours
    the coherence and the completeness votes give it).

    With the PatchMatch M-step, ``p(j)`` is any output neighbourhood (found
    by PatchMatch from the exemplar to the output, warm-started from the last
    ``p(j)``); with an index M-step it is one of the grid centres ``X†``.
    """

    def __init__(self, exemplar, centers, completeness_weight, spacing):
        # with augmented copies (an atlas) only the exemplar's own neighbourhoods must appear: the copies are
        # more candidates, not more content the output owes
        on_grid = (exemplar.corner[:, 0] % spacing == 0) & (exemplar.corner[:, 1] % spacing == 0) & exemplar.own
        self.jidx = np.flatnonzero(on_grid)
        self.scale = completeness_weight * len(centers) / max(1, len(self.jidx))

    def search(self, exemplar, x, centers, mode, current, method, rng, warp=None):
        """``p(j)`` (output centres) of every ``q_j`` among ``centers``, never farther than ``current``, and
        ``ρ_j``."""
        feats = patch_features(exemplar.patches(self.jidx), exemplar.mu).astype(np.float64, copy=False)
        q = patch_features(output_patches(x, centers, exemplar.size, mode, warp), exemplar.mu)
        index = PatchIndex(q.astype(np.float32), weights=exemplar.weights, method=method, rng=rng)
        found = centers[index.query(feats.astype(np.float32), k=1)[0][:, 0]]
        rho = distances_at(exemplar, x, found, mode, self.jidx, warp)
        if current is not None:
            keep = distances_at(exemplar, x, current, mode, self.jidx, warp)
            better = rho < keep
            found = np.where(better[:, None], found, current)
            rho = np.where(better, rho, keep)
        return found, rho

    def search_field(self, exemplar, x, mode, current, iterations, rng):
        """The same by PatchMatch over every output neighbourhood (wrapping around a tileable output)."""
        w = exemplar.size
        pad = w - 1 if mode == "wrap" else 0
        image = np.pad(x, ((0, pad), (0, pad), (0, 0)), mode="wrap") if pad else x
        start = None if current is None else unwrap_centers(current, x.shape[:2], w, pad)[:, None]
        # float (H, W, C) arrays: x may overshoot [0, 1] a little, and has guide channels when guided
        field, d2, _ = patchmatch_features(exemplar.image, image, w, centers=exemplar.centers(self.jidx), init=start,
                                        iterations=iterations, exemplar_mask=None, pixel_weights=exemplar.g,
                                        mode="valid", penalty=None, rng=rng)
        found = field[:, 0]
        if pad:
            found = np.mod(found, x.shape[:2])
        return found, d2[:, 0].astype(np.float64)


def robust_energy(rho, r, eps2, x, constraint):
    """E = sum_p (ρ_p + ε²)^{r/2} + λ E_c(x): the robust eq. 1 plus eq. 2."""
    e = float(np.sum((rho + eps2) ** (r / 2.0)))
    if constraint is not None and np.isfinite(constraint[2]):  # hard constraints hold by construction
        m, t, lam = constraint
        e += lam * float(np.einsum("ij,ijc->", m, (x - t) ** 2))
    return e


def nearest_label(guide, labels):
    """``(H, W)`` index of the label vector nearest to every pixel's guide channels ``(H, W, G)`` (the search
    layer's exact search: ties go to the lowest index)."""
    index, _ = nearest(labels, guide.reshape(-1, guide.shape[-1]), method="exact")
    return index[:, 0].reshape(guide.shape[:-1])


def histogram_groups(exemplar, n_colours, free, shape, guide=None, labels=None):
    """What histogram matching matches after every E-step: ``(where, targets)`` pairs.

    ``where`` selects output pixels (None: all of them) and ``targets`` holds, per colour channel, the
    sorted values they get (exact quantile assignment, :mod:`texsynth.core.histogram`). Without labels:
    one pair, the pixels ``free`` of constraints (None: every pixel) against every exemplar pixel that
    may be copied. With label guides (``labels``, the label vectors scaled as the guide channels): one
    pair per label, its output pixels against the exemplar pixels of the same label, each pixel's label
    being the label vector nearest to its guide channels at this level (the pyramid blurs them); a
    label the exemplar level does not show takes every exemplar pixel. Matching every output pixel to the
    whole exemplar would shift the colours wherever the output's labels cover other proportions than
    the exemplar's. The guide channels are given, not matched.
    """
    allowed = exemplar.valid > 0.5
    parts = [(free, allowed)]
    if labels is not None:
        out_label, ex_label = nearest_label(guide, labels), nearest_label(exemplar.image[..., n_colours:], labels)
        parts = []
        for label in range(len(labels)):
            where = out_label == label if free is None else (out_label == label) & free
            own = allowed & (ex_label == label)
            parts.append((where, own if own.any() else allowed))
    groups = []
    for where, source in parts:
        count = shape[0] * shape[1] if where is None else int(where.sum())
        if count:
            pixels = exemplar.image[source]  # (pixels, C)
            groups.append((where, [quantile_targets(np.sort(pixels[:, c]), count).astype(exemplar.image.dtype)
                                   for c in range(n_colours)]))
    return groups


def match_channel(image, channel, where, targets):
    """Give channel ``c`` of ``image`` (at ``where``, or everywhere if None) the histogram ``targets``, in place."""
    if where is None:
        image[..., channel] = match_to_targets(image[..., channel], targets, False)[0]
    else:
        image[..., channel][where] = match_to_targets(image[..., channel][where], targets, False)[0]
