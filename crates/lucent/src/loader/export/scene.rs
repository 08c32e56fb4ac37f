//! The scene model as a [`SceneDescription`], and [`export_scene`], which
//! writes it with its meshes.
//!
//! Everything is read back from the model, not from the file the scene came
//! from: a camera through [`Camera::pbrt_parameters`], an environment map
//! through its source file and factor, each placed primitive with its
//! object-to-world matrix. A mesh is written once, however many primitives
//! place it (instancing survives), as `STEM-meshes/mesh-N.ply` beside the
//! scene file. The loose triangles that the builder merged into one
//! world-space mesh are written back as `[[triangle]]` tables (each keeps
//! its own material and emission, and the builder merges them again).

use super::super::description::*;
use super::super::values::*;
use super::super::{LoadedScene, SceneFormat};
use super::TextureExport;
use crate::camera::{Camera, Projection, SphericalMapping};
use crate::color::Color;
use crate::film::{Filter, ToneMap};
use crate::geometry::{Mat4, Transform, Vec3};
use crate::light::{Environment, EnvironmentMapping, Falloff, Light};
use crate::medium::{Medium, MediumInterface};
use crate::primitive::Primitive;
use crate::render::{IntegratorKind, RenderSettings};
use crate::sampling::SamplerKind;
use crate::scene::Scene;
use crate::shapes::{DefaultUv, Mesh, Shape};
use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Why a scene cannot be written as a scene file.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// A file cannot be written.
    #[error("cannot write '{path}': {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The output name has neither `.toml` nor `.json`.
    #[error("'{0}': a scene file ends in .toml or .json")]
    Format(PathBuf),
    /// Part of the scene has no scene-file form.
    #[error("cannot export {what}: {why}")]
    Unsupported {
        /// What.
        what: String,
        /// Why.
        why: String,
    },
    /// The description cannot be serialised (a bug).
    #[error("cannot serialise the scene: {0}")]
    Serialize(String),
}

/// What [`export_scene`] wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExportSummary {
    /// The scene file.
    pub scene_file: PathBuf,
    /// The mesh files, in the order written.
    pub mesh_files: Vec<PathBuf>,
    /// Triangles in the mesh files.
    pub triangles: usize,
    /// Images written beside the scene (those made in memory, such as a
    /// `.glb` file's embedded textures), as linear EXR files in
    /// `STEM-textures/`.
    pub image_files: Vec<PathBuf>,
}

/// Write `loaded` as a scene file at `path` (TOML or JSON, by extension)
/// with its meshes as binary PLY files in `STEM-meshes/` beside it. Every
/// file is written to a temporary name and renamed into place, so an error
/// leaves no partial file and an existing scene file is replaced only by a
/// complete one.
pub fn export_scene(loaded: &LoadedScene, path: &Path) -> Result<ExportSummary, ExportError> {
    let format = SceneFormat::from_path(path).ok_or_else(|| ExportError::Format(path.to_owned()))?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
        _ => PathBuf::from("."),
    };
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
    let mesh_dir_name = format!("{stem}-meshes");
    let (description, meshes, images) = describe(loaded, &dir, &mesh_dir_name, &format!("{stem}-textures"))?;
    let text = match format {
        SceneFormat::Toml => toml::to_string(&description).map_err(|e| ExportError::Serialize(e.to_string()))?,
        SceneFormat::Json => {
            serde_json::to_string_pretty(&description).map_err(|e| ExportError::Serialize(e.to_string()))? + "\n"
        }
    };
    let mut summary =
        ExportSummary { scene_file: path.to_owned(), mesh_files: Vec::new(), triangles: 0, image_files: Vec::new() };
    if !meshes.is_empty() {
        let mesh_dir = dir.join(&mesh_dir_name);
        std::fs::create_dir_all(&mesh_dir).map_err(|source| ExportError::Io { path: mesh_dir.clone(), source })?;
        for (name, mesh) in &meshes {
            let file = mesh_dir.join(format!("{name}.ply"));
            let data = mesh.to_triangle_mesh();
            summary.triangles += data.triangle_count();
            let mut bytes = Vec::new();
            crate::mesh::write_ply(&data, &mut bytes)
                .map_err(|source| ExportError::Io { path: file.clone(), source })?;
            write_atomically(&file, &bytes)?;
            summary.mesh_files.push(file);
        }
    }
    for (name, map) in &images {
        let file = dir.join(name);
        if let Some(parent) = file.parent() {
            std::fs::create_dir_all(parent).map_err(|source| ExportError::Io { path: parent.to_owned(), source })?;
        }
        write_atomically(&file, &exr_bytes(map, &file)?)?;
        summary.image_files.push(file);
    }
    write_atomically(path, text.as_bytes())?;
    Ok(summary)
}

