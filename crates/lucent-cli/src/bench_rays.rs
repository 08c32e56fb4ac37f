//! `lucent bench-rays`: the raybench ray-traversal benchmark
//! (`../shared/tools/raybench/SPEC.md`, protocol version 1), so that
//! lucent's mesh BVH can be compared with the Embree reference
//! (`embree_ref.cpp`) on bit-identical rays.
//!
//! Untimed: loading the mesh ([`lucent::tools::load_raybench_mesh`]), the
//! frame, generating the ray sets ([`rays`]) and printing. Timed: three
//! builds of a [`MeshBvh`] from scratch (median reported, the last one
//! traced), then for each set (primary, shadow, incoherent) one untimed
//! warm-up pass and five timed passes (median reported). A pass hands the
//! rays out in chunks of 4096 from a shared atomic counter to every thread of
//! a pool of N threads, traces them one at a time and records each result in
//! a preallocated array; with N = 1 it runs on the calling thread alone.

mod dump;
mod rays;

use crate::cli::BenchRaysArgs;
use lucent::geometry::{Ray, Vec3};
use lucent::mesh::TriangleMesh;
use lucent::shapes::MeshBvh;
use rayon::ThreadPool;
use rays::{Frame, RayRecord};
use serde_json::{json, Value};
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicUsize, Ordering};
use std::time::Instant;

/// Builds timed; the median is reported.
const BUILDS: usize = 3;
/// Rays handed out at a time.
const CHUNK: usize = 4096;

/// Runs `lucent bench-rays`.
pub fn run(args: &BenchRaysArgs) -> Result<(), String> {
    let mesh = lucent::tools::load_raybench_mesh(&args.mesh).map_err(|e| e.to_string())?;
    run_on_mesh(args, &mesh)
}

