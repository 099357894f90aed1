"""Lapped textures (Praun, Finkelstein & Hoppe 2000): one irregular patch pasted over a surface until it is covered.

Praun et al. [1]_ texture a surface with a single *splotch*, an image whose
alpha channel cuts an irregular opaque blob with a soft rim out of the
texture, and paste copies of it until every triangle is covered. Each
paste, as followed here:

1. **Seed**: a random face not yet covered.
2. **Grow**: from the seed, ring by ring: the faces that share an edge
   with the faces the last ring added and face the seed's way (normals
   within about 78 degrees, so a patch does not wrap round a thin part)
   get texture coordinates by extension (each face's projection onto its
   frame of the field, shifted to agree with the coordinates its corners in
   the patch hold), and those with a corner inside the splotch (alpha above
   0) join; the patch stops growing when a ring adds none. The splotch's
   shape, laid on the surface by the parametrisation, decides where the
   patch ends, however the surface curves.
3. **Parametrise**: the patch's vertices get texture coordinates by least
   squares (as Praun et al. describe it): over every face the gradient of ``u``
   should be the tangent field ``t / (w pixel_size)`` and that of ``v`` be
   ``(n x t) / (h pixel_size)`` for an ``h x w`` exemplar (the splotch
   aligned with the field, each exemplar pixel ``pixel_size`` long on the
   surface), each face weighted by its area, with the seed face's centroid at
   the splotch centre ``(0.5, 0.5)``; solved again whenever the patch has
   grown by half since the last solve, and once more for the final patch
   (a rim face that this last solve moves wholly outside the splotch
   leaves it).
4. **Cover**: faces whose three corners lie in the splotch's opaque part
   (alpha at least 0.99) count as covered.

Overlaps are alpha-blended in paste order (later patches over earlier
ones). The result is *baked* into a texture atlas: every face gets a
``texels x texels`` cell holding its blend (read from the level of the
splotch's Gaussian pyramid whose pixels match the texels, against
aliasing), and the returned mesh indexes
the atlas through per-face uv, so any OBJ/PLY viewer shows it; the layers
themselves (per patch, its faces and their uv in the splotch) are in the
info for renderers that composite them.

The default splotch (when the exemplar has no alpha channel and no
``mask`` is given) is a blob of radius ``0.42 (1 + 0.12 noise(theta))``
(smooth random angular noise) with a soft rim 0.08 wide, in the unit square
of the exemplar.

What could not be checked: the paper was not at hand (a course's lecture
slides show its patch growth in pictures only). Praun et al.
add faces one at a time and re-optimise; here a whole ring of adjacent faces
is tested at once against extended coordinates, and the least squares are
solved again after every 50 % of growth (on the 70,000-face bunny a solve
per ring took 68 solves per patch and 27 s in all). Their splotch masks were drawn by hand; their
orientation-and-scale energy is followed in the least-squares form
described above, its weights could not be checked. The atlas baking is this
implementation's output format (the paper renders the layers directly).

References
----------
.. [1] E. Praun, A. Finkelstein and H. Hoppe, "Lapped textures", SIGGRAPH
   2000, pp. 465-470. :doi:`10.1145/344779.344987`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np
import scipy.sparse
import scipy.sparse.csgraph
import scipy.sparse.linalg
from scipy.ndimage import map_coordinates

from ..core._progress import Progress
from ..core._validate import as_image, as_rng, as_size, check_memory, check_positive_float, check_positive_int
from ..core.pyramid import gaussian_pyramid, max_levels
from ._field import check_field, field_vectors
from ._meshio import as_mesh

__all__ = ["lapped_textures", "LappedInfo", "default_splotch"]

_FACING = 0.2      # a patch grows over faces whose normals have at least this cosine with the seed's
_RESOLVE = 1.5     # ... and is parametrised again each time it has grown by this factor
_OPAQUE = 0.99     # alpha above which a corner counts as covered
_ANCHOR = 1e3      # weight of the seed's position in the least squares
_SPLOTCH_BYTES = 24 * 8  # the default splotch's float64 arrays per pixel at its peak (18: its harmonics), with a margin


@dataclass
class LappedInfo:
    """Extra results of :func:`lapped_textures`.

    Attributes
    ----------
    patches : list of (numpy.ndarray, numpy.ndarray)
        Per pasted patch, in paste order: its face indices ``(F,)`` and their
        corners' coordinates in the splotch ``(F, 3, 2)`` (``v`` up).
    splotch : numpy.ndarray
        ``(h, w, C + 1)`` the pasted image with its alpha channel last.
    field : numpy.ndarray
        ``(N, 3)`` the tangent vector at each vertex.
    layers : numpy.ndarray of int
        ``(M,)`` how many patches overlap each face.
    seconds : float
    stage_seconds : dict
        ``"field"``, ``"paste"`` and ``"bake"``.
    """

    patches: list = dataclass_field(default_factory=list)
    splotch: np.ndarray | None = None
    field: np.ndarray | None = None
    layers: np.ndarray | None = None
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)


def default_splotch(shape, *, rng=None):
    """The default alpha mask: a soft-edged irregular blob filling most of the unit square.

    Parameters
    ----------
    shape : int or (int, int)
        ``(h, w)`` of the mask (an int means square).
    rng : None, int or numpy.random.Generator

    Returns
    -------
    numpy.ndarray
        ``(h, w)`` alpha in [0, 1], 1 inside the blob.

    Examples
    --------
    >>> a = default_splotch((32, 32), rng=0)
    >>> float(a[16, 16]), float(a[0, 0])
    (1.0, 0.0)
    """
    h, w = as_size(shape, "shape")
    check_memory(float(h) * w * _SPLOTCH_BYTES, (h, w), "shape", "the splotch")
    rng = as_rng(rng)
    y, x = np.mgrid[0:h, 0:w]
    dy, dx = (y + 0.5) / h - 0.5, (x + 0.5) / w - 0.5
    theta, rho = np.arctan2(dy, dx), np.hypot(dx, dy)
    harmonics = np.arange(2, 6)
    amps = rng.normal(0, 1, (2, len(harmonics))) / harmonics
    noise = (amps[0] * np.cos(harmonics * theta[..., None]) + amps[1] * np.sin(harmonics * theta[..., None])).sum(-1)
    noise /= max(np.abs(noise).max(), 1e-12)
    radius = 0.42 * (1 + 0.12 * noise)
    return np.clip((radius - rho) / 0.08, 0, 1)


def _splotch(exemplar, mask, rng):
    image = as_image(exemplar, "exemplar")
    image = image[..., None] if image.ndim == 2 else image
    if mask is not None:
        alpha = as_image(mask, "mask")
        if alpha.shape[:2] != image.shape[:2] or alpha.ndim == 3 and alpha.shape[2] != 1:
            raise ValueError(f"mask must be one alpha value per exemplar pixel, shape {image.shape[:2]}, got shape "
                             f"{alpha.shape}")
        alpha = alpha.reshape(image.shape[:2])
    elif image.shape[2] in (2, 4):
        image, alpha = image[..., :-1], image[..., -1]
    else:
        alpha = default_splotch(image.shape[:2], rng=rng)
    if not (alpha >= _OPAQUE).any():
        raise ValueError("the splotch has no opaque pixel (alpha >= 0.99), so no face could ever be covered; pass a "
                         "mask (or an alpha channel) with an opaque interior")
    return np.concatenate([image, alpha[..., None]], axis=2)


def _sample(image, uv):
    """Bilinear samples of ``image`` (h, w, C) at ``uv`` (..., 2) with v up; zero outside the unit square."""
    h, w = image.shape[:2]
    rows = (1.0 - uv[..., 1]) * h - 0.5
    cols = uv[..., 0] * w - 0.5
    coords = np.stack([rows.ravel(), cols.ravel()])
    out = np.stack([map_coordinates(image[..., c], coords, order=1, mode="nearest") for c in range(image.shape[2])],
                   axis=-1).reshape(uv.shape[:-1] + (image.shape[2],))
    inside = (uv[..., 0] >= 0) & (uv[..., 0] <= 1) & (uv[..., 1] >= 0) & (uv[..., 1] <= 1)
    return out * inside[..., None]


class _Paster:
    """The surface data every paste reads: face adjacency and the face frames of the field."""

    def __init__(self, mesh, vectors, side_u, side_v):
        self.mesh = mesh
        self.side = np.array([side_u, side_v])  # the exemplar's width and height on the surface
        adjacency = mesh.face_adjacency
        rows = np.repeat(np.arange(len(mesh.faces)), 3)
        keep = adjacency.ravel() >= 0
        self.graph = scipy.sparse.csr_matrix((np.ones(keep.sum(), np.int8), (rows[keep], adjacency.ravel()[keep])),
                                             shape=(len(mesh.faces),) * 2)
        n = mesh.face_normals
        t = vectors[mesh.faces].sum(axis=1)
        t -= np.einsum("ij,ij->i", t, n)[:, None] * n
        length = np.linalg.norm(t, axis=1, keepdims=True)
        fallback = vectors[mesh.faces[:, 0]] - np.einsum("ij,ij->i", vectors[mesh.faces[:, 0]], n)[:, None] * n
        t = np.where(length > 1e-9, t, fallback)
        t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-300)
        self.t, self.b = t, np.cross(n, t)

    def grow(self, seed, alpha):
        """The patch of one paste (module notes, steps 2-3): faces and their (F, 3, 2) corner uv."""
        corners = self.mesh.faces
        facing = self.mesh.face_normals @ self.mesh.face_normals[seed] > _FACING
        member = np.zeros(len(corners), dtype=bool)
        member[seed] = True
        faces = added = np.array([seed])
        vertex_uv = np.full((len(self.mesh.vertices), 2), np.nan)
        uv_solved = self.parametrize(faces, seed)
        vertex_uv[corners[seed]] = uv_solved[0]
        while True:
            ring = np.flatnonzero((self.graph[added].sum(axis=0).A1 > 0) & ~member & facing)
            if ring.shape[0] == 0:
                break
            uv = self.extend(ring, vertex_uv)
            touches = (_sample(alpha, uv)[..., 0] > 0).any(axis=1)
            if not touches.any():
                break
            added = ring[touches]
            faces = np.concatenate([faces, added])
            member[added] = True
            fresh = np.isnan(vertex_uv[corners[added], 0])
            vertex_uv[corners[added][fresh]] = uv[touches][fresh]
            if len(faces) >= _RESOLVE * len(uv_solved):  # the least squares again, over the grown patch
                uv_solved = self.parametrize(faces, seed)
                vertex_uv[corners[faces]] = uv_solved
        # the final patch solved (unless the last ring's solve already was of it)
        return faces, uv_solved if len(uv_solved) == len(faces) else self.parametrize(faces, seed)

    def extend(self, ring, vertex_uv):
        """(R, 3, 2) corner uv of faces beside the patch: each face's frame projection, shifted to agree with
        the uv its patch corners hold (on average)."""
        corners = self.mesh.faces[ring]
        p = self.mesh.vertices[corners]
        proj = np.stack([np.einsum("rkj,rj->rk", p, self.t[ring]) / self.side[0],
                         np.einsum("rkj,rj->rk", p, self.b[ring]) / self.side[1]], axis=-1)
        held = vertex_uv[corners]
        known = ~np.isnan(held[..., 0])
        shift = np.where(known[..., None], held - proj, 0.0).sum(axis=1) / known.sum(axis=1)[:, None]
        return np.where(known[..., None], held, proj + shift[:, None, :])

    def parametrize(self, faces, seed):
        """Least-squares (u, v) of the region's vertices (module notes, step 3); returns (F, 3, 2) corner uv."""
        corners = self.mesh.faces[faces]
        verts, local = np.unique(corners, return_inverse=True)
        local = local.reshape(-1, 3)
        p = self.mesh.vertices[corners]
        weight = np.sqrt(self.mesh.face_areas[faces])[:, None] / self.side.max()
        rows, cols, vals, rhs = [], [], [], []
        for a, b in ((0, 1), (1, 2), (2, 0)):
            e = p[:, b] - p[:, a]
            r = np.arange(len(faces)) + len(rhs) * len(faces)
            rows += [r, r]
            cols += [local[:, b], local[:, a]]
            vals += [weight[:, 0], -weight[:, 0]]
            rhs.append(weight * np.stack([np.einsum("ij,ij->i", e, self.t[faces]),
                                          np.einsum("ij,ij->i", e, self.b[faces])], axis=1) / self.side)
        m = 3 * len(faces)
        seed_local = local[np.flatnonzero(faces == seed)[0]]
        rows.append(np.full(3, m))
        cols.append(seed_local)
        vals.append(np.full(3, _ANCHOR / 3))
        rhs.append(np.array([[0.5 * _ANCHOR, 0.5 * _ANCHOR]]))
        a = scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                    shape=(m + 1, len(verts)))
        normal = (a.T @ a).tocsc()
        uv = scipy.sparse.linalg.splu(normal).solve(np.asarray(a.T @ np.concatenate(rhs)))
        return uv[local]