/// The finest level of `map` as a 32-bit float OpenEXR file (RGB, or RGBA
/// where the image has alpha; grey as RGB).
fn exr_bytes(map: &crate::texture::MipMap, file: &Path) -> Result<Vec<u8>, ExportError> {
    let level = map.level(0).expect("a MIP map has a finest level");
    let (w, h, c) = (level.width(), level.height(), level.channels());
    let data = level.data();
    let image = match c {
        4 => image::DynamicImage::ImageRgba32F(
            image::Rgba32FImage::from_raw(w, h, data.to_vec()).expect("texels match the size"),
        ),
        _ => {
            let rgb: Vec<f32> = match c {
                1 => data.iter().flat_map(|&v| [v, v, v]).collect(),
                _ => data.to_vec(),
            };
            image::DynamicImage::ImageRgb32F(image::Rgb32FImage::from_raw(w, h, rgb).expect("texels match the size"))
        }
    };
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::OpenExr)
        .map_err(|e| ExportError::Io { path: file.to_owned(), source: std::io::Error::other(e.to_string()) })?;
    Ok(bytes.into_inner())
}

/// Write `bytes` to a temporary file beside `path`, then rename it to
/// `path`.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let io = |source| ExportError::Io { path: path.to_owned(), source };
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

/// The description of `loaded` (image paths relative to `dir`, meshes
/// named as files in `dir/mesh_dir`), and the meshes to write, by name.
pub(crate) fn describe(
    loaded: &LoadedScene,
    dir: &Path,
    mesh_dir: &str,
    image_dir: &str,
) -> Result<(SceneDescription, NamedMeshes, MemoryImages), ExportError> {
    let scene = &loaded.scene;
    let mut out = Describer {
        textures: TextureExport::new(dir).with_image_dir(image_dir),
        dir: dir.to_owned(),
        mesh_dir: mesh_dir.to_owned(),
        mesh_names: HashMap::new(),
        meshes: Vec::new(),
        mesh_files: BTreeMap::new(),
        material_names: material_names(scene.materials().len()),
        d: SceneDescription {
            camera: camera(scene),
            textures: BTreeMap::new(),
            render: render(scene, &loaded.settings),
            environment: None,
            ambient: None,
            materials: BTreeMap::new(),
            media: scene
                .media()
                .iter()
                .enumerate()
                .map(|(i, m)| (medium_name(i, scene.media().len()), medium(m)))
                .collect(),
            point_light: Vec::new(),
            spot_light: Vec::new(),
            directional_light: Vec::new(),
            sphere: Vec::new(),
            plane: Vec::new(),
            triangle: Vec::new(),
            quad: Vec::new(),
            disk: Vec::new(),
            cylinder: Vec::new(),
            group: Vec::new(),
            meshes: BTreeMap::new(),
            mesh: Vec::new(),
            prototypes: BTreeMap::new(),
            instance: Vec::new(),
        },
    };
    if scene.ambient() != Color::ZERO {
        out.d.ambient = Some(AmbientDesc { color: rgb(scene.ambient()), intensity: NonNegative(1.0) });
    }
    out.environment(scene)?;
    for (i, m) in scene.materials().iter().enumerate() {
        let desc = out
            .textures
            .material(m, &out.material_names)
            .map_err(|why| ExportError::Unsupported { what: format!("material #{i}"), why })?;
        out.d.materials.insert(out.material_names[i].clone(), desc);
    }
    for light in scene.lights() {
        out.light(light);
    }
    for (i, p) in scene.primitives().iter().enumerate() {
        out.primitive(scene, p).map_err(|why| ExportError::Unsupported { what: format!("primitive #{i}"), why })?;
    }
    out.d.meshes = out.mesh_files;
    out.d.textures = out.textures.textures;
    Ok((out.d, out.meshes, out.textures.images))
}

