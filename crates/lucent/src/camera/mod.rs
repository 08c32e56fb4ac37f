//! Cameras: perspective (a pinhole, or a thin lens for depth of field),
//! orthographic and spherical.
//!
//! [`Camera::new`] makes lucent's own look-at perspective camera;
//! [`Camera::pbrt`] makes pbrt-v4's cameras from a camera-to-world transform
//! and a [`Projection`] (see `projection.rs` for pbrt's conventions).

mod importance;
mod lanes;
mod projection;

pub use importance::ImportanceSample;
pub use projection::{Projection, SphericalMapping};

use crate::geometry::{Ray, Vec2, Vec3};
use crate::light::equal_area::{equal_area_square_to_sphere, wrap_equal_area_square};
use crate::sampling::concentric_disk;
use std::f32::consts::PI;

/// Why camera parameters are unusable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// The field of view must lie strictly between 0 and 180 degrees.
    #[error("field of view must be strictly between 0 and 180 degrees, got {0}")]
    FieldOfView(f32),
    /// Eye and look-at point coincide.
    #[error("eye and look_at are the same point: the view direction is undefined")]
    NoViewDirection,
    /// The up vector is zero or parallel to the view direction.
    #[error("up vector is zero or parallel to the view direction")]
    BadUp,
    /// Width or height is zero.
    #[error("image width and height must be at least 1")]
    EmptyImage,
    /// Lens radius negative, or focal distance not positive.
    #[error("lens radius must be ≥ 0 and focal distance > 0 (got radius {radius}, focal distance {focal_distance})")]
    BadLens {
        /// Lens radius given.
        radius: f32,
        /// Focal distance given.
        focal_distance: f32,
    },
    /// A coordinate is NaN or infinite.
    #[error("camera parameters must be finite numbers")]
    NonFinite,
    /// A screen window that is not finite or has no extent.
    #[error("screen window must be four finite numbers [xmin, xmax, ymin, ymax] with xmin < xmax and ymin < ymax, got {0:?}")]
    ScreenWindow([f32; 4]),
    /// A frame aspect ratio that is not a finite positive number.
    #[error("frame aspect ratio must be a finite number > 0, got {0}")]
    FrameAspectRatio(f32),
    /// The equal-area spherical mapping needs a square image.
    #[error("a spherical camera with the equal-area mapping needs a square image, got {width}×{height} (use the equirectangular mapping for other shapes)")]
    NotSquare {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
    },
}

/// A thin lens: rays leave from a disk around the eye and converge on the
/// plane of focus.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    /// Radius of the lens disk (world units; camera-space units for
    /// [`Camera::pbrt`]).
    pub radius: f32,
    /// Distance from the eye to the plane of focus, along the view axis.
    pub focal_distance: f32,
}

impl ThinLens {
    /// pbrt-v4's default `focaldistance` for perspective and orthographic
    /// cameras.
    pub const PBRT_FOCAL_DISTANCE: f32 = 1e6;

    fn check(self) -> Result<Option<ThinLens>, CameraError> {
        let ThinLens { radius, focal_distance } = self;
        if !(radius >= 0.0 && radius.is_finite() && focal_distance > 0.0 && focal_distance.is_finite()) {
            return Err(CameraError::BadLens { radius, focal_distance });
        }
        Ok((radius > 0.0).then_some(self))
    }
}

/// How film positions become rays.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Model {
    /// Rays from the eye (or the lens) through the screen window at unit
    /// distance along `w`.
    Perspective,
    /// Parallel rays along `w` from the screen window in the plane of the
    /// eye.
    Orthographic,
    /// Rays from the eye in every direction.
    Spherical(SphericalMapping),
}

