//! pbrt-v4's cameras (PBRT 4th ed., ch. 5; pbrt-v4's `cameras.cpp`):
//! perspective, orthographic and spherical, from a camera-to-world
//! transform.
//!
//! # Camera space
//!
//! pbrt's camera space is left-handed: the camera sits at the origin and
//! looks down `+z`; `+y` is up on the image and `+x` is to the right on the
//! image. pbrt's current transformation matrix at the `Camera` directive is
//! world-to-camera; [`Camera::pbrt`] takes its inverse, camera-to-world,
//! and applies it to ray origins and directions (directions renormalised),
//! whatever it is: a mirror (the common `Scale -1 1 1`) or a scale included.
//!
//! # Screen window and raster
//!
//! The image is the *screen window* `[xmin, xmax] × [ymin, ymax]` of the
//! plane `z = 1` (perspective, after dividing by `tan(fov/2)`, see below)
//! or `z = 0` (orthographic, in camera-space units). Raster `(0, 0)` (the
//! top-left corner of the image) is `(xmin, ymax)` and `(width, height)` is
//! `(xmax, ymin)`: raster `y` runs downwards, screen `y` upwards. Its
//! default, from the frame aspect ratio `a` (`frameaspectratio`, by default
//! `width / height`), is `[−a, a] × [−1, 1]` when `a > 1`, else
//! `[−1, 1] × [−1/a, 1/a]`: the shorter side spans `[−1, 1]`.
//!
//! # Perspective
//!
//! The screen point `(x, y)` is the direction `(x tan(fov/2), y tan(fov/2),
//! 1)`: `fov` spans the screen window's `[−1, 1]`, the *shorter* image axis
//! by default. With a thin lens (radius `r`, focal distance `f`), a ray
//! starts at `r · concentric_disk(lens sample)` in the plane `z = 0` and
//! passes through the point where the pinhole ray meets the plane `z = f`
//! (Shirley–Chiu's concentric map, as pbrt's
//! `SampleUniformDiskConcentric`).
//!
//! # Orthographic
//!
//! The ray from raster point `p` starts at the screen point `(x, y, 0)` and
//! runs along `+z`; the lens is pbrt's (see
//! [`Camera::generate_ray`](super::Camera::generate_ray)).
//!
//! # Spherical
//!
//! Every pixel is a direction from the origin; the whole image covers the
//! sphere ([`SphericalMapping`]). pbrt-v4 ignores the screen window and the
//! lens for it, and so does lucent.

use super::{Camera, CameraError, Model, ThinLens};
use crate::geometry::{Transform, Vec2, Vec3};

/// How a spherical camera's image covers the sphere of directions
/// (pbrt-v4's `mapping`; see `Camera`'s `spherical_direction` for the
/// exact directions).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SphericalMapping {
    /// Latitude–longitude: the top row looks up (`+y`), `φ = 2π s` around
    /// it from `+x` through `+z` (pbrt's `"equirectangular"`).
    Equirectangular,
    /// The equal-area octahedral map (pbrt's `"equalarea"`, its default):
    /// a square image whose centre looks up (`+y`).
    #[default]
    EqualArea,
}

/// pbrt-v4's camera projections, with their parameters. `None` means
/// pbrt's default (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// `Camera "perspective"`.
    Perspective {
        /// `fov`: the field of view of the screen window's `[−1, 1]` (the
        /// shorter image axis by default), in degrees, strictly between 0
        /// and 180 (pbrt's default 90).
        fov_degrees: f32,
        /// `screenwindow`: `[xmin, xmax, ymin, ymax]`.
        screen_window: Option<[f32; 4]>,
        /// `frameaspectratio`: replaces `width / height` in the default
        /// screen window.
        frame_aspect_ratio: Option<f32>,
        /// `lensradius` and `focaldistance` (pbrt's default focal distance
        /// is [`ThinLens::PBRT_FOCAL_DISTANCE`]); `None` or radius 0: a
        /// pinhole.
        lens: Option<ThinLens>,
    },
    /// `Camera "orthographic"`: the screen window is in camera-space units.
    Orthographic {
        /// `screenwindow`: `[xmin, xmax, ymin, ymax]`.
        screen_window: Option<[f32; 4]>,
        /// `frameaspectratio`: replaces `width / height` in the default
        /// screen window.
        frame_aspect_ratio: Option<f32>,
        /// `lensradius` and `focaldistance`.
        lens: Option<ThinLens>,
    },
    /// `Camera "spherical"`.
    Spherical {
        /// `mapping` (pbrt's default: equal-area).
        mapping: SphericalMapping,
    },
}

