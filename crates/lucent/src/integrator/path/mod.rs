mod conductor_lanes;
mod environment_lanes;
mod lanes;
mod light_lanes;
mod scatter_lanes;
mod sphere_lanes;

pub use lanes::PATH_LANES;

use super::{Integrator, RayStats};
use crate::bsdf::{Bsdf, BxDF};
use crate::color::Color;
use crate::geometry::{Ray, Vec3};
use crate::interaction::SurfaceInteraction;
use crate::light::{LiSample, LightSampleContext};
use crate::material::{Material, MaterialContext};
use crate::medium::{FreeFlight, HenyeyGreenstein, MediumEvent, MediumId};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Unidirectional path tracing with next-event estimation and multiple
/// importance sampling (Veach & Guibas, "Optimally Combining Sampling
/// Techniques for Monte Carlo Rendering", SIGGRAPH 1995; the structure of
/// PBRT 4th ed. §13.4, `PathIntegrator`).
///
/// At every non-specular vertex one light is chosen in proportion to its
/// power and sampled (next-event estimation), and the BSDF is sampled to
/// continue the path. Light reaching the path by either technique is
/// weighted with the power heuristic (β = 2), so each contribution is
/// counted once:
///
/// `w_light = p_light² / (p_light² + p_bsdf²)`, and symmetrically,
///
/// where both pdfs are per unit solid angle and `p_light` includes the
/// probability of choosing the light. Delta lights (point, spot,
/// directional) and delta BSDF lobes (mirror, smooth glass) can only be
/// reached by one technique and get weight 1.
///
/// Russian roulette (Arvo & Kirk 1990) ends paths after [`RR_DEPTH`]
/// bounces: a path survives with probability `q = min(max(β·η²), 0.95)`
/// and is then divided by `q`, so the estimate stays unbiased while dim
/// paths stop early. `η²` undoes the radiance scaling of refraction (PBRT
/// 4th ed. §13.4.4), so light inside glass is not killed for being scaled
/// down; the cap 0.95 ends paths that never lose energy (as in Mitsuba 3).
///
/// Sample dimensions are consumed in a fixed pattern per vertex (light
/// choice, light position, lobe choice, direction, roulette), so that a
/// low-discrepancy sampler stays well stratified along the path.
///
/// [`DirectLighting`] can switch one of the two techniques off, to check
/// that each alone converges to the same image (the renderer uses MIS).
///
/// Materials are resolved at each hit ([`Material::bsdf_at`]): a `Mix`
/// picks one of its materials, bump and normal maps set the shading frame,
/// and an `Interface` (no surface) is skipped: the ray continues from the
/// hit in the same direction without counting a bounce, at most 100 times
/// in a row (pbrt-v4's `SkipIntersection`).
/// Shadow rays pass through interfaces too, as in pbrt-v4's default
/// `volpath` integrator, whose transmittance rays stop only at surfaces
/// with a material (pbrt-v4's plain `path` integrator uses `IntersectP`,
/// for which interfaces occlude; that makes lights behind a medium
/// boundary reachable only by BSDF sampling, and point lights not at all).
/// Emission found after skipping an interface is weighted as if the
/// interface were not there.
///
/// **Participating media** (in scenes that have them, [`crate::medium`]):
/// each ray knows the medium it travels in (the camera's at first, then
/// whatever the boundaries it crosses say). On a segment in a medium the
/// medium samples whether and where the ray scatters
/// ([`crate::medium::HomogeneousMedium::sample`]: analytic transmittance,
/// a channel chosen by throughput, one-sample MIS over the channels). A
/// scattering point is a path vertex like a surface, with the
/// Henyey–Greenstein phase function in the place of the BSDF: next-event
/// estimation (the light's contribution times the phase function),
/// weighted by the power heuristic against phase-function sampling, which
/// continues the path; it counts as a bounce (as in pbrt-v4's `volpath`).
/// Shadow rays then carry transmittance: they pass through boundaries
/// without a surface (interfaces) and multiply the transmittance of each
/// medium they cross; any other surface blocks them. In scenes without
/// media none of this runs.
///
/// With `regularize` (pbrt-v4's option of the same name), after the first
/// non-specular bounce every BSDF is regularised
/// ([`Bsdf::regularize`]): near-specular lobes are widened, which trades
/// bias for much less noise in caustics.
///
/// With `max_indirect`, a contribution of *indirect* light whose largest
/// component exceeds it is scaled down to it. Following the path from the
/// camera, through any mirrors and glass, to the first non-specular
/// surface it meets, light is direct if it comes to that surface straight
/// from an emitter (or the environment), and indirect if it bounced on
/// something else first: interreflections and caustics, where a rare path
/// finds a small bright light through specular surfaces (a firefly).
/// Direct light, including emitters and their highlights seen in mirrors
/// and through glass, is never clamped; what is lost is the energy of
/// indirect contributions above the clamp (the idea of the "clamp
/// indirect" option of Blender's Cycles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathIntegrator {
    /// Most scattering events along a path (1: direct light only).
    pub max_depth: u32,
    /// How light is found at each vertex.
    pub direct: DirectLighting,
    /// Whether near-specular lobes are roughened after the first
    /// non-specular bounce (default false).
    pub regularize: bool,
    /// The largest component of a contribution of indirect light (see
    /// above); `None` (the default): no clamp.
    pub max_indirect: Option<f32>,
}

