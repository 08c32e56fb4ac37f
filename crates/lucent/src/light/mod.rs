//! Light sources.
//!
//! [`Light`] is a light of the classic renderer: point, spot or directional
//! (all "delta" lights: each shaded point sees them from exactly one
//! direction). Ambient light is a property of the scene
//! (the layer above). The path integrator also has area lights
//! (emissive surfaces) and environment lights; [`Emitter`] is any of them
//! and a [`LightSet`] picks one to sample.
//!
//! pbrt-v4's lights map onto these: `point`, `spot` and `distant` through
//! [`Light::pbrt_point`], [`Light::pbrt_spot`] and [`Light::pbrt_distant`]
//! (their parameters, with pbrt's defaults, in [`PointLightParams`] and
//! its siblings); `infinite` through [`Environment::uniform`] and
//! [`Environment::from_file_with`] (equal-area maps, [`equal_area`]);
//! `diffuse` area lights are [`AreaLight`]s, with `reverse` for pbrt's
//! `ReverseOrientation`.

mod area;
mod emission;
mod emitter;
pub(crate) use emitter::scene_radius;
mod environment;
pub mod equal_area;
mod equirect;
mod pbrt;
mod rectangles;
mod set;

pub use area::{AreaLight, EmissionImage};
pub use emission::LeSample;
pub use emitter::{Emitter, LiSample, LightSampleContext};
pub use environment::{
    read_environment_image, Environment, EnvironmentError, EnvironmentMap, EnvironmentMapping, MapOptions,
};
pub use equal_area::{equal_area_sphere_to_square, equal_area_square_to_sphere};
pub use equirect::{equirect_direction, equirect_uv};
pub use pbrt::{DistantLightParams, PointLightParams, SpotLightParams};
pub(crate) use rectangles::merge_rectangles;
pub use set::LightSet;
// Moved to `shapes` with the rest of the triangle's light sampling.
pub use crate::shapes::triangle_solid_angle;

use crate::color::Color;
use crate::geometry::Vec3;

/// Why light parameters are unusable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LightError {
    /// A direction has zero length.
    #[error("the light direction has zero length")]
    ZeroDirection,
    /// Intensity negative or not finite.
    #[error("intensity must be a finite number ≥ 0, got {0}")]
    Intensity(f32),
    /// A spot cone angle outside (0, 180] or a blend width outside [0, angle].
    #[error(
        "spot cone angle must be in (0, 180] degrees and cone_delta in [0, angle], got angle {angle}, delta {delta}"
    )]
    Cone {
        /// Cone half-angle given.
        angle: f32,
        /// Blend width given.
        delta: f32,
    },
    /// A coordinate is NaN or infinite.
    #[error("light parameters must be finite numbers")]
    NonFinite,
    /// A colour is negative or not finite.
    #[error("a light's colour must be finite and ≥ 0 in every channel")]
    Color,
}

/// How a light's intensity decreases with distance `d`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Falloff {
    /// Constant with distance (the classic ray tracer's point light).
    #[default]
    None,
    /// `1 / d²`: physically correct for a point source.
    InverseSquare,
}

impl Falloff {
    #[inline]
    fn factor(self, distance_squared: f32) -> f32 {
        match self {
            Falloff::None => 1.0,
            Falloff::InverseSquare => 1.0 / distance_squared,
        }
    }
}

/// A light source.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Emits equally in all directions from a point.
    Point {
        /// Position.
        position: Vec3,
        /// Colour × intensity.
        intensity: Color,
        /// Distance falloff.
        falloff: Falloff,
    },
    /// A point light restricted to a cone.
    Spot {
        /// Position.
        position: Vec3,
        /// Unit axis of the cone.
        direction: Vec3,
        /// Colour × intensity on the axis.
        intensity: Color,
        /// Distance falloff.
        falloff: Falloff,
        /// Cosine of the cone's half-angle: no light beyond it.
        cos_total: f32,
        /// Cosine of the angle where the smooth falloff to the edge starts.
        cos_falloff_start: f32,
    },
    /// Parallel light from infinitely far away, like the sun.
    Directional {
        /// Unit direction the light travels in.
        direction: Vec3,
        /// Colour × intensity (irradiance on a surface facing it).
        intensity: Color,
    },
}

/// What a shaded point receives from a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point towards the light.
    pub wi: Vec3,
    /// Incident light (irradiance on a surface perpendicular to `wi`).
    pub li: Color,
    /// Where the light is, for the shadow ray.
    pub source: LightSource,
}

/// Where a shadow ray must reach to see a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSource {
    /// A point in the scene: occluders count only before it.
    At(Vec3),
    /// Infinitely far along `wi`.
    Infinite,
}

fn check_intensity(color: Color, intensity: f32) -> Result<Color, LightError> {
    if !(intensity >= 0.0 && intensity.is_finite()) {
        return Err(LightError::Intensity(intensity));
    }
    if !color.is_finite() {
        return Err(LightError::NonFinite);
    }
    Ok(color * intensity)
}

fn unit(v: Vec3) -> Result<Vec3, LightError> {
    if !v.is_finite() {
        return Err(LightError::NonFinite);
    }
    let l = v.length();
    if l == 0.0 {
        return Err(LightError::ZeroDirection);
    }
    Ok(v / l)
}

