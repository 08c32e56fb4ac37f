//! Bidirectional path tracing (Veach & Guibas, "Bidirectional Estimators
//! for Light Transport", 1994; Veach's thesis, 1997, ch. 10; the structure
//! of PBRT 3rd ed. §16.3 and pbrt-v4's `BDPTIntegrator`).
//!
//! Each camera sample traces two subpaths: one from the camera (the camera
//! ray, continued by BSDF and phase-function sampling in *radiance* mode)
//! and one from a light (an emitted ray, continued in *importance* mode,
//! [`TransportMode`]). Every prefix of one is then joined to every prefix
//! of the other: with `s` light vertices and `t` camera vertices, the
//! strategy `(s, t)` is
//!
//! * `s = 0`: the camera subpath itself hits a light (what a path tracer
//!   finds by BSDF sampling);
//! * `s = 1`: the camera subpath's last vertex is joined to a point
//!   sampled on a light (next-event estimation);
//! * `t = 1`: the light subpath's last vertex is joined to a point sampled
//!   on the camera lens: light tracing. The contribution lands wherever on
//!   the film that connection points, not at the camera sample's pixel: it
//!   is *splatted* ([`FilmSplat`]) into the film's light image;
//! * otherwise both last vertices are joined by a shadow ray, through the
//!   geometry term `G = |cos θ₁| |cos θ₂| / d²` and the transmittance of
//!   any media between them.
//!
//! A path of `k` edges can be made by `k + 2` strategies; their
//! contributions are weighted by the balance heuristic over all of them
//! ([`mis_weight`], Veach 1997 §10.2), so each path is counted once and
//! mostly by the strategy that samples it best: light tracing for
//! caustics seen directly (a light through glass onto a diffuse floor),
//! next-event estimation for direct light, and so on. Strategies that
//! cannot make a path (through a delta lobe, or to a delta light) get no
//! weight.
//!
//! Both subpaths use the same BSDFs, phase functions, lights, camera and
//! sampler as the path tracer; the light subpath uses the adjoint BSDF and
//! corrects for shading normals (Veach 1997, §5.3), so that it carries
//! importance exactly. Depth counts as in the path tracer: a path of at
//! most `max_depth` scattering vertices (`s + t − 2 ≤ max_depth`).
//!
//! Light subpaths in scenes with media start in the medium their first ray
//! finds at the first boundary it meets (the side it arrives from), or the
//! camera's medium when that surface is no boundary: lights carry no
//! medium of their own in lucent. A medium's emission is found by the
//! camera subpath alone (no other strategy can sample it), with weight 1.
//!
//! Cameras without an importance function (orthographic, spherical; see
//! [`crate::camera::Camera::has_importance`]) render without the `t = 1`
//! strategies, which the weights of the others then leave out.

mod vertex;

use super::medium_segment::MediumSegment;
use super::path::{material_context, MAX_INTERFACE_SKIPS};
use super::{FilmSplat, Integrator, RayStats};
use crate::bsdf::TransportMode;
use crate::color::Color;
use crate::geometry::{Ray, Vec2, Vec3};
use crate::interaction::SHADOW_EPSILON;
use crate::light::{Emitter, Falloff, Light};
use crate::medium::{MediumEvent, MediumId};
use crate::sampling::Sampler;
use crate::scene::Scene;
use vertex::{infinite_light_density, sample_context, shading_normal_correction, Context, Vertex, VertexKind};

/// Bidirectional path tracing with multiple importance sampling over every
/// strategy (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BdptIntegrator {
    /// Most scattering vertices of a path (1: direct light only).
    pub max_depth: u32,
    /// For checking: only the strategy `(s, t)` contributes, unweighted
    /// (pbrt-v4's `visualizestrategies`). Each strategy alone estimates
    /// all the light of the paths it can make, so on a scene where every
    /// strategy can make every path of `s + t − 2` bounces they all
    /// converge to the same image. `None` (the default): all strategies,
    /// weighted.
    pub only_strategy: Option<(usize, usize)>,
    /// The scene's finite bounds, where lights at infinity start their
    /// rays from ([`crate::light::Emitter::sample_le`]).
    bounds: crate::geometry::Bounds3,
    /// The centre of the sphere around `bounds`.
    centre: Vec3,
    /// Whether the scene may have surfaces that rays pass through
    /// ([`super::path::may_have_interfaces`]).
    interfaces: bool,
}

