//! `Texture`: pbrt-v4's textures as lucent's ([`crate::texture`]). Image
//! files go through one [`ImageCache`] per import, so a file used by many
//! textures is read once.

use super::spectra::{param_loc, SpectrumUse};
use super::Importer;
use crate::color::Color;
use crate::geometry::Vec3;
use crate::loader::pbrt::{Loc, ParamList, PbrtError};
use crate::texture::{
    ColorEncoding, FilterFunction, FloatTexture, ImageTexture, ImageTextureParams, Texture, TextureMapping, WrapMode,
};
use std::path::Path;
use std::sync::Arc;

impl Importer<'_> {
    /// The mapping of a texture: `mapping` (`uv`, `spherical`,
    /// `cylindrical`, `planar`) with its parameters, relative to the CTM.
    fn mapping(&mut self, params: &ParamList, loc: &Loc) -> Result<TextureMapping, PbrtError> {
        let kind = params.string("mapping")?.unwrap_or("uv").to_owned();
        let world_from_texture = self.state.ctm;
        Ok(match kind.as_str() {
            "uv" => TextureMapping::uv(
                params.float("uscale")?.unwrap_or(1.0),
                params.float("vscale")?.unwrap_or(1.0),
                params.float("udelta")?.unwrap_or(0.0),
                params.float("vdelta")?.unwrap_or(0.0),
            ),
            "spherical" => TextureMapping::spherical(&world_from_texture),
            "cylindrical" => TextureMapping::cylindrical(&world_from_texture),
            "planar" => TextureMapping::planar(
                &world_from_texture,
                params.vector3("v1")?.unwrap_or(Vec3::X),
                params.vector3("v2")?.unwrap_or(Vec3::Y),
                params.float("udelta")?.unwrap_or(0.0),
                params.float("vdelta")?.unwrap_or(0.0),
            ),
            other => {
                return Err(PbrtError::at(
                    &param_loc(params, "mapping", loc),
                    format!("unknown texture mapping \"{other}\" (accepted: uv, spherical, cylindrical, planar)"),
                ))
            }
        })
    }

    /// An `imagemap` texture's image and lookup parameters.
    fn image_texture(&mut self, params: &ParamList, loc: &Loc) -> Result<ImageTexture, PbrtError> {
        let name = params
            .string("filename")?
            .ok_or_else(|| PbrtError::at(loc, "Texture \"imagemap\" needs a \"string filename\""))?;
        let at = param_loc(params, "filename", loc);
        let path = self.resolve(name, &at);
        let encoding = match params.string("encoding")? {
            Some(e) => ColorEncoding::parse(e).map_err(|e| PbrtError::at(&param_loc(params, "encoding", loc), e))?,
            None => ColorEncoding::pbrt_default_for(&path),
        };
        let mut options = ImageTextureParams::default();
        if let Some(f) = params.string("filter")? {
            options.filter =
                FilterFunction::parse(f).map_err(|e| PbrtError::at(&param_loc(params, "filter", loc), e))?;
        }
        if let Some(w) = params.string("wrap")? {
            options.wrap = WrapMode::parse(w).map_err(|e| PbrtError::at(&param_loc(params, "wrap", loc), e))?.into();
        }
        options.scale = params.float("scale")?.unwrap_or(1.0);
        options.invert = params.bool("invert")?.unwrap_or(false);
        options.max_anisotropy = params.float("maxanisotropy")?.unwrap_or(8.0);
        let mipmap = self.load_mipmap(&path, encoding, &at)?;
        let mapping = self.mapping(params, loc)?;
        Ok(ImageTexture::new(mapping, mipmap, options))
    }

    fn load_mipmap(
        &mut self,
        path: &Path,
        encoding: ColorEncoding,
        at: &Loc,
    ) -> Result<Arc<crate::texture::MipMap>, PbrtError> {
        let mipmap = self.images.mipmap(path, encoding).map_err(|e| PbrtError::at(at, e.to_string()))?;
        self.files.push(path.to_path_buf());
        Ok(mipmap)
    }

    /// The image of an area light (`AreaLightSource "diffuse"` with a
    /// `filename`): a bilinearly interpolated image over the surface's
    /// texture coordinates, in the file's default encoding.
    pub fn emission_image(&mut self, path: &Path, at: &Loc) -> Result<Texture, PbrtError> {
        let mipmap = self.load_mipmap(path, ColorEncoding::pbrt_default_for(path), at)?;
        let options = ImageTextureParams { filter: FilterFunction::Bilinear, ..ImageTextureParams::default() };
        Ok(Texture::image(Arc::new(ImageTexture::new(TextureMapping::uv(1.0, 1.0, 0.0, 0.0), mipmap, options))))
    }

    /// A tangent-space normal map (`normalmap`): the image read linearly.
    pub fn normal_map_texture(&mut self, path: &Path, at: &Loc) -> Result<Texture, PbrtError> {
        let mipmap = self.load_mipmap(path, ColorEncoding::Linear, at)?;
        let options = ImageTextureParams::default();
        Ok(Texture::image(Arc::new(ImageTexture::new(TextureMapping::uv(1.0, 1.0, 0.0, 0.0), mipmap, options))))
    }

    /// A nested spectrum texture parameter (`tex`, `tex1`, ...) with a
    /// constant default.
    fn sub_texture(&mut self, params: &ParamList, name: &str, default: f32) -> Result<Arc<Texture>, PbrtError> {
        Ok(Arc::new(
            self.spectrum_texture(params, name, SpectrumUse::Unbounded)?
                .unwrap_or(Texture::Constant(Color::splat(default))),
        ))
    }

    fn sub_float(
        &mut self,
        params: &ParamList,
        name: &str,
        default: f32,
        loc: &Loc,
    ) -> Result<Arc<FloatTexture>, PbrtError> {
        Ok(Arc::new(self.float_texture(params, name, default, loc)?))
    }

    /// Handle a `Texture` directive.
    pub fn texture(
        &mut self,
        name: &str,
        value_type: &str,
        class: &str,
        params: &ParamList,
        loc: &Loc,
    ) -> Result<(), PbrtError> {
        let spectrum = match value_type {
            "spectrum" | "color" | "rgb" => true,
            "float" => false,
            other => {
                return Err(PbrtError::at(
                    loc,
                    format!("Texture \"{name}\": unknown value type \"{other}\" (accepted: \"float\", \"spectrum\")"),
                ))
            }
        };
        let err = |e: String| PbrtError::at(loc, format!("Texture \"{name}\": {e}"));
        if spectrum {
            let t = match class {
                "constant" => (*self.sub_texture(params, "value", 1.0)?).clone(),
                "scale" => {
                    Texture::scale(self.sub_texture(params, "tex", 1.0)?, self.sub_float(params, "scale", 1.0, loc)?)
                }
                "mix" => Texture::mix(
                    self.sub_texture(params, "tex1", 0.0)?,
                    self.sub_texture(params, "tex2", 1.0)?,
                    self.sub_float(params, "amount", 0.5, loc)?,
                ),
                "directionmix" => {
                    let dir = params.vector3("dir")?.unwrap_or(Vec3::Y);
                    let (t1, t2) = (self.sub_texture(params, "tex1", 0.0)?, self.sub_texture(params, "tex2", 1.0)?);
                    Texture::direction_mix(t1, t2, dir, &self.state.ctm).map_err(err)?
                }
                "checkerboard" => {
                    self.checkerboard_dimension(params, loc)?;
                    let mapping = self.mapping(params, loc)?;
                    let (t1, t2) = (self.sub_texture(params, "tex1", 1.0)?, self.sub_texture(params, "tex2", 0.0)?);
                    Texture::checkerboard(mapping, t1, t2)
                }
                "bilerp" => {
                    let mapping = self.mapping(params, loc)?;
                    let mut v = [Color::ZERO; 4];
                    for (slot, (n, d)) in v.iter_mut().zip([("v00", 0.0), ("v01", 1.0), ("v10", 0.0), ("v11", 1.0)]) {
                        *slot = self.color(params, n, SpectrumUse::Unbounded)?.unwrap_or(Color::splat(d));
                    }
                    Texture::bilerp(mapping, v[0], v[1], v[2], v[3])
                }
                "imagemap" => Texture::image(Arc::new(self.image_texture(params, loc)?)),
                other => {
                    self.unsupported_texture(other, params, loc)?;
                    Texture::Constant(Color::splat(0.5))
                }
            };
            self.materials.textures.insert(name.to_owned(), Arc::new(t));
        } else {
            let t = match class {
                "constant" => FloatTexture::Constant(params.float("value")?.unwrap_or(1.0)),
                "scale" => FloatTexture::scale(
                    self.sub_float(params, "tex", 1.0, loc)?,
                    self.sub_float(params, "scale", 1.0, loc)?,
                ),
                "mix" => FloatTexture::mix(
                    self.sub_float(params, "tex1", 0.0, loc)?,
                    self.sub_float(params, "tex2", 1.0, loc)?,
                    self.sub_float(params, "amount", 0.5, loc)?,
                ),
                "directionmix" => {
                    let dir = params.vector3("dir")?.unwrap_or(Vec3::Y);
                    let (t1, t2) =
                        (self.sub_float(params, "tex1", 0.0, loc)?, self.sub_float(params, "tex2", 1.0, loc)?);
                    FloatTexture::direction_mix(t1, t2, dir, &self.state.ctm).map_err(err)?
                }
                "checkerboard" => {
                    self.checkerboard_dimension(params, loc)?;
                    let mapping = self.mapping(params, loc)?;
                    let (t1, t2) =
                        (self.sub_float(params, "tex1", 1.0, loc)?, self.sub_float(params, "tex2", 0.0, loc)?);
                    FloatTexture::checkerboard(mapping, t1, t2)
                }
                "bilerp" => {
                    let mapping = self.mapping(params, loc)?;
                    let v = [
                        params.float("v00")?.unwrap_or(0.0),
                        params.float("v01")?.unwrap_or(1.0),
                        params.float("v10")?.unwrap_or(0.0),
                        params.float("v11")?.unwrap_or(1.0),
                    ];
                    FloatTexture::bilerp(mapping, v[0], v[1], v[2], v[3])
                }
                "imagemap" => FloatTexture::image(Arc::new(self.image_texture(params, loc)?)),
                other => {
                    self.unsupported_texture(other, params, loc)?;
                    FloatTexture::Constant(0.5)
                }
            };
            self.materials.float_textures.insert(name.to_owned(), Arc::new(t));
        }
        Ok(())
    }

    /// Only 2D checkerboards are supported.
    fn checkerboard_dimension(&mut self, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        match params.int("dimension")?.unwrap_or(2) {
            2 => Ok(()),
            3 => self
                .warnings
                .warn(loc, "a 3D checkerboard is not supported: rendered as a 2D checkerboard of the mapping"),
            d => Err(PbrtError::at(
                &param_loc(params, "dimension", loc),
                format!("checkerboard \"integer dimension\" must be 2 or 3, got {d}"),
            )),
        }
    }

    fn unsupported_texture(&mut self, class: &str, params: &ParamList, loc: &Loc) -> Result<(), PbrtError> {
        for p in &params.params {
            p.used.set(true);
        }
        self.warnings.warn(
            loc,
            format!("Texture class \"{class}\" is not supported: a constant 0.5 is used (supported: imagemap, constant, scale, mix, directionmix, checkerboard, bilerp)"),
        )
    }
}
