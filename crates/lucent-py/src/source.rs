//! TEMPORARY stand-in for `lucent::loader::{SceneSource, SceneOverrides}`,
//! which the library is gaining with the same signatures; removed once they
//! land (then `scene.rs` imports the library's).

use lucent::film::check_image_size;
use lucent::loader::pbrt::{import_pbrt, ImportOptions};
use lucent::loader::{ImageDimension, IntegratorDesc, LoadedScene, MaxDepth, SampleCount, SamplerDesc, SceneFile};
use lucent::render::IntegratorKind;
use lucent::sampling::SamplerKind;
use lucent::scene::SceneError;
use std::path::{Path, PathBuf};

/// What a render changes of a scene's own settings.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneOverrides {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub spp: Option<u32>,
    pub seed: Option<u64>,
    pub integrator: Option<IntegratorKind>,
    pub sampler: Option<SamplerKind>,
    pub max_depth: Option<u32>,
    pub strict: bool,
    pub environment: Option<PathBuf>,
}

/// A scene loaded and built.
pub struct SceneSource {
    pub loaded: LoadedScene,
    path: Option<PathBuf>,
    description: String,
}

fn is_pbrt(path: &Path) -> bool {
    let name = path.file_name().map(|n| n.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    name.ends_with(".pbrt") || name.ends_with(".pbrt.gz")
}

impl SceneSource {
    pub fn open(path: &Path, o: &SceneOverrides) -> Result<SceneSource, SceneError> {
        if is_pbrt(path) {
            let options = ImportOptions {
                strict: o.strict,
                environment: o.environment.clone(),
                resolution: match (o.width, o.height) {
                    (None, None) => None,
                    (w, h) => Some((w, h)),
                },
            };
            let mut loaded = import_pbrt(path, &options)?;
            let s = &mut loaded.settings;
            if let Some(v) = o.spp {
                s.spp = v;
            }
            if let Some(v) = o.seed {
                s.seed = v;
            }
            if let Some(v) = o.integrator {
                s.integrator = v;
            }
            if let Some(v) = o.sampler {
                s.sampler = v;
            }
            if let Some(v) = o.max_depth {
                s.max_depth = v;
            }
            return Ok(SceneSource { loaded, path: Some(path.to_owned()), description: String::new() });
        }
        Self::from_file(SceneFile::load(path)?, o)
    }

    pub fn from_file(mut file: SceneFile, o: &SceneOverrides) -> Result<SceneSource, SceneError> {
        if o.strict || o.environment.is_some() {
            return Err(SceneError::new(file.path.clone(), "strict and env apply to pbrt-v4 scenes only"));
        }
        let r = &mut file.description.render;
        if let Some(v) = o.width {
            r.width = ImageDimension(v);
        }
        if let Some(v) = o.height {
            r.height = ImageDimension(v);
        }
        if let Some(v) = o.spp {
            r.spp = SampleCount(v);
        }
        if let Some(v) = o.seed {
            r.seed = v;
        }
        if let Some(v) = o.integrator {
            r.integrator = match v {
                IntegratorKind::Whitted => IntegratorDesc::Whitted,
                IntegratorKind::Path => IntegratorDesc::Path,
            };
        }
        if let Some(v) = o.sampler {
            r.sampler = Some(match v {
                SamplerKind::Stratified => SamplerDesc::Stratified,
                SamplerKind::Sobol => SamplerDesc::Sobol,
                SamplerKind::Independent => SamplerDesc::Independent,
            });
        }
        if let Some(v) = o.max_depth {
            r.max_depth = Some(MaxDepth(v));
        }
        if o.width.is_some() || o.height.is_some() {
            check_image_size(r.width.0, r.height.0).map_err(|e| SceneError::new(file.path.clone(), e.to_string()))?;
        }
        let loaded = file.build()?;
        Ok(SceneSource { loaded, path: file.path.clone(), description: format!("{:?}", file.description) })
    }

    pub fn files(&self) -> Vec<PathBuf> {
        let mut files = self.loaded.files.clone();
        files.extend(self.path.iter().filter(|p| p.is_file()).cloned());
        files.sort();
        files.dedup();
        files
    }

    pub fn base_dir(&self) -> Option<&Path> {
        self.path.as_deref().and_then(Path::parent)
    }

    pub fn fingerprint(&self) -> Result<u64, SceneError> {
        fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
            bytes.iter().fold(hash, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
        }
        let mut settings = self.loaded.settings.clone();
        if settings.sampler != SamplerKind::Stratified {
            settings.spp = 1;
        }
        let mut h = fnv1a(0xcbf2_9ce4_8422_2325, format!("{}\n{settings:?}", self.description).as_bytes());
        for path in self.files() {
            let bytes = std::fs::read(&path).map_err(|e| SceneError::new(Some(path.clone()), e.to_string()))?;
            h = fnv1a(h, &bytes);
        }
        Ok(h)
    }
}
