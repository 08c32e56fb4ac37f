//! The camera's importance function `We`, the adjoint of radiance, for
//! bidirectional methods (light tracing, BDPT): PBRT 4th ed., §5.4.2–5.4.3
//! ("The Camera Measurement Equation") and pbrt-v4's
//! `PerspectiveCamera::We`, `PDF_We` and `SampleWi`; Veach 1997, §4.5
//! (importance and the measurement equation) and ch. 10 (bidirectional path
//! tracing).
//!
//! # Normalisation
//!
//! A measurement is `I = ∫_lens ∫_Ω We(p, ω) L(p, −ω) cos θ dω dA(p)`, with
//! `θ` the angle between `ω` and the lens normal. Like pbrt, lucent takes
//! `We` for the *whole image*: it is chosen so that a camera ray drawn the
//! way [`Camera::generate_ray`] draws it (film position uniform over the
//! image, lens point uniform over the lens) has
//! `We cos θ = pdf_pos · pdf_dir`, where `pdf_pos` (area measure on the lens)
//! and `pdf_dir` (solid angle) are the densities of that ray. Hence
//! `∫∫ We cos θ dω dA = 1`, and the camera-ray estimator
//! `We L cos θ / (pdf_pos pdf_dir)` is `L` itself.
//!
//! A pixel, being one of the `width · height` equal parts of the image, has
//! the importance `width · height · We` on the rays that land in it; so a
//! light-tracing contribution splatted at [`ImportanceSample::film`] is
//! scaled by `width · height / N` for `N` light subpaths, which is `1/spp`
//! when one light subpath is traced per pixel sample (pbrt's convention).
//!
//! # Geometry
//!
//! The camera basis `(u, v, w)` need not be orthonormal (a scale or mirror
//! in [`Camera::pbrt`]'s transform makes it otherwise). Everything is
//! measured from the lens plane `eye + span(u, v)`, with its unit normal
//! `n` on `w`'s side ([`Camera::forward`]; `n = w/|w|` whenever the basis
//! is orthogonal) and `h = w·n` (`|w|` then):
//!
//! * the image rectangle (the screen window `eye + w + x u + y v`) lies at
//!   distance `h` along `n` and has area `4 · half_width · half_height ·
//!   |u × v|`; at unit distance its area is
//!   `A = 4 · half_width · half_height · |u × v| / h²`;
//! * a thin lens is the disk `eye + r (d_x u + d_y v)`, `d` in the unit disk,
//!   of area `A_lens = π r² |u × v|`; a pinhole has `A_lens = 1`, as in pbrt
//!   (its `pdf_pos` is a Dirac delta whose weight is left out, consistently,
//!   of `We`, `pdf_pos` and the pdf of [`Camera::sample_importance`]);
//! * the plane of focus lies at distance `f h` along `n` (`f` the focal
//!   distance: `generate_ray` aims at `eye + f (w + x u + y v)`).
//!
//! **Direction pdf.** A pinhole ray's image-plane point is uniform over the
//! image rectangle at unit distance, density `1/A` per unit area; a point
//! there at angle `θ` lies at distance `1/cos θ` and is foreshortened by
//! `cos θ`, so `dω = cos³θ dA` and `pdf_dir = 1 / (A cos³θ)` (PBRT 4th ed.,
//! §5.4.3). With a thin lens the focus point is uniform over the
//! rectangle scaled to the plane of focus, seen from the lens point at
//! distance `f h / cos θ`: the same `1 / (A cos³θ)`.
//!
//! **Importance.** `We = pdf_pos · pdf_dir / cos θ = 1 / (A · A_lens · cos⁴θ)`
//! (PBRT 4th ed., §5.4.3), on the rays that land in the image, and zero
//! elsewhere.
//!
//! **Film position.** Write a vector in the basis as `a u + b v + c w` (by
//! the dual basis, so exactly for any non-degenerate basis). The ray from
//! lens point `o = eye + a_o u + b_o v` in direction `d` crosses the plane
//! of focus (`c = f`) at `o + (f / c_d) d`, which is `eye + f (x u + y v +
//! w)` with the screen point `(x, y) = (a_d, b_d) / c_d + (a_o, b_o) / f`;
//! for a pinhole, `(a_d, b_d) / c_d`. Inverting `Camera::screen` then gives
//! pixels.

