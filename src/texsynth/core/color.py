"""Colour decorrelation: the principal axes of an image's colours, the one place they are computed.

Spectral and statistical methods treat the channels of a colour exemplar one by
one, which is right only where the channels are uncorrelated. So they rotate the
colours into their principal axes first (principal component analysis of the
``C x C`` colour covariance), work on each component alone, and rotate back:
Heeger-Bergen (Briand et al. 2014, sec. 3.3), Portilla-Simoncelli in colour
(Ruiters et al. 2010, sec. 4.5) and tiling and blending (Heitz & Neyret 2018,
sec. 1.3). :func:`color_pca` is that rotation.

A ``3 x 3`` eigen-decomposition costs microseconds; the covariance (one GEMM over
the pixels) is the whole cost. scikit-learn's ``PCA`` does the same job through an
SVD of every pixel and its validation: ``benchmarks/bench_packages.py`` measures
both (figures in ``docs/benchmarks.md``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["color_pca"]


def color_pca(pixels, *, canonical_signs=False):
    """Mean colour and principal colour axes of a set of pixels (largest variance first).

    Parameters
    ----------
    pixels : array_like, shape (N, C)
        Colours, one row per pixel (``image.reshape(-1, C)``), floating point. The covariance is
        computed in their dtype (float32 stays float32).
    canonical_signs : bool
        An eigenvector's sign is arbitrary: LAPACK builds may return either. True flips each axis
        so that its entry of largest magnitude is positive, so a basis (and statistics measured in
        it) does not depend on the LAPACK build; False (default) keeps LAPACK's signs.

    Returns
    -------
    mean : numpy.ndarray, shape (C,)
        The mean colour.
    basis : numpy.ndarray, shape (C, C)
        Orthonormal principal axes as columns, by decreasing variance:
        ``components = (pixels - mean) @ basis`` and ``pixels = components @ basis.T + mean``.

    Notes
    -----
    The eigenvectors of the biased covariance ``(x - m)^T (x - m) / N`` (Jolliffe, *Principal
    Component Analysis*, 2nd ed., 2002, sec. 1.1).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> grey = rng.random((500, 1))
    >>> pixels = np.hstack([grey, 0.5 * grey, 0.01 * rng.random((500, 1))])  # mostly one axis
    >>> mean, basis = color_pca(pixels, canonical_signs=True)
    >>> np.round(basis[:, 0], 3).tolist()
    [0.894, 0.447, 0.0]
    >>> bool(np.allclose(basis.T @ basis, np.eye(3)))
    True
    """
    mean = pixels.mean(axis=0)
    centred = pixels - mean
    _, basis = np.linalg.eigh(centred.T @ centred / max(len(pixels), 1))
    basis = basis[:, ::-1]  # principal component first
    if canonical_signs:
        signs = np.sign(basis[np.argmax(np.abs(basis), axis=0), np.arange(basis.shape[1])])
        basis = basis * np.where(signs == 0, 1.0, signs)
    return mean, basis
