//! The vertices of bidirectional path tracing, and the densities of moving
//! between them (Veach 1997, ch. 10; PBRT 3rd ed. §16.3.1 and pbrt-v4's
//! `Vertex`).
//!
//! A subpath is a list of vertices: its endpoint on the camera lens or on a
//! light, then points on surfaces and in media. Each vertex keeps the
//! throughput `β` of the subpath up to it and two densities, both per unit
//! *area* at the vertex (per unit solid angle for a vertex on a light at
//! infinity):
//!
//! * `pdf_fwd`: the density with which the subpath's own sampling produced
//!   it (from the vertex before it);
//! * `pdf_rev`: the density with which it would have been produced by
//!   sampling in the other direction (from the vertex after it), as the
//!   other subpath would have.
//!
//! The multiple importance weights of every strategy are ratios of these
//! (see [`super::mis_weight`]).

use crate::bsdf::{Bsdf, TransportMode};
use crate::color::Color;
use crate::geometry::{Bounds3, Vec3};
use crate::interaction::SurfaceInteraction;
use crate::light::{Emitter, LightSampleContext, LightSet};
use crate::medium::{HenyeyGreenstein, MediumId};
use crate::scene::Scene;
use std::f32::consts::PI;

/// What a path vertex is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum VertexKind {
    /// A point on the camera's lens (the eye for a pinhole).
    Camera,
    /// A point on a light, or where a ray leaves towards a light at
    /// infinity: the emitter's index in the scene's light set.
    Light(usize),
    /// A point on a surface that scatters (with its BSDF).
    Surface,
    /// A scattering point in a participating medium.
    Medium,
}

/// One vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
pub(super) struct Vertex {
    pub kind: VertexKind,
    /// Position (for a light at infinity: a point outside the scene in its
    /// direction).
    pub p: Vec3,
    /// Unit geometric normal of a surface point (area lights included);
    /// zero for points not on a surface.
    pub n: Vec3,
    /// Unit shading normal (as `n` off surfaces).
    pub ns: Vec3,
    /// Unit direction towards the previous vertex of the subpath (surfaces
    /// and media).
    pub wo: Vec3,
    /// The surface hit and its BSDF ([`VertexKind::Surface`]).
    pub si: Option<SurfaceInteraction>,
    pub bsdf: Option<Bsdf>,
    /// The phase function ([`VertexKind::Medium`]).
    pub phase: Option<HenyeyGreenstein>,
    /// The medium the ray that reached the vertex travelled in (for an
    /// endpoint: the one its rays start in).
    pub medium: Option<MediumId>,
    /// Throughput of the subpath up to and including this vertex.
    pub beta: Color,
    /// Whether the vertex scattered by a delta lobe (it cannot be
    /// connected to, and strategies ending there have zero density).
    pub delta: bool,
    /// Whether the vertex is on a light at infinity (the environment, or a
    /// directional light).
    pub infinite: bool,
    pub pdf_fwd: f32,
    pub pdf_rev: f32,
}

/// What the densities need of the scene: its lights and the sphere that
/// bounds it (for lights at infinity).
pub(super) struct Context<'a> {
    pub scene: &'a Scene,
    pub bounds: Bounds3,
    /// Radius of the scene's bounding sphere ([`Emitter::sample_le`]'s).
    pub radius: f32,
    /// Its centre.
    pub centre: Vec3,
    /// Whether the scene may have surfaces that rays pass through.
    pub interfaces: bool,
}

impl Context<'_> {
    fn lights(&self) -> &LightSet {
        self.scene.light_set()
    }
}

impl Vertex {
    fn new(kind: VertexKind, p: Vec3, beta: Color, pdf_fwd: f32) -> Self {
        Vertex {
            kind,
            p,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
            wo: Vec3::ZERO,
            si: None,
            bsdf: None,
            phase: None,
            medium: None,
            beta,
            delta: false,
            infinite: false,
            pdf_fwd,
            pdf_rev: 0.0,
        }
    }

    /// The camera endpoint at lens point `p`, in `medium`.
    pub fn camera(p: Vec3, beta: Color, medium: Option<MediumId>) -> Self {
        Vertex { medium, ..Self::new(VertexKind::Camera, p, beta, 0.0) }
    }

    /// A light endpoint: emitter `index` at `p` with normal `n` (zero off
    /// surfaces), `infinite` for lights at infinity.
    pub fn light(index: usize, p: Vec3, n: Vec3, infinite: bool, beta: Color, pdf_fwd: f32) -> Self {
        Vertex { n, ns: n, infinite, ..Self::new(VertexKind::Light(index), p, beta, pdf_fwd) }
    }