/// Images made in memory, to be written beside the scene file, each with
/// its name relative to the scene file's folder.
pub(crate) type MemoryImages = Vec<(String, Arc<crate::texture::MipMap>)>;

/// The emission keys of an exported object.
#[derive(Default)]
struct EmissionKeys {
    emission: Option<Rgb>,
    two_sided: bool,
    reverse_orientation: bool,
    emission_texture: Option<String>,
}

/// Meshes to write, with their names under `[meshes]`.
type NamedMeshes = Vec<(String, Arc<Mesh>)>;

struct Describer {
    textures: TextureExport,
    dir: PathBuf,
    mesh_dir: String,
    /// Meshes already named, by address: each is written once.
    mesh_names: HashMap<*const Mesh, String>,
    meshes: NamedMeshes,
    mesh_files: BTreeMap<String, MeshFileDesc>,
    material_names: Vec<String>,
    d: SceneDescription,
}

/// The name under `[media]` of medium `i` of `n`: `medium-1`…,
/// zero-padded to one width, so that the file's (sorted) order is the
/// scene's and every medium keeps its index.
fn medium_name(i: usize, n: usize) -> String {
    let width = n.to_string().len();
    format!("medium-{:0width$}", i + 1)
}

/// The `medium_inside` and `medium_outside` keys of a surface of a scene
/// with `n` media.
fn medium_names(media: MediumInterface, n: usize) -> (Option<String>, Option<String>) {
    let name = |m: Option<crate::medium::MediumId>| m.map(|m| medium_name(m.index(), n));
    (name(media.inside), name(media.outside))
}

/// A medium's table: its coefficients with the scale applied.
fn medium(m: &Medium) -> MediumDesc {
    match m {
        Medium::Homogeneous(h) => MediumDesc::Homogeneous(HomogeneousDesc {
            preset: None,
            sigma_a: Some(rgb(h.sigma_a())),
            sigma_s: Some(rgb(h.sigma_s())),
            scale: None,
            g: (h.phase().g() != 0.0).then(|| Finite(h.phase().g())),
            emission: (h.le() != Color::ZERO).then(|| rgb(h.le())),
        }),
    }
}

/// Names `material-0`… zero-padded to one width, so that the file's
/// (sorted) order is the scene's and every material keeps its index.
fn material_names(n: usize) -> Vec<String> {
    let width = n.saturating_sub(1).to_string().len();
    (0..n).map(|i| format!("material-{i:0width$}")).collect()
}

fn rgb(c: Color) -> Rgb {
    Rgb(c.to_array())
}

fn v3(v: Vec3) -> Vec3Desc {
    Vec3Desc(v.to_array())
}

/// A transform list of one matrix (none for the identity).
fn matrix_ops(m: Mat4) -> Vec<TransformOp> {
    if m == Mat4::IDENTITY {
        return Vec::new();
    }
    vec![TransformOp::Matrix(m.transpose().to_cols_array_2d())]
}

/// A transform list of one matrix with its inverse (none for the
/// identity), which reads back bit for bit.
fn transform_ops(t: &Transform) -> Vec<TransformOp> {
    if t.is_identity() {
        return Vec::new();
    }
    let rows = |m: Mat4| m.transpose().to_cols_array_2d();
    vec![TransformOp::Affine(AffineDesc { matrix: rows(t.matrix()), inverse: rows(t.inverse_matrix()) })]
}

