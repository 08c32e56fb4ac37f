//! A cache of MIP-mapped image files, so that a file used by many textures
//! is read and filtered once (pbrt-v4's `ImageTextureBase::textureCache`).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use super::image::{read_image, ColorEncoding, ImageError};
use super::mipmap::{ImageSource, MipMap};

/// The cache's table: a MIP map per (canonical path, encoding key).
type MipMaps = HashMap<(PathBuf, (u8, u32)), Arc<MipMap>>;

/// Image files loaded so far, keyed by canonical path and colour encoding.
/// Safe to share between threads: loads happen outside the lock, and when
/// two threads load the same file at once the first to finish wins and both
/// get its map.
#[derive(Debug, Default)]
pub struct ImageCache {
    maps: Mutex<MipMaps>,
}

impl ImageCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// The MIP map of the image file at `path`, decoded with `encoding`
    /// (see [`read_image`] for which formats honour it): loaded on first
    /// use, the same `Arc` afterwards.
    pub fn mipmap(&self, path: &Path, encoding: ColorEncoding) -> Result<Arc<MipMap>, ImageError> {
        let canonical = std::fs::canonicalize(path).map_err(|e| ImageError::new(path, format!("cannot open: {e}")))?;
        let key = (canonical, encoding.key());
        if let Some(m) = self.lock().get(&key) {
            return Ok(Arc::clone(m));
        }
        let image = read_image(path, encoding)?;
        let source = ImageSource { path: key.0.clone(), encoding };
        let map = Arc::new(MipMap::new(image).map_err(|m| ImageError::new(path, m))?.with_source(source));
        Ok(Arc::clone(self.lock().entry(key).or_insert(map)))
    }

    /// Number of cached maps.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, MipMaps> {
        // A panic elsewhere while holding the lock leaves the map valid.
        self.maps.lock().unwrap_or_else(|e| e.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_file_is_loaded_once() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.png");
        image::RgbImage::from_pixel(4, 2, image::Rgb([128, 128, 128])).save(&p).unwrap();
        let cache = ImageCache::new();
        let a = cache.mipmap(&p, ColorEncoding::Srgb).unwrap();
        // Another spelling of the same path.
        let again = dir.path().join(".").join("a.png");
        let b = cache.mipmap(&again, ColorEncoding::Srgb).unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        assert_eq!(cache.len(), 1);
        // It remembers where it came from, canonically.
        let src = a.source().unwrap();
        assert_eq!((src.path.clone(), src.encoding), (std::fs::canonicalize(&p).unwrap(), ColorEncoding::Srgb));
        assert_eq!(a.levels(), 3);
        assert!((a.level(0).unwrap().data()[0] - 0.2158605).abs() < 1e-6);
        // Another encoding is another map.
        let lin = cache.mipmap(&p, ColorEncoding::Linear).unwrap();
        assert!(!Arc::ptr_eq(&a, &lin));
        assert!((lin.level(0).unwrap().data()[0] - 128.0 / 255.0).abs() < 1e-7);
        assert_eq!(cache.len(), 2);
    }

    #[test]
    fn errors_name_the_file_and_are_not_cached() {
        let dir = tempfile::tempdir().unwrap();
        let cache = ImageCache::new();
        let e = cache.mipmap(&dir.path().join("missing.exr"), ColorEncoding::Linear).unwrap_err();
        assert!(e.to_string().contains("missing.exr") && e.message.contains("cannot open"), "{e}");
        let p = dir.path().join("bad.exr");
        std::fs::write(&p, b"v/1\x01 not really an EXR").unwrap();
        let e = cache.mipmap(&p, ColorEncoding::Linear).unwrap_err();
        assert!(e.to_string().contains("bad.exr"), "{e}");
        assert!(cache.is_empty());
    }

    #[test]
    fn shared_between_threads() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.pfm");
        let mut b = b"Pf\n1 1\n-1\n".to_vec();
        b.extend_from_slice(&0.5f32.to_le_bytes());
        std::fs::write(&p, b).unwrap();
        let cache = ImageCache::new();
        let maps: Vec<Arc<MipMap>> = std::thread::scope(|s| {
            let hs: Vec<_> = (0..4).map(|_| s.spawn(|| cache.mipmap(&p, ColorEncoding::Linear).unwrap())).collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        let first = cache.mipmap(&p, ColorEncoding::Linear).unwrap();
        assert!(maps.iter().all(|m| Arc::ptr_eq(m, &first)));
        assert_eq!(cache.len(), 1);
    }
}
