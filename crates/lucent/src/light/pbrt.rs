//! Delta lights with pbrt-v4's parameters (`LightSource "point"`, `"spot"`,
//! `"distant"`; PBRT 4th ed., §12.1–12.4, and pbrt-v4's `lights.cpp`).
//!
//! Each parameter set is a struct whose [`Default`] holds pbrt-v4's
//! defaults; colours are linear RGB (the importer converts spectra). The
//! positions and directions are in light space and are carried to the world
//! by the `light_to_world` transform (pbrt-v4's CTM at the `LightSource`
//! directive).
//!
//! # Photometric normalisation
//!
//! pbrt-v4 lets a light be specified by what it delivers instead of its
//! intensity: `power` (point and spot lights, the total emitted power) or
//! `illuminance` (distant lights, what a surface facing the light
//! receives). The colour is then normalised to unit luminance
//! (`lum(c) = 0.2126 R + 0.7152 G + 0.0722 B`) and multiplied by the value
//! asked for, and by `scale`, so that the *luminance* of the power (or the
//! illuminance) is `scale ·` that value. A value ≤ 0 means "not given" (pbrt's
//! default is −1). (pbrt-v4 normalises the spectrum's luminance in the same
//! way for spectra such as blackbodies, but for an RGB colour it normalises
//! only the colour space's illuminant, not the RGB itself, so its power is
//! `lum(RGB)` times the value asked for: the two agree for white.)

use super::{Falloff, Light, LightError};
use crate::color::{luminance, Color};
use crate::geometry::{Transform, Vec3};
use std::f32::consts::PI;

/// pbrt-v4's `point` light: intensity `I` (W/sr) from `from`, falling off
/// with the inverse square of the distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLightParams {
    /// `I`: radiant intensity, linear RGB (default 1, 1, 1).
    pub i: Color,
    /// `scale` (default 1).
    pub scale: f32,
    /// `power`: when > 0, `I` is rescaled so that the emitted power
    /// `Φ = 4π lum(I)` equals `scale · power` (default: not given).
    pub power: Option<f32>,
    /// `from`: the position in light space (default the origin).
    pub from: Vec3,
}

impl Default for PointLightParams {
    fn default() -> Self {
        Self { i: Color::ONE, scale: 1.0, power: None, from: Vec3::ZERO }
    }
}

/// pbrt-v4's `spot` light: a point light at `from` shining towards `to`,
/// full within `cone_angle − cone_delta` of the axis and falling smoothly
/// to zero at `cone_angle`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLightParams {
    /// `I`: radiant intensity on the axis, linear RGB (default 1, 1, 1).
    pub i: Color,
    /// `scale` (default 1).
    pub scale: f32,
    /// `power`: when > 0, `I` is rescaled so that the emitted power
    /// `Φ = 2π lum(I) (1 − (cos θ_start + cos θ_end) / 2)` equals
    /// `scale · power` (default: not given).
    pub power: Option<f32>,
    /// `from`: the apex in light space (default the origin).
    pub from: Vec3,
    /// `to`: a point on the axis in light space (default `(0, 0, 1)`).
    pub to: Vec3,
    /// `coneangle`: half-angle of the cone in degrees (default 30).
    pub cone_angle: f32,
    /// `conedelta`: width in degrees of the smooth falloff at the cone's
    /// edge (default 5).
    pub cone_delta: f32,
}

impl Default for SpotLightParams {
    fn default() -> Self {
        Self {
            i: Color::ONE,
            scale: 1.0,
            power: None,
            from: Vec3::ZERO,
            to: Vec3::Z,
            cone_angle: 30.0,
            cone_delta: 5.0,
        }
    }
}

/// pbrt-v4's `distant` light: parallel light travelling from `from`
/// towards `to`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistantLightParams {
    /// `L`: radiance, linear RGB (default 1, 1, 1). A distant light's
    /// "radiance" is the irradiance it gives a surface facing it.
    pub l: Color,
    /// `scale` (default 1).
    pub scale: f32,
    /// `illuminance`: when > 0, `L` is rescaled so that a surface facing
    /// the light receives the luminance `scale · illuminance` (default: not
    /// given).
    pub illuminance: Option<f32>,
    /// `from` (default the origin).
    pub from: Vec3,
    /// `to` (default `(0, 0, 1)`): the light travels along `to − from`.
    pub to: Vec3,
}

