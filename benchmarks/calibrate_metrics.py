"""Calibration of texsynth.metrics on real textures: the table in docs/metrics.md.

For each texture (an exemplar crop of EXEMPLAR px) we score the three baselines
at OUTPUT px: histogram-matched noise, a random-block mosaic and the tiled
exemplar, and print a Markdown table. Run:

    python benchmarks/calibrate_metrics.py
"""

import time
from pathlib import Path


from texsynth.io import load_image
from texsynth.metrics import texture_report
from texsynth.testing import relative_scores

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
NAMES = [
    ("embark/1.jpg", "stochastic"),
    ("skimage/gravel.png", "stochastic"),
    ("lcv/metal.pgm", "stochastic"),
    ("jcjohnson/bread.png", "stochastic"),
    ("rohitrango/t1.png", "structured"),
    ("skimage/brick.png", "structured"),
    ("lcv/reptil_skin.pgm", "structured"),
    ("rohitrango/t8.png", "regular"),
    ("lcv/text.pgm", "text"),
    ("rohitrango/t16.png", "text"),
    ("lcv/nuts.pgm", "objects"),
]
EXEMPLAR, OUTPUT, PATCH = 64, 96, 8


def load(name):
    image = load_image(TEXTURES / name)
    if image.ndim == 3 and image.shape[-1] == 4:
        image = image[..., :3]
    return image[:EXEMPLAR, :EXEMPLAR]


def main():
    print(f"exemplar {EXEMPLAR}x{EXEMPLAR} crop, output {OUTPUT}x{OUTPUT}, patch {PATCH}\n")
    print("| texture | kind | baseline | energy | completeness | verbatim copy | histogram | spectrum | energy score | completeness score | spectrum score |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    start = time.perf_counter()
    for name, kind in NAMES:
        ex = load(name)
        report = texture_report(ex, ex, patch_size=PATCH, rng=0)
        for base in ("noise", "mosaic", "tiled"):
            values = report.reference[base]
            from texsynth.metrics import TextureReport
            scores = relative_scores(TextureReport(values=values, reference=report.reference))
            print(f"| {name} | {kind} | {base} | {values['energy']:.4f} | {values['completeness']:.4f} | "
                  f"{values['verbatim_copy']:.2f} | {values['histogram']:.4f} | {values['spectrum']:.3f} | "
                  f"{scores['energy']:.2f} | {scores['completeness']:.2f} | {scores['spectrum']:.2f} |")
    print(f"\n{time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
