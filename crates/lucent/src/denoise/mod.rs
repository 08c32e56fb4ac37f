//! Denoising with Intel Open Image Denoise (OIDN): a rendered image, with
//! the albedo and normal auxiliary images if it has them, goes through
//! OIDN's `RT` filter, the neural network trained on path-traced images
//! that Blender's Cycles also uses.
//!
//! OIDN is not linked: [`Denoiser::new`] opens the shared library at run
//! time (see [`library`] for where it looks), so lucent builds, tests and
//! renders without it, and only `--denoise` needs it.
//!
//! ```no_run
//! use lucent::denoise::{DenoiseOptions, Denoiser};
//! # let film = lucent::film::Film::new(4, 4).unwrap();
//! let denoiser = Denoiser::new()?; // an error saying how to get OIDN, without it
//! let clean = denoiser.denoise(&film, None, None, &DenoiseOptions::default())?;
//! # Ok::<(), lucent::denoise::DenoiseError>(())
//! ```

pub mod library;

pub use library::{Library, LoadError, LIBRARY_NAME, LIBRARY_VARIABLE};

use crate::color::Color;
use crate::film::Film;
use std::ffi::{c_int, c_void, CString};
use std::fmt;
use std::str::FromStr;

/// OIDN's quality setting (`OIDNQuality`): how much time the network may
/// take.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Quality {
    /// OIDN's default (high, on the CPU).
    #[default]
    Default,
    /// For interactive previews.
    Fast,
    /// Between the two.
    Balanced,
    /// For final frames.
    High,
}

impl Quality {
    fn code(self) -> c_int {
        match self {
            Quality::Default => 0,
            Quality::Fast => 4,
            Quality::Balanced => 5,
            Quality::High => 6,
        }
    }
}

impl FromStr for Quality {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "default" => Ok(Quality::Default),
            "fast" => Ok(Quality::Fast),
            "balanced" => Ok(Quality::Balanced),
            "high" => Ok(Quality::High),
            _ => Err(format!("unknown denoising quality '{s}' (accepted: default, fast, balanced, high)")),
        }
    }
}

impl fmt::Display for Quality {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quality::Default => "default",
            Quality::Fast => "fast",
            Quality::Balanced => "balanced",
            Quality::High => "high",
        })
    }
}

/// How the albedo and normal images are given to the network.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AuxMode {
    /// Denoise them first, each with its own OIDN filter, then give them
    /// as noise-free (`cleanAux`): OIDN's advice for the best quality when
    /// they carry noise (depth of field, motion, textures under few
    /// samples).
    #[default]
    Prefilter,
    /// They are free of noise already: given as they are, as `cleanAux`.
    Clean,
    /// Given as they are, noise and all (`cleanAux` off): the network
    /// copes, at some loss of detail.
    Noisy,
}

impl FromStr for AuxMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "prefilter" => Ok(AuxMode::Prefilter),
            "clean" => Ok(AuxMode::Clean),
            "noisy" => Ok(AuxMode::Noisy),
            _ => Err(format!("unknown auxiliary-image mode '{s}' (accepted: prefilter, clean, noisy)")),
        }
    }
}

impl fmt::Display for AuxMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AuxMode::Prefilter => "prefilter",
            AuxMode::Clean => "clean",
            AuxMode::Noisy => "noisy",
        })
    }
}

/// How to denoise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DenoiseOptions {
    /// The network's quality setting.
    pub quality: Quality,
    /// How the albedo and normal are used.
    pub aux: AuxMode,
    /// OIDN's worker threads (`None`: OIDN's default, every core).
    pub threads: Option<usize>,
}

