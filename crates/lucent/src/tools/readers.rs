//! Every reader of a file format, fed bytes as the program feeds it a
//! file: the entry points of the coverage-guided fuzz targets (`fuzz/`,
//! `cargo fuzz run NAME`) and of the test that replays their corpora and
//! every input that ever crashed (`fuzz/regressions/`) on stable Rust.
//!
//! A reader may accept or refuse its input; it must never panic, hang or
//! allocate without bound. A scene that loads is also rendered, as the
//! command line would with `--width 8 --height 8 --spp 1 --max-depth 8`,
//! and must give finite pixels.

use crate::film::{load_checkpoint, AovSet, PartialFilm};
use crate::loader::pbrt::parse_str;
use crate::loader::{SceneOverrides, SceneSource};
use crate::render::{render, RenderOptions};
use crate::spectrum::SpectrumType;
use std::path::{Path, PathBuf};

/// A reader under test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reader {
    /// PLY meshes, ASCII and binary ([`crate::mesh::parse_ply`]).
    Ply,
    /// Wavefront OBJ meshes ([`crate::mesh::parse_obj`]).
    Obj,
    /// pbrt-v4 scene text, parsed only ([`parse_str`]).
    PbrtParse,
    /// A pbrt-v4 scene file imported and rendered ([`import_pbrt`]).
    PbrtImport,
    /// A TOML scene, built and rendered ([`parse_scene`]), with the files
    /// it reads: `--- NAME` lines start other files, as for
    /// [`Reader::PbrtFiles`] (meshes, image textures, environment maps).
    /// An input without such lines is the scene alone.
    SceneToml,
    /// A JSON scene, built and rendered, with its files as
    /// [`Reader::SceneToml`].
    SceneJson,
    /// PFM images ([`crate::texture::read_pfm`]).
    Pfm,
    /// Any image a texture or environment map may be
    /// ([`crate::texture::read_image`]).
    Image,
    /// lucent's partial renders, `.lpart` ([`PartialFilm::from_bytes`]).
    Lpart,
    /// `.lpart` files less their checksum, which the reader appends
    /// (FNV-1a of the rest) before reading: structure for the fuzzer, whose
    /// mutations would otherwise nearly all stop at the checksum.
    LpartBody,
    /// lucent's checkpoints, `.ckpt` ([`load_checkpoint`]).
    Checkpoint,
    /// glTF 2.0 files, `.glb` or `.gltf` by their first bytes, imported and
    /// rendered ([`crate::loader::gltf::import_gltf`]).
    Gltf,
    /// pbrt-v4 `.spd` spectra ([`crate::spectrum::parse_spd`]), projected to
    /// RGB as each kind of parameter would be.
    Spd,
    /// A pbrt-v4 scene with the files it reads: the input is several files
    /// in one ([`split_files`]: the scene, then `--- NAME` lines each
    /// starting another file: includes, `.spd` spectra, PLY meshes,
    /// images), written to a folder of their own, imported and rendered.
    /// Structure for the fuzzer: it reaches `Include`, `Import` and every
    /// file-valued parameter, not only the first file.
    PbrtFiles,
}

impl Reader {
    /// Every reader.
    pub const ALL: [Reader; 14] = [
        Reader::Ply,
        Reader::Obj,
        Reader::PbrtParse,
        Reader::PbrtImport,
        Reader::SceneToml,
        Reader::SceneJson,
        Reader::Pfm,
        Reader::Image,
        Reader::Lpart,
        Reader::LpartBody,
        Reader::Checkpoint,
        Reader::Gltf,
        Reader::Spd,
        Reader::PbrtFiles,
    ];

    /// The fuzz target's name (and its folders under `fuzz/`).
    pub fn name(self) -> &'static str {
        match self {
            Reader::Ply => "ply",
            Reader::Obj => "obj",
            Reader::PbrtParse => "pbrt_parse",
            Reader::PbrtImport => "pbrt_import",
            Reader::SceneToml => "scene_toml",
            Reader::SceneJson => "scene_json",
            Reader::Pfm => "pfm",
            Reader::Image => "image",
            Reader::Lpart => "lpart",
            Reader::LpartBody => "lpart_body",
            Reader::Checkpoint => "checkpoint",
            Reader::Gltf => "gltf",
            Reader::Spd => "spd",
            Reader::PbrtFiles => "pbrt_files",
        }
    }

    /// Feed `data` to the reader. Returns whether it accepted the input;
    /// panics only where lucent has a defect (a panic inside a reader, or a
    /// scene that loads but renders NaN or infinite pixels).
    pub fn feed(self, data: &[u8]) -> bool {
        match self {
            Reader::Ply => crate::mesh::parse_ply(data, Path::new("fuzz.ply")).is_ok(),
            Reader::Obj => crate::mesh::parse_obj(data, Path::new("fuzz.obj")).is_ok(),
            Reader::PbrtParse => match std::str::from_utf8(data) {
                Ok(text) => parse_str(text, Path::new("fuzz.pbrt"), &mut |_, _| Ok(())).is_ok(),
                Err(_) => false,
            },
            Reader::PbrtImport => open_and_render("scene.pbrt", data),
            Reader::SceneToml => open_files_and_render("scene.toml", data),
            Reader::SceneJson => open_files_and_render("scene.json", data),
            Reader::Gltf => open_and_render(if data.starts_with(b"glTF") { "scene.glb" } else { "scene.gltf" }, data),
            Reader::Pfm => crate::texture::read_pfm(Path::new("fuzz.pfm"), data).is_ok(),
            Reader::Spd => {
                let Ok(text) = std::str::from_utf8(data) else { return false };
                let Ok(spectrum) = crate::spectrum::parse_spd(text) else { return false };
                for kind in [SpectrumType::Albedo, SpectrumType::Unbounded, SpectrumType::Illuminant] {
                    let rgb = spectrum.to_linear_srgb(kind);
                    assert!(!rgb.is_nan(), "a spectrum that parses projected to a NaN colour: {rgb}");
                }
                true
            }
            Reader::PbrtFiles => open_files_and_render("scene.pbrt", data),
            Reader::Image => {
                // Named .tga: TGA, the one format without magic bytes, is
                // known by its extension; the others by their contents.
                let path = scratch_file("image.tga", data);
                crate::texture::read_image(&path, crate::texture::ColorEncoding::Srgb).is_ok()
            }
            Reader::Lpart => PartialFilm::from_bytes(data, "fuzz.lpart").is_ok(),
            Reader::LpartBody => {
                let mut file = data.to_vec();
                file.extend_from_slice(&crate::film::fnv1a(data).to_le_bytes());
                PartialFilm::from_bytes(&file, "fuzz.lpart").is_ok()
            }
            Reader::Checkpoint => {
                let path = scratch_file("render.ckpt", data);
                // The fingerprint and size of the render asking for it:
                // those the file claims, so that the fuzzer gets past the
                // check to the pixel data (a real render compares its own).
                let word = |i: usize| data.get(i..i + 4).map_or(8, |b| u32::from_le_bytes(b.try_into().unwrap()));
                let fingerprint = data.get(24..32).map_or(0, |b| u64::from_le_bytes(b.try_into().unwrap()));
                let flags = word(32);
                let aovs = AovSet::from_bits(flags & !(1 << 31)).unwrap_or_default();
                load_checkpoint(&path, fingerprint, word(12), word(16), aovs, flags >> 31 == 1).is_ok()
            }
        }
    }
}

