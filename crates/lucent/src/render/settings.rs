//! How a scene is rendered: [`RenderSettings`].

use crate::color::Color;
use crate::film::{AovSet, Filter, ToneMap};
use crate::sampling::SamplerKind;

/// How an image is sampled, which light transport computes it, and how it
/// is displayed: everything about a render that is not the scene itself.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Samples per pixel.
    pub spp: u32,
    /// Most bounces: mirror reflections for Whitted, path vertices for the
    /// path tracer.
    pub max_depth: u32,
    /// How radiance above 1 is mapped for 8-bit output.
    pub tone_map: ToneMap,
    /// Whether 8-bit output is sRGB-encoded (otherwise linear).
    pub srgb: bool,
    /// Seed of all random sampling decisions.
    pub seed: u64,
    /// Which light transport algorithm renders the scene.
    pub integrator: IntegratorKind,
    /// The sample sequence.
    pub sampler: SamplerKind,
    /// Pixel reconstruction filter.
    pub filter: Filter,
    /// pbrt-v4's `regularize` option of the path integrator: roughen
    /// near-specular lobes after the first non-specular bounce (default
    /// false; the Whitted integrator ignores it).
    pub regularize: bool,
    /// Per-channel factor applied to every sample's radiance before it
    /// reaches the film (pbrt-v4's exposure and white balance,
    /// [`crate::film::pbrt_film_scale`]); (1, 1, 1) by default.
    pub film_scale: Color,
    /// If set, a sample (after `film_scale`) whose largest component
    /// exceeds this is scaled down to it (pbrt-v4's `maxcomponentvalue`),
    /// taming fireflies at the cost of bias; `None` by default.
    pub max_component: Option<f32>,
    /// Path tracer: if set, a contribution of indirect light (see
    /// [`crate::integrator::PathIntegrator::max_indirect`]) whose largest
    /// component exceeds this is scaled down to it, taming the fireflies
    /// of caustics at the cost of bias where indirect light is that
    /// bright; `None` by default.
    pub max_indirect: Option<f32>,
    /// Auxiliary images to make besides the colour (none by default).
    pub aovs: AovSet,
    /// Place each sample by importance sampling the filter, so that it
    /// lands in one pixel with the filter's sign as its weight (pbrt-v4's
    /// way, and what a denoiser needs: no noise shared between
    /// neighbours), instead of splatting it, weighted, into every pixel
    /// the filter covers (false, the default). With the default box filter
    /// of radius ½ both give the same image.
    pub filter_importance: bool,
    /// Adaptive sampling: stop sampling pixels whose estimated error is
    /// below this threshold (see [`crate::film::adaptive`]); `None` (the
    /// default): every pixel takes every sample.
    pub adaptive: Option<f32>,
}

/// The light transport algorithms.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Classic ray tracing ([`crate::integrator::WhittedIntegrator`]).
    #[default]
    Whitted,
    /// Path tracing ([`crate::integrator::PathIntegrator`]).
    Path,
    /// Bidirectional path tracing ([`crate::integrator::BdptIntegrator`]).
    Bdpt,
}

impl IntegratorKind {
    /// The depth a render uses when none is given: 5 mirror bounces for
    /// Whitted, 64 path vertices for the path tracer (which ends paths by
    /// Russian roulette), 5 for bidirectional path tracing (pbrt-v4's
    /// default: its subpaths are traced to full depth and joined every way,
    /// so its cost grows with the square of the depth).
    pub fn default_max_depth(self) -> u32 {
        match self {
            IntegratorKind::Whitted => 5,
            IntegratorKind::Path => 64,
            IntegratorKind::Bdpt => 5,
        }
    }

    /// The name used in scene files, on the command line and in Python.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::Path => "path",
            IntegratorKind::Bdpt => "bdpt",
        }
    }

    /// The sampler a render uses when none is given: the classic jittered
    /// grid for Whitted, Sobol points for the path tracer.
    pub fn default_sampler(self) -> SamplerKind {
        match self {
            IntegratorKind::Whitted => SamplerKind::Stratified,
            IntegratorKind::Path | IntegratorKind::Bdpt => SamplerKind::Sobol,
        }
    }
}

impl RenderSettings {
    /// The defaults of `integrator`: 16 samples per pixel, its own depth
    /// and sampler, a box filter, classic tone mapping, sRGB output, seed 0,
    /// no regularisation, film scale 1, no clamp of samples or of
    /// indirect light, and no auxiliary images.
    pub fn for_integrator(integrator: IntegratorKind) -> Self {
        Self {
            spp: 16,
            max_depth: integrator.default_max_depth(),
            tone_map: ToneMap::Classic,
            srgb: true,
            seed: 0,
            integrator,
            sampler: integrator.default_sampler(),
            filter: Filter::default(),
            regularize: false,
            film_scale: Color::ONE,
            max_component: None,
            max_indirect: None,
            aovs: AovSet::NONE,
            filter_importance: false,
            adaptive: None,
        }
    }
}

impl RenderSettings {
    /// What the film keeps per pixel for these settings: the auxiliary
    /// images asked for, and for bidirectional path tracing the light
    /// image of its light-tracing splats
    /// ([`AovSet::with_light_image`]). Make accumulators with this.
    pub fn film_aovs(&self) -> AovSet {
        match self.integrator {
            IntegratorKind::Bdpt => self.aovs.with_light_image(),
            _ => self.aovs,
        }
    }
}

impl Default for RenderSettings {
    /// [`RenderSettings::for_integrator`] of the Whitted integrator.
    fn default() -> Self {
        Self::for_integrator(IntegratorKind::Whitted)
    }
}