use super::{Camera, Model};
use crate::geometry::{Vec2, Vec3};
use crate::sampling::concentric_disk;
use std::f32::consts::PI;

/// A point on the camera's lens sampled towards a reference point: the
/// importance arriving there (pbrt-v4's `CameraWiSample`), from
/// [`Camera::sample_importance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImportanceSample {
    /// Importance `We` of the ray from `p_lens` towards the reference point
    /// (`We(p_lens, −wi)`, as [`Camera::importance`] gives it).
    pub we: f32,
    /// Unit direction from the reference point towards `p_lens`.
    pub wi: Vec3,
    /// Solid-angle pdf of `wi` at the reference point:
    /// `dist² / (|n_lens · wi| · A_lens)` (`A_lens = 1` for a pinhole).
    pub pdf: f32,
    /// The sampled lens point (the eye for a pinhole).
    pub p_lens: Vec3,
    /// Unit normal of the lens, [`Camera::forward`] (the unit view
    /// direction `ŵ`), pointing into the scene.
    pub n_lens: Vec3,
    /// Where the ray lands on the film, in pixels (`(0, 0)` the top-left
    /// corner of the image, as for [`Camera::generate_ray`]).
    pub film: Vec2,
}

/// The quantities of the module docs that the importance functions share.
struct Lens {
    /// Unit normal of the lens plane, on `w`'s side.
    n: Vec3,
    /// The dual basis divided by `u · (v × w)`: `p · du` is the `u`
    /// coordinate of `p` in the basis `(u, v, w)`, and so on.
    du: Vec3,
    dv: Vec3,
    dw: Vec3,
    /// Area of the image rectangle at unit distance along `n`.
    area: f32,
    /// Area of the lens (1 for a pinhole).
    lens_area: f32,
    /// The focal distance `f` for a thin lens, `None` for a pinhole.
    focal_distance: Option<f32>,
}

impl Camera {
    /// The lens and image geometry of a perspective camera; `None` for the
    /// other models (or a degenerate basis).
    fn importance_lens(&self) -> Option<Lens> {
        if self.model != Model::Perspective {
            return None;
        }
        let (u, v, w) = (self.u, self.v, self.w);
        let uv = u.cross(v);
        let det = w.dot(uv);
        let uv_len = uv.length();
        if !(det.is_finite() && det != 0.0 && uv_len > 0.0) {
            return None;
        }
        let n = uv * (det.signum() / uv_len);
        let h = det.abs() / uv_len;
        let area = 4.0 * self.half_width * self.half_height * uv_len / (h * h);
        let (lens_area, focal_distance) = match self.lens {
            Some(l) => (PI * l.radius * l.radius * uv_len, Some(l.focal_distance)),
            None => (1.0, None),
        };
        let inv = 1.0 / det;
        Some(Lens { n, du: v.cross(w) * inv, dv: w.cross(u) * inv, dw: uv * inv, area, lens_area, focal_distance })
    }

