//! `lucent`: render scene files from the command line.

/// `println!` that reports a failure (a closed pipe, a full disk) as an error
/// for `main` to print, instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout(), $($arg)*).map_err(|e| format!("cannot write to standard output: {e}"))
    }};
}

mod bench;
mod bench_rays;
mod cli;
mod diff;
mod path_render;
mod progress;
mod sky;

use clap::Parser;
use cli::{Cli, Command, RenderArgs};
use lucent::film::PendingImage;
use lucent::render::{render, RenderOptions};
use lucent::scene::{SceneFile, SceneFormat};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The showcase scene, built in so that `lucent render` works with no file.
pub const BUILTIN_SCENE: &str = include_str!("../../../scenes/showcase.toml");

fn main() -> ExitCode {
    let cli = Cli::try_parse().unwrap_or_else(|e| bench_rays::exit_on_parse_error(e));
    let result = match cli.command {
        Command::Render(args) => run_render(&args),
        Command::Check { scene } => run_check(&scene),
        Command::Bench(args) => bench::run(&args),
        Command::BenchRays(args) => bench_rays::run(&args),
        Command::Diff(args) => diff::run(&args),
        Command::Sky(args) => sky::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// Load a scene file, or the built-in showcase when `path` is `None`.
pub fn load(path: Option<&Path>) -> Result<SceneFile, String> {
    match path {
        Some(p) => SceneFile::load(p).map_err(|e| e.to_string()),
        None => SceneFile::parse(BUILTIN_SCENE.to_owned(), SceneFormat::Toml, Some("<built-in showcase>".into()))
            .map_err(|e| e.to_string()),
    }
}

/// Apply command-line overrides to a loaded scene file. An image size set
/// on the command line is checked here, so that an error names the options
/// rather than a line of the file.
pub fn apply_overrides(file: &mut SceneFile, args: &cli::SceneOverrides) -> Result<(), String> {
    let r = &mut file.description.render;
    if let Some(w) = args.width {
        r.width = lucent::scene::ImageDimension(w);
    }
    if let Some(h) = args.height {
        r.height = lucent::scene::ImageDimension(h);
    }
    if let Some(spp) = args.spp {
        r.spp = lucent::scene::SampleCount(spp);
    }
    if let Some(seed) = args.seed {
        r.seed = seed;
    }
    if let Some(i) = args.integrator {
        r.integrator = match i {
            cli::IntegratorArg::Whitted => lucent::scene::IntegratorDesc::Whitted,
            cli::IntegratorArg::Path => lucent::scene::IntegratorDesc::Path,
        };
    }
    if let Some(s) = args.sampler {
        r.sampler = match s {
            cli::SamplerArg::Sobol => lucent::scene::SamplerDesc::Sobol,
            cli::SamplerArg::Independent => lucent::scene::SamplerDesc::Independent,
        };
    }
    if let Some(d) = args.max_depth {
        r.max_depth = Some(lucent::scene::MaxDepth(d));
    }
    if args.width.is_some() || args.height.is_some() {
        lucent::film::check_image_size(r.width.0, r.height.0).map_err(|e| {
            let given: Vec<String> = [("--width", args.width), ("--height", args.height)]
                .iter()
                .filter_map(|(name, v)| v.map(|v| format!("{name} {v}")))
                .collect();
            format!("{}: {e}", given.join(" "))
        })?;
    }
    Ok(())
}

fn run_render(args: &RenderArgs) -> Result<(), String> {
    let mut file = load(args.scene.as_deref())?;
    apply_overrides(&mut file, &args.overrides)?;
    let scene = file.build().map_err(|e| e.to_string())?;
    warn(&scene, args.quiet);

    let out_path = args.output.clone().unwrap_or_else(|| default_output(args.scene.as_deref()));
    if scene.settings.integrator == lucent::render::IntegratorKind::Path {
        return path_render::run(args, &file, &scene, &out_path);
    }
    for (flag, given) in [
        ("--time", args.time.is_some()),
        ("--checkpoint-every", args.checkpoint_every.is_some()),
        ("--resume", args.resume),
    ] {
        if given {
            return Err(format!(
                "{flag} needs the path integrator (set `integrator = \"path\"` in [render], or --integrator path)"
            ));
        }
    }
    // Reserve the output before rendering: a bad path fails now, not after
    // the render, and the existing file is untouched until the new one is
    // complete.
    let pending = PendingImage::create(&out_path).map_err(|e| e.to_string())?;

    let bar = progress::RowProgress::new(scene.camera.height() as u64, args.quiet);
    let report = |done: usize, _total: usize| bar.set(done as u64);
    let options = RenderOptions { threads: args.threads.filter(|&t| t > 0), progress: Some(&report) };
    let output = render(&scene, &options).map_err(|e| e.to_string())?;
    bar.finish();

    pending.write(&output.film, scene.settings.tone_map, scene.settings.srgb).map_err(|e| e.to_string())?;
    if !args.quiet {
        say!(
            "{}: {}×{}, {} spp, {:.2} s, {:.1} M rays, {:.2} Mrays/s",
            out_path.display(),
            scene.camera.width(),
            scene.camera.height(),
            scene.settings.spp,
            output.elapsed.as_secs_f64(),
            output.stats.total() as f64 / 1e6,
            output.mrays_per_second()
        )?;
    }
    Ok(())
}

fn run_check(path: &Path) -> Result<(), String> {
    let scene = SceneFile::load(path).and_then(|f| f.build()).map_err(|e| e.to_string())?;
    warn(&scene, false);
    let count = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    say!(
        "{}: ok ({}, {}, {}, {}×{}, {} spp)",
        path.display(),
        count(scene.primitives().len(), "object"),
        count(scene.materials().len(), "material"),
        count(scene.lights().len() + scene.area_lights().len() + scene.environment().is_some() as usize, "light"),
        scene.camera.width(),
        scene.camera.height(),
        scene.settings.spp
    )?;
    Ok(())
}

/// Print the scene's non-fatal problems (skipped degenerate triangles...).
fn warn(scene: &lucent::scene::Scene, quiet: bool) {
    if !quiet {
        for w in &scene.warnings {
            eprintln!("warning: {w}");
        }
    }
}

fn default_output(scene: Option<&Path>) -> PathBuf {
    let stem = scene.and_then(|p| p.file_stem()).map_or_else(|| "showcase".into(), |s| s.to_os_string());
    let mut name = PathBuf::from(stem);
    name.set_extension("png");
    name
}
