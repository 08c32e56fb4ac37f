//! Materials: how a surface reflects light. A material describes the surface
//! only; what light reaches it is the integrator's business.
//!
//! The physically based materials follow pbrt-v4's (PBRT 4th ed., ch. 10
//! and §14.3; pbrt-v4's `materials.h`), with RGB colours instead of
//! spectra. A material is evaluated at a hit in two steps:
//!
//! 1. [`Material::resolve`] turns a [`Material::Mix`] into one of its two
//!    materials (deterministically, see [`Material::Mix`]), unwraps shading
//!    modifiers (bump and normal maps, [`Material::Shaded`]) into the
//!    shading frame, and answers `None` for a [`Material::Interface`]: no
//!    surface, the ray continues.
//! 2. The resolved material's BxDF is built with textures evaluated at the
//!    point and placed in the shading frame: [`Material::bsdf_at`] does
//!    both steps for the path integrator.

mod classic;
mod metallic_roughness;
mod shading;

pub use classic::{ClassicMaterial, PhongBsdf};
pub use metallic_roughness::MetallicRoughnessMaterial;
pub use shading::{bump_map, normal_map, NormalPerturbation, ShadingGeometry, BUMP_DELTA};

use crate::bsdf::{
    reflectance_to_complex_ior, roughness_to_alpha, Bsdf, Bxdf, ConductorBxdf, ConductorFresnel, DielectricBxdf,
    DiffuseBxdf, LayeredBxdf, TrowbridgeReitz,
};
use crate::color::Color;
use crate::geometry::{Vec2, Vec3};
use crate::mesh::VertexAttributes;
use crate::sampling::mix_seed;
use crate::texture::{FloatTexture, Texture, TextureContext};
use std::f32::consts::FRAC_1_PI;

/// Index of a material in its scene; only the scene builder's
/// `add_material` makes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaterialId(u32);

impl MaterialId {
    /// The handle of the material at `index` in a scene's material list.
    pub(crate) fn new(index: usize) -> Self {
        Self(index as u32)
    }

    /// The index into the scene's material list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Why material parameters are unusable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// A coefficient is negative or not finite.
    #[error("{name} must be a finite number ≥ 0, got {value}")]
    Coefficient {
        /// Parameter name.
        name: &'static str,
        /// Value given.
        value: f32,
    },
}

/// Microfacet roughness of a surface: GGX `αx` along ∂p/∂u and `αy` along
/// ∂p/∂v, given as textures, read directly as α or through pbrt-v4's
/// remapping `α = √roughness` ([`roughness_to_alpha`]).
///
/// pbrt-v4's `roughness` parameter sets both `u` and `v`; `uroughness` and
/// `vroughness` override one each; `remaproughness` defaults to true. In
/// lucent's own scene files `roughness` is α itself ([`Roughness::alpha`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Roughness {
    /// Roughness along ∂p/∂u.
    pub u: FloatTexture,
    /// Roughness along ∂p/∂v.
    pub v: FloatTexture,
    /// Whether `u` and `v` are mapped to α by `α = √r` (pbrt-v4's
    /// `remaproughness`) rather than being α.
    pub remap: bool,
}

impl Roughness {
    /// Isotropic GGX α given directly (no remapping): lucent's scene-file
    /// convention. 0 is smooth.
    pub fn alpha(alpha: f32) -> Self {
        Self { u: FloatTexture::Constant(alpha), v: FloatTexture::Constant(alpha), remap: false }
    }

    /// pbrt-v4's `roughness` (both directions), remapped when `remap`.
    pub fn isotropic(roughness: impl Into<FloatTexture>, remap: bool) -> Self {
        let r = roughness.into();
        Self { u: r.clone(), v: r, remap }
    }

    /// pbrt-v4's `uroughness` and `vroughness`, remapped when `remap`.
    pub fn anisotropic(u: impl Into<FloatTexture>, v: impl Into<FloatTexture>, remap: bool) -> Self {
        Self { u: u.into(), v: v.into(), remap }
    }

    /// The GGX distribution at `ctx`.
    pub fn distribution(&self, ctx: &TextureContext) -> TrowbridgeReitz {
        let (mut u, mut v) = (self.u.evaluate(ctx), self.v.evaluate(ctx));
        if self.remap {
            u = roughness_to_alpha(u);
            v = roughness_to_alpha(v);
        }
        TrowbridgeReitz::anisotropic(u, v)
    }
}

impl Default for Roughness {
    /// Smooth, with pbrt-v4's `remaproughness` true.
    fn default() -> Self {
        Self::isotropic(0.0, true)
    }
}

impl From<f32> for Roughness {
    /// [`Roughness::alpha`].
    fn from(alpha: f32) -> Self {
        Self::alpha(alpha)
    }
}

/// Copper's complex index of refraction in RGB (at 650, 550 and 450 nm;
/// Johnson & Christy 1972, via refractiveindex.info): pbrt-v4's default
/// conductor (`metal-Cu-eta`, `metal-Cu-k`), reduced to three channels.
pub const COPPER_ETA: Color = Color::new(0.214, 0.934, 1.124);
/// See [`COPPER_ETA`].
pub const COPPER_K: Color = Color::new(3.670, 2.577, 2.404);

