//! The path integrator's loop: many paths at once, advanced a vertex at a
//! time in stages.
//!
//! A batch of up to [`PATH_LANES`] camera rays (one lane each) is traced
//! together. Each round of the loop takes every live lane one vertex
//! further, in four stages, each run over all the lanes that need it
//! before the next starts:
//!
//! 1. **surface**: the ray query, the medium segment up to the hit (scenes
//!    with media), light found by the ray (emitters; the environment for
//!    all the lanes that left the scene at once, so that their reads of
//!    its image overlap), and the material at the hit. A lane that hit an
//!    interface or scattered in a medium goes straight to the next round;
//!    a lane that left the scene or reached the depth limit ends; the
//!    others have a BSDF to shade with;
//! 2. **samples**: the five sample dimensions of the vertex ([`VertexSamples`])
//!    for every shading lane at once ([`Sampler::vertex_lanes`]);
//! 3. **light**: next-event estimation (diffuse vertices sampling a
//!    rectangle light all at once, in vector code: [`super::light_lanes`];
//!    the points of sphere lights for any non-specular vertex likewise:
//!    [`super::sphere_lanes`]);
//! 4. **scatter**: the BSDF sample that continues the path, and Russian
//!    roulette (diffuse vertices all at once, in vector code:
//!    [`super::scatter_lanes`]; rough conductors likewise:
//!    [`super::conductor_lanes`]).
//!
//! This is the structure of vectorised production path tracers (Lee et
//! al., "Vectorized Production Path Tracing", HPG 2017: queue, then shade
//! in SIMD; Mitsuba 3 runs its whole loop on wide lanes), in the form that
//! lets each stage run across lanes: the sample stage does, so do the
//! light stage for diffuse vertices and rectangle lights, the sampling of
//! sphere lights and the scatter stage for diffuse and rough conductor
//! vertices, and each stage is a loop over an index list that a vector
//! kernel can take over (for the lanes it knows; the others keep the
//! scalar code, in the same loop).
//!
//! Lanes never interact: a lane's result depends only on its own ray and
//! sampler, whatever the other lanes of its batch, in which order they
//! run, or when they end. A render is therefore the same whatever the
//! batches (and the number of threads), and equal to tracing each path
//! alone ([`crate::integrator::Integrator::li`] is a batch of one).

use super::conductor_lanes::ConductorLanes;
use super::environment_lanes::EnvironmentLanes;
use super::light_lanes::RectangleLanes;
use super::scatter_lanes::DiffuseLanes;
use super::sphere_lanes::SphereLanes;
use super::{
    material_context, DirectLighting, MediumStep, PathIntegrator, PathVertexState, MAX_INTERFACE_SKIPS, RR_DEPTH,
};
use crate::bsdf::{Bsdf, Bxdf};
use crate::color::Color;
use crate::geometry::{Ray, Vec3};
use crate::integrator::medium_segment::MediumSegment;
use crate::integrator::RayStats;
use crate::interaction::SurfaceInteraction;
use crate::light::{Emitter, LiSample, LightSampleContext};
use crate::medium::MediumId;
use crate::sampling::{Sampler, VertexSamples};
use crate::scene::Scene;

/// Most paths traced together in one batch: a run of 64 pixels of a row,
/// one sample each. (16 lanes measured 2% slower on the Cornell box: the
/// stages then run on fewer lanes once paths start to end.)
pub const PATH_LANES: usize = crate::geometry::LANES;

/// One path's state between vertices.
#[derive(Clone, Copy)]
pub(super) struct PathState {
    /// Radiance found so far.
    pub(super) radiance: Color,
    /// Path throughput: product of f·|cos θ|/pdf along the path so far.
    pub(super) beta: Color,
    /// Accumulated η² of refractions, for Russian roulette.
    pub(super) eta_scale: f32,
    /// Whether the last bounce was from a delta lobe (no MIS possible).
    pub(super) specular_bounce: bool,
    /// Whether any vertex so far scattered non-specularly.
    pub(super) any_non_specular: bool,
    /// Whether a vertex before the last one scattered non-specularly:
    /// light found from the last one is then indirect (`max_indirect`).
    pub(super) indirect: bool,
    /// Interfaces passed in a row.
    skips: u32,
    /// The pdf of the last scattering direction, and where it was chosen,
    /// for MIS of light the ray finds.
    pub(super) prev_pdf: f32,
    pub(super) prev_ctx: LightSampleContext,
    /// The ray to trace next.
    pub(super) ray: Ray,
    /// Scattering events so far.
    pub(super) depth: u32,
    /// The medium the ray travels in (always `None` without media).
    pub(super) medium: Option<MediumId>,
}

