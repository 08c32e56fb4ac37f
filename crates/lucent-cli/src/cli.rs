use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// lucent: a ray tracer.
///
/// Scenes are TOML or JSON files (see docs/scene-format.md). Output format
/// follows the extension: .png and .bmp are 8-bit, tone mapped and
/// sRGB-encoded; .exr is linear 32-bit float radiance before tone mapping.
#[derive(Parser, Debug)]
#[command(name = "lucent", version, about, long_about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene to an image.
    Render(RenderArgs),
    /// Parse and validate a scene file without rendering it.
    Check {
        /// The scene file (.toml or .json).
        scene: PathBuf,
    },
    /// Measure rendering speed (Mrays/s) with 1 thread and with all threads.
    Bench(BenchArgs),
}

/// Values that override the scene file's `[render]` table.
#[derive(Args, Debug, Clone, Default)]
pub struct SceneOverrides {
    /// Image width in pixels (overrides the scene).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub height: Option<u32>,
    /// Samples per pixel (overrides the scene). n×n gives an n×n jittered grid.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    pub spp: Option<u32>,
    /// Random seed (overrides the scene).
    #[arg(long)]
    pub seed: Option<u64>,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene file (.toml or .json); without one, the built-in showcase
    /// scene is rendered.
    pub scene: Option<PathBuf>,
    /// Output image: .png, .bmp or .exr [default: the scene's name with .png,
    /// in the current directory].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Worker threads, 1 to 1024 [default: all cores]. The image is
    /// identical for any thread count.
    #[arg(long, value_parser = thread_count())]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// The scene file; without one, the built-in showcase scene.
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Renders per thread count; the median is reported.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub repeats: u32,
    /// Thread counts to measure, comma-separated, each 1 to 1024 [default: 1
    /// and all cores].
    #[arg(long, value_delimiter = ',', value_parser = thread_count())]
    pub threads: Vec<usize>,
    /// Print the results as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Accepted worker-thread counts: a larger pool only wastes memory.
fn thread_count() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=1024)
}
