"""The ``texsynth`` commands whose inputs are shapes rather than images: meshes, volumes and BTF samples.

``texsynth surface`` (texture a mesh: vertex synthesis, lapped textures, progressively-variant
textures), ``texsynth geometry`` (a larger shape like an example), ``texsynth geometry-analogies``
(a geometric texture carried from one shape to another), ``texsynth mesh-quilting`` (a swatch of
elements over a surface) and ``texsynth btf`` (a BTF sample larger, or over a mesh).
:mod:`texsynth.cli` builds the parser and dispatches; each command here is a pair of functions,
``add_X_parser(sub)`` and ``run_X(args)``, which returns the paths written.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from ._cli_values import CommandError, parse_size
from .core.files import atomic_write, prepare_target
from .io._images import check_suffix
from .registry import group_options

__all__ = ["add_surface_parser", "add_geometry_parser", "add_geometry_analogies_parser", "add_mesh_quilting_parser",
           "add_btf_parser", "run_surface", "run_geometry", "run_geometry_analogies", "run_mesh_quilting", "run_btf"]

def add_surface_parser(sub):
    surface = sub.add_parser("surface", help="texture a mesh: vertex synthesis (Turk; Wei & Levoy) or lapped "
                                             "textures (Praun et al.)",
                             description="Synthesise a texture over a triangle mesh (texsynth.synthesize_surface) "
                                         "or paste lapped textures (texsynth.lapped_textures); docs/methods/"
                                         "vertex_synthesis.md and lapped.md.")
    surface.add_argument("mesh", metavar="MESH", help="the surface: .obj or .ply (others with the mesh extra: trimesh)")
    surface.add_argument("exemplar", metavar="EXEMPLAR", help="the texture image")
    surface.add_argument("-o", "--output", required=True, help="output mesh (.ply or .obj; a texture goes beside it)")
    surface.add_argument("--mode", choices=("vertex", "lapped", "progressive", "feature-aligned"), default="vertex",
                         help="vertex: colour retiled vertices (default); lapped: paste patches into a texture atlas; "
                              "progressive: from EXEMPLAR to --exemplar-b along --blend (Zhang et al. 2003); "
                              "feature-aligned: the exemplar's edges along the mesh's ridges and valleys (Xu et al. "
                              "2009)")
    surface.add_argument("--curves", help="feature-aligned mode: an .npy of the curves' vertices (a bool mask or "
                                          "indices of MESH's vertices); default: its ridges and valleys")
    surface.add_argument("--exemplar-b", help="progressive mode: the texture where the transition reaches 1")
    surface.add_argument("--blend", default="z",
                         help="progressive mode: the transition, x, y or z (0 at the mesh's lowest coordinate, 1 at "
                              "its highest; default z) or an .npy file of one value in [0, 1] per vertex")
    surface.add_argument("--n-vertices", type=int, help="vertex mode: retile to about this many vertices")
    surface.add_argument("--pixel-size", type=float,
                         help="surface length of one exemplar pixel; vertex mode: sets the density instead of "
                              "--n-vertices (neither: the mesh's own vertices); lapped mode: default a quarter of "
                              "the square root of the area per exemplar side")
    surface.add_argument("--field", default="smooth",
                         help="texture orientation: smooth (default), random, latitude or meridian (about the z "
                              "axis through the mesh's centre), or an .npy file of one (x, y, z) vector per vertex")
    surface.add_argument("--symmetry", type=int, choices=(1, 2, 4), default=1,
                         help="rotational symmetry of the texture, for the smooth field (default 1)")
    surface.add_argument("--levels", type=int, help="vertex mode: hierarchy levels (default 3)")
    surface.add_argument("--preset", choices=("default", "paper"), default="default", help="vertex mode: defaults")
    surface.add_argument("--order", choices=("independent", "sweep"),
                         help="vertex mode: all vertices of a level at once per pass (independent, the default "
                              "preset's) or one at a time along Turk's sweep (the paper preset's)")
    surface.add_argument("-s", "--seed", type=int, default=None, help="random seed")
    surface.add_argument("--preview", help="also write a rendered preview image (PNG)")
    surface.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")
    surface.add_argument("--allow-outside", action="store_true",
                         help="follow the files MESH names (mtllib, map_Kd, TextureFile) even outside the mesh's "
                              "folder; off by default, so a mesh from elsewhere cannot read other files")


def _surface_field(text, mesh):
    """The --field value: a name, a latitude/meridian callable about the mesh's vertical axis, or a .npy file."""
    import numpy as np

    center = mesh.vertices.mean(axis=0) * np.array([1.0, 1.0, 0.0])

    def latitude(p):
        return np.cross([0.0, 0.0, 1.0], p - center)

    if text in ("smooth", "random"):
        return text
    if text == "latitude":
        return latitude
    if text == "meridian":
        return lambda p: np.cross(p - center, latitude(p))
    if not text.endswith(".npy"):
        raise CommandError(f"--field must be smooth, random, latitude, meridian or an .npy file, got {text!r}")
    return np.load(text, allow_pickle=False)


