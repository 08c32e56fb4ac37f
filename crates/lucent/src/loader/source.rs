//! One way to open any scene: [`SceneSource`] loads lucent's own TOML/JSON
//! or a pbrt-v4 file, applies the changes a caller makes to its settings
//! (the command line's `--width`, `--spp`, …, or Python's keyword
//! arguments), and fingerprints what decides its samples, so that
//! checkpoints and partial renders of it can be recognised.

use super::gltf::{import_gltf, is_gltf_path, GltfOptions};
use super::pbrt::{import_pbrt, ImportOptions};
use super::{
    AovDesc, ImageDimension, IntegratorDesc, LoadedScene, MaxDepth, Positive, SampleCount, SamplerDesc,
    SceneDescription, SceneFile,
};
use crate::film::{check_image_size, AovSet};
use crate::render::{IntegratorKind, RenderSettings};
use crate::sampling::SamplerKind;
use crate::scene::SceneError;
use std::path::{Path, PathBuf};

/// Changes to a scene's own settings, made when it is opened (as the
/// command line's options make them). `None` keeps the scene's value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneOverrides {
    /// Image width in pixels.
    pub width: Option<u32>,
    /// Image height in pixels.
    pub height: Option<u32>,
    /// Samples per pixel.
    pub spp: Option<u32>,
    /// Seed of the sampler.
    pub seed: Option<u64>,
    /// The light transport algorithm.
    pub integrator: Option<IntegratorKind>,
    /// The sample sequence.
    pub sampler: Option<SamplerKind>,
    /// Most bounces.
    pub max_depth: Option<u32>,
    /// Auxiliary images (replacing the scene's `aov` list).
    pub aovs: Option<AovSet>,
    /// Place samples by filter importance sampling (see
    /// [`RenderSettings::filter_importance`](crate::render::RenderSettings::filter_importance)).
    pub filter_importance: Option<bool>,
    /// Adaptive sampling's threshold (replacing the scene's `adaptive`).
    pub adaptive: Option<f32>,
    /// The path tracer's clamp of indirect light (replacing the scene's
    /// `max_indirect`).
    pub max_indirect: Option<f32>,
    /// The clamp of indirect light where neither the scene nor
    /// [`max_indirect`](Self::max_indirect) sets one (`lucent render
    /// --denoise` asks for 10, as Blender's Cycles clamps by default).
    pub default_max_indirect: Option<f32>,
    /// pbrt-v4 and glTF scenes only: every importer warning is an error.
    pub strict: bool,
    /// pbrt-v4 scenes: the image for every `infinite` light with a
    /// `filename` (for scenes shipped without their environment map);
    /// glTF scenes (which have no environment): the environment.
    pub environment: Option<PathBuf>,
    /// glTF scenes only: which scene of the file (`scenes[N]`).
    pub gltf_scene: Option<usize>,
    /// glTF scenes only: which camera, by name or index.
    pub camera: Option<String>,
}

/// A scene opened from a file or from parsed text, built, with what is
/// needed to fingerprint it.
#[derive(Clone, Debug)]
pub struct SceneSource {
    /// The built scene and its settings.
    pub loaded: LoadedScene,
    /// The scene file, if the scene came from one.
    path: Option<PathBuf>,
    /// What decides the samples besides the files: the description with
    /// its display settings left out (TOML/JSON), or a tag (pbrt-v4, whose
    /// text is among the files).
    key: String,
    /// Whether the scene file itself is among `loaded.files`.
    pbrt: bool,
}

