"""PNG pictures of node fields without a plotting library: zlib and the PNG chunk format."""
import struct
import zlib

import numpy as np

# viridis at 0, 1/4, 1/2, 3/4, 1 (matplotlib's table), linearly interpolated between
VIRIDIS = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], dtype=float)


def colours(values, vmin=0.0, vmax=1.0):
    t = np.clip((np.asarray(values, dtype=float) - vmin) / (vmax - vmin), 0.0, 1.0) * (len(VIRIDIS) - 1)
    k = np.minimum(t.astype(int), len(VIRIDIS) - 2)
    w = (t - k)[..., None]
    return ((1 - w) * VIRIDIS[k] + w * VIRIDIS[k + 1]).astype(np.uint8)


def node_image(x, spacing, values, pixels=6, vmin=0.0, vmax=1.0):
    """An RGB array: each node of the 2D grid a square of `pixels`, white where no node."""
    ij = np.rint((x - x.min(axis=0)) / spacing).astype(int)
    w, h = ij[:, 0].max() + 1, ij[:, 1].max() + 1
    img = np.full((h, w, 3), 255, dtype=np.uint8)
    img[h - 1 - ij[:, 1], ij[:, 0]] = colours(values, vmin, vmax)
    return np.kron(img, np.ones((pixels, pixels, 1), dtype=np.uint8))


def grid(images, gap=4):
    """Rows of images (a list of lists of equal-sized RGB arrays) with white gaps."""
    h, w = images[0][0].shape[:2]
    rows, cols = len(images), max(len(r) for r in images)
    out = np.full((rows * h + (rows + 1) * gap, cols * w + (cols + 1) * gap, 3), 255, dtype=np.uint8)
    for r, row in enumerate(images):
        for c, im in enumerate(row):
            y, x = gap + r * (h + gap), gap + c * (w + gap)
            out[y:y + h, x:x + w] = im
    return out


def write(path, rgb):
    """An 8-bit RGB PNG."""
    rgb = np.ascontiguousarray(rgb, dtype=np.uint8)
    h, w = rgb.shape[:2]
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
