//! `Shape` (and the area light it may carry): pbrt-v4's shapes as lucent
//! primitives.
//!
//! Triangle meshes (`trianglemesh`, `plymesh`, `loopsubdiv` after
//! subdivision, `bilinearmesh`) become shared [`Mesh`]es; quadrics
//! (`sphere`, `disk`, `cylinder`) lucent's own shapes. An emissive shape
//! becomes a diffuse area light on the side pbrt-v4 emits from: the side
//! of the shape's normal, flipped by `ReverseOrientation`; for meshes with
//! per-vertex normals `N`, the side those normals point to (pbrt-v4 makes
//! the geometric normal face the shading normal).
//!
//! `ReverseOrientation` turns every shape created under it inside out, as
//! in pbrt-v4: a quadric's normal is negated at each hit (`flipNormal`), a
//! triangle mesh's vertex normals `N` are negated when it is created and
//! its geometric normal follows them (or, without `N`, is negated). lucent
//! does both through [`Primitive::with_reverse_orientation`], which
//! negates the geometric and the shading normal of every hit: the side a
//! dielectric calls outside, and so whether a ray enters or leaves it.

use super::builder_error;
use super::{AreaLightSpec, Importer};
use crate::geometry::{Transform, Vec2, Vec3};
use crate::loader::pbrt::{Loc, ParamList, PbrtError};
use crate::material::MaterialId;
use crate::mesh::TriangleMesh;
use crate::primitive::Primitive;
use crate::scene::Emission;
use crate::shapes::{DefaultUv, Mesh, Shape, Sphere};
use std::sync::Arc;