/// Parameters of pbrt-v4's `coateddiffuse` material: a diffuse base under a
/// dielectric coat with an optional scattering medium between (a
/// [`crate::bsdf::CoatedDiffuseBxdf`]). `Default` gives pbrt-v4's defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct CoatedDiffuseMaterial {
    /// Albedo of the base (default 0.5), each channel in [0, 1].
    pub reflectance: Texture,
    /// Roughness of the coat (default 0, remapped).
    pub roughness: Roughness,
    /// Thickness of the medium in mean free paths (default 0.01).
    pub thickness: FloatTexture,
    /// Index of refraction of the coat (default 1.5).
    pub eta: f32,
    /// Scattering albedo of the medium (default 0: none).
    pub albedo: Texture,
    /// Henyey–Greenstein asymmetry of the medium (default 0), in [−1, 1].
    pub g: FloatTexture,
    /// Most scattering events per random walk (default 10).
    pub max_depth: u32,
    /// Random walks per evaluation (default 1).
    pub n_samples: u32,
}

impl Default for CoatedDiffuseMaterial {
    fn default() -> Self {
        Self {
            reflectance: Texture::Constant(Color::splat(0.5)),
            roughness: Roughness::default(),
            thickness: FloatTexture::Constant(0.01),
            eta: 1.5,
            albedo: Texture::Constant(Color::ZERO),
            g: FloatTexture::Constant(0.0),
            max_depth: 10,
            n_samples: 1,
        }
    }
}

/// Parameters of pbrt-v4's `coatedconductor` material: a conductor under a
/// dielectric coat with an optional scattering medium between (a
/// [`crate::bsdf::CoatedConductorBxdf`]). `Default` gives pbrt-v4's
/// defaults (copper under a smooth coat of index 1.5).
#[derive(Clone, Debug, PartialEq)]
pub struct CoatedConductorMaterial {
    /// Roughness of the coat (`interface.roughness`, default 0, remapped).
    pub interface_roughness: Roughness,
    /// Index of refraction of the coat (`interface.eta`, default 1.5).
    pub interface_eta: f32,
    /// The conductor (`conductor.eta` and `conductor.k`, or
    /// `reflectance`; default copper). Its index is that in vacuum: it is
    /// divided by `interface_eta` for the base under the coat, as pbrt-v4
    /// does; a Schlick reflectance is used as given.
    pub conductor: ConductorFresnel<Texture>,
    /// Roughness of the conductor (`conductor.roughness`, default 0,
    /// remapped).
    pub conductor_roughness: Roughness,
    /// Thickness of the medium in mean free paths (default 0.01).
    pub thickness: FloatTexture,
    /// Scattering albedo of the medium (default 0: none).
    pub albedo: Texture,
    /// Henyey–Greenstein asymmetry of the medium (default 0).
    pub g: FloatTexture,
    /// Most scattering events per random walk (default 10).
    pub max_depth: u32,
    /// Random walks per evaluation (default 1).
    pub n_samples: u32,
}

impl Default for CoatedConductorMaterial {
    fn default() -> Self {
        Self {
            interface_roughness: Roughness::default(),
            interface_eta: 1.5,
            conductor: ConductorFresnel::Complex { eta: Texture::Constant(COPPER_ETA), k: Texture::Constant(COPPER_K) },
            conductor_roughness: Roughness::default(),
            thickness: FloatTexture::Constant(0.01),
            albedo: Texture::Constant(Color::ZERO),
            g: FloatTexture::Constant(0.0),
            max_depth: 10,
            n_samples: 1,
        }
    }
}