impl BdptIntegrator {
    /// A bidirectional path tracer for `scene`, with paths of at most
    /// `max_depth` scattering vertices.
    pub fn new(scene: &Scene, max_depth: u32) -> Self {
        let bounds = scene.bounds();
        let centre =
            if bounds.is_empty() || bounds.is_infinite() { Vec3::ZERO } else { 0.5 * (bounds.min + bounds.max) };
        Self { max_depth, only_strategy: None, bounds, centre, interfaces: super::path::may_have_interfaces(scene) }
    }

    /// This integrator with only strategy `(s, t)`, unweighted (see
    /// [`BdptIntegrator::only_strategy`]).
    pub fn with_only_strategy(self, s: usize, t: usize) -> Self {
        Self { only_strategy: Some((s, t)), ..self }
    }

    fn context<'a>(&self, scene: &'a Scene) -> Context<'a> {
        Context {
            scene,
            bounds: self.bounds,
            radius: crate::light::scene_radius(&self.bounds),
            centre: self.centre,
            interfaces: self.interfaces,
        }
    }
}

impl Integrator for BdptIntegrator {
    /// The camera sample's radiance by every strategy but light tracing
    /// (`t = 1`), whose contributions need [`Integrator::li_splat`].
    fn li(&self, scene: &Scene, ray: &Ray, sampler: &mut Sampler, stats: &mut RayStats) -> Color {
        let mut splats = Vec::new();
        self.li_splat(scene, ray, sampler, &mut splats, stats)
    }

    fn splats_light(&self) -> bool {
        true
    }

    fn li_splat(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        splats: &mut Vec<FilmSplat>,
        stats: &mut RayStats,
    ) -> Color {
        // The subpaths' vertices, in buffers each thread keeps (a vertex
        // holds a surface interaction and a BSDF: hundreds of bytes).
        thread_local! {
            static SUBPATHS: std::cell::RefCell<(Vec<Vertex>, Vec<Vertex>)> = const { std::cell::RefCell::new((Vec::new(), Vec::new())) };
        }
        SUBPATHS.with(|buffers| {
            let (camera, light) = &mut *buffers.borrow_mut();
            camera.clear();
            light.clear();
            self.li_subpaths(scene, ray, sampler, splats, stats, camera, light)
        })
    }
}

impl BdptIntegrator {
    /// [`Integrator::li_splat`] with the subpaths' buffers.
    #[allow(clippy::too_many_arguments)]
    fn li_subpaths(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        splats: &mut Vec<FilmSplat>,
        stats: &mut RayStats,
        camera: &mut Vec<Vertex>,
        light: &mut Vec<Vertex>,
    ) -> Color {
        let ctx = self.context(scene);
        let depth = self.max_depth as usize;
        stats.camera += 1;
        let mut radiance = camera_subpath(&ctx, ray, sampler, depth + 2, camera, stats);
        light_subpath(&ctx, sampler, depth + 1, light, stats);
        let has_importance = scene.camera().has_importance();
        for t in 1..=camera.len() {
            // Next-event estimation (s = 1) samples its own light point: it
            // runs even when the light subpath could not start.
            for s in 0..=light.len().max(1) {
                let path_depth = s as i64 + t as i64 - 2;
                if (s == 1 && t == 1) || path_depth < 0 || path_depth > depth as i64 {
                    continue;
                }
                if t == 1 && !has_importance {
                    continue;
                }
                let only = self.only_strategy.map(|only| only == (s, t));
                if only == Some(false) {
                    continue;
                }
                match connect(&ctx, light, camera, s, t, only.is_none(), sampler, stats) {
                    Some(Connection { l, film: Some(film) }) => splats.push(FilmSplat { film, l }),
                    Some(Connection { l, film: None }) => radiance += l,
                    None => {}
                }
            }
        }
        radiance
    }
}