/// Runs the benchmark on `mesh`, loaded from `args.mesh`.
fn run_on_mesh(args: &BenchRaysArgs, mesh: &TriangleMesh) -> Result<(), String> {
    if mesh.triangle_count() == 0 {
        return Err(format!("{}: the mesh has no triangles", args.mesh));
    }
    let frame = Frame::new(&mesh.positions).ok_or_else(|| format!("{}: the mesh has no vertices", args.mesh))?;
    if !(frame.bmin.iter().chain(&frame.bmax).all(|v| v.is_finite()) && frame.diag.is_finite()) {
        return Err(format!("{}: the mesh has a vertex coordinate that is not a finite number", args.mesh));
    }

    let primary = rays::primary_rays(&frame);
    let incoherent = rays::incoherent_rays(&frame);

    // The build always runs inside a pool of N threads (MeshBvh::build uses
    // the current rayon pool, and outside one that would be the global
    // pool of all cores); tracing uses the pool only for N > 1.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .thread_name(|i| format!("bench-rays-{i}"))
        .build()
        .map_err(|e| format!("cannot start {} threads: {e}", args.threads))?;
    let tracers = (args.threads > 1).then_some(&pool);

    let mut primary_t = atomic_results(primary.len());
    if let Some(n) = args.dump_rays {
        let bvh = pool.install(|| MeshBvh::build(mesh));
        trace_closest(&bvh, &primary, &primary_t, tracers);
        let hit_t = load_all(&mut primary_t);
        let (shadow, shadow_source) = rays::shadow_rays(&frame, &primary, &hit_t);
        let sets = dump::DumpSets {
            mesh: &args.mesh,
            triangles: mesh.triangle_count(),
            frame: &frame,
            primary: &primary,
            primary_t: &hit_t,
            shadow: &shadow,
            shadow_source: &shadow_source,
            incoherent: &incoherent,
        };
        let stdout = std::io::stdout();
        let mut out = std::io::BufWriter::with_capacity(1 << 20, stdout.lock());
        return dump::write_dump(&mut out, &sets, n).map_err(|e| format!("cannot write to standard output: {e}"));
    }

    // Builds: each from scratch; the previous structure is freed before the
    // next one is timed, and the last one is traced.
    let mut build_times = Vec::with_capacity(BUILDS);
    let mut built = None;
    for _ in 0..BUILDS {
        drop(built.take());
        let start = Instant::now();
        let bvh = pool.install(|| MeshBvh::build(mesh));
        build_times.push(start.elapsed().as_secs_f64());
        built = Some(bvh);
    }
    let bvh = built.expect("at least one build");
    build_times.sort_by(f64::total_cmp);
    let passes = args.passes as usize;

    // Primary: the warm-up pass supplies the hits of the shadow rays.
    let primary_hits = trace_closest(&bvh, &primary, &primary_t, tracers);
    let primary_tsum = tsum(&primary_t);
    let hit_t = load_all(&mut primary_t);
    let (shadow, _) = rays::shadow_rays(&frame, &primary, &hit_t);
    drop(hit_t);
    let primary_times = timed_passes(
        "primary",
        passes,
        (primary_hits, primary_tsum),
        || trace_closest(&bvh, &primary, &primary_t, tracers),
        || tsum(&primary_t),
    )?;

    // Shadow: any hit.
    let occluded_flags: Vec<AtomicBool> = (0..shadow.len()).map(|_| AtomicBool::new(false)).collect();
    let shadow_occluded = trace_occluded(&bvh, &shadow, &occluded_flags, tracers);
    let shadow_times = timed_passes(
        "shadow",
        passes,
        (shadow_occluded, 0.0),
        || trace_occluded(&bvh, &shadow, &occluded_flags, tracers),
        || 0.0,
    )?;

    // Incoherent: closest hit.
    let incoherent_t = atomic_results(incoherent.len());
    let incoherent_hits = trace_closest(&bvh, &incoherent, &incoherent_t, tracers);
    let incoherent_tsum = tsum(&incoherent_t);
    let incoherent_times = timed_passes(
        "incoherent",
        passes,
        (incoherent_hits, incoherent_tsum),
        || trace_closest(&bvh, &incoherent, &incoherent_t, tracers),
        || tsum(&incoherent_t),
    )?;

    let report = Report {
        mesh: &args.mesh,
        triangles: mesh.triangle_count(),
        vertices: mesh.vertex_count(),
        threads: args.threads,
        passes,
        frame,
        build_times,
        accel_bytes: bvh.memory_bytes(),
        huge_pages: bvh.huge_pages_advised(),
        primary: SetResult { rays: primary.len(), count: primary_hits, tsum: primary_tsum, times: primary_times },
        shadow: SetResult { rays: shadow.len(), count: shadow_occluded, tsum: 0.0, times: shadow_times },
        incoherent: SetResult {
            rays: incoherent.len(),
            count: incoherent_hits,
            tsum: incoherent_tsum,
            times: incoherent_times,
        },
    };
    if args.json {
        say!("{}", report.json_line())
    } else {
        report.print_table()
    }
}

/// Exits on a command-line error. For `lucent bench-rays` the message is
/// one line on stderr (the first paragraph of clap's message, joined), with
/// clap's status 2; every other command, and `--help` / `--version`, exit
/// exactly as clap makes them.
pub fn exit_on_parse_error(e: clap::Error) -> ! {
    let bench_rays = std::env::args_os().nth(1).is_some_and(|a| a == "bench-rays");
    if !bench_rays || !e.use_stderr() {
        e.exit()
    }
    let text = e.to_string();
    let first: Vec<&str> = text.lines().map(str::trim).take_while(|l| !l.is_empty()).collect();
    eprintln!("{}", first.join(" "));
    std::process::exit(e.exit_code())
}

/// One result slot per ray, written by whichever thread traces the ray
/// (relaxed atomic stores are plain stores on x86-64).
fn atomic_results(n: usize) -> Vec<AtomicU32> {
    (0..n).map(|_| AtomicU32::new(0)).collect()
}

/// The distances stored in `slots`.
fn load_all(slots: &mut [AtomicU32]) -> Vec<f32> {
    slots.iter_mut().map(|t| f32::from_bits(*t.get_mut())).collect()
}

