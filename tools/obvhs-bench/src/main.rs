//! The raybench protocol (`../shared/tools/raybench/SPEC.md`) run on the
//! `obvhs` crate's compressed eight-wide BVH (CWBVH, Ylitie et al. 2017),
//! so that lucent's own BVH can be compared with a well-kept Rust crate on
//! the same rays. One thread (obvhs is built without its `parallel`
//! feature), one ray at a time, the crate's own Möller–Trumbore triangle
//! test and `medium_build` preset: what a user of the crate would write.
//!
//! ```sh
//! cd tools/obvhs-bench && cargo run --release -- ../../../shared/data/bunny/bun_zipper.ply
//! ```
//!
//! It prints one JSON line with the protocol's keys, which
//! `compare.py` reads beside `lucent bench-rays --json` and `embree_ref`.
//! Not part of the workspace: CI does not build it.

// The ray generation of `lucent bench-rays`, shared file, bit-identical rays.
#[path = "../../../crates/lucent-cli/src/bench_rays/rays.rs"]
#[allow(dead_code)]
mod rays;

use obvhs::{cwbvh::builder::build_cwbvh_from_tris, ray::Ray, ray::RayHit, triangle::Triangle, BvhBuildParams};
use rays::{Frame, RayRecord};
use std::time::{Duration, Instant};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn to_ray(r: &RayRecord) -> Ray {
    Ray::new(glam::Vec3A::from_array(r.o), glam::Vec3A::from_array(r.d), r.tnear, r.tfar)
}

/// One untimed pass then five timed ones; returns (per-ray results of the
/// last pass, median Mrays/s).
fn passes<T>(rays: &[RayRecord], mut trace: impl FnMut(&RayRecord) -> T) -> (Vec<T>, f64) {
    let mut out: Vec<T> = rays.iter().map(&mut trace).collect();
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = Instant::now();
        out = rays.iter().map(&mut trace).collect();
        times.push(start.elapsed().as_secs_f64());
    }
    (out, rays.len() as f64 / median(times) / 1e6)
}

fn main() {
    let fail = |msg: String| -> ! {
        eprintln!("obvhs-bench: {msg}");
        std::process::exit(1)
    };
    let arg = std::env::args().nth(1).unwrap_or_else(|| fail("usage: obvhs-bench MESH".into()));
    let mesh = lucent::tools::load_raybench_mesh(&arg).unwrap_or_else(|e| fail(e.to_string()));
    if mesh.triangle_count() == 0 {
        fail(format!("{arg}: the mesh has no triangles"));
    }
    let frame = Frame::new(&mesh.positions).unwrap_or_else(|| fail(format!("{arg}: the mesh has no vertices")));
    let primary = rays::primary_rays(&frame);
    let incoherent = rays::incoherent_rays(&frame);

    // Build: the conversion to the crate's triangles is part of it, as
    // lucent's copy into triangle blocks is part of its build.
    let mut build_times = Vec::new();
    let mut built = None;
    for _ in 0..3 {
        drop(built.take());
        let start = Instant::now();
        let tris: Vec<Triangle> = (0..mesh.triangle_count())
            .map(|i| {
                let [a, b, c] = mesh.triangle(i).map(|p| glam::Vec3A::from_array(p.to_array()));
                Triangle { v0: a, v1: b, v2: c }
            })
            .collect();
        let bvh = build_cwbvh_from_tris(&tris, BvhBuildParams::medium_build(), &mut Duration::default());
        build_times.push(start.elapsed().as_secs_f64());
        built = Some((tris, bvh));
    }
    let (tris, bvh) = built.expect("three builds");
    let bytes = bvh.nodes.len() * std::mem::size_of_val(&bvh.nodes[0])
        + bvh.primitive_indices.len() * 4
        + tris.len() * std::mem::size_of::<Triangle>();

    let closest = |r: &RayRecord| {
        let mut hit = RayHit::none();
        bvh.ray_traverse(to_ray(r), &mut hit, |ray, id| tris[bvh.primitive_indices[id] as usize].intersect(ray));
        hit.t
    };
    let tsum = |t: &[f32]| t.iter().filter(|t| t.is_finite()).map(|&t| f64::from(t)).sum::<f64>();
    let (primary_t, primary_mrays) = passes(&primary, closest);
    let (shadow, _) = rays::shadow_rays(&frame, &primary, &primary_t);
    let (occluded, shadow_mrays) = passes(&shadow, |r| {
        !bvh.ray_traverse_miss(to_ray(r), |ray, id| tris[bvh.primitive_indices[id] as usize].intersect(ray))
    });
    let (incoherent_t, incoherent_mrays) = passes(&incoherent, closest);

    let line = serde_json::json!({
        "implementation": "obvhs-0.3.3",
        "mesh": arg,
        "triangles": mesh.triangle_count(),
        "threads": 1,
        "build_s": median(build_times),
        "primary_mrays": primary_mrays,
        "primary_hits": primary_t.iter().filter(|t| t.is_finite()).count(),
        "primary_tsum": tsum(&primary_t),
        "shadow_rays": shadow.len(),
        "shadow_mrays": shadow_mrays,
        "shadow_occluded": occluded.iter().filter(|&&o| o).count(),
        "incoherent_mrays": incoherent_mrays,
        "incoherent_hits": incoherent_t.iter().filter(|t| t.is_finite()).count(),
        "incoherent_tsum": tsum(&incoherent_t),
        "vertices": mesh.positions.len(),
        "accel_bytes": bytes,
        "api": "CwBvh::ray_traverse / ray_traverse_miss, BvhBuildParams::medium_build, Triangle::intersect (Moller-Trumbore)",
    });
    println!("{line}");
}