/// A strategy's weighted contribution, and for light tracing where on the
/// film it lands.
struct Connection {
    l: Color,
    film: Option<Vec2>,
}

/// Trace the camera subpath from `ray` into `path` (at most `max_vertices`,
/// the camera included). Returns the emission of media found on the way
/// (see the module docs).
fn camera_subpath(
    ctx: &Context,
    ray: &Ray,
    sampler: &mut Sampler,
    max_vertices: usize,
    path: &mut Vec<Vertex>,
    stats: &mut RayStats,
) -> Color {
    if max_vertices == 0 {
        return Color::ZERO;
    }
    let ray = Ray::new(ray.origin, ray.dir.normalize());
    let camera = ctx.scene.camera();
    let mut start = Vertex::camera(ray.origin, Color::ONE, ctx.scene.camera_medium());
    let (_, pdf_dir) = camera.pdf_importance_from(ray.origin, ray.dir);
    // A camera without importance takes no part in connections, and no
    // connection to the lens could make a ray that leaves from outside the
    // image (filter importance sampling places some there): mark the
    // endpoint degenerate, so that no weight counts the t = 1 strategies.
    start.delta = !camera.has_importance() || pdf_dir == 0.0;
    path.push(start);
    random_walk(
        ctx,
        ray,
        ctx.scene.camera_medium(),
        sampler,
        Color::ONE,
        pdf_dir,
        max_vertices - 1,
        TransportMode::Radiance,
        path,
        stats,
    )
}

/// Trace a light subpath into `path` (at most `max_vertices`, the light
/// endpoint included): a light chosen by power, a ray sampled from its
/// emission, then a random walk in importance mode.
fn light_subpath(
    ctx: &Context,
    sampler: &mut Sampler,
    max_vertices: usize,
    path: &mut Vec<Vertex>,
    stats: &mut RayStats,
) {
    if max_vertices == 0 {
        return;
    }
    let lights = ctx.scene.light_set();
    let u_light = sampler.get_1d();
    let (u_pos, u_dir) = (sampler.get_2d(), sampler.get_2d());
    let Some((index, pmf)) = lights.sample(u_light) else { return };
    let emitter = &lights.emitters()[index];
    let Some(le) = emitter.sample_le(u_pos, u_dir, &ctx.bounds) else { return };
    if le.pdf_pos <= 0.0 || le.pdf_dir <= 0.0 || le.l.max_element() <= 0.0 {
        return;
    }
    let infinite = matches!(emitter, Emitter::Environment(_) | Emitter::Delta(Light::Directional { .. }));
    let mut start = Vertex::light(index, le.ray.origin, le.n, infinite, le.l, pmf * le.pdf_pos);
    let cos = if le.n == Vec3::ZERO { 1.0 } else { le.n.dot(le.ray.dir).abs() };
    let beta = le.l * (cos / (pmf * le.pdf_pos * le.pdf_dir));
    let medium = if ctx.scene.has_media() { light_ray_medium(ctx.scene, &le.ray) } else { None };
    start.medium = medium;
    path.push(start);
    stats.secondary += 1;
    random_walk(
        ctx,
        le.ray,
        medium,
        sampler,
        beta,
        le.pdf_dir,
        max_vertices - 1,
        TransportMode::Importance,
        path,
        stats,
    );
    // A point or spot light without distance falloff (the classic ray
    // tracer's light, constant irradiance at any distance) emits, in
    // effect, an intensity that grows as d² with the distance to what it
    // lights: the first vertex of its subpath, and so all after it, carry
    // that factor, as next-event estimation does with its constant
    // irradiance.
    if let (
        Emitter::Delta(Light::Point { falloff: Falloff::None, .. } | Light::Spot { falloff: Falloff::None, .. }),
        true,
    ) = (emitter, path.len() > 1)
    {
        let d2 = (path[1].p - path[0].p).length_squared();
        for v in &mut path[1..] {
            v.beta *= d2;
        }
    }
    // The densities of a light at infinity are over the disk its rays
    // leave from and over directions (pbrt-v4's correction): the first
    // vertex was reached with the disk's density, and the endpoint is
    // chosen with the directional density of all lights at infinity.
    if infinite && path.len() > 1 {
        let v = &mut path[1];
        v.pdf_fwd = le.pdf_pos;
        if v.is_on_surface() {
            v.pdf_fwd *= le.ray.dir.dot(v.n).abs();
        }
        path[0].pdf_fwd = infinite_light_density(ctx, -le.ray.dir);
    }
}

