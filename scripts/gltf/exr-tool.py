"""Look at reference EXRs with Blender's image I/O (no other Python packages).

    blender -b --factory-startup --python scripts/gltf/exr-tool.py -- png IN.exr OUT.png [EXPOSURE]
    blender -b --factory-startup --python scripts/gltf/exr-tool.py -- compare A.exr B.exr
    blender -b --factory-startup --python scripts/gltf/exr-tool.py -- montage OUT.png COLUMNS IN.png ...

png: an 8-bit sRGB preview of a linear image (clipped at 1; EXPOSURE in
stops, default 0). compare: per-channel means of both, and of |A - B|, the
relative mean difference sum|A - B| / sum|B| and the RMSE, over RGB; both
images must have the same size. montage: tiles same-size PNGs row by row.
"""

import sys

try:
    import bpy
    import numpy as np
except ImportError:
    sys.exit("exr-tool.py runs inside Blender (Debian: apt-get install -y blender)\n" + __doc__)


def load(path):
    """H x W x 4 float32, row 0 = top."""
    img = bpy.data.images.load(path)
    w, h = img.size
    if w == 0:
        sys.exit(f"exr-tool.py: cannot read {path}")
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1]


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def save_png(path, rgba):
    """rgba: H x W x 4 in [0, 1], display values, row 0 = top."""
    h, w, _ = rgba.shape
    img = bpy.data.images.new("out", w, h, alpha=True)
    img.pixels.foreach_set(np.ascontiguousarray(rgba[::-1], dtype=np.float32).ravel())
    img.filepath_raw = path
    img.file_format = 'PNG'
    img.save()
    bpy.data.images.remove(img)


def main(argv):
    if not argv:
        sys.exit(__doc__)
    cmd, args = argv[0], argv[1:]
    if cmd == "png" and len(args) in (2, 3):
        px = load(args[0])
        scale = 2.0 ** float(args[2]) if len(args) == 3 else 1.0
        out = np.concatenate([srgb(px[..., :3] * scale), np.ones_like(px[..., :1])], axis=-1)
        save_png(args[1], out)
    elif cmd == "compare" and len(args) == 2:
        a, b = (load(p)[..., :3].astype(np.float64) for p in args)
        if a.shape != b.shape:
            sys.exit(f"exr-tool.py: sizes differ: {a.shape[1]}x{a.shape[0]} and {b.shape[1]}x{b.shape[0]}")
        d = np.abs(a - b)
        fmt = lambda v: "(" + ", ".join(f"{x:.5f}" for x in v) + ")"
        print(f"mean A {fmt(a.mean(axis=(0, 1)))}  mean B {fmt(b.mean(axis=(0, 1)))}")
        print(f"mean |A-B| {fmt(d.mean(axis=(0, 1)))}  relative {d.sum() / max(np.abs(b).sum(), 1e-30):.5f}"
              f"  RMSE {np.sqrt((d ** 2).mean()):.5f}")
    elif cmd == "montage" and len(args) >= 3:
        out, cols, files = args[0], int(args[1]), args[2:]
        tiles = [load(p) for p in files]
        h, w, _ = tiles[0].shape
        if any(t.shape != tiles[0].shape for t in tiles):
            sys.exit("exr-tool.py: montage needs images of one size")
        rows = (len(tiles) + cols - 1) // cols
        canvas = np.ones((rows * h, cols * w, 4), dtype=np.float32)
        for i, t in enumerate(tiles):
            r, c = divmod(i, cols)
            canvas[r * h:(r + 1) * h, c * w:(c + 1) * w] = t
        save_png(out, canvas)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