/// The checksum of SPEC.md section 6: the sum of `t` over the hits, in f64,
/// in increasing ray index (so it does not depend on the thread count).
fn tsum(t: &[AtomicU32]) -> f64 {
    let mut sum = 0.0;
    for slot in t {
        let t = f32::from_bits(slot.load(Ordering::Relaxed));
        if t < f32::INFINITY {
            sum += f64::from(t);
        }
    }
    sum
}

/// Runs `body(begin, end)` over `0..n` in chunks of [`CHUNK`] consecutive
/// indices pulled in order from a shared atomic counter, on every thread of
/// `pool`, or on the calling thread alone without one. Returns the sum of
/// what `body` returned.
fn for_each_chunk(n: usize, pool: Option<&ThreadPool>, body: impl Fn(usize, usize) -> u64 + Sync) -> u64 {
    let next = AtomicUsize::new(0);
    let worker = || {
        let mut total = 0;
        loop {
            let begin = next.fetch_add(CHUNK, Ordering::Relaxed);
            if begin >= n {
                break total;
            }
            total += body(begin, n.min(begin + CHUNK));
        }
    };
    match pool {
        None => worker(),
        Some(pool) => pool.broadcast(|_| worker()).into_iter().sum(),
    }
}

#[inline(always)]
fn to_ray(r: &RayRecord) -> Ray {
    Ray::new(Vec3::from_array(r.o), Vec3::from_array(r.d))
}

/// Closest hit for every ray; stores `t` (`+inf` for a miss) and returns the
/// number of hits.
fn trace_closest(bvh: &MeshBvh, rays: &[RayRecord], t_out: &[AtomicU32], pool: Option<&ThreadPool>) -> u64 {
    for_each_chunk(rays.len(), pool, |begin, end| {
        let mut hits = 0;
        for (ray, slot) in rays[begin..end].iter().zip(&t_out[begin..end]) {
            let t = match bvh.intersect(&to_ray(ray), ray.tnear, ray.tfar) {
                Some(hit) => {
                    hits += 1;
                    hit.t
                }
                None => f32::INFINITY,
            };
            slot.store(t.to_bits(), Ordering::Relaxed);
        }
        hits
    })
}

/// Any hit for every ray; stores the occluded flag and returns the number
/// of occluded rays.
fn trace_occluded(bvh: &MeshBvh, rays: &[RayRecord], out: &[AtomicBool], pool: Option<&ThreadPool>) -> u64 {
    for_each_chunk(rays.len(), pool, |begin, end| {
        let mut occluded = 0;
        for (ray, slot) in rays[begin..end].iter().zip(&out[begin..end]) {
            let o = bvh.occluded(&to_ray(ray), ray.tnear, ray.tfar);
            occluded += u64::from(o);
            slot.store(o, Ordering::Relaxed);
        }
        occluded
    })
}

/// Times `passes` runs of `pass` (which returns its hit count) after the
/// warm-up pass that gave `warm` = (count, checksum). Tracing is
/// deterministic, so every pass must give the same count and checksum
/// (checked outside the timed region); anything else is an error. Returns
/// the pass times in seconds, sorted.
fn timed_passes(
    set: &str,
    passes: usize,
    warm: (u64, f64),
    mut pass: impl FnMut() -> u64,
    mut checksum: impl FnMut() -> f64,
) -> Result<Vec<f64>, String> {
    let mut times = Vec::with_capacity(passes);
    for i in 1..=passes {
        let start = Instant::now();
        let count = pass();
        times.push(start.elapsed().as_secs_f64());
        let sum = checksum();
        if count != warm.0 || sum.to_bits() != warm.1.to_bits() {
            return Err(format!(
                "{set} rays: timed pass {i} counted {count} (checksum {sum:?}), the warm-up pass {} (checksum {:?}): \
                 tracing is not deterministic",
                warm.0, warm.1
            ));
        }
    }
    times.sort_by(f64::total_cmp);
    Ok(times)
}

/// The median of sorted `times` (the upper one for an even count, as the
/// reference takes it).
fn median(sorted: &[f64]) -> f64 {
    sorted[sorted.len() / 2]
}