/// Whether `path` names a pbrt-v4 file (`.pbrt`, `.pbrt.gz`).
pub fn is_pbrt_path(path: &Path) -> bool {
    let name = path.file_name().map(|n| n.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    name.ends_with(".pbrt") || name.ends_with(".pbrt.gz")
}

impl SceneSource {
    /// Open the scene at `path`: pbrt-v4 (`.pbrt`, `.pbrt.gz`) or lucent's
    /// TOML/JSON, by extension, with `overrides` applied.
    ///
    /// ```
    /// use lucent::loader::{SceneOverrides, SceneSource};
    /// let dir = tempfile::tempdir().unwrap();
    /// let path = dir.path().join("scene.toml");
    /// std::fs::write(&path, "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n").unwrap();
    /// let overrides = SceneOverrides { width: Some(32), spp: Some(2), ..Default::default() };
    /// let source = SceneSource::open(&path, &overrides).unwrap();
    /// assert_eq!(source.loaded.scene.camera().width(), 32);
    /// assert_eq!(source.loaded.settings.spp, 2);
    /// assert_eq!(source.files(), vec![path]);
    /// ```
    pub fn open(path: &Path, overrides: &SceneOverrides) -> Result<Self, SceneError> {
        let is_gltf = is_gltf_path(path);
        if !is_gltf && (overrides.gltf_scene.is_some() || overrides.camera.is_some()) {
            return Err(SceneError::new(
                Some(path.to_owned()),
                "choosing a scene or a camera applies to glTF scenes (.gltf, .glb) only",
            ));
        }
        if is_gltf {
            let options = GltfOptions {
                strict: overrides.strict,
                environment: overrides.environment.clone(),
                resolution: match (overrides.width, overrides.height) {
                    (None, None) => None,
                    (w, h) => Some((w, h)),
                },
                scene: overrides.gltf_scene,
                camera: overrides.camera.clone(),
            };
            let mut loaded = import_gltf(path, &options)?;
            apply_to_settings(&mut loaded.settings, overrides);
            let key = format!("glTF scene {:?} camera {:?}", overrides.gltf_scene, overrides.camera);
            return Ok(Self { loaded, path: Some(path.to_owned()), key, pbrt: true });
        }
        if is_pbrt_path(path) {
            let options = ImportOptions {
                strict: overrides.strict,
                environment: overrides.environment.clone(),
                resolution: match (overrides.width, overrides.height) {
                    (None, None) => None,
                    (w, h) => Some((w, h)),
                },
            };
            let mut loaded = import_pbrt(path, &options)?;
            apply_to_settings(&mut loaded.settings, overrides);
            return Ok(Self { loaded, path: Some(path.to_owned()), key: "pbrt-v4".into(), pbrt: true });
        }
        Self::from_file(SceneFile::load(path)?, overrides)
    }

    /// Build a parsed TOML/JSON scene with `overrides` applied. Relative
    /// paths in it resolve against the directory of `file.path`.
    pub fn from_file(mut file: SceneFile, overrides: &SceneOverrides) -> Result<Self, SceneError> {
        if overrides.strict || overrides.environment.is_some() {
            return Err(SceneError::new(
                file.path.clone(),
                "`strict` and an environment override apply to pbrt-v4 (.pbrt) and glTF (.gltf, .glb) scenes only",
            ));
        }
        apply(&mut file, overrides)?;
        let loaded = file.build()?;
        Ok(Self { key: description_key(&file.description), loaded, path: file.path, pbrt: false })
    }

    /// The scene file, if the scene came from one.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The directory that relative paths in the scene resolve against
    /// (`None`: the current directory).
    pub fn base_dir(&self) -> Option<&Path> {
        self.path.as_deref().and_then(Path::parent).filter(|d| !d.as_os_str().is_empty())
    }

    /// Every file the scene was made from: the scene file (if any), the
    /// files it includes and every mesh, image and spectrum it read,
    /// sorted and without repeats.
    pub fn files(&self) -> Vec<PathBuf> {
        let mut files = self.loaded.files.clone();
        if let (Some(p), false) = (&self.path, self.pbrt) {
            files.push(p.clone());
        }
        files.sort();
        files.dedup();
        files
    }

    /// A fingerprint of everything that decides the samples of a render of
    /// this scene: the description, with its sample count and display
    /// settings (tone mapping, sRGB) left out since those may change
    /// between a render and its continuation; the settings as resolved
    /// (so a default written out explicitly fingerprints the same as the
    /// default); and the name (relative to the scene's directory) and
    /// contents of every file it read. It does not depend on where the
    /// scene's directory is, so a copy of it elsewhere (on another
    /// machine) fingerprints the same. The stratified sampler lays each
    /// pixel's samples out as grids of `spp`, so with it the sample count
    /// is part of the fingerprint too.
    pub fn fingerprint(&self) -> Result<u64, SceneError> {
        let mut settings = self.loaded.settings.clone();
        if settings.sampler != SamplerKind::Stratified {
            settings.spp = 1;
        }
        settings.tone_map = Default::default();
        settings.srgb = true;
        // The auxiliary images change no sample; the files that hold the
        // sums say which they hold.
        settings.aovs = AovSet::NONE;
        let mut h = fnv1a(FNV_OFFSET, format!("{}\n{settings:?}", self.key).as_bytes());
        let base = self.base_dir().unwrap_or(Path::new("."));
        for path in &self.loaded.files {
            let bytes = std::fs::read(path).map_err(|e| {
                SceneError::new(self.path.clone(), format!("cannot read {} again: {e}", path.display()))
            })?;
            h = fnv1a(fnv1a(h, super::export::relative_path(path, base).as_bytes()), &bytes);
        }
        Ok(h)
    }
}

/// The overrides of an imported scene's (pbrt-v4, glTF) render settings;
/// the image size is the importer's business.
fn apply_to_settings(s: &mut RenderSettings, overrides: &SceneOverrides) {
    s.spp = overrides.spp.unwrap_or(s.spp);
    s.seed = overrides.seed.unwrap_or(s.seed);
    s.integrator = overrides.integrator.unwrap_or(s.integrator);
    s.sampler = overrides.sampler.unwrap_or(s.sampler);
    s.max_depth = overrides.max_depth.unwrap_or(s.max_depth);
    s.aovs = overrides.aovs.unwrap_or(s.aovs);
    s.filter_importance = overrides.filter_importance.unwrap_or(s.filter_importance);
    s.adaptive = overrides.adaptive.or(s.adaptive);
    s.max_indirect = overrides.max_indirect.or(s.max_indirect).or(overrides.default_max_indirect);
}

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a, 64-bit: stable across runs and platforms, unlike std's randomly
/// keyed hasher.
fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

/// Apply `overrides` to a parsed scene file. An image size set here is
/// checked here, so that an error names the override rather than a line of
/// the file.
fn apply(file: &mut SceneFile, o: &SceneOverrides) -> Result<(), SceneError> {
    let path = file.path.clone();
    let r = &mut file.description.render;
    if let Some(w) = o.width {
        r.width = ImageDimension(w);
    }
    if let Some(h) = o.height {
        r.height = ImageDimension(h);
    }
    if let Some(spp) = o.spp {
        r.spp = SampleCount(spp);
    }
    if let Some(seed) = o.seed {
        r.seed = seed;
    }
    if let Some(i) = o.integrator {
        r.integrator = match i {
            IntegratorKind::Whitted => IntegratorDesc::Whitted,
            IntegratorKind::Path => IntegratorDesc::Path,
            IntegratorKind::Bdpt => IntegratorDesc::Bdpt,
        };
    }
    if let Some(s) = o.sampler {
        r.sampler = Some(match s {
            SamplerKind::Stratified => SamplerDesc::Stratified,
            SamplerKind::Sobol => SamplerDesc::Sobol,
            SamplerKind::Independent => SamplerDesc::Independent,
        });
    }
    if let Some(d) = o.max_depth {
        r.max_depth = Some(MaxDepth(d));
    }
    if let Some(fis) = o.filter_importance {
        r.filter_importance = fis;
    }
    if let Some(m) = o.max_indirect {
        r.max_indirect =
            Some(Positive::try_from(m).map_err(|e| SceneError::new(path.clone(), format!("max_indirect: {e}")))?);
    }
    if let (None, Some(m)) = (r.max_indirect, o.default_max_indirect) {
        r.max_indirect =
            Some(Positive::try_from(m).map_err(|e| SceneError::new(path.clone(), format!("max_indirect: {e}")))?);
    }
    if let Some(t) = o.adaptive {
        r.adaptive = Some(
            Positive::try_from(t)
                .map_err(|e| SceneError::new(path.clone(), format!("the adaptive sampling threshold: {e}")))?,
        );
    }
    if let Some(aovs) = o.aovs {
        r.aov = aovs.iter().map(AovDesc::from).collect();
    }
    if o.width.is_some() || o.height.is_some() {
        check_image_size(r.width.0, r.height.0).map_err(|e| {
            let given: Vec<String> = [("width", o.width), ("height", o.height)]
                .iter()
                .filter_map(|(name, v)| v.map(|v| format!("{name} {v}")))
                .collect();
            SceneError::new(path, format!("{}: {e}", given.join(", ")))
        })?;
    }
    Ok(())
}

/// The description with what may change between a render and its
/// continuation (the sample count, tone mapping, sRGB, depth and sampler,
/// which the resolved settings carry) left out.
fn description_key(description: &SceneDescription) -> String {
    let mut d = description.clone();
    d.render.spp = SampleCount(1);
    d.render.tone_map = Default::default();
    d.render.srgb = true;
    d.render.max_depth = None;
    d.render.sampler = None;
    d.render.aov = Vec::new();
    format!("{d:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n[render]\nintegrator = \"path\"\n\
        [materials.m.matte]\ncolor = [1, 0, 0]\n[[mesh]]\nfile = \"m/tri.obj\"\nmaterial = \"m\"\n";
    const TRI: &str = "v -1 0 1\nv 1 0 1\nv 0 1 1\nf 1 2 3\n";

    fn write_scene(dir: &Path, scene: &str, tri: &str) -> PathBuf {
        std::fs::create_dir_all(dir.join("m")).unwrap();
        std::fs::write(dir.join("m/tri.obj"), tri).unwrap();
        std::fs::write(dir.join("s.toml"), scene).unwrap();
        dir.join("s.toml")
    }

    /// The fingerprint follows what decides the samples, not where the
    /// scene's directory is or how its defaults are written.
    #[test]
    fn fingerprints_are_independent_of_the_scene_directory() {
        let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let none = SceneOverrides::default();
        let here = SceneSource::open(&write_scene(a.path(), SCENE, TRI), &none).unwrap();
        let there = SceneSource::open(&write_scene(&b.path().join("deeper"), SCENE, TRI), &none).unwrap();
        assert_eq!(here.fingerprint().unwrap(), there.fingerprint().unwrap());
        assert_eq!(here.files(), vec![a.path().join("m/tri.obj"), a.path().join("s.toml")]);
        assert_eq!(here.base_dir(), Some(a.path()));
        // The sample count and display settings are not part of it.
        let more = SceneOverrides { spp: Some(99), ..Default::default() };
        let explicit = SCENE.replace("[render]\n", "[render]\nsrgb = true\nmax_depth = 64\n");
        let same = SceneSource::open(&write_scene(b.path(), &explicit, TRI), &more).unwrap();
        assert_eq!(same.fingerprint().unwrap(), here.fingerprint().unwrap());
        // The seed, the mesh's contents and the image size are.
        let seeded =
            SceneSource::open(&write_scene(b.path(), SCENE, TRI), &SceneOverrides { seed: Some(1), ..none.clone() });
        assert_ne!(seeded.unwrap().fingerprint().unwrap(), here.fingerprint().unwrap());
        let moved = SceneSource::open(&write_scene(b.path(), SCENE, &TRI.replace("0 1 1", "0 2 1")), &none).unwrap();
        assert_ne!(moved.fingerprint().unwrap(), here.fingerprint().unwrap());
        let wide = SceneSource::open(&write_scene(b.path(), SCENE, TRI), &SceneOverrides { width: Some(9), ..none });
        assert_ne!(wide.unwrap().fingerprint().unwrap(), here.fingerprint().unwrap());
    }

    /// The render overrides of issue 29: AOVs change no sample (not in the
    /// fingerprint); filter importance sampling, adaptive sampling and the
    /// clamp do; the default clamp applies only where none is set.
    #[test]
    fn aovs_fis_adaptive_and_clamp_overrides() {
        let dir = tempfile::tempdir().unwrap();
        let path = write_scene(dir.path(), SCENE, TRI);
        let open = |o: SceneOverrides| SceneSource::open(&path, &o).unwrap();
        let plain = open(SceneOverrides::default());
        let aovs = open(SceneOverrides { aovs: Some(AovSet::of(&[crate::film::Aov::Depth])), ..Default::default() });
        assert_eq!(aovs.loaded.settings.aovs.to_string(), "depth");
        assert_eq!(aovs.fingerprint().unwrap(), plain.fingerprint().unwrap());
        let fis = open(SceneOverrides { filter_importance: Some(true), ..Default::default() });
        assert!(fis.loaded.settings.filter_importance);
        assert_ne!(fis.fingerprint().unwrap(), plain.fingerprint().unwrap());
        let adaptive = open(SceneOverrides { adaptive: Some(0.02), ..Default::default() });
        assert_eq!(adaptive.loaded.settings.adaptive, Some(0.02));
        assert_ne!(adaptive.fingerprint().unwrap(), plain.fingerprint().unwrap());
        let defaulted = open(SceneOverrides { default_max_indirect: Some(10.0), ..Default::default() });
        assert_eq!(defaulted.loaded.settings.max_indirect, Some(10.0));
        let clamped = SCENE.replace("[render]\n", "[render]\nmax_indirect = 3\n");
        let own = SceneSource::open(
            &write_scene(dir.path(), &clamped, TRI),
            &SceneOverrides { default_max_indirect: Some(10.0), ..Default::default() },
        )
        .unwrap();
        assert_eq!(own.loaded.settings.max_indirect, Some(3.0));
        let given = SceneSource::open(
            &write_scene(dir.path(), &clamped, TRI),
            &SceneOverrides { max_indirect: Some(5.0), default_max_indirect: Some(10.0), ..Default::default() },
        )
        .unwrap();
        assert_eq!(given.loaded.settings.max_indirect, Some(5.0));
        let e = SceneSource::open(&path, &SceneOverrides { adaptive: Some(-1.0), ..Default::default() }).unwrap_err();
        assert!(e.to_string().contains("adaptive sampling threshold"), "{e}");
    }

    #[test]
    fn pbrt_options_are_refused_for_lucent_scenes() {
        let dir = tempfile::tempdir().unwrap();
        let o = SceneOverrides { strict: true, ..Default::default() };
        let e = SceneSource::open(&write_scene(dir.path(), SCENE, TRI), &o).unwrap_err();
        assert!(e.to_string().contains("glTF (.gltf, .glb) scenes only"), "{e}");
        let o = SceneOverrides { width: Some(65_536), height: Some(65_536), ..Default::default() };
        let e = SceneSource::open(&write_scene(dir.path(), SCENE, TRI), &o).unwrap_err();
        assert!(e.to_string().contains("s.toml: width 65536, height 65536: image size"), "{e}");
    }
}