    /// A surface vertex reached from direction `wo`.
    pub fn surface(si: SurfaceInteraction, bsdf: Bsdf, wo: Vec3, beta: Color, medium: Option<MediumId>) -> Self {
        Vertex {
            n: si.n,
            ns: bsdf.frame().z,
            wo,
            si: Some(si),
            bsdf: Some(bsdf),
            medium,
            ..Self::new(VertexKind::Surface, si.p, beta, 0.0)
        }
    }

    /// A scattering point in `medium`, reached from direction `wo`.
    pub fn medium(p: Vec3, phase: HenyeyGreenstein, wo: Vec3, beta: Color, medium: MediumId) -> Self {
        Vertex { wo, phase: Some(phase), medium: Some(medium), ..Self::new(VertexKind::Medium, p, beta, 0.0) }
    }

    /// Whether the vertex lies on a surface (its densities then include
    /// the cosine at it).
    #[inline]
    pub fn is_on_surface(&self) -> bool {
        self.n != Vec3::ZERO
    }

    /// The emitter at this vertex, if it is on a light (a light endpoint,
    /// or a surface of an area light).
    pub fn light_index(&self) -> Option<usize> {
        match self.kind {
            VertexKind::Light(i) => Some(i),
            VertexKind::Surface => self.si.and_then(|si| si.light).map(|i| i as usize),
            _ => None,
        }
    }

    /// Whether the vertex is the endpoint on a delta light (a point, spot
    /// or directional light), which no ray can hit.
    pub fn is_delta_light(&self, ctx: &Context) -> bool {
        matches!(self.kind, VertexKind::Light(i) if ctx.lights().emitters()[i].is_delta())
    }

    /// Whether a connection can end here: not at a surface whose every
    /// lobe is a delta, nor at a directional light (a delta direction).
    pub fn is_connectible(&self, ctx: &Context) -> bool {
        match self.kind {
            VertexKind::Surface => self.bsdf.is_some_and(|b| !b.is_specular()),
            VertexKind::Medium | VertexKind::Camera => true,
            VertexKind::Light(i) => {
                !matches!(ctx.lights().emitters()[i], Emitter::Delta(crate::light::Light::Directional { .. }))
            }
        }
    }

    /// The scattering function for light leaving towards the previous
    /// vertex and arriving from `next` (BSDF or phase function; zero at
    /// endpoints), for the quantity `mode` transports: for importance, with
    /// the correction for shading normals that light subpaths carry
    /// ([`shading_normal_correction`]; as pbrt-v3's `Vertex::f`).
    pub fn f(&self, next: &Vertex, mode: TransportMode) -> Color {
        let wi = (next.p - self.p).normalize_or_zero();
        match self.kind {
            VertexKind::Surface => match (self.bsdf, &self.si) {
                (Some(b), Some(si)) => {
                    let f = b.f_mode(self.wo, wi, mode);
                    match mode {
                        TransportMode::Radiance => f,
                        TransportMode::Importance => f * shading_normal_correction(si, self.ns, self.wo, wi),
                    }
                }
                _ => Color::ZERO,
            },
            VertexKind::Medium => Color::splat(self.phase.map_or(0.0, |ph| ph.p(self.wo, wi))),
            _ => Color::ZERO,
        }
    }

    /// Convert the solid-angle density `pdf` of the direction from this
    /// vertex to `next` into a density per unit area at `next` (PBRT 3rd ed.
    /// eq. 5.6: `p_A = p_ω · |cos θ_next| / d²`); a light at infinity keeps
    /// the solid-angle density.
    pub fn convert_density(&self, pdf: f32, next: &Vertex) -> f32 {
        if next.infinite {
            return pdf;
        }
        let w = next.p - self.p;
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let mut pdf = pdf / d2;
        if next.is_on_surface() {
            pdf *= next.n.dot(w / d2.sqrt()).abs();
        }
        pdf
    }

    /// The density per unit area at `next` with which sampling at this
    /// vertex (coming from `prev`) would produce `next` (pbrt-v4's
    /// `Vertex::PDF`): the BSDF or phase function's, or the camera's, or,
    /// on a light, the light's emission density ([`Vertex::pdf_light`]).
    pub fn pdf(&self, ctx: &Context, prev: Option<&Vertex>, next: &Vertex) -> f32 {
        if let VertexKind::Light(_) = self.kind {
            return self.pdf_light(ctx, next);
        }
        let wn = (next.p - self.p).normalize_or_zero();
        if wn == Vec3::ZERO {
            return 0.0;
        }
        let wp = prev.map_or(self.wo, |v| (v.p - self.p).normalize_or_zero());
        let pdf = match self.kind {
            VertexKind::Camera => ctx.scene.camera().pdf_importance_from(self.p, wn).1,
            VertexKind::Surface => self.bsdf.map_or(0.0, |b| b.pdf(wp, wn)),
            VertexKind::Medium => self.phase.map_or(0.0, |ph| ph.p(wp, wn)),
            VertexKind::Light(_) => unreachable!("handled above"),
        };
        self.convert_density(pdf, next)
    }

