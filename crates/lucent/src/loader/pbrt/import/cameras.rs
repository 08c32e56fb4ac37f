//! `Camera`: pbrt-v4's perspective, orthographic and spherical cameras
//! ([`Camera::pbrt`]).
//!
//! pbrt's camera space is left-handed: the camera looks down `+z`, `+x` is
//! to the right of the image and `+y` up. The camera-to-world transform is
//! the inverse of the CTM at the `Camera` directive.

use super::spectra::param_loc;
use super::Importer;
use crate::camera::{Camera, Projection, SphericalMapping, ThinLens};
use crate::geometry::Transform;
use crate::loader::pbrt::{Loc, ParamList, PbrtError};

/// The camera of a `Camera` directive for a `width × height` image.
pub(crate) fn camera(
    importer: &mut Importer,
    ty: &str,
    params: &ParamList,
    camera_from_world: Transform,
    at: &Loc,
    width: u32,
    height: u32,
) -> Result<Camera, PbrtError> {
    let screen_window = match params.floats("screenwindow")? {
        None => None,
        Some(w) if w.len() == 4 => Some([w[0], w[1], w[2], w[3]]),
        Some(w) => {
            return Err(PbrtError::at(
                &param_loc(params, "screenwindow", at),
                format!("\"float screenwindow\" needs 4 values (xmin xmax ymin ymax), got {}", w.len()),
            ))
        }
    };
    let frame_aspect_ratio = params.float("frameaspectratio")?;
    let lens = {
        let radius = params.float("lensradius")?.unwrap_or(0.0);
        let focal_distance = params.float("focaldistance")?.unwrap_or(ThinLens::PBRT_FOCAL_DISTANCE);
        (radius != 0.0).then_some(ThinLens { radius, focal_distance })
    };
    for shutter in ["shutteropen", "shutterclose"] {
        let _ = params.get(shutter);
    }
    let projection = match ty {
        "perspective" => Projection::Perspective {
            fov_degrees: params.float("fov")?.unwrap_or(90.0),
            screen_window,
            frame_aspect_ratio,
            lens,
        },
        "orthographic" => Projection::Orthographic { screen_window, frame_aspect_ratio, lens },
        "spherical" => {
            let mapping = match params.string("mapping")?.unwrap_or("equalarea") {
                "equalarea" => SphericalMapping::EqualArea,
                "equirectangular" => SphericalMapping::Equirectangular,
                other => {
                    return Err(PbrtError::at(
                        &param_loc(params, "mapping", at),
                        format!("unknown spherical mapping \"{other}\" (accepted: equalarea, equirectangular)"),
                    ))
                }
            };
            Projection::Spherical { mapping }
        }
        other => {
            importer.warnings.warn(
                at,
                format!("Camera \"{other}\" is not supported: a perspective camera of the same fov is used (accepted: perspective, orthographic, spherical)"),
            )?;
            for p in &params.params {
                p.used.set(true);
            }
            Projection::Perspective {
                fov_degrees: params.float("fov").ok().flatten().unwrap_or(90.0),
                screen_window: None,
                frame_aspect_ratio: None,
                lens: None,
            }
        }
    };
    Camera::pbrt(&camera_from_world.inverse(), projection, width, height)
        .map_err(|e| PbrtError::at(at, format!("Camera \"{ty}\": {e}")))
}
