//! The perspective camera: a pinhole, or a thin lens for depth of field.

use crate::geometry::{Ray, Vec2, Vec3};
use crate::sampling::concentric_disk;

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
}

/// A thin lens: rays leave from a disk around the eye and converge on the
/// plane of focus.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    /// Radius of the lens disk (world units).
    pub radius: f32,
    /// Distance from the eye to the plane of focus, along the view axis.
    pub focal_distance: f32,
}

/// A perspective camera looking from `eye` at `look_at`.
///
/// The camera basis is `w` (unit view direction), `u = w × up` (right) and
/// `v = u × w` (up on the image). The image plane sits at distance 1 along
/// `w`; it spans `tan(fov/2)` either side horizontally and
/// `tan(fov/2) · height/width` vertically, so pixels are square.
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
    half_width: f32,
    half_height: f32,
    width: u32,
    height: u32,
    lens: Option<ThinLens>,
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
        Ok(Self { eye, u, v, w, half_width, half_height, width, height, lens: None })
    }

    /// Turn this into a thin-lens camera.
    pub fn with_lens(mut self, lens: ThinLens) -> Result<Self, CameraError> {
        let ThinLens { radius, focal_distance } = lens;
        if !(radius >= 0.0 && radius.is_finite() && focal_distance > 0.0 && focal_distance.is_finite()) {
            return Err(CameraError::BadLens { radius, focal_distance });
        }
        self.lens = (radius > 0.0).then_some(lens);
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

    /// The camera basis `(u, v, w)`: right, up, forward.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        (self.u, self.v, self.w)
    }

    /// The thin lens, if any.
    pub fn lens(&self) -> Option<ThinLens> {
        self.lens
    }

    /// The direction, relative to the eye, of the image-plane point at film
    /// position `film` (in pixels: `(0, 0)` is the top-left corner of the
    /// image, `(width, height)` the bottom-right). Its `w` component is 1.
    #[inline]
    pub fn image_plane_direction(&self, film: Vec2) -> Vec3 {
        let x = (2.0 * film.x / self.width as f32 - 1.0) * self.half_width;
        let y = (1.0 - 2.0 * film.y / self.height as f32) * self.half_height;
        self.w + x * self.u + y * self.v
    }

    /// The primary ray through film position `film` (pixels), using
    /// `lens_sample ∈ [0,1)²` on the lens when there is one. The direction is
    /// unit length.
    ///
    /// With a thin lens the ray starts at a point uniformly distributed over
    /// the lens disk (in the camera's own `u`, `v` plane) and passes through
    /// the point where the pinhole ray meets the plane of focus, so every
    /// lens sample of a point on that plane reaches the same pixel.
    #[inline]
    pub fn generate_ray(&self, film: Vec2, lens_sample: Vec2) -> Ray {
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