fn camera(scene: &Scene) -> CameraDesc {
    let (m, projection) = scene.camera().pbrt_parameters();
    let mut c = CameraDesc {
        eye: None,
        look_at: None,
        up: Direction([0.0, 1.0, 0.0]),
        fov: None,
        lens_radius: None,
        focal_distance: None,
        projection: None,
        transform: vec![TransformOp::Matrix(m.transpose().to_cols_array_2d())],
        screen_window: None,
        frame_aspect_ratio: None,
        mapping: None,
        medium: scene.camera_medium().map(|m| medium_name(m.index(), scene.media().len())),
    };
    let window = |w: Option<[f32; 4]>| w.map(|w| w.map(Finite));
    match projection {
        Projection::Perspective { fov_degrees, screen_window, lens, .. } => {
            c.projection = Some(ProjectionDesc::Perspective);
            // The default window for the image's shape is written as a
            // field of view, so that a different `--width`/`--height` keeps
            // working as it does on the original scene.
            match screen_window.and_then(|w| default_window_extent(w, scene.camera())) {
                Some(t) => c.fov = Some(FieldOfView((2.0 * (t as f64).atan()).to_degrees() as f32)),
                None => {
                    c.fov = Some(FieldOfView(fov_degrees));
                    c.screen_window = window(screen_window);
                }
            }
            if let Some(l) = lens {
                c.lens_radius = Some(NonNegative(l.radius));
                c.focal_distance = Some(Positive(l.focal_distance));
            }
        }
        Projection::Orthographic { screen_window, lens, .. } => {
            c.projection = Some(ProjectionDesc::Orthographic);
            if screen_window.and_then(|w| default_window_extent(w, scene.camera())) != Some(1.0) {
                c.screen_window = window(screen_window);
            }
            if let Some(l) = lens {
                c.lens_radius = Some(NonNegative(l.radius));
                c.focal_distance = Some(Positive(l.focal_distance));
            }
        }
        Projection::Spherical { mapping } => {
            c.projection = Some(ProjectionDesc::Spherical);
            c.mapping = Some(match mapping {
                SphericalMapping::EqualArea => SphericalMappingDesc::EqualArea,
                SphericalMapping::Equirectangular => SphericalMappingDesc::Equirectangular,
            });
        }
    }
    c
}

/// If `w` is pbrt-v4's default screen window for the camera's image shape
/// (centred, `[-a, a, -1, 1]` for an image wider than tall by `a`, else
/// `[-1, 1, -1/a, 1/a]`) scaled by some `t`, that `t`: the half-extent of
/// the shorter axis.
fn default_window_extent(w: [f32; 4], camera: &Camera) -> Option<f32> {
    let a = camera.width() as f64 / camera.height() as f64;
    let [x0, x1, y0, y1] = w.map(f64::from);
    let t = x1.min(y1);
    let shape = if a > 1.0 { x1 / y1 } else { y1 / x1 };
    let centred = x0 == -x1 && y0 == -y1 && t > 0.0;
    (centred && (shape - a.max(1.0 / a)).abs() <= 1e-6 * a.max(1.0 / a)).then_some(t as f32)
}

fn render(scene: &Scene, s: &RenderSettings) -> RenderDesc {
    let filter = match s.filter {
        Filter::Box { radius } => FilterDesc::new(FilterKindDesc::Box, radius),
        Filter::Tent { radius } => FilterDesc::new(FilterKindDesc::Tent, radius),
        Filter::Gaussian { radius, sigma } => {
            FilterDesc { sigma: Some(Positive(sigma)), ..FilterDesc::new(FilterKindDesc::Gaussian, radius) }
        }
        Filter::Mitchell { radius, b, c } => {
            FilterDesc { b: Some(Finite(b)), c: Some(Finite(c)), ..FilterDesc::new(FilterKindDesc::Mitchell, radius) }
        }
        Filter::Lanczos { radius, tau } => {
            FilterDesc { tau: Some(Positive(tau)), ..FilterDesc::new(FilterKindDesc::Lanczos, radius) }
        }
    };
    RenderDesc {
        width: ImageDimension(scene.camera().width()),
        height: ImageDimension(scene.camera().height()),
        spp: SampleCount(s.spp),
        max_depth: Some(MaxDepth(s.max_depth)),
        background: rgb(scene.background()),
        tone_map: match s.tone_map {
            ToneMap::Classic => ToneMapDesc::Classic,
            ToneMap::Clamp => ToneMapDesc::Clamp,
            ToneMap::Reinhard => ToneMapDesc::Reinhard,
            ToneMap::Aces => ToneMapDesc::Aces,
        },
        srgb: s.srgb,
        seed: s.seed,
        integrator: match s.integrator {
            IntegratorKind::Whitted => IntegratorDesc::Whitted,
            IntegratorKind::Path => IntegratorDesc::Path,
            IntegratorKind::Bdpt => IntegratorDesc::Bdpt,
        },
        sampler: Some(match s.sampler {
            SamplerKind::Stratified => SamplerDesc::Stratified,
            SamplerKind::Sobol => SamplerDesc::Sobol,
            SamplerKind::Independent => SamplerDesc::Independent,
        }),
        filter: Some(filter),
        regularize: s.regularize,
        film_scale: (s.film_scale != Color::ONE).then(|| rgb(s.film_scale)),
        max_component: s.max_component.map(Positive),
        max_indirect: s.max_indirect.map(Positive),
        aov: s.aovs.iter().map(AovDesc::from).collect(),
        filter_importance: s.filter_importance,
        adaptive: s.adaptive.map(Positive),
    }
}