/// The screen window: the one given, else pbrt's default for the frame
/// aspect ratio `frame` (or `width / height`).
fn screen_window(
    window: Option<[f32; 4]>,
    frame: Option<f32>,
    width: u32,
    height: u32,
) -> Result<[f32; 4], CameraError> {
    if let Some(w) = window {
        if !(w.iter().all(|v| v.is_finite()) && w[0] < w[1] && w[2] < w[3]) {
            return Err(CameraError::ScreenWindow(w));
        }
        return Ok(w);
    }
    let a = match frame {
        Some(a) if !(a > 0.0 && a.is_finite()) => return Err(CameraError::FrameAspectRatio(a)),
        Some(a) => a,
        None => width as f32 / height as f32,
    };
    Ok(if a > 1.0 { [-a, a, -1.0, 1.0] } else { [-1.0, 1.0, -1.0 / a, 1.0 / a] })
}

impl Camera {
    /// A pbrt-v4 camera: `camera_to_world` places pbrt's camera space (the
    /// inverse of the CTM at the `Camera` directive; see the module docs of
    /// `projection.rs` for the conventions), `projection` says how rays
    /// leave it, and the image is `width × height` pixels (row 0 at the
    /// top).
    ///
    /// ```
    /// use lucent::camera::{Camera, Projection};
    /// use lucent::geometry::{Transform, Vec2, Vec3};
    /// let p = Projection::Perspective { fov_degrees: 90.0, screen_window: None, frame_aspect_ratio: None, lens: None };
    /// let cam = Camera::pbrt(&Transform::IDENTITY, p, 200, 100).unwrap();
    /// // Looks down +z; the right edge of the image is at x/z = 2 (fov spans
    /// // the shorter, vertical, axis).
    /// let r = cam.generate_ray(Vec2::new(200.0, 50.0), Vec2::splat(0.5));
    /// assert!((r.dir.x / r.dir.z - 2.0).abs() < 1e-6);
    /// ```
    pub fn pbrt(
        camera_to_world: &Transform,
        projection: Projection,
        width: u32,
        height: u32,
    ) -> Result<Camera, CameraError> {
        if width == 0 || height == 0 {
            return Err(CameraError::EmptyImage);
        }
        let eye = camera_to_world.point(Vec3::ZERO);
        let u = camera_to_world.vector(Vec3::X);
        let v = camera_to_world.vector(Vec3::Y);
        let w = camera_to_world.vector(Vec3::Z);
        if !(eye.is_finite() && u.is_finite() && v.is_finite() && w.is_finite()) {
            return Err(CameraError::NonFinite);
        }
        let (model, window, lens) = match projection {
            Projection::Perspective { fov_degrees, screen_window: sw, frame_aspect_ratio, lens } => {
                if !fov_degrees.is_finite() {
                    return Err(CameraError::NonFinite);
                }
                if !(fov_degrees > 0.0 && fov_degrees < 180.0) {
                    return Err(CameraError::FieldOfView(fov_degrees));
                }
                let sw = screen_window(sw, frame_aspect_ratio, width, height)?;
                // The screen window at z = 1: scaled by tan(fov/2), in double
                // precision as in `Camera::new`.
                let t = ((fov_degrees as f64).to_radians() * 0.5).tan();
                let window = sw.map(|x| (x as f64 * t) as f32);
                (Model::Perspective, window, lens)
            }
            Projection::Orthographic { screen_window: sw, frame_aspect_ratio, lens } => {
                (Model::Orthographic, screen_window(sw, frame_aspect_ratio, width, height)?, lens)
            }
            Projection::Spherical { mapping } => {
                if mapping == SphericalMapping::EqualArea && width != height {
                    return Err(CameraError::NotSquare { width, height });
                }
                (Model::Spherical(mapping), [-1.0, 1.0, -1.0, 1.0], None)
            }
        };
        let lens = match lens {
            Some(l) => l.check()?,
            None => None,
        };
        let [x0, x1, y0, y1] = window;
        Ok(Camera {
            eye,
            u,
            v,
            w,
            half_width: 0.5 * (x1 - x0),
            half_height: 0.5 * (y1 - y0),
            centre: Vec2::new(0.5 * (x0 + x1), 0.5 * (y0 + y1)),
            width,
            height,
            lens,
            model,
        })
    }
}