/// A camera: where rays start and where they go for each film position.
///
/// [`Camera::new`] makes a perspective camera looking from `eye` at
/// `look_at`. The camera basis is `w` (unit view direction), `u = w × up`
/// (right) and `v = u × w` (up on the image). The image plane sits at
/// distance 1 along `w`; it spans `tan(fov/2)` either side horizontally and
/// `tan(fov/2) · height/width` vertically, so pixels are square.
///
/// [`Camera::pbrt`] makes pbrt-v4's perspective, orthographic and spherical
/// cameras; there `(u, v, w)` and `eye` are the camera-to-world images of
/// the camera-space axes and origin.
///
/// ```
/// use lucent::camera::Camera;
/// use lucent::geometry::{Vec2, Vec3};
/// let cam = Camera::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 20.0), Vec3::Y, 90.0, 64, 48).unwrap();
/// // The ray through the image centre points at the look-at point.
/// let ray = cam.generate_ray(Vec2::new(32.0, 24.0), Vec2::splat(0.5));
/// assert!((ray.dir.normalize() - Vec3::Z).length() < 1e-6);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    eye: Vec3,
    u: Vec3,
    v: Vec3,
    w: Vec3,
    /// Half the extent of the screen window along `u` and `v` (at unit
    /// distance for a perspective camera).
    half_width: f32,
    half_height: f32,
    /// The centre of the screen window (zero for [`Camera::new`]).
    centre: Vec2,
    width: u32,
    height: u32,
    lens: Option<ThinLens>,
    model: Model,
}

impl Camera {
    /// A pinhole camera. `fov` is the horizontal field of view in degrees.
    pub fn new(eye: Vec3, look_at: Vec3, up: Vec3, fov: f32, width: u32, height: u32) -> Result<Self, CameraError> {
        if !(eye.is_finite() && look_at.is_finite() && up.is_finite() && fov.is_finite()) {
            return Err(CameraError::NonFinite);
        }
        if !(fov > 0.0 && fov < 180.0) {
            return Err(CameraError::FieldOfView(fov));
        }
        if width == 0 || height == 0 {
            return Err(CameraError::EmptyImage);
        }
        let view = look_at - eye;
        if view.length_squared() == 0.0 {
            return Err(CameraError::NoViewDirection);
        }
        let w = view.normalize();
        let right = w.cross(up);
        if right.length_squared() <= 1e-12 * up.length_squared() || up.length_squared() == 0.0 {
            return Err(CameraError::BadUp);
        }
        let u = right.normalize();
        let v = u.cross(w);
        // tan is computed in double precision: near 180° its argument is
        // close to π/2, where single precision loses digits.
        let half_width = ((fov as f64).to_radians() * 0.5).tan() as f32;
        let half_height = half_width * height as f32 / width as f32;
        Ok(Self {
            eye,
            u,
            v,
            w,
            half_width,
            half_height,
            centre: Vec2::ZERO,
            width,
            height,
            lens: None,
            model: Model::Perspective,
        })
    }

    /// Turn this into a thin-lens camera (a lens of radius 0 is a pinhole).
    /// A spherical camera has no lens: it stays as it is.
    pub fn with_lens(mut self, lens: ThinLens) -> Result<Self, CameraError> {
        let lens = lens.check()?;
        if !matches!(self.model, Model::Spherical(_)) {
            self.lens = lens;
        }
        Ok(self)
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The eye position (centre of the lens).
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// The camera basis `(u, v, w)`: right, up (on the image), forward.
    /// Unit and right-handed for [`Camera::new`]; for [`Camera::pbrt`], the
    /// camera-to-world images of camera space's `+x`, `+y`, `+z` (unit for a
    /// rigid transform, and left-handed unless the transform mirrors).
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        (self.u, self.v, self.w)
    }

    /// The thin lens, if any.
    pub fn lens(&self) -> Option<ThinLens> {
        self.lens
    }

    /// The point of the screen window at film position `film` (pixels), in
    /// the camera's `(u, v)` coordinates: the left edge of the image is the
    /// window's `xmin`, the top edge its `ymax`.
    #[inline]
    fn screen(&self, film: Vec2) -> Vec2 {
        let (x, y) = self.screen_xy(film.x, film.y);
        Vec2::new(x, y)
    }