/// A surface description.
///
/// The classic materials, for the Whitted integrator (and given an
/// energy-conserving reading under the path tracer, see [`Material::bxdf`]):
///
/// * **Matte** is a Lambertian reflector: BRDF `kd · colour / π`.
/// * **Phong** adds a specular lobe `ks · max(0, r·wo)^exponent`, with `r`
///   the mirror direction of the light about the normal (the form of Suffern,
///   *Ray Tracing from the Ground Up*, ch. 15, white highlights), and a
///   perfect mirror term: the colour seen along the reflected view ray,
///   weighted by `kr`.
///
/// Both reflect the scene's ambient light as `ka · colour · ambient`, where
/// `ka` defaults to `kd`.
///
/// The physically based materials, for the path integrator (see
/// [`crate::bsdf`]), one per pbrt-v4 material: `diffuse` → `Diffuse`,
/// `conductor` → `Conductor`, `dielectric` → `Dielectric`,
/// `thindielectric` → `ThinDielectric`, `diffusetransmission` →
/// `DiffuseTransmission`, `coateddiffuse` → `CoatedDiffuse`,
/// `coatedconductor` → `CoatedConductor`, `mix` → `Mix`, `interface` →
/// `Interface`; any of them with `displacement` or `normalmap` →
/// [`Material::with_bump`] / [`Material::with_normal_map`]. `Plastic` is
/// lucent's own closed-form coated diffuse.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Matte or Phong.
    Classic(ClassicMaterial),
    /// Lambertian reflection.
    Diffuse {
        /// Albedo, each channel in [0, 1] (pbrt-v4 default 0.5).
        reflectance: Texture,
    },
    /// A metal.
    Conductor {
        /// How the Fresnel reflectance is given: complex index `eta`, `k`
        /// (pbrt-v4's default is copper, [`COPPER_ETA`], [`COPPER_K`]),
        /// pbrt-v4's `reflectance`, or Schlick's reflectance at normal
        /// incidence.
        fresnel: ConductorFresnel<Texture>,
        /// GGX roughness (0: a perfect mirror).
        roughness: Roughness,
    },
    /// Glass, water: reflects and refracts.
    Dielectric {
        /// Index of refraction of the inside (the outside is vacuum;
        /// pbrt-v4 default 1.5).
        eta: f32,
        /// GGX roughness (0: smooth).
        roughness: Roughness,
        /// Scales transmitted light (white: clear glass; pbrt-v4 has no
        /// tint, use white).
        tint: Color,
    },
    /// A diffuse base under a clear dielectric coat.
    Plastic {
        /// Albedo of the base.
        reflectance: Texture,
        /// Index of refraction of the coat.
        eta: f32,
        /// GGX roughness α of the coat (0: smooth).
        roughness: f32,
    },
    /// A thin dielectric pane: specular reflection and straight
    /// transmission, with the inter-reflections of its two faces.
    ThinDielectric {
        /// Index of refraction (pbrt-v4 default 1.5).
        eta: f32,
    },
    /// Lambertian reflection and transmission (pbrt-v4's
    /// `diffusetransmission`): albedos `scale · reflectance` and
    /// `scale · transmittance`, each clamped to [0, 1].
    DiffuseTransmission {
        /// Reflectance (pbrt-v4 default 0.25).
        reflectance: Texture,
        /// Transmittance (pbrt-v4 default 0.25).
        transmittance: Texture,
        /// Scale of both (pbrt-v4 default 1).
        scale: f32,
    },
    /// pbrt-v4's `coateddiffuse`.
    CoatedDiffuse(CoatedDiffuseMaterial),
    /// pbrt-v4's `coatedconductor`.
    CoatedConductor(CoatedConductorMaterial),
    /// glTF 2.0's metallic-roughness material with the Khronos material
    /// extensions.
    MetallicRoughness(Box<MetallicRoughnessMaterial>),
    /// pbrt-v4's `mix`: at each hit one of the two materials is used, the
    /// second with probability `amount`, chosen deterministically:
    /// `amount ≤ 0` gives the first, `amount ≥ 1` the second, and otherwise
    /// the first if `amount < u` for a hash `u ∈ [0, 1)` of the hit point,
    /// the outgoing direction and the two ids (pbrt-v4's
    /// `MixMaterial::ChooseMaterial`). The same hit seen from the same
    /// direction always gets the same material, so the choice acts as a
    /// stochastic blend without adding a sample dimension.
    Mix {
        /// The two materials.
        materials: [MaterialId; 2],
        /// Probability of the second (pbrt-v4 default 0.5).
        amount: FloatTexture,
    },
    /// No surface: the boundary of a participating medium in pbrt-v4. Rays
    /// pass straight through it; see [`Material::resolve`].
    Interface,
    /// A material with its shading normal perturbed by a bump or normal
    /// map ([`Material::with_bump`], [`Material::with_normal_map`]). The
    /// perturbation applies to whatever the inner material resolves to,
    /// unless that has its own.
    Shaded {
        /// The material shaded.
        material: Box<Material>,
        /// How its normal is perturbed.
        normal: NormalPerturbation,
    },
}

/// Where a material is evaluated: the hit as the material sees it
/// (pbrt-v4's `MaterialEvalContext`). The integrators make it from a
/// `SurfaceInteraction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialContext {
    /// World-space position.
    pub p: Vec3,
    /// Unit geometric normal.
    pub n: Vec3,
    /// Unit shading normal.
    pub ns: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// A second uv set and a vertex colour (see
    /// [`crate::mesh::VertexAttributes`]).
    pub attributes: VertexAttributes,
    /// ∂p/∂u (not normalised).
    pub dpdu: Vec3,
    /// ∂p/∂v (not normalised).
    pub dpdv: Vec3,
    /// Unit direction towards where the light leaves (the ray's origin).
    pub wo: Vec3,
}

impl MaterialContext {
    /// The context textures are evaluated in: position, geometric normal,
    /// texture coordinates and vertex attributes.
    #[inline]
    pub fn texture_context(&self) -> TextureContext {
        TextureContext::new(self.p, self.n, self.uv).with_attributes(self.attributes)
    }
}

/// A material resolved at a hit: the material that scatters (never `Mix`,
/// `Interface` or `Shaded`) and the shading geometry it is evaluated in.
#[derive(Clone, Copy, Debug)]
pub struct ResolvedMaterial<'a> {
    /// The scattering material.
    pub material: &'a Material,
    /// Shading normal and tangents, bump or normal mapped if asked.
    pub shading: ShadingGeometry,
}

/// Most `Mix` and `Shaded` levels [`Material::resolve`] unwraps; deeper
/// nesting (only possible with ids from another scene) resolves to black.
pub const MAX_MATERIAL_NESTING: usize = 32;

static BLACK: Material = Material::Diffuse { reflectance: Texture::Constant(Color::ZERO) };

fn coefficient(name: &'static str, value: f32) -> Result<f32, MaterialError> {
    if value >= 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(MaterialError::Coefficient { name, value })
    }
}