    /// The film position (pixels) of the ray from `origin` in direction
    /// `dir` (with `dir · n > 0`), if it lands in `[0, width) × [0, height)`.
    fn importance_film(&self, lens: &Lens, origin: Vec3, dir: Vec3) -> Option<Vec2> {
        let c = dir.dot(lens.dw);
        let mut s = Vec2::new(dir.dot(lens.du), dir.dot(lens.dv)) / c;
        if let Some(f) = lens.focal_distance {
            let o = origin - self.eye;
            s += Vec2::new(o.dot(lens.du), o.dot(lens.dv)) / f;
        }
        // `screen` inverted: x = (2 px / width − 1) hw + cx,
        // y = (1 − 2 py / height) hh + cy.
        let (width, height) = (self.width as f32, self.height as f32);
        let px = ((s.x - self.centre.x) / self.half_width + 1.0) * 0.5 * width;
        let py = (1.0 - (s.y - self.centre.y) / self.half_height) * 0.5 * height;
        // (NaN fails these comparisons too.)
        (px >= 0.0 && px < width && py >= 0.0 && py < height).then_some(Vec2::new(px, py))
    }

    /// Whether the camera has an importance function: perspective cameras
    /// (pinhole or thin lens) do; orthographic and spherical ones do not (as
    /// in pbrt-v4, whose `OrthographicCamera` and `SphericalCamera` leave
    /// `We` unimplemented), and bidirectional methods then skip connections
    /// to the camera.
    pub fn has_importance(&self) -> bool {
        self.importance_lens().is_some()
    }

    /// The unit view direction `ŵ`: the unit normal of the lens and image
    /// planes (the plane of `u` and `v`), on the side of `w`. It is
    /// `w / |w|` whenever the basis is orthogonal (always for
    /// [`Camera::new`], and for [`Camera::pbrt`] unless its transform
    /// shears).
    pub fn forward(&self) -> Vec3 {
        let uv = self.u.cross(self.v);
        let det = self.w.dot(uv);
        let uv_len = uv.length();
        if det != 0.0 && uv_len > 0.0 {
            // As in `importance_lens`, to the last bit.
            uv * (det.signum() / uv_len)
        } else {
            self.w.normalize_or_zero()
        }
    }

    /// Importance `We` of a ray leaving lens point `origin` in unit
    /// direction `dir`, and its film position in pixels (`(0, 0)` the
    /// top-left corner, as for [`Camera::generate_ray`], which it inverts);
    /// `None` when the ray is behind the camera (`dir · ŵ ≤ 0`) or misses
    /// the image (lands outside `[0, width) × [0, height)`), or the camera
    /// has no importance.
    ///
    /// `We = 1 / (A · A_lens · cos⁴θ)` (PBRT 4th ed., §5.4.3), with `A`
    /// the area of the image rectangle at unit distance along `ŵ`,
    /// `A_lens = π r² |u × v|` (`π r²` for a unit basis) for a thin lens and
    /// 1 for a pinhole, and `cos θ = dir · ŵ` (see the module docs).
    ///
    /// `origin` is taken to lie on the lens (in the plane of the eye, `u`
    /// and `v`); for a pinhole it is not used: the ray is taken to leave the
    /// eye.
    pub fn importance(&self, origin: Vec3, dir: Vec3) -> Option<(f32, Vec2)> {
        let lens = self.importance_lens()?;
        self.importance_with(&lens, origin, dir)
    }

    fn importance_with(&self, lens: &Lens, origin: Vec3, dir: Vec3) -> Option<(f32, Vec2)> {
        let cos = dir.dot(lens.n);
        if cos.is_nan() || cos <= 0.0 {
            return None;
        }
        let film = self.importance_film(lens, origin, dir)?;
        let cos2 = cos * cos;
        let we = 1.0 / (lens.area * lens.lens_area * cos2 * cos2);
        we.is_finite().then_some((we, film))
    }

