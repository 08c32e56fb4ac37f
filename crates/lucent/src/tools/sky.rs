//! Procedural environment maps: a simple daylight sky and a photo studio,
//! as equirectangular [`Film`]s in the mapping of
//! [`Environment`](crate::light::Environment) (`+y` up, image centre towards `−z`,
//! `u` growing towards `+x`, top row the zenith), ready to be written as
//! `.hdr` or `.exr` and loaded with
//! [`Environment::from_file`](crate::light::Environment::from_file).
//!
//! Both are deterministic and analytic (no physical sky model): each pixel
//! is the solid-angle-weighted average of a 2 × 2 grid of directions inside
//! it, and pixels near the sun of a much finer grid (sub-samples about 1/32
//! of the sun's radius apart), so that a sun smaller than a pixel still
//! carries its energy.
//!
//! Azimuths are measured in the horizontal plane from `−z` (the image
//! centre) towards `+x`, i.e. the `u` direction of the image: azimuth `φ`
//! is at `u = 1/2 + φ / 360°`.

use crate::color::Color;
use crate::film::{Film, FilmError};
use crate::geometry::{Vec2, Vec3};
use crate::light::equirect_direction;
use std::f32::consts::PI;

/// Parameters of [`sky`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyParams {
    /// Sun elevation above the horizon, degrees (below 0 the sun is hidden
    /// by the ground and the sky dims to dusk).
    pub sun_elevation: f32,
    /// Sun azimuth, degrees, from `−z` towards `+x`.
    pub sun_azimuth: f32,
    /// Irradiance the sun disk delivers to a surface facing it (the sky
    /// adds roughly 1–2 on a horizontal surface). Its radiance is this
    /// divided by the disk's solid angle term `π sin²(radius)`.
    pub sun_intensity: f32,
    /// Angular radius of the sun disk, degrees (the real sun: 0.27°).
    pub sun_radius: f32,
}

impl Default for SkyParams {
    fn default() -> Self {
        Self { sun_elevation: 35.0, sun_azimuth: 45.0, sun_intensity: 8.0, sun_radius: 0.5 }
    }
}

/// Unit direction at `elevation` and `azimuth` (radians) in the convention
/// of the module docs.
pub fn direction_from_angles(elevation: f32, azimuth: f32) -> Vec3 {
    let (se, ce) = elevation.sin_cos();
    let (sa, ca) = azimuth.sin_cos();
    Vec3::new(ce * sa, se, -ce * ca)
}

