"""Statistical (parametric) synthesis: impose the exemplar's statistics on noise.

- :func:`heeger_bergen`: Heeger & Bergen 1995, steerable-pyramid histograms.
- :func:`portilla_simoncelli`: Portilla & Simoncelli 2000, joint wavelet
  statistics (:func:`ps_statistics`, :func:`ps_step` and
  :func:`interpolate_statistics` for methods that use them).
- :func:`random_phase_noise`: Galerne, Gousseau & Morel 2011, random phase
  noise and asymptotic discrete spot noise (micro-textures in one FFT).
- :func:`tile_and_blend`, :func:`tile_and_blend_at`: Heitz & Neyret 2018,
  infinite by-example noise by tiling and histogram-preserving blending.
"""

from ._heeger_bergen import PERIODIC_EXEMPLAR, HeegerBergenInfo, heeger_bergen, match_histogram
from ._portilla_simoncelli import PSInfo, portilla_simoncelli, ps_step
from ._ps_statistics import SNR_CAP, SNR_GROUPS, PSStatistics, interpolate_statistics, ps_statistics, statistics_snr
from ._random_phase import RandomPhaseInfo, random_phase_noise
from ._tiling_blending import TileBlendInfo, tile_and_blend, tile_and_blend_at

__all__ = [
    "heeger_bergen", "HeegerBergenInfo", "match_histogram",
    "portilla_simoncelli", "ps_statistics", "ps_step", "interpolate_statistics", "statistics_snr",
    "PSStatistics", "PSInfo", "SNR_GROUPS", "SNR_CAP", "PERIODIC_EXEMPLAR",
    "random_phase_noise", "RandomPhaseInfo", "tile_and_blend", "tile_and_blend_at", "TileBlendInfo",
]
