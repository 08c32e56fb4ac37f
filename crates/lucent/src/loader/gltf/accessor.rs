//! Accessors read by hand (glTF 2.0 §3.6.2): every component type,
//! normalised integers (`KHR_mesh_quantization`), strides and sparse
//! substitution, with each range checked against its buffer view before
//! anything is allocated, so that a malformed file gets an error that names
//! the accessor instead of a panic or a huge allocation.

use super::data::{view_bytes, Buffers};
use super::GltfError;
use gltf::accessor::{DataType, Dimensions};

/// The byte size of one component.
fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// Component `i` of the element at `bytes` as a number: floats as they
/// are, normalised integers mapped to [0, 1] or [−1, 1] (glTF 2.0 §3.11,
/// "Animations", gives the mapping: `max(c / 127, −1)` and so on), other
/// integers as their value.
#[inline]
fn component(bytes: &[u8], t: DataType, normalized: bool, i: usize) -> f32 {
    let s = component_size(t) * i;
    let b = &bytes[s..s + component_size(t)];
    match (t, normalized) {
        (DataType::F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        (DataType::U32, _) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        (DataType::I8, true) => (b[0] as i8 as f32 / 127.0).max(-1.0),
        (DataType::I8, false) => b[0] as i8 as f32,
        (DataType::U8, true) => b[0] as f32 / 255.0,
        (DataType::U8, false) => b[0] as f32,
        (DataType::I16, true) => (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
        (DataType::I16, false) => i16::from_le_bytes([b[0], b[1]]) as f32,
        (DataType::U16, true) => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
        (DataType::U16, false) => u16::from_le_bytes([b[0], b[1]]) as f32,
    }
}

/// An unsigned integer component (indices).
#[inline]
fn index_component(b: &[u8], t: DataType) -> Option<u32> {
    match t {
        DataType::U8 => Some(b[0] as u32),
        DataType::U16 => Some(u16::from_le_bytes([b[0], b[1]]) as u32),
        DataType::U32 => Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => None,
    }
}

/// The elements of `count` items of `size` bytes at `offset` in a view of
/// `stride` (0: tightly packed), each a slice, checked against the view.
fn elements<'a>(
    view: &'a [u8],
    offset: usize,
    count: usize,
    size: usize,
    stride: Option<usize>,
    what: &str,
) -> Result<impl Iterator<Item = &'a [u8]> + 'a, GltfError> {
    let stride = stride.unwrap_or(size);
    if stride < size {
        return Err(GltfError::new(what, format!("byteStride {stride} is smaller than an element ({size} bytes)")));
    }
    let end = count
        .checked_sub(1)
        .and_then(|last| last.checked_mul(stride))
        .and_then(|v| v.checked_add(offset))
        .and_then(|v| v.checked_add(size));
    match end {
        Some(end) if end <= view.len() => {}
        _ => {
            return Err(GltfError::new(
                what,
                format!(
                    "{count} elements of {size} bytes at byte {offset} (stride {stride}) do not fit in their buffer view of {} bytes",
                    view.len()
                ),
            ))
        }
    }
    Ok((0..count).map(move |i| &view[offset + i * stride..offset + i * stride + size]))
}

/// The number of components of an element.
fn width(d: Dimensions) -> usize {
    d.multiplicity()
}

/// Read `accessor` as `N`-component float vectors; `allowed` lists the
/// component types the attribute may have (glTF 2.0 §3.7.2.1 and
/// `KHR_mesh_quantization`), as `(type, normalized)`.
pub(super) fn read_floats<const N: usize>(
    accessor: &gltf::Accessor,
    buffers: &Buffers,
    allowed: &[(DataType, bool)],
    what: &str,
) -> Result<Vec<[f32; N]>, GltfError> {
    let what = format!("{what} (accessors[{}])", accessor.index());
    let (t, normalized) = (accessor.data_type(), accessor.normalized());
    if width(accessor.dimensions()) != N {
        return Err(GltfError::new(&what, format!("has type {:?}; expected {N} components", accessor.dimensions())));
    }
    // `normalized` means nothing for floats.
    let ok = allowed.contains(&(t, normalized)) || (t == DataType::F32 && allowed.contains(&(t, false)));
    if !ok {
        let accepted: Vec<String> =
            allowed.iter().map(|(t, n)| format!("{t:?}{}", if *n { " normalized" } else { "" })).collect();
        return Err(GltfError::new(
            &what,
            format!(
                "has component type {t:?}{} (accepted: {})",
                if normalized { " normalized" } else { "" },
                accepted.join(", ")
            ),
        ));
    }
    let count = accessor.count();
    let size = component_size(t) * N;
    let mut out: Vec<[f32; N]> = match accessor.view() {
        Some(view) => {
            let bytes = view_bytes(&view, buffers)?;
            let items = elements(bytes, accessor.offset(), count, size, view.stride(), &what)?;
            if t == DataType::F32 {
                // The common case, without the per-component dispatch.
                items
                    .map(|e| std::array::from_fn(|i| f32::from_le_bytes(e[4 * i..4 * i + 4].try_into().unwrap())))
                    .collect()
            } else {
                items.map(|e| std::array::from_fn(|i| component(e, t, normalized, i))).collect()
            }
        }
        None => {
            // All zeros, then sparse values (glTF 2.0 §3.6.2.3). Nothing in
            // the file backs the zeros, so their count is bounded by what
            // the file could describe otherwise.
            let limit = buffers.total_len().max(1 << 16);
            if count > limit {
                return Err(GltfError::new(
                    &what,
                    format!("has no buffer view and {count} elements (more than the file's {limit} bytes of data)"),
                ));
            }
            vec![[0.0; N]; count]
        }
    };
    if let Some(sparse) = accessor.sparse() {
        let n = sparse.count();
        let iview = view_bytes(&sparse.indices().view(), buffers)?;
        let it = match sparse.indices().index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let swhat = format!("{what}.sparse");
        let indices: Vec<u32> = elements(iview, sparse.indices().offset(), n, component_size(it), None, &swhat)?
            .map(|b| index_component(b, it).unwrap_or(0))
            .collect();
        let vview = view_bytes(&sparse.values().view(), buffers)?;
        let values = elements(vview, sparse.values().offset(), n, size, None, &swhat)?;
        for (i, v) in indices.into_iter().zip(values) {
            let slot = out.get_mut(i as usize).ok_or_else(|| {
                GltfError::new(&swhat, format!("index {i} is outside the accessor's {count} elements"))
            })?;
            *slot = std::array::from_fn(|c| component(v, t, normalized, c));
        }
    }
    Ok(out)
}

/// Read an index accessor (unsigned bytes, shorts or ints, scalar).
pub(super) fn read_indices(accessor: &gltf::Accessor, buffers: &Buffers, what: &str) -> Result<Vec<u32>, GltfError> {
    let t = accessor.data_type();
    if !matches!(t, DataType::U8 | DataType::U16 | DataType::U32) || accessor.dimensions() != Dimensions::Scalar {
        return Err(GltfError::new(
            what,
            format!("indices must be scalars of unsigned bytes, shorts or ints, got {:?} {t:?}", accessor.dimensions()),
        ));
    }
    // Integers up to 2²⁴ are exact in f32; read through floats only for
    // sparse substitution, which is rare for indices.
    if accessor.sparse().is_some() {
        let v = read_floats::<1>(accessor, buffers, &[(t, false)], what)?;
        if t == DataType::U32 && v.iter().any(|x| x[0] > (1 << 24) as f32) {
            return Err(GltfError::new(what, "sparse indices above 2²⁴ are not supported"));
        }
        return Ok(v.into_iter().map(|x| x[0] as u32).collect());
    }
    let what = format!("{what} (accessors[{}])", accessor.index());
    let Some(view) = accessor.view() else {
        return Err(GltfError::new(&what, "indices without a buffer view"));
    };
    let bytes = view_bytes(&view, buffers)?;
    let out = elements(bytes, accessor.offset(), accessor.count(), component_size(t), view.stride(), &what)?
        .map(|b| index_component(b, t).unwrap_or(0))
        .collect();
    Ok(out)
}