    /// The densities with which [`Camera::generate_ray`] produces a ray in
    /// unit direction `dir` (film position uniform over the image, lens
    /// sample uniform): `(pdf_pos, pdf_dir)`, `pdf_pos = 1 / A_lens` with
    /// respect to area on the lens (1 for a pinhole), `pdf_dir = 1 / (A
    /// cos³θ)` with respect to solid angle (pbrt-v4's `PDF_We`; see
    /// [`Camera::importance`] for `A`, `A_lens`, `θ`). `(0, 0)` when `dir`
    /// is behind the camera or misses the image, or the camera has no
    /// importance. `We = pdf_pos · pdf_dir / cos θ`.
    ///
    /// Whether `dir` lands in the image is judged for the ray leaving the
    /// eye: exact for a pinhole; with a thin lens, use
    /// [`Camera::pdf_importance_from`] with the ray's own lens point
    /// (near the image border the two can differ).
    pub fn pdf_importance(&self, dir: Vec3) -> (f32, f32) {
        self.pdf_importance_from(self.eye, dir)
    }

    /// [`Camera::pdf_importance`] for the ray leaving lens point `origin`
    /// (pbrt-v4's `PDF_We` of a ray): the ray lands in the image, and the
    /// pdfs are nonzero, exactly when [`Camera::importance`] of the same
    /// ray is `Some`.
    pub fn pdf_importance_from(&self, origin: Vec3, dir: Vec3) -> (f32, f32) {
        let Some(lens) = self.importance_lens() else {
            return (0.0, 0.0);
        };
        let cos = dir.dot(lens.n);
        if cos.is_nan() || cos <= 0.0 || self.importance_film(&lens, origin, dir).is_none() {
            return (0.0, 0.0);
        }
        let pdf_dir = 1.0 / (lens.area * cos * cos * cos);
        if !pdf_dir.is_finite() {
            return (0.0, 0.0);
        }
        (1.0 / lens.lens_area, pdf_dir)
    }

    /// Sample a lens point seen from reference point `p_ref` (pbrt-v4's
    /// `SampleWi`): `u ∈ [0, 1)²` is mapped to the lens disk by the
    /// concentric map, as [`Camera::generate_ray`] maps its lens sample (a
    /// pinhole always gives the eye). `None` when the ray from the lens
    /// point towards `p_ref` is behind the camera or misses the image,
    /// `p_ref` is on the lens point, or the camera has no importance.
    ///
    /// The lens point is uniform over the lens, density `1 / A_lens` by
    /// area; as a solid-angle density at `p_ref`,
    /// `pdf = dist² / (|n_lens · wi| · A_lens)` (`A_lens = 1` for a
    /// pinhole). A light subpath vertex at `p_ref` with throughput `β` and
    /// BSDF `f` then contributes `β f(wo, wi) |n_ref · wi| We / pdf` at
    /// [`ImportanceSample::film`] (with the visibility of the segment, and
    /// the film scale of the module docs).
    pub fn sample_importance(&self, p_ref: Vec3, u: Vec2) -> Option<ImportanceSample> {
        let lens = self.importance_lens()?;
        let p_lens = match self.lens {
            Some(l) => {
                let d = l.radius * concentric_disk(u);
                self.eye + d.x * self.u + d.y * self.v
            }
            None => self.eye,
        };
        let to_lens = p_lens - p_ref;
        let dist2 = to_lens.length_squared();
        if !(dist2 > 0.0 && dist2.is_finite()) {
            return None;
        }
        let wi = to_lens / dist2.sqrt();
        let (we, film) = self.importance_with(&lens, p_lens, -wi)?;
        let pdf = dist2 / (wi.dot(lens.n).abs() * lens.lens_area);
        (pdf.is_finite() && pdf > 0.0).then_some(ImportanceSample { we, wi, pdf, p_lens, n_lens: lens.n, film })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Projection, SphericalMapping, ThinLens};
    use crate::geometry::{Mat4, Transform};
    use crate::sampling::{uniform_sphere, Pcg32};
    use glam::Vec4;

    fn perspective(fov: f32, window: Option<[f32; 4]>, lens: Option<ThinLens>) -> Projection {
        Projection::Perspective { fov_degrees: fov, screen_window: window, frame_aspect_ratio: None, lens }
    }

    fn pinhole() -> Camera {
        Camera::new(Vec3::new(1.0, 2.0, -3.0), Vec3::new(4.0, 0.5, 9.0), Vec3::Y, 70.0, 160, 90).unwrap()
    }

