#!/usr/bin/env python3
"""Mitsuba 3's ray queries on the Cornell box, for the time budget of a path sample (issue 11, goal 1).

Loads `../shared/references/cornell-box/scene-mitsuba3.xml` with the
`llvm_ad_rgb` variant, writes its triangles as one binary PLY file (so that
`lucent bench-rays` and Embree's `embree_ref` can trace the same geometry
under the raybench protocol), and times Mitsuba's three queries on 2^22
rays drawn like raybench's incoherent set (origins uniform in the scene's
bounding box, directions uniform on the sphere), each query one Dr.Jit
kernel over all rays:

* `closest`: `scene.ray_intersect_preliminary` (distance and primitive);
* `full`: `scene.ray_intersect` with the surface interaction a path tracer
  reads (position, normals, shading frame, uv);
* `any`: `scene.ray_test` (shadow rays).

Each query runs ROUNDS times on fresh rays; the first round compiles the
kernels and is left out of the medians. Set-up as for
`scripts/bench-mitsuba.py` (Debian's `libllvm19`, a virtual environment with
`pip install mitsuba numpy`):

    target/mi-venv/bin/python scripts/mitsuba-rays.py --ply target/cornell.ply
    target/release/lucent bench-rays target/cornell.ply
"""

import argparse
import os
import time
from pathlib import Path

SCENE = Path("../shared/references/cornell-box/scene-mitsuba3.xml")
LLVM = Path("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")


def write_ply(scene, path):
    """All triangles of `scene`'s meshes, merged, as binary little-endian PLY."""
    import numpy as np

    positions, faces, offset = [], [], 0
    for shape in scene.shapes():
        v = np.array(shape.vertex_positions_buffer(), dtype="<f4").reshape(-1, 3)
        f = np.array(shape.faces_buffer(), dtype="<i4").reshape(-1, 3) + offset
        positions.append(v)
        faces.append(f)
        offset += len(v)
    v, f = np.concatenate(positions), np.concatenate(faces)
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    rows = np.zeros(len(f), dtype=[("n", "u1"), ("i", "<i4", 3)])
    rows["n"], rows["i"] = 3, f
    with open(path, "wb") as out:
        out.write(header.encode())
        out.write(v.tobytes())
        out.write(rows.tobytes())
    print(f"wrote {path}: {len(v)} vertices, {len(f)} triangles")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--threads", type=int, default=1, help="Dr.Jit worker threads (default 1)")
    parser.add_argument("--rounds", type=int, default=6, help="rounds per query, the first one not counted")
    parser.add_argument("--rays", type=int, default=1 << 22, help="rays per query")
    parser.add_argument("--ply", type=Path, help="also write the scene's triangles to this PLY file")
    args = parser.parse_args()
    if args.rounds < 2 or args.rays < 1 or args.threads < 1:
        parser.error("--rounds must be at least 2, --rays and --threads at least 1")
    if not SCENE.is_file():
        parser.error(f"{SCENE} not found: run from the repository root, beside ../shared")
    if "DRJIT_LIBLLVM_PATH" not in os.environ and LLVM.is_file():
        os.environ["DRJIT_LIBLLVM_PATH"] = str(LLVM)
    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError:
        parser.error("Mitsuba 3 is not installed in this interpreter: run it with the virtual "
                     "environment's python that has `pip install mitsuba numpy`")
    mi.set_variant("llvm_ad_rgb")
    dr.set_thread_count(args.threads)
    scene = mi.load_file(str(SCENE))
    if args.ply:
        write_ply(scene, args.ply)

    n, bbox = args.rays, scene.bbox()
    extent = bbox.max - bbox.min

    def rays(seed):
        rng = mi.PCG32(size=n, initstate=seed)
        o = mi.Point3f(bbox.min.x + rng.next_float32() * extent.x,
                       bbox.min.y + rng.next_float32() * extent.y,
                       bbox.min.z + rng.next_float32() * extent.z)
        z = 1 - 2 * rng.next_float32()
        r, phi = dr.safe_sqrt(1 - z * z), 2 * dr.pi * rng.next_float32()
        return mi.Ray3f(o, mi.Vector3f(r * dr.cos(phi), r * dr.sin(phi), z))

    queries = {
        "closest": lambda ray: dr.eval(scene.ray_intersect_preliminary(ray).t),
        "full": lambda ray: (lambda si: dr.eval(si.p, si.n, si.sh_frame.n, si.uv, si.t))(scene.ray_intersect(ray)),
        "any": lambda ray: dr.eval(scene.ray_test(ray)),
    }
    speeds = {k: [] for k in queries}
    for round_ in range(args.rounds):
        for i, (name, query) in enumerate(queries.items()):
            ray = rays(1000 * round_ + i)
            dr.eval(ray)
            start = time.perf_counter()
            query(ray)
            speeds[name].append(n / (time.perf_counter() - start) / 1e6)
    for name, v in speeds.items():
        v = sorted(v[1:])
        print(f"mitsuba {name}: median {v[len(v) // 2]:.2f} Mrays/s ({', '.join(f'{x:.2f}' for x in v)})")


if __name__ == "__main__":
    main()