def _surface_blend(text):
    """The --blend value: an axis (a callable of positions, 0 to 1 over the mesh's extent) or a .npy file."""
    import numpy as np

    if text in ("x", "y", "z"):
        axis = "xyz".index(text)

        def along(p):
            low, high = p[:, axis].min(), p[:, axis].max()
            return (p[:, axis] - low) / max(high - low, 1e-12)

        return along
    if not text.endswith(".npy"):
        raise CommandError(f"--blend must be x, y, z or an .npy file of one value per vertex, got {text!r}")
    return np.load(text, allow_pickle=False)


def run_surface(args):
    import numpy as np

    from .io import load_image, save_image
    from .surface import (feature_aligned_surface, lapped_textures, progressive_surface, read_mesh, render_mesh,
                          synthesize_surface, write_mesh)

    out = Path(args.output)
    if out.resolve() in {Path(args.mesh).resolve(), Path(args.exemplar).resolve()}:
        raise CommandError(f"output {args.output!r} is also an input; choose another output path")
    if out.exists() and not args.overwrite:
        raise CommandError(f"output {args.output!r} exists; pass --overwrite to replace it")
    if args.mode == "lapped":  # lapped textures write a texture (and, for .obj, a material) beside the mesh
        for companion in (out.with_suffix(".png"), out.with_suffix(".mtl")):
            if companion.exists() and not args.overwrite:
                raise CommandError(f"{str(companion)!r}, the texture or material of output {args.output!r}, exists; "
                                   "pass --overwrite to replace it")
    if args.preview:  # checked before the synthesis, as the output is
        preview = Path(args.preview)
        if preview.resolve() in {out.with_suffix(s).resolve() for s in ("", ".png", ".mtl")}:
            raise CommandError(f"--preview {args.preview!r} is a file the mesh output writes (its texture "
                               f"{out.stem}.png or material {out.stem}.mtl); choose another name, e.g. "
                               f"{out.stem}_preview.png")
        check_suffix(preview)
        if preview.exists() and not args.overwrite:
            raise CommandError(f"--preview {args.preview!r} exists; pass --overwrite to replace it")
    if args.exemplar_b is not None and args.mode != "progressive":
        raise CommandError("--exemplar-b belongs to --mode progressive")
    if args.curves is not None and args.mode != "feature-aligned":
        raise CommandError("--curves belongs to --mode feature-aligned")
    if args.exemplar_b is not None and out.resolve() == Path(args.exemplar_b).resolve():
        raise CommandError(f"output {args.output!r} is also an input; choose another output path")
    mesh = read_mesh(args.mesh, allow_outside=args.allow_outside)
    exemplar = load_image(args.exemplar)
    field = _surface_field(args.field, mesh)
    if args.mode == "lapped":
        if args.n_vertices is not None or args.levels is not None or args.order is not None:
            raise CommandError("--n-vertices, --levels and --order belong to --mode vertex; lapped textures keep "
                               "the mesh")
        result = lapped_textures(mesh, exemplar, pixel_size=args.pixel_size, field=field, symmetry=args.symmetry,
                                 rng=args.seed)
    elif args.mode == "feature-aligned":
        if args.pixel_size is not None or args.order is not None or args.preset != "default" or args.field != "smooth":
            raise CommandError("--pixel-size, --order, --preset and --field belong to --mode vertex; the curves set "
                               "the field in feature-aligned mode, which takes --n-vertices, --levels, --symmetry")
        options = group_options(feature_aligned_surface, {
            "n_vertices": args.n_vertices, "symmetry": args.symmetry, "rng": args.seed,
            **({"curves": np.load(args.curves, allow_pickle=False)} if args.curves else {}),
            **({"levels": args.levels} if args.levels is not None else {})})
        result = feature_aligned_surface(mesh, exemplar[..., :3] if exemplar.ndim == 3 and exemplar.shape[2] == 4
                                         else exemplar, **options)
    elif args.mode == "progressive":
        if args.exemplar_b is None:
            raise CommandError("--mode progressive needs --exemplar-b B.png, the texture where --blend reaches 1")
        if args.pixel_size is not None or args.order is not None or args.preset != "default":
            raise CommandError("--pixel-size, --order and --preset belong to --mode vertex; progressive mode takes "
                               "--n-vertices and --levels")
        options = group_options(progressive_surface, {
            "n_vertices": args.n_vertices, "field": field, "rng": args.seed,
            **({"levels": args.levels} if args.levels is not None else {})})
        result = progressive_surface(mesh, exemplar, load_image(args.exemplar_b), _surface_blend(args.blend),
                                     **options)
    else:
        options = group_options(synthesize_surface, {
            "n_vertices": args.n_vertices, "pixel_size": args.pixel_size, "field": field, "symmetry": args.symmetry,
            "preset": args.preset, "rng": args.seed,
            **{name: value for name, value in (("levels", args.levels), ("order", args.order)) if value is not None}})
        result = synthesize_surface(mesh, exemplar[..., :3] if exemplar.ndim == 3 and exemplar.shape[2] == 4
                                    else exemplar, **options)
    written = [write_mesh(out, result, overwrite=args.overwrite)]
    if args.preview:
        save_image(args.preview, render_mesh(result, 768), overwrite=args.overwrite)
        written.append(Path(args.preview))
    return written


