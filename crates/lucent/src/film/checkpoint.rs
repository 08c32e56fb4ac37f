//! Checkpoints: the state of a progressive render on disk, so that an
//! interrupted render can be resumed, or a finished one given more samples,
//! ending bit-identical to the same render done in one go.
//!
//! The file is little-endian binary:
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `LUCENTCK` |
//! | 4 | format version (2) |
//! | 4, 4 | width, height |
//! | 4 | samples per pixel done |
//! | 8 | fingerprint of everything that determines the samples |
//! | 4 | the auxiliary images held ([`AovSet::bits`]), and bit 31 set for adaptive sampling |
//! | 8 per sum | per pixel, `Σw·r, Σw·g, Σw·b, Σw`, `Σw·a` of each AOV channel and, for adaptive sampling, `Σw·r, Σw·g, Σw·b, Σw` of the odd-numbered samples, as i64 fixed point (see [`Accumulator`]) |
//! | 4 per pixel | adaptive sampling only: the pixel's sample count, bit 31 set once it stopped |
//!
//! Version 1 files (from lucent before AOVs: no AOV field, four sums per
//! pixel) are read too.
//!
//! It is written to a temporary file beside the target and renamed into
//! place, so a crash never leaves a truncated checkpoint.

use super::{check_image_size, Accumulator, AovSet};
use std::io::{Read, Write};
use std::path::Path;

const MAGIC: &[u8; 8] = b"LUCENTCK";
const VERSION: u32 = 2;
/// The bit of the AOV field that marks an adaptive render's checkpoint.
const ADAPTIVE: u32 = 1 << 31;
/// Bytes before the sums in version 1; version 2 adds 4.
const HEADER_V1: usize = 8 + 4 + 4 + 4 + 4 + 8;

/// Why a checkpoint cannot be written or used.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// Reading or writing failed.
    #[error("checkpoint {path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// Not a checkpoint, or damaged.
    #[error("checkpoint {path}: {message}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// The checkpoint holds other auxiliary images than the render makes.
    #[error(
        "checkpoint {path} holds the auxiliary images {held}, but the render asks for {asked}; render with the same --aov, or without --resume"
    )]
    AovMismatch {
        /// The file.
        path: String,
        /// The AOVs the checkpoint holds.
        held: AovSet,
        /// The AOVs the render makes.
        asked: AovSet,
    },
    /// The checkpoint belongs to another render.
    #[error(
        "checkpoint {path} was made by a different render (scene file, image size, seed, sampler, filter, integrator or depth differ); delete it or render without --resume"
    )]
    Mismatch {
        /// The file.
        path: String,
    },
}