/// Most interfaces a ray passes through in a row before the path (or, for
/// a shadow ray, the light) is given up: a guard against rays trapped by
/// numerical trouble; real scenes need a few.
pub(crate) const MAX_INTERFACE_SKIPS: u32 = 100;

/// The material's view of a hit seen from `wo` (unit).
#[inline]
pub(super) fn material_context(si: &SurfaceInteraction, wo: Vec3) -> MaterialContext {
    MaterialContext {
        p: si.p,
        n: si.n,
        ns: si.ns,
        uv: si.uv,
        attributes: si.attributes,
        dpdu: si.dpdu,
        dpdv: si.dpdv,
        wo,
    }
}

/// Whether a scene has materials that may resolve to an interface (an
/// `Interface`, or a `Mix` or `Shaded` that may contain one): only then do
/// shadow rays need more than one visibility test.
pub(super) fn may_have_interfaces(scene: &Scene) -> bool {
    scene.materials().iter().any(|m| matches!(m, Material::Interface | Material::Mix { .. } | Material::Shaded { .. }))
}

/// The transmittance of a shadow ray that starts in `medium` (a ray from a
/// surface or medium point towards the point `target`, with `t_max` just
/// short of it, or, without a target, to infinity along unit `ray.dir`):
/// the product of each medium's transmittance over the length it crosses,
/// through boundaries without a surface (interfaces); zero when a surface
/// blocks the ray. For scenes with media ([`Scene::has_media`]).
pub(super) fn shadow_transmittance(
    scene: &Scene,
    mut ray: Ray,
    mut t_max: f32,
    target: Option<Vec3>,
    mut medium: Option<MediumId>,
) -> Color {
    let mut tr = Color::ONE;
    for _ in 0..MAX_INTERFACE_SKIPS {
        let hit = scene.intersect(&ray, t_max);
        if let Some(m) = medium {
            // Ray parameters measure lengths in units of |dir|.
            let t = hit.as_ref().map_or(t_max, |h| h.t);
            tr *= scene.medium(m).transmittance(t * ray.dir.length());
            if tr.max_element() <= 0.0 {
                return Color::ZERO;
            }
        }
        let Some(hit) = hit else { return tr };
        let ctx = material_context(&hit, -ray.dir.normalize());
        if !scene.material(hit.material).passes_through(&ctx, scene.materials()) {
            return Color::ZERO;
        }
        if hit.media.is_transition() {
            medium = hit.media.medium_along(ray.dir, hit.n);
        }
        (ray, t_max) = match target {
            Some(p) => hit.spawn_ray_to(p),
            None => (hit.spawn_ray(ray.dir), f32::INFINITY),
        };
    }
    Color::ZERO
}

