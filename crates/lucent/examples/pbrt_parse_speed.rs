//! How fast the pbrt-v4 parser reads: writes a large scene file (triangle
//! meshes with `point3 P`, `normal N`, `point2 uv` and `integer indices`
//! arrays, and many small directives) to a temporary directory, parses it
//! with `parse_file`, and prints the throughput.
//!
//! ```text
//! cargo run --release -p lucent --example pbrt_parse_speed [MEGABYTES] [--gz]
//! ```
//!
//! MEGABYTES defaults to 200; `--gz` also measures the file gzip-compressed.

use lucent::loader::pbrt::{parse_file_with_stats, Directive, ParamValues};
use std::fmt::Write as _;
use std::io::Write as _;
use std::time::Instant;

/// A small deterministic generator (xorshift64*), so that every run parses
/// the same file.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A number in [-10, 10) as an exporter prints it (6 decimals).
    fn coordinate(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
    }
}

/// One mesh of `n` vertices as pbrt-v4 text.
fn mesh(rng: &mut Rng, n: usize, out: &mut String) {
    out.push_str("AttributeBegin\n  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.4 0.3 ]\n");
    let _ = writeln!(out, "  Translate {:.3} {:.3} {:.3}", rng.coordinate(), rng.coordinate(), rng.coordinate());
    out.push_str("  Shape \"trianglemesh\"\n    \"point3 P\" [");
    for i in 0..3 * n {
        let _ = write!(out, " {:.6}", rng.coordinate());
        if i % 12 == 11 {
            out.push_str("\n     ");
        }
    }
    out.push_str(" ]\n    \"normal N\" [");
    for i in 0..3 * n {
        let _ = write!(out, " {:.5}", rng.coordinate() / 10.0);
        if i % 12 == 11 {
            out.push('\n');
        }
    }
    out.push_str(" ]\n    \"point2 uv\" [");
    for _ in 0..2 * n {
        let _ = write!(out, " {:.4}", (rng.coordinate() + 10.0) / 20.0);
    }
    out.push_str(" ]\n    \"integer indices\" [");
    for i in 0..3 * n {
        let _ = write!(out, " {}", rng.next() % n as u64);
        if i % 24 == 23 {
            out.push('\n');
        }
    }
    out.push_str(" ]\nAttributeEnd\n");
    // Many small directives between the meshes.
    for k in 0..50 {
        let _ = writeln!(
            out,
            "AttributeBegin # sphere {k}\n  Translate {:.2} {:.2} {:.2}\n  Shape \"sphere\" \"float radius\" [ 0.5 ]\n  \
             NamedMaterial \"m{k}\"\nAttributeEnd",
            rng.coordinate(),
            rng.coordinate(),
            rng.coordinate()
        );
    }
}

/// CPU seconds this process has used (the machine may be shared, so wall
/// time can overstate the parser's cost); `None` off Linux.
fn cpu_seconds() -> Option<f64> {
    #[cfg(target_os = "linux")]
    {
        let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
        // SAFETY: `t` is a valid, writable timespec.
        let ok = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) } == 0;
        ok.then_some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let megabytes: usize = args.iter().find_map(|a| a.parse().ok()).unwrap_or(200);
    let gz = args.iter().any(|a| a == "--gz");
    let dir = tempfile::tempdir()?;
    let path = dir.path().join("speed.pbrt");

    let start = Instant::now();
    let mut file = std::io::BufWriter::new(std::fs::File::create(&path)?);
    file.write_all(
        b"LookAt 0 0 -30 0 0 0 0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
          Film \"rgb\" \"integer xresolution\" 640 \"integer yresolution\" 480 \"string filename\" \"out.exr\"\n\
          Sampler \"zsobol\" \"integer pixelsamples\" 64\nWorldBegin\n",
    )?;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut written = 0;
    let mut chunk = String::new();
    while written < megabytes * 1_000_000 {
        chunk.clear();
        mesh(&mut rng, 5000, &mut chunk);
        file.write_all(chunk.as_bytes())?;
        written += chunk.len();
    }
    file.flush()?;
    drop(file);
    let size = std::fs::metadata(&path)?.len();
    println!("wrote {:.1} MB in {:.1} s", size as f64 / 1e6, start.elapsed().as_secs_f64());

    let measure = |path: &std::path::Path, label: &str| -> Result<(), Box<dyn std::error::Error>> {
        let mut values = 0usize;
        let mut shapes = 0usize;
        let start = Instant::now();
        let cpu_start = cpu_seconds();
        let stats = parse_file_with_stats(path, &mut |d, _| {
            if let Directive::Shape(_, params) = &d {
                shapes += 1;
                values += params.iter().map(|p| p.values.len()).sum::<usize>();
                if let Some(p) = params.get("P") {
                    assert!(matches!(p.values, ParamValues::Floats(_)));
                }
            }
            Ok(())
        })?;
        let seconds = start.elapsed().as_secs_f64();
        let cpu = cpu_seconds().zip(cpu_start).map(|(b, a)| b - a);
        println!(
            "{label}: parsed {:.1} MB of text in {seconds:.3} s: {:.0} MB/s ({} directives, {shapes} shapes, {values} \
             values, {} tokens); peak tokens held: {}, peak read buffer: {} KiB",
            stats.bytes as f64 / 1e6,
            stats.bytes as f64 / 1e6 / seconds,
            stats.directives,
            stats.tokens,
            stats.peak_tokens_held,
            stats.peak_buffer_bytes / 1024
        );
        if let Some(cpu) = cpu {
            println!("{label}: {cpu:.3} s of CPU time: {:.0} MB/s per CPU second", stats.bytes as f64 / 1e6 / cpu);
        }
        Ok(())
    };
    measure(&path, "plain")?;
    if gz {
        let gz_path = dir.path().join("speed.pbrt.gz");
        let mut encoder = flate2::write::GzEncoder::new(std::fs::File::create(&gz_path)?, flate2::Compression::fast());
        std::io::copy(&mut std::fs::File::open(&path)?, &mut encoder)?;
        encoder.finish()?;
        println!("gzip: {:.1} MB", std::fs::metadata(&gz_path)?.len() as f64 / 1e6);
        measure(&gz_path, "gzip")?;
    }
    Ok(())
}