/// Most files [`split_files`] makes of one input.
pub const MAX_FILES: usize = 8;

/// The files of a multi-file input ([`Reader::PbrtFiles`],
/// [`Reader::SceneToml`], [`Reader::SceneJson`]): up to the first line
/// `--- NAME` it is the scene, named `scene`; each such line starts the
/// file `NAME` (letters, digits, `.`, `_` and `-`, not starting with `.`; a
/// line with another name is content), up to [`MAX_FILES`] files. Later
/// files of one name replace earlier ones.
pub fn split_files(scene: &str, data: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = vec![(scene.to_owned(), Vec::new())];
    for line in data.split_inclusive(|&b| b == b'\n') {
        let name = line
            .strip_prefix(b"--- ")
            .map(|n| n.strip_suffix(b"\n").unwrap_or(n))
            .and_then(|n| std::str::from_utf8(n).ok())
            .filter(|n| {
                !n.is_empty()
                    && !n.starts_with('.')
                    && n.len() <= 64
                    && n.bytes().all(|b| b.is_ascii_alphanumeric() || b"._-".contains(&b))
            });
        match name {
            Some(n) if files.len() < MAX_FILES => files.push((n.to_owned(), Vec::new())),
            _ => files.last_mut().expect("the scene file").1.extend_from_slice(line),
        }
    }
    files
}

/// A folder of this process and thread named `lucent-readers-…-NAME` in
/// the temporary directory, made if missing.
fn scratch_dir(name: &str) -> PathBuf {
    let thread = format!("{:?}", std::thread::current().id()).replace(|c: char| !c.is_ascii_alphanumeric(), "");
    std::env::temp_dir().join(format!("lucent-readers-{}-{thread}-{name}", std::process::id()))
}

/// Remove the scratch folders this thread's readers wrote (the fuzzers
/// keep theirs for the process's life; tests call this when done).
pub fn remove_scratch() {
    for name in ["one", "files"] {
        let _ = std::fs::remove_dir_all(scratch_dir(name));
    }
}

/// Write `data` to a file of this process and thread (readers that take a
/// path: an include or a texture then resolves next to it).
fn scratch_file(name: &str, data: &[u8]) -> PathBuf {
    let dir = scratch_dir("one");
    std::fs::create_dir_all(&dir).expect("a scratch folder in the temporary directory");
    let path = dir.join(name);
    std::fs::write(&path, data).expect("a scratch file in the temporary directory");
    path
}

/// Open a scene file as the command line does (with a small image), and
/// if it loads, render it and check its pixels.
fn open_and_render(name: &str, data: &[u8]) -> bool {
    open_and_render_path(&scratch_file(name, data))
}

/// [`open_and_render`] of the scene `scene` of a multi-file input
/// ([`split_files`]), its files written beside it.
fn open_files_and_render(scene: &str, data: &[u8]) -> bool {
    let files = split_files(scene, data);
    if files.len() == 1 {
        return open_and_render(scene, data);
    }
    let dir = scratch_dir("files");
    // A fresh folder per input: no file of an earlier input is seen.
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder in the temporary directory");
    for (name, bytes) in &files {
        std::fs::write(dir.join(name), bytes).expect("a scratch file in the temporary directory");
    }
    open_and_render_path(&dir.join(scene))
}

/// [`open_and_render`] of a file already written.
fn open_and_render_path(path: &Path) -> bool {
    let path = path.to_owned();
    let overrides =
        SceneOverrides { width: Some(8), height: Some(8), spp: Some(1), max_depth: Some(8), ..Default::default() };
    let Ok(source) = SceneSource::open(&path, &overrides) else { return false };
    let options = RenderOptions { threads: Some(1), ..RenderOptions::default() };
    if let Ok(out) = render(&source.loaded.scene, &source.loaded.settings, options) {
        assert!(out.film.pixels().iter().all(|p| p.is_finite()), "a scene that loads rendered a non-finite pixel");
    }
    true
}