impl Default for DistantLightParams {
    fn default() -> Self {
        Self { l: Color::ONE, scale: 1.0, illuminance: None, from: Vec3::ZERO, to: Vec3::Z }
    }
}

/// `color · scale`, normalised to luminance `scale · target` when a target
/// `> 0` is given and `k` is the luminance the colour would deliver per
/// unit of its own luminance (`4π` for the power of a point light, say).
fn normalised(color: Color, scale: f32, target: Option<f32>, k: f32) -> Result<Color, LightError> {
    if !(scale >= 0.0 && scale.is_finite()) {
        return Err(LightError::Intensity(scale));
    }
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(LightError::Color);
    }
    let mut c = color * scale;
    match target {
        Some(t) if !t.is_finite() => return Err(LightError::NonFinite),
        Some(t) if t > 0.0 => {
            let lum = luminance(color);
            // A black light stays black: there is nothing to rescale.
            if lum > 0.0 && k > 0.0 {
                c *= t / (k * lum);
            }
        }
        _ => {}
    }
    if c.is_finite() {
        Ok(c)
    } else {
        Err(LightError::NonFinite)
    }
}

impl Light {
    /// pbrt-v4's `point` light, placed by `light_to_world`: at
    /// `light_to_world(from)`, with inverse-square falloff.
    pub fn pbrt_point(light_to_world: &Transform, p: &PointLightParams) -> Result<Light, LightError> {
        let intensity = normalised(p.i, p.scale, p.power, 4.0 * PI)?;
        Light::point(light_to_world.point(p.from), intensity, 1.0, Falloff::InverseSquare)
    }

    /// pbrt-v4's `spot` light, placed by `light_to_world`: apex at
    /// `light_to_world(from)`, axis along `light_to_world(to − from)`, with
    /// inverse-square falloff and pbrt's smoothstep at the cone's edge
    /// ([`Light::spot`]). The cone must satisfy `0 < coneangle ≤ 180` and
    /// `0 ≤ conedelta ≤ coneangle`.
    pub fn pbrt_spot(light_to_world: &Transform, p: &SpotLightParams) -> Result<Light, LightError> {
        let (angle, delta) = (p.cone_angle, p.cone_delta);
        if !(angle > 0.0 && angle <= 180.0 && delta >= 0.0 && delta <= angle) {
            return Err(LightError::Cone { angle, delta });
        }
        // PBRT 4th ed., §12.2.1: the power of a spot light whose intensity
        // is I inside θ_start and falls off (smoothstep in cos θ) to zero at
        // θ_end is 2π I (1 − cos θ_start) + 2π I (cos θ_start − cos θ_end)/2.
        let cos_end = angle.to_radians().cos();
        let cos_start = (angle - delta).to_radians().cos();
        let k = 2.0 * PI * (1.0 - 0.5 * (cos_start + cos_end));
        let intensity = normalised(p.i, p.scale, p.power, k)?;
        let axis = light_to_world.vector(p.to - p.from);
        Light::spot(light_to_world.point(p.from), axis, intensity, 1.0, angle, delta, Falloff::InverseSquare)
    }

