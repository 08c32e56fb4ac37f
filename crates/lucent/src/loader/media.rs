//! Scene-file media: `[media.NAME.homogeneous]` as scene media, and the
//! camera's `medium`.

use super::description::*;
use super::locate::*;
use super::SceneFile;
use crate::color::Color;
use crate::medium::{measured_medium, measured_medium_names, HomogeneousMedium, Medium, MediumId};
use crate::scene::{SceneBuilder, SceneError};
use std::collections::HashMap;

impl SceneFile {
    /// Add the `[media]` to the scene; their handles by name.
    pub(super) fn add_media(&self, scene: &mut SceneBuilder) -> Result<HashMap<String, MediumId>, SceneError> {
        let mut ids = HashMap::new();
        for (name, desc) in &self.description.media {
            let at = find_table(&self.source, name);
            let medium = match desc {
                MediumDesc::Homogeneous(h) => self.homogeneous(name, h)?,
            };
            let id = scene.add_medium(medium).map_err(|e| e.in_file(self.path.clone(), &self.source, at, name))?;
            ids.insert(name.clone(), id);
        }
        if let Some(name) = &self.description.camera.medium {
            let id = ids.get(name).copied().ok_or_else(|| {
                self.error(
                    find_value(&self.source, "medium", name).or_else(|| find_header(&self.source, "camera")),
                    format!("[camera]: medium \"{name}\" is not defined under [media] (defined: {})", known(&ids)),
                )
            })?;
            scene.set_camera_medium(Some(id)).map_err(|e| e.in_file(self.path.clone(), &self.source, None, name))?;
        }
        Ok(ids)
    }

    fn homogeneous(&self, name: &str, h: &HomogeneousDesc) -> Result<Medium, SceneError> {
        let at = find_table(&self.source, name);
        let (sigma_a, sigma_s) = match &h.preset {
            Some(preset) => {
                if h.sigma_a.is_some() || h.sigma_s.is_some() {
                    return Err(self.error(
                        at,
                        format!("medium \"{name}\": give either `preset` or `sigma_a` and `sigma_s`, not both"),
                    ));
                }
                measured_medium(preset).ok_or_else(|| {
                    let names: Vec<&str> = measured_medium_names().collect();
                    self.error(
                        find_value(&self.source, "preset", preset).or(at),
                        format!("medium \"{name}\": unknown preset \"{preset}\" (accepted: {})", names.join(", ")),
                    )
                })?
            }
            None => (h.sigma_a.map_or(Color::ONE, Color::from), h.sigma_s.map_or(Color::ONE, Color::from)),
        };
        let scale = h.scale.map_or(1.0, |s| s.get());
        let g = h.g.map_or(0.0, |g| g.get());
        let le = h.emission.map_or(Color::ZERO, Color::from);
        let medium = HomogeneousMedium::new(sigma_a, sigma_s, scale, g, le)
            .map_err(|e| self.error(at, format!("medium \"{name}\": {e}")))?;
        Ok(Medium::Homogeneous(medium))
    }
}

/// The defined names, for messages.
fn known(ids: &HashMap<String, MediumId>) -> String {
    let mut names: Vec<&str> = ids.keys().map(String::as_str).collect();
    names.sort_unstable();
    if names.is_empty() {
        "none".to_owned()
    } else {
        names.join(", ")
    }
}
