#!/usr/bin/env python3
"""Render Benedikt Bitterli's scene collection (its pbrt-v4 form) with lucent
and with pbrt-v4, compare the images, and write the table into
docs/pbrt-v4.md.

Nothing is fetched: give the path of a checkout of the collection (the
public repository gonsolo/bitterli, whose scenes are */pbrt/scene-v4.pbrt)
and of a pbrt-v4 binary (../shared/tools/pbrt-v4/build.sh builds one).
Only the Python standard library is used.

For each scene:

1. A work copy is made under --out: every file of the scene's pbrt folder
   linked, the scene file copied with its film resolution reduced to
   --width (same aspect ratio). Files the scene names that the checkout
   lacks (some large files are missing from public snapshots) are replaced
   by the same stand-ins for both renderers: a grey 4x4 image for a
   texture (a 64x64 square for PFM, which may be an environment map), a
   tiny far-away triangle for a PLY mesh, an empty file for a .pbrt
   include. The stand-ins used are listed in the table.
2. pbrt-v4 renders it with its own integrator (bdpt, sppm, volpath, path)
   at --spp samples per pixel, lucent with its path tracer; each twice,
   with two seeds (the second renders only measure each one's noise).
3. `lucent diff` compares: the mean of each channel (lucent / pbrt), and
   the relative MSE of 8x8 block means (noise shrinks in block means, a
   real difference in brightness does not).

A scene passes when lucent's mean luminance is within 5% of pbrt-v4's and
the block relMSE against pbrt-v4 is at most twice the noise of two
independent renders (measured: each renderer renders twice, with two
seeds, and each self-comparison holds its noise twice).

Usage:
  python3 scripts/bitterli.py --bitterli ~/bitterli --pbrt /tmp/pbrt-build/build/pbrt \\
      [--lucent target/release/lucent] [--out /tmp/bitterli-compare] [--width 400] \\
      [--spp 16] [--threads 2] [--scenes cornell-box,veach-mis] [--write-docs]
"""

import argparse
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import time
import zlib

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(REPO, "docs", "pbrt-v4.md")
START, END = "<!-- bitterli:start -->", "<!-- bitterli:end -->"

# A file name in a parameter list: "string filename" "x" or [ "x" ].
FILENAME = re.compile(r'"string\s+filename"\s*\[?\s*"([^"]+)"')
INCLUDE = re.compile(r'^\s*(?:Include|Import)\s+"([^"]+)"', re.M)
DIRECTIVE = re.compile(r'^\s*([A-Z][A-Za-z]+)', re.M)
RESOLUTION = re.compile(r'("integer\s+([xy])resolution"\s*\[?\s*)(\d+)')

LUMINANCE = (0.2126, 0.7152, 0.0722)


def standin_tga(path, w=4, h=4, grey=128):
    header = bytes([0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0]) + struct.pack("<HH", w, h) + bytes([24, 0])
    with open(path, "wb") as f:
        f.write(header + bytes([grey, grey, grey]) * (w * h))


def standin_png(path, w=4, h=4, grey=128):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    rows = b"".join(b"\x00" + bytes([grey, grey, grey]) * w for _ in range(h))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def standin_pfm(path, n=64, value=0.5):
    # Square (an equal-area environment map must be), little-endian.
    with open(path, "wb") as f:
        f.write(f"PF\n{n} {n}\n-1.0\n".encode() + struct.pack("<3f", value, value, value) * (n * n))


def standin_ply(path):
    # One tiny triangle far below the scene: nothing to see, valid for both.
    with open(path, "w") as f:
        f.write(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
            "0 -1e5 0\n1e-3 -1e5 0\n0 -1e5 1e-3\n3 0 1 2\n"
        )


STANDINS = {
    ".tga": standin_tga,
    ".png": standin_png,
    ".pfm": standin_pfm,
    ".ply": standin_ply,
    ".pbrt": lambda p: open(p, "w").close(),
}


