//! Objects: shapes, meshes, groups, prototypes and instances, and their
//! transforms.

use super::super::values::*;
use super::TexValue;
use super::{default_up, positive_one};
use serde::{de::Error as _, Deserialize, Deserializer, Serialize};

/// Defines the struct of an object table: the given fields plus those every
/// object has (`name` and `transform`), written once
/// here. (`#[serde(flatten)]` would share them as a struct, but serde does
/// not allow it together with `deny_unknown_fields`.)
macro_rules! object {
    ($(#[$doc:meta])* pub struct $name:ident { $($(#[$fdoc:meta])* pub $field:ident: $ty:ty,)* }) => {
        $(#[$doc])*
        #[derive(Clone, Debug, Deserialize, Serialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            /// Optional name for messages.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub name: Option<String>,
            $($(#[$fdoc])* pub $field: $ty,)*
            /// Object transform.
            #[serde(default, skip_serializing_if = "Vec::is_empty")]
            pub transform: Vec<TransformOp>,
            /// Alpha cut-out: a number or a texture; where it is 0 the
            /// surface does not exist, for camera and shadow rays alike.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub alpha: Option<TexValue>,
            /// The medium (a name under `[media]`) on the inside of the
            /// surface, the side opposite its normal (default: none).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub medium_inside: Option<String>,
            /// The medium on the outside, the normal's side (default:
            /// none).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub medium_outside: Option<String>,
        }
    };
}

/// [`object!`] for a surface that may emit light: adds `emission`,
/// `two_sided`, `reverse_orientation` and `emission_texture`.
macro_rules! emissive_object {
    ($(#[$doc:meta])* pub struct $name:ident { $($(#[$fdoc:meta])* pub $field:ident: $ty:ty,)* }) => {
        object! {
            $(#[$doc])*
            pub struct $name {
                $($(#[$fdoc])* pub $field: $ty,)*
                /// Emitted radiance: the surface becomes an area light.
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub emission: Option<Rgb>,
                /// Whether an emitting surface emits from both sides
                /// (default: front only).
                #[serde(default, skip_serializing_if = "std::ops::Not::not")]
                pub two_sided: bool,
                /// Whether the surface is turned inside out (pbrt-v4's
                /// `ReverseOrientation`; default false): its normals are
                /// negated, so a dielectric's outside is the other side,
                /// and a one-sided emitter emits from its back.
                #[serde(default, skip_serializing_if = "std::ops::Not::not")]
                pub reverse_orientation: bool,
                /// A colour texture (a name under `[textures]`) that
                /// multiplies `emission` over the surface, by its texture
                /// coordinates.
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub emission_texture: Option<String>,
            }
        }
    };
}

/// One step of a transform list; the list is applied in the order written.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TransformOp {
    /// Move by `[x, y, z]`.
    Translate(Vec3Desc),
    /// Scale by `[x, y, z]` (no zero components).
    Scale(#[serde(deserialize_with = "nonzero_scale")] Vec3Desc),
    /// Rotate about x, degrees.
    RotateX(Finite),
    /// Rotate about y, degrees.
    RotateY(Finite),
    /// Rotate about z, degrees.
    RotateZ(Finite),
    /// Rotate about an axis.
    Rotate(AxisAngle),
    /// A general affine matrix, four rows of four, acting on column vectors.
    Matrix(#[serde(deserialize_with = "affine_matrix")] [[f32; 4]; 4]),
    /// A matrix with its inverse, as `lucent convert` writes transforms so
    /// that they read back bit for bit.
    Affine(AffineDesc),
}

/// `{ affine = { matrix = [...], inverse = [...] } }`: an affine matrix
/// with its inverse (each four rows of four).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AffineDesc {
    /// The matrix.
    #[serde(deserialize_with = "affine_matrix")]
    pub matrix: [[f32; 4]; 4],
    /// Its inverse.
    #[serde(deserialize_with = "affine_matrix")]
    pub inverse: [[f32; 4]; 4],
}

impl TransformOp {
    /// The transform of this step.
    pub fn to_transform(&self) -> Result<crate::geometry::Transform, crate::geometry::TransformError> {
        use crate::geometry::Transform;
        let rows = |r: &[[f32; 4]; 4]| glam::Mat4::from_cols_array_2d(r).transpose();
        match self {
            TransformOp::Translate(v) => Ok(Transform::translate((*v).into())),
            TransformOp::Scale(v) => Transform::scale((*v).into()),
            TransformOp::RotateX(a) => Ok(Transform::rotate_x(a.get())),
            TransformOp::RotateY(a) => Ok(Transform::rotate_y(a.get())),
            TransformOp::RotateZ(a) => Ok(Transform::rotate_z(a.get())),
            TransformOp::Rotate(aa) => Transform::rotate(aa.axis.into(), aa.angle.get()),
            TransformOp::Matrix(m) => Transform::from_matrix(rows(m)),
            TransformOp::Affine(a) => Transform::from_matrix_and_inverse(rows(&a.matrix), rows(&a.inverse)),
        }
    }
}

// Transforms and triangles are checked as they are read, like other values,
// so that the error points at the offending value even inside a group.

fn nonzero_scale<'de, D: Deserializer<'de>>(d: D) -> Result<Vec3Desc, D::Error> {
    let v = Vec3Desc::deserialize(d)?;
    if v.0.contains(&0.0) {
        return Err(D::Error::custom(format!(
            "scale {v} has a zero component: the transform would be singular (it flattens the object, which \
             cannot be undone); use non-zero factors"
        )));
    }
    Ok(v)
}

fn affine_matrix<'de, D: Deserializer<'de>>(d: D) -> Result<[[f32; 4]; 4], D::Error> {
    let rows = <[[Finite; 4]; 4]>::deserialize(d)?.map(|r| r.map(Finite::get));
    crate::geometry::Transform::from_matrix(glam::Mat4::from_cols_array_2d(&rows).transpose())
        .map_err(|e| D::Error::custom(transform_error_message(&e)))?;
    Ok(rows)
}

/// A user-facing message for a transform that cannot be used.
pub(crate) fn transform_error_message(e: &crate::geometry::TransformError) -> String {
    match e {
        crate::geometry::TransformError::Singular(det) => format!(
            "the transform is singular (determinant {det}): it collapses an axis, which cannot be undone; \
             scale factors must be non-zero and matrix columns independent"
        ),
        other => other.to_string(),
    }
}

fn triangle_corners<'de, D: Deserializer<'de>>(d: D) -> Result<[Vec3Desc; 3], D::Error> {
    let v = <[Vec3Desc; 3]>::deserialize(d)?;
    crate::shapes::Triangle::new(v.map(glam::Vec3A::from), None).map_err(D::Error::custom)?;
    Ok(v)
}

/// Axis and angle of a general rotation.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AxisAngle {
    /// Rotation axis.
    pub axis: Direction,
    /// Angle in degrees (right-handed about the axis).
    pub angle: Finite,
}

emissive_object! {
    /// A `[[sphere]]`.
    pub struct SphereDesc {
        /// Centre (default origin).
        #[serde(default = "origin")]
        pub center: Vec3Desc,
        /// Radius (default 1).
        #[serde(default = "positive_one")]
        pub radius: Positive,
        /// Material name (default: the enclosing group's).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
        /// Clip below this height along the sphere's own `z` axis (default:
        /// `-radius`). Any of `z_min`, `z_max`, `phi_max` makes this
        /// pbrt-v4's sphere: `z` up, with pbrt's (u, v) parameterisation.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub z_min: Option<Finite>,
        /// Clip above this height (default: `radius`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub z_max: Option<Finite>,
        /// Keep the azimuths `0 ≤ φ ≤ phi_max` degrees about `z` (default 360).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub phi_max: Option<Finite>,
    }
}

emissive_object! {
    /// A `[[disk]]`: pbrt-v4's disk, an annulus sector in the plane
    /// `z = height` of its own space, facing `+z`.
    pub struct DiskDesc {
        /// Height along `z` (default 0).
        #[serde(default = "zero_finite")]
        pub height: Finite,
        /// Outer radius (default 1).
        #[serde(default = "positive_one")]
        pub radius: Positive,
        /// Inner radius (default 0).
        #[serde(default = "zero_non_negative")]
        pub inner_radius: NonNegative,
        /// Keep the azimuths `0 ≤ φ ≤ phi_max` degrees (default 360).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub phi_max: Option<Finite>,
        /// Material name (default: the enclosing group's).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
    }
}

emissive_object! {
    /// A `[[cylinder]]`: pbrt-v4's open cylinder about its own `z` axis.
    pub struct CylinderDesc {
        /// Radius (default 1).
        #[serde(default = "positive_one")]
        pub radius: Positive,
        /// Lower end along `z` (default -1).
        #[serde(default = "minus_one")]
        pub z_min: Finite,
        /// Upper end along `z` (default 1).
        #[serde(default = "positive_one_finite")]
        pub z_max: Finite,
        /// Keep the azimuths `0 ≤ φ ≤ phi_max` degrees (default 360).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub phi_max: Option<Finite>,
        /// Material name (default: the enclosing group's).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
    }
}

fn zero_finite() -> Finite {
    Finite(0.0)
}

fn zero_non_negative() -> NonNegative {
    NonNegative(0.0)
}

fn minus_one() -> Finite {
    Finite(-1.0)
}

fn positive_one_finite() -> Finite {
    Finite(1.0)
}

fn origin() -> Vec3Desc {
    Vec3Desc([0.0; 3])
}

object! {
    /// A `[[plane]]`.
    pub struct PlaneDesc {
        /// A point on the plane (default origin).
        #[serde(default = "origin")]
        pub point: Vec3Desc,
        /// Normal (default `[0, 1, 0]`).
        #[serde(default = "default_up")]
        pub normal: Direction,
        /// Material name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
    }
}

emissive_object! {
    /// A `[[triangle]]`.
    pub struct TriangleDesc {
        /// The three corners, counter-clockwise seen from the front.
        #[serde(deserialize_with = "triangle_corners")]
        pub vertices: [Vec3Desc; 3],
        /// Per-corner normals for smooth shading.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub normals: Option<[Direction; 3]>,
        /// Material name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
    }
}

emissive_object! {
    /// A `[[quad]]`: a planar quadrilateral, made of the two triangles
    /// (v0, v1, v2) and (v0, v2, v3).
    pub struct QuadDesc {
        /// The four corners in order around the quad, counter-clockwise seen
        /// from the front.
        pub vertices: [Vec3Desc; 4],
        /// Material name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
    }
}

/// A `[[group]]`: objects (and groups) sharing a transform.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GroupDesc {
    /// Optional name for messages.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Applied to every member, after the member's own transform.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub transform: Vec<TransformOp>,
    /// Default material of members that name none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Member spheres.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sphere: Vec<SphereDesc>,
    /// Member planes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub plane: Vec<PlaneDesc>,
    /// Member triangles.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub triangle: Vec<TriangleDesc>,
    /// Member quads.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub quad: Vec<QuadDesc>,
    /// Member disks.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub disk: Vec<DiskDesc>,
    /// Member cylinders.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cylinder: Vec<CylinderDesc>,
    /// Nested groups.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub group: Vec<GroupDesc>,
    /// Member meshes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mesh: Vec<MeshDesc>,
    /// Member placements of prototypes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub instance: Vec<InstanceDesc>,
}

/// How a mesh gets its shading normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NormalsDesc {
    /// The file's vertex normals if it has them, else flat shading.
    #[default]
    File,
    /// Computed smooth normals (angle-weighted), whatever the file has.
    Smooth,
    /// Flat shading: the geometric normal of each triangle.
    Flat,
}

/// A `[meshes.NAME]` table: a mesh file loaded once.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshFileDesc {
    /// Path of a `.ply` or `.obj` file, relative to the scene file.
    pub file: String,
    /// Shading normals (default `file`).
    #[serde(default, skip_serializing_if = "is_default")]
    pub normals: NormalsDesc,
    /// Texture coordinates of triangles without per-vertex uvs (default
    /// `barycentric`).
    #[serde(default, skip_serializing_if = "is_default")]
    pub default_uv: DefaultUvDesc,
}

/// How a triangle of a mesh without per-vertex texture coordinates is
/// parameterised.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum DefaultUvDesc {
    /// Corner uvs (0, 0), (1, 0), (0, 1): the barycentrics.
    #[default]
    Barycentric,
    /// Corner uvs (0, 0), (1, 0), (1, 1): pbrt-v4's.
    Pbrt,
}

pub(crate) fn is_default<T: Default + PartialEq>(v: &T) -> bool {
    *v == T::default()
}

emissive_object! {
    /// A `[[mesh]]`: a mesh placed in the scene.
    pub struct MeshDesc {
        /// A mesh defined under `[meshes]`; or give `file`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub mesh: Option<String>,
        /// A mesh file (relative to the scene file); or give `mesh`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub file: Option<String>,
        /// Shading normals, with `file` (default `file`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub normals: Option<NormalsDesc>,
        /// Texture coordinates without per-vertex uvs, with `file` (default
        /// `barycentric`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub default_uv: Option<DefaultUvDesc>,
        /// Material of every face; without it, an OBJ's own materials are used,
        /// else the group's material.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
    }
}

/// An `[[instance]]`: a prototype placed with its own transform.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    /// Optional name for messages.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The prototype, a name under `[prototypes]`.
    pub prototype: String,
    /// Replaces the material of every member, when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Applied after the prototype's own transform.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub transform: Vec<TransformOp>,
}