impl FilterDesc {
    fn new(kind: FilterKindDesc, radius: f32) -> Self {
        Self { kind, radius: Some(Positive(radius)), sigma: None, b: None, c: None, tau: None }
    }
}

impl Describer {
    fn environment(&mut self, scene: &Scene) -> Result<(), ExportError> {
        let Some(env) = scene.environment() else { return Ok(()) };
        let desc = match env {
            Environment::Constant(c) => EnvironmentDesc {
                color: Some(rgb(*c)),
                file: None,
                intensity: NonNegative(1.0),
                rotation: None,
                mapping: None,
                transform: Vec::new(),
                illuminance: None,
            },
            Environment::Image(map) => {
                let source = map.source().ok_or_else(|| ExportError::Unsupported {
                    what: "the environment".into(),
                    why: "its image was made in memory, not read from a file".into(),
                })?;
                let q = map.light_to_world();
                EnvironmentDesc {
                    color: None,
                    file: Some(relative_path(source, &self.dir)),
                    intensity: NonNegative(map.scale()),
                    rotation: None,
                    mapping: Some(match map.mapping() {
                        EnvironmentMapping::Equirectangular => SphericalMappingDesc::Equirectangular,
                        EnvironmentMapping::EqualArea => SphericalMappingDesc::EqualArea,
                    }),
                    transform: matrix_ops(Mat4::from_mat3(q)),
                    illuminance: None,
                }
            }
        };
        self.d.environment = Some(desc);
        Ok(())
    }

    fn light(&mut self, light: &Light) {
        let falloff = |f: Falloff| {
            Some(match f {
                Falloff::None => FalloffDesc::None,
                Falloff::InverseSquare => FalloffDesc::InverseSquare,
            })
        };
        match *light {
            Light::Point { position, intensity, falloff: f } => self.d.point_light.push(PointLightDesc {
                position: v3(position),
                color: rgb(intensity),
                intensity: NonNegative(1.0),
                falloff: falloff(f),
            }),
            Light::Spot { position, direction, intensity, falloff: f, cos_total, cos_falloff_start } => {
                let angle = cos_total.clamp(-1.0, 1.0).acos().to_degrees();
                let start = cos_falloff_start.clamp(-1.0, 1.0).acos().to_degrees();
                self.d.spot_light.push(SpotLightDesc {
                    position: v3(position),
                    direction: Direction(direction.to_array()),
                    color: rgb(intensity),
                    intensity: NonNegative(1.0),
                    angle: Positive(angle),
                    cone_delta: Some(NonNegative((angle - start).max(0.0))),
                    falloff: falloff(f),
                })
            }
            Light::Directional { direction, intensity } => self.d.directional_light.push(DirectionalLightDesc {
                direction: Direction(direction.to_array()),
                color: rgb(intensity),
                intensity: NonNegative(1.0),
            }),
        }
    }

    /// The emission keys of face `face` of `p`, and `reverse_orientation`
    /// (which in a scene file turns the surface and its light around
    /// together, as pbrt-v4's `ReverseOrientation` does).
    fn emission(&mut self, scene: &Scene, p: &Primitive, face: u32) -> Result<EmissionKeys, String> {
        let Some(l) = p.face_area_light(face).and_then(|i| scene.area_lights().get(i as usize)) else {
            return Ok(EmissionKeys { reverse_orientation: p.reverse_orientation(), ..EmissionKeys::default() });
        };
        let mut radiance = l.radiance;
        let texture = match &l.image {
            None => None,
            Some(image) => match self.textures.color(&image.texture)? {
                TexValue::Name(name) => Some(name),
                TexValue::Rgb(c) => {
                    radiance *= Color::from_array(c);
                    None
                }
                TexValue::Number(x) => {
                    radiance *= x;
                    None
                }
            },
        };
        Ok(EmissionKeys {
            emission: Some(rgb(radiance)),
            two_sided: l.two_sided,
            reverse_orientation: p.reverse_orientation() || (l.reverse && !l.two_sided),
            emission_texture: texture,
        })
    }