def _bake(mesh, patches, splotch, texels):
    """Blend the layers of every face into its cell of a texture atlas; returns (uv (M, 3, 2), atlas)."""
    m = len(mesh.faces)
    channels = splotch.shape[2] - 1
    cols = int(np.ceil(np.sqrt(m)))
    rows = int(np.ceil(m / cols))
    check_memory(8.0 * rows * cols * texels * texels * (channels + 2) * 3, texels, "texels", "the texture atlas")
    # cell-local corners (x right, y down, in texels) and the barycentric coordinates of the texel centres
    corners = np.array([[0.5, texels - 0.5], [texels - 0.5, texels - 0.5], [0.5, 0.5]])
    y, x = np.mgrid[0:texels, 0:texels] + 0.5
    basis = np.array([corners[1] - corners[0], corners[2] - corners[0]]).T
    lam = np.linalg.solve(basis, np.stack([x.ravel() - corners[0, 0], y.ravel() - corners[0, 1]]))
    bary = np.stack([1 - lam.sum(axis=0), lam[0], lam[1]], axis=1)              # (T*T, 3)
    color = np.zeros((m, texels * texels, channels))
    cover = np.zeros((m, texels * texels))
    # pre-filtered splotch: each patch reads the pyramid level whose pixels match its texels' footprint
    mips = gaussian_pyramid(splotch, max_levels(splotch.shape[:2]))
    for faces, uv in patches:  # paste order: "over" compositing, later patches on top
        footprint = np.median(np.abs(uv - uv[:, [1, 2, 0]]).max(axis=(1, 2))) * max(splotch.shape[:2]) / texels
        level = int(np.clip(np.floor(np.log2(max(footprint, 1.0))), 0, len(mips) - 1))
        sample = _sample(mips[level], np.einsum("kc,fcd->fkd", bary, uv))
        alpha = sample[..., -1]
        color[faces] = alpha[..., None] * sample[..., :-1] + (1 - alpha[..., None]) * color[faces]
        cover[faces] = alpha + (1 - alpha) * cover[faces]
    # un-premultiply (a texel only partly covered keeps the colour of what covers it); empty texels: face mean
    mean = color.sum(axis=1) / np.maximum(cover.sum(axis=1), 1e-12)[:, None]
    color = np.where(cover[..., None] > 1e-6, color / np.maximum(cover, 1e-6)[..., None], mean[:, None, :])
    atlas = np.zeros((rows * texels, cols * texels, channels))
    r, c = np.divmod(np.arange(m), cols)
    cell = color.reshape(m, texels, texels, channels)
    atlas.reshape(rows, texels, cols, texels, channels)[r, :, c, :, :] = cell
    offset = np.stack([c * texels, r * texels], axis=1)[:, None, :] + corners[None]
    uv = np.stack([offset[..., 0] / atlas.shape[1], 1 - offset[..., 1] / atlas.shape[0]], axis=-1)
    return uv, np.clip(atlas, 0, 1)


