//! The lights of the path integrator: every way light enters the scene,
//! behind one interface that can be sampled from a shading point (PBRT 4th
//! ed., ch. 12).

use super::{AreaLight, Environment, Light};
use crate::color::Color;
use crate::geometry::{Bounds3, Vec2, Vec3};

/// The shading point a light is sampled from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSampleContext {
    /// The point.
    pub p: Vec3,
    /// Unit geometric normal there (either orientation), or zero for a
    /// point not on a surface.
    pub n: Vec3,
}

/// Light arriving at a shading point from a sampled point of a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiSample {
    /// Incident radiance (delta lights: what they deliver, as
    /// [`Light::sample_li`]).
    pub l: Color,
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Solid-angle pdf of `wi` (1 for delta lights).
    pub pdf: f32,
    /// The sampled point on the light, for the shadow ray; `None` for a
    /// light infinitely far away along `wi`.
    pub p_light: Option<Vec3>,
}

/// A light of any kind.
#[derive(Clone, Debug)]
pub enum Emitter {
    /// A point, spot or directional light.
    Delta(Light),
    /// An emissive surface.
    Area(AreaLight),
    /// Light from infinitely far away in every direction.
    Environment(Environment),
}

impl Emitter {
    /// Sample light arriving at `ctx` from a 2D sample `u`.
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LiSample> {
        let _ = (ctx, u);
        todo!()
    }

    /// Solid-angle pdf with which [`Emitter::sample_li`] from `ctx` chooses
    /// direction `wi`, that reaches this light at `p_light` whose unit
    /// geometric normal is `n_light` (ignored for environment lights;
    /// 0 for delta lights).
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        let _ = (ctx, wi, p_light, n_light);
        todo!()
    }

    /// Whether the light is a delta light (cannot be hit by a ray).
    pub fn is_delta(&self) -> bool {
        matches!(self, Emitter::Delta(_))
    }

    /// Total emitted power (luminance of the RGB power), for choosing
    /// lights; `scene` bounds the scene, for lights at infinity.
    pub fn power(&self, scene: &Bounds3) -> f32 {
        let _ = scene;
        todo!()
    }
}