impl Material {
    /// A Lambertian material.
    ///
    /// ```
    /// use lucent::material::Material;
    /// use lucent::color::Color;
    /// let red = Material::matte(Color::new(1.0, 0.0, 0.0), 0.8).unwrap();
    /// assert_eq!(red.classic().unwrap().kr, 0.0);
    /// ```
    pub fn matte(color: impl Into<Texture>, kd: f32) -> Result<Self, MaterialError> {
        let kd = coefficient("kd", kd)?;
        Ok(Self::Classic(ClassicMaterial { color: color.into(), ka: kd, kd, ks: 0.0, exponent: 1.0, kr: 0.0 }))
    }

    /// A Phong material with mirror reflection.
    pub fn phong(color: impl Into<Texture>, kd: f32, ks: f32, exponent: f32, kr: f32) -> Result<Self, MaterialError> {
        let kd = coefficient("kd", kd)?;
        Ok(Self::Classic(ClassicMaterial {
            color: color.into(),
            ka: kd,
            kd,
            ks: coefficient("ks", ks)?,
            exponent: coefficient("exponent", exponent)?,
            kr: coefficient("kr", kr)?,
        }))
    }

    /// Override the ambient coefficient of a classic material (other
    /// materials have none and are returned unchanged).
    pub fn with_ka(mut self, ka: f32) -> Result<Self, MaterialError> {
        match &mut self {
            Self::Classic(c) => c.ka = coefficient("ka", ka)?,
            Self::Shaded { material, .. } => {
                **material = std::mem::replace(&mut **material, Self::Interface).with_ka(ka)?
            }
            _ => {}
        }
        Ok(self)
    }

    /// This material bump mapped by the height field `displacement`
    /// (world units along the normal; pbrt-v4's `displacement` parameter):
    /// see [`bump_map`].
    pub fn with_bump(self, displacement: impl Into<FloatTexture>) -> Self {
        Self::Shaded { material: Box::new(self), normal: NormalPerturbation::Bump(displacement.into()) }
    }

    /// This material with the tangent-space normal map `map` (pbrt-v4's
    /// `normalmap` parameter, an RGB image): see [`normal_map`].
    pub fn with_normal_map(self, map: impl Into<Texture>) -> Self {
        Self::Shaded { material: Box::new(self), normal: NormalPerturbation::NormalMap(map.into()) }
    }

    /// The classic parameters, for a matte or Phong material.
    pub fn classic(&self) -> Option<&ClassicMaterial> {
        match self {
            Self::Classic(c) => Some(c),
            Self::Shaded { material, .. } => material.classic(),
            _ => None,
        }
    }

    /// Whether this is an [`Material::Interface`]: no surface at all.
    pub fn is_interface(&self) -> bool {
        matches!(self, Self::Interface)
    }

    /// Resolve this material at a hit (step 1 of the module
    /// documentation): `Mix` chooses one of its materials in `materials`
    /// (the scene's list), `Shaded` perturbs the shading geometry, and
    /// `Interface` gives `None`: the ray is to continue through the surface
    /// as if it were not there (pbrt-v4's `SkipIntersection`), without
    /// counting a bounce. A `Mix` id not in `materials`, or nesting deeper
    /// than [`MAX_MATERIAL_NESTING`], resolves to black.
    #[inline]
    pub fn resolve<'a>(&'a self, ctx: &MaterialContext, materials: &'a [Material]) -> Option<ResolvedMaterial<'a>> {
        let (m, normal) = self.unwrap(ctx, materials);
        if m.is_interface() {
            return None;
        }
        let shading = match normal {
            Some(n) => n.apply(ctx),
            None => ShadingGeometry::of(ctx),
        };
        Some(ResolvedMaterial { material: m, shading })
    }

    /// Whether this material resolves to an [`Material::Interface`] at
    /// `ctx` (what [`Material::resolve`] answers `None` for), without
    /// computing the shading geometry: for shadow rays.
    pub fn passes_through(&self, ctx: &MaterialContext, materials: &[Material]) -> bool {
        self.unwrap(ctx, materials).0.is_interface()
    }