/// Where a path scatters: at a surface with its BSDF, or at a point of a
/// medium with its phase function.
#[derive(Clone, Copy)]
enum Scatterer<'a> {
    Surface(&'a SurfaceInteraction, &'a Bsdf),
    Medium(Vec3, &'a HenyeyGreenstein),
}

/// Whether a shadow ray from `si` to the point `target` (or, without one,
/// in direction `dir` to infinity) is blocked by a surface, passing
/// through interfaces. `interfaces` caches [`may_have_interfaces`] for the
/// scene (computed on first need).
pub(super) fn occluded(
    scene: &Scene,
    si: &SurfaceInteraction,
    target: Option<Vec3>,
    dir: Vec3,
    interfaces: &mut Option<bool>,
) -> bool {
    let (mut ray, mut t_max) = match target {
        Some(p) => si.spawn_ray_to(p),
        None => (si.spawn_ray(dir), f32::INFINITY),
    };
    let blocked = match target {
        Some(p) => scene.intersect_p_toward(&ray, t_max, p),
        None => scene.intersect_p(&ray, t_max),
    };
    if !blocked {
        return false;
    }
    if !*interfaces.get_or_insert_with(|| may_have_interfaces(scene)) {
        return true;
    }
    for _ in 0..MAX_INTERFACE_SKIPS {
        let Some(hit) = scene.intersect(&ray, t_max) else { return false };
        let ctx = material_context(&hit, -ray.dir.normalize());
        if !scene.material(hit.material).passes_through(&ctx, scene.materials()) {
            return true;
        }
        (ray, t_max) = match target {
            Some(p) => hit.spawn_ray_to(p),
            None => (hit.spawn_ray(dir), f32::INFINITY),
        };
    }
    true
}

/// How a path finds light at a vertex: by sampling a light (next-event
/// estimation), by sampling the BSDF and hitting an emitter, or both,
/// combined by multiple importance sampling. All three are unbiased
/// estimators of the same integral; only their noise differs. (Delta
/// lights can only be found by light sampling, and delta lobes only by BSDF
/// sampling, whatever the choice.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DirectLighting {
    /// Both techniques, weighted by the power heuristic.
    #[default]
    Mis,
    /// Light sampling only: emitters hit by BSDF-sampled rays after a
    /// non-specular bounce are not counted.
    LightsOnly,
    /// BSDF sampling only: no shadow rays.
    BsdfOnly,
}

impl PathIntegrator {
    /// A path tracer with multiple importance sampling.
    pub fn new(max_depth: u32) -> Self {
        Self { max_depth, direct: DirectLighting::Mis, regularize: false, max_indirect: None }
    }

    /// This integrator with pbrt-v4's `regularize` option set to `on`.
    pub fn with_regularize(self, on: bool) -> Self {
        Self { regularize: on, ..self }
    }

    /// This integrator with indirect contributions clamped to `max` (see
    /// [`PathIntegrator::max_indirect`]).
    pub fn with_max_indirect(self, max: Option<f32>) -> Self {
        Self { max_indirect: max, ..self }
    }

    /// A contribution `c` to the pixel, clamped if it is `indirect` and a
    /// clamp is set: scaled so that its largest component is at most
    /// `max_indirect`, keeping its hue.
    #[inline]
    fn contribution(&self, c: Color, indirect: bool) -> Color {
        match self.max_indirect {
            Some(max) if indirect && c.max_element() > max => c * (max / c.max_element()),
            _ => c,
        }
    }

    /// The weight of light reached by a BSDF-sampled ray after a
    /// non-specular bounce, whose pdf was `p_bsdf`, from an emitter whose
    /// light-sampling pdf would have been `p_light`.
    #[inline]
    fn bsdf_weight(&self, p_bsdf: f32, p_light: f32) -> f32 {
        match self.direct {
            DirectLighting::Mis => power_heuristic(p_bsdf, p_light),
            DirectLighting::LightsOnly => 0.0,
            DirectLighting::BsdfOnly => 1.0,
        }
    }
}

/// Paths are never ended by Russian roulette before this many bounces
/// (Mitsuba 3's default `rr_depth`): ending them earlier saves rays but
/// adds much variance to indirect light.
pub const RR_DEPTH: u32 = 5;