    /// pbrt-v4's `distant` light, placed by `light_to_world`: light
    /// travelling along `light_to_world(to − from)` (normalised), with
    /// irradiance `L · scale` on a surface facing it (or
    /// `scale · illuminance` in luminance).
    pub fn pbrt_distant(light_to_world: &Transform, p: &DistantLightParams) -> Result<Light, LightError> {
        // A surface facing a distant light receives E = L: k = 1.
        let irradiance = normalised(p.l, p.scale, p.illuminance, 1.0)?;
        Light::directional(light_to_world.vector(p.to - p.from), irradiance, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Bounds3;
    use crate::light::Emitter;

    #[test]
    fn defaults_are_pbrts() {
        let s = SpotLightParams::default();
        assert_eq!((s.cone_angle, s.cone_delta, s.to, s.i), (30.0, 5.0, Vec3::Z, Color::ONE));
        let d = DistantLightParams::default();
        assert_eq!((d.from, d.to, d.scale), (Vec3::ZERO, Vec3::Z, 1.0));
        // The default distant light shines along +z.
        let Light::Directional { direction, intensity } = Light::pbrt_distant(&Transform::IDENTITY, &d).unwrap() else {
            panic!("a directional light")
        };
        assert_eq!((direction, intensity), (Vec3::Z, Color::ONE));
    }

    #[test]
    fn point_power_sets_the_total_flux() {
        let i = Color::new(1.0, 0.5, 0.25);
        let p = PointLightParams { i, scale: 2.0, power: Some(100.0), from: Vec3::new(1.0, 0.0, 0.0) };
        let t = Transform::translate(Vec3::new(0.0, 3.0, 0.0));
        let light = Light::pbrt_point(&t, &p).unwrap();
        // Placed at light_to_world(from).
        let Light::Point { position, falloff, .. } = light else { panic!("a point light") };
        assert_eq!((position, falloff), (Vec3::new(1.0, 3.0, 0.0), Falloff::InverseSquare));
        // Φ = 4π lum(I) = scale · power.
        let phi = Emitter::Delta(light.clone()).power(&Bounds3::EMPTY);
        assert!((phi - 200.0).abs() < 1e-3, "{phi}");
        // Irradiance at distance d on a surface facing the light:
        // E = Φ / (4π d²) in luminance.
        let d = 2.5f32;
        let s = light.sample_li(position + Vec3::new(0.0, 0.0, d)).unwrap();
        let e = luminance(s.li);
        assert!((e - 200.0 / (4.0 * PI * d * d)).abs() < 1e-5, "{e}");
        // The colour keeps its chromaticity.
        assert!((s.li.y / s.li.x - 0.5).abs() < 1e-6);
        // Without power: I · scale.
        let plain = Light::pbrt_point(&Transform::IDENTITY, &PointLightParams { i, scale: 3.0, ..Default::default() });
        let Light::Point { intensity, .. } = plain.unwrap() else { panic!() };
        assert_eq!(intensity, i * 3.0);
        // power ≤ 0 means "not given", as pbrt's default −1.
        let neg = PointLightParams { i, power: Some(-1.0), ..Default::default() };
        let Light::Point { intensity, .. } = Light::pbrt_point(&Transform::IDENTITY, &neg).unwrap() else { panic!() };
        assert_eq!(intensity, i);
    }

    #[test]
    fn spot_power_follows_pbrt_and_the_cone_is_pbrts() {
        let p = SpotLightParams {
            i: Color::new(0.2, 1.0, 0.4),
            power: Some(50.0),
            from: Vec3::new(0.0, 4.0, 0.0),
            to: Vec3::new(0.0, 0.0, 0.0),
            ..Default::default()
        };
        let light = Light::pbrt_spot(&Transform::IDENTITY, &p).unwrap();
        let Light::Spot { position, direction, intensity, cos_total, cos_falloff_start, falloff } = light.clone()
        else {
            panic!("a spot light")
        };
        assert_eq!((position, direction, falloff), (Vec3::new(0.0, 4.0, 0.0), -Vec3::Y, Falloff::InverseSquare));
        assert!((cos_total - 30f32.to_radians().cos()).abs() < 1e-7);
        assert!((cos_falloff_start - 25f32.to_radians().cos()).abs() < 1e-7);
        let k = 2.0 * PI * (1.0 - 0.5 * (25f32.to_radians().cos() + 30f32.to_radians().cos()));
        assert!((luminance(intensity) * k - 50.0).abs() < 1e-3);
        assert!((Emitter::Delta(light.clone()).power(&Bounds3::EMPTY) - 50.0).abs() < 1e-3);
        // Numerically: ∫ I(ω) dω over the sphere, with pbrt's smoothstep
        // falloff, is the power (midpoint rule in cos θ).
        let n = 200_000;
        let mut flux = 0.0f64;
        for j in 0..n {
            let cos = -1.0 + 2.0 * (j as f64 + 0.5) / n as f64;
            let sin = (1.0 - cos * cos).sqrt();
            let p_at = position + Vec3::new(sin as f32, -cos as f32, 0.0);
            if let Some(s) = light.sample_li(p_at) {
                flux += luminance(s.li) as f64 * 2.0 * std::f64::consts::PI * 2.0 / n as f64;
            }
        }
        assert!((flux - 50.0).abs() < 0.05, "{flux}");
        // In the falloff region, pbrt's smoothstep of cos θ.
        let theta = 27.5f32.to_radians();
        let s = light.sample_li(position + Vec3::new(theta.sin(), -theta.cos(), 0.0)).unwrap();
        let t = (theta.cos() - cos_total) / (cos_falloff_start - cos_total);
        let want = intensity * (t * t * (3.0 - 2.0 * t));
        assert!((s.li - want).abs().max_element() < 1e-5 * want.max_element(), "{} vs {want}", s.li);
    }

    #[test]
    fn spot_and_distant_follow_the_transform() {
        let t = Transform::rotate_x(90.0).then(&Transform::translate(Vec3::new(1.0, 2.0, 3.0)));
        let Light::Spot { position, direction, .. } = Light::pbrt_spot(&t, &SpotLightParams::default()).unwrap() else {
            panic!()
        };
        // +z turned 90° about x is −y.
        assert!((position - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        assert!((direction + Vec3::Y).length() < 1e-6, "{direction}");
        let Light::Directional { direction, .. } = Light::pbrt_distant(&t, &DistantLightParams::default()).unwrap()
        else {
            panic!()
        };
        assert!((direction + Vec3::Y).length() < 1e-6, "{direction}");
    }

    #[test]
    fn distant_illuminance_is_what_a_facing_surface_receives() {
        let p = DistantLightParams {
            l: Color::new(3.0, 2.0, 1.0),
            scale: 0.5,
            illuminance: Some(10.0),
            from: Vec3::new(0.0, 10.0, 0.0),
            to: Vec3::ZERO,
        };
        let light = Light::pbrt_distant(&Transform::IDENTITY, &p).unwrap();
        let s = light.sample_li(Vec3::new(4.0, 0.0, -2.0)).unwrap();
        assert_eq!(s.wi, Vec3::Y);
        // The surface facing the light (normal +y) receives E = L·cos 0.
        assert!((luminance(s.li) - 5.0).abs() < 1e-5, "{}", s.li);
        assert!((s.li.x / s.li.z - 3.0).abs() < 1e-5);
    }

    #[test]
    fn bad_parameters_are_refused() {
        let id = Transform::IDENTITY;
        let neg = PointLightParams { i: Color::new(-1.0, 0.0, 0.0), ..Default::default() };
        assert_eq!(Light::pbrt_point(&id, &neg), Err(LightError::Color));
        let nan = PointLightParams { power: Some(f32::NAN), ..Default::default() };
        assert_eq!(Light::pbrt_point(&id, &nan), Err(LightError::NonFinite));
        let bad_scale = PointLightParams { scale: -2.0, ..Default::default() };
        assert_eq!(Light::pbrt_point(&id, &bad_scale), Err(LightError::Intensity(-2.0)));
        let cone = SpotLightParams { cone_angle: 10.0, cone_delta: 20.0, ..Default::default() };
        assert_eq!(Light::pbrt_spot(&id, &cone), Err(LightError::Cone { angle: 10.0, delta: 20.0 }));
        let same = SpotLightParams { to: Vec3::ZERO, ..Default::default() };
        assert_eq!(Light::pbrt_spot(&id, &same), Err(LightError::ZeroDirection));
        let same = DistantLightParams { to: Vec3::ZERO, ..Default::default() };
        assert_eq!(Light::pbrt_distant(&id, &same), Err(LightError::ZeroDirection));
        // A black light with a power stays black (no 0/0).
        let black = PointLightParams { i: Color::ZERO, power: Some(10.0), ..Default::default() };
        let Light::Point { intensity, .. } = Light::pbrt_point(&id, &black).unwrap() else { panic!() };
        assert_eq!(intensity, Color::ZERO);
    }
}
