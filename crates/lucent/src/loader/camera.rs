//! The `[camera]` table: lucent's classic camera, or one of pbrt-v4's
//! camera models when `projection` is given.

use super::description::*;
use super::locate::*;
use super::values::*;
use super::SceneFile;
use crate::camera::{Camera, CameraError, Projection, SphericalMapping, ThinLens};
use crate::geometry::{Mat4, Transform, Vec3};
use crate::scene::SceneError;

impl SceneFile {
    /// The camera of a `width × height` image.
    pub(super) fn camera(&self, width: u32, height: u32) -> Result<Camera, SceneError> {
        let c = &self.description.camera;
        let key = |k: &str| find_key(&self.source, k, 0).or_else(|| find_header(&self.source, "camera"));
        let Some(projection) = c.projection else {
            let pbrt_only = [
                ("transform", !c.transform.is_empty()),
                ("screen_window", c.screen_window.is_some()),
                ("frame_aspect_ratio", c.frame_aspect_ratio.is_some()),
                ("mapping", c.mapping.is_some()),
            ];
            if let Some((k, _)) = pbrt_only.iter().find(|(_, given)| *given) {
                return Err(self.error(
                    key(k),
                    format!("[camera]: `{k}` needs `projection` (\"perspective\", \"orthographic\" or \"spherical\")"),
                ));
            }
            return self.classic_camera(c, width, height);
        };

        let to_world = match (c.transform.is_empty(), c.eye, c.look_at) {
            (false, None, None) => self.transform(&c.transform, "[camera]", key("transform"))?,
            (false, _, _) => {
                return Err(self.error(key("transform"), "[camera]: give `transform` or `eye` and `look_at`, not both"))
            }
            (true, Some(eye), Some(look_at)) => {
                // The classic camera's basis: x to the right, y up on the
                // image, z along the view.
                let basis = Camera::new(eye.into(), look_at.into(), c.up.into(), 90.0, width, height)
                    .map_err(|e| self.camera_error(e))?;
                let (u, v, w) = basis.basis();
                let eye = Vec3::from(eye);
                let m = Mat4::from_cols(u.extend(0.0), v.extend(0.0), w.extend(0.0), eye.extend(1.0));
                Transform::from_matrix(m).map_err(|e| self.error(key("up"), format!("[camera]: {e}")))?
            }
            (true, _, _) => {
                return Err(self.error(
                    key("projection"),
                    "[camera]: place the camera with a camera-to-world `transform`, or with `eye` and `look_at`",
                ))
            }
        };
        if c.focal_distance.is_some() && c.lens_radius.is_none() {
            return Err(self.error(
                key("focal_distance"),
                "focal_distance needs lens_radius (a pinhole camera has everything in focus)",
            ));
        }
        let lens = c.lens_radius.map(|r| ThinLens {
            radius: r.get(),
            focal_distance: c.focal_distance.map_or(ThinLens::PBRT_FOCAL_DISTANCE, Positive::get),
        });
        let window = c.screen_window.map(|w| w.map(Finite::get));
        let frame = c.frame_aspect_ratio.map(Positive::get);
        let not_for = |k: &str, given: bool, model: &str| -> Result<(), SceneError> {
            if given {
                return Err(self.error(key(k), format!("[camera]: `{k}` does not apply to a {model} camera")));
            }
            Ok(())
        };
        let projection = match projection {
            ProjectionDesc::Perspective => {
                not_for("mapping", c.mapping.is_some(), "perspective")?;
                Projection::Perspective {
                    fov_degrees: c.fov.map_or(90.0, FieldOfView::get),
                    screen_window: window,
                    frame_aspect_ratio: frame,
                    lens,
                }
            }
            ProjectionDesc::Orthographic => {
                not_for("fov", c.fov.is_some(), "orthographic")?;
                not_for("mapping", c.mapping.is_some(), "orthographic")?;
                Projection::Orthographic { screen_window: window, frame_aspect_ratio: frame, lens }
            }
            ProjectionDesc::Spherical => {
                for (k, given) in [
                    ("fov", c.fov.is_some()),
                    ("lens_radius", lens.is_some()),
                    ("screen_window", window.is_some()),
                    ("frame_aspect_ratio", frame.is_some()),
                ] {
                    not_for(k, given, "spherical")?;
                }
                Projection::Spherical {
                    mapping: match c.mapping {
                        None | Some(SphericalMappingDesc::EqualArea) => SphericalMapping::EqualArea,
                        Some(SphericalMappingDesc::Equirectangular) => SphericalMapping::Equirectangular,
                    },
                }
            }
        };
        Camera::pbrt(&to_world, projection, width, height).map_err(|e| self.camera_error(e))
    }

    fn classic_camera(&self, c: &CameraDesc, width: u32, height: u32) -> Result<Camera, SceneError> {
        let (Some(eye), Some(look_at)) = (c.eye, c.look_at) else {
            let missing = if c.eye.is_none() { "eye" } else { "look_at" };
            return Err(self.error(
                find_header(&self.source, "camera"),
                format!("[camera]: `{missing}` is missing (the camera needs `eye` and `look_at`)"),
            ));
        };
        let fov = c.fov.map_or(60.0, FieldOfView::get);
        let mut camera = Camera::new(eye.into(), look_at.into(), c.up.into(), fov, width, height)
            .map_err(|e| self.camera_error(e))?;
        if let Some(radius) = c.lens_radius {
            let focal_distance =
                c.focal_distance.map_or_else(|| (Vec3::from(look_at) - Vec3::from(eye)).length(), |f| f.get());
            camera = camera
                .with_lens(ThinLens { radius: radius.get(), focal_distance })
                .map_err(|e| self.error(find_key(&self.source, "lens_radius", 0), e.to_string()))?;
        } else if c.focal_distance.is_some() {
            return Err(self.error(
                find_key(&self.source, "focal_distance", 0),
                "focal_distance needs lens_radius (a pinhole camera has everything in focus)",
            ));
        }
        Ok(camera)
    }

    /// A camera error, located at the key it is about.
    fn camera_error(&self, e: CameraError) -> SceneError {
        let key = match e {
            CameraError::NoViewDirection => find_key(&self.source, "look_at", 0),
            CameraError::BadUp => find_key(&self.source, "up", 0).or_else(|| find_key(&self.source, "look_at", 0)),
            CameraError::ScreenWindow(_) => find_key(&self.source, "screen_window", 0),
            CameraError::FrameAspectRatio(_) => find_key(&self.source, "frame_aspect_ratio", 0),
            CameraError::FieldOfView(_) => find_key(&self.source, "fov", 0),
            _ => None,
        };
        self.error(key.or_else(|| find_header(&self.source, "camera")), format!("[camera]: {e}"))
    }
}