    /// The density per unit area at `v` with which this vertex, on a light,
    /// emits towards `v` (pbrt-v4's `Vertex::PdfLight`): the emission's
    /// direction density over `d²` times the cosine at `v`, or, for a light
    /// at infinity, the density of the ray's origin on the disk that
    /// emission sampling places across the scene's bounding sphere: zero
    /// for a point outside the cylinder those rays sweep (on an infinite
    /// plane, far away), which no light subpath reaches.
    pub fn pdf_light(&self, ctx: &Context, v: &Vertex) -> f32 {
        let Some(index) = self.light_index() else { return 0.0 };
        let w = v.p - self.p;
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let w = w / d2.sqrt();
        let mut pdf = if self.infinite {
            let c = v.p - ctx.centre;
            if (c - w * c.dot(w)).length_squared() > ctx.radius * ctx.radius {
                return 0.0;
            }
            1.0 / (PI * ctx.radius * ctx.radius)
        } else {
            let (_, pdf_dir) = ctx.lights().emitters()[index].pdf_le(self.p, self.n, w, &ctx.bounds);
            pdf_dir / d2
        };
        if v.is_on_surface() {
            pdf *= v.n.dot(w).abs();
        }
        pdf
    }

    /// The density with which light sampling would choose this vertex as
    /// the origin of a light subpath emitting towards `v` (pbrt-v4's
    /// `Vertex::PdfLightOrigin`): the light's probability times its
    /// position density, or for lights at infinity the directional density
    /// of every such light together.
    pub fn pdf_light_origin(&self, ctx: &Context, v: &Vertex) -> f32 {
        let Some(index) = self.light_index() else { return 0.0 };
        let w = (v.p - self.p).normalize_or_zero();
        if w == Vec3::ZERO {
            return 0.0;
        }
        if self.infinite {
            return infinite_light_density(ctx, -w);
        }
        let lights = ctx.lights();
        let (pdf_pos, _) = lights.emitters()[index].pdf_le(self.p, self.n, w, &ctx.bounds);
        lights.pmf(index) * pdf_pos
    }

    /// Light this vertex, on a light, emits towards `v` (zero elsewhere).
    pub fn le(&self, ctx: &Context, v: &Vertex) -> Color {
        let Some(index) = self.light_index() else { return Color::ZERO };
        let w = (v.p - self.p).normalize_or_zero();
        if w == Vec3::ZERO {
            return Color::ZERO;
        }
        match &ctx.lights().emitters()[index] {
            // A ray escaping towards -w finds the environment behind it.
            Emitter::Environment(env) => env.le(-w),
            Emitter::Area(area) => match &self.si {
                Some(si) => area.emitted_at(si.p, si.uv, si.attributes, w),
                None => Color::ZERO,
            },
            Emitter::Delta(_) => Color::ZERO,
        }
    }
}

/// Veach's correction of the adjoint BSDF for shading normals (Veach 1997,
/// §5.3, eq. 5.19): `|wo·ns| |wi·ng| / (|wo·ng| |wi·ns|)`, so that light
/// subpaths carry importance exactly where shading and geometric normals
/// differ.
pub(super) fn shading_normal_correction(si: &SurfaceInteraction, ns: Vec3, wo: Vec3, wi: Vec3) -> f32 {
    let num = wo.dot(ns).abs() * wi.dot(si.n).abs();
    let den = wo.dot(si.n).abs() * wi.dot(ns).abs();
    if den == 0.0 {
        0.0
    } else {
        num / den
    }
}

/// The solid-angle density with which light sampling finds a light at
/// infinity in direction `w` (towards the light): the environment's
/// probability times its density there (directional lights are deltas).
pub(super) fn infinite_light_density(ctx: &Context, w: Vec3) -> f32 {
    match ctx.scene.environment_light() {
        Some((index, env)) => ctx.lights().pmf(index) * env.pdf_li(w),
        None => 0.0,
    }
}

/// The context light sampling uses at a vertex.
pub(super) fn sample_context(v: &Vertex) -> LightSampleContext {
    LightSampleContext { p: v.p, n: v.n }
}