/// Why an image cannot be denoised.
#[derive(Debug, thiserror::Error)]
pub enum DenoiseError {
    /// OIDN is missing or unusable.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// OIDN reported an error.
    #[error("Open Image Denoise failed: {0}")]
    Oidn(String),
    /// An auxiliary image does not match the colour image.
    #[error("the {what} image has {got} values, but a {width}×{height} image needs {expected}")]
    Size {
        /// Which image.
        what: &'static str,
        /// Its number of values.
        got: usize,
        /// The number expected.
        expected: usize,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
    },
    /// OIDN takes a normal image only together with an albedo image.
    #[error("a normal image can only be used together with an albedo image (OIDN has no normal-only filter)")]
    NormalWithoutAlbedo,
}

/// An opened OIDN, ready to denoise images.
#[derive(Debug)]
pub struct Denoiser {
    library: Library,
}

/// OIDN's `OIDN_FORMAT_FLOAT3`.
const FORMAT_FLOAT3: c_int = 3;
/// OIDN's `OIDN_DEVICE_TYPE_CPU`: lucent is a CPU renderer, and the CPU
/// device gives the same result wherever it runs.
const DEVICE_CPU: c_int = 1;

impl Denoiser {
    /// Find and open OIDN ([`Library::find`]).
    pub fn new() -> Result<Self, DenoiseError> {
        Ok(Denoiser { library: Library::find()? })
    }

    /// Use an opened library.
    pub fn with_library(library: Library) -> Self {
        Denoiser { library }
    }

    /// Where OIDN was opened from.
    pub fn library_path(&self) -> &str {
        self.library.path()
    }

    /// Denoise `color` (linear radiance: OIDN's HDR mode), guided by
    /// `albedo` and `normal` (3 values per pixel, row by row from the top,
    /// as [`AovImages::layer`](crate::film::AovImages::layer) gives them).
    /// Non-finite and negative colour values are given to the network as 0.
    pub fn denoise(
        &self,
        color: &Film,
        albedo: Option<&[f32]>,
        normal: Option<&[f32]>,
        options: &DenoiseOptions,
    ) -> Result<Film, DenoiseError> {
        let (w, h) = (color.width(), color.height());
        let n = w as usize * h as usize * 3;
        for (what, image) in [("albedo", albedo), ("normal", normal)] {
            if let Some(image) = image.filter(|i| i.len() != n) {
                return Err(DenoiseError::Size { what, got: image.len(), expected: n, width: w, height: h });
            }
        }
        if normal.is_some() && albedo.is_none() {
            return Err(DenoiseError::NormalWithoutAlbedo);
        }
        let clean = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
        let mut input: Vec<f32> = color.pixels().iter().flat_map(|c| c.to_array()).map(clean).collect();
        let mut albedo: Option<Vec<f32>> =
            albedo.map(|a| a.iter().map(|&v| if v.is_finite() { v } else { 0.0 }).collect());
        let mut normal: Option<Vec<f32>> =
            normal.map(|a| a.iter().map(|&v| if v.is_finite() { v } else { 0.0 }).collect());
        let mut output = vec![0.0f32; n];

        let device = Device::new(&self.library, options.threads)?;
        if options.aux == AuxMode::Prefilter {
            // Each auxiliary image through its own filter, in place.
            if let Some(a) = albedo.as_mut() {
                let ptr = a.as_mut_ptr().cast();
                device.run(w, h, &[("albedo", ptr), ("output", ptr)], &[], options.quality)?;
            }
            if let Some(nrm) = normal.as_mut() {
                let ptr = nrm.as_mut_ptr().cast();
                device.run(w, h, &[("normal", ptr), ("output", ptr)], &[], options.quality)?;
            }
        }
        let mut images = vec![("color", input.as_mut_ptr().cast()), ("output", output.as_mut_ptr().cast())];
        if let Some(a) = albedo.as_mut() {
            images.push(("albedo", a.as_mut_ptr().cast()));
        }
        if let Some(nrm) = normal.as_mut() {
            images.push(("normal", nrm.as_mut_ptr().cast()));
        }
        let clean_aux = albedo.is_some() && options.aux != AuxMode::Noisy;
        device.run(w, h, &images, &[("hdr", true), ("cleanAux", clean_aux)], options.quality)?;

        let mut film = Film::new(w, h).expect("the size of an existing film");
        for (p, v) in film.pixels_mut().iter_mut().zip(output.chunks_exact(3)) {
            *p = Color::new(v[0], v[1], v[2]);
        }
        Ok(film)
    }
}