/// Hermite smoothstep of `x` between `a` and `b`.
#[inline]
fn smooth_step(x: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Light {
    /// A point light.
    pub fn point(position: Vec3, color: Color, intensity: f32, falloff: Falloff) -> Result<Self, LightError> {
        if !position.is_finite() {
            return Err(LightError::NonFinite);
        }
        Ok(Light::Point { position, intensity: check_intensity(color, intensity)?, falloff })
    }

    /// A spot light with cone half-angle `angle` (degrees). Intensity is full
    /// inside `angle - delta` and falls smoothly to zero at `angle`
    /// (the smoothstep falloff of PBRT 4th ed., §12.2.1).
    pub fn spot(
        position: Vec3,
        direction: Vec3,
        color: Color,
        intensity: f32,
        angle: f32,
        delta: f32,
        falloff: Falloff,
    ) -> Result<Self, LightError> {
        if !position.is_finite() {
            return Err(LightError::NonFinite);
        }
        if !(angle > 0.0 && angle <= 180.0 && delta >= 0.0 && delta <= angle) {
            return Err(LightError::Cone { angle, delta });
        }
        Ok(Light::Spot {
            position,
            direction: unit(direction)?,
            intensity: check_intensity(color, intensity)?,
            falloff,
            cos_total: angle.to_radians().cos(),
            cos_falloff_start: (angle - delta).to_radians().cos(),
        })
    }

    /// A directional light; `direction` is the way the light travels.
    pub fn directional(direction: Vec3, color: Color, intensity: f32) -> Result<Self, LightError> {
        Ok(Light::Directional { direction: unit(direction)?, intensity: check_intensity(color, intensity)? })
    }

    /// The light arriving at `p`. `None` when the point is outside a spot
    /// light's cone or exactly at the light.
    #[inline]
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        match *self {
            Light::Point { position, intensity, falloff } => {
                let to = position - p;
                let d2 = to.length_squared();
                if d2 == 0.0 {
                    return None;
                }
                let wi = to / d2.sqrt();
                Some(LightSample { wi, li: intensity * falloff.factor(d2), source: LightSource::At(position) })
            }
            Light::Spot { position, direction, intensity, falloff, cos_total, cos_falloff_start } => {
                let to = position - p;
                let d2 = to.length_squared();
                if d2 == 0.0 {
                    return None;
                }
                let wi = to / d2.sqrt();
                let cos_theta = (-wi).dot(direction);
                let cone = smooth_step(cos_theta, cos_total, cos_falloff_start);
                if cone <= 0.0 {
                    return None;
                }
                Some(LightSample { wi, li: intensity * (cone * falloff.factor(d2)), source: LightSource::At(position) })
            }
            Light::Directional { direction, intensity } => {
                Some(LightSample { wi: -direction, li: intensity, source: LightSource::Infinite })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_inverse_square() {
        let l = Light::point(Vec3::new(0.0, 4.0, 0.0), Color::ONE, 32.0, Falloff::InverseSquare).unwrap();
        let s = l.sample_li(Vec3::ZERO).unwrap();
        assert_eq!(s.wi, Vec3::Y);
        assert_eq!(s.li, Color::splat(2.0));
        let c = Light::point(Vec3::new(0.0, 4.0, 0.0), Color::ONE, 32.0, Falloff::None).unwrap();
        assert_eq!(c.sample_li(Vec3::ZERO).unwrap().li, Color::splat(32.0));
    }

    #[test]
    fn spot_light_cone() {
        let l = Light::spot(Vec3::ZERO, -Vec3::Y, Color::ONE, 1.0, 30.0, 10.0, Falloff::None).unwrap();
        // On the axis: full.
        assert_eq!(l.sample_li(-Vec3::Y).unwrap().li, Color::ONE);
        // 25° off axis: inside the blend region, partial.
        let a = 25f32.to_radians();
        let p = Vec3::new(a.sin(), -a.cos(), 0.0);
        let li = l.sample_li(p).unwrap().li.x;
        assert!(li > 0.0 && li < 1.0);
        // 35° off: outside.
        let a = 35f32.to_radians();
        assert!(l.sample_li(Vec3::new(a.sin(), -a.cos(), 0.0)).is_none());
        // Behind.
        assert!(l.sample_li(Vec3::Y).is_none());
    }

    #[test]
    fn directional_light_is_constant() {
        let l = Light::directional(Vec3::new(0.0, -2.0, 0.0), Color::ONE, 3.0).unwrap();
        let s = l.sample_li(Vec3::new(100.0, 5.0, -7.0)).unwrap();
        assert_eq!(s.wi, Vec3::Y);
        assert_eq!(s.li, Color::splat(3.0));
        assert_eq!(s.source, LightSource::Infinite);
    }

    #[test]
    fn bad_lights_are_refused() {
        assert_eq!(Light::directional(Vec3::ZERO, Color::ONE, 1.0), Err(LightError::ZeroDirection));
        assert!(Light::point(Vec3::ZERO, Color::ONE, -1.0, Falloff::None).is_err());
        assert!(Light::spot(Vec3::ZERO, Vec3::Y, Color::ONE, 1.0, 0.0, 0.0, Falloff::None).is_err());
    }
}