_MESH = {".obj": "a mesh (.obj, .ply)", ".ply": "a mesh (.obj, .ply)"}
_VOLUME_OR_MESH = {**_MESH, ".npy": "a volume (.npy)"}


def add_geometry_parser(sub):
    geometry = sub.add_parser("geometry", help="a larger shape like an example mesh or volume (Lagae et al. 2005)",
                              description="Synthesise a larger shape like an example (texsynth.geometry."
                                          "synthesize_geometry): the example as a signed distance volume, quilted "
                                          "block by block along 3-D minimum cuts, and the result's surface as a "
                                          "mesh (docs/methods/lagae.md).")
    geometry.add_argument("example", metavar="EXAMPLE",
                          help="the example: a closed mesh (.obj, .ply; others with the mesh extra: trimesh), "
                               "voxelised at --voxels, or a volume (.npy: a signed distance field, negative "
                               "inside, or a bool occupancy)")
    geometry.add_argument("-o", "--output", required=True,
                          help="output: a mesh (.obj, .ply) or the distance volume (.npy)")
    geometry.add_argument("--size", default="2x",
                          help="output size in voxels: N (a cube), WxHxD, or a factor of the example's (default 2x)")
    geometry.add_argument("--voxels", type=int, default=48,
                          help="a mesh example: voxels along its longest side (default 48)")
    geometry.add_argument("--block", type=int, help="side of the blocks in voxels (default: a third of the "
                                                    "example's smallest side, 8 to 32)")
    geometry.add_argument("--overlap", type=int, help="voxels by which blocks overlap (default: block / 4)")
    geometry.add_argument("--levels", type=int, default=1, help="hierarchical passes (default 1)")
    geometry.add_argument("--copy-elements", action="store_true",
                          help="copy the example's separate elements whole instead of stitching the field")
    geometry.add_argument("-s", "--seed", type=int, default=None, help="random seed")
    geometry.add_argument("--preview", help="also write a rendered preview image (PNG)")
    geometry.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")
    geometry.add_argument("--allow-outside", action="store_true",
                          help="a mesh may name files outside its own folder (materials)")