impl PathState {
    /// A path starting along `camera_ray` in `medium`.
    pub(super) fn new(camera_ray: &Ray, medium: Option<MediumId>) -> Self {
        Self {
            radiance: Color::ZERO,
            beta: Color::ONE,
            eta_scale: 1.0,
            specular_bounce: false,
            any_non_specular: false,
            indirect: false,
            skips: 0,
            prev_pdf: 0.0,
            prev_ctx: LightSampleContext { p: camera_ray.origin, n: Vec3::ZERO },
            ray: Ray::new(camera_ray.origin, camera_ray.dir.normalize()),
            depth: 0,
            medium,
        }
    }
}

/// What the surface stage found for a lane.
enum Surface {
    /// The path has ended.
    End,
    /// The ray left the scene into an environment light: the path ends
    /// with the light it finds there, added for all such lanes at once
    /// ([`PathIntegrator::escape`]).
    Escape,
    /// The path goes on with a new ray and no vertex to shade (it passed an
    /// interface, or scattered in a medium).
    Trace,
    /// A surface to shade, written to the lane's vertex.
    Shade,
}

/// The lanes of a batch that some stage runs on, in any order.
pub(super) struct LaneList {
    lanes: [u8; PATH_LANES],
    len: usize,
}

impl LaneList {
    pub(super) fn empty() -> Self {
        Self { lanes: [0; PATH_LANES], len: 0 }
    }

    fn first(n: usize) -> Self {
        let mut list = Self::empty();
        for i in 0..n {
            list.push(i);
        }
        list
    }

    #[inline]
    pub(super) fn push(&mut self, lane: usize) {
        self.lanes[self.len] = lane as u8;
        self.len += 1;
    }

    #[inline]
    pub(super) fn as_slice(&self) -> &[u8] {
        &self.lanes[..self.len]
    }
}

/// What the light stage's kernels ([`RectangleLanes`], [`SphereLanes`],
/// [`EnvironmentLanes`]) share when they estimate the light of the lanes
/// they took: the integrator and the scene, every lane's path, vertex and
/// samples, and the batch's counters.
pub(super) struct LightStage<'s> {
    pub(super) integrator: &'s PathIntegrator,
    pub(super) scene: &'s Scene,
    pub(super) paths: &'s mut [PathState],
    pub(super) hits: &'s [Option<SurfaceInteraction>],
    pub(super) bsdfs: &'s [Option<Bsdf>],
    pub(super) u: &'s [VertexSamples],
    pub(super) stats: &'s mut RayStats,
    /// Whether the scene has interfaces (found on the first shadow ray).
    pub(super) interfaces: &'s mut Option<bool>,
}

impl LightStage<'_> {
    /// Add the light sample `ls` of lane `lane`, whose light (not a delta
    /// light) was picked with probability `pmf`: weighed as
    /// [`PathIntegrator::sample_light`] weighs it, tested with a shadow ray
    /// where it carries light, and added to the lane's path (indirect if an
    /// earlier vertex was non-specular, as for the scalar light sample).
    #[inline(always)]
    pub(super) fn add_light_sample(&mut self, lane: usize, pmf: f32, ls: LiSample) {
        let (Some(si), Some(bsdf)) = (&self.hits[lane], &self.bsdfs[lane]) else {
            unreachable!("a lane taken has a vertex")
        };
        let path = &mut self.paths[lane];
        let wo = -path.ray.dir;
        let direct = path.beta
            * self.integrator.weigh_light_sample(self.scene, si, bsdf, wo, false, pmf, ls, self.stats, self.interfaces);
        path.radiance += self.integrator.contribution(direct, path.any_non_specular);
    }
}