def referenced_files(scene_dir, name, seen):
    """Every file named by `name` (relative to scene_dir) and the files it
    includes, as paths relative to scene_dir."""
    path = os.path.join(scene_dir, name)
    if name in seen or not os.path.isfile(path) or not name.endswith(".pbrt"):
        return
    seen.add(name)
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    directives = [(d.start(), d.group(1)) for d in DIRECTIVE.finditer(text)]
    for m in list(FILENAME.finditer(text)) + list(INCLUDE.finditer(text)):
        ref = m.group(1)
        # The Film's filename is where pbrt writes, not a file it reads.
        before = [name for at, name in directives if at <= m.start()]
        if before and before[-1] == "Film":
            continue
        yield ref
        if ref.endswith(".pbrt"):
            yield from referenced_files(scene_dir, ref, seen)


def prepare(scene_dir, work, width):
    """The work copy of a scene (see the module docs); returns the scene
    file's path and the stand-ins made."""
    if os.path.isdir(work):
        shutil.rmtree(work)
    for root, _dirs, files in os.walk(scene_dir):
        rel = os.path.relpath(root, scene_dir)
        os.makedirs(os.path.join(work, rel), exist_ok=True)
        for f in files:
            os.symlink(os.path.join(root, f), os.path.join(work, rel, f))
    scene = os.path.join(work, "scene-v4.pbrt")
    os.unlink(scene)
    with open(os.path.join(scene_dir, "scene-v4.pbrt"), encoding="utf-8", errors="replace") as f:
        text = f.read()
    res = {m.group(2): int(m.group(3)) for m in RESOLUTION.finditer(text)}
    x, y = res.get("x", 1280), res.get("y", 720)
    new = {"x": width, "y": max(1, round(width * y / x))}
    text = RESOLUTION.sub(lambda m: m.group(1) + str(new[m.group(2)]), text)
    if not res:
        print(f"  note: no film resolution in the file; rendered at pbrt's default", file=sys.stderr)
    with open(scene, "w", encoding="utf-8") as f:
        f.write(text)
    standins = []
    for ref in sorted(set(referenced_files(scene_dir, "scene-v4.pbrt", set()))):
        target = os.path.join(work, ref)
        if os.path.exists(target):
            continue
        # By the name's ending (a name such as "models/.pbrt" has no
        # extension for os.path.splitext).
        make = next((f for ext, f in STANDINS.items() if ref.lower().endswith(ext)), None)
        if make is None:
            standins.append(f"{ref} (absent, no stand-in)")
            continue
        os.makedirs(os.path.dirname(target), exist_ok=True)
        make(target)
        standins.append(ref)
    return scene, standins


def run(cmd, cwd, timeout):
    start = time.time()
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, f"timed out after {timeout} s", time.time() - start
    if p.returncode != 0:
        lines = [l for l in (p.stderr + p.stdout).splitlines() if l.strip()]
        first = next((l for l in lines if "rror" in l), lines[0] if lines else f"exit {p.returncode}")
        return None, first.strip()[:160], time.time() - start
    return p, None, time.time() - start


def diff(lucent, a, b, cwd, side=None):
    cmd = [lucent, "diff", a, b, "--json", "--block", "8"]
    if side:
        cmd += ["--side-by-side", side]
    p, err, _ = run(cmd, cwd, 600)
    if err:
        raise RuntimeError(err)
    return json.loads(p.stdout)


def luminance(rgb):
    return sum(w * c for w, c in zip(LUMINANCE, rgb))


