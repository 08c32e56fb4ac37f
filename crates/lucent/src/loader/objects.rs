//! Scene-file objects: shapes, meshes, groups and prototypes, flattened with
//! their transforms and inherited materials into scene-builder calls.

use super::description::*;
use super::locate::*;
use super::materials::material_from_file;
use super::textures::TextureTable;
use super::values::*;
use super::SceneFile;
use crate::geometry::{Transform, Vec3};
use crate::material::MaterialId;
use crate::primitive::Primitive;
use crate::scene::{Emission, SceneBuilder, SceneError, SourceLocation};
use crate::shapes::{Cylinder, DefaultUv, Disk, Mesh, Plane, Shape, Sphere, Triangle};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

impl SceneFile {
    pub(super) fn add_group(
        &self,
        scene: &mut SceneBuilder,
        ctx: &mut BuildContext<'_>,
        group: &GroupDesc,
        parent: Transform,
        parent_material: Option<&str>,
        place: Place<'_>,
    ) -> Result<(), SceneError> {
        let Place { label, at: group_at, forced_material } = place;
        let group_transform = self.transform(&group.transform, label, group_at)?.then(&parent);
        let material = group.material.as_deref().or(parent_material);
        // Top-level objects are the n-th `[[kind]]` table of the file;
        // nested ones are identified by their path in the message and
        // located at the top-level table that holds them.
        let tables = TableLocator::new(&self.source);
        let locate = |kind: &str, index: usize| if label.is_empty() { tables.nth_table(kind, index) } else { group_at };
        let resolve = |ctx: &BuildContext<'_>, what: &str, own: Option<&str>, at| -> Result<MaterialId, SceneError> {
            let name = forced_material.or(own).or(material).ok_or_else(|| {
                self.error(at, format!("{what} has no material (set `material`, or one on its group)"))
            })?;
            self.material_id(ctx, what, name)
        };
        let add = |ctx: &mut BuildContext<'_>,
                   obj: Object<'_>,
                   shape: Result<Shape, crate::shapes::ShapeError>,
                   scene: &mut SceneBuilder|
         -> Result<(), SceneError> {
            let what = describe(label, obj.kind, obj.index, obj.name);
            let at = locate(obj.kind, obj.index);
            let shape = shape.map_err(|e| self.error(at, format!("{what}: {e}")))?;
            let id = resolve(ctx, &what, obj.material.as_deref(), at)?;
            let t = self.transform(obj.transform, &what, at)?.then(&group_transform);
            let primitive = self.with_alpha(ctx, Primitive::new(shape, t, id), obj.alpha, &what, at)?;
            self.place(scene, ctx, primitive, obj.emission, &what, at)
        };
        for (i, s) in group.sphere.iter().enumerate() {
            let r = s.radius.get();
            let mut transform = s.transform.clone();
            let shape = if s.z_min.is_some() || s.z_max.is_some() || s.phi_max.is_some() {
                // pbrt-v4's sphere is defined at its origin: the centre
                // becomes a translation, applied first.
                if s.center.0 != [0.0; 3] {
                    transform.insert(0, TransformOp::Translate(s.center));
                }
                let z = |v: Option<Finite>, d: f32| v.map_or(d, Finite::get);
                Sphere::partial(r, z(s.z_min, -r), z(s.z_max, r), z(s.phi_max, 360.0))
            } else {
                Sphere::new(s.center.into(), r)
            };
            let keys = SurfaceKeys::of(s.emission, s.two_sided, s.reverse_orientation, &s.emission_texture)
                .with_media(&s.medium_inside, &s.medium_outside);
            let obj = Object::new("sphere", i, &s.name, &s.material, &transform, &s.alpha, keys);
            add(ctx, obj, shape.map(Shape::from), scene)?;
        }
        for (i, d) in group.disk.iter().enumerate() {
            let phi = d.phi_max.map_or(360.0, Finite::get);
            let shape = Disk::new(d.height.get(), d.radius.get(), d.inner_radius.get(), phi).map(Shape::from);
            let keys = SurfaceKeys::of(d.emission, d.two_sided, d.reverse_orientation, &d.emission_texture)
                .with_media(&d.medium_inside, &d.medium_outside);
            add(ctx, Object::new("disk", i, &d.name, &d.material, &d.transform, &d.alpha, keys), shape, scene)?;
        }
        for (i, c) in group.cylinder.iter().enumerate() {
            let phi = c.phi_max.map_or(360.0, Finite::get);
            let shape = Cylinder::new(c.radius.get(), c.z_min.get(), c.z_max.get(), phi).map(Shape::from);
            let keys = SurfaceKeys::of(c.emission, c.two_sided, c.reverse_orientation, &c.emission_texture)
                .with_media(&c.medium_inside, &c.medium_outside);
            add(ctx, Object::new("cylinder", i, &c.name, &c.material, &c.transform, &c.alpha, keys), shape, scene)?;
        }
        for (i, p) in group.plane.iter().enumerate() {
            let shape = Plane::new(p.point.into(), p.normal.into()).map(Shape::from);
            let keys = SurfaceKeys::default().with_media(&p.medium_inside, &p.medium_outside);
            add(ctx, Object::new("plane", i, &p.name, &p.material, &p.transform, &p.alpha, keys), shape, scene)?;
        }
        for (i, t) in group.triangle.iter().enumerate() {
            let v = t.vertices.map(Vec3::from);
            let n = t.normals.map(|n| n.map(Vec3::from));
            let shape = Triangle::new(v, n).map(Shape::from);
            let keys = SurfaceKeys::of(t.emission, t.two_sided, t.reverse_orientation, &t.emission_texture)
                .with_media(&t.medium_inside, &t.medium_outside);
            let obj = Object::new("triangle", i, &t.name, &t.material, &t.transform, &t.alpha, keys);
            add(ctx, obj, shape, scene)?;
        }
        for (i, q) in group.quad.iter().enumerate() {
            let keys = SurfaceKeys::of(q.emission, q.two_sided, q.reverse_orientation, &q.emission_texture)
                .with_media(&q.medium_inside, &q.medium_outside);
            let obj = Object::new("quad", i, &q.name, &q.material, &q.transform, &q.alpha, keys);
            match quad_triangles(q.vertices.map(Vec3::from)) {
                Ok([a, b]) => {
                    add(ctx, obj, Ok(a), scene)?;
                    add(ctx, obj, Ok(b), scene)?;
                }
                Err(e) => add(ctx, obj, Err(e), scene)?,
            }
        }
        for (i, m) in group.mesh.iter().enumerate() {
            let what = describe(label, "mesh", i, &m.name);
            let at = locate("mesh", i);
            let (mesh, file_materials) = self.mesh(scene, ctx, m, &what, at)?;
            let t = self.transform(&m.transform, &what, at)?.then(&group_transform);
            let explicit = forced_material.or(m.material.as_deref());
            let primitive = match (explicit, file_materials) {
                (None, Some(table)) => {
                    // The file's own materials; a face without one falls back
                    // to the group's material, or the file's first.
                    let fallback = match material {
                        Some(name) => self.material_id(ctx, &what, name)?,
                        None => table[0],
                    };
                    Primitive::new(Shape::Mesh(mesh), t, fallback).with_face_materials(table)
                }
                _ => Primitive::new(Shape::Mesh(mesh), t, resolve(ctx, &what, m.material.as_deref(), at)?),
            };
            let primitive = self.with_alpha(ctx, primitive, &m.alpha, &what, at)?;
            let keys = SurfaceKeys::of(m.emission, m.two_sided, m.reverse_orientation, &m.emission_texture)
                .with_media(&m.medium_inside, &m.medium_outside);
            self.place(scene, ctx, primitive, keys, &what, at)?;
        }
        for (i, g) in group.group.iter().enumerate() {
            let child_label = describe(label, "group", i, &g.name);
            let child_at = locate("group", i);
            let place = Place { label: &child_label, at: child_at, forced_material };
            self.add_group(scene, ctx, g, group_transform, material, place)?;
        }
        for (i, inst) in group.instance.iter().enumerate() {
            let what = describe(label, "instance", i, &inst.name);
            let at = locate("instance", i);
            let Some(prototype) = self.description.prototypes.get(&inst.prototype) else {
                let known: Vec<&str> = self.description.prototypes.keys().map(String::as_str).collect();
                let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
                return Err(self.error(
                    find_value(&self.source, "prototype", &inst.prototype).or(at),
                    format!("{what}: prototype \"{}\" is not defined (defined: {known})", inst.prototype),
                ));
            };
            if ctx.active_prototypes.contains(&inst.prototype) {
                return Err(self.error(at, format!("{what}: prototype \"{}\" contains itself", inst.prototype)));
            }
            let t = self.transform(&inst.transform, &what, at)?.then(&group_transform);
            let child_label = format!("{what} of \"{}\"", inst.prototype);
            let forced = forced_material.or(inst.material.as_deref());
            ctx.active_prototypes.push(inst.prototype.clone());
            let place = Place { label: &child_label, at, forced_material: forced };
            let result = self.add_group(scene, ctx, prototype, t, material, place);
            ctx.active_prototypes.pop();
            result?;
        }
        Ok(())
    }

    /// Add a primitive to the scene, as an area light when it emits, turned
    /// inside out by `reverse_orientation`.
    fn place(
        &self,
        scene: &mut SceneBuilder,
        ctx: &mut BuildContext<'_>,
        primitive: Primitive,
        keys: SurfaceKeys<'_>,
        what: &str,
        at: Option<SourceLocation>,
    ) -> Result<(), SceneError> {
        let SurfaceKeys { emission, two_sided, reverse, texture, medium_inside, medium_outside } = keys;
        let mut media = crate::medium::MediumInterface::NONE;
        for (name, side, key) in [
            (medium_inside, &mut media.inside, "medium_inside"),
            (medium_outside, &mut media.outside, "medium_outside"),
        ] {
            if let Some(name) = name {
                *side = Some(ctx.media.get(name).copied().ok_or_else(|| {
                    let mut known: Vec<&str> = ctx.media.keys().map(String::as_str).collect();
                    known.sort_unstable();
                    let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
                    self.error(
                        find_value(&self.source, key, name).or(at),
                        format!("{what}: medium \"{name}\" is not defined under [media] (defined: {known})"),
                    )
                })?);
            }
        }
        let emission = match emission {
            Some(radiance) => {
                let image = match texture {
                    Some(name) => Some(
                        ctx.textures
                            .color_named(name, what)
                            .map(|t| (*t).clone())
                            .map_err(|e| self.error(find_value(&self.source, "emission_texture", name).or(at), e))?,
                    ),
                    None => None,
                };
                Some(Emission { radiance: radiance.into(), two_sided, reverse, image })
            }
            None if two_sided || texture.is_some() => {
                let key = if two_sided { "two_sided" } else { "emission_texture" };
                return Err(self.error(at, format!("{what}: `{key}` applies only with `emission`")));
            }
            None => None,
        };
        let primitive = primitive.with_reverse_orientation(reverse).with_media(media);
        let at = if emission.is_some() { find_key_after(&self.source, "emission", at).or(at) } else { at };
        scene.add(primitive, emission).map_err(|e| e.in_file(self.path.clone(), &self.source, at, what))?;
        Ok(())
    }

    /// `primitive` with the cut-out of an `alpha` key, if given.
    fn with_alpha(
        &self,
        ctx: &mut BuildContext<'_>,
        primitive: Primitive,
        alpha: &Option<TexValue>,
        what: &str,
        at: Option<SourceLocation>,
    ) -> Result<Primitive, SceneError> {
        let Some(alpha) = alpha else { return Ok(primitive) };
        let texture = ctx.textures.float(alpha, &format!("{what}: alpha")).map_err(|e| {
            let at = match alpha {
                TexValue::Name(name) => find_value(&self.source, "alpha", name).or(at),
                _ => find_key_after(&self.source, "alpha", at).or(at),
            };
            self.error(at, e)
        })?;
        Ok(primitive.with_alpha(texture))
    }

    fn material_id(&self, ctx: &BuildContext<'_>, what: &str, name: &str) -> Result<MaterialId, SceneError> {
        ctx.ids.get(name).copied().ok_or_else(|| {
            let mut known: Vec<&str> = ctx.ids.keys().map(String::as_str).filter(|k| !k.contains(':')).collect();
            known.sort_unstable();
            let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
            self.error(
                find_value(&self.source, "material", name),
                format!("{what}: material \"{name}\" is not defined (defined: {known})"),
            )
        })
    }

    /// Load (once) the mesh a `[[mesh]]` refers to; returns it with the
    /// scene materials made from the file's own materials, if it has any.
    fn mesh(
        &self,
        scene: &mut SceneBuilder,
        ctx: &mut BuildContext<'_>,
        m: &MeshDesc,
        what: &str,
        at: Option<SourceLocation>,
    ) -> Result<LoadedMesh, SceneError> {
        let (file, normals, default_uv) = match (&m.mesh, &m.file) {
            (Some(name), None) => {
                if m.normals.is_some() {
                    return Err(
                        self.error(at, format!("{what}: `normals` belongs to [meshes.{name}], not to a placement"))
                    );
                }
                let def = self.description.meshes.get(name).ok_or_else(|| {
                    let known: Vec<&str> = self.description.meshes.keys().map(String::as_str).collect();
                    let known = if known.is_empty() { "none".to_owned() } else { known.join(", ") };
                    self.error(
                        find_value(&self.source, "mesh", name).or(at),
                        format!("{what}: mesh \"{name}\" is not defined under [meshes] (defined: {known})"),
                    )
                })?;
                if m.default_uv.is_some() {
                    return Err(
                        self.error(at, format!("{what}: `default_uv` belongs to [meshes.{name}], not to a placement"))
                    );
                }
                (def.file.as_str(), def.normals, def.default_uv)
            }
            (None, Some(file)) => (file.as_str(), m.normals.unwrap_or_default(), m.default_uv.unwrap_or_default()),
            _ => return Err(self.error(at, format!("{what}: give either `mesh` (a name under [meshes]) or `file`"))),
        };
        let path = self.relative(file);
        let key = (path.clone(), normals, default_uv);
        if let Some(found) = ctx.meshes.get(&key) {
            return Ok(found.clone());
        }
        let file_at = find_value(&self.source, "file", file).or(at);
        let mut data = crate::mesh::load_mesh(&path).map_err(|e| self.error(file_at, format!("{what}: {e}")))?;
        match normals {
            NormalsDesc::File => {}
            NormalsDesc::Smooth => data.compute_smooth_normals(),
            NormalsDesc::Flat => data.normals = None,
        }
        let file_materials = if data.materials.is_empty() || data.material_ids.is_none() {
            None
        } else {
            let mut table: Vec<MaterialId> = Vec::with_capacity(data.materials.len());
            for mm in &data.materials {
                let key = format!("{file}:{}", mm.name);
                let id = match ctx.ids.get(&key) {
                    Some(&id) => id,
                    None => {
                        let id = scene
                            .add_material(material_from_file(mm))
                            .map_err(|e| e.in_file(self.path.clone(), &self.source, file_at, what))?;
                        ctx.ids.insert(key, id);
                        id
                    }
                };
                table.push(id);
            }
            Some(Arc::from(table))
        };
        let mesh = Mesh::new(data).map_err(|e| self.error(file_at, format!("{what}: {e}")))?.with_default_uv(
            match default_uv {
                DefaultUvDesc::Barycentric => DefaultUv::Barycentric,
                DefaultUvDesc::Pbrt => DefaultUv::Pbrt,
            },
        );
        if mesh.degenerate_count() > 0 {
            scene.warn(format!(
                "{}: {} zero-area triangle{} skipped",
                path.display(),
                mesh.degenerate_count(),
                if mesh.degenerate_count() == 1 { "" } else { "s" }
            ));
        }
        let entry = (Arc::new(mesh), file_materials);
        ctx.meshes.insert(key, entry.clone());
        Ok(entry)
    }

    /// The transform of `ops`. Scales and matrices are checked as they are
    /// read; what can still fail here (a rotation about an axis too long to
    /// normalise) is reported at `at`, the object's table.
    pub(super) fn transform(
        &self,
        ops: &[TransformOp],
        what: &str,
        at: Option<SourceLocation>,
    ) -> Result<Transform, SceneError> {
        let mut t = Transform::IDENTITY;
        for op in ops {
            let step = op.to_transform();
            let step = step.map_err(|e| {
                let what = if what.is_empty() { "transform".to_owned() } else { format!("{what}: transform") };
                self.error(at, format!("{what}: {}", transform_error_message(&e)))
            })?;
            t = t.then(&step);
        }
        Ok(t)
    }
}

