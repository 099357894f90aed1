"""Loading and saving images, volumes and frame sequences.

Loading converts to float in [0, 1] with the library's conventions
(docs/conventions.md, "Images"): 8- and 16-bit files are divided by their white
level (255, 65535), CMYK files are converted to RGB, and integer pixel types
without an agreed white level (signed, or wider than 16 bits) are refused
rather than guessed.

Saving converts float [0, 1] to the file type's integer format (uint8 for
PNG/JPEG/GIF/BMP, uint16 for 16-bit PNG and TIFF), or writes float32 TIFF
(``bits=32``). 16-bit PNG is read and written for grey, grey+alpha, RGB and
RGBA: Pillow (imageio's PNG plugin) handles 16-bit grey only and reads 16-bit
colour PNG as 8 bits, so those go through a small PNG codec of this module
(zlib and numpy, no new dependency). Every save is atomic
(:mod:`texsynth.core.files`): the data go to a hidden temporary file beside
the target, which is renamed over the target only once complete, so a file is
never half-written. The temporary file
is removed when the write fails or the process is interrupted, by Ctrl-C
(SIGINT) or by SIGTERM (``kill``, ``timeout``, a job scheduler); what a killed
writer (SIGKILL) left is removed by the next write of the same target. New
files get the permissions the umask gives, as any other program's output; a
replaced file keeps its permission bits. Nothing is overwritten unless
``overwrite=True``.

OpenEXR files (``.exr``: half or float32 samples) are read and written through
the ``OpenEXR`` package of the Academy Software Foundation, an optional extra
(``python -m pip install '.[exr]'`` in a checkout); without it a ``.exr`` path raises an
ImportError naming the extra. TGA files (``.tga``, 8 bits, alpha kept) go
through Pillow like PNG.

Float data outside [0, 1] (heights, displacement, HDR colour) is refused by
the library's functions, whose contract is images in [0, 1]; to work on such a
file, ``load_image(path, normalize=True)`` returns the image scaled into
[0, 1] by the file's minimum and maximum together with that ``value_range``,
and :func:`restore_range` maps a result back (the command line does both).
The float formats (float TIFF, EXR) store any finite values.
"""

from ._chunked import save_chunked
from ._coordinates import load_coordinates, save_coordinates
from ._frames import load_frames, save_frames
from ._images import image_bits, load_image, normalize_range, restore_range, save_image, to_uint

__all__ = ["load_image", "save_image", "save_chunked", "load_frames", "save_frames", "to_uint", "image_bits",
           "normalize_range", "restore_range", "save_coordinates", "load_coordinates"]
