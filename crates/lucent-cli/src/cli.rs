use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// lucent: a ray tracer.
///
/// Scenes are TOML or JSON files (see docs/scene-format.md). Output format
/// follows the extension: .png and .bmp are 8-bit, tone mapped and
/// sRGB-encoded; .exr (32-bit float) and .hdr (Radiance RGBE) are linear
/// radiance before tone mapping.
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
        /// The scene file (.toml, .json, .pbrt, .gltf or .glb).
        scene: PathBuf,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Write a scene (a pbrt-v4 or glTF file, or a TOML/JSON one) as a lucent scene
    /// file, TOML or JSON by the output's extension, with its meshes as
    /// binary PLY files in OUTPUT_STEM-meshes/ beside it: edit it, and it
    /// renders the same image.
    Convert {
        /// The scene to read (.pbrt, .pbrt.gz, .gltf, .glb, .toml or .json).
        scene: PathBuf,
        /// The scene file to write (.toml or .json).
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        #[command(flatten)]
        overrides: SceneOverrides,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Measure rendering speed (Mrays/s) with 1 thread and with all threads.
    Bench(BenchArgs),
    /// Benchmark ray traversal on a triangle mesh (the raybench protocol),
    /// to compare with the Embree reference on the same rays.
    #[command(long_about = BENCH_RAYS_ABOUT)]
    BenchRays(BenchRaysArgs),
    /// Compare an image with a reference image (MSE, relative MSE, largest
    /// error).
    Diff(crate::diff::DiffArgs),
    /// Add up partial renders (.lpart files written by `render --samples`)
    /// into the image of all their samples: bit-identical to one render of
    /// them, whatever the order or grouping of the parts.
    Merge(MergeArgs),
    /// Write a procedural environment map (daylight sky or photo studio)
    /// as a linear .hdr or .exr equirectangular image.
    Sky(SkyArgs),
    /// Denoise a rendered .exr with Intel Open Image Denoise, guided by its
    /// albedo and normal layers if it has them (render with --aov
    /// albedo,normal). OIDN is opened at run time: `pip install pyoidn`, or
    /// set LUCENT_OIDN to the library.
    Denoise(DenoiseCommandArgs),
}

/// `lucent denoise`.
#[derive(Args, Debug)]
pub struct DenoiseCommandArgs {
    /// The noisy image: an .exr with R, G, B (and Albedo.R/G/B, Ns.X/Y/Z).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// The denoised image (.exr keeps the input's layers and its colour as
    /// Noisy.R/G/B; .png, .bmp and .hdr get the colour).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// OIDN's quality setting.
    #[arg(long, value_enum, default_value_t)]
    pub quality: crate::denoise::QualityArg,
    /// How the albedo and normal layers guide the denoiser.
    #[arg(long, value_enum, default_value_t)]
    pub aux: crate::denoise::AuxArg,
    /// Worker threads of OIDN, 1 to 1024 [default: all cores].
    #[arg(long, value_parser = thread_count())]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `lucent render`'s denoising options.
#[derive(Args, Debug, Clone, Default)]
pub struct DenoiseArgs {
    /// Write the image denoised by Intel Open Image Denoise (opened at run
    /// time: `pip install pyoidn`, or LUCENT_OIDN=/path/to/the/library),
    /// guided by albedo and normal images rendered for it. An .exr output
    /// keeps the noisy colour as Noisy.R/G/B. Samples are then placed by
    /// filter importance sampling, so that each lands in one pixel.
    #[arg(long)]
    pub denoise: bool,
    /// OIDN's quality setting for --denoise.
    #[arg(long, value_enum, default_value_t, requires = "denoise")]
    pub denoise_quality: crate::denoise::QualityArg,
    /// How the albedo and normal guide --denoise.
    #[arg(long, value_enum, default_value_t, requires = "denoise")]
    pub denoise_aux: crate::denoise::AuxArg,
}

/// Which procedural environment `lucent sky` writes.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkyKind {
    /// Blue sky gradient, darker ground, bright sun disk.
    Sky,
    /// Dark grey studio with large soft boxes and a floor gradient.
    Studio,
}

impl SkyKind {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            SkyKind::Sky => "sky",
            SkyKind::Studio => "studio",
        }
    }
}