    /// Follow `Mix` choices and `Shaded` wrappers down to the material that
    /// scatters, and the innermost normal perturbation on the way.
    #[inline]
    fn unwrap<'a>(
        &'a self,
        ctx: &MaterialContext,
        materials: &'a [Material],
    ) -> (&'a Material, Option<&'a NormalPerturbation>) {
        let mut m = self;
        let mut normal = None;
        for _ in 0..MAX_MATERIAL_NESTING {
            match m {
                Self::Mix { materials: ids, amount } => {
                    let id = Self::mix_choice(ids, amount, ctx);
                    m = materials.get(id.index()).unwrap_or(&BLACK);
                }
                Self::Shaded { material, normal: n } => {
                    // The innermost perturbation wins.
                    normal = Some(n);
                    m = material;
                }
                _ => return (m, normal),
            }
        }
        (&BLACK, None)
    }

    /// Which of a `Mix`'s two materials is used at `ctx` (see
    /// [`Material::Mix`]). Never inlined: inlined into
    /// [`Material::resolve`]'s loop, the compiler hoisted the hash of the
    /// point and direction out of it, paying ~140 instructions at every hit
    /// of every material, mixed or not (callgrind, Cornell box).
    #[inline(never)]
    pub fn mix_choice(ids: &[MaterialId; 2], amount: &FloatTexture, ctx: &MaterialContext) -> MaterialId {
        let a = amount.evaluate(&ctx.texture_context());
        if a <= 0.0 || a.is_nan() {
            return ids[0];
        }
        if a >= 1.0 {
            return ids[1];
        }
        let bits = |v: Vec3| [v.x.to_bits() as u64, v.y.to_bits() as u64, v.z.to_bits() as u64];
        let [px, py, pz] = bits(ctx.p);
        let [wx, wy, wz] = bits(ctx.wo);
        let h = mix_seed(&[px, py, pz, wx, wy, wz, ids[0].0 as u64, ids[1].0 as u64]);
        let u = (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32);
        if a < u {
            ids[0]
        } else {
            ids[1]
        }
    }

    /// The path integrator's BSDF at a hit: [`Material::resolve`], then
    /// the resolved material's [`Material::bxdf_at`] in its shading frame
    /// (normal and ∂p/∂u). `None` for an interface.
    #[inline(always)]
    pub fn bsdf_at(&self, ctx: &MaterialContext, materials: &[Material]) -> Option<Bsdf> {
        let (shading, bxdf) = self.shading_and_bxdf(ctx, materials)?;
        Some(Bsdf::new(shading.ns, shading.dpdu, bxdf))
    }

    /// What both BSDF constructors start from: [`Material::resolve`]'s
    /// shading geometry and the resolved material's [`Material::bxdf_at`].
    #[inline(always)]
    fn shading_and_bxdf(&self, ctx: &MaterialContext, materials: &[Material]) -> Option<(ShadingGeometry, Bxdf)> {
        let r = self.resolve(ctx, materials)?;
        Some((r.shading, r.material.bxdf_at(&ctx.texture_context())))
    }

    /// [`Material::bsdf_at`] for the path integrator's lanes: a diffuse
    /// BSDF comes with its frame unfinished ([`Bsdf::diffuse_unframed`]),
    /// to be made by the diffuse scatter kernel with those of the other
    /// lanes; every other BSDF is [`Material::bsdf_at`]'s.
    #[inline(always)]
    pub(crate) fn bsdf_at_unframed(&self, ctx: &MaterialContext, materials: &[Material]) -> Option<Bsdf> {
        let (shading, bxdf) = self.shading_and_bxdf(ctx, materials)?;
        Some(match bxdf {
            Bxdf::Diffuse(lobe) => Bsdf::diffuse_unframed(shading.ns, shading.dpdu, lobe),
            bxdf => Bsdf::new(shading.ns, shading.dpdu, bxdf),
        })
    }

    /// The scattering function of the path integrator at a point with
    /// texture coordinates `uv` (textures that need a position see the
    /// origin): [`Material::bxdf_at`] of [`TextureContext::from_uv`].
    pub fn bxdf(&self, uv: Vec2) -> Bxdf {
        self.bxdf_at(&TextureContext::from_uv(uv))
    }

    /// The scattering function of the path integrator with textures
    /// evaluated at `ctx`.
    ///
    /// The classic materials are read so as to conserve energy: matte is
    /// Lambertian with albedo `kd·colour`; Phong is that plus a normalised
    /// Phong lobe (Lafortune & Willems 1994) of weight `ks` and a perfect
    /// mirror of weight `kr` (see [`Bxdf::phong`]). The others follow
    /// pbrt-v4's `GetBxDF` of the same material. `Shaded` gives its inner
    /// material's BxDF (its frame is [`Material::resolve`]'s business);
    /// `Mix` and `Interface` cannot scatter without being resolved and give
    /// black.
    #[inline]
    pub fn bxdf_at(&self, ctx: &TextureContext) -> Bxdf {
        // The most common material, built in place; the rest out of line.
        match self {
            Self::Diffuse { reflectance } => Bxdf::diffuse(unit(reflectance.evaluate(ctx))),
            _ => self.bxdf_at_any(ctx),
        }
    }

    /// [`Material::bxdf_at`] for every material.
    fn bxdf_at_any(&self, ctx: &TextureContext) -> Bxdf {
        match self {
            Self::Classic(m) => {
                let albedo = m.kd * m.color.evaluate(ctx);
                if m.ks == 0.0 && m.kr == 0.0 {
                    Bxdf::diffuse(albedo)
                } else {
                    Bxdf::phong(albedo, m.ks, m.exponent, m.kr)
                }
            }
            Self::Diffuse { reflectance } => Bxdf::diffuse(unit(reflectance.evaluate(ctx))),
            Self::Conductor { fresnel, roughness } => Bxdf::Conductor(ConductorBxdf {
                fresnel: conductor_fresnel(fresnel, ctx, 1.0),
                distrib: roughness.distribution(ctx),
            }),
            Self::Dielectric { eta, roughness, tint } => {
                Bxdf::Dielectric(DielectricBxdf::new(*eta, roughness.distribution(ctx), *tint))
            }
            Self::Plastic { reflectance, eta, roughness } => Bxdf::plastic(reflectance.evaluate(ctx), *eta, *roughness),
            Self::ThinDielectric { eta } => Bxdf::thin_dielectric(*eta),
            Self::DiffuseTransmission { reflectance, transmittance, scale } => Bxdf::diffuse_transmission(
                unit(*scale * reflectance.evaluate(ctx)),
                unit(*scale * transmittance.evaluate(ctx)),
            ),
            Self::CoatedDiffuse(c) => Bxdf::CoatedDiffuse(LayeredBxdf::new(
                DielectricBxdf::new(c.eta, c.roughness.distribution(ctx), Color::ONE),
                DiffuseBxdf { r: unit(c.reflectance.evaluate(ctx)) },
                c.thickness.evaluate(ctx),
                unit(c.albedo.evaluate(ctx)),
                c.g.evaluate(ctx),
                c.max_depth,
                c.n_samples,
            )),
            Self::CoatedConductor(c) => {
                let top = DielectricBxdf::new(c.interface_eta, c.interface_roughness.distribution(ctx), Color::ONE);
                Bxdf::CoatedConductor(LayeredBxdf::new(
                    top,
                    ConductorBxdf {
                        fresnel: conductor_fresnel(&c.conductor, ctx, top.eta),
                        distrib: c.conductor_roughness.distribution(ctx),
                    },
                    c.thickness.evaluate(ctx),
                    unit(c.albedo.evaluate(ctx)),
                    c.g.evaluate(ctx),
                    c.max_depth,
                    c.n_samples,
                ))
            }
            Self::MetallicRoughness(m) => m.bxdf_at(ctx),
            Self::Shaded { material, .. } => material.bxdf_at(ctx),
            Self::Mix { .. } | Self::Interface => Bxdf::Black,
        }
    }

    /// The classic reflection model at a point with texture coordinates
    /// `uv`, as the Whitted integrator sees it (resolve `Mix`, `Shaded` and
    /// `Interface` first with [`Material::resolve`]). Physically based
    /// materials are approximated: a diffuse surface as matte, a conductor
    /// or a dielectric as a mirror weighted by its reflectance at normal
    /// incidence (the Whitted integrator does not refract), plastic and
    /// coated diffuse as matte plus the coat's mirror, a coated conductor
    /// as the conductor's mirror, a thin dielectric as a mirror of the
    /// pane's reflectance, diffuse transmission as matte (its transmission
    /// is lost). `Mix` and `Interface` give black; `Shaded` its inner
    /// material's model.
    #[inline]
    pub fn bsdf(&self, uv: Vec2) -> PhongBsdf {
        self.bsdf_in(&TextureContext::from_uv(uv))
    }

    /// [`Material::bsdf`] with textures evaluated at `ctx` (position,
    /// normal, vertex attributes and all).
    pub fn bsdf_in(&self, ctx: &TextureContext) -> PhongBsdf {
        let matte = |albedo: Color, kr: Color| PhongBsdf {
            ambient: albedo,
            diffuse: albedo * FRAC_1_PI,
            ks: 0.0,
            exponent: 1.0,
            kr,
        };
        match self {
            Self::Classic(m) => {
                let albedo = m.color.evaluate(ctx);
                PhongBsdf {
                    ambient: m.ka * albedo,
                    diffuse: m.kd * albedo * FRAC_1_PI,
                    ks: m.ks,
                    exponent: m.exponent,
                    kr: Color::splat(m.kr),
                }
            }
            Self::Diffuse { reflectance } => matte(unit(reflectance.evaluate(ctx)), Color::ZERO),
            Self::Conductor { fresnel, .. } => matte(Color::ZERO, conductor_fresnel(fresnel, ctx, 1.0).eval(1.0)),
            Self::Dielectric { eta, .. } => matte(Color::ZERO, Color::splat(dielectric_r0(*eta))),
            Self::Plastic { reflectance, eta, .. } => {
                matte(reflectance.evaluate(ctx), Color::splat(dielectric_r0(*eta)))
            }
            Self::ThinDielectric { eta } => {
                let r = dielectric_r0(*eta);
                matte(Color::ZERO, Color::splat(2.0 * r / (1.0 + r)))
            }
            Self::DiffuseTransmission { reflectance, scale, .. } => {
                matte(unit(*scale * reflectance.evaluate(ctx)), Color::ZERO)
            }
            Self::CoatedDiffuse(c) => matte(unit(c.reflectance.evaluate(ctx)), Color::splat(dielectric_r0(c.eta))),
            Self::CoatedConductor(c) => {
                matte(Color::ZERO, conductor_fresnel(&c.conductor, ctx, c.interface_eta.max(1e-3)).eval(1.0))
            }
            Self::MetallicRoughness(m) => {
                // Diffuse from the dielectric part, a mirror of the metal's
                // colour (or the dielectric's 4% reflectance).
                let base = m.base_color.as_ref().map_or(Color::ONE, |t| t.evaluate(ctx)) * m.base_color_factor;
                let metallic = m.metallic.evaluate(ctx).clamp(0.0, 1.0);
                let r0 = Color::splat(dielectric_r0(m.ior));
                matte(unit(base * (1.0 - metallic)), unit(r0 * (1.0 - metallic) + base * metallic))
            }
            Self::Shaded { material, .. } => material.bsdf_in(ctx),
            Self::Mix { .. } | Self::Interface => matte(Color::ZERO, Color::ZERO),
        }
    }
}

