//! OpenEXR files with layers: the colour `R`, `G`, `B` and the auxiliary
//! images' channels (`Albedo.R`, `Ns.X`, `Z`...), written by a render with
//! AOVs and read back by `lucent denoise`.

use super::{Aov, AovImages, AovSet, Film, Layers};
use crate::color::Color;
use std::io::Write;
use std::path::Path;

/// Why an EXR with layers cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ExrError {
    /// The file cannot be read or decoded.
    #[error("cannot read '{path}': {message}")]
    Read {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The file lacks the colour channels.
    #[error("'{path}' has no colour channels R, G and B (it has {found})")]
    NoColour {
        /// The file.
        path: String,
        /// The channels it has.
        found: String,
    },
}

/// An OpenEXR file of 32-bit float channels: `R`, `G`, `B` and every
/// channel of `aovs` (one part, no layer name; the AOV channels carry
/// theirs as `Layer.Channel`, as pbrt-v4 and Blender write them), with
/// lossless ZIP compression of 16 rows per block.
///
/// Of `layers`: the noisy colour, if given, is written as `Noisy.R/G/B`
/// (the colour before denoising, beside the denoised `R`, `G`, `B`), and
/// the sample counts of adaptive sampling as `SampleCount`.
pub fn write(out: &mut (impl Write + std::io::Seek), film: &Film, layers: &Layers<'_>) -> exr::error::Result<()> {
    let (noisy, aovs) = (layers.noisy, layers.aovs);
    use exr::prelude::*;
    let (w, h) = (film.width() as usize, film.height() as usize);
    let colour = |f: &Film, i: usize| FlatSamples::F32(f.pixels().iter().map(|c| c.to_array()[i]).collect());
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for (i, name) in ["R", "G", "B"].into_iter().enumerate() {
        channels.push(AnyChannel::new(name, colour(film, i)));
    }
    if let Some(noisy) = noisy {
        for (i, name) in ["Noisy.R", "Noisy.G", "Noisy.B"].into_iter().enumerate() {
            channels.push(AnyChannel::new(name, colour(noisy, i)));
        }
    }
    if let Some(counts) = layers.sample_counts {
        channels.push(AnyChannel::new("SampleCount", FlatSamples::F32(counts.iter().map(|&c| c as f32).collect())));
    }
    let stride = aovs.aovs.channel_count();
    for (k, name) in aovs.aovs.channel_names().into_iter().enumerate() {
        let values = aovs.values.iter().skip(k).step_by(stride).copied().collect();
        channels.push(AnyChannel::new(name, FlatSamples::F32(values)));
    }
    let layer =
        Layer::new((w, h), LayerAttributes::default(), Encoding::SMALL_FAST_LOSSLESS, AnyChannels::sort(channels));
    Image::from_layer(layer).write().non_parallel().to_buffered(out)
}

/// Read the colour (`R`, `G`, `B`, required) and every auxiliary image
/// whose channels are all present (named as [`Aov::channels`] says) from
/// the first layer of an OpenEXR file. Other channels are ignored.
pub fn read(path: &Path) -> Result<(Film, AovImages), ExrError> {
    use exr::prelude::*;
    let name = path.display().to_string();
    // The size first, from the header alone: a file that claims a huge
    // image is refused before anything is allocated for it.
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| ExrError::Read { path: name.clone(), message: e.to_string() })?;
    for header in meta.headers.iter() {
        let size = header.layer_size;
        let (w, h) =
            (u32::try_from(size.width()).unwrap_or(u32::MAX), u32::try_from(size.height()).unwrap_or(u32::MAX));
        super::check_image_size(w, h).map_err(|e| ExrError::Read { path: name.clone(), message: e.to_string() })?;
    }
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| ExrError::Read { path: name.clone(), message: e.to_string() })?;
    let layer = &image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    let channel = |n: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == n)
            .map(|c| c.sample_data.values_as_f32().collect::<Vec<f32>>())
    };
    let (Some(r), Some(g), Some(b)) = (channel("R"), channel("G"), channel("B")) else {
        let found: Vec<String> = layer.channel_data.list.iter().map(|c| c.name.to_string()).collect();
        return Err(ExrError::NoColour {
            path: name,
            found: if found.is_empty() { "none".into() } else { found.join(", ") },
        });
    };
    let read_error = |m: String| ExrError::Read { path: name.clone(), message: m };
    let mut film = Film::new(w as u32, h as u32).map_err(|e| read_error(e.to_string()))?;
    for (i, p) in film.pixels_mut().iter_mut().enumerate() {
        *p = Color::new(r[i], g[i], b[i]);
    }
    let held: Vec<Aov> = Aov::ALL.into_iter().filter(|a| a.channels().iter().all(|c| channel(c).is_some())).collect();
    let aovs = AovSet::of(&held);
    let columns: Vec<Vec<f32>> = aovs.channel_names().iter().map(|c| channel(c).expect("checked")).collect();
    let values = (0..w * h).flat_map(|i| columns.iter().map(move |c| c[i])).collect();
    Ok((film, AovImages { width: w as u32, height: h as u32, aovs, values }))
}