/// `lucent sky`: the image is equirectangular, +y up, its centre looking
/// towards -z and u growing towards +x; azimuths are measured from -z
/// towards +x.
#[derive(Args, Debug)]
pub struct SkyArgs {
    /// Output image: .hdr (Radiance RGBE) or .exr (OpenEXR float).
    #[arg(value_name = "OUT")]
    pub output: PathBuf,
    /// What to draw.
    #[arg(long, value_enum, default_value_t = SkyKind::Sky)]
    pub kind: SkyKind,
    /// Width in pixels; the height is half of it.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(2..=65_536))]
    pub width: u32,
    /// Sun elevation above the horizon, degrees, -90 to 90 (sky only).
    #[arg(long, default_value_t = 35.0, allow_negative_numbers = true)]
    pub sun_elevation: f32,
    /// Sun azimuth, degrees from -z towards +x (sky only).
    #[arg(long, default_value_t = 45.0, allow_negative_numbers = true)]
    pub sun_azimuth: f32,
    /// Irradiance of the sun on a surface facing it (sky only).
    #[arg(long, default_value_t = 8.0, allow_negative_numbers = true)]
    pub sun_intensity: f32,
    /// Angular radius of the sun disk, degrees (sky only).
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub sun_radius: f32,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
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
    /// Light transport algorithm (overrides the scene).
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorArg>,
    /// Sample sequence (overrides the scene).
    #[arg(long, value_enum)]
    pub sampler: Option<SamplerArg>,
    /// Most bounces, 0 to 10000 (overrides the scene).
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=10_000))]
    pub max_depth: Option<u32>,
    /// Auxiliary images to write as layers of the .exr output,
    /// comma-separated: albedo (Albedo.R/G/B), normal (Ns.X/Y/Z, world
    /// space), position (P.X/Y/Z, world space), depth (Z); `none` for none
    /// (overrides the scene's `aov`).
    #[arg(long, value_name = "LIST", value_parser = aov_list)]
    pub aov: Option<lucent::film::AovSet>,
    /// Place each sample in one pixel by importance sampling the filter
    /// instead of splatting it into every pixel the filter covers (on with
    /// --denoise; overrides the scene's `filter_importance`).
    #[arg(long)]
    pub filter_importance: bool,
    /// Adaptive sampling: stop sampling pixels whose estimated relative
    /// error is below THRESHOLD (e.g. 0.01; see docs/denoising.md), deciding
    /// after 16, 24, 32... samples; --spp is then the most a pixel takes.
    /// An .exr output gets the samples per pixel as SampleCount (overrides
    /// the scene's `adaptive`).
    #[arg(long, value_name = "THRESHOLD", value_parser = positive_threshold)]
    pub adaptive: Option<f32>,
    /// Path tracer: scale down every contribution of indirect light whose
    /// largest channel exceeds MAX to MAX (tames the fireflies of caustics,
    /// at some bias; overrides the scene's `max_indirect`).
    #[arg(long, value_name = "MAX", value_parser = positive_threshold)]
    pub max_indirect: Option<f32>,
}

/// `--adaptive` and `--max-indirect` values: a finite number > 0.
fn positive_threshold(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("expected a number > 0, got '{s}'")),
    }
}

/// `--aov` values.
fn aov_list(s: &str) -> Result<lucent::film::AovSet, String> {
    s.parse().map_err(|e: lucent::film::UnknownAov| e.to_string())
}

/// `--integrator` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorArg {
    /// Classic ray tracing: hard shadows, mirrors, ambient light.
    Whitted,
    /// Path tracing: global illumination, area lights, glass and metal.
    Path,
    /// Bidirectional path tracing: the path tracer's light transport, with
    /// light subpaths for caustics.
    Bdpt,
}

/// `--sampler` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerArg {
    /// The classic jittered grid (the Whitted integrator's default).
    Stratified,
    /// Owen-scrambled Sobol (low discrepancy; the path tracer's default).
    Sobol,
    /// Independent random numbers.
    Independent,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene file (.toml or .json); without one, the built-in showcase
    /// scene is rendered.
    pub scene: Option<PathBuf>,
    /// Output image: .png, .bmp, .exr or .hdr [default: the scene's name with .png,
    /// in the current directory].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    #[command(flatten)]
    pub import: ImportArgs,
    /// Worker threads, 1 to 1024 [default: all cores]. The image is
    /// identical for any thread count.
    #[arg(long, value_parser = thread_count())]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
    /// Render for this many seconds (stopping after the last
    /// pass that fits), up to --spp if that is given too.
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
    pub time: Option<f64>,
    /// Every SECONDS, write the image so far to the output and
    /// the accumulated samples to OUTPUT.ckpt, so the render can be watched
    /// and resumed.
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
    pub checkpoint_every: Option<f64>,
    /// Continue from OUTPUT.ckpt (an interrupted render, or a
    /// finished one to which --spp adds samples); the result is identical
    /// to rendering in one go.
    #[arg(long)]
    pub resume: bool,
    /// Render only the sample indices START..END (END excluded) of every
    /// pixel and write them, exactly, as a partial render (-o must end in
    /// .lpart); `lucent merge` adds disjoint parts into the image of all
    /// their samples.
    #[arg(long, value_name = "START..END", value_parser = sample_range)]
    pub samples: Option<std::ops::Range<u32>>,
    #[command(flatten)]
    pub denoise: DenoiseArgs,
}