/// The power heuristic with β = 2 for one sample of each of two
/// techniques.
#[inline]
pub fn power_heuristic(pdf_f: f32, pdf_g: f32) -> f32 {
    let (f, g) = (pdf_f * pdf_f, pdf_g * pdf_g);
    // Written as selects, not early returns, so that loops over many lanes
    // (the light stage's kernel) vectorise: the quotient is computed
    // whatever the case and only used when it is the answer.
    let sum = f + g;
    let q = f / sum;
    let w = if sum == 0.0 { 0.0 } else { q };
    if f.is_infinite() {
        1.0
    } else {
        w
    }
}

impl Integrator for PathIntegrator {
    /// Radiance arriving along the camera ray `camera_ray`, one path sample:
    /// a batch of one lane.
    fn li(&self, scene: &Scene, camera_ray: &Ray, sampler: &mut Sampler, stats: &mut RayStats) -> Color {
        let mut radiance = [Color::ZERO];
        self.li_lanes(scene, std::slice::from_ref(camera_ray), std::slice::from_mut(sampler), &mut radiance, stats);
        radiance[0]
    }

    /// Many path samples at once, a vertex at a time (see [`lanes`]).
    fn li_lanes(
        &self,
        scene: &Scene,
        rays: &[Ray],
        samplers: &mut [Sampler],
        radiance: &mut [Color],
        stats: &mut RayStats,
    ) {
        assert!(rays.len() == samplers.len() && rays.len() == radiance.len());
        let chunks = rays.chunks(PATH_LANES).zip(samplers.chunks_mut(PATH_LANES)).zip(radiance.chunks_mut(PATH_LANES));
        for ((rays, samplers), radiance) in chunks {
            self.li_batch(scene, rays, samplers, radiance, stats);
        }
    }
}

impl PathIntegrator {
    /// One light sample at `si`, MIS-weighted against BSDF sampling; the
    /// result still has to be multiplied by the path throughput. `medium`
    /// is the medium the path's ray was in (for scenes with media).
    #[allow(clippy::too_many_arguments)]
    fn sample_light(
        &self,
        scene: &Scene,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        wo: Vec3,
        medium: Option<MediumId>,
        u_light: f32,
        u_point: crate::geometry::Vec2,
        stats: &mut RayStats,
        interfaces: &mut Option<bool>,
    ) -> Color {
        if scene.has_media() {
            let vertex = Scatterer::Surface(si, bsdf);
            return self.sample_light_in_media(scene, vertex, wo, medium, u_light, u_point, stats);
        }
        let lights = scene.light_set();
        let Some((index, pmf)) = lights.sample(u_light) else { return Color::ZERO };
        let emitter = &lights.emitters()[index];
        let ctx = LightSampleContext { p: si.p, n: si.n };
        let Some(ls) = emitter.sample_li(&ctx, u_point) else { return Color::ZERO };
        self.weigh_light_sample(scene, si, bsdf, wo, emitter.is_delta(), pmf, ls, stats, interfaces)
    }