    fn primitive(&mut self, scene: &Scene, p: &Primitive) -> Result<(), String> {
        let material = Some(self.material_names[p.material().index()].clone());
        let transform = transform_ops(&p.transform());
        let EmissionKeys { emission, two_sided, reverse_orientation, emission_texture } = self.emission(scene, p, 0)?;
        let alpha = p.alpha().map(|a| self.textures.float(a)).transpose()?;
        let (medium_inside, medium_outside) = medium_names(p.media(), scene.media().len());
        match p.shape() {
            Shape::Sphere(s) => {
                let (center, z_min, z_max, phi_max) = match s.clipping() {
                    None => (v3(s.center()), None, None, None),
                    Some((lo, hi, phi)) => {
                        (Vec3Desc([0.0; 3]), Some(Finite(lo)), Some(Finite(hi)), Some(Finite(phi.to_degrees())))
                    }
                };
                self.d.sphere.push(SphereDesc {
                    name: None,
                    center,
                    radius: Positive(s.radius()),
                    material,
                    z_min,
                    z_max,
                    phi_max,
                    transform,
                    emission,
                    two_sided,
                    reverse_orientation,
                    emission_texture,
                    alpha,
                    medium_inside: medium_inside.clone(),
                    medium_outside: medium_outside.clone(),
                });
            }
            Shape::Plane(pl) => self.d.plane.push(PlaneDesc {
                name: None,
                point: v3(pl.point()),
                normal: Direction(pl.normal().to_array()),
                material,
                transform,
                alpha,
                medium_inside: medium_inside.clone(),
                medium_outside: medium_outside.clone(),
            }),
            Shape::Rectangle(r) => {
                let (c, ex, ey) = r.corner_and_edges();
                self.d.quad.push(QuadDesc {
                    name: None,
                    vertices: [c, c + ex, c + ex + ey, c + ey].map(v3),
                    material,
                    transform,
                    emission,
                    two_sided,
                    reverse_orientation,
                    emission_texture,
                    alpha,
                    medium_inside: medium_inside.clone(),
                    medium_outside: medium_outside.clone(),
                })
            }
            Shape::Triangle(t) => self.d.triangle.push(TriangleDesc {
                name: None,
                vertices: t.vertices().map(v3),
                normals: t.normals().map(|ns| ns.map(|n| Direction(n.to_array()))),
                material,
                transform,
                emission,
                two_sided,
                reverse_orientation,
                emission_texture,
                alpha,
                medium_inside: medium_inside.clone(),
                medium_outside: medium_outside.clone(),
            }),
            Shape::Disk(disk) => self.d.disk.push(DiskDesc {
                name: None,
                height: Finite(disk.height()),
                radius: Positive(disk.radius()),
                inner_radius: NonNegative(disk.inner_radius()),
                phi_max: Some(Finite(disk.phi_max().to_degrees())),
                material,
                transform,
                emission,
                two_sided,
                reverse_orientation,
                emission_texture,
                alpha,
                medium_inside: medium_inside.clone(),
                medium_outside: medium_outside.clone(),
            }),
            Shape::Cylinder(c) => {
                let (z_min, z_max) = c.z_range();
                self.d.cylinder.push(CylinderDesc {
                    name: None,
                    radius: Positive(c.radius()),
                    z_min: Finite(z_min),
                    z_max: Finite(z_max),
                    phi_max: Some(Finite(c.phi_max().to_degrees())),
                    material,
                    transform,
                    emission,
                    two_sided,
                    reverse_orientation,
                    emission_texture,
                    alpha,
                    medium_inside: medium_inside.clone(),
                    medium_outside: medium_outside.clone(),
                })
            }
            Shape::Mesh(mesh) if p.face_materials().is_some() => self.split_mesh(scene, p, mesh)?,
            Shape::Mesh(mesh) => {
                let name = self.mesh_name(mesh);
                self.d.mesh.push(MeshDesc {
                    name: None,
                    mesh: Some(name),
                    file: None,
                    normals: None,
                    default_uv: None,
                    material,
                    transform,
                    emission,
                    two_sided,
                    reverse_orientation,
                    emission_texture,
                    alpha,
                    medium_inside: medium_inside.clone(),
                    medium_outside: medium_outside.clone(),
                });
            }
        }
        Ok(())
    }