def _geometry_size(text, shape):
    """``--size`` of ``texsynth geometry``: ``(depth, height, width)`` from N, WxHxD or a factor of ``shape``."""
    factor = re.fullmatch(r"(\d+(?:\.\d*)?|\.\d+)[xX]", text.strip())
    if factor:
        size = tuple(int(math.floor(side * float(factor.group(1)) + 0.5)) for side in shape)
        if min(size) < 1:
            raise CommandError(f"--size {text} makes the example smaller than a voxel; pass a larger factor or N")
        return size
    size = parse_size(text)
    if len(size) == 2:
        if "x" in text.lower():
            raise CommandError(f"--size of a volume is N (a cube), WxHxD or a factor such as 2x; got {text!r}")
        size = (size[0],) * 3
    return size


def _save_volume(tmp, volume):
    import numpy as np

    with open(tmp, "wb") as f:  # a file object: np.save would append ".npy" to a name ending in ".NPY"
        np.save(f, volume)


def run_geometry(args):
    import numpy as np

    from .geometry import mesh_to_sdf, synthesize_geometry
    from .surface import read_mesh

    out = _checked_output(args, [args.example], _VOLUME_OR_MESH)
    example = Path(args.example)
    if example.suffix.lower() == ".npy":
        volume, spacing, origin = np.load(example, allow_pickle=False), 1.0, np.zeros(3)
    else:
        volume, spacing, origin = mesh_to_sdf(read_mesh(example, allow_outside=args.allow_outside), args.voxels)
    options = {"block": args.block, "overlap": args.overlap}
    sdf = synthesize_geometry(volume, _geometry_size(args.size, np.shape(volume)), levels=args.levels,
                              copy_elements=args.copy_elements, rng=args.seed,
                              **{name: value for name, value in options.items() if value is not None})
    return _write_volume_or_mesh(args, out, sdf, spacing, origin)


def add_geometry_analogies_parser(sub):
    from .data import volume_names

    analogies = sub.add_parser("geometry-analogies",
                               help="a geometric texture carried from one shape to another (Bhat et al. 2004)",
                               description="Geometric texture analogies (texsynth.geometry.geometry_analogies, "
                                           "docs/methods/geometry_analogies.md): A is to A_PRIME as B is to the "
                                           "output, the texture laid along --field-b on B.")
    names = ", ".join(volume_names())
    analogies.add_argument("a", metavar="A", help=f"the plain example: a volume (.npy) or a bundled one ({names})")
    analogies.add_argument("a_prime", metavar="A_PRIME", help="the same with its geometric texture, on A's grid")
    analogies.add_argument("b", metavar="B", help="the new plain shape: a volume (.npy), a bundled one, or a closed "
                                                  "mesh (.obj, .ply) voxelised at --voxels")
    analogies.add_argument("-o", "--output", required=True, help="output: a mesh (.obj, .ply) or the volume (.npy)")
    analogies.add_argument("--field-a", default="z", help="the texture's direction on A: x, y or z (a volume's "
                                                          "width, height, depth axis), dz,dy,dx, or around-x|y|z "
                                                          "(circles about that axis through the centre); default z")
    analogies.add_argument("--field-b", default="z", help="the same on B, or an .npy of (D, H, W, 3) vectors")
    analogies.add_argument("--size", type=int, default=48, help="voxels of a bundled volume's side (default 48)")
    analogies.add_argument("--voxels", type=int, default=96, help="a mesh B: voxels along its longest side")
    analogies.add_argument("--levels", type=int, default=2, help="levels, coarse to fine (default 2)")
    analogies.add_argument("-s", "--seed", type=int, default=None, help="random seed")
    analogies.add_argument("--preview", help="also write a rendered preview image (PNG)")
    analogies.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")