impl Importer<'_> {
    /// The current material, made on first use: pbrt-v4's default is
    /// `diffuse` with reflectance 0.5.
    pub fn current_material(&mut self, loc: &Loc) -> Result<MaterialId, PbrtError> {
        if let Some(id) = self.state.material {
            return Ok(id);
        }
        let id = match self.materials.default {
            Some(id) => id,
            None => {
                let id = self.material("diffuse", &ParamList::default(), loc)?;
                self.materials.default = Some(id);
                id
            }
        };
        self.state.material = Some(id);
        Ok(id)
    }

    /// Handle a `Shape` directive.
    pub fn shape(&mut self, ty: &str, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        let material = self.current_material(loc)?;
        let transform = self.state.ctm;
        let area = self.state.area_light.clone();
        let reverse = self.state.reverse_orientation;
        let alpha = self.alpha(params, loc)?;
        let shape: Shape = match ty {
            "trianglemesh" => {
                let mesh = self.triangle_mesh(params, loc)?;
                self.mesh_shape(mesh, transform, area.as_ref(), loc)?
            }
            "plymesh" => {
                let name = params
                    .string("filename")?
                    .ok_or_else(|| PbrtError::at(loc, "Shape \"plymesh\" needs a \"string filename\""))?;
                let path = self.resolve(name, &super::spectra::param_loc(params, "filename", loc));
                if params.get("displacement").is_some() || params.get("edgelength").is_some() {
                    self.warnings
                        .warn(loc, "plymesh displacement is not supported: the mesh is rendered undisplaced")?;
                }
                let mesh = crate::mesh::load_ply(&path)
                    .map_err(|e| PbrtError::at(&super::spectra::param_loc(params, "filename", loc), e.to_string()))?;
                self.files.push(path);
                self.mesh_shape(mesh, transform, area.as_ref(), loc)?
            }
            "loopsubdiv" => {
                let levels = params.int("levels")?.unwrap_or(3);
                if !(0..=8).contains(&levels) {
                    return Err(PbrtError::at(
                        loc,
                        format!("loopsubdiv: \"integer levels\" must be from 0 to 8, got {levels}"),
                    ));
                }
                let (positions, indices) = self.positions_and_indices(params, loc, "loopsubdiv")?;
                let mesh = crate::mesh::loop_subdivide(&positions, &indices, levels as u32)
                    .map_err(|e| PbrtError::at(loc, format!("loopsubdiv: {}", e.message)))?;
                self.mesh_shape(mesh, transform, area.as_ref(), loc)?
            }
            "bilinearmesh" => {
                let positions =
                    params.point3s("P")?.ok_or_else(|| PbrtError::at(loc, "bilinearmesh needs \"point3 P\""))?;
                let indices: Vec<u32> = match params.ints("indices")? {
                    Some(i) => self.indices(i, positions.len(), 4, loc, "bilinearmesh")?,
                    None if positions.len() == 4 => vec![0, 1, 2, 3],
                    None => {
                        return Err(PbrtError::at(
                            loc,
                            "bilinearmesh with more than 4 vertices needs \"integer indices\"",
                        ))
                    }
                };
                let uvs = params.point2s("uv")?;
                let normals = params.normals("N")?;
                let quads: Vec<[u32; 4]> = indices.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
                let mesh = crate::mesh::bilinear_patches(&positions, &quads, uvs.as_deref(), normals.as_deref())
                    .map_err(|e| PbrtError::at(loc, format!("bilinearmesh: {}", e.message)))?;
                self.mesh_shape(mesh, transform, area.as_ref(), loc)?
            }
            "sphere" => {
                let radius = positive(params, "radius", 1.0, loc)?;
                let zmin = params.float("zmin")?.unwrap_or(-radius);
                let zmax = params.float("zmax")?.unwrap_or(radius);
                let phimax = params.float("phimax")?.unwrap_or(360.0);
                // pbrt's parameterisation (z up), clipped or not.
                Shape::from(
                    Sphere::partial(radius, zmin, zmax, phimax)
                        .map_err(|e| PbrtError::at(loc, format!("sphere: {e}")))?,
                )
            }
            "disk" => {
                let height = params.float("height")?.unwrap_or(0.0);
                let radius = positive(params, "radius", 1.0, loc)?;
                let inner = params.float("innerradius")?.unwrap_or(0.0);
                let phimax = params.float("phimax")?.unwrap_or(360.0);
                Shape::from(
                    crate::shapes::Disk::new(height, radius, inner, phimax)
                        .map_err(|e| PbrtError::at(loc, format!("disk: {e}")))?,
                )
            }
            "cylinder" => {
                let radius = positive(params, "radius", 1.0, loc)?;
                let zmin = params.float("zmin")?.unwrap_or(-1.0);
                let zmax = params.float("zmax")?.unwrap_or(1.0);
                let phimax = params.float("phimax")?.unwrap_or(360.0);
                Shape::from(
                    crate::shapes::Cylinder::new(radius, zmin, zmax, phimax)
                        .map_err(|e| PbrtError::at(loc, format!("cylinder: {e}")))?,
                )
            }
            "curve" => {
                for p in &params.params {
                    p.used.set(true);
                }
                return self.warnings.warn_once("curve", loc, "Shape \"curve\" is not supported: curves are skipped");
            }
            other => {
                for p in &params.params {
                    p.used.set(true);
                }
                return self.warnings.warn(
                    loc,
                    format!("unknown Shape \"{other}\" is skipped (supported: trianglemesh, plymesh, loopsubdiv, bilinearmesh, sphere, disk, cylinder)"),
                );
            }
        };
        // Meshes are oriented face by face above, as if not reversed; every
        // shape then emits from its front (normal side), or from its back
        // under ReverseOrientation. A quadric's normal is also turned by a
        // transform that mirrors (pbrt-v4's flipNormal = ReverseOrientation
        // ^ transformSwapsHandedness); a triangle's is not, since its
        // winding turns too.
        let mirrored = transform.matrix().determinant() < 0.0;
        let reverse = reverse ^ (mirrored && !matches!(shape, Shape::Mesh(_)));
        let emission = area.as_ref().map(|a| Emission {
            radiance: a.radiance,
            two_sided: a.two_sided,
            reverse,
            image: a.image.clone(),
        });
        let media = self.current_media(loc)?;
        let mut primitive =
            Primitive::new(shape, transform, material).with_reverse_orientation(reverse).with_media(media);
        if let Some(alpha) = alpha {
            primitive = primitive.with_alpha(alpha);
        }
        self.builder.add(primitive, emission).map_err(|e| builder_error(loc, e))?;
        Ok(())
    }

    /// The `alpha` parameter: a float or a float texture; `None` when the
    /// surface is opaque.
    fn alpha(&mut self, params: &ParamList, loc: &Loc) -> Result<Option<crate::texture::FloatTexture>, PbrtError> {
        if params.get("alpha").is_none() {
            return Ok(None);
        }
        let alpha = self.float_texture(params, "alpha", 1.0, loc)?;
        Ok(match alpha {
            crate::texture::FloatTexture::Constant(a) if a >= 1.0 => None,
            other => Some(other),
        })
    }

    /// A mesh shape, its faces oriented so that their winding gives the
    /// side an area light emits from when the mesh is not reversed.
    fn mesh_shape(
        &mut self,
        mut mesh: TriangleMesh,
        transform: Transform,
        area: Option<&AreaLightSpec>,
        loc: &Loc,
    ) -> Result<Shape, PbrtError> {
        if area.is_some_and(|a| !a.two_sided) {
            orient_for_emission(&mut mesh, transform.matrix().determinant() < 0.0);
        }
        let mesh = Mesh::new(mesh).map_err(|e| PbrtError::at(loc, e.to_string()))?.with_default_uv(DefaultUv::Pbrt);
        Ok(Shape::Mesh(Arc::new(mesh)))
    }

    /// `P` and `indices` of a mesh (indices may be omitted for a single
    /// triangle).
    fn positions_and_indices(
        &mut self,
        params: &ParamList,
        loc: &Loc,
        what: &str,
    ) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), PbrtError> {
        let positions = params.point3s("P")?.ok_or_else(|| PbrtError::at(loc, format!("{what} needs \"point3 P\"")))?;
        let flat = match params.ints("indices")? {
            Some(i) => self.indices(i, positions.len(), 3, loc, what)?,
            None if positions.len() == 3 => vec![0, 1, 2],
            None => {
                return Err(PbrtError::at(
                    loc,
                    format!(
                        "{what} with {} vertices needs \"integer indices\" (only a single triangle may omit them)",
                        positions.len()
                    ),
                ))
            }
        };
        let indices = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Ok((positions, indices))
    }

    /// Check an index list: a multiple of `per` long, each index a vertex.
    fn indices(
        &mut self,
        i: &[i32],
        vertices: usize,
        per: usize,
        loc: &Loc,
        what: &str,
    ) -> Result<Vec<u32>, PbrtError> {
        if !i.len().is_multiple_of(per) {
            return Err(PbrtError::at(
                loc,
                format!("{what}: \"integer indices\" has {} values, not a multiple of {per}", i.len()),
            ));
        }
        i.iter()
            .map(|&v| {
                if v >= 0 && (v as usize) < vertices {
                    Ok(v as u32)
                } else {
                    Err(PbrtError::at(
                        loc,
                        format!("{what}: index {v} is out of range (the mesh has {vertices} vertices)"),
                    ))
                }
            })
            .collect()
    }

    /// A `trianglemesh`: `P`, `indices`, and optional `N`, `uv`.
    fn triangle_mesh(&mut self, params: &ParamList, loc: &Loc) -> Result<TriangleMesh, PbrtError> {
        let (positions, indices) = self.positions_and_indices(params, loc, "trianglemesh")?;
        let n = positions.len();
        let normals = params.normals("N")?;
        if let Some(normals) = &normals {
            if normals.len() != n {
                return Err(PbrtError::at(loc, format!("trianglemesh: {} normals for {n} vertices", normals.len())));
            }
        }
        let uvs: Option<Vec<Vec2>> = match params.point2s("uv")? {
            Some(uv) => Some(uv),
            None => params.point2s("st")?,
        };
        if let Some(uvs) = &uvs {
            if uvs.len() != n {
                return Err(PbrtError::at(loc, format!("trianglemesh: {} uv coordinates for {n} vertices", uvs.len())));
            }
        }
        if params.get("S").is_some() {
            let _ = params.get("S");
            self.warnings.warn_once(
                "tangents",
                loc,
                "per-vertex tangents \"S\" are ignored (computed from uv instead)",
            )?;
        }
        if params.get("faceIndices").is_some() {
            let _ = params.ints("faceIndices")?;
        }
        Ok(TriangleMesh {
            positions,
            indices,
            normals: normals.map(|n| n.into_iter().map(|v| v.normalize_or_zero()).collect()),
            uvs,
            ..TriangleMesh::default()
        })
    }
}