/// Where a group is, for messages: its label (`group #1 > group "arm"`,
/// empty for the scene's root) and the location of the top-level `[[group]]`
/// that holds it.
#[derive(Clone, Copy)]
pub(super) struct Place<'a> {
    pub(super) label: &'a str,
    pub(super) at: Option<SourceLocation>,
    /// An instance's material, replacing every member's.
    pub(super) forced_material: Option<&'a str>,
}

/// The keys every object kind shares, for [`SceneFile::add_group`].
#[derive(Clone, Copy)]
struct Object<'a> {
    kind: &'static str,
    index: usize,
    name: &'a Option<String>,
    material: &'a Option<String>,
    transform: &'a [TransformOp],
    alpha: &'a Option<TexValue>,
    emission: SurfaceKeys<'a>,
}

/// The keys of an object about its surface: emission, orientation and
/// the media on its two sides.
#[derive(Clone, Copy, Default)]
pub(super) struct SurfaceKeys<'a> {
    emission: Option<Rgb>,
    two_sided: bool,
    reverse: bool,
    texture: Option<&'a str>,
    medium_inside: Option<&'a str>,
    medium_outside: Option<&'a str>,
}

impl<'a> SurfaceKeys<'a> {
    fn of(emission: Option<Rgb>, two_sided: bool, reverse: bool, texture: &'a Option<String>) -> Self {
        Self { emission, two_sided, reverse, texture: texture.as_deref(), ..Self::default() }
    }