def _volume_field(text, shape):
    """A --field value: an axis, a vector ``dz,dy,dx``, circles about an axis (a callable) or an .npy file."""
    import numpy as np

    axes = {"z": 0, "y": 1, "x": 2}
    if text in axes:
        return tuple(float(axis == axes[text]) for axis in range(3))
    center = (np.asarray(shape, float) - 1) / 2
    if text.startswith("around-") and text[7:] in axes:
        axis = np.eye(3)[axes[text[7:]]]
        return lambda p: np.cross(axis, p - center)
    if text.endswith(".npy"):
        return np.load(text, allow_pickle=False)
    try:
        vector = tuple(float(v) for v in text.split(","))
    except ValueError:
        vector = ()
    if len(vector) != 3:
        raise CommandError(f"a field must be x, y, z, dz,dy,dx, around-x|y|z or an .npy file, got {text!r}")
    return vector


def _read_volume(text, size):
    """A volume from an .npy file or a bundled volume's name."""
    import numpy as np

    from .data import volume, volume_names

    if text in volume_names() and not Path(text).exists():
        return volume(text, size)
    if Path(text).suffix.lower() != ".npy":
        raise CommandError(f"{text!r} must be a volume (.npy) or one of {', '.join(volume_names())}")
    return np.load(text, allow_pickle=False)


def run_geometry_analogies(args):
    import numpy as np

    from .geometry import geometry_analogies, mesh_to_sdf
    from .surface import read_mesh

    out = _checked_output(args, [args.a, args.a_prime, args.b], _VOLUME_OR_MESH)
    a, a_prime = _read_volume(args.a, args.size), _read_volume(args.a_prime, args.size)
    spacing, origin = 1.0, np.zeros(3)
    if Path(args.b).suffix.lower() in _MESH:
        b, spacing, origin = mesh_to_sdf(read_mesh(args.b), args.voxels, margin=4)
    else:
        b = _read_volume(args.b, args.size)
    result = geometry_analogies(a, a_prime, b, field_a=_volume_field(args.field_a, np.shape(a)),
                                field_b=_volume_field(args.field_b, np.shape(b)), levels=args.levels, rng=args.seed)
    return _write_volume_or_mesh(args, out, result, spacing, origin)


def _checked_output(args, inputs, kinds):
    """The output path, refused before any work: not one of ``kinds`` (``{suffix: what}``), an input, or an existing
    file (and the same for --preview)."""
    out = Path(args.output)
    if out.suffix.lower() not in kinds:
        raise CommandError(f"output {args.output!r} must be {' or '.join(sorted(set(kinds.values())))}")
    if out.resolve() in {Path(p).resolve() for p in inputs if p}:
        raise CommandError(f"output {args.output!r} is also an input; choose another output path")
    if out.exists() and not args.overwrite:
        raise CommandError(f"output {args.output!r} exists; pass --overwrite to replace it")
    if args.preview:
        check_suffix(Path(args.preview))
        if Path(args.preview).exists() and not args.overwrite:
            raise CommandError(f"--preview {args.preview!r} exists; pass --overwrite to replace it")
    return out


def _write_volume_or_mesh(args, out, sdf, spacing, origin):
    """A distance volume as an .npy file or as a mesh in the input's units and place, and its preview."""
    from .geometry import sdf_to_mesh
    from .io import save_image
    from .surface import render_mesh, write_mesh

    if out.suffix.lower() == ".npy":
        prepare_target(out, args.overwrite)
        atomic_write(out, lambda tmp: _save_volume(tmp, sdf))
        mesh = sdf_to_mesh(sdf) if args.preview else None
    else:
        vertices, faces = sdf_to_mesh(sdf, spacing=spacing)
        mesh = (vertices + origin, faces)
        write_mesh(out, mesh, overwrite=args.overwrite)
    written = [out]
    if args.preview:
        save_image(args.preview, render_mesh(mesh, 768), overwrite=args.overwrite)
        written.append(Path(args.preview))
    return written


