//! The lights of the path integrator: every way light enters the scene,
//! behind one interface that can be sampled from a shading point (PBRT 4th
//! ed., ch. 12).

use super::{AreaLight, Environment, Light, LightSource};
use crate::color::{luminance, Color};
use crate::geometry::{Bounds3, Vec2, Vec3};
use std::f32::consts::PI;

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
    /// Sample light arriving at `ctx` from a 2D sample `u` in `[0, 1)²`.
    /// `None` when no light arrives (outside a spot cone, a one-sided light
    /// seen from behind, a black environment...).
    ///
    /// Always inlined, with [`AreaLight::sample_li`], into the path
    /// integrator's light stage. Returned through memory, the 80-byte result
    /// was written by the callee in small stores and its discriminant read
    /// back at once with one 16-byte load, which the CPU cannot forward
    /// from those stores: a stall of about 1% of the Cornell box's time
    /// (docs/performance.md, twentieth sitting).
    #[inline(always)]
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LiSample> {
        match self {
            Emitter::Delta(light) => {
                let s = light.sample_li(ctx.p)?;
                let p_light = match s.source {
                    LightSource::At(p) => Some(p),
                    LightSource::Infinite => None,
                };
                Some(LiSample { l: s.li, wi: s.wi, pdf: 1.0, p_light })
            }
            Emitter::Area(area) => area.sample_li(ctx, u),
            Emitter::Environment(env) => env.sample_li(ctx, u),
        }
    }

    /// Solid-angle pdf with which [`Emitter::sample_li`] from `ctx` chooses
    /// direction `wi`, that reaches this light at `p_light` whose unit
    /// geometric normal is `n_light` (ignored for environment lights;
    /// 0 for delta lights).
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        // Area lights use their own normal: the pdf must be exactly the one
        // `sample_li` computed.
        let _ = n_light;
        match self {
            Emitter::Delta(_) => 0.0,
            Emitter::Area(area) => area.pdf_li(ctx, wi, p_light),
            Emitter::Environment(env) => env.pdf_li(wi),
        }
    }

    /// Whether the light is a delta light (cannot be hit by a ray).
    pub fn is_delta(&self) -> bool {
        matches!(self, Emitter::Delta(_))
    }

    /// Total emitted power (luminance of the RGB power), for choosing
    /// lights; `scene` bounds the scene, for lights at infinity, whose power
    /// is what crosses the scene's bounding sphere (radius `r`). An empty or
    /// unbounded `scene` counts as a sphere of radius 1: pass the bounds of
    /// the finite geometry when the scene has infinite planes.
    ///
    /// Following PBRT 4th ed. (`Phi()` of each light, ch. 12): a point light
    /// `4π I`; a spot light `2π I (1 − (cos θ_start + cos θ_total) / 2)`
    /// (§12.2.1); a directional light `π r² E` (§12.4); area lights
    /// [`AreaLight::power`]; environments [`Environment::power`]. Lights
    /// with no inverse-square falloff are counted the same way.
    pub fn power(&self, scene: &Bounds3) -> f32 {
        match self {
            Emitter::Delta(Light::Point { intensity, .. }) => 4.0 * PI * luminance(*intensity),
            Emitter::Delta(Light::Spot { intensity, cos_total, cos_falloff_start, .. }) => {
                2.0 * PI * luminance(*intensity) * (1.0 - 0.5 * (cos_falloff_start + cos_total))
            }
            Emitter::Delta(Light::Directional { intensity, .. }) => {
                let r = scene_radius(scene);
                PI * r * r * luminance(*intensity)
            }
            Emitter::Area(area) => area.power(),
            Emitter::Environment(env) => env.power(scene_radius(scene)),
        }
    }
}

/// Radius of the sphere around `bounds` (half its diagonal); 1 for an empty
/// or infinite box.
pub(crate) fn scene_radius(bounds: &Bounds3) -> f32 {
    if bounds.is_empty() || bounds.is_infinite() {
        return 1.0;
    }
    let r = 0.5 * (bounds.max - bounds.min).length();
    if r.is_finite() {
        r
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::Falloff;

    #[test]
    fn delta_lights_wrap_the_classic_sample() {
        let ctx = LightSampleContext { p: Vec3::ZERO, n: Vec3::Y };
        let point =
            Emitter::Delta(Light::point(Vec3::new(0.0, 2.0, 0.0), Color::ONE, 8.0, Falloff::InverseSquare).unwrap());
        let s = point.sample_li(&ctx, Vec2::ZERO).unwrap();
        assert_eq!((s.l, s.wi, s.pdf, s.p_light), (Color::splat(2.0), Vec3::Y, 1.0, Some(Vec3::new(0.0, 2.0, 0.0))));
        assert_eq!(point.pdf_li(&ctx, Vec3::Y, Vec3::new(0.0, 2.0, 0.0), -Vec3::Y), 0.0);
        assert!(point.is_delta());
        let sun = Emitter::Delta(Light::directional(-Vec3::Y, Color::ONE, 3.0).unwrap());
        let s = sun.sample_li(&ctx, Vec2::ZERO).unwrap();
        assert_eq!((s.l, s.wi, s.p_light), (Color::splat(3.0), Vec3::Y, None));
        assert!(!Emitter::Environment(Environment::Constant(Color::ONE)).is_delta());
    }

    #[test]
    fn delta_light_powers_follow_pbrt() {
        let b = Bounds3::from_points(Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)); // radius 1
        let point = Emitter::Delta(Light::point(Vec3::ZERO, Color::ONE, 2.0, Falloff::InverseSquare).unwrap());
        assert!((point.power(&b) - 8.0 * PI).abs() < 1e-4);
        // A spot with no blend, half-angle 60°: 2π I (1 − cos 60°).
        let spot = Emitter::Delta(
            Light::spot(Vec3::ZERO, Vec3::Y, Color::ONE, 1.0, 60.0, 0.0, Falloff::InverseSquare).unwrap(),
        );
        assert!((spot.power(&b) - PI).abs() < 1e-4);
        let sun = Emitter::Delta(Light::directional(Vec3::Y, Color::ONE, 2.0).unwrap());
        assert!((sun.power(&b) - 2.0 * PI).abs() < 1e-4);
        // Unbounded scenes count as radius 1.
        assert!((sun.power(&Bounds3::INFINITE) - 2.0 * PI).abs() < 1e-4);
    }
}