impl PathIntegrator {
    /// Radiance along each of at most [`PATH_LANES`] `rays`, one path
    /// sample per ray, with `samplers[i]` positioned at ray `i`'s pixel
    /// sample (film and lens dimensions consumed): into `radiance[i]`.
    pub(super) fn li_batch(
        &self,
        scene: &Scene,
        rays: &[Ray],
        samplers: &mut [Sampler],
        radiance: &mut [Color],
        stats: &mut RayStats,
    ) {
        let n = rays.len();
        debug_assert!(n <= PATH_LANES);
        let medium = scene.camera_medium();
        let mut paths = [PathState::new(&Ray::new(Vec3::ZERO, Vec3::Z), None); PATH_LANES];
        for (path, ray) in paths.iter_mut().zip(rays) {
            *path = PathState::new(ray, medium);
        }
        stats.camera += n as u64;
        // Each lane's vertex: the surface its ray hit and the BSDF there
        // (both written by the surface stage for the lanes it shades).
        let mut hits: [Option<SurfaceInteraction>; PATH_LANES] = [None; PATH_LANES];
        let mut bsdfs: [Option<Bsdf>; PATH_LANES] = [None; PATH_LANES];
        let mut u = [VertexSamples::default(); PATH_LANES];
        let mut interfaces: Option<bool> = None;
        let mut live = LaneList::first(n);
        let nee = self.direct != DirectLighting::BsdfOnly;
        // Non-specular vertices whose light is an environment image take
        // their samples in steps across lanes ([`EnvironmentLanes`]).
        let mut environment = EnvironmentLanes::new(scene).filter(|_| nee);
        // Diffuse vertices that sample a rectangle light take the lane
        // kernel ([`RectangleLanes`]; not in scenes with media, whose light
        // samples carry transmittance). Its buffers are made on first use.
        let kernel = !scene.has_media() && scene.light_set().has_rectangles();
        let mut rectangles: Option<RectangleLanes> = None;
        // Non-specular vertices whose light is a sphere sample its cone in
        // the lane kernel ([`SphereLanes`]; likewise not with media).
        let sphere_kernel = !scene.has_media() && scene.light_set().has_spheres();
        let mut spheres: Option<SphereLanes> = None;
        // Diffuse vertices scatter in the lane kernel ([`DiffuseLanes`]),
        // rough conductors in theirs ([`ConductorLanes`]).
        let mut diffuse: Option<DiffuseLanes> = None;
        let mut conductors: Option<ConductorLanes> = None;
        while live.len > 0 {
            // 1. Ray queries and what they find.
            let mut next = LaneList::empty();
            let mut shade = LaneList::empty();
            let mut escape = LaneList::empty();
            for &lane in live.as_slice() {
                let i = lane as usize;
                match self.surface(scene, &mut paths[i], &mut hits[i], &mut bsdfs[i], &mut samplers[i], stats) {
                    Surface::End => {}
                    Surface::Escape => escape.push(i),
                    Surface::Trace => next.push(i),
                    Surface::Shade => shade.push(i),
                }
            }
            // 2. The vertex's sample dimensions, drawn even where unused to
            // keep the pattern fixed.
            Sampler::vertex_lanes(samplers, shade.as_slice(), &mut u);
            // The environment image's light samples, for the lanes whose
            // light pick it is.
            if let Some(e) = &mut environment {
                e.start(scene, &bsdfs, &u, shade.as_slice());
            }
            if escape.len > 0 {
                self.escape(scene, &mut paths, escape.as_slice());
            }
            // 3. Next-event estimation.
            if nee {
                if let Some(r) = &mut rectangles {
                    r.clear();
                }
                if let Some(s) = &mut spheres {
                    s.clear();
                }
                for &lane in shade.as_slice() {
                    let i = lane as usize;
                    let (Some(si), Some(bsdf)) = (&hits[i], &bsdfs[i]) else { continue };
                    if bsdf.is_specular() || environment.as_ref().is_some_and(|e| e.took(lane)) {
                        continue;
                    }
                    // The light pick, made once for both kernels (the scalar
                    // `sample_light` makes its own), where one may take the
                    // lane: the rectangle kernel takes only diffuse ones.
                    let diffuse = kernel && matches!(bsdf.bxdf(), Bxdf::Diffuse(_));
                    if diffuse || sphere_kernel {
                        let Some(pick) = scene.light_set().sample(u[i].light) else { continue };
                        if diffuse && rectangles.get_or_insert_with(RectangleLanes::new).take(scene, lane, si, pick) {
                            continue;
                        }
                        if sphere_kernel
                            && spheres.get_or_insert_with(SphereLanes::new).take(scene, lane, si, pick, u[i].point)
                        {
                            continue;
                        }
                    }
                    let path = &mut paths[i];
                    let wo = -path.ray.dir;
                    let direct = path.beta
                        * self.sample_light(
                            scene,
                            si,
                            bsdf,
                            wo,
                            path.medium,
                            u[i].light,
                            u[i].point,
                            stats,
                            &mut interfaces,
                        );
                    // The light's last bounce is this vertex: indirect if an
                    // earlier one was non-specular.
                    path.radiance += self.contribution(direct, path.any_non_specular);
                }
                let mut stage = LightStage {
                    integrator: self,
                    scene,
                    paths: &mut paths,
                    hits: &hits,
                    bsdfs: &bsdfs,
                    u: &u,
                    stats,
                    interfaces: &mut interfaces,
                };
                if let Some(r) = &mut rectangles {
                    r.estimate(&mut stage);
                }
                if let Some(s) = &mut spheres {
                    s.estimate(&mut stage);
                }
                if let Some(e) = &environment {
                    e.estimate(&mut stage);
                }
            }
            // 4. Continue by sampling the BSDF.
            if let Some(d) = &mut diffuse {
                d.clear();
            }
            if let Some(c) = &mut conductors {
                c.clear();
            }
            for &lane in shade.as_slice() {
                let i = lane as usize;
                let (Some(si), Some(bsdf)) = (&hits[i], &bsdfs[i]) else { continue };
                // (A kernel's buffers are made on its first lane.)
                match bsdf.bxdf() {
                    Bxdf::Diffuse(lobe) => {
                        // (Its frame unfinished: the kernel makes it.)
                        debug_assert!(bsdf.frame_pending());
                        let kernel = diffuse.get_or_insert_with(DiffuseLanes::new);
                        kernel.take(lane, &paths[i], si, bsdf.frame(), lobe, &u[i]);
                    }
                    Bxdf::Conductor(lobe) if ConductorLanes::takes(lobe) => {
                        let kernel = conductors.get_or_insert_with(ConductorLanes::new);
                        kernel.take(lane, &paths[i], si, bsdf.frame(), lobe, &u[i]);
                    }
                    _ => {
                        if self.scatter(&mut paths[i], si, bsdf, &u[i], stats) {
                            next.push(i);
                        }
                    }
                }
            }
            if let Some(d) = &mut diffuse {
                d.scatter(&mut paths, &hits, stats, &mut next);
            }
            if let Some(c) = &mut conductors {
                c.scatter(&mut paths, &hits, stats, &mut next);
            }
            live = next;
        }
        for (out, path) in radiance.iter_mut().zip(&paths) {
            *out = path.radiance;
        }
    }