def add_mesh_quilting_parser(sub):
    from .data import swatch_names

    quilting = sub.add_parser("mesh-quilting", help="a swatch of geometry elements quilted over a surface "
                                                    "(Zhou et al. 2006)",
                              description="Quilt a swatch of separate geometry elements over a surface inside a "
                                          "thin shell (texsynth.geometry.mesh_quilting, docs/methods/"
                                          "mesh_quilting.md); the output is the surface with its elements.")
    quilting.add_argument("swatch", metavar="SWATCH",
                          help="the swatch: a mesh file whose connected components are the elements, standing on "
                               f"z = 0, or a bundled swatch: {', '.join(swatch_names())}")
    quilting.add_argument("surface", metavar="SURFACE",
                          help="the base surface: a mesh file, or one of sphere, torus, bumpy")
    quilting.add_argument("-o", "--output", required=True, help="output mesh (.obj, .ply)")
    quilting.add_argument("--unit-length", type=float, default=None,
                          help="surface length of one swatch unit (default: the surface holds about 200 elements)")
    quilting.add_argument("--thickness", type=float, default=None,
                          help="the shell's thickness in surface units (default: the swatch's height, scaled)")
    quilting.add_argument("--elements-only", action="store_true", help="write the elements without the surface")
    quilting.add_argument("-s", "--seed", type=int, default=None, help="random seed")
    quilting.add_argument("--preview", help="also write a rendered preview image (PNG)")
    quilting.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")
    quilting.add_argument("--allow-outside", action="store_true",
                          help="a mesh may name files outside its own folder (materials)")


def _named_mesh(text, names, make, allow_outside):
    """A mesh file, or (no such file) one of ``names`` made by ``make(name)``."""
    from .surface import read_mesh

    if text in names and not Path(text).exists():
        return make(text)
    return read_mesh(text, allow_outside=allow_outside)


_QUILTED_ELEMENTS = 200  # mesh-quilting's default --unit-length: about this many elements over the surface