    fn with_media(self, inside: &'a Option<String>, outside: &'a Option<String>) -> Self {
        Self { medium_inside: inside.as_deref(), medium_outside: outside.as_deref(), ..self }
    }
}

impl<'a> Object<'a> {
    fn new(
        kind: &'static str,
        index: usize,
        name: &'a Option<String>,
        material: &'a Option<String>,
        transform: &'a [TransformOp],
        alpha: &'a Option<TexValue>,
        emission: SurfaceKeys<'a>,
    ) -> Self {
        Self { kind, index, name, material, transform, alpha, emission }
    }
}

/// A quad as its two triangles, (v0, v1, v2) and (v0, v2, v3): separate
/// primitives in the top-level BVH (cheaper to intersect than a two-triangle
/// mesh with its own BVH), watertight along the shared diagonal.
fn quad_triangles(v: [Vec3; 4]) -> Result<[Shape; 2], crate::shapes::ShapeError> {
    Ok([Triangle::new([v[0], v[1], v[2]], None)?.into(), Triangle::new([v[0], v[2], v[3]], None)?.into()])
}

/// A mesh ready to place, with the scene materials of the file's own
/// materials (by mesh-local index), if it has any.
pub(super) type LoadedMesh = (Arc<Mesh>, Option<Arc<[MaterialId]>>);

/// State carried through the walk over groups and prototypes.
pub(super) struct BuildContext<'a> {
    /// Material names (scene materials, and `FILE:NAME` for a mesh file's
    /// own) to scene handles.
    pub(super) ids: HashMap<String, MaterialId>,
    /// Meshes loaded so far, by path and normals mode: each file is read and
    /// built once however often it is placed.
    pub(super) meshes: HashMap<(PathBuf, NormalsDesc, DefaultUvDesc), LoadedMesh>,
    /// Prototypes being expanded, to refuse one that contains itself.
    pub(super) active_prototypes: Vec<String>,
    /// The `[textures]`, for `alpha` and `emission_texture`.
    pub(super) textures: TextureTable<'a>,
    /// The `[media]` by name.
    pub(super) media: HashMap<String, crate::medium::MediumId>,
}

fn describe(parent: &str, kind: &str, index: usize, name: &Option<String>) -> String {
    let own = match name {
        Some(n) => format!("{kind} \"{n}\""),
        None => format!("{kind} #{}", index + 1),
    };
    if parent.is_empty() {
        own
    } else {
        format!("{parent} > {own}")
    }
}