/// A positive float parameter.
fn positive(params: &ParamList, name: &str, default: f32, loc: &Loc) -> Result<f32, PbrtError> {
    let v = params.float(name)?.unwrap_or(default);
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(PbrtError::at(
            &super::spectra::param_loc(params, name, loc),
            format!("\"float {name}\" must be a positive number, got {v}"),
        ))
    }
}

/// Reorder the corners of an emissive mesh's faces so that the winding
/// (after a transform that mirrors when `mirrored`) points to the side
/// pbrt-v4 emits from when the mesh is not reversed: the per-vertex
/// normals' side when there are normals, else the winding's own side.
/// (Under `ReverseOrientation` the light emits from the other side:
/// [`Emission::reverse`].)
fn orient_for_emission(mesh: &mut TriangleMesh, mirrored: bool) {
    for face in &mut mesh.indices {
        let [a, b, c] = face.map(|i| i as usize);
        let (p0, p1, p2) = (mesh.positions[a], mesh.positions[b], mesh.positions[c]);
        let winding = (p1 - p0).cross(p2 - p0);
        let wanted = match &mesh.normals {
            Some(n) => n[a] + n[b] + n[c],
            None => winding,
        };
        // A mirroring transform turns the winding of the world-space copy
        // against the object-space one, while normals keep their side.
        let agrees = (winding.dot(wanted) >= 0.0) != mirrored;
        if !agrees {
            face.swap(1, 2);
        }
    }
}