def _unit_length(swatch, base):
    """The unit length that puts about ``_QUILTED_ELEMENTS`` of the swatch's elements over ``base``:
    ``sqrt(n_swatch * area / (n * swatch_area))``, the swatch's area that of its base's bounding box."""
    import numpy as np
    from scipy import sparse
    from scipy.sparse import csgraph

    vertices, faces = (swatch.vertices, swatch.faces) if hasattr(swatch, "faces") else swatch
    vertices, faces = np.asarray(vertices, float), np.asarray(faces)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]]])
    graph = sparse.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(len(vertices),) * 2)
    n_swatch = csgraph.connected_components(graph, directed=False)[0]
    extent = np.ptp(vertices[:, :2], axis=0)
    a, b, c = (base.vertices[base.faces[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()
    return float(np.sqrt(n_swatch * area / (_QUILTED_ELEMENTS * max(extent[0] * extent[1], 1e-12))))


def run_mesh_quilting(args):
    import numpy as np

    from . import surface
    from .data import swatch, swatch_names
    from .geometry import mesh_quilting
    from .io import save_image

    out = _checked_output(args, [args.swatch, args.surface], _MESH)
    elements = _named_mesh(args.swatch, swatch_names(), swatch, args.allow_outside)
    base = surface.as_mesh(_named_mesh(args.surface, ("sphere", "torus", "bumpy"),
                                       lambda name: getattr(surface, name)(20000), args.allow_outside), "surface")
    unit_length = _unit_length(elements, base) if args.unit_length is None else args.unit_length
    options = {} if args.thickness is None else {"thickness": args.thickness}
    vertices, faces = mesh_quilting(elements, base, unit_length=unit_length, rng=args.seed, **options)
    if not args.elements_only:
        faces = np.concatenate([base.faces, faces + len(base.vertices)])
        vertices = np.concatenate([base.vertices, vertices])
    surface.write_mesh(out, (vertices, faces), overwrite=args.overwrite)
    written = [out]
    if args.preview:
        save_image(args.preview, surface.render_mesh((vertices, faces), 768), overwrite=args.overwrite)
        written.append(Path(args.preview))
    return written


def add_btf_parser(sub):
    from .data import btf_names

    btf = sub.add_parser("btf", help="a BTF (images under many lights) larger or over a mesh (Tong et al. 2002)",
                         description="Synthesise a BTF sample (texsynth.pixel.synthesize_btf: one arrangement of its "
                                     "3-D textons for every light) or cover a mesh with it (texsynth.surface."
                                     "synthesize_btf_surface, rendered under --light); docs/methods/btf.md.")
    btf.add_argument("sample", metavar="SAMPLE",
                     help="the BTF sample: an .npz of images (M, H, W) and lights (M, 3) (and views (M, 3)), or a "
                          f"bundled one: {', '.join(btf_names())}")
    btf.add_argument("-o", "--output", required=True,
                     help="output: a BTF .npz (images, lights, views), or with --mesh a mesh (.ply, .obj)")
    btf.add_argument("--size", help="plane: output size WIDTHxHEIGHT, N or a factor (default 2x)")
    btf.add_argument("--mesh", help="cover this mesh (.obj, .ply) instead of making a larger sample")
    btf.add_argument("--n-vertices", type=int, help="--mesh: retile to about this many vertices")
    btf.add_argument("--light", default="0,0,1",
                     help="--mesh: the direction towards the light, x,y,z in the mesh's coordinates (default 0,0,1)")
    btf.add_argument("--n-textons", type=int, default=64, help="3-D textons made by k-means (default 64)")
    btf.add_argument("-s", "--seed", type=int, default=None, help="random seed")
    btf.add_argument("--preview", help="also write a preview image (PNG): four lights, or the lit mesh")
    btf.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")


def _read_btf(text):
    """A BTF from an .npz (images, lights, views) or a bundled sample's name."""
    import numpy as np

    from .core.btf import BTF
    from .data import btf, btf_names

    if text in btf_names() and not Path(text).exists():
        return btf(text)
    if Path(text).suffix.lower() != ".npz":
        raise CommandError(f"SAMPLE must be an .npz of images and lights or one of {', '.join(btf_names())}; "
                           f"got {text!r}")
    with np.load(text, allow_pickle=False) as saved:
        missing = {"images", "lights"} - set(saved.files)
        if missing:
            raise CommandError(f"{text!r} has no {' or '.join(sorted(missing))} array; a BTF .npz holds images "
                               "(M, H, W) and lights (M, 3), and may hold views (M, 3)")
        return BTF(saved["images"], saved["lights"], saved["views"] if "views" in saved.files else None)


def run_btf(args):
    import numpy as np

    from .core.btf import render_btf
    from .io import save_image
    from .pixel import synthesize_btf
    from .surface import read_mesh, render_btf_surface, render_mesh, synthesize_btf_surface, write_mesh

    out = _checked_output(args, [args.sample, args.mesh], _MESH if args.mesh else {".npz": "a BTF (.npz)"})
    if args.mesh and args.size:
        raise CommandError("--size belongs to the plane; with --mesh use --n-vertices")
    if not args.mesh and args.n_vertices is not None:
        raise CommandError("--n-vertices belongs to --mesh")
    sample = _read_btf(args.sample)
    written = [out]
    if args.mesh:
        try:
            light = np.array([float(v) for v in args.light.split(",")])
        except ValueError:
            light = np.zeros(0)
        if light.shape != (3,):
            raise CommandError(f"--light must be three numbers x,y,z, got {args.light!r}")
        covered = synthesize_btf_surface(read_mesh(args.mesh), sample, n_vertices=args.n_vertices,
                                         n_textons=args.n_textons, rng=args.seed)
        lit = render_btf_surface(covered, light)
        write_mesh(out, lit, overwrite=args.overwrite)
        preview = render_mesh(lit, 768, ambient=1.0) if args.preview else None  # the BTF holds the shading
    else:
        size = parse_size(args.size or "2x", sample.shape)
        result = synthesize_btf(sample, size, n_textons=args.n_textons, rng=args.seed)
        prepare_target(out, args.overwrite)
        atomic_write(out, lambda tmp: _save_btf(tmp, result))
        lights = result.lights[np.linspace(0, len(result) - 1, 4).round().astype(int)]
        preview = np.concatenate([render_btf(result, light) for light in lights], axis=1) if args.preview else None
    if args.preview:
        save_image(args.preview, np.clip(preview, 0.0, 1.0), overwrite=args.overwrite)
        written.append(Path(args.preview))
    return written


def _save_btf(tmp, btf):
    import numpy as np

    with open(tmp, "wb") as f:  # a file object: np.savez would append ".npz" to another suffix
        np.savez(f, images=btf.images, lights=btf.lights, views=btf.views)
