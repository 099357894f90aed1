"""Synthesis of a BTF on the plane through a texton map (Tong et al. 2002, the planar case).

Tong et al. [1]_ synthesise a bidirectional texture function (BTF: images of
one surface under many light and view directions) as a 2-D texture whose
pixels are *3-D textons* (Leung & Malik [2]_): vectors of filter responses
over every image at once. One synthesis places the sample's pixels in the
output, and every image of the BTF follows the same placement, so a stone
casts its own shadow in the output under every light. The steps:

1. the 3-D textons of the sample and their dot-product table
   (:func:`texsynth.core.btf.btf_textons`);
2. the sample as an image of texton coordinates, from the table by classical
   scaling (:func:`texsynth.core.btf.texton_image`): distances between
   neighbourhoods of textons are the paper's, computed from the table;
3. k-coherent synthesis (Ashikhmin 2001; Tong et al.'s k-coherence sets,
   :class:`texsynth.core.search.KCoherence`) of that texton image by
   :func:`~texsynth.synthesize_pixels` (``candidates="k-coherent"``), which
   records the sample pixel each output pixel came from;
4. every image of the BTF rendered through that source-coordinate map
   (:func:`texsynth.core.coordinates.apply_coordinates`).

The output is a :class:`~texsynth.core.btf.BTF` of the same directions; any
light between them is rendered by :func:`texsynth.core.btf.render_btf`.

What could not be checked: the paper was not at hand; this follows its
published description. Tong et al. synthesise on surfaces; the plane is the
same synthesis on a pixel grid. Their texton count and ``k`` could not be
checked (defaults 64 textons, ``k = 2``); the texton coordinates keep the 4
leading axes of the exact embedding (the pixel synthesis takes at most 4
channels), whose share of the distances is reported in
``info.texton_share``.

References
----------
.. [1] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
   "Synthesis of bidirectional texture functions on arbitrary surfaces",
   SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
.. [2] T. Leung and J. Malik, "Representing and recognizing the visual
   appearance of materials using three-dimensional textons", IJCV 43(1),
   2001, pp. 29-44. :doi:`10.1023/A:1011126920638`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np

from ..core._validate import as_rng, as_size, check_group, check_memory, check_positive_int
from ..core.btf import BTF, Textons, as_btf, texton_image
from ..core.coordinates import apply_coordinates
from ..core.search import Search
from ._wei_levoy import Neighborhood, synthesize_pixels

__all__ = ["synthesize_btf", "BTFSynthesisInfo"]


@dataclass
class BTFSynthesisInfo:
    """Extra results of :func:`synthesize_btf`.

    Attributes
    ----------
    textons : texsynth.core.btf.Textons
        The sample's textons (labels and dot-product table).
    texton_image : numpy.ndarray
        ``(h, w, 4)`` the sample as texton coordinates: the exemplar of the
        synthesis.
    texton_share : float
        The share of the textons' squared distances the 4 coordinates keep
        (1.0: the paper's distances exactly).
    coordinates : numpy.ndarray
        ``(H, W, 2)`` the sample pixel ``(row, col)``
        of every output pixel (``docs/conventions.md``).
    synthesis : PixelSynthesisInfo
        The info of the composed synthesis (:func:`~texsynth.synthesize_pixels`).
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of ``"textons"``, ``"synthesis"`` and ``"render"``.
    """

    textons: Textons | None = None
    texton_image: np.ndarray | None = None
    texton_share: float = 1.0
    coordinates: np.ndarray | None = None
    synthesis: object = None
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)


def synthesize_btf(
    btf,
    size,
    *,
    textons="auto",
    n_textons=64,
    neighborhood=Neighborhood(neighborhood_size=9, levels=3),
    search=Search(candidates="k-coherent", k=2),
    rng=None,
    progress=False,
    return_info=False,
):
    """Synthesise a BTF of any size from a sample, one placement for every light (Tong et al. 2002).

    Examples
    --------
    >>> import texsynth
    >>> from texsynth.pixel import synthesize_btf
    >>> sample = texsynth.data.btf("stones", 32, n_lights=8)
    >>> out = synthesize_btf(sample, 40, n_textons=8, neighborhood=texsynth.Neighborhood(levels=2), rng=0)
    >>> out.images.shape, bool(np.allclose(out.lights, sample.lights))
    ((8, 40, 40), True)

    The sample's 3-D textons are synthesised as one 2-D texture (module
    notes, steps 1-3), and every image of the sample is copied through the
    resulting source-coordinate map (step 4), so all lights share one
    arrangement of the sample's elements and their shadows.

    Parameters
    ----------
    btf : texsynth.core.btf.BTF
        The sample (e.g. :func:`texsynth.data.btf`).
    size : int or (int, int)
        Output ``(height, width)``.
    textons : Textons or "auto"
        The sample's textons, if made before; ``"auto"``: made here
        (:func:`texsynth.core.btf.btf_textons`).
    n_textons : int
        With ``textons="auto"``: how many (default 64).
    neighborhood : Neighborhood
        The multi-resolution neighbourhood (:class:`~texsynth.Neighborhood`;
        default 9 x 9 over 3 levels, for elements of about 10-20 pixels).
    search : Search
        The pixel synthesis's search (default ``candidates="k-coherent"``,
        ``k=2``: Tong et al.'s k-coherent search; the scanline order is the
        only one with k-coherent candidates).
    rng : None, int or numpy.random.Generator
        Seeds k-means and the synthesis. Same seed, same output.
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``.
    return_info : bool
        Also return a :class:`BTFSynthesisInfo`.

    Returns
    -------
    texsynth.core.btf.BTF
        ``(M, height, width)`` images with the sample's directions.
    info : BTFSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    TypeError, ValueError
        For a ``btf`` that is not a BTF, bad textons, size or options, or an
        output (``M`` images of ``size``) larger than the memory available.

    References
    ----------
    .. [1] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
       "Synthesis of bidirectional texture functions on arbitrary surfaces",
       SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
    """
    start = time.perf_counter()
    btf = as_btf(btf)
    size = as_size(size)
    check_positive_int(n_textons, "n_textons", minimum=2)
    check_group(neighborhood, Neighborhood, "neighborhood")
    check_group(search, Search, "search")
    check_memory(len(btf) * size[0] * size[1] * btf.images.itemsize * 2, size, "size", "the output BTF",
                 also={"btf images": len(btf)})
    rng = as_rng(rng)
    textons, image, share = texton_image(btf, textons, n_textons, rng=rng)
    stages = {"textons": time.perf_counter() - start}
    _, synthesis = synthesize_pixels(image, size, neighborhood=neighborhood, search=search, rng=rng,
                                     progress=progress, return_info=True)
    stages["synthesis"] = time.perf_counter() - start - stages["textons"]
    images = np.stack(apply_coordinates(list(btf.images), synthesis.coordinates))
    out = BTF(images, btf.lights, btf.views)
    stages["render"] = time.perf_counter() - start - stages["textons"] - stages["synthesis"]
    if not return_info:
        return out
    return out, BTFSynthesisInfo(textons, image, share, synthesis.coordinates, synthesis,
                                 time.perf_counter() - start, stages)