/// Clamp a colour to [0, 1] per channel (NaN to 0): an albedo.
#[inline]
fn unit(c: Color) -> Color {
    let c = Color::new(
        if c.x.is_nan() { 0.0 } else { c.x },
        if c.y.is_nan() { 0.0 } else { c.y },
        if c.z.is_nan() { 0.0 } else { c.z },
    );
    c.clamp(Color::ZERO, Color::ONE)
}

/// A conductor's Fresnel model at `ctx`, under a medium of index
/// `outside_eta` (1: vacuum): complex indices (and pbrt-v4's reflectance
/// mapped to one) are divided by it, as pbrt-v4's `CoatedConductorMaterial`
/// does; a Schlick reflectance is used as given.
fn conductor_fresnel(f: &ConductorFresnel<Texture>, ctx: &TextureContext, outside_eta: f32) -> ConductorFresnel {
    let s = if outside_eta > 0.0 && outside_eta.is_finite() { 1.0 / outside_eta } else { 1.0 };
    match f {
        ConductorFresnel::Complex { eta, k } => {
            ConductorFresnel::Complex { eta: eta.evaluate(ctx) * s, k: k.evaluate(ctx) * s }
        }
        ConductorFresnel::Reflectance { r } => {
            let (eta, k) = reflectance_to_complex_ior(r.evaluate(ctx));
            ConductorFresnel::Complex { eta: eta * s, k: k * s }
        }
        ConductorFresnel::Schlick { r0 } => ConductorFresnel::Schlick { r0: r0.evaluate(ctx) },
    }
}