/// The medium a light's ray starts in: the one on the side of its origin
/// at the first boundary between media the ray meets ahead (passing
/// surfaces that separate nothing), or else behind its origin; the camera's
/// when there is no boundary either way (a medium that fills the world).
fn light_ray_medium(scene: &Scene, ray: &Ray) -> Option<MediumId> {
    for dir in [ray.dir, -ray.dir] {
        let mut r = Ray::new(ray.origin, dir);
        for _ in 0..MAX_INTERFACE_SKIPS {
            let Some(hit) = scene.intersect(&r, f32::INFINITY) else { break };
            if hit.media.is_transition() {
                // The origin's side is the one the search ray came from.
                return hit.media.medium_along(-dir, hit.n);
            }
            r = hit.spawn_ray(dir);
        }
    }
    scene.camera_medium()
}

/// Extend `path` from its last vertex along `ray` (unit direction, chosen
/// with solid-angle density `pdf`) by BSDF and phase-function sampling, up
/// to `max_vertices` more vertices (pbrt-v4's `RandomWalk`). In radiance
/// mode a ray that leaves the scene ends the path on the environment, if
/// any. Returns the medium emission found (radiance mode).
#[allow(clippy::too_many_arguments)]
fn random_walk(
    ctx: &Context,
    mut ray: Ray,
    mut medium: Option<MediumId>,
    sampler: &mut Sampler,
    mut beta: Color,
    mut pdf: f32,
    max_vertices: usize,
    mode: TransportMode,
    path: &mut Vec<Vertex>,
    stats: &mut RayStats,
) -> Color {
    let scene = ctx.scene;
    let mut emitted = Color::ZERO;
    let mut added = 0;
    let mut skips = 0;
    while added < max_vertices {
        // In a medium, the segment's free flight first: it bounds the
        // query (as in the path tracer's surface stage).
        let segment = MediumSegment::draw(scene, medium, beta, sampler);
        let hit = scene.intersect(&ray, MediumSegment::query_bound(segment));
        // The segment through a medium: scatter in it, or pass with its
        // transmittance.
        if let Some(MediumSegment { medium: m, flight }) = segment {
            let t_max = hit.as_ref().map_or(f32::INFINITY, |si| si.t);
            match scene.medium(m).sample_flight(flight, t_max) {
                MediumEvent::Pass { weight } => beta *= weight,
                MediumEvent::Scatter { t, weight, emission } => {
                    if mode == TransportMode::Radiance {
                        emitted += beta * emission;
                    }
                    beta *= weight;
                    if beta.max_element() <= 0.0 || !beta.is_finite() {
                        break;
                    }
                    let phase = *scene.medium(m).phase();
                    let wo = -ray.dir;
                    let mut v = Vertex::medium(ray.at(t), phase, wo, beta, m);
                    let prev = path.last().expect("a walk starts at an endpoint");
                    v.pdf_fwd = prev.convert_density(pdf, &v);
                    path.push(v);
                    added += 1;
                    skips = 0;
                    if added >= max_vertices {
                        break;
                    }
                    let (wi, p) = phase.sample(wo, sampler.get_2d());
                    stats.secondary += 1;
                    // Henyey–Greenstein sampling is exact (f/pdf = 1), and
                    // symmetric: the reverse density is the same.
                    pdf = p;
                    let n = path.len();
                    let rev = path[n - 1].convert_density(p, &path[n - 2]);
                    path[n - 2].pdf_rev = rev;
                    ray = Ray::new(ray.at(t), wi);
                    continue;
                }
            }
            if beta.max_element() <= 0.0 || !beta.is_finite() {
                break;
            }
        }
        let Some(si) = hit else {
            // Escaped: in radiance mode, the path ends on the environment.
            if mode == TransportMode::Radiance {
                if let Some((index, _)) = scene.environment_light() {
                    let mut v = Vertex::light(index, ray.origin + ray.dir, Vec3::ZERO, true, beta, pdf);
                    v.medium = medium;
                    path.push(v);
                }
            }
            break;
        };
        let wo = -ray.dir;
        let mctx = material_context(&si, wo);
        let Some(bsdf) = scene.material(si.material).bsdf_at(&mctx, scene.materials()) else {
            // An interface: no surface, the ray goes on.
            skips += 1;
            if skips > MAX_INTERFACE_SKIPS {
                break;
            }
            if si.media.is_transition() {
                medium = si.media.medium_along(ray.dir, si.n);
            }
            ray = si.spawn_ray(ray.dir);
            continue;
        };
        skips = 0;
        let mut v = Vertex::surface(si, bsdf, wo, beta, medium);
        let prev = path.last().expect("a walk starts at an endpoint");
        v.pdf_fwd = prev.convert_density(pdf, &v);
        path.push(v);
        added += 1;
        if added >= max_vertices {
            break;
        }
        let (u_lobe, u_dir) = (sampler.get_1d(), sampler.get_2d());
        let Some(bs) = bsdf.sample_f_mode(wo, u_lobe, u_dir, mode) else { break };
        if bs.pdf <= 0.0 || bs.f.max_element() <= 0.0 {
            break;
        }
        stats.secondary += 1;
        beta *= bs.f * (bs.wi.dot(bsdf.frame().z).abs() / bs.pdf);
        if mode == TransportMode::Importance {
            beta *= shading_normal_correction(&si, bsdf.frame().z, wo, bs.wi);
        }
        if beta.max_element() <= 0.0 || !beta.is_finite() {
            break;
        }
        let n = path.len();
        let (pdf_rev, delta) = if bs.specular { (0.0, true) } else { (bsdf.pdf(bs.wi, wo), false) };
        pdf = if bs.specular { 0.0 } else { bs.pdf };
        path[n - 1].delta = delta;
        let rev = path[n - 1].convert_density(pdf_rev, &path[n - 2]);
        path[n - 2].pdf_rev = rev;
        if si.media.is_transition() {
            medium = si.media.medium_along(bs.wi, si.n);
        }
        ray = si.spawn_ray(bs.wi);
    }
    emitted
}