    fn thin_lens() -> Camera {
        pinhole().with_lens(ThinLens { radius: 0.4, focal_distance: 6.0 }).unwrap()
    }

    /// A pbrt camera with a screen window, mirrored, scaled (a basis that
    /// is not unit) and moved.
    fn pbrt_scaled() -> Camera {
        let t = Transform::scale(Vec3::new(-2.0, 0.5, 1.5))
            .unwrap()
            .then(&Transform::rotate(Vec3::new(1.0, 1.0, 0.0), 30.0).unwrap())
            .then(&Transform::translate(Vec3::new(0.5, -1.0, 2.0)));
        let lens = ThinLens { radius: 0.3, focal_distance: 4.0 };
        Camera::pbrt(&t, perspective(60.0, Some([-0.5, 1.5, -1.0, 0.25]), Some(lens)), 120, 80).unwrap()
    }

    /// A pbrt camera whose transform shears: `u`, `v`, `w` not orthogonal.
    fn pbrt_sheared(lens: Option<ThinLens>) -> Camera {
        let m = Mat4::from_cols(
            Vec4::new(1.0, 0.0, 0.2, 0.0),
            Vec4::new(0.3, 1.2, 0.0, 0.0),
            Vec4::new(0.2, 0.1, 0.9, 0.0),
            Vec4::new(0.0, 1.0, -2.0, 1.0),
        );
        Camera::pbrt(&Transform::from_matrix(m).unwrap(), perspective(50.0, None, lens), 64, 48).unwrap()
    }

    fn cameras() -> Vec<(&'static str, Camera)> {
        let pbrt_pinhole =
            Camera::pbrt(&Transform::rotate_y(20.0), perspective(45.0, Some([0.0, 1.0, -0.5, 0.5]), None), 100, 50)
                .unwrap();
        vec![
            ("pinhole", pinhole()),
            ("thin lens", thin_lens()),
            ("pbrt pinhole with a screen window", pbrt_pinhole),
            ("pbrt scaled thin lens", pbrt_scaled()),
            ("pbrt sheared pinhole", pbrt_sheared(None)),
            ("pbrt sheared thin lens", pbrt_sheared(Some(ThinLens { radius: 0.2, focal_distance: 3.0 }))),
        ]
    }

    fn uniform2(rng: &mut Pcg32) -> Vec2 {
        Vec2::new(rng.uniform(), rng.uniform())
    }

    /// Where the ray from `origin` along `dir` meets the plane at distance
    /// `dist` along `n` from `eye`.
    fn hit_plane(origin: Vec3, dir: Vec3, eye: Vec3, n: Vec3, dist: f32) -> Vec3 {
        origin + dir * ((dist - (origin - eye).dot(n)) / dir.dot(n))
    }

    #[test]
    fn importance_inverts_generate_ray() {
        let mut rng = Pcg32::new(7, 1);
        for (name, cam) in cameras() {
            assert!(cam.has_importance(), "{name}");
            let size = Vec2::new(cam.width() as f32, cam.height() as f32);
            for _ in 0..2000 {
                let film = uniform2(&mut rng) * size;
                let ray = cam.generate_ray(film, uniform2(&mut rng));
                let (we, back) = cam.importance(ray.origin, ray.dir).unwrap_or_else(|| panic!("{name}: {film}"));
                assert!(we > 0.0 && we.is_finite(), "{name}: We {we}");
                assert!((back - film).abs().max_element() < 1e-3, "{name}: {film} came back as {back}");
                let (pdf_pos, pdf_dir) = cam.pdf_importance_from(ray.origin, ray.dir);
                assert!(pdf_pos > 0.0 && pdf_dir > 0.0, "{name}");
            }
        }
    }

