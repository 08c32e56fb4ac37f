//! The bytes a glTF file points at: its buffers (the `.glb`'s binary chunk,
//! files beside it, `data:` URIs) and its images (the same three places),
//! read with every size checked before anything is allocated from it.

use super::GltfError;
use crate::texture::{decode_image, ColorEncoding, ImageSource, MipMap};
use base64::Engine;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The largest buffer or image file read (4 GiB: glTF's own byte lengths
/// are 32-bit in practice, and the `.glb` container's are).
const MAX_BYTES: u64 = 1 << 32;

/// Where a URI points: decoded bytes of a `data:` URI, or a file.
enum Resolved {
    Bytes(Vec<u8>),
    File(PathBuf),
}

/// Resolve `uri` against the folder of the glTF file: a `data:` URI
/// (base64 only, as glTF 2.0 §3.6.1.1 allows) or a relative file path,
/// percent-decoded. Absolute URLs (`http:`, …) are refused.
fn resolve(uri: &str, base: &Path, what: &str) -> Result<Resolved, GltfError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((header, payload)) = rest.split_once(',') else {
            return Err(GltfError::new(what, "a data: URI without a comma"));
        };
        if !header.ends_with(";base64") {
            return Err(GltfError::new(what, "a data: URI that is not base64 (glTF allows only base64)"));
        }
        // base64 gives 3 bytes per 4 characters: the size is known first.
        if payload.len() as u64 / 4 * 3 > MAX_BYTES {
            return Err(GltfError::new(what, "a data: URI over 4 GiB"));
        }
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(payload.trim_end())
            .map_err(|e| GltfError::new(what, format!("the data: URI is not valid base64: {e}")))?;
        return Ok(Resolved::Bytes(bytes));
    }
    if let Some((scheme, _)) = uri.split_once(':') {
        // A one-letter "scheme" is a Windows drive letter, not a URL.
        if scheme.len() > 1 && scheme.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c)) {
            return Err(GltfError::new(
                what,
                format!("the URI \"{uri}\" is not a relative file path (lucent reads no URLs)"),
            ));
        }
    }
    let decoded = percent_encoding::percent_decode_str(uri)
        .decode_utf8()
        .map_err(|_| GltfError::new(what, format!("the URI \"{uri}\" is not UTF-8 once percent-decoded")))?;
    Ok(Resolved::File(base.join(decoded.as_ref())))
}

/// Read a whole file, refusing one over [`MAX_BYTES`] before reading it.
fn read_file(path: &Path, what: &str) -> Result<Vec<u8>, GltfError> {
    let meta = std::fs::metadata(path)
        .map_err(|e| GltfError::new(what, format!("cannot open {}: {}", path.display(), io_reason(&e))))?;
    if meta.is_dir() {
        return Err(GltfError::new(what, format!("{} is a directory", path.display())));
    }
    if meta.len() > MAX_BYTES {
        return Err(GltfError::new(what, format!("{} is over 4 GiB", path.display())));
    }
    std::fs::read(path).map_err(|e| GltfError::new(what, format!("cannot read {}: {}", path.display(), io_reason(&e))))
}

fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_owned(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_owned(),
        _ => e.to_string(),
    }
}

/// Every buffer of the document, each at least as long as it declares
/// itself; the files read, for shipping the scene elsewhere.
pub(super) struct Buffers<'f> {
    /// Each buffer: a range of the `.glb` file's bytes (not copied), or
    /// bytes read from a file or a `data:` URI.
    data: Vec<std::borrow::Cow<'f, [u8]>>,
    pub files: Vec<PathBuf>,
}

impl Buffers<'_> {
    /// Buffer `i`, cut to its declared length.
    pub fn get(&self, i: usize) -> Option<&[u8]> {
        self.data.get(i).map(|b| &**b)
    }

    /// The bytes of all buffers together.
    pub fn total_len(&self) -> usize {
        self.data.iter().map(|b| b.len()).sum()
    }
}