/// The transmittance between two vertices (zero when a surface blocks the
/// way), tracing from `from` towards `to`'s position.
fn transmittance(ctx: &Context, from: &Vertex, to: &Vertex, stats: &mut RayStats) -> Color {
    stats.shadow += 1;
    let target = to.p;
    let medium = match &from.si {
        Some(si) if si.media.is_transition() => si.media.medium_along(target - from.p, si.n),
        _ => from.medium,
    };
    let (ray, t_max, target) = if to.infinite {
        // Towards a light at infinity: nothing may block the way out.
        let dir = (target - from.p).normalize_or_zero();
        let ray = match &from.si {
            Some(si) => si.spawn_ray(dir),
            None => Ray::new(from.p, dir),
        };
        (ray, f32::INFINITY, None)
    } else {
        // The far end, if on a surface, is kept out by `t_max` just short
        // of it.
        let (ray, t_max) = match &from.si {
            Some(si) => si.spawn_ray_to(target),
            None => (Ray::new(from.p, target - from.p), 1.0 - SHADOW_EPSILON),
        };
        (ray, t_max, Some(target))
    };
    // Without media, an any-hit query settles most shadow rays; only a
    // blocked ray in a scene with interfaces needs the walk through them.
    if !ctx.scene.has_media() {
        if !ctx.scene.intersect_p(&ray, t_max) {
            return Color::ONE;
        }
        if !ctx.interfaces {
            return Color::ZERO;
        }
    }
    super::path::shadow_transmittance(ctx.scene, ray, t_max, target, medium)
}