    #[test]
    fn centre_importance_is_one_over_the_image_area() {
        // fov 90° on a 2:1 image: the image at unit distance is 2 × 1.
        let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 90.0, 200, 100).unwrap();
        assert_eq!(cam.forward(), Vec3::Z);
        let (we, film) = cam.importance(Vec3::ZERO, Vec3::Z).unwrap();
        assert!((we - 0.5).abs() < 1e-6 && film == Vec2::new(100.0, 50.0), "{we} {film}");
        assert_eq!(cam.pdf_importance(Vec3::Z), (1.0, 0.5));
        // Off axis, We falls as cos⁻⁴θ; pdf_dir as cos⁻³θ.
        let d = Vec3::new(0.5, 0.25, 1.0).normalize();
        let (we, film) = cam.importance(Vec3::ZERO, d).unwrap();
        assert!((we - 0.5 / d.z.powi(4)).abs() < 1e-5 * we, "{we}");
        // u = w × up = −x, so screen x = −0.5 (a quarter of the width left of
        // the centre); screen y = 0.25, half the half-height above it.
        assert!((film - Vec2::new(50.0, 25.0)).length() < 1e-4, "{film}");
        let (_, pdf_dir) = cam.pdf_importance(d);
        assert!((pdf_dir - 0.5 / d.z.powi(3)).abs() < 1e-5 * pdf_dir);
        // A thin lens of radius 2 divides it by the lens area 4π.
        let lens = cam.clone().with_lens(ThinLens { radius: 2.0, focal_distance: 10.0 }).unwrap();
        let (we, _) = lens.importance(Vec3::ZERO, Vec3::Z).unwrap();
        assert!((we - 0.5 / (4.0 * PI)).abs() < 1e-7, "{we}");
        assert_eq!(lens.pdf_importance(Vec3::Z).0, 1.0 / (4.0 * PI));
    }

    #[test]
    fn importance_is_zero_behind_and_outside_the_image() {
        for (name, cam) in cameras() {
            let eye = cam.eye();
            let n = cam.forward();
            for dir in [-n, cam.basis().0.normalize(), (cam.basis().1 * 100.0 + cam.basis().2).normalize()] {
                assert_eq!(cam.importance(eye, dir), None, "{name}: {dir}");
                assert_eq!(cam.pdf_importance(dir), (0.0, 0.0), "{name}: {dir}");
                assert_eq!(cam.pdf_importance_from(eye, dir), (0.0, 0.0), "{name}: {dir}");
            }
        }
        // The image is half-open: the right and bottom edges are outside.
        let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 90.0, 200, 100).unwrap();
        let left = cam.image_plane_direction(Vec2::new(0.0, 50.0)).normalize();
        assert!(cam.importance(Vec3::ZERO, left).is_some());
        let right = cam.image_plane_direction(Vec2::new(200.0, 50.0)).normalize();
        assert!(cam.importance(Vec3::ZERO, right).is_none());
    }

    #[test]
    fn importance_is_the_ray_density_over_cos() {
        let mut rng = Pcg32::new(11, 2);
        for (name, cam) in cameras() {
            let size = Vec2::new(cam.width() as f32, cam.height() as f32);
            let n = cam.forward();
            for _ in 0..500 {
                let ray = cam.generate_ray(uniform2(&mut rng) * size, uniform2(&mut rng));
                let (we, _) = cam.importance(ray.origin, ray.dir).unwrap();
                let (pdf_pos, pdf_dir) = cam.pdf_importance_from(ray.origin, ray.dir);
                let cos = ray.dir.dot(n);
                assert!((we - pdf_pos * pdf_dir / cos).abs() <= 1e-5 * we, "{name}");
            }
        }
    }

    /// `∫ pdf_dir dω` over the sphere of directions from `origin`, by
    /// stratified uniform directions (200 000 of them).
    fn pdf_dir_integral(cam: &Camera, origin: Option<Vec3>, rng: &mut Pcg32) -> f64 {
        let (nx, ny) = (500, 400);
        let mut sum = 0.0f64;
        for i in 0..nx {
            for j in 0..ny {
                let u = Vec2::new((i as f32 + rng.uniform()) / nx as f32, (j as f32 + rng.uniform()) / ny as f32);
                let d = uniform_sphere(u);
                let (_, pdf_dir) = match origin {
                    Some(o) => cam.pdf_importance_from(o, d),
                    None => cam.pdf_importance(d),
                };
                sum += pdf_dir as f64;
            }
        }
        sum * 4.0 * std::f64::consts::PI / (nx * ny) as f64
    }

    #[test]
    fn pdf_dir_integrates_to_one() {
        let mut rng = Pcg32::new(3, 3);
        for (name, cam) in cameras() {
            let total = pdf_dir_integral(&cam, None, &mut rng);
            assert!((total - 1.0).abs() < 0.01, "{name}: ∫ pdf_dir dω = {total}");
            if let Some(l) = cam.lens() {
                // From a point on the lens rim, through the focus rectangle.
                let (u, v, _) = cam.basis();
                let o = cam.eye() + l.radius * (0.6 * u - 0.8 * v);
                let total = pdf_dir_integral(&cam, Some(o), &mut rng);
                assert!((total - 1.0).abs() < 0.01, "{name}: ∫ pdf_dir dω from the lens rim = {total}");
            }
        }
    }

    #[test]
    fn sample_importance_matches_importance() {
        let mut rng = Pcg32::new(5, 4);
        for (name, cam) in cameras() {
            let size = Vec2::new(cam.width() as f32, cam.height() as f32);
            let n = cam.forward();
            let lens_area = cam.lens().map_or(1.0, |l| {
                let (u, v, _) = cam.basis();
                PI * l.radius * l.radius * u.cross(v).length()
            });
            let mut found = 0;
            for _ in 0..1000 {
                // A point seen by the camera, at distance 2 to 20 along a
                // camera ray.
                let ray = cam.generate_ray(uniform2(&mut rng) * size, uniform2(&mut rng));
                let p_ref = ray.at(2.0 + 18.0 * rng.uniform());
                let Some(s) = cam.sample_importance(p_ref, uniform2(&mut rng)) else {
                    continue;
                };
                found += 1;
                let dist2 = (s.p_lens - p_ref).length_squared();
                assert!((s.wi - (s.p_lens - p_ref) / dist2.sqrt()).length() < 1e-6, "{name}");
                assert!((s.pdf - dist2 / (s.wi.dot(n).abs() * lens_area)).abs() <= 1e-5 * s.pdf, "{name}");
                assert_eq!(s.n_lens, n);
                assert_eq!(cam.importance(s.p_lens, -s.wi), Some((s.we, s.film)), "{name}");
                if cam.lens().is_none() {
                    assert_eq!(s.p_lens, cam.eye());
                    assert!((s.pdf - dist2 / (-s.wi).dot(n)).abs() <= 1e-5 * s.pdf);
                }
            }
            // Only lens points near a border see the point outside the image.
            assert!(found > 900, "{name}: {found}");
            // Behind the camera, and on the eye of a pinhole: nothing.
            let eye = cam.eye();
            assert_eq!(cam.sample_importance(eye - 3.0 * n, Vec2::splat(0.3)), None, "{name}");
            if cam.lens().is_none() {
                assert_eq!(cam.sample_importance(eye, Vec2::splat(0.3)), None, "{name}");
            }
        }
    }

    #[test]
    fn points_on_the_plane_of_focus_reach_one_film_position() {
        let cam = thin_lens();
        let film = Vec2::new(40.25, 70.5);
        let focus = cam.eye() + 6.0 * cam.image_plane_direction(film);
        let mut rng = Pcg32::new(9, 5);
        for _ in 0..200 {
            let s = cam.sample_importance(focus, uniform2(&mut rng)).unwrap();
            assert!((s.film - film).length() < 1e-3, "{}", s.film);
        }
    }

    /// `∫_lens ∫_Ω We cos θ dω dA = 1`, by light tracing: points of a plane
    /// in front of the camera, large enough to fill its view, connected to
    /// the lens by `sample_importance`. `dω = cos_ref dA_ref / dist²` turns
    /// the integral into one over the plane, and the estimator into
    /// `We |cos_ref| area / pdf`. Each quarter of the image gets a quarter.
    #[test]
    fn importance_integrates_to_one_over_the_image() {
        let mut rng = Pcg32::new(13, 6);
        for (name, cam) in cameras() {
            let n = cam.forward();
            let u = cam.basis().0;
            // A frame of the plane at distance 5 along n.
            let e1 = (u - u.dot(n) * n).normalize();
            let e2 = n.cross(e1);
            let centre = cam.eye() + 5.0 * n;
            // Half-size covering every ray of the camera at distance 5.
            let size = Vec2::new(cam.width() as f32, cam.height() as f32);
            let mut half = 0.0f32;
            for corner in [Vec2::ZERO, Vec2::new(size.x, 0.0), Vec2::new(0.0, size.y), size] {
                for lens in [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0), Vec2::ONE] {
                    let r = cam.generate_ray(corner, lens);
                    let p = hit_plane(r.origin, r.dir, cam.eye(), n, 5.0) - centre;
                    half = half.max(p.dot(e1).abs()).max(p.dot(e2).abs());
                }
            }
            half *= 1.05;
            let area = 4.0 * half * half;
            let (nx, ny) = (400, 400);
            let mut quarters = [0.0f64; 4];
            for i in 0..nx {
                for j in 0..ny {
                    let s = Vec2::new((i as f32 + rng.uniform()) / nx as f32, (j as f32 + rng.uniform()) / ny as f32);
                    let p_ref = centre + (2.0 * s.x - 1.0) * half * e1 + (2.0 * s.y - 1.0) * half * e2;
                    let Some(is) = cam.sample_importance(p_ref, uniform2(&mut rng)) else {
                        continue;
                    };
                    let q = usize::from(is.film.x >= 0.5 * size.x) + 2 * usize::from(is.film.y >= 0.5 * size.y);
                    quarters[q] += (is.we * is.wi.dot(n).abs() * area / is.pdf) as f64;
                }
            }
            let quarters = quarters.map(|q| q / (nx * ny) as f64);
            let total: f64 = quarters.iter().sum();
            assert!((total - 1.0).abs() < 0.01, "{name}: ∫∫ We cos = {total}");
            for q in quarters {
                assert!((q - 0.25).abs() < 0.01, "{name}: quarters {quarters:?}");
            }
        }
    }

    #[test]
    fn orthographic_and_spherical_cameras_have_no_importance() {
        let ortho = Projection::Orthographic { screen_window: None, frame_aspect_ratio: None, lens: None };
        let equirect = Projection::Spherical { mapping: SphericalMapping::Equirectangular };
        let equal_area = Projection::Spherical { mapping: SphericalMapping::EqualArea };
        for p in [ortho, equirect, equal_area] {
            let cam = Camera::pbrt(&Transform::IDENTITY, p, 32, 32).unwrap();
            assert!(!cam.has_importance(), "{p:?}");
            let r = cam.generate_ray(Vec2::new(16.5, 16.5), Vec2::splat(0.5));
            assert_eq!(cam.importance(r.origin, r.dir), None, "{p:?}");
            assert_eq!(cam.pdf_importance(r.dir), (0.0, 0.0), "{p:?}");
            assert_eq!(cam.pdf_importance_from(r.origin, r.dir), (0.0, 0.0), "{p:?}");
            assert_eq!(cam.sample_importance(r.at(3.0), Vec2::splat(0.5)), None, "{p:?}");
            assert_eq!(cam.forward(), Vec3::Z);
        }
    }
}