    /// [`Camera::screen`] of the film position `(x, y)`, as two numbers
    /// (also the lanes' definition, `lanes.rs`).
    #[inline(always)]
    fn screen_xy(&self, x: f32, y: f32) -> (f32, f32) {
        let sx = (2.0 * x / self.width as f32 - 1.0) * self.half_width + self.centre.x;
        let sy = (1.0 - 2.0 * y / self.height as f32) * self.half_height + self.centre.y;
        (sx, sy)
    }

    /// The direction, relative to the eye, of the image-plane point at film
    /// position `film` (in pixels: `(0, 0)` is the top-left corner of the
    /// image, `(width, height)` the bottom-right). Its `w` component is 1.
    /// (The pinhole ray's direction for a perspective camera; for the other
    /// projections, the same screen-window point seen from the eye.)
    #[inline]
    pub fn image_plane_direction(&self, film: Vec2) -> Vec3 {
        let s = self.screen(film);
        self.w + s.x * self.u + s.y * self.v
    }

    /// The unit direction, in camera space `(u, v, w)` coordinates, of a
    /// spherical camera's ray at film position `film`, following pbrt-v4's
    /// `SphericalCamera`: `(s, t) = film / (width, height)`, a direction
    /// `d` of the sphere in a z-up frame, then `y` and `z` swapped so that
    /// the mapping's zenith is camera `+y` (up on the image).
    ///
    /// * Equirectangular: `θ = π t`, `φ = 2π s`,
    ///   `d = (sin θ cos φ, sin θ sin φ, cos θ)`; so the top row looks
    ///   along `+y`, the bottom row along `−y`, the middle row is the
    ///   horizon with `s = 0` (the left edge) towards `+x`, `s = ¼`
    ///   towards `+z` (forward), `s = ½` (the centre) towards `−x` and
    ///   `s = ¾` towards `−z`.
    /// * Equal-area: `d` = [`equal_area_square_to_sphere`] of `(s, t)`
    ///   (folded back into the square by [`wrap_equal_area_square`]): the
    ///   image centre looks along `+y`, the corners along `−y`, the middle
    ///   of the right edge along `+x` and of the bottom edge along `+z`.
    #[inline]
    fn spherical_direction(&self, mapping: SphericalMapping, film: Vec2) -> Vec3 {
        let st = Vec2::new(film.x / self.width as f32, film.y / self.height as f32);
        let d = match mapping {
            SphericalMapping::Equirectangular => {
                let (sin_t, cos_t) = (PI * st.y).sin_cos();
                let (sin_p, cos_p) = (2.0 * PI * st.x).sin_cos();
                Vec3::new(sin_t * cos_p, sin_t * sin_p, cos_t)
            }
            SphericalMapping::EqualArea => equal_area_square_to_sphere(wrap_equal_area_square(st)),
        };
        Vec3::new(d.x, d.z, d.y)
    }