/// The generalised geometry term between two vertices (PBRT 3rd ed.
/// eq. 16.6 with media): `|cos θ₀| |cos θ₁| / d²` (a cosine only at a
/// surface, with its shading normal) times the transmittance between them.
fn geometry(ctx: &Context, a: &Vertex, b: &Vertex, stats: &mut RayStats) -> Color {
    let d = a.p - b.p;
    let d2 = d.length_squared();
    if d2 == 0.0 {
        return Color::ZERO;
    }
    let mut g = 1.0 / d2;
    let w = d / d2.sqrt();
    if a.is_on_surface() {
        g *= a.ns.dot(w).abs();
    }
    if b.is_on_surface() {
        g *= b.ns.dot(w).abs();
    }
    if g == 0.0 {
        return Color::ZERO;
    }
    // Trace from a vertex with a surface (its spawn offset) or a free
    // point; a light endpoint has no surface record to offset from.
    let tr = if a.si.is_some() || b.si.is_none() && b.kind != VertexKind::Camera {
        transmittance(ctx, a, b, stats)
    } else {
        transmittance(ctx, b, a, stats)
    };
    tr * g
}

/// The contribution of strategy `(s, t)`: `s` light vertices and `t`
/// camera vertices joined (pbrt-v4's `ConnectBDPT`), weighted by
/// [`mis_weight`] if `weighted`. `None` when it is zero.
#[allow(clippy::too_many_arguments)]
fn connect(
    ctx: &Context,
    light: &[Vertex],
    camera: &[Vertex],
    s: usize,
    t: usize,
    weighted: bool,
    sampler: &mut Sampler,
    stats: &mut RayStats,
) -> Option<Connection> {
    let scene = ctx.scene;
    // A camera subpath that ended on a light at infinity (its last vertex
    // is that light, not a scattering point) is joined to nothing: only
    // s = 0 uses it.
    if t > 1 && s != 0 && camera[t - 1].kind != VertexKind::Surface && camera[t - 1].kind != VertexKind::Medium {
        return None;
    }
    let mut sampled: Option<Vertex> = None;
    let mut film = None;
    let l = if s == 0 {
        // The camera subpath alone: its last vertex is on a light.
        let pt = &camera[t - 1];
        pt.light_index()?;
        pt.le(ctx, &camera[t - 2]) * pt.beta
    } else if t == 1 {
        // Light tracing: join the light subpath's last vertex to the lens.
        let qs = &light[s - 1];
        if !qs.is_connectible(ctx) {
            return None;
        }
        let is = scene.camera().sample_importance(qs.p, sampler.get_2d())?;
        if is.pdf <= 0.0 || is.we <= 0.0 {
            return None;
        }
        let cam = Vertex::camera(is.p_lens, Color::splat(is.we / is.pdf), scene.camera_medium());
        let l = join_endpoint(ctx, qs, &cam, is.wi, TransportMode::Importance, stats)?;
        film = Some(is.film);
        sampled = Some(cam);
        l
    } else if s == 1 {
        // Next-event estimation: join the camera subpath's last vertex to
        // a point sampled on a light.
        let pt = &camera[t - 1];
        if !pt.is_connectible(ctx) {
            return None;
        }
        let lights = scene.light_set();
        let u_light = sampler.get_1d();
        let u = sampler.get_2d();
        let (index, pmf) = lights.sample(u_light)?;
        let emitter = &lights.emitters()[index];
        let ls = emitter.sample_li(&sample_context(pt), u)?;
        if ls.pdf <= 0.0 || ls.l.max_element() <= 0.0 {
            return None;
        }
        let (p_light, n_light, infinite) = match ls.p_light {
            Some(p) => {
                let n = match emitter {
                    Emitter::Area(area) => area.shape.front_side(p).normalize_or_zero(),
                    _ => Vec3::ZERO,
                };
                (p, n, false)
            }
            // A light at infinity: a point beyond the scene along wi.
            None => (pt.p + ls.wi * (2.0 * ctx.radius.max(1.0)), Vec3::ZERO, true),
        };
        let mut lv = Vertex::light(index, p_light, n_light, infinite, ls.l / (ls.pdf * pmf), 0.0);
        lv.medium = pt.medium;
        lv.pdf_fwd = lv.pdf_light_origin(ctx, pt);
        let l = join_endpoint(ctx, pt, &lv, ls.wi, TransportMode::Radiance, stats)?;
        sampled = Some(lv);
        l
    } else {
        // Join two inner vertices.
        let (qs, pt) = (&light[s - 1], &camera[t - 1]);
        if !qs.is_connectible(ctx) || !pt.is_connectible(ctx) {
            return None;
        }
        let l = qs.beta * qs.f(pt, TransportMode::Importance) * pt.f(qs, TransportMode::Radiance) * pt.beta;
        if l.max_element() <= 0.0 {
            return None;
        }
        l * geometry(ctx, qs, pt, stats)
    };
    if l.max_element() <= 0.0 || !l.is_finite() {
        return None;
    }
    let w = if weighted { mis_weight(ctx, light, camera, sampled.as_ref(), s, t) } else { 1.0 };
    Some(Connection { l: l * w, film })
}