impl Camera {
    /// This camera as pbrt-v4 parameters: its camera-to-world matrix (the
    /// columns are the camera's `x`, `y`, `z` axes and its origin, the eye)
    /// and a [`Projection`] from which [`Camera::pbrt`] makes this camera
    /// again, for the same image size. A perspective camera is described
    /// with `fov` 90°, whose screen window at unit distance is the window
    /// itself, so the screen window is given explicitly; what a scene file
    /// said (a classic horizontal `fov`, pbrt's shorter-axis `fov`) is not
    /// kept, only the camera it made. The result is exact up to the
    /// rounding of `centre ± half-extent`.
    ///
    /// ```
    /// use lucent::camera::Camera;
    /// use lucent::geometry::{Transform, Vec3};
    /// let cam = Camera::new(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y, 40.0, 64, 48).unwrap();
    /// let (m, projection) = cam.pbrt_parameters();
    /// let again = Camera::pbrt(&Transform::from_matrix(m).unwrap(), projection, 64, 48).unwrap();
    /// assert_eq!(again, cam);
    /// ```
    pub fn pbrt_parameters(&self) -> (crate::geometry::Mat4, Projection) {
        let m = crate::geometry::Mat4::from_cols(
            self.u.extend(0.0),
            self.v.extend(0.0),
            self.w.extend(0.0),
            self.eye.extend(1.0),
        );
        let c = self.centre;
        let window = [c.x - self.half_width, c.x + self.half_width, c.y - self.half_height, c.y + self.half_height];
        let projection = match self.model {
            Model::Perspective => Projection::Perspective {
                fov_degrees: 90.0,
                screen_window: Some(window),
                frame_aspect_ratio: None,
                lens: self.lens,
            },
            Model::Orthographic => {
                Projection::Orthographic { screen_window: Some(window), frame_aspect_ratio: None, lens: self.lens }
            }
            Model::Spherical(mapping) => Projection::Spherical { mapping },
        };
        (m, projection)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::equal_area::equal_area_sphere_to_square;

    fn perspective(fov: f32, window: Option<[f32; 4]>, lens: Option<ThinLens>) -> Projection {
        Projection::Perspective { fov_degrees: fov, screen_window: window, frame_aspect_ratio: None, lens }
    }

    fn ray(cam: &Camera, x: f32, y: f32) -> crate::geometry::Ray {
        cam.generate_ray(Vec2::new(x, y), Vec2::splat(0.5))
    }

    #[test]
    fn perspective_follows_pbrts_screen() {
        let cam = Camera::pbrt(&Transform::IDENTITY, perspective(90.0, None, None), 200, 100).unwrap();
        // The centre looks down +z, from the origin.
        let c = ray(&cam, 100.0, 50.0);
        assert_eq!(c.origin, Vec3::ZERO);
        assert!((c.dir - Vec3::Z).length() < 1e-7);
        // fov spans the shorter (vertical) axis: the top edge is at y/z = 1;
        // the right edge at x/z = aspect = 2.
        let top = ray(&cam, 100.0, 0.0).dir;
        assert!((top.y / top.z - 1.0).abs() < 1e-6 && top.x.abs() < 1e-7, "{top}");
        let right = ray(&cam, 200.0, 50.0).dir;
        assert!((right.x / right.z - 2.0).abs() < 1e-6 && right.y.abs() < 1e-7, "{right}");
        // +x on the image is camera +x, and raster y runs downwards.
        let corner = ray(&cam, 200.0, 100.0).dir;
        assert!((corner.x / corner.z - 2.0).abs() < 1e-6 && (corner.y / corner.z + 1.0).abs() < 1e-6);
        // A tall image: fov spans the width.
        let tall = Camera::pbrt(&Transform::IDENTITY, perspective(60.0, None, None), 50, 100).unwrap();
        let t = 30f32.to_radians().tan();
        let r = ray(&tall, 50.0, 50.0).dir;
        assert!((r.x / r.z - t).abs() < 1e-6);
        let b = ray(&tall, 25.0, 100.0).dir;
        assert!((b.y / b.z + 2.0 * t).abs() < 1e-6);
        // frameaspectratio replaces the image's.
        let p = Projection::Perspective {
            fov_degrees: 90.0,
            screen_window: None,
            frame_aspect_ratio: Some(0.5),
            lens: None,
        };
        let f = Camera::pbrt(&Transform::IDENTITY, p, 200, 100).unwrap();
        let r = ray(&f, 200.0, 0.0).dir;
        assert!((r.x / r.z - 1.0).abs() < 1e-6 && (r.y / r.z - 2.0).abs() < 1e-6, "{r}");
    }

    #[test]
    fn screen_window_crops() {
        // The upper-right quarter of the default window [-1,1]².
        let cam =
            Camera::pbrt(&Transform::IDENTITY, perspective(90.0, Some([0.0, 1.0, 0.0, 1.0]), None), 64, 64).unwrap();
        let tl = ray(&cam, 0.0, 0.0).dir;
        assert!(tl.x.abs() < 1e-7 && (tl.y / tl.z - 1.0).abs() < 1e-6, "{tl}");
        let br = ray(&cam, 64.0, 64.0).dir;
        assert!((br.x / br.z - 1.0).abs() < 1e-6 && br.y.abs() < 1e-7, "{br}");
        let mid = ray(&cam, 32.0, 32.0).dir;
        assert!((mid.x / mid.z - 0.5).abs() < 1e-6 && (mid.y / mid.z - 0.5).abs() < 1e-6);
    }

    #[test]
    fn the_transform_places_the_camera() {
        // A mirror (pbrt scenes' `Scale -1 1 1`) then a turn and a move.
        let t = Transform::scale(Vec3::new(-1.0, 1.0, 1.0))
            .unwrap()
            .then(&Transform::rotate_y(90.0))
            .then(&Transform::translate(Vec3::new(1.0, 2.0, 3.0)));
        let cam = Camera::pbrt(&t, perspective(90.0, None, None), 100, 100).unwrap();
        let c = ray(&cam, 50.0, 50.0);
        assert!((c.origin - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        // Camera +z turned 90° about y is +x.
        assert!((c.dir - Vec3::X).length() < 1e-6, "{}", c.dir);
        // Image right: camera +x mirrored to −x, turned to +z.
        let r = ray(&cam, 100.0, 50.0).dir;
        assert!((r - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6, "{r}");
        let (u, v, w) = cam.basis();
        assert!((u - Vec3::Z).length() < 1e-6 && (v - Vec3::Y).length() < 1e-6 && (w - Vec3::X).length() < 1e-6);
    }

    #[test]
    fn thin_lens_focuses_on_the_plane_z_f() {
        let lens = ThinLens { radius: 0.5, focal_distance: 7.0 };
        let cam = Camera::pbrt(&Transform::IDENTITY, perspective(50.0, None, Some(lens)), 80, 60).unwrap();
        let film = Vec2::new(13.5, 47.25);
        let pin = cam.image_plane_direction(film) * 7.0;
        for u in [Vec2::new(0.1, 0.9), Vec2::new(0.7, 0.2), Vec2::new(0.5, 0.5)] {
            let r = cam.generate_ray(film, u);
            assert!(r.origin.z == 0.0 && r.origin.length() <= 0.5 + 1e-6);
            let t = (7.0 - r.origin.z) / r.dir.z;
            assert!((r.at(t) - pin).length() < 1e-4);
        }
        // Radius 0 is a pinhole.
        let pinhole = ThinLens { radius: 0.0, focal_distance: ThinLens::PBRT_FOCAL_DISTANCE };
        let cam = Camera::pbrt(&Transform::IDENTITY, perspective(50.0, None, Some(pinhole)), 8, 6).unwrap();
        assert_eq!(cam.lens(), None);
    }

    #[test]
    fn orthographic_rays_are_parallel_from_the_window() {
        let p = Projection::Orthographic { screen_window: None, frame_aspect_ratio: None, lens: None };
        let cam = Camera::pbrt(&Transform::translate(Vec3::new(0.0, 0.0, -5.0)), p, 200, 100).unwrap();
        // Default window [-2, 2] × [-1, 1] in camera units.
        let r = ray(&cam, 150.0, 25.0);
        assert!((r.origin - Vec3::new(1.0, 0.5, -5.0)).length() < 1e-6, "{}", r.origin);
        assert_eq!(r.dir, Vec3::Z);
        let r = ray(&cam, 0.0, 100.0);
        assert!((r.origin - Vec3::new(-2.0, -1.0, -5.0)).length() < 1e-6);
        // With a window and a lens: pbrt's rays start on the lens around the
        // eye and pass through the focus point of the lens-less ray.
        let lens = ThinLens { radius: 0.25, focal_distance: 4.0 };
        let p = Projection::Orthographic {
            screen_window: Some([0.0, 4.0, 0.0, 2.0]),
            frame_aspect_ratio: None,
            lens: Some(lens),
        };
        let cam = Camera::pbrt(&Transform::IDENTITY, p, 40, 20).unwrap();
        let r = cam.generate_ray(Vec2::new(10.0, 5.0), Vec2::new(0.3, 0.8));
        assert!(r.origin.z == 0.0 && r.origin.length() <= 0.25 + 1e-6);
        let t = 4.0 / r.dir.z;
        assert!((r.at(t) - Vec3::new(1.0, 1.5, 4.0)).length() < 1e-5, "{}", r.at(t));
    }

    #[test]
    fn spherical_equirectangular_follows_pbrt() {
        let p = Projection::Spherical { mapping: SphericalMapping::Equirectangular };
        let cam = Camera::pbrt(&Transform::IDENTITY, p, 360, 180).unwrap();
        // Centre pixel: θ = π/2, φ = π: camera −x (pbrt's SphericalDirection
        // with y and z swapped).
        let c = ray(&cam, 180.0, 90.0);
        assert_eq!(c.origin, Vec3::ZERO);
        assert!((c.dir + Vec3::X).length() < 1e-6, "{}", c.dir);
        // The top row looks up, the bottom row down.
        for x in [0.0, 45.0, 300.0] {
            assert!((ray(&cam, x, 0.0).dir - Vec3::Y).length() < 1e-6);
            assert!((ray(&cam, x, 180.0).dir + Vec3::Y).length() < 1e-6);
        }
        // On the horizon: s = 0 is +x, s = 1/4 is +z (forward), s = 3/4 is −z.
        assert!((ray(&cam, 0.0, 90.0).dir - Vec3::X).length() < 1e-6);
        assert!((ray(&cam, 90.0, 90.0).dir - Vec3::Z).length() < 1e-6);
        assert!((ray(&cam, 270.0, 90.0).dir + Vec3::Z).length() < 1e-6);
        // Above the horizon in the upper half.
        assert!(ray(&cam, 10.0, 30.0).dir.y > 0.5);
    }

    #[test]
    fn spherical_equal_area_covers_the_sphere() {
        let p = Projection::Spherical { mapping: SphericalMapping::EqualArea };
        assert_eq!(
            Camera::pbrt(&Transform::IDENTITY, p, 20, 10),
            Err(CameraError::NotSquare { width: 20, height: 10 })
        );
        let cam = Camera::pbrt(&Transform::rotate_z(90.0), p, 64, 64).unwrap();
        // The centre looks along camera +y, turned 90° about z to −x.
        assert!((ray(&cam, 32.0, 32.0).dir + Vec3::X).length() < 1e-6);
        let id = Camera::pbrt(&Transform::IDENTITY, p, 64, 64).unwrap();
        assert!((ray(&id, 32.0, 32.0).dir - Vec3::Y).length() < 1e-6);
        assert!((ray(&id, 0.0, 0.0).dir + Vec3::Y).length() < 1e-6);
        assert!((ray(&id, 64.0, 32.0).dir - Vec3::X).length() < 1e-6);
        assert!((ray(&id, 32.0, 64.0).dir - Vec3::Z).length() < 1e-6);
        // Every pixel centre's direction maps back to that pixel.
        for j in 0..64 {
            for i in 0..64 {
                let d = ray(&id, i as f32 + 0.5, j as f32 + 0.5).dir;
                let st = equal_area_sphere_to_square(Vec3::new(d.x, d.z, d.y)) * 64.0;
                assert_eq!((st.x as u32, st.y as u32), (i, j));
            }
        }
    }

    #[test]
    fn bad_parameters_are_refused() {
        let id = Transform::IDENTITY;
        assert_eq!(Camera::pbrt(&id, perspective(180.0, None, None), 4, 4), Err(CameraError::FieldOfView(180.0)));
        assert_eq!(Camera::pbrt(&id, perspective(f32::NAN, None, None), 4, 4), Err(CameraError::NonFinite));
        assert_eq!(Camera::pbrt(&id, perspective(60.0, None, None), 0, 4), Err(CameraError::EmptyImage));
        let w = [1.0, -1.0, -1.0, 1.0];
        assert_eq!(Camera::pbrt(&id, perspective(60.0, Some(w), None), 4, 4), Err(CameraError::ScreenWindow(w)));
        let lens = ThinLens { radius: 1.0, focal_distance: 0.0 };
        assert!(matches!(
            Camera::pbrt(&id, perspective(60.0, None, Some(lens)), 4, 4),
            Err(CameraError::BadLens { .. })
        ));
        let p = Projection::Orthographic { screen_window: None, frame_aspect_ratio: Some(-1.0), lens: None };
        assert_eq!(Camera::pbrt(&id, p, 4, 4), Err(CameraError::FrameAspectRatio(-1.0)));
    }
}
