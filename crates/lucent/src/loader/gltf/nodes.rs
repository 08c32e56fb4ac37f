//! The node tree of a glTF scene (glTF 2.0 §3.5): meshes placed by their
//! nodes' global transforms (a mesh used by several nodes is built once),
//! `KHR_lights_punctual` lights and the camera.

use super::{GltfError, GltfOptions, Importer};
use crate::camera::{Camera, Projection};
use crate::color::Color;
use crate::geometry::{Bounds3, Mat4, Transform, Vec3};
use crate::light::{Falloff, Light};
use crate::medium::{HomogeneousMedium, Medium, MediumInterface};
use crate::primitive::Primitive;
use crate::scene::Emission;
use crate::shapes::{Mesh, Shape};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

/// Luminous efficacy used to turn photometric units into radiometric ones:
/// 683 lm/W, the definition of the candela at 555 nm (and what Blender's
/// glTF add-on uses, `PBR_WATTS_TO_LUMENS`).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Most levels of nested nodes.
const MAX_DEPTH: usize = 1024;

/// What placing the scene found.
pub(super) struct Placed {
    pub camera: Camera,
    pub has_lights: bool,
    pub notes: Vec<String>,
}

/// A camera of the tree with its node's global transform.
struct PlacedCamera<'a> {
    camera: gltf::Camera<'a>,
    world: Mat4,
}

/// The rigid part of `m` (rotation and translation), its axes normalised:
/// cameras must not be scaled (glTF 2.0 §3.10.1 asks that they are not).
fn rigid(m: Mat4) -> Mat4 {
    let x = m.x_axis.truncate().normalize_or_zero();
    let y0 = m.y_axis.truncate();
    let y = (y0 - x * x.dot(y0)).normalize_or_zero();
    let z = x.cross(y);
    Mat4::from_cols(x.extend(0.0), y.extend(0.0), z.extend(0.0), m.w_axis)
}

/// Image size: the options' width and/or height, the other from `aspect`;
/// 1280 wide by default.
fn image_size(options: &GltfOptions, aspect: f32) -> (u32, u32) {
    let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 16.0 / 9.0 };
    let from_w = |w: u32| ((w as f32 / aspect).round() as u32).max(1);
    let from_h = |h: u32| ((h as f32 * aspect).round() as u32).max(1);
    match options.resolution {
        Some((Some(w), Some(h))) => (w, h),
        Some((Some(w), None)) => (w, from_w(w)),
        Some((None, Some(h))) => (from_h(h), h),
        _ => (1280, from_w(1280)),
    }
}