/// An OIDN CPU device, released when dropped.
struct Device<'a> {
    library: &'a Library,
    handle: library::Device,
}

impl<'a> Device<'a> {
    fn new(library: &'a Library, threads: Option<usize>) -> Result<Self, DenoiseError> {
        let api = &library.api;
        // SAFETY: OIDN's C API as declared in `library`; the handle is
        // checked for null and released by `Drop`.
        let handle = unsafe { (api.new_device)(DEVICE_CPU) };
        if handle.is_null() {
            return Err(DenoiseError::Oidn("cannot create a CPU device (is this CPU supported?)".into()));
        }
        let device = Device { library, handle };
        if let Some(t) = threads {
            let name = CString::new("numThreads").expect("no NUL");
            // SAFETY: a live device and a NUL-terminated parameter name.
            unsafe { (api.set_device_int)(handle, name.as_ptr(), t.min(c_int::MAX as usize) as c_int) };
        }
        // SAFETY: a live device.
        unsafe { (api.commit_device)(handle) };
        device.check()?;
        Ok(device)
    }

    /// The device's error since the last check, as an `Err`.
    fn check(&self) -> Result<(), DenoiseError> {
        match self.library.device_error(self.handle) {
            Some(e) => Err(DenoiseError::Oidn(e)),
            None => Ok(()),
        }
    }

    /// Run one `RT` filter on `w × h` images of three floats per pixel,
    /// each `(name, pointer)` of `images` a buffer of `3·w·h` floats that
    /// lives until this returns.
    fn run(
        &self,
        w: u32,
        h: u32,
        images: &[(&str, *mut c_void)],
        flags: &[(&str, bool)],
        quality: Quality,
    ) -> Result<(), DenoiseError> {
        let api = &self.library.api;
        let c = |s: &str| CString::new(s).expect("no NUL in OIDN parameter names");
        // SAFETY: a live device and a NUL-terminated filter type.
        let filter = unsafe { (api.new_filter)(self.handle, c("RT").as_ptr()) };
        self.check()?;
        if filter.is_null() {
            return Err(DenoiseError::Oidn("cannot create the RT filter".into()));
        }
        struct Release<'a>(&'a library::Api, library::Filter);
        impl Drop for Release<'_> {
            fn drop(&mut self) {
                // SAFETY: the filter was created above and is released once.
                unsafe { (self.0.release_filter)(self.1) };
            }
        }
        let _release = Release(api, filter);
        let (wu, hu) = (w as usize, h as usize);
        for &(name, ptr) in images {
            // SAFETY: each pointer addresses 3·w·h floats, tightly packed
            // (pixel stride 12 bytes, row stride 12·w), alive and not
            // otherwise accessed until the filter has run (`run` returns
            // after `execute_filter`, which is synchronous).
            unsafe {
                (api.set_shared_filter_image)(filter, c(name).as_ptr(), ptr, FORMAT_FLOAT3, wu, hu, 0, 12, 12 * wu)
            };
        }
        for &(name, value) in flags {
            // SAFETY: a live filter and a NUL-terminated parameter name.
            unsafe { (api.set_filter_bool)(filter, c(name).as_ptr(), value) };
        }
        // SAFETY: as above.
        unsafe { (api.set_filter_int)(filter, c("quality").as_ptr(), quality.code()) };
        // SAFETY: a live filter whose images are set.
        unsafe { (api.commit_filter)(filter) };
        self.check()?;
        // SAFETY: as above; the execution is synchronous.
        unsafe { (api.execute_filter)(filter) };
        self.check()
    }
}

impl Drop for Device<'_> {
    fn drop(&mut self) {
        // SAFETY: the device was created by `new` and is released once.
        unsafe { (self.library.api.release_device)(self.handle) };
    }
}
