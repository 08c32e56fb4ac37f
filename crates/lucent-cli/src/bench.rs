use crate::cli::BenchArgs;
use lucent::render::{render, RenderOptions};

struct Measurement {
    threads: usize,
    median_seconds: f64,
    median_mrays: f64,
    rays: u64,
}

/// `lucent bench`: render the scene `repeats` times for each thread count and
/// report medians (the machine is shared and noisy: medians and ratios from
/// one run are what can be compared).
pub fn run(args: &BenchArgs) -> Result<(), String> {
    let source = crate::source::load(args.scene.as_deref(), &args.overrides, &Default::default())?;
    let loaded = &source.loaded;
    let (scene, settings) = (&loaded.scene, &loaded.settings);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut counts = args.threads.clone();
    if counts.is_empty() {
        counts = vec![1, cores];
        counts.dedup();
    }
    if counts.contains(&0) {
        return Err("--threads: thread counts must be at least 1".into());
    }

    // Interleave the thread counts (1, N, 1, N, ...) so that a slow spell of
    // the shared machine hits every configuration alike, then take medians.
    let mut seconds = vec![Vec::new(); counts.len()];
    let mut rays = vec![0u64; counts.len()];
    for _ in 0..args.repeats {
        for (i, &threads) in counts.iter().enumerate() {
            let options = RenderOptions { threads: Some(threads), ..Default::default() };
            let out = render(scene, settings, options).map_err(|e| e.to_string())?;
            seconds[i].push(out.elapsed.as_secs_f64());
            rays[i] = out.stats.total();
        }
    }
    let results: Vec<Measurement> = counts
        .iter()
        .zip(seconds.iter_mut().zip(&rays))
        .map(|(&threads, (times, &rays))| {
            times.sort_by(f64::total_cmp);
            let median = times[times.len() / 2];
            Measurement { threads, median_seconds: median, median_mrays: rays as f64 / median / 1e6, rays }
        })
        .collect();

    let base = results[0].median_mrays;
    // Camera samples (paths, for the path tracer) per render.
    let samples = scene.camera().width() as f64 * scene.camera().height() as f64 * settings.spp as f64;
    let name = args.scene.as_ref().map_or_else(|| "<built-in showcase>".to_owned(), |p| p.display().to_string());
    if args.json {
        let rows: Vec<serde_json::Value> = results
            .iter()
            .map(|m| {
                serde_json::json!({
                    "threads": m.threads,
                    "median_seconds": m.median_seconds,
                    "mrays_per_second": m.median_mrays,
                    "msamples_per_second": samples / m.median_seconds / 1e6,
                    "rays": m.rays,
                    "speedup": m.median_mrays / base,
                })
            })
            .collect();
        let report = serde_json::json!({
            "scene": name,
            "width": scene.camera().width(),
            "height": scene.camera().height(),
            "spp": settings.spp,
            "repeats": args.repeats,
            "results": rows,
        });
        say!("{report}")?;
    } else {
        say!(
            "{name}: {}×{}, {} spp, {} integrator, median of {} renders",
            scene.camera().width(),
            scene.camera().height(),
            settings.spp,
            settings.integrator.name(),
            args.repeats
        )?;
        say!("{:>8} {:>12} {:>12} {:>12} {:>10}", "threads", "seconds", "Mrays/s", "Msamples/s", "speedup")?;
        for m in &results {
            say!(
                "{:>8} {:>12.3} {:>12.2} {:>12.3} {:>9.2}×",
                m.threads,
                m.median_seconds,
                m.median_mrays,
                samples / m.median_seconds / 1e6,
                m.median_mrays / base
            )?;
        }
    }
    Ok(())
}