    /// The rest of [`PathIntegrator::sample_light`] once the light (a delta
    /// light if `delta`, picked with probability `pmf`) gave its sample
    /// `ls`: the BSDF's value, the shadow ray and the MIS weight.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn weigh_light_sample(
        &self,
        scene: &Scene,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        wo: Vec3,
        delta: bool,
        pmf: f32,
        ls: LiSample,
        stats: &mut RayStats,
        interfaces: &mut Option<bool>,
    ) -> Color {
        if ls.pdf <= 0.0 || ls.l.max_element() <= 0.0 {
            return Color::ZERO;
        }
        // Both directions in the shading frame once, for the BSDF's value,
        // the cosine (the local z) and the pdf ([`Bsdf::f`], [`Bsdf::pdf`]).
        let (wo_local, wi_local) = (bsdf.frame().to_local(wo), bsdf.frame().to_local(ls.wi));
        // The BSDF's value before the shadow ray, which spares the ray
        // where the value is 0; the ray first where the value is the
        // dearer of the two (a coated BSDF's random walk), so that an
        // occluded sample does not pay for the walk.
        let visibility_first = bsdf.bxdf().f_costs_more_than_a_ray(wo_local, wi_local);
        if visibility_first {
            stats.shadow += 1;
            if occluded(scene, si, ls.p_light, ls.wi, interfaces) {
                return Color::ZERO;
            }
        }
        let f = bsdf.bxdf().f(wo_local, wi_local) * wi_local.z.abs();
        if f.max_element() <= 0.0 {
            return Color::ZERO;
        }
        if !visibility_first {
            stats.shadow += 1;
            if occluded(scene, si, ls.p_light, ls.wi, interfaces) {
                return Color::ZERO;
            }
        }
        let p_light = pmf * ls.pdf;
        if delta || self.direct == DirectLighting::LightsOnly {
            f * ls.l / p_light
        } else {
            let w = power_heuristic(p_light, bsdf.bxdf().pdf(wo_local, wi_local));
            f * ls.l * (w / p_light)
        }
    }

    /// [`PathIntegrator::sample_light`] in a scene with media, at a surface
    /// or medium vertex: the shadow ray carries the transmittance of the
    /// media it crosses ([`shadow_transmittance`]). `medium` is the medium
    /// the path's ray was in (a shadow ray from a surface boundary starts
    /// in the medium of the side it leaves to).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn sample_light_in_media(
        &self,
        scene: &Scene,
        vertex: Scatterer<'_>,
        wo: Vec3,
        medium: Option<MediumId>,
        u_light: f32,
        u_point: crate::geometry::Vec2,
        stats: &mut RayStats,
    ) -> Color {
        let lights = scene.light_set();
        let Some((index, pmf)) = lights.sample(u_light) else { return Color::ZERO };
        let emitter = &lights.emitters()[index];
        let ctx = match vertex {
            Scatterer::Surface(si, _) => LightSampleContext { p: si.p, n: si.n },
            Scatterer::Medium(p, _) => LightSampleContext { p, n: Vec3::ZERO },
        };
        let Some(ls) = emitter.sample_li(&ctx, u_point) else { return Color::ZERO };
        if ls.pdf <= 0.0 || ls.l.max_element() <= 0.0 {
            return Color::ZERO;
        }
        // The scattering function's value and density towards the light;
        // after the shadow ray where they are the dearer of the two (see
        // `weigh_light_sample`).
        let scatter = || match vertex {
            Scatterer::Surface(_, bsdf) => (bsdf.f(wo, ls.wi) * ls.wi.dot(bsdf.frame().z).abs(), bsdf.pdf(wo, ls.wi)),
            Scatterer::Medium(_, phase) => {
                let p = phase.p(wo, ls.wi);
                (Color::splat(p), p)
            }
        };
        let visibility_first = match vertex {
            Scatterer::Surface(_, bsdf) => {
                bsdf.bxdf().f_costs_more_than_a_ray(bsdf.frame().to_local(wo), bsdf.frame().to_local(ls.wi))
            }
            Scatterer::Medium(..) => false,
        };
        let mut scattered = None;
        if !visibility_first {
            let (f, p) = scatter();
            if f.max_element() <= 0.0 {
                return Color::ZERO;
            }
            scattered = Some((f, p));
        }
        stats.shadow += 1;
        let (ray, t_max, start) = match vertex {
            Scatterer::Surface(si, _) => {
                let start = if si.media.is_transition() { si.media.medium_along(ls.wi, si.n) } else { medium };
                let (ray, t_max) = match ls.p_light {
                    Some(p) => si.spawn_ray_to(p),
                    None => (si.spawn_ray(ls.wi), f32::INFINITY),
                };
                (ray, t_max, start)
            }
            Scatterer::Medium(p, _) => match ls.p_light {
                Some(target) => (Ray::new(p, target - p), 1.0 - crate::interaction::SHADOW_EPSILON, medium),
                None => (Ray::new(p, ls.wi), f32::INFINITY, medium),
            },
        };
        let tr = shadow_transmittance(scene, ray, t_max, ls.p_light, start);
        if tr.max_element() <= 0.0 {
            return Color::ZERO;
        }
        let (f, p_scatter) = match scattered {
            Some(fp) => fp,
            None => {
                let (f, p) = scatter();
                if f.max_element() <= 0.0 {
                    return Color::ZERO;
                }
                (f, p)
            }
        };
        let p_light = pmf * ls.pdf;
        if emitter.is_delta() || self.direct == DirectLighting::LightsOnly {
            f * tr * ls.l / p_light
        } else {
            let w = power_heuristic(p_light, p_scatter);
            f * tr * ls.l * (w / p_light)
        }
    }

    /// A ray segment `[0, t_max)` in `medium`: whether and where the path
    /// scatters, and at a scattering point, the light sampled there (next-
    /// event estimation with the phase function) and the direction the
    /// phase function continues in (see the type's docs). `flight` is the
    /// segment's free flight, which the caller drew before its ray query
    /// and bounded the query with.
    /// Out of line: only scenes with media call it.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn medium_segment(
        &self,
        scene: &Scene,
        medium: MediumId,
        ray: &Ray,
        t_max: f32,
        flight: FreeFlight,
        at: PathVertexState,
        sampler: &mut Sampler,
        stats: &mut RayStats,
    ) -> MediumStep {
        let PathVertexState { beta, eta_scale, depth, any_non_specular } = at;
        let m = scene.medium(medium);
        let (t, weight, emission) = match m.sample_flight(flight, t_max) {
            MediumEvent::Pass { weight } => return MediumStep::Pass(weight),
            MediumEvent::Scatter { t, weight, emission } => (t, weight, emission),
        };
        // Emission along the segment: direct light (after a non-specular
        // vertex, indirect).
        let mut radiance = Color::ZERO;
        if emission.max_element() > 0.0 {
            radiance += self.contribution(beta * emission, any_non_specular);
        }
        let mut beta = beta * weight;
        if beta.max_element() <= 0.0 || !beta.is_finite() || depth >= self.max_depth {
            return MediumStep::Stop(radiance);
        }
        let p = ray.at(t);
        let wo = -ray.dir;
        let phase = m.phase();
        // The same five dimensions per vertex as at a surface.
        let u_light = sampler.get_1d();
        let u_point = sampler.get_2d();
        if self.direct != DirectLighting::BsdfOnly {
            let vertex = Scatterer::Medium(p, phase);
            let direct = beta * self.sample_light_in_media(scene, vertex, wo, Some(medium), u_light, u_point, stats);
            radiance += self.contribution(direct, any_non_specular);
        }
        let _u_lobe = sampler.get_1d();
        let u_dir = sampler.get_2d();
        let u_rr = sampler.get_1d();
        // Henyey–Greenstein sampling is exact: f / pdf = 1.
        let (wi, pdf) = phase.sample(wo, u_dir);
        stats.secondary += 1;
        if depth + 1 >= RR_DEPTH {
            let survive = (beta * eta_scale).max_element().min(0.95);
            if u_rr >= survive {
                return MediumStep::Stop(radiance);
            }
            beta /= survive;
        }
        MediumStep::Scatter(MediumScatter { radiance, beta, ray: Ray::new(p, wi), pdf })
    }
}

/// What [`PathIntegrator::medium_segment`] needs of the path.
#[derive(Clone, Copy)]
struct PathVertexState {
    beta: Color,
    eta_scale: f32,
    depth: u32,
    any_non_specular: bool,
}

/// The outcome of a ray segment in a medium.
enum MediumStep {
    /// The ray reaches the surface (or leaves the scene): multiply the
    /// throughput by this.
    Pass(Color),
    /// The path ends here, after adding this radiance.
    Stop(Color),
    /// The path scattered and goes on.
    Scatter(MediumScatter),
}

/// A scattering event in a medium: what it added and how the path goes on.
struct MediumScatter {
    /// Radiance found here (emission and next-event estimation).
    radiance: Color,
    /// The new throughput.
    beta: Color,
    /// The ray the phase function continues along (from the scattering
    /// point).
    ray: Ray,
    /// The phase function's pdf of its direction (for MIS at the next hit).
    pdf: f32,
}