/// Read the buffers of `doc`; `blob` is a `.glb`'s binary chunk.
pub(super) fn read_buffers<'f>(
    doc: &gltf::Document,
    blob: Option<&'f [u8]>,
    base: &Path,
) -> Result<Buffers<'f>, GltfError> {
    use std::borrow::Cow;
    let mut blob = blob;
    let mut out = Buffers { data: Vec::new(), files: Vec::new() };
    for buffer in doc.buffers() {
        let what = format!("buffers[{}]", buffer.index());
        let bytes: Cow<'f, [u8]> = match buffer.source() {
            gltf::buffer::Source::Bin => Cow::Borrowed(
                blob.take()
                    .ok_or_else(|| GltfError::new(&what, "refers to the binary chunk, which the file does not have"))?,
            ),
            gltf::buffer::Source::Uri(uri) => match resolve(uri, base, &format!("{what}.uri"))? {
                Resolved::Bytes(b) => Cow::Owned(b),
                Resolved::File(path) => {
                    let b = read_file(&path, &format!("{what}.uri"))?;
                    out.files.push(path);
                    Cow::Owned(b)
                }
            },
        };
        if bytes.len() < buffer.length() {
            return Err(GltfError::new(
                &what,
                format!("declares {} bytes (byteLength) but holds {}", buffer.length(), bytes.len()),
            ));
        }
        // The `.glb` chunk may be padded to 4 bytes; keep what is declared.
        let bytes = match bytes {
            Cow::Borrowed(b) => Cow::Borrowed(&b[..buffer.length()]),
            Cow::Owned(mut b) => {
                b.truncate(buffer.length());
                Cow::Owned(b)
            }
        };
        out.data.push(bytes);
    }
    Ok(out)
}

/// The slice of a buffer view, checked against its buffer.
pub(super) fn view_bytes<'a>(view: &gltf::buffer::View, buffers: &'a Buffers) -> Result<&'a [u8], GltfError> {
    let what = format!("bufferViews[{}]", view.index());
    let data = buffers
        .get(view.buffer().index())
        .ok_or_else(|| GltfError::new(&what, "refers to a buffer that does not exist"))?;
    let end = view.offset().checked_add(view.length());
    match end {
        Some(end) if end <= data.len() => Ok(&data[view.offset()..end]),
        _ => Err(GltfError::new(
            &what,
            format!(
                "bytes {}..{} lie outside its buffer of {} bytes",
                view.offset(),
                view.offset() as u128 + view.length() as u128,
                data.len()
            ),
        )),
    }
}

/// Decoded images, each decoded once per encoding (a texture used for
/// colour and for data is decoded twice).
#[derive(Default)]
pub(super) struct Images {
    maps: HashMap<(usize, bool), Arc<MipMap>>,
    pub files: Vec<PathBuf>,
}

impl Images {
    /// The MIP map of image `image`, sRGB-decoded when `srgb` (colour
    /// textures) and linear otherwise (glTF 2.0 §3.9.2, §3.9.3).
    pub fn mipmap(
        &mut self,
        doc: &gltf::Document,
        index: usize,
        srgb: bool,
        base: &Path,
        buffers: &Buffers,
    ) -> Result<Arc<MipMap>, GltfError> {
        let key = (index, srgb);
        if let Some(m) = self.maps.get(&key) {
            return Ok(Arc::clone(m));
        }
        let what = format!("images[{index}]");
        let encoding = if srgb { ColorEncoding::Srgb } else { ColorEncoding::Linear };
        // Read from the JSON rather than `gltf::Image::source`, which
        // panics on an image with neither `bufferView` nor `uri`, or a
        // `bufferView` without `mimeType` (gltf 1.4.1). The format is told
        // by the bytes, not the MIME type.
        let json = doc.as_json().images.get(index).ok_or_else(|| GltfError::new(&what, "does not exist"))?;
        let (bytes, path) = match (&json.buffer_view, &json.uri) {
            (Some(v), _) => {
                let view = doc.views().nth(v.value()).ok_or_else(|| {
                    GltfError::new(&what, format!("refers to bufferViews[{}], which does not exist", v.value()))
                })?;
                (view_bytes(&view, buffers)?.to_vec(), None)
            }
            (None, Some(uri)) => match resolve(uri, base, &format!("{what}.uri"))? {
                Resolved::Bytes(b) => (b, None),
                Resolved::File(p) => (read_file(&p, &format!("{what}.uri"))?, Some(p)),
            },
            (None, None) => return Err(GltfError::new(&what, "has neither a bufferView nor a uri")),
        };
        let label = path.clone().unwrap_or_else(|| PathBuf::from(&what));
        let decoded = decode_image(&label, &bytes, encoding).map_err(|e| GltfError::new(&what, e.to_string()))?;
        let mut map = MipMap::new(decoded).map_err(|e| GltfError::new(&what, e))?;
        if let Some(p) = path {
            let canonical = std::fs::canonicalize(&p).unwrap_or_else(|_| p.clone());
            map = map.with_source(ImageSource { path: canonical, encoding });
            if !self.files.contains(&p) {
                self.files.push(p);
            }
        }
        let map = Arc::new(map);
        self.maps.insert(key, Arc::clone(&map));
        Ok(map)
    }
}