def compare_scene(name, args):
    scene_dir = os.path.join(args.bitterli, name, "pbrt")
    work = os.path.join(args.out, name)
    scene, standins = prepare(scene_dir, work, args.width)
    row = {"scene": name, "standins": standins}
    with open(scene, encoding="utf-8", errors="replace") as f:
        m = re.search(r'^\s*Integrator\s+"(\w+)"', f.read(), re.M)
    row["integrator"] = m.group(1) if m else "volpath"
    pbrt_outs = []
    for seed in (1, 2):
        out = os.path.join(work, f"pbrt-{seed}.exr")
        cmd = [args.pbrt, "--nthreads", str(args.threads), "--spp", str(args.spp), "--seed", str(seed)]
        _, err, t = run(cmd + ["--outfile", out, "scene-v4.pbrt"], work, args.timeout)
        if err:
            row["error"] = f"pbrt-v4: {err}"
            return row
        if seed == 1:
            row["pbrt_s"] = t
        pbrt_outs.append(out)
    pbrt_out = pbrt_outs[0]
    outs = []
    for seed in (1, 2):
        out = os.path.join(work, f"lucent-{seed}.exr")
        cmd = [args.lucent, "render", "scene-v4.pbrt", "--spp", str(args.spp), "--threads", str(args.threads)]
        # The first render without --quiet: its warnings say what lucent
        # does not render.
        cmd += ["--seed", str(seed), "-o", out] + (["--quiet"] if seed == 2 else [])
        p, err, t = run(cmd, work, args.timeout)
        if err:
            row["error"] = f"lucent: {err}"
            return row
        if seed == 1:
            row["lucent_s"] = t
            warnings = [l for l in p.stderr.splitlines() if l.startswith("warning:")]
            row["warnings"] = len(warnings)
            # What lucent does not render (the message after the location).
            row["unsupported"] = sorted({w.split(": ", 2)[-1][:100] for w in warnings if "not supported" in w})
        outs.append(out)
    d = diff(args.lucent, outs[0], pbrt_out, work, side=os.path.join(work, "lucent-vs-pbrt.png"))
    noise_lucent = diff(args.lucent, outs[0], outs[1], work)["block_rel_mse"]
    noise_pbrt = diff(args.lucent, pbrt_outs[0], pbrt_outs[1], work)["block_rel_mse"]
    row["mean"], row["mean_pbrt"] = d["mean"], d["mean_reference"]
    row["block_rel_mse"] = d["block_rel_mse"]
    # Each self-comparison holds its renderer's noise twice; two
    # independent renders differ by the sum of their noises.
    row["noise"] = (noise_lucent + noise_pbrt) / 2
    row["noise_lucent"], row["noise_pbrt"] = noise_lucent, noise_pbrt
    lp = luminance(d["mean_reference"])
    row["ratio"] = luminance(d["mean"]) / lp if lp > 0 else float("nan")
    row["pass"] = abs(row["ratio"] - 1) <= 0.05 and row["block_rel_mse"] <= 2 * max(row["noise"], 1e-6)
    if luminance(d["mean"]) == 0 and lp == 0:
        row["pass"] = None  # black in both: nothing to compare
    return row