/// The contribution of joining subpath vertex `v` to an endpoint `e`
/// sampled from it (a point on the lens for `t = 1`, on a light for
/// `s = 1`) in unit direction `wi`: `β_v · f_v · |cos θ_v| · β_e` times the
/// transmittance between them, traced from `v` (a surface or medium point:
/// the sampled endpoint may lie on a light's surface). `None` when zero.
fn join_endpoint(
    ctx: &Context,
    v: &Vertex,
    e: &Vertex,
    wi: Vec3,
    mode: TransportMode,
    stats: &mut RayStats,
) -> Option<Color> {
    let mut l = v.beta * v.f(e, mode) * e.beta;
    if v.is_on_surface() {
        l *= wi.dot(v.ns).abs();
    }
    if l.max_element() <= 0.0 {
        return None;
    }
    Some(l * transmittance(ctx, v, e, stats))
}

/// The densities MIS works with at one vertex.
#[derive(Clone, Copy)]
struct Densities {
    fwd: f32,
    rev: f32,
    delta: bool,
    /// Whether `rev` is zero because no strategy from the other side can
    /// make this vertex (a light at infinity's rays never reach it), not
    /// because of a delta lobe: the strategies that need it then get no
    /// weight (rather than the `0 → 1` remapping of delta densities).
    unreachable: bool,
}

/// Most vertices of a subpath the weights handle without allocating.
const INLINE_VERTICES: usize = 16;