    /// The primary ray through film position `film` (pixels), using
    /// `lens_sample ∈ [0,1)²` on the lens when there is one. The direction is
    /// unit length.
    ///
    /// With a thin lens the ray starts at a point uniformly distributed over
    /// the lens disk (in the camera's own `u`, `v` plane) and passes through
    /// the point where the pinhole ray meets the plane of focus, so every
    /// lens sample of a point on that plane reaches the same pixel.
    ///
    /// An orthographic camera's rays start on the screen window in the
    /// plane of the eye and run along `w`; with a lens, pbrt-v4's
    /// `OrthographicCamera` is followed exactly: the ray starts at the lens
    /// point *around the eye* (not around the window point) and passes
    /// through the point where the lens-less ray meets the plane of focus.
    /// A spherical camera's rays all start at the eye
    /// ([`Camera::pbrt`] documents the directions).
    #[inline]
    pub fn generate_ray(&self, film: Vec2, lens_sample: Vec2) -> Ray {
        match self.model {
            Model::Perspective => {
                let dir = self.image_plane_direction(film);
                match self.lens {
                    None => Ray::new(self.eye, dir.normalize()),
                    Some(lens) => {
                        let d = lens.radius * concentric_disk(lens_sample);
                        let origin = self.eye + d.x * self.u + d.y * self.v;
                        // `dir` has unit w-component: scaling it by the focal
                        // distance lands on the plane of focus.
                        let focus = self.eye + lens.focal_distance * dir;
                        Ray::new(origin, (focus - origin).normalize())
                    }
                }
            }
            Model::Orthographic => {
                let s = self.screen(film);
                let start = self.eye + s.x * self.u + s.y * self.v;
                match self.lens {
                    None => Ray::new(start, self.w.normalize()),
                    Some(lens) => {
                        let d = lens.radius * concentric_disk(lens_sample);
                        let origin = self.eye + d.x * self.u + d.y * self.v;
                        let focus = start + lens.focal_distance * self.w;
                        Ray::new(origin, (focus - origin).normalize())
                    }
                }
            }
            Model::Spherical(mapping) => {
                let d = self.spherical_direction(mapping, film);
                Ray::new(self.eye, (d.x * self.u + d.y * self.v + d.z * self.w).normalize())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_hits_the_look_at_point() {
        let look = Vec3::new(3.0, -2.0, 17.0);
        let cam = Camera::new(Vec3::new(1.0, 1.0, 1.0), look, Vec3::Y, 60.0, 200, 100).unwrap();
        let r = cam.generate_ray(Vec2::new(100.0, 50.0), Vec2::splat(0.5));
        let t = (look - r.origin).length();
        assert!((r.at(t) - look).length() < 1e-4);
    }

    #[test]
    fn corners_follow_the_field_of_view() {
        let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 90.0, 100, 50).unwrap();
        let right = cam.image_plane_direction(Vec2::new(100.0, 25.0));
        assert!((right - Vec3::new(-1.0, 0.0, 1.0)).length() < 1e-6, "u = w × up points to -x here: {right}");
        let top = cam.image_plane_direction(Vec2::new(50.0, 0.0));
        assert!((top - Vec3::new(0.0, 0.5, 1.0)).length() < 1e-6);
    }

    #[test]
    fn wide_angles_stay_finite() {
        for fov in [166.0, 175.0, 179.9] {
            let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, fov, 64, 48).unwrap();
            for film in [Vec2::ZERO, Vec2::new(64.0, 48.0), Vec2::new(32.0, 24.0)] {
                let r = cam.generate_ray(film, Vec2::splat(0.5));
                assert!(r.dir.is_finite() && (r.dir.length() - 1.0).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn invalid_parameters_are_refused() {
        let e = |fov| Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, fov, 10, 10);
        assert_eq!(e(0.0), Err(CameraError::FieldOfView(0.0)));
        assert_eq!(e(180.0), Err(CameraError::FieldOfView(180.0)));
        assert_eq!(e(-5.0), Err(CameraError::FieldOfView(-5.0)));
        assert_eq!(Camera::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 60.0, 1, 1), Err(CameraError::NoViewDirection));
        assert_eq!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, 60.0, 1, 1), Err(CameraError::BadUp));
        assert_eq!(Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 0, 1), Err(CameraError::EmptyImage));
    }

    #[test]
    fn every_lens_sample_of_a_focal_plane_point_reaches_the_same_pixel() {
        let cam = Camera::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 80.0), Vec3::Y, 40.0, 160, 120)
            .unwrap()
            .with_lens(ThinLens { radius: 2.0, focal_distance: 80.0 })
            .unwrap();
        let film = Vec2::new(37.25, 91.5);
        let pinhole = cam.image_plane_direction(film);
        let target = 80.0 * pinhole; // on the plane of focus (w-component 80)
        for i in 0..8 {
            for j in 0..8 {
                let s = Vec2::new((i as f32 + 0.5) / 8.0, (j as f32 + 0.5) / 8.0);
                let r = cam.generate_ray(film, s);
                // Where the ray crosses the focal plane w = 80:
                let t = (80.0 - r.origin.z) / r.dir.z;
                assert!((r.at(t) - target).length() < 1e-3, "lens sample {s} missed the focus point");
                // and it started on the lens disk, in the u/v plane.
                assert!(r.origin.z.abs() < 1e-6 && r.origin.length() <= 2.0 + 1e-5);
            }
        }
    }
}