/// `x` rounded to `digits` significant decimal digits (as C's `%.{digits}g`
/// prints it, read back).
fn significant(x: f64, digits: usize) -> f64 {
    format!("{:.*e}", digits.saturating_sub(1), x).parse().unwrap_or(x)
}

/// `x` printed in plain decimal notation with `digits` significant digits.
fn significant_digits(x: f64, digits: i32) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    let decimals = (digits - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

/// Millions of rays per second, rounded to 3 decimals as the reference
/// prints them.
fn mrays(rays: usize, seconds: f64) -> f64 {
    if rays == 0 {
        return 0.0;
    }
    let v = rays as f64 / seconds.max(1e-9) / 1e6;
    format!("{v:.3}").parse().unwrap_or(v)
}

/// The measurements of one ray set.
struct SetResult {
    rays: usize,
    /// Hits, or occluded rays.
    count: u64,
    tsum: f64,
    /// Pass times, sorted.
    times: Vec<f64>,
}

impl SetResult {
    fn mrays(&self) -> f64 {
        mrays(self.rays, median(&self.times))
    }
    /// [min, max] Mrays/s over the passes.
    fn mrays_range(&self) -> [f64; 2] {
        [mrays(self.rays, self.times[self.times.len() - 1]), mrays(self.rays, self.times[0])]
    }
}

struct Report<'a> {
    mesh: &'a str,
    triangles: usize,
    vertices: usize,
    threads: usize,
    passes: usize,
    frame: Frame,
    /// Sorted.
    build_times: Vec<f64>,
    accel_bytes: usize,
    /// Whether the structure's memory was advised for huge pages.
    huge_pages: bool,
    primary: SetResult,
    shadow: SetResult,
    incoherent: SetResult,
}