    /// The surface stage for one lane: trace its ray, cross the medium up
    /// to the hit, add the light the ray finds, and resolve the material
    /// (into `hit` and `bsdf`, for [`Surface::Shade`]). Both are written
    /// where they are computed and read from there, so that the hit record
    /// and the BSDF are not copied on their way (each is written by the
    /// call that makes it straight into the lane's slot).
    fn surface(
        &self,
        scene: &Scene,
        path: &mut PathState,
        hit: &mut Option<SurfaceInteraction>,
        bsdf: &mut Option<Bsdf>,
        sampler: &mut Sampler,
        stats: &mut RayStats,
    ) -> Surface {
        let ray = path.ray;
        // In a medium, the segment's free flight first: it bounds the
        // query, so that a path that collides before reaching a surface
        // (most paths in a dense medium) builds no hit record.
        let segment = MediumSegment::draw(scene, path.medium, path.beta, sampler);
        scene.intersect_into(&ray, MediumSegment::query_bound(segment), hit);
        if let Some(segment) = segment {
            // The segment up to the hit (or infinity) in a medium: it may
            // scatter on the way, or pass with its transmittance. (Out of
            // line: scenes without media never come here.)
            let t_max = hit.as_ref().map_or(f32::INFINITY, |si| si.t);
            let at = PathVertexState {
                beta: path.beta,
                eta_scale: path.eta_scale,
                depth: path.depth,
                any_non_specular: path.any_non_specular,
            };
            match self.medium_segment(scene, segment.medium, &ray, t_max, segment.flight, at, sampler, stats) {
                MediumStep::Pass(weight) => {
                    path.beta *= weight;
                    if path.beta.max_element() <= 0.0 || !path.beta.is_finite() {
                        return Surface::End;
                    }
                }
                MediumStep::Stop(add) => {
                    path.radiance += add;
                    return Surface::End;
                }
                MediumStep::Scatter(s) => {
                    // A scattering point is a vertex: interfaces are counted
                    // again from here.
                    path.skips = 0;
                    path.radiance += s.radiance;
                    path.beta = s.beta;
                    path.specular_bounce = false;
                    path.indirect = path.any_non_specular;
                    path.any_non_specular = true;
                    path.prev_pdf = s.pdf;
                    path.prev_ctx = LightSampleContext { p: s.ray.origin, n: Vec3::ZERO };
                    path.ray = s.ray;
                    path.depth += 1;
                    return Surface::Trace;
                }
            }
        }
        let lights = scene.light_set();
        let Some(si) = hit.as_ref() else {
            // The ray leaves the scene: environment light, if any.
            return if scene.environment_light().is_some() { Surface::Escape } else { Surface::End };
        };
        let wo = -ray.dir;

        // Light emitted by the surface hit.
        if let Some(index) = si.light {
            let index = index as usize;
            if let Emitter::Area(area) = &lights.emitters()[index] {
                let le = area.emitted_at(si.p, si.uv, si.attributes, wo);
                if le.max_element() > 0.0 {
                    let c = if path.depth == 0 || path.specular_bounce {
                        path.beta * le
                    } else {
                        let p_light =
                            lights.pmf(index) * lights.emitters()[index].pdf_li(&path.prev_ctx, ray.dir, si.p, si.n);
                        path.beta * le * self.bsdf_weight(path.prev_pdf, p_light)
                    };
                    path.radiance += self.contribution(c, path.indirect);
                }
            }
        }
        // The material at the hit; an interface is no surface: go on
        // through it without counting a bounce. (A diffuse BSDF's frame is
        // left to the diffuse scatter kernel, which makes those of all its
        // lanes at once: `Bsdf::diffuse_unframed`.)
        let mctx = material_context(si, wo);
        *bsdf = scene.material(si.material).bsdf_at_unframed(&mctx, scene.materials());
        let Some(bsdf) = bsdf.as_mut() else {
            path.skips += 1;
            if path.skips > MAX_INTERFACE_SKIPS {
                return Surface::End;
            }
            if si.media.is_transition() {
                path.medium = si.media.medium_along(ray.dir, si.n);
            }
            path.ray = si.spawn_ray(ray.dir);
            return Surface::Trace;
        };
        path.skips = 0;
        if path.depth >= self.max_depth {
            return Surface::End;
        }
        if self.regularize && path.any_non_specular {
            bsdf.regularize();
        }
        Surface::Shade
    }