/// The balance-heuristic weight of strategy `(s, t)` against every other
/// strategy that makes the same path (Veach 1997, §10.2; pbrt-v4's
/// `MISWeight`): `1 / Σᵢ (pᵢ / p_(s,t))`, where the ratios of densities of
/// neighbouring strategies are products of the vertices' `pdf_rev/pdf_fwd`.
/// `sampled` is the endpoint sampled by the strategy itself for `s = 1`
/// (a light point) or `t = 1` (a lens point).
fn mis_weight(ctx: &Context, light: &[Vertex], camera: &[Vertex], sampled: Option<&Vertex>, s: usize, t: usize) -> f32 {
    if s + t == 2 {
        return 1.0;
    }
    // The path's vertices as this strategy made them: the sampled endpoint
    // in place of the subpath's own.
    let vertex_l = |i: usize| match sampled {
        Some(v) if s == 1 && i == 0 => v,
        _ => &light[i],
    };
    let vertex_c = |i: usize| match sampled {
        Some(v) if t == 1 && i == 0 => v,
        _ => &camera[i],
    };
    let mut lbuf = [Densities { fwd: 0.0, rev: 0.0, delta: false, unreachable: false }; INLINE_VERTICES];
    let mut cbuf = [Densities { fwd: 0.0, rev: 0.0, delta: false, unreachable: false }; INLINE_VERTICES];
    let mut lheap = Vec::new();
    let mut cheap = Vec::new();
    let ld: &mut [Densities] = if s <= INLINE_VERTICES {
        &mut lbuf[..s]
    } else {
        lheap.resize(s, lbuf[0]);
        &mut lheap
    };
    let cd: &mut [Densities] = if t <= INLINE_VERTICES {
        &mut cbuf[..t]
    } else {
        cheap.resize(t, cbuf[0]);
        &mut cheap
    };
    for (i, d) in ld.iter_mut().enumerate() {
        let v = vertex_l(i);
        *d = Densities { fwd: v.pdf_fwd, rev: v.pdf_rev, delta: v.delta, unreachable: false };
    }
    for (i, d) in cd.iter_mut().enumerate() {
        let v = vertex_c(i);
        *d = Densities { fwd: v.pdf_fwd, rev: v.pdf_rev, delta: v.delta, unreachable: false };
    }
    let qs = (s > 0).then(|| vertex_l(s - 1));
    let pt = (t > 0).then(|| vertex_c(t - 1));
    let qs_minus = (s > 1).then(|| vertex_l(s - 2));
    let pt_minus = (t > 1).then(|| vertex_c(t - 2));
    // The connection vertices are not degenerate: the strategy joined them.
    if t > 0 {
        cd[t - 1].delta = false;
    }
    if s > 0 {
        ld[s - 1].delta = false;
    }
    // The reverse densities at and next to the connection.
    if let Some(pt) = pt {
        cd[t - 1].rev = match qs {
            Some(qs) => qs.pdf(ctx, qs_minus, pt),
            None => pt_minus.map_or(0.0, |pm| pt.pdf_light_origin(ctx, pm)),
        };
        // A sampled point at infinity whose rays cannot reach pt.
        cd[t - 1].unreachable = qs.is_some_and(|qs| qs.infinite) && cd[t - 1].rev == 0.0;
    }
    if let (Some(pt), Some(pm)) = (pt, pt_minus) {
        cd[t - 2].rev = match qs {
            Some(qs) => pt.pdf(ctx, Some(qs), pm),
            None => pt.pdf_light(ctx, pm),
        };
        cd[t - 2].unreachable = qs.is_none() && pt.infinite && cd[t - 2].rev == 0.0;
    }
    if let (Some(qs), Some(pt)) = (qs, pt) {
        ld[s - 1].rev = pt.pdf(ctx, pt_minus, qs);
    }
    if let (Some(qm), Some(qs), Some(pt)) = (qs_minus, qs, pt) {
        ld[s - 2].rev = qs.pdf(ctx, Some(pt), qm);
    }
    let remap = |p: f32| if p != 0.0 { p } else { 1.0 };
    let mut sum = 0.0f32;
    // Strategies with more light vertices (the camera subpath shorter).
    let mut r = 1.0f32;
    for i in (1..t).rev() {
        if cd[i].unreachable {
            break;
        }
        r *= remap(cd[i].rev) / remap(cd[i].fwd);
        if !cd[i].delta && !cd[i - 1].delta {
            sum += r;
        }
    }
    // Strategies with more camera vertices.
    let mut r = 1.0f32;
    for i in (0..s).rev() {
        r *= remap(ld[i].rev) / remap(ld[i].fwd);
        let delta_before = if i > 0 { ld[i - 1].delta } else { vertex_l(0).is_delta_light(ctx) };
        if !ld[i].delta && !delta_before {
            sum += r;
        }
    }
    let w = 1.0 / (1.0 + sum);
    if w.is_finite() {
        w
    } else {
        0.0
    }
}