impl Report<'_> {
    /// `[bmin.x, bmin.y, bmin.z, bmax.x, bmax.y, bmax.z]` with 9 significant
    /// digits: the reference's decimals, which give back the f32 values.
    fn bbox(&self) -> [f64; 6] {
        let f = &self.frame;
        [f.bmin[0], f.bmin[1], f.bmin[2], f.bmax[0], f.bmax[1], f.bmax[2]].map(|v| significant(f64::from(v), 9))
    }

    /// The JSON line of SPEC.md section 6: the required keys first, then
    /// the optional ones, in the reference's order.
    fn json_line(&self) -> String {
        let b = &self.build_times;
        let fields: Vec<(&str, Value)> = vec![
            ("implementation", json!(format!("lucent-{}", env!("CARGO_PKG_VERSION")))),
            ("mesh", json!(self.mesh)),
            ("triangles", json!(self.triangles)),
            ("threads", json!(self.threads)),
            ("build_s", json!(significant(median(b), 4))),
            ("primary_mrays", json!(self.primary.mrays())),
            ("primary_hits", json!(self.primary.count)),
            ("primary_tsum", json!(self.primary.tsum)),
            ("shadow_rays", json!(self.shadow.rays)),
            ("shadow_mrays", json!(self.shadow.mrays())),
            ("shadow_occluded", json!(self.shadow.count)),
            ("incoherent_mrays", json!(self.incoherent.mrays())),
            ("incoherent_hits", json!(self.incoherent.count)),
            ("incoherent_tsum", json!(self.incoherent.tsum)),
            ("vertices", json!(self.vertices)),
            ("bbox", json!(self.bbox())),
            (
                "api",
                json!(format!(
                    "MeshBvh::intersect/occluded (binned-SAH eight-wide BVH, watertight triangle test, {} build), one ray at a time",
                    lucent::accel::traversal_isa()
                )),
            ),
            ("accel_bytes", json!(self.accel_bytes)),
            ("huge_pages", json!(self.huge_pages)),
            ("build_s_range", json!([significant(b[0], 4), significant(b[b.len() - 1], 4)])),
            ("primary_mrays_range", json!(self.primary.mrays_range())),
            ("shadow_mrays_range", json!(self.shadow.mrays_range())),
            ("incoherent_mrays_range", json!(self.incoherent.mrays_range())),
            ("passes", json!(self.passes)),
        ];
        let body: Vec<String> = fields.iter().map(|(k, v)| format!("{}:{v}", Value::from(*k))).collect();
        format!("{{{}}}", body.join(","))
    }

    /// The same figures as a table for a person.
    fn print_table(&self) -> Result<(), String> {
        let b = &self.build_times;
        let [x0, y0, z0, x1, y1, z1] = self.bbox();
        say!(
            "{}: {} triangles, {} vertices, bbox ({x0}, {y0}, {z0}) to ({x1}, {y1}, {z1})",
            self.mesh,
            self.triangles,
            self.vertices
        )?;
        say!(
            "lucent-{} ({} traversal), {} thread{}: build {:.4} s (median of {BUILDS}, {:.4} to {:.4}), {:.1} MB ({:.1} bytes/triangle{})",
            env!("CARGO_PKG_VERSION"),
            lucent::accel::traversal_isa(),
            self.threads,
            if self.threads == 1 { "" } else { "s" },
            median(b),
            b[0],
            b[b.len() - 1],
            self.accel_bytes as f64 / 1e6,
            self.accel_bytes as f64 / self.triangles as f64,
            if self.huge_pages { ", advised for huge pages" } else { "" }
        )?;
        say!(
            "{:<11} {:>9} {:>9} {:>9} {:>19}  {}",
            "ray set",
            "rays",
            "hits",
            "Mrays/s",
            format!("(range of {})", self.passes),
            "sum of t over hits"
        )?;
        let rows =
            [("primary", &self.primary, true), ("shadow", &self.shadow, false), ("incoherent", &self.incoherent, true)];
        for (name, set, closest) in rows {
            let [lo, hi] = set.mrays_range();
            say!(
                "{:<11} {:>9} {:>9} {:>9.3} {:>19}  {}",
                name,
                set.rays,
                set.count,
                set.mrays(),
                format!("({lo:.3} to {hi:.3})"),
                if closest { significant_digits(set.tsum, 17) } else { "(occluded, any hit)".to_owned() }
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_as_the_reference_prints() {
        assert_eq!(significant(0.123456789, 4), 0.1235);
        assert_eq!(significant(-0.0946899965405, 9), -0.0946899965);
        assert_eq!(significant(1.0, 9), 1.0);
        assert_eq!(significant_digits(93671.99748243392, 17), "93671.997482433915");
        assert_eq!(significant_digits(0.5, 3), "0.500");
        assert_eq!(significant_digits(1234567.0, 3), "1234567");
        assert_eq!(significant_digits(0.0, 17), "0");
        assert_eq!(mrays(1_048_576, 0.1), 10.486);
        assert_eq!(mrays(0, 0.0), 0.0);
        assert!(mrays(5, 0.0).is_finite());
    }

    #[test]
    fn chunks_cover_every_index_once() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        for n in [0, 1, CHUNK - 1, CHUNK, CHUNK + 1, 10 * CHUNK + 17] {
            let seen: Vec<AtomicU32> = atomic_results(n);
            for p in [None, Some(&pool)] {
                let total = for_each_chunk(n, p, |b, e| {
                    assert!(e - b <= CHUNK && b % CHUNK == 0);
                    for s in &seen[b..e] {
                        s.fetch_add(1, Ordering::Relaxed);
                    }
                    (e - b) as u64
                });
                assert_eq!(total, n as u64);
            }
            assert!(seen.iter().all(|s| s.load(Ordering::Relaxed) == 2));
        }
    }

    #[test]
    fn timed_passes_reject_a_changing_count() {
        let mut n = 0;
        let e = timed_passes(
            "primary",
            3,
            (10, 1.5),
            || {
                n += 1;
                if n == 2 {
                    11
                } else {
                    10
                }
            },
            || 1.5,
        )
        .unwrap_err();
        assert!(e.contains("timed pass 2 counted 11") && e.contains("warm-up pass 10"), "{e}");
        assert!(timed_passes("shadow", 2, (3, 0.0), || 3, || 0.0).unwrap().len() == 2);
        assert!(timed_passes("incoherent", 1, (3, 2.0), || 3, || 2.5).is_err());
    }
}
