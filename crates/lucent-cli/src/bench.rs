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
    let mut file = crate::load(args.scene.as_deref())?;
    crate::apply_overrides(&mut file, &args.overrides)?;
    let scene = file.build().map_err(|e| e.to_string())?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut counts = args.threads.clone();
    if counts.is_empty() {
        counts = vec![1, cores];
        counts.dedup();
    }
    if counts.contains(&0) {
        return Err("--threads: thread counts must be at least 1".into());
    }

    let mut results = Vec::new();
    for &threads in &counts {
        let mut seconds = Vec::new();
        let mut rays = 0;
        for _ in 0..args.repeats {
            let out =
                render(&scene, &RenderOptions { threads: Some(threads), progress: None }).map_err(|e| e.to_string())?;
            seconds.push(out.elapsed.as_secs_f64());
            rays = out.stats.total();
        }
        seconds.sort_by(f64::total_cmp);
        let median = seconds[seconds.len() / 2];
        results.push(Measurement { threads, median_seconds: median, median_mrays: rays as f64 / median / 1e6, rays });
    }

    let base = results[0].median_mrays;
    let name = args.scene.as_ref().map_or_else(|| "<built-in showcase>".to_owned(), |p| p.display().to_string());
    if args.json {
        let rows: Vec<String> = results
            .iter()
            .map(|m| {
                format!(
                    "{{\"threads\": {}, \"median_seconds\": {:.6}, \"mrays_per_second\": {:.4}, \"rays\": {}, \"speedup\": {:.4}}}",
                    m.threads,
                    m.median_seconds,
                    m.median_mrays,
                    m.rays,
                    m.median_mrays / base
                )
            })
            .collect();
        say!(
            "{{\"scene\": {:?}, \"width\": {}, \"height\": {}, \"spp\": {}, \"repeats\": {}, \"results\": [{}]}}",
            name,
            scene.camera.width(),
            scene.camera.height(),
            scene.settings.spp,
            args.repeats,
            rows.join(", ")
        )?;
    } else {
        say!(
            "{name}: {}×{}, {} spp, median of {} renders",
            scene.camera.width(),
            scene.camera.height(),
            scene.settings.spp,
            args.repeats
        )?;
        say!("{:>8} {:>12} {:>12} {:>10}", "threads", "seconds", "Mrays/s", "speedup")?;
        for m in &results {
            say!(
                "{:>8} {:>12.3} {:>12.2} {:>9.2}×",
                m.threads,
                m.median_seconds,
                m.median_mrays,
                m.median_mrays / base
            )?;
        }
    }
    Ok(())
}