    /// The light that the rays of `lanes`, which left the scene, find in
    /// the environment light. The environment's radiance and (for MIS) its
    /// pdf of each direction are looked up for all the lanes at once
    /// ([`crate::light::Environment::le_pdf_many`]), so that their reads
    /// of the image overlap.
    fn escape(&self, scene: &Scene, paths: &mut [PathState], lanes: &[u8]) {
        let Some((index, env)) = scene.environment_light() else { return };
        let n = lanes.len();
        let mut dirs = [Vec3::ZERO; PATH_LANES];
        for (dir, &lane) in dirs.iter_mut().zip(lanes) {
            *dir = paths[lane as usize].ray.dir;
        }
        let mut found = [(Color::ZERO, 0.0); PATH_LANES];
        env.le_pdf_many(&dirs[..n], &mut found[..n]);
        let pmf = scene.light_set().pmf(index);
        for (&(le, pdf), &lane) in found.iter().zip(lanes) {
            let path = &mut paths[lane as usize];
            let c = if path.depth == 0 || path.specular_bounce {
                path.beta * le
            } else {
                // MIS against the environment's own sampling
                // (`Emitter::pdf_li` of the environment).
                path.beta * le * self.bsdf_weight(path.prev_pdf, pmf * pdf)
            };
            path.radiance += self.contribution(c, path.indirect);
        }
    }

    /// The scatter stage for one lane: sample the BSDF at `si` for the
    /// path's next direction, then Russian roulette. Whether the path goes
    /// on.
    pub(super) fn scatter(
        &self,
        path: &mut PathState,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        u: &VertexSamples,
        stats: &mut RayStats,
    ) -> bool {
        let wo = -path.ray.dir;
        let Some(bs) = bsdf.sample_f(wo, u.lobe, u.dir) else { return false };
        if bs.pdf <= 0.0 || bs.f.max_element() <= 0.0 {
            return false;
        }
        path.beta *= bs.f * (bs.wi.dot(bsdf.frame().z).abs() / bs.pdf);
        if !path.beta.is_finite() {
            return false;
        }
        path.specular_bounce = bs.specular;
        // Light found by this bounce is indirect if a vertex before this
        // one scattered non-specularly.
        path.indirect = path.any_non_specular;
        path.any_non_specular |= !bs.specular;
        path.prev_pdf = bs.pdf;
        path.prev_ctx = LightSampleContext { p: si.p, n: si.n };
        if bs.transmission {
            path.eta_scale *= bs.eta * bs.eta;
        }
        if si.media.is_transition() {
            path.medium = si.media.medium_along(bs.wi, si.n);
        }
        path.ray = si.spawn_ray(bs.wi);
        stats.secondary += 1;

        // Russian roulette, from the vertex RR_DEPTH on: survive with
        // probability min(max β·η², 0.95) and divide by it.
        if path.depth + 1 >= RR_DEPTH {
            let survive = (path.beta * path.eta_scale).max_element().min(0.95);
            if u.rr >= survive {
                return false;
            }
            path.beta /= survive;
        }
        path.depth += 1;
        true
    }
}