impl Importer<'_> {
    /// Place every node of the chosen scene.
    pub(super) fn place_nodes(&mut self, options: &GltfOptions) -> Result<Placed, GltfError> {
        let doc = self.doc;
        let scene = match options.scene {
            Some(i) => doc.scenes().nth(i).ok_or_else(|| {
                GltfError::new("scenes", format!("there is no scene {i} (the file has {})", doc.scenes().len()))
            })?,
            None => match doc.default_scene().or_else(|| doc.scenes().next()) {
                Some(s) => s,
                None => return Err(GltfError::new("scenes", "the file has no scene")),
            },
        };
        let mut notes = Vec::new();
        if doc.animations().next().is_some() {
            notes.push("the file's animations are ignored: the scene is rendered as it stands".to_owned());
        }
        let mut stack: Vec<(gltf::Node, Mat4, usize)> =
            scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect::<Vec<_>>();
        stack.reverse();
        let mut seen = HashSet::new();
        let mut cameras = Vec::new();
        let mut meshes: HashMap<(usize, usize), Option<Arc<Mesh>>> = HashMap::new();
        let mut bounds = Bounds3::EMPTY;
        let mut has_lights = false;
        while let Some((node, parent, depth)) = stack.pop() {
            let what = format!("nodes[{}]", node.index());
            if !seen.insert(node.index()) {
                return Err(GltfError::new(
                    &what,
                    "appears twice in the scene's hierarchy (glTF's nodes form disjoint trees)",
                ));
            }
            if depth > MAX_DEPTH {
                return Err(GltfError::new(&what, format!("nodes are nested more than {MAX_DEPTH} levels deep")));
            }
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            let world = parent * local;
            if !world.is_finite() {
                return Err(GltfError::new(&what, "its transform is not finite"));
            }
            if node.skin().is_some() {
                self.warn_once(
                    "skin",
                    format!("{what}: skins are not supported: meshes are rendered in their bind pose"),
                )?;
            }
            if let Some(camera) = node.camera() {
                cameras.push(PlacedCamera { camera, world });
            }
            if let Some(light) = node.light() {
                self.light(&light, world, &what)?;
                has_lights = true;
            }
            if let Some(mesh) = node.mesh() {
                let transform = match Transform::from_matrix(world) {
                    Ok(t) => t,
                    Err(_) => {
                        // A node scaled to nothing shows nothing.
                        self.warn_once("singular", format!("{what}: its transform is singular: not rendered"))?;
                        for child in node.children() {
                            stack.push((child, world, depth + 1));
                        }
                        continue;
                    }
                };
                for primitive in mesh.primitives() {
                    let key = (mesh.index(), primitive.index());
                    let shape = match meshes.get(&key) {
                        Some(s) => s.clone(),
                        None => {
                            let s = self.primitive_mesh(mesh.index(), &primitive)?;
                            meshes.insert(key, s.clone());
                            s
                        }
                    };
                    let Some(shape) = shape else { continue };
                    bounds = bounds.union(&transform.bounds(&shape.bounds()));
                    has_lights |= self.place_primitive(shape, transform, primitive.material())?;
                }
            }
            let children: Vec<_> = node.children().collect();
            for child in children.into_iter().rev() {
                stack.push((child, world, depth + 1));
            }
        }
        let camera = self.camera(&cameras, options, &bounds, &mut notes)?;
        Ok(Placed { camera, has_lights, notes })
    }

    /// Place one primitive with its material; whether it emits.
    fn place_primitive(
        &mut self,
        shape: Arc<Mesh>,
        transform: Transform,
        material: gltf::Material,
    ) -> Result<bool, GltfError> {
        let key = material.index();
        let vertex_colors = shape.has_colors();
        let (id, converted) = match self.materials.get(&(key, vertex_colors)) {
            Some(m) => m.clone(),
            None => {
                let converted = self.material(key.map(|_| material), vertex_colors)?;
                let id = self
                    .builder
                    .add_material(converted.material.clone())
                    .map_err(|e| GltfError::new(&format!("materials[{}]", key.unwrap_or(0)), e.to_string()))?;
                self.materials.insert((key, vertex_colors), (id, converted.clone()));
                (id, converted)
            }
        };
        let what = format!("materials[{}]", key.map_or("default".to_owned(), |k| k.to_string()));
        let mut primitive = Primitive::new(Shape::Mesh(shape), transform, id);
        if let Some(alpha) = &converted.alpha {
            primitive = primitive.with_alpha(alpha.clone());
        }
        if let Some((color, distance)) = converted.volume {
            // KHR_materials_volume: Beer–Lambert absorption inside, with
            // σa = −ln(attenuationColor) / attenuationDistance.
            let sigma_a = Color::new(
                -color.x.max(1e-6).ln() / distance,
                -color.y.max(1e-6).ln() / distance,
                -color.z.max(1e-6).ln() / distance,
            )
            .max(Color::ZERO);
            let medium = HomogeneousMedium::new(sigma_a, Color::ZERO, 1.0, 0.0, Color::ZERO)
                .map_err(|e| GltfError::new(&what, format!("KHR_materials_volume: {e}")))?;
            let id = self
                .builder
                .add_medium(Medium::Homogeneous(medium))
                .map_err(|e| GltfError::new(&what, e.to_string()))?;
            primitive = primitive.with_media(MediumInterface::new(Some(id), None));
        }
        let emission = converted.emission.as_ref().map(|(radiance, image)| Emission {
            radiance: *radiance,
            two_sided: converted.double_sided,
            reverse: false,
            image: image.clone(),
        });
        let emits = emission.is_some();
        self.builder.add(primitive, emission).map_err(|e| GltfError::new(&what, e.to_string()))?;
        Ok(emits)
    }

    /// A `KHR_lights_punctual` light placed by its node: position from the
    /// node's translation, direction its `−z`. Photometric intensities
    /// (candela; lux for directional lights) are divided by
    /// [`LUMENS_PER_WATT`] to give radiant intensity (W/sr) and irradiance
    /// (W/m²), as in Blender's glTF add-on. `range` is ignored (lights
    /// fall off with the inverse square, as physically they do).
    fn light(&mut self, light: &gltf::khr_lights_punctual::Light, world: Mat4, what: &str) -> Result<(), GltfError> {
        use gltf::khr_lights_punctual::Kind;
        let color = Color::from(light.color());
        let intensity = light.intensity() / LUMENS_PER_WATT;
        let position = world.transform_point3a(Vec3::ZERO);
        let direction = world.transform_vector3a(-Vec3::Z);
        if light.range().is_some() {
            self.note_once("light range is ignored: lights fall off with the inverse square of distance");
        }
        let l = match light.kind() {
            Kind::Point => Light::point(position, color, intensity, Falloff::InverseSquare),
            Kind::Directional => Light::directional(direction, color, intensity),
            Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                let outer = outer_cone_angle.to_degrees().clamp(1e-3, 90.0);
                let inner = inner_cone_angle.to_degrees().clamp(0.0, outer);
                Light::spot(position, direction, color, intensity, outer, outer - inner, Falloff::InverseSquare)
            }
        }
        .map_err(|e| GltfError::new(what, format!("KHR_lights_punctual light {}: {e}", light.index())))?;
        self.builder.add_light(l);
        Ok(())
    }

    fn note_once(&mut self, message: &str) {
        self.note(message);
    }

    /// The camera: the one asked for, else the first in the tree, else one
    /// framing `bounds`.
    fn camera(
        &mut self,
        cameras: &[PlacedCamera],
        options: &GltfOptions,
        bounds: &Bounds3,
        notes: &mut Vec<String>,
    ) -> Result<Camera, GltfError> {
        let chosen = match &options.camera {
            Some(want) => {
                let by_index = want.parse::<usize>().ok();
                let found = cameras
                    .iter()
                    .find(|c| Some(c.camera.index()) == by_index || c.camera.name() == Some(want.as_str()));
                let names: Vec<String> = cameras
                    .iter()
                    .map(|c| match c.camera.name() {
                        Some(n) => format!("{} \"{n}\"", c.camera.index()),
                        None => c.camera.index().to_string(),
                    })
                    .collect();
                Some(found.ok_or_else(|| {
                    GltfError::new(
                        "cameras",
                        format!(
                            "no camera \"{want}\" is placed in the scene (cameras placed: {})",
                            if names.is_empty() { "none".to_owned() } else { names.join(", ") }
                        ),
                    )
                })?)
            }
            None => cameras.first(),
        };
        let Some(c) = chosen else {
            notes.push(
                "the file has no camera: a camera on +z frames the scene's bounds (45° vertical field of view)"
                    .to_owned(),
            );
            return Ok(framing_camera(bounds, options));
        };
        let what = format!("cameras[{}]", c.camera.index());
        // glTF cameras look down −z with +y up (right-handed); pbrt's
        // camera space looks down +z: flip z.
        let world_from_camera = rigid(c.world) * Mat4::from_scale(glam::Vec3::new(1.0, 1.0, -1.0));
        let world_from_camera =
            Transform::from_matrix(world_from_camera).map_err(|e| GltfError::new(&what, e.to_string()))?;
        let (projection, aspect) = match c.camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let aspect = match options.resolution {
                    Some((Some(w), Some(h))) => w as f32 / h as f32,
                    _ => p.aspect_ratio().unwrap_or(16.0 / 9.0),
                };
                let yfov = p.yfov().to_degrees();
                // The screen window's vertical extent is [−1, 1], so that
                // `fov` is glTF's vertical field of view at any aspect.
                (
                    Projection::Perspective {
                        fov_degrees: yfov,
                        screen_window: Some([-aspect, aspect, -1.0, 1.0]),
                        frame_aspect_ratio: None,
                        lens: None,
                    },
                    aspect,
                )
            }
            gltf::camera::Projection::Orthographic(o) => {
                let (x, y) = (o.xmag().abs(), o.ymag().abs());
                let aspect = if y > 0.0 { x / y } else { 1.0 };
                (
                    Projection::Orthographic {
                        screen_window: Some([-x, x, -y, y]),
                        frame_aspect_ratio: None,
                        lens: None,
                    },
                    aspect,
                )
            }
        };
        let (w, h) = image_size(options, aspect);
        // With both sizes given, the perspective window follows the image.
        let projection = match projection {
            Projection::Perspective { fov_degrees, lens, .. } => {
                let a = w as f32 / h as f32;
                Projection::Perspective {
                    fov_degrees,
                    screen_window: Some([-a, a, -1.0, 1.0]),
                    frame_aspect_ratio: None,
                    lens,
                }
            }
            p => p,
        };
        Camera::pbrt(&world_from_camera, projection, w, h).map_err(|e| GltfError::new(&what, e.to_string()))
    }
}

/// A camera on the `+z` side of `bounds`, looking at their centre from
/// far enough that the bounding sphere fills a 45° vertical field of view
/// (what glTF viewers do without a camera).
fn framing_camera(bounds: &Bounds3, options: &GltfOptions) -> Camera {
    let (center, radius) = if bounds.is_empty() {
        (Vec3::ZERO, 1.0)
    } else {
        let c = (bounds.min + bounds.max) * 0.5;
        (c, ((bounds.max - bounds.min).length() * 0.5).max(1e-3))
    };
    let fov = 45.0f32;
    let distance = radius / (fov.to_radians() * 0.5).sin();
    let (w, h) = image_size(options, 16.0 / 9.0);
    let eye = center + Vec3::Z * distance;
    Camera::new(eye, center, Vec3::Y, fov, w, h)
        .or_else(|_| Camera::new(Vec3::Z * 5.0, Vec3::ZERO, Vec3::Y, fov, w, h))
        .expect("a valid framing camera")
}