#[inline]
fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Fill a `width × width/2` film with `f(direction)`, averaging `2 × 2`
/// directions per pixel, or `fine_n × fine_n` where `fine(direction of the
/// pixel centre, pixel angular size)` says so.
fn render_map(
    width: u32,
    f: impl Fn(Vec3) -> Color,
    fine: impl Fn(Vec3, f32) -> bool,
    fine_n: u32,
) -> Result<Film, FilmError> {
    let height = (width / 2).max(1);
    let mut film = Film::new(width, height)?;
    let pixel_angle = 2.0 * PI / width as f32;
    for y in 0..height {
        for x in 0..width {
            let centre = Vec2::new((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
            let n = if fine(equirect_direction(centre), pixel_angle) { fine_n } else { 2 };
            // Average over solid angle: dω ∝ sin θ du dv, so each
            // sub-sample is weighted by its sin θ.
            let (mut sum, mut weight) = (Color::ZERO, 0.0);
            for j in 0..n {
                let v = (y as f32 + (j as f32 + 0.5) / n as f32) / height as f32;
                let sin_theta = (PI * v).sin();
                for i in 0..n {
                    let uv = Vec2::new((x as f32 + (i as f32 + 0.5) / n as f32) / width as f32, v);
                    sum += f(equirect_direction(uv)) * sin_theta;
                    weight += sin_theta;
                }
            }
            film.pixels_mut()[(y * width + x) as usize] = if weight > 0.0 { sum / weight } else { Color::ZERO };
        }
    }
    Ok(film)
}

/// A daylight sky: a gradient from a deep blue zenith to a pale horizon, a
/// glow around the sun, a darker ground below the horizon and a sun disk of
/// high radiance that dominates the lighting. `width` pixels wide, half as
/// high.
pub fn sky(width: u32, params: &SkyParams) -> Result<Film, FilmError> {
    let elev = params.sun_elevation.to_radians();
    let sun = direction_from_angles(elev, params.sun_azimuth.to_radians());
    let radius = params.sun_radius.to_radians().clamp(1e-4, 0.5 * PI);
    let cos_radius = radius.cos();
    // Uniform disk of angular radius ρ: E = π L sin²ρ at normal incidence.
    let sun_radiance = params.sun_intensity.max(0.0) / (PI * radius.sin().powi(2));
    // Warmer and the sky dimmer when the sun is low.
    let day = smoothstep(-6f32.to_radians(), 30f32.to_radians(), elev);
    let sun_color = Color::new(1.0, 0.55, 0.3).lerp(Color::new(1.0, 0.97, 0.92), day);
    let zenith = Color::new(0.12, 0.25, 0.65) * (0.1 + 0.9 * day);
    let horizon = Color::new(0.75, 0.8, 0.9) * (0.15 + 0.85 * day) + Color::new(0.3, 0.12, 0.0) * (1.0 - day) * 0.3;
    let ground = Color::new(0.16, 0.14, 0.12) * (0.1 + 0.9 * day);
    let sun_visible = elev + radius > 0.0;
    let f = |d: Vec3| -> Color {
        let cos_sun = d.dot(sun);
        // Sky: blend on an eased elevation; glow ∝ a narrow and a wide lobe.
        let up = d.y.max(0.0);
        let t = up.powf(0.45);
        let glow = 0.6 * (-8.0 * (1.0 - cos_sun)).exp() + 0.15 * (cos_sun.max(0.0)).powi(4);
        let sky = horizon.lerp(zenith, t) + sun_color * glow * (0.2 + 0.8 * day);
        // Ground: darker towards the nadir, blended over ~1° at the horizon.
        let g = ground * (0.6 + 0.4 * (1.0 + d.y).powi(2));
        let mut c = g.lerp(sky, smoothstep(-0.02, 0.0, d.y));
        if sun_visible && cos_sun >= cos_radius && d.y >= 0.0 {
            c += sun_color * sun_radiance;
        }
        c
    };
    let fine = |d: Vec3, pixel: f32| d.dot(sun) >= (radius + 2.0 * pixel).min(PI).cos();
    // Near the sun, sub-samples about 1/32 of its radius apart, so that the
    // disk's solid angle is captured within a few percent.
    let pixel_height = PI / (width / 2).max(1) as f32;
    let fine_n = (32.0 * pixel_height / radius).ceil().clamp(16.0, 256.0) as u32;
    render_map(width, f, fine, fine_n)
}

/// A photo studio: a dark grey background, a floor brightening towards the
/// nadir, and three large soft boxes (a key light, a fill light and an
/// overhead strip) with soft edges. `width` pixels wide, half as high.
pub fn studio(width: u32) -> Result<Film, FilmError> {
    // (centre azimuth, centre elevation, half width, half height) in
    // degrees, and radiance.
    let boxes: [(f32, f32, f32, f32, Color); 3] = [
        (-50.0, 30.0, 16.0, 11.0, Color::splat(12.0)),
        (70.0, 15.0, 10.0, 14.0, Color::new(4.0, 4.2, 4.5)),
        (180.0, 70.0, 40.0, 5.0, Color::splat(6.0)),
    ];
    let f = |d: Vec3| -> Color {
        let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
        let azimuth = d.x.atan2(-d.z).to_degrees();
        let background = Color::splat(0.03);
        let floor = Color::splat(0.05) + Color::splat(0.12) * (-d.y).max(0.0);
        let mut c = floor.lerp(background, smoothstep(-2.0, 0.0, elevation));
        for &(az, el, hw, hh, l) in &boxes {
            // Angular offsets; azimuth differences wrap around ±180°.
            let da = ((azimuth - az + 540.0).rem_euclid(360.0) - 180.0).abs() * elevation.to_radians().cos();
            let de = (elevation - el).abs();
            let edge = 1.5;
            let w = (1.0 - smoothstep(hw - edge, hw + edge, da)) * (1.0 - smoothstep(hh - edge, hh + edge, de));
            c += l * w;
        }
        c
    };
    render_map(width, f, |_, _| false, 2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::luminance;

    /// Irradiance on a surface with normal `n`, summed over the pixels.
    fn irradiance(film: &Film, n: Vec3) -> f32 {
        let (w, h) = (film.width(), film.height());
        let mut e = 0.0f64;
        for y in 0..h {
            let t0 = PI * y as f32 / h as f32;
            let t1 = PI * (y + 1) as f32 / h as f32;
            let omega = 2.0 * PI / w as f32 * (t0.cos() - t1.cos());
            for x in 0..w {
                let d = equirect_direction(Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32));
                e += (luminance(film.pixel(x, y)) * d.dot(n).max(0.0) * omega) as f64;
            }
        }
        e as f32
    }

    #[test]
    fn sun_delivers_its_intensity_and_dominates() {
        let p = SkyParams { sun_elevation: 90.0, sun_azimuth: 0.0, sun_intensity: 10.0, sun_radius: 0.5 };
        let with_sun = sky(256, &p).unwrap();
        let without = sky(256, &SkyParams { sun_intensity: 0.0, ..p }).unwrap();
        assert_eq!((with_sun.width(), with_sun.height()), (256, 128));
        let e_sun = irradiance(&with_sun, Vec3::Y) - irradiance(&without, Vec3::Y);
        // The sun colour's luminance at full day is ≈ 0.97.
        assert!((e_sun / (10.0 * luminance(Color::new(1.0, 0.97, 0.92))) - 1.0).abs() < 0.03, "{e_sun}");
        assert!(e_sun > 3.0 * irradiance(&without, Vec3::Y));
        // Deterministic.
        assert_eq!(sky(256, &p).unwrap(), with_sun);
    }

    #[test]
    fn sky_is_above_ground_and_sun_where_asked() {
        let p = SkyParams { sun_elevation: 30.0, sun_azimuth: 90.0, ..SkyParams::default() };
        let film = sky(360, &p).unwrap();
        let (w, h) = (film.width(), film.height());
        // Brightest pixel: azimuth 90° is u = 3/4, elevation 30° is v = 1/3.
        let (mut best, mut at) = (0.0, (0, 0));
        for y in 0..h {
            for x in 0..w {
                let l = luminance(film.pixel(x, y));
                if l > best {
                    best = l;
                    at = (x, y);
                }
            }
        }
        assert!((at.0 as i32 - 270).abs() <= 1 && (at.1 as i32 - 60).abs() <= 1, "{at:?}");
        assert!(luminance(film.pixel(0, 10)) > luminance(film.pixel(0, h - 10)), "sky brighter than ground");
    }

    #[test]
    fn studio_has_bright_boxes_on_dark_grey() {
        let film = studio(360).unwrap();
        let lum: Vec<f32> = film.pixels().iter().map(|&c| luminance(c)).collect();
        let max = lum.iter().cloned().fold(0.0, f32::max);
        let dark = lum.iter().filter(|&&l| l < 0.2).count();
        assert!(max >= 10.0, "{max}");
        assert!(dark > lum.len() / 2, "mostly dark background");
        assert_eq!(studio(360).unwrap(), film);
    }
}
