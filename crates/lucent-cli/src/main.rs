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
mod denoise;
mod diff;
mod partial;
mod progress;
mod render;
mod sky;
mod source;

use clap::Parser;
use cli::{Cli, Command, RenderArgs};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The clamp of indirect light that `--denoise` applies where the scene
/// sets none.
const DENOISE_MAX_INDIRECT: f32 = 10.0;

/// The showcase scene, built in so that `lucent render` works with no file.
pub const BUILTIN_SCENE: &str = include_str!("../../../scenes/showcase.toml");

fn main() -> ExitCode {
    let cli = Cli::try_parse().unwrap_or_else(|e| bench_rays::exit_on_parse_error(e));
    let result = match cli.command {
        Command::Render(args) => run_render(&args),
        Command::Check { scene, import } => run_check(&scene, &import),
        Command::Convert { scene, output, overrides, import } => run_convert(&scene, &output, &overrides, &import),
        Command::Bench(args) => bench::run(&args),
        Command::BenchRays(args) => bench_rays::run(&args),
        Command::Diff(args) => diff::run(&args),
        Command::Merge(args) => partial::merge(&args),
        Command::Sky(args) => sky::run(&args),
        Command::Denoise(args) => denoise::command(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run_render(args: &RenderArgs) -> Result<(), String> {
    render::handle_interrupts();
    // A denoiser wants every sample in one pixel: filter importance
    // sampling.
    let mut overrides = args.overrides.clone();
    overrides.filter_importance |= args.denoise.denoise;
    let source = source::load_with(args.scene.as_deref(), &overrides, &args.import, |o| {
        // A denoiser turns fireflies into blotches: clamp indirect light
        // at 10 unless the scene or --max-indirect sets a clamp
        // (docs/denoising.md, "Fireflies", has the measurements).
        if args.denoise.denoise {
            o.default_max_indirect = Some(DENOISE_MAX_INDIRECT);
        }
    })?;
    warn(&source.loaded.scene, args.quiet);
    let out_path = args.output.clone().unwrap_or_else(|| default_output(args.scene.as_deref()));
    if args.samples.is_some() || partial::is_part(&out_path) {
        if args.denoise.denoise {
            return Err("--denoise applies to images, not to partial renders (.lpart): merge the parts into an .exr with `lucent merge`, then run `lucent denoise` on it (render the parts with --aov albedo,normal and --filter-importance for the best result)".into());
        }
        return partial::render(args, &source, &out_path);
    }
    render::run(args, &source, &out_path)
}

fn run_check(path: &Path, import: &cli::ImportArgs) -> Result<(), String> {
    let loaded = source::load(Some(path), &cli::SceneOverrides::default(), import)?.loaded;
    let (scene, settings) = (&loaded.scene, &loaded.settings);
    warn(scene, false);
    let count = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    say!(
        "{}: ok ({}, {}, {}, {}×{}, {} spp)",
        path.display(),
        count(scene.primitives().len(), "object"),
        count(scene.materials().len(), "material"),
        count(scene.lights().len() + scene.area_lights().len() + scene.environment().is_some() as usize, "light"),
        scene.camera().width(),
        scene.camera().height(),
        settings.spp
    )?;
    Ok(())
}

fn run_convert(
    path: &Path,
    output: &Path,
    overrides: &cli::SceneOverrides,
    import: &cli::ImportArgs,
) -> Result<(), String> {
    if lucent::loader::SceneFormat::from_path(output).is_none() {
        return Err(format!("{}: the output must be a .toml or .json scene file", output.display()));
    }
    let same = |a: &Path, b: &Path| match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same(path, output) {
        return Err(format!("{}: the output would overwrite the input; choose another name", output.display()));
    }
    let loaded = source::load(Some(path), overrides, import)?.loaded;
    warn(&loaded.scene, false);
    let summary = lucent::loader::export_scene(&loaded, output).map_err(|e| e.to_string())?;
    let meshes = match summary.mesh_files.len() {
        0 => String::new(),
        n => format!(
            ", {n} mesh file{} ({} triangles) in {}",
            if n == 1 { "" } else { "s" },
            summary.triangles,
            summary.mesh_files[0].parent().map_or_else(String::new, |d| d.display().to_string())
        ),
    };
    say!("wrote {}{meshes}", output.display())?;
    Ok(())
}

/// Print the scene's non-fatal problems (skipped degenerate triangles...).
fn warn(scene: &lucent::scene::Scene, quiet: bool) {
    if !quiet {
        for w in scene.warnings() {
            // Importers' notes (what a file has that is no problem) are
            // warnings prefixed "note: ".
            if w.starts_with("note: ") {
                eprintln!("{w}");
            } else {
                eprintln!("warning: {w}");
            }
        }
    }
}

fn default_output(scene: Option<&Path>) -> PathBuf {
    let name =
        scene.and_then(|p| p.file_name()).map_or_else(|| "showcase".into(), |s| s.to_string_lossy().into_owned());
    // `scene.pbrt.gz` → `scene.png`
    let stem = name.strip_suffix(".gz").unwrap_or(&name);
    let stem = Path::new(stem).file_stem().map_or_else(|| stem.to_owned(), |s| s.to_string_lossy().into_owned());
    let mut name = PathBuf::from(stem);
    name.set_extension("png");
    name
}