/// Write `acc` with its `fingerprint` to `path`, atomically.
pub fn save_checkpoint(path: &Path, acc: &Accumulator, fingerprint: u64) -> Result<(), CheckpointError> {
    let io = |e: std::io::Error| CheckpointError::Io { path: path.display().to_string(), message: e.to_string() };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::Builder::new().prefix(".lucent-").suffix(".tmp").tempfile_in(dir).map_err(io)?;
    {
        let mut w = std::io::BufWriter::new(tmp.as_file_mut());
        w.write_all(MAGIC).map_err(io)?;
        for v in [VERSION, acc.width(), acc.height(), acc.spp()] {
            w.write_all(&v.to_le_bytes()).map_err(io)?;
        }
        w.write_all(&fingerprint.to_le_bytes()).map_err(io)?;
        let flags = acc.aovs().bits() | if acc.is_adaptive() { ADAPTIVE } else { 0 };
        w.write_all(&flags.to_le_bytes()).map_err(io)?;
        for v in acc.raw() {
            w.write_all(&v.to_le_bytes()).map_err(io)?;
        }
        for c in acc.raw_counts().unwrap_or_default() {
            w.write_all(&c.to_le_bytes()).map_err(io)?;
        }
        w.flush().map_err(io)?;
    }
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

/// Read a checkpoint, checking that it belongs to the render with
/// `fingerprint`, size `width × height`, auxiliary images `aovs` and
/// (or not) `adaptive` sampling.
pub fn load_checkpoint(
    path: &Path,
    fingerprint: u64,
    width: u32,
    height: u32,
    aovs: AovSet,
    adaptive: bool,
) -> Result<Accumulator, CheckpointError> {
    let name = path.display().to_string();
    let invalid = |m: &str| CheckpointError::Invalid { path: name.clone(), message: m.to_owned() };
    let mut f = std::fs::File::open(path).map_err(|e| CheckpointError::Io {
        path: name.clone(),
        message: format!("cannot open it: {}", e.kind().to_string().to_lowercase()),
    })?;
    let mut header = [0u8; HEADER_V1 + 4];
    f.read_exact(&mut header[..HEADER_V1]).map_err(|_| invalid("too short to be a lucent checkpoint"))?;
    if &header[..8] != MAGIC {
        return Err(invalid("not a lucent checkpoint (wrong magic bytes)"));
    }
    let version = u32::from_le_bytes(header[8..12].try_into().unwrap());
    let header_len = match version {
        1 => HEADER_V1,
        2 => {
            f.read_exact(&mut header[HEADER_V1..]).map_err(|_| invalid("too short to be a lucent checkpoint"))?;
            HEADER_V1 + 4
        }
        _ => {
            return Err(invalid(&format!(
                "format version {version} is not supported (this lucent reads versions 1 and {VERSION})"
            )))
        }
    };
    let u32_at = |i: usize| u32::from_le_bytes(header[i..i + 4].try_into().unwrap());
    let (w, h, spp) = (u32_at(12), u32_at(16), u32_at(20));
    let stored = u64::from_le_bytes(header[24..32].try_into().unwrap());
    if stored != fingerprint || w != width || h != height {
        return Err(CheckpointError::Mismatch { path: name });
    }
    let flags = if version == 1 { 0 } else { u32_at(HEADER_V1) };
    let held_adaptive = flags & ADAPTIVE != 0;
    let held = flags & !ADAPTIVE;
    let held = AovSet::from_bits(held).ok_or_else(|| invalid(&format!("unknown auxiliary images (bits {held:#x})")))?;
    if held_adaptive != adaptive {
        // The fingerprint covers the settings, so this is a damaged file.
        return Err(CheckpointError::Mismatch { path: name });
    }
    if held != aovs {
        return Err(CheckpointError::AovMismatch { path: name, held, asked: aovs });
    }
    check_image_size(w, h).map_err(|e| invalid(&e.to_string()))?;
    let pixels = w as usize * h as usize;
    let sums_len = pixels * (4 + aovs.stored_channels() + if adaptive { 4 } else { 0 });
    let counts_len = if adaptive { pixels } else { 0 };
    let expected = (sums_len * 8 + counts_len * 4) as u64;
    let actual = f.metadata().map(|m| m.len()).unwrap_or(0).saturating_sub(header_len as u64);
    if actual != expected {
        return Err(invalid(&format!("truncated or padded: {actual} bytes of pixel data, expected {expected}")));
    }
    let mut bytes = Vec::new();
    bytes.try_reserve_exact(expected as usize).map_err(|_| invalid("not enough memory to read it"))?;
    bytes.resize(expected as usize, 0);
    f.read_exact(&mut bytes).map_err(|_| invalid("truncated pixel data"))?;
    let (sums, counts) = bytes.split_at(sums_len * 8);
    let sums: Vec<i64> = sums.chunks_exact(8).map(|c| i64::from_le_bytes(c.try_into().unwrap())).collect();
    let counts = adaptive.then(|| counts.chunks_exact(4).map(|c| u32::from_le_bytes(c.try_into().unwrap())).collect());
    Accumulator::from_parts(w, h, spp, aovs, &sums, counts)
        .map_err(|_| invalid("its sample counts do not fit its sample total"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_refusals() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.ckpt");
        let mut acc = Accumulator::new(3, 2).unwrap();
        acc.splat(1, 1, crate::color::Color::new(1.5, -0.0, 1e5), 0.5);
        acc.add_spp(9);
        save_checkpoint(&path, &acc, 42).unwrap();
        let none = AovSet::NONE;
        assert_eq!(load_checkpoint(&path, 42, 3, 2, none, false).unwrap(), acc);
        assert!(matches!(load_checkpoint(&path, 43, 3, 2, none, false), Err(CheckpointError::Mismatch { .. })));
        assert!(matches!(load_checkpoint(&path, 42, 2, 3, none, false), Err(CheckpointError::Mismatch { .. })));
        let depth = AovSet::of(&[crate::film::Aov::Depth]);
        let e = load_checkpoint(&path, 42, 3, 2, depth, false).unwrap_err();
        assert!(matches!(e, CheckpointError::AovMismatch { .. }), "{e}");
        assert!(e.to_string().contains("holds the auxiliary images none, but the render asks for depth"), "{e}");
        // A version 1 file (before AOVs): no AOV field.
        let bytes = std::fs::read(&path).unwrap();
        let mut v1 = bytes[..HEADER_V1].to_vec();
        v1[8..12].copy_from_slice(&1u32.to_le_bytes());
        v1.extend_from_slice(&bytes[HEADER_V1 + 4..]);
        std::fs::write(&path, &v1).unwrap();
        assert_eq!(load_checkpoint(&path, 42, 3, 2, none, false).unwrap(), acc);
        // AOV sums round-trip.
        let mut with_depth = Accumulator::with_aovs(3, 2, depth).unwrap();
        with_depth.splat_with_aovs(2, 0, crate::color::Color::splat(0.5), &[3.25], 0.75);
        with_depth.add_spp(4);
        save_checkpoint(&path, &with_depth, 42).unwrap();
        assert_eq!(load_checkpoint(&path, 42, 3, 2, depth, false).unwrap(), with_depth);
        // Adaptive state: sums of the odd half and per-pixel counts.
        let mut adaptive = Accumulator::with_layout(3, 2, depth, true).unwrap();
        adaptive.add_spp(16);
        adaptive.stop_converged(0.5);
        adaptive.add_spp(8);
        save_checkpoint(&path, &adaptive, 42).unwrap();
        assert_eq!(load_checkpoint(&path, 42, 3, 2, depth, true).unwrap(), adaptive);
        assert!(matches!(load_checkpoint(&path, 42, 3, 2, depth, false), Err(CheckpointError::Mismatch { .. })));
        save_checkpoint(&path, &acc, 42).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        assert!(load_checkpoint(&path, 42, 3, 2, none, false).unwrap_err().to_string().contains("truncated"));
        std::fs::write(&path, b"PNG....").unwrap();
        assert!(load_checkpoint(&path, 42, 3, 2, none, false).unwrap_err().to_string().contains("too short"));
        assert!(load_checkpoint(&dir.path().join("missing"), 42, 3, 2, none, false)
            .unwrap_err()
            .to_string()
            .contains("cannot open"));
    }
}
