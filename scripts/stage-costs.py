#!/usr/bin/env python3
"""Where a path sample's cost goes, by stage (issue 28, goal 4).

Groups the self cost of every function in a profile into the stages of the
path tracer (ray queries, sample values, light sampling, BSDFs, film, ...)
and prints a Markdown table, one column per profile:

    # instructions per sample (callgrind; valgrind has no AVX-512)
    LUCENT_SIMD=avx2 valgrind --tool=callgrind --callgrind-out-file=cg.out \\
        lucent render scenes/cornell-box.toml --width 96 --height 96 --spp 32 --threads 1 -q
    scripts/stage-costs.py callgrind --samples 294912 cg.out

    # microseconds per sample (perf shares times user seconds per sample)
    perf record -e cpu-clock -o perf.data lucent render scenes/cornell-box.toml \\
        --width 256 --height 256 --spp 32 --threads 1 -q
    scripts/stage-costs.py perf --us-per-sample 2.51 perf.data
    # two builds: --us-per-sample 3.21,2.51 before.data after.data

Functions are matched by name, so what the compiler inlined is counted in
its caller: compare builds by the totals of a stage, and read the
per-stage split as approximate where inlining differs between builds.
"""

import argparse
import re
import subprocess

# (stage, regular expression on the function's name); the first match wins.
STAGES = [
    ("ray queries: traversal", r"MeshBvh::(intersect|occluded)"),
    ("ray queries: hit record", r"Mesh::hit_at|triangle_dpduv"),
    (
        "ray queries: dispatch and shadow-ray set-up",
        r"Primitive::intersect|Mesh::intersect|BvhAggregate|Shape::intersect|path::occluded|offset_ray_origin"
        r"|Scene::intersect",
    ),
    ("sample values", r"vertex_lanes|sobol_vertices|dimension_hash|Sampler::"),
    ("light sampling", r"AreaLight|Rectangle|SphericalRectangle|Emitter::|AliasTable|atan|LightSet|light_lanes::"),
    ("material and BSDF", r"Bxdf|Bsdf|BxDF|shading_frame|sincos|Material::|Texture::|concentric|cosine_hemisphere|scatter_lanes::"),
    ("film", r"SplatBand|Filter1d|floorf|Accumulator|film::"),
    ("camera and the render loop", r"Camera::|camera::|camera_lanes|sobol_camera|Fn<A> for &F|render::"),
    ("path loop (li / li_lanes itself, copies)", r"PathIntegrator|memmove|memcpy|memset"),
]
QUERY_STAGES = [name for name, _ in STAGES if name.startswith("ray queries")]


def stage_of(function):
    for name, pattern in STAGES:
        if re.search(pattern, function):
            return name
    return "other"


def callgrind_costs(path):
    """Self instructions per function, and the program total."""
    text = subprocess.run(
        ["callgrind_annotate", "--auto=no", "--threshold=100", path], capture_output=True, text=True, check=True
    ).stdout
    costs, total = [], None
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)", line)
        if not m:
            continue
        n, function = int(m.group(1).replace(",", "")), m.group(2)
        if "PROGRAM TOTALS" in function:
            total = n
        else:
            costs.append((n, function))
    return costs, total


def perf_shares(path):
    """Self percentage of the samples per function."""
    text = subprocess.run(
        ["perf", "report", "-i", path, "--no-children", "--stdio"], capture_output=True, text=True, check=True
    ).stdout
    shares = []
    for line in text.splitlines():
        m = re.match(r"\s+([\d.]+)%\s+\S+\s+\S+\s+\[[.k]\]\s+(.*)", line)
        if m:
            shares.append((float(m.group(1)), m.group(2)))
    return shares, 100.0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("kind", choices=["callgrind", "perf"], help="what the profiles are")
    parser.add_argument("profiles", nargs="+", help="callgrind.out files or perf.data files")
    parser.add_argument("--samples", type=float, help="callgrind: path samples the profiled render traced")
    parser.add_argument(
        "--us-per-sample",
        type=lambda v: [float(x) for x in v.split(",")],
        help="perf: user µs per sample of each profiled render, comma-separated, in order",
    )
    args = parser.parse_args()
    if args.kind == "callgrind" and not args.samples:
        parser.error("callgrind profiles need --samples")
    if args.kind == "perf" and (not args.us_per_sample or len(args.us_per_sample) != len(args.profiles)):
        parser.error("perf profiles need one --us-per-sample value each")

    columns = []
    for i, path in enumerate(args.profiles):
        costs, total = callgrind_costs(path) if args.kind == "callgrind" else perf_shares(path)
        # One sample's cost in the unit of the table: instructions, or µs.
        scale = 1.0 / args.samples if args.kind == "callgrind" else args.us_per_sample[i] / 100.0
        by_stage = {}
        for n, function in costs:
            by_stage[stage_of(function)] = by_stage.get(stage_of(function), 0.0) + n
        columns.append((by_stage, total, scale))

    unit = "{:,.0f}" if args.kind == "callgrind" else "{:.2f} µs"
    print("| stage | " + " | ".join(args.profiles) + " |")
    print("|---" * (len(args.profiles) + 1) + "|")
    for name in [name for name, _ in STAGES] + ["other"]:
        cells = [f"{unit.format(c.get(name, 0.0) * s)} ({100 * c.get(name, 0.0) / t:.1f}%)" for c, t, s in columns]
        print(f"| {name} | " + " | ".join(cells) + " |")
    queries = [sum(c.get(q, 0.0) for q in QUERY_STAGES) for c, _, _ in columns]
    print("| **ray queries** | " + " | ".join(unit.format(q * s) for q, (_, _, s) in zip(queries, columns)) + " |")
    print(
        "| **everything else** | "
        + " | ".join(unit.format((t - q) * s) for q, (_, t, s) in zip(queries, columns))
        + " |"
    )
    print("| **a sample** | " + " | ".join(unit.format(t * s) for _, t, s in columns) + " |")


if __name__ == "__main__":
    main()
