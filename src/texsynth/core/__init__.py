"""The shared layer every algorithm family stands on.

=============================  ==========================================================
:mod:`texsynth.core.neighborhood`  patches of an image (valid / wrap / reflect), causal
                                   masks, fall-off weights, and their weighted average back
                                   into an image (the E-step of texture optimization)
:mod:`texsynth.core.pyramid`       Gaussian, Laplacian and steerable pyramids
:mod:`texsynth.core.search`        the one place a nearest neighbour is chosen:
                                   :class:`~texsynth.core.search.PatchIndex` and its backends
:mod:`texsynth.core.em`            the EM loop of patch-energy synthesis and its IRLS weights
:mod:`texsynth.core.flows`         flow fields and warping along them
:mod:`texsynth.core.tps`           thin-plate splines and TPS-RPM point matching
:mod:`texsynth.core.scale`         the exemplar's feature scale, which scale-aware defaults read
:mod:`texsynth.core.histogram`     histogram matching by exact quantile assignment
:mod:`texsynth.core.seams`         optimal seams: minimum-error boundary cuts (dynamic programming)
                                   and grid min-cuts with seam nodes
:mod:`texsynth.core.coordinates`   source-coordinate maps: other channels (normals, height)
                                   rendered through a synthesis
:mod:`texsynth.core.fields`        orientation and scale fields over an output, bilinear
                                   sampling in local frames and its adjoint (splatting)
:mod:`texsynth.core.convolve`      linear convolution by FFT (``scipy.signal.fftconvolve``'s
                                   values without importing ``scipy.signal``)
:mod:`texsynth.core.files`         atomic writes of files and folders (the one place a file is
                                   written)
:mod:`texsynth.core.color`         colour decorrelation: the principal axes of an image's colours
:mod:`texsynth.core.chunked`       outputs rendered block by block as lazy Dask arrays
:mod:`texsynth.core.textons`       texton masks, and two exemplars warped and blended into a
                                   progressively-variant sample (Zhang et al. 2003)
:mod:`texsynth.core.triangles`     the closest point of a triangle (meshes, shells)
:mod:`texsynth.core.btf`           BTF samples (images under many lights and views), the
                                   Leung-Malik filter bank, 3-D textons and their dot products
=============================  ==========================================================

The core imports no algorithm family; the families import the core (see
``docs/architecture.md``). Submodules load on first use.
"""

from ._lazy import attach

__getattr__, __dir__, __all__ = attach(__name__, ["neighborhood", "pyramid", "search", "em", "flows", "tps", "scale", "seams", "histogram", "coordinates", "fields", "convolve", "files", "color", "chunked", "textons", "triangles", "btf"])