/// `lucent merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The partial renders (.lpart), in any order.
    #[arg(value_name = "PART", required = true)]
    pub parts: Vec<PathBuf>,
    /// Output: an image (.png, .bmp, .exr, .hdr), or a .lpart holding the
    /// sum (to merge further later).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// A range of sample indices `START..END`, 0 <= START < END <= 2^20.
fn sample_range(s: &str) -> Result<std::ops::Range<u32>, String> {
    let bad = || format!("expected START..END with 0 <= START < END <= 1048576 (e.g. 0..16), got '{s}'");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b) = (a.trim().parse::<u32>().map_err(|_| bad())?, b.trim().parse::<u32>().map_err(|_| bad())?);
    if a >= b || b > 1_048_576 {
        return Err(bad());
    }
    Ok(a..b)
}

/// Options of the pbrt-v4 and glTF importers.
#[derive(Args, Debug, Default)]
pub struct ImportArgs {
    /// pbrt-v4 and glTF scenes: make every warning (an unsupported feature
    /// or parameter) an error.
    #[arg(long)]
    pub strict: bool,
    /// pbrt-v4 scenes: light `infinite` lights that name an image with this
    /// image instead (.exr, .hdr, .pfm, or an 8-bit image read as sRGB; for
    /// scenes shipped without theirs). glTF scenes: the environment (a
    /// latitude-longitude image, +y up).
    #[arg(long, value_name = "IMAGE")]
    pub env: Option<PathBuf>,
    /// glTF scenes: render scene N of the file (default: its `scene`, else
    /// the first).
    #[arg(long = "scene", value_name = "N")]
    pub gltf_scene: Option<usize>,
    /// glTF scenes: look through this camera, by name or by index in
    /// `cameras` (default: the first placed in the scene).
    #[arg(long, value_name = "NAME|N")]
    pub camera: Option<String>,
}

/// A duration in seconds: a finite number > 0.
fn positive_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 1e9 => Ok(v),
        _ => Err(format!("expected a number of seconds > 0, got '{s}'")),
    }
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

const BENCH_RAYS_ABOUT: &str = "Benchmark ray traversal on a triangle mesh, following the raybench
protocol (shared/tools/raybench/SPEC.md), so that lucent's mesh BVH can be
compared with the Embree reference (embree_ref) on bit-identical rays.

Three ray sets are generated from the mesh's bounding box: 1024×1024 primary
rays of a pinhole camera (closest hit); one shadow ray towards a point light
per primary hit (any hit); 1,048,576 incoherent rays with random origins in
the box and random directions (closest hit). The BVH is built 3 times
(median reported); each set is traced once untimed, then in 5 timed passes
(median reported), one ray at a time, in chunks of 4096 rays handed out
dynamically to the threads.

Prints the mesh, the build time, and the Mrays/s, hit counts and checksum
(sum of t over the hits) of each set; with --json, exactly one JSON line
(SPEC.md section 6) for shared/tools/raybench/compare.py.

Example:
  lucent bench-rays sphere:500:1000 --threads 2 --json";

/// `lucent bench-rays`: see [`BENCH_RAYS_ABOUT`].
#[derive(Args, Debug)]
pub struct BenchRaysArgs {
    /// The mesh: `sphere:STACKS:SLICES` (a UV sphere of radius 1, STACKS >= 2,
    /// SLICES >= 3), a PLY file (ascii or binary), or a text file listing PLY
    /// files, one per line, relative to the list file.
    #[arg(value_name = "MESH")]
    pub mesh: String,
    /// Threads for building and tracing, 1 to 1024; 1 means no parallelism
    /// at all.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = thread_count())]
    pub threads: usize,
    /// Print the results as one JSON line (SPEC.md section 6) instead of a
    /// table.
    #[arg(long)]
    pub json: bool,
    /// Print the first N rays of each set as f32 bit patterns (SPEC.md
    /// section 7) and exit without timing; check them with `gen_rays.py
    /// --check`.
    #[arg(long, value_name = "N")]
    pub dump_rays: Option<usize>,
    /// Timed passes per ray set (the protocol's 5; fewer only for quick
    /// tests).
    #[arg(long, hide = true, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub passes: u32,
}

/// Accepted worker-thread counts: a larger pool only wastes memory.
fn thread_count() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=1024)
}