    /// A mesh whose faces have materials of their own (the loose triangles
    /// the builder merged, or an OBJ file's materials) as `[[triangle]]`
    /// tables, each with its material and emission.
    fn split_mesh(&mut self, scene: &Scene, p: &Primitive, mesh: &Mesh) -> Result<(), String> {
        if mesh.has_uvs() || mesh.default_uv() != DefaultUv::Barycentric {
            return Err("a mesh with per-face materials and texture coordinates has no scene-file form".into());
        }
        let data = mesh.to_triangle_mesh();
        let transform = transform_ops(&p.transform());
        let alpha = p.alpha().map(|a| self.textures.float(a)).transpose()?;
        let (medium_inside, medium_outside) = medium_names(p.media(), scene.media().len());
        for (face, tri) in data.indices.iter().enumerate() {
            let face = face as u32;
            let vertices = tri.map(|i| data.positions[i as usize]);
            if crate::shapes::Triangle::new(vertices, None).is_err() {
                continue; // zero-area: skipped by the mesh too
            }
            let normals = data.normals.as_ref().map(|ns| tri.map(|i| Direction(ns[i as usize].to_array())));
            let EmissionKeys { emission, two_sided, reverse_orientation, emission_texture } =
                self.emission(scene, p, face)?;
            self.d.triangle.push(TriangleDesc {
                name: None,
                vertices: vertices.map(v3),
                normals,
                material: Some(self.material_names[p.face_material(face).index()].clone()),
                transform: transform.clone(),
                emission,
                two_sided,
                reverse_orientation,
                emission_texture,
                alpha: alpha.clone(),
                medium_inside: medium_inside.clone(),
                medium_outside: medium_outside.clone(),
            });
        }
        Ok(())
    }

    /// The name under `[meshes]` of `mesh`, registering it the first time.
    fn mesh_name(&mut self, mesh: &Arc<Mesh>) -> String {
        if let Some(name) = self.mesh_names.get(&Arc::as_ptr(mesh)) {
            return name.clone();
        }
        let name = format!("mesh-{}", self.meshes.len());
        self.mesh_names.insert(Arc::as_ptr(mesh), name.clone());
        self.meshes.push((name.clone(), mesh.clone()));
        self.mesh_files.insert(
            name.clone(),
            MeshFileDesc {
                file: format!("{}/{name}.ply", self.mesh_dir),
                normals: NormalsDesc::File,
                default_uv: match mesh.default_uv() {
                    DefaultUv::Barycentric => DefaultUvDesc::Barycentric,
                    DefaultUv::Pbrt => DefaultUvDesc::Pbrt,
                },
            },
        );
        name
    }
}

/// `path` as a scene file in `dir` names it: relative to `dir` when the
/// two share a directory below the root (comparing their canonical forms,
/// or absolute forms for paths that do not exist), else absolute; with `/`
/// separators.
pub(crate) fn relative_path(path: &Path, dir: &Path) -> String {
    let full = |p: &Path| std::fs::canonicalize(p).or_else(|_| std::path::absolute(p)).unwrap_or_else(|_| p.to_owned());
    let (path, dir) = (full(path), full(dir));
    let p: Vec<_> = path.components().collect();
    let d: Vec<_> = dir.components().collect();
    let common = p.iter().zip(&d).take_while(|(a, b)| a == b).count();
    // The root (and, on Windows, the drive) alone is not a shared directory.
    let root = p.iter().take_while(|c| !matches!(c, std::path::Component::Normal(_))).count();
    if common <= root {
        return path.to_string_lossy().into_owned();
    }
    let mut parts: Vec<String> = vec!["..".to_owned(); d.len() - common];
    parts.extend(p[common..].iter().map(|c| c.as_os_str().to_string_lossy().into_owned()));
    parts.join("/")
}