def table(rows, args):
    out = [
        f"Rendered at {args.width} pixels wide, {args.spp} spp, {args.threads} threads "
        f"(`python3 scripts/bitterli.py --width {args.width} --spp {args.spp}`). "
        "*ratio*: lucent's mean luminance / pbrt-v4's; *block relMSE*: relative MSE of 8×8 block means, "
        "lucent against pbrt-v4; *noise*: what two independent renders differ by, from each renderer against "
        "itself with another seed ((lucent's + pbrt-v4's) / 2); *pass*: ratio within 5% and block relMSE at "
        "most twice the noise.",
        "",
        "| scene | pbrt integrator | ratio | mean r g b (lucent / pbrt) | block relMSE | noise | pass | lucent s | pbrt s | stand-ins |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        standins = len(r.get("standins", []))
        if "error" in r:
            out.append(f"| {r['scene']} | {r.get('integrator', '')} | | {r['error']} | | | no | | | {standins} |")
            continue
        means = " ".join(f"{a / b:.3f}" if b > 0 else "–" for a, b in zip(r["mean"], r["mean_pbrt"]))
        verdict = {True: "yes", False: "no", None: "– (black in both)"}[r["pass"]]
        if r.get("unsupported") and r["pass"] is not True:
            verdict += " (unsupported: " + "; ".join(r["unsupported"]) + ")"
        out.append(
            f"| {r['scene']} | {r['integrator']} | {r['ratio']:.3f} | {means} | {r['block_rel_mse']:.2e} | "
            f"{r['noise']:.2e} | {verdict} | {r['lucent_s']:.1f} | {r['pbrt_s']:.1f} | {standins} |"
        )
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bitterli", required=True, help="a checkout of gonsolo/bitterli")
    ap.add_argument("--pbrt", required=True, help="the pbrt-v4 binary")
    ap.add_argument("--lucent", default=os.path.join(REPO, "target", "release", "lucent"))
    ap.add_argument("--out", default=os.path.join(os.environ.get("TMPDIR", "/tmp"), "bitterli-compare"))
    ap.add_argument("--width", type=int, default=400)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--timeout", type=int, default=1800, help="seconds per render")
    ap.add_argument("--scenes", help="comma-separated names (default: every */pbrt/scene-v4.pbrt)")
    ap.add_argument("--write-docs", action="store_true", help=f"replace the table in {DOCS}")
    ap.add_argument(
        "--from-results", action="store_true", help="render nothing: make the table from --out's results.json"
    )
    args = ap.parse_args()
    if args.from_results:
        with open(os.path.join(os.path.abspath(args.out), "results.json")) as f:
            rows = json.load(f)
        finish(rows, args)
        return
    # Renders run in each scene's folder: make every path absolute.
    for key in ("bitterli", "pbrt", "lucent", "out"):
        setattr(args, key, os.path.abspath(getattr(args, key)))
    for what, path in (("--bitterli", args.bitterli), ("--pbrt", args.pbrt), ("--lucent", args.lucent)):
        if not os.path.exists(path):
            sys.exit(f"error: {what} {path} does not exist")
    names = sorted(
        n for n in os.listdir(args.bitterli) if os.path.isfile(os.path.join(args.bitterli, n, "pbrt", "scene-v4.pbrt"))
    )
    if args.scenes:
        wanted = args.scenes.split(",")
        unknown = [n for n in wanted if n not in names]
        if unknown:
            sys.exit(f"error: no such scene: {', '.join(unknown)} (scenes: {', '.join(names)})")
        names = wanted
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name in names:
        print(f"{name} ...", file=sys.stderr, flush=True)
        try:
            row = compare_scene(name, args)
        except (OSError, RuntimeError, ValueError) as e:
            row = {"scene": name, "error": str(e)[:160]}
        rows.append(row)
        print("  " + json.dumps(row), file=sys.stderr, flush=True)
    # A run of some scenes updates their rows in an earlier run's results.
    results = os.path.join(args.out, "results.json")
    if os.path.exists(results):
        with open(results) as f:
            done = {r["scene"]: r for r in json.load(f)}
        done.update({r["scene"]: r for r in rows})
        rows = [done[n] for n in sorted(done)]
    with open(results, "w") as f:
        json.dump(rows, f, indent=1)
    finish(rows, args)


def finish(rows, args):
    """Print the table of `rows`, and write it into the docs if asked."""
    text = table(rows, args)
    print(text)
    if args.write_docs:
        with open(DOCS, encoding="utf-8") as f:
            doc = f.read()
        if START not in doc or END not in doc:
            sys.exit(f"error: {DOCS} has no {START} … {END} section to replace")
        head, rest = doc.split(START, 1)
        _, tail = rest.split(END, 1)
        with open(DOCS, "w", encoding="utf-8") as f:
            f.write(head + START + "\n" + text + "\n" + END + tail)


if __name__ == "__main__":
    main()