def lapped_textures(mesh, exemplar, *, pixel_size=None, field="smooth", symmetry=1, mask=None, texels=8,
                    rng=None, progress=False, return_info=False):
    """Lapped textures: paste an irregular patch of the exemplar over a surface until it is covered.

    Examples
    --------
    >>> import texsynth
    >>> ball, bread = texsynth.surface.sphere(642), texsynth.data.load("bread")[:64, :64]
    >>> out, info = texsynth.lapped_textures(ball, bread, pixel_size=0.04, rng=0, return_info=True)  # 8 pastes
    >>> out.uv.shape == (1280, 3, 2), int(info.layers.min()) >= 1
    (True, True)

    Each paste grows a patch of faces from a random uncovered seed face,
    lays the splotch (an irregular, soft-edged piece of the exemplar) on it
    along a tangent field, and blends it over what is there; the result is
    baked into a texture atlas (Praun, Finkelstein & Hoppe 2000 [1]_).

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`).
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` image; with 2 or 4 channels the last is
        the splotch's alpha.
    pixel_size : float, optional
        The length on the surface of one exemplar pixel. Default: the
        exemplar's longer side spans a quarter of the square root of the
        surface area (about 16 splotches' worth of opaque area).
    field : {"smooth", "random"}, array_like (N, 3) or callable
        The direction of the exemplar's x axis
        (:func:`~texsynth.surface.tangent_field`).
    symmetry : {1, 2, 4}
        Rotational symmetry of the texture, for the relaxed field.
    mask : array_like, optional
        ``(h, w)`` alpha of the splotch, instead of the exemplar's alpha or
        the default blob (:func:`default_splotch`).
    texels : int
        Side of each face's cell in the baked atlas (default 8).
    rng : None, int or numpy.random.Generator
        Seeds the field, the default splotch and the seed faces.
    progress : bool or callable
        True shows a tqdm bar over the faces covered.
    return_info : bool
        Also return a :class:`LappedInfo`.

    Returns
    -------
    Mesh
        The input mesh textured by the baked atlas through per-face uv.
    info : LappedInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an invalid mesh, exemplar, mask, field (wrong length, NaN),
        ``pixel_size`` or ``texels``, or an atlas that would not fit in
        memory.

    References
    ----------
    .. [1] E. Praun, A. Finkelstein and H. Hoppe, "Lapped textures", SIGGRAPH
       2000, pp. 465-470. :doi:`10.1145/344779.344987`
    """
    start = time.perf_counter()
    mesh = as_mesh(mesh)
    rng = as_rng(rng)
    field = check_field(field, len(mesh.vertices), symmetry)
    texels = check_positive_int(texels, "texels", 2)
    area = float(mesh.face_areas.sum())
    splotch = _splotch(exemplar, mask, rng)
    h, w = splotch.shape[:2]
    pixel_size = (0.25 * np.sqrt(area) / max(h, w) if pixel_size is None
                  else check_positive_float(pixel_size, "pixel_size"))
    info = LappedInfo(splotch=splotch)
    t0 = time.perf_counter()
    vectors = field_vectors(mesh.vertices, mesh.vertex_normals, field, symmetry=symmetry, rng=rng,
                            vertices=mesh.vertices)
    info.field = vectors
    info.stage_seconds["field"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    paster = _Paster(mesh, vectors, w * pixel_size, h * pixel_size)
    covered = np.zeros(len(mesh.faces), dtype=bool)
    alpha = splotch[..., -1:]
    with Progress(progress, len(mesh.faces), "lapped textures") as bar:
        while not covered.all():
            seed = int(rng.choice(np.flatnonzero(~covered)))
            faces, uv = paster.grow(seed, alpha)
            corner_alpha = _sample(alpha, uv)[..., 0]
            keep = (corner_alpha > 0).any(axis=1) | (faces == seed)  # the last solve may move a rim face out
            faces, uv, corner_alpha = faces[keep], uv[keep], corner_alpha[keep]
            newly = faces[(corner_alpha >= _OPAQUE).all(axis=1) & ~covered[faces]]
            # the seed always counts as covered, so every paste makes progress (a face larger than the splotch's
            # opaque part is then covered by the patch that reaches it best)
            newly = np.union1d(newly, [seed])
            covered[newly] = True
            info.patches.append((faces, uv))
            bar.advance({"patches": len(info.patches)}, n=len(newly))
    info.stage_seconds["paste"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    atlas_uv, atlas = _bake(mesh, info.patches, splotch, texels)
    info.layers = np.bincount(np.concatenate([f for f, _ in info.patches]), minlength=len(mesh.faces))
    info.stage_seconds["bake"] = time.perf_counter() - t0
    info.seconds = time.perf_counter() - start
    out = mesh.with_texture(atlas_uv, atlas)
    return (out, info) if return_info else out
