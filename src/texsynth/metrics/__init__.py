"""Quality metrics for synthesised textures, and the baselines that calibrate them.

A synthesis is judged against its exemplar on four axes of its neighbourhoods and values:

coherence (:func:`texture_energy`)
    How far each output neighbourhood is from its nearest exemplar
    neighbourhood: Kwatra et al. 2005, eq. 1, normalised per value. Low means
    every part of the output looks like some part of the exemplar.
completeness (:func:`completeness`)
    How far each exemplar neighbourhood is from its nearest output
    neighbourhood (the other half of the bidirectional similarity of Simakov
    et al. 2008). Low means the output shows everything the exemplar has.
copying (:func:`verbatim_copy`)
    The largest output region copied from the exemplar with one single
    offset, as a fraction of the exemplar's area. A tiled exemplar scores
    about 1; a good synthesis well below 0.5.
statistics (:func:`histogram_distance`, :func:`spectrum_distance`)
    Per-channel Wasserstein distance of the value histograms, and distance of
    the radially averaged log power spectra.

and on the exemplar's large-scale structure, on the luminance:

orientation (:func:`orientation_distance`)
    Degrees between the distributions of orientations (structure tensor,
    weighted by coherence) over the Gaussian pyramid down to its coarse
    levels: roots that stay vertical score near 0, roots turned diagonal far.
periodicity (:func:`lattice`, :func:`induced_lattice`, :func:`lattice_kept`)
    The peaks of the normalised autocorrelation: lattice vectors and their
    strength. An output must not repeat itself where the exemplar does not
    (a tiled exemplar does), and must keep a regular exemplar's lattice.
elements (:func:`element_integrity`)
    The connected components of a texton mask: whole as in the exemplar (1),
    or cut into fragments at seams (towards 0).

and, for clips, on how frames follow one another (:func:`temporal_correlation`, :func:`flicker`).

Raw numbers mean little on their own; :func:`baselines` makes three reference
images from the exemplar - histogram-matched white noise (worst coherence),
a random-block mosaic (what naive patch pasting gives) and the tiled exemplar
(best coherence, worst copying) - and :func:`texture_report` scores an output
against them. Each structure metric has a threshold (``ORIENTATION_THRESHOLD``, ...)
calibrated against the same baselines. ``docs/metrics.md`` holds the calibration
tables on real textures.
"""

from . import _patches, _structure, _video
from ._patches import (
    TextureReport,
    baselines,
    completeness,
    histogram_distance,
    mosaic_baseline,
    noise_baseline,
    spectrum_distance,
    texture_energy,
    texture_report,
    tiled_baseline,
    verbatim_copy,
    verdict_report,  # texsynth.testing's measurements; not in __all__
)
from ._structure import (
    ELEMENT_INTEGRITY_THRESHOLD,
    INDUCED_LATTICE_THRESHOLD,
    LATTICE_KEPT_THRESHOLD,
    LATTICE_STRENGTH,
    ORIENTATION_THRESHOLD,
    Lattice,
    correlation_length,
    dominant_orientation,
    element_integrity,
    induced_lattice,
    lattice,
    lattice_kept,
    orientation_distance,
)
from ._video import flicker, temporal_correlation

__all__ = _patches.__all__ + _structure.__all__ + _video.__all__