/// Reflectance of a dielectric interface at normal incidence,
/// `((η-1)/(η+1))²`.
fn dielectric_r0(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_brdf_is_albedo_over_pi() {
        let m = Material::matte(Color::new(0.5, 1.0, 0.25), 0.8).unwrap();
        let b = m.bsdf(Vec2::ZERO);
        let f = b.f(Vec3::Y, Vec3::new(0.6, 0.8, 0.0), Vec3::Y);
        assert!((f - Color::new(0.4, 0.8, 0.2) / std::f32::consts::PI).length() < 1e-7);
        assert_eq!(b.ambient, Color::new(0.4, 0.8, 0.2));
    }

    #[test]
    fn phong_peak_is_in_the_mirror_direction() {
        let m = Material::phong(Color::ONE, 0.0, 0.5, 10.0, 0.0).unwrap();
        let b = m.bsdf(Vec2::ZERO);
        let wi = Vec3::new(1.0, 1.0, 0.0).normalize();
        let mirror = Vec3::new(-1.0, 1.0, 0.0).normalize();
        assert!((b.f(mirror, wi, Vec3::Y).x - 0.5).abs() < 1e-6);
        let off = Vec3::new(-1.0, 2.0, 0.0).normalize();
        let expected = 0.5 * off.dot(mirror).powf(10.0);
        assert!((b.f(off, wi, Vec3::Y).x - expected).abs() < 1e-6);
    }

    #[test]
    fn negative_coefficients_are_refused() {
        assert!(Material::matte(Color::ONE, -0.1).is_err());
        assert!(Material::phong(Color::ONE, 0.5, 0.5, 10.0, f32::NAN).is_err());
    }

    fn plane_ctx() -> MaterialContext {
        MaterialContext {
            p: Vec3::new(0.3, 0.0, -0.2),
            n: Vec3::Y,
            ns: Vec3::Y,
            uv: Vec2::new(0.3, 0.2),
            attributes: VertexAttributes::plain(Vec2::new(0.3, 0.2)),
            dpdu: Vec3::X,
            dpdv: -Vec3::Z,
            wo: Vec3::new(0.0, 0.8, 0.6),
        }
    }

    #[test]
    fn bump_ramp_tilts_the_normal_by_atan_a() {
        // d = a·u on the plane y = 0 (∂p/∂u = x, ∂p/∂v = −z, n = y): the
        // displaced surface rises along x with slope a, so its normal is
        // (−a, 1, 0)/√(1 + a²), tilted by atan(a) away from +u.
        for a in [0.1f32, 0.5, 2.0] {
            let ctx = plane_ctx();
            let g = bump_map(&ctx, |tc| a * tc.uv.x);
            let expected = Vec3::new(-a, 1.0, 0.0).normalize();
            assert!((g.ns - expected).length() < 1e-4, "a {a}: {}", g.ns);
            let tilt = g.ns.dot(Vec3::Y).acos();
            assert!((tilt - a.atan()).abs() < 1e-4, "a {a}: tilt {tilt}");
            // ∂p'/∂u = ∂p/∂u + a n.
            assert!((g.dpdu - Vec3::new(1.0, a, 0.0)).length() < 1e-3);
        }
        // A constant displacement changes nothing.
        let ctx = plane_ctx();
        let m = Material::Diffuse { reflectance: Texture::Constant(Color::ONE) }.with_bump(0.3);
        let r = m.resolve(&ctx, &[]).unwrap();
        assert!((r.shading.ns - Vec3::Y).length() < 1e-6);
        // A bump on a surface whose normal points against ∂p/∂u × ∂p/∂v
        // keeps the normal's side.
        let flipped = MaterialContext { dpdv: Vec3::Z, ..ctx };
        let g = bump_map(&flipped, |tc| 0.5 * tc.uv.x);
        assert!(g.ns.y > 0.0 && (g.ns - Vec3::new(-0.5, 1.0, 0.0).normalize()).length() < 1e-4);
    }

    #[test]
    fn normal_map_reads_tangent_space_normals() {
        let ctx = plane_ctx();
        // (0.5, 0.5, 1) is the unperturbed normal.
        let g = normal_map(&ctx, Color::new(0.5, 0.5, 1.0));
        assert!((g.ns - Vec3::Y).length() < 1e-6);
        // (1, 0.5, 0.5) + tilt: 2·rgb − 1 = (1, 0, 1)/√2 leans 45° towards
        // ∂p/∂u.
        let g = normal_map(&ctx, Color::new(1.0, 0.5, 1.0));
        assert!((g.ns - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5, "{}", g.ns);
        // Towards ∂p/∂v (= −z here).
        let g = normal_map(&ctx, Color::new(0.5, 1.0, 1.0));
        assert!((g.ns - Vec3::new(0.0, 1.0, -1.0).normalize()).length() < 1e-5, "{}", g.ns);
        assert!(g.dpdu.dot(g.ns).abs() < 1e-6 && g.dpdv.dot(g.ns).abs() < 1e-6);
        // Through a material, into the BSDF's frame.
        let m =
            Material::Diffuse { reflectance: Texture::Constant(Color::ONE) }.with_normal_map(Color::new(1.0, 0.5, 1.0));
        let bsdf = m.bsdf_at(&ctx, &[]).unwrap();
        assert!((bsdf.frame().z - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5);
    }

    #[test]
    fn mix_choice_is_deterministic_and_matches_amount() {
        let ids = [MaterialId::new(0), MaterialId::new(1)];
        let ctx = plane_ctx();
        assert_eq!(Material::mix_choice(&ids, &FloatTexture::Constant(0.0), &ctx), ids[0]);
        assert_eq!(Material::mix_choice(&ids, &FloatTexture::Constant(-1.0), &ctx), ids[0]);
        assert_eq!(Material::mix_choice(&ids, &FloatTexture::Constant(1.0), &ctx), ids[1]);
        let mut rng = crate::sampling::Pcg32::new(9, 9);
        for amount in [0.1f32, 0.5, 0.8] {
            let n = 100_000;
            let mut second = 0;
            for _ in 0..n {
                let c = MaterialContext {
                    p: Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0,
                    wo: Vec3::new(rng.uniform() - 0.5, 1.0, rng.uniform() - 0.5).normalize(),
                    ..ctx
                };
                let a = Material::mix_choice(&ids, &FloatTexture::Constant(amount), &c);
                assert_eq!(a, Material::mix_choice(&ids, &FloatTexture::Constant(amount), &c), "deterministic");
                second += (a == ids[1]) as u32;
            }
            let p = second as f64 / n as f64;
            let se = (amount as f64 * (1.0 - amount as f64) / n as f64).sqrt();
            assert!((p - amount as f64).abs() < 4.0 * se, "amount {amount}: {p}");
        }
    }

    #[test]
    fn resolve_follows_mixes_to_interfaces() {
        let materials = vec![
            Material::Interface,
            Material::Diffuse { reflectance: Texture::Constant(Color::ONE) },
            Material::Mix { materials: [MaterialId::new(0), MaterialId::new(1)], amount: FloatTexture::Constant(0.0) },
        ];
        let ctx = plane_ctx();
        assert!(materials[0].resolve(&ctx, &materials).is_none());
        assert!(materials[2].resolve(&ctx, &materials).is_none());
        assert!(materials[2].passes_through(&ctx, &materials));
        let to_diffuse =
            Material::Mix { materials: [MaterialId::new(0), MaterialId::new(1)], amount: FloatTexture::Constant(1.0) };
        let r = to_diffuse.resolve(&ctx, &materials).unwrap();
        assert_eq!(r.material, &materials[1]);
        // A mix that refers to itself ends as black instead of looping.
        let selfish = vec![Material::Mix {
            materials: [MaterialId::new(0), MaterialId::new(0)],
            amount: FloatTexture::Constant(0.5),
        }];
        assert_eq!(selfish[0].resolve(&ctx, &selfish).unwrap().material, &BLACK);
    }

    #[test]
    fn pbrt_roughness_is_remapped_and_anisotropic() {
        let ctx = TextureContext::from_uv(Vec2::ZERO);
        let d = Roughness::anisotropic(0.04, 0.25, true).distribution(&ctx);
        assert!((d.alpha_x() - 0.2).abs() < 1e-6 && (d.alpha_y() - 0.5).abs() < 1e-6);
        let d = Roughness::alpha(0.3).distribution(&ctx);
        assert_eq!((d.alpha_x(), d.alpha_y()), (0.3, 0.3));
        // pbrt-v4's reflectance parameter of a conductor: exact Fresnel
        // with that reflectance at normal incidence.
        let m = Material::Conductor {
            fresnel: ConductorFresnel::Reflectance { r: Texture::Constant(Color::new(0.9, 0.5, 0.1)) },
            roughness: Roughness::default(),
        };
        let Bxdf::Conductor(c) = m.bxdf_at(&ctx) else { panic!() };
        assert!((c.fresnel.eval(1.0) - Color::new(0.9, 0.5, 0.1)).abs().max_element() < 1e-4);
    }
}
