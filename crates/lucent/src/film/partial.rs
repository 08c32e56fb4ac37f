//! Partial films: the exact sums of a range of sample indices, which add up
//! to the image of all of them.
//!
//! A pixel's image value is `Σ wᵢ·Lᵢ / Σ wᵢ` over its samples, and the
//! [`Accumulator`] keeps both sums as fixed-point integers. Integer
//! addition is exact, associative and commutative, so the sums of disjoint
//! ranges of sample indices rendered anywhere (other processes, other
//! machines) add up to exactly the sums of one render of all of them: the
//! merged image is bit-identical to a single render, whatever the order or
//! grouping of the merge.
//!
//! # The `.lpart` file (version 2)
//!
//! Little-endian binary:
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `LUCENTPT` |
//! | 4 | format version (1) |
//! | 4, 4 | width, height |
//! | 8 | fingerprint of the scene and settings (the loader's `SceneSource::fingerprint`) |
//! | 4, 4 | tone mapping (0 classic, 1 clamp, 2 Reinhard, 3 ACES) and sRGB (0 or 1) for 8-bit output |
//! | 4 | the auxiliary images held ([`AovSet::bits`]) |
//! | 4 | number of sample ranges `n` (at least 1) |
//! | 8·n | the ranges, `start` and `end` (exclusive) as u32, sorted, non-empty, neither overlapping nor touching |
//! | 8 per sum | per pixel, row by row from the top, `Σw·r, Σw·g, Σw·b, Σw` and `Σw·a` of each AOV channel, as i64 fixed point |
//! | 8 | checksum: 64-bit FNV-1a of every byte before it |
//!
//! Version 1 (lucent before AOVs) lacks the AOV field and holds four sums
//! per pixel; it is read too.
//!
//! Writing goes to a temporary file beside the target, renamed into place
//! when complete, so a crash never leaves a truncated part.

use super::{check_image_size, Accumulator, AovImages, AovSet, Film, ToneMap};
use std::fmt::Write as _;
use std::io::Write as _;
use std::ops::Range;
use std::path::Path;

const MAGIC: &[u8; 8] = b"LUCENTPT";
const VERSION: u32 = 2;
/// Bytes before the ranges: magic, version, size, fingerprint, display,
/// AOVs, count (version 1 has no AOVs: 4 bytes fewer).
const HEADER: usize = 8 + 4 + 8 + 8 + 8 + 4 + 4;
const HEADER_V1: usize = HEADER - 4;

/// Why a partial film cannot be read, written or merged.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PartialError {
    /// Reading or writing a file failed.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// Not a partial film, or damaged.
    #[error("{name}: {message}")]
    Damaged {
        /// The file (or "partial render" for bytes from elsewhere).
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The parts come from different renders.
    #[error("{0}")]
    DifferentRenders(String),
    /// The parts hold some of the same samples.
    #[error("{0}")]
    Overlap(String),
    /// A part would hold no samples.
    #[error("a partial render must hold at least one sample (got the empty range {0}..{1})")]
    Empty(u32, u32),
    /// The sums grew past what an i64 holds.
    #[error("the merged sums overflow: more samples than a film can hold")]
    Overflow,
}

/// The fixed-point sums of one or more ranges of sample indices of a
/// render, with the fingerprint of that render.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartialFilm {
    width: u32,
    height: u32,
    fingerprint: u64,
    tone_map: ToneMap,
    srgb: bool,
    aovs: AovSet,
    ranges: Vec<Range<u32>>,
    /// Per pixel: the colour's four sums and one per AOV channel.
    sums: Vec<i64>,
}

impl PartialFilm {
    /// The samples `samples` held by `acc` (whose other samples, if any,
    /// must be ones it never added, as the render loop's `render_partial`
    /// leaves them), of the render
    /// with `fingerprint`, to be shown with `tone_map` and `srgb`.
    ///
    /// ```
    /// use lucent::film::{Accumulator, PartialFilm, ToneMap};
    /// use lucent::color::Color;
    /// let (a, b) = (Accumulator::new(1, 1).unwrap(), Accumulator::new(1, 1).unwrap());
    /// a.splat(0, 0, Color::splat(1.0), 1.0);
    /// b.splat(0, 0, Color::splat(3.0), 1.0);
    /// let a = PartialFilm::new(&a, 0..1, 7, ToneMap::Classic, true).unwrap();
    /// let b = PartialFilm::new(&b, 1..2, 7, ToneMap::Classic, true).unwrap();
    /// let both = b.merge(&a).unwrap();
    /// assert_eq!(both.ranges(), std::slice::from_ref(&(0..2)));
    /// assert_eq!(both.to_film().pixel(0, 0), Color::splat(2.0));
    /// ```
    pub fn new(
        acc: &Accumulator,
        samples: Range<u32>,
        fingerprint: u64,
        tone_map: ToneMap,
        srgb: bool,
    ) -> Result<Self, PartialError> {
        if samples.start >= samples.end {
            return Err(PartialError::Empty(samples.start, samples.end));
        }
        Ok(Self {
            width: acc.width(),
            height: acc.height(),
            fingerprint,
            tone_map,
            srgb,
            aovs: acc.aovs(),
            ranges: vec![samples],
            sums: acc.raw(),
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The fingerprint of the render the samples belong to.
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }

    /// Tone mapping for 8-bit output (that of the first part merged).
    pub fn tone_map(&self) -> ToneMap {
        self.tone_map
    }

    /// Whether 8-bit output is sRGB-encoded.
    pub fn srgb(&self) -> bool {
        self.srgb
    }

    /// The auxiliary images held besides colour.
    pub fn aovs(&self) -> AovSet {
        self.aovs
    }

    /// The sample indices held, as sorted, disjoint, non-adjacent ranges.
    pub fn ranges(&self) -> &[Range<u32>] {
        &self.ranges
    }

    /// Samples per pixel held.
    pub fn spp(&self) -> u32 {
        self.ranges.iter().map(|r| r.end - r.start).sum()
    }

    /// The sample indices below the highest one held that are missing:
    /// empty when the part holds exactly samples `0..spp()`, as one render
    /// of `spp()` samples does.
    pub fn missing(&self) -> Vec<Range<u32>> {
        let mut gaps = Vec::new();
        let mut next = 0;
        for r in &self.ranges {
            if r.start > next {
                gaps.push(next..r.start);
            }
            next = r.end;
        }
        gaps
    }

    /// The sums as an accumulator holding [`spp`](Self::spp) samples.
    pub fn to_accumulator(&self) -> Accumulator {
        Accumulator::from_raw(self.width, self.height, self.spp(), self.aovs, &self.sums)
            .expect("size checked on creation")
    }

    /// The image of the samples held: each pixel's weighted mean.
    pub fn to_film(&self) -> Film {
        self.to_accumulator().to_film()
    }

    /// The auxiliary images of the samples held.
    pub fn to_aov_images(&self) -> AovImages {
        self.to_accumulator().to_aov_images()
    }

    /// The sum of two parts of the same render: refused if they come from
    /// different renders (fingerprint or size) or share samples.
    pub fn merge(&self, other: &PartialFilm) -> Result<PartialFilm, PartialError> {
        if (self.width, self.height) != (other.width, other.height) {
            return Err(PartialError::DifferentRenders(format!(
                "the parts come from different renders: their image sizes differ ({}×{} and {}×{})",
                self.width, self.height, other.width, other.height
            )));
        }
        if self.fingerprint != other.fingerprint {
            return Err(PartialError::DifferentRenders(format!(
                "the parts come from different renders (fingerprints {:016x} and {:016x}: the scene, its files, the seed, sampler, integrator, depth or filter differ)",
                self.fingerprint, other.fingerprint
            )));
        }
        if self.aovs != other.aovs {
            return Err(PartialError::DifferentRenders(format!(
                "the parts come from different renders: one holds the auxiliary images {}, the other {} (render every part with the same --aov)",
                self.aovs, other.aovs
            )));
        }
        let mut ranges: Vec<Range<u32>> = self.ranges.iter().chain(&other.ranges).cloned().collect();
        ranges.sort_by_key(|r| r.start);
        for pair in ranges.windows(2) {
            if pair[1].start < pair[0].end {
                return Err(PartialError::Overlap(format!(
                    "the parts overlap: samples {} are in both (each sample index may be merged once)",
                    show_range(&(pair[1].start..pair[0].end.min(pair[1].end)))
                )));
            }
        }
        let sums = self
            .sums
            .iter()
            .zip(&other.sums)
            .map(|(a, b)| a.checked_add(*b).ok_or(PartialError::Overflow))
            .collect::<Result<Vec<i64>, _>>()?;
        Ok(PartialFilm { ranges: coalesce(ranges), sums, ..self.clone_header() })
    }

    /// Merge any number of parts, in any order.
    pub fn merge_all<'a>(parts: impl IntoIterator<Item = &'a PartialFilm>) -> Result<PartialFilm, PartialError> {
        let mut parts = parts.into_iter();
        let first = parts.next().ok_or(PartialError::Empty(0, 0))?.clone();
        parts.try_fold(first, |acc, p| acc.merge(p))
    }

    /// The file's bytes (laid out as the documentation of `film::partial` describes).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER + 8 * self.ranges.len() + 8 * self.sums.len() + 8);
        out.extend_from_slice(MAGIC);
        for v in [VERSION, self.width, self.height] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&self.fingerprint.to_le_bytes());
        for v in [tone_map_code(self.tone_map), self.srgb as u32, self.aovs.bits(), self.ranges.len() as u32] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        for r in &self.ranges {
            out.extend_from_slice(&r.start.to_le_bytes());
            out.extend_from_slice(&r.end.to_le_bytes());
        }
        for v in &self.sums {
            out.extend_from_slice(&v.to_le_bytes());
        }
        let checksum = fnv1a(&out);
        out.extend_from_slice(&checksum.to_le_bytes());
        out
    }

    /// Read a part from its bytes; `name` (a file name) is used in errors.
    pub fn from_bytes(bytes: &[u8], name: &str) -> Result<PartialFilm, PartialError> {
        let damaged = |m: String| PartialError::Damaged { name: name.to_owned(), message: m };
        if bytes.len() < HEADER_V1 + 8 {
            return Err(damaged("too short to be a lucent partial render (.lpart)".into()));
        }
        if &bytes[..8] != MAGIC {
            return Err(damaged("not a lucent partial render (.lpart): wrong magic bytes".into()));
        }
        let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap());
        let version = u32_at(8);
        let header = match version {
            1 => HEADER_V1,
            2 if bytes.len() >= HEADER + 8 => HEADER,
            2 => return Err(damaged("too short to be a lucent partial render (.lpart)".into())),
            _ => {
                return Err(damaged(format!(
                    "format version {version} is not supported (this lucent reads versions 1 and {VERSION})"
                )))
            }
        };
        let (split, stored) = bytes.split_at(bytes.len() - 8);
        if fnv1a(split) != u64::from_le_bytes(stored.try_into().unwrap()) {
            return Err(damaged("the checksum does not match: the file is damaged or truncated".into()));
        }
        let (width, height) = (u32_at(12), u32_at(16));
        check_image_size(width, height).map_err(|e| damaged(e.to_string()))?;
        let fingerprint = u64::from_le_bytes(bytes[20..28].try_into().unwrap());
        let tone_map = tone_map_from_code(u32_at(28)).ok_or_else(|| damaged("unknown tone mapping code".into()))?;
        let srgb = match u32_at(32) {
            0 => false,
            1 => true,
            v => return Err(damaged(format!("sRGB flag {v} is neither 0 nor 1"))),
        };
        let aovs = if version == 1 { 0 } else { u32_at(36) };
        let aovs =
            AovSet::from_bits(aovs).ok_or_else(|| damaged(format!("unknown auxiliary images (bits {aovs:#x})")))?;
        let n = u32_at(header - 4) as usize;
        let sums_len = width as usize * height as usize * (4 + aovs.stored_channels());
        let expected = (header as u64) + 8 * n as u64 + 8 * sums_len as u64 + 8;
        if bytes.len() as u64 != expected {
            return Err(damaged(format!("{} bytes, expected {expected} for its header", bytes.len())));
        }
        if n == 0 {
            return Err(damaged("it holds no sample range".into()));
        }
        let ranges: Vec<Range<u32>> = (0..n).map(|i| u32_at(header + 8 * i)..u32_at(header + 8 * i + 4)).collect();
        let mut previous_end = None;
        for r in &ranges {
            if r.start >= r.end || previous_end.is_some_and(|e| r.start <= e) {
                return Err(damaged(format!("invalid sample ranges {}", show_ranges(&ranges))));
            }
            previous_end = Some(r.end);
        }
        let start = header + 8 * n;
        let sums = bytes[start..start + 8 * sums_len]
            .chunks_exact(8)
            .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        Ok(PartialFilm { width, height, fingerprint, tone_map, srgb, aovs, ranges, sums })
    }

    /// Write the part to `path` atomically (a temporary file renamed into
    /// place).
    pub fn save(&self, path: &Path) -> Result<(), PartialError> {
        let io = |e: std::io::Error| PartialError::Io { path: path.display().to_string(), message: e.to_string() };
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let mut tmp = tempfile::Builder::new().prefix(".lucent-").suffix(".tmp").tempfile_in(dir).map_err(io)?;
        tmp.as_file_mut().write_all(&self.to_bytes()).map_err(io)?;
        tmp.as_file().sync_all().map_err(io)?;
        tmp.persist(path).map_err(|e| io(e.error))?;
        Ok(())
    }

    /// Read a part written by [`save`](Self::save).
    pub fn load(path: &Path) -> Result<PartialFilm, PartialError> {
        let name = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| PartialError::Io {
            path: name.clone(),
            message: format!("cannot read it: {}", e.kind().to_string().to_lowercase()),
        })?;
        Self::from_bytes(&bytes, &name)
    }

    fn clone_header(&self) -> PartialFilm {
        PartialFilm { ranges: Vec::new(), sums: Vec::new(), ..*self }
    }
}

/// Join ranges that touch (sorted, non-overlapping input).
fn coalesce(ranges: Vec<Range<u32>>) -> Vec<Range<u32>> {
    let mut out: Vec<Range<u32>> = Vec::with_capacity(ranges.len());
    for r in ranges {
        match out.last_mut() {
            Some(last) if last.end == r.start => last.end = r.end,
            _ => out.push(r),
        }
    }
    out
}

/// `3..5` as "3 to 4", a single index as "3".
fn show_range(r: &Range<u32>) -> String {
    if r.end == r.start + 1 {
        r.start.to_string()
    } else {
        format!("{} to {}", r.start, r.end - 1)
    }
}

/// Ranges as `START..END` separated by commas.
pub fn show_ranges(ranges: &[Range<u32>]) -> String {
    let mut s = String::new();
    for (i, r) in ranges.iter().enumerate() {
        let _ = write!(s, "{}{}..{}", if i > 0 { ", " } else { "" }, r.start, r.end);
    }
    s
}

fn tone_map_code(t: ToneMap) -> u32 {
    match t {
        ToneMap::Classic => 0,
        ToneMap::Clamp => 1,
        ToneMap::Reinhard => 2,
        ToneMap::Aces => 3,
    }
}

fn tone_map_from_code(c: u32) -> Option<ToneMap> {
    Some(match c {
        0 => ToneMap::Classic,
        1 => ToneMap::Clamp,
        2 => ToneMap::Reinhard,
        3 => ToneMap::Aces,
        _ => return None,
    })
}

/// 64-bit FNV-1a (Fowler, Noll and Vo), as the checksum of the file.
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;

    fn part(range: Range<u32>, fp: u64, value: f32) -> PartialFilm {
        let acc = Accumulator::new(2, 1).unwrap();
        acc.splat(0, 0, Color::new(value, 2.0 * value, 0.5), 1.0);
        acc.splat(1, 0, Color::splat(value), 0.25);
        PartialFilm::new(&acc, range, fp, ToneMap::Reinhard, false).unwrap()
    }

    #[test]
    fn merging_is_exact_in_any_order_and_grouping() {
        let (a, b, c) = (part(0..2, 9, 0.1), part(2..3, 9, 7.3), part(3..8, 9, 1e-4));
        let abc = a.merge(&b).unwrap().merge(&c).unwrap();
        let cab = c.merge(&a.merge(&b).unwrap()).unwrap();
        let bca = PartialFilm::merge_all([&b, &c, &a]).unwrap();
        assert_eq!(abc, cab);
        assert_eq!(abc, bca);
        assert_eq!(abc.ranges(), std::slice::from_ref(&(0..8)));
        assert_eq!(abc.spp(), 8);
        assert!(abc.missing().is_empty());
        assert_eq!(abc.tone_map(), ToneMap::Reinhard);
        // The sums are those of one accumulator given all six splats.
        let all = Accumulator::new(2, 1).unwrap();
        for v in [0.1, 7.3, 1e-4] {
            all.splat(0, 0, Color::new(v, 2.0 * v, 0.5), 1.0);
            all.splat(1, 0, Color::splat(v), 0.25);
        }
        assert_eq!(abc.to_accumulator().raw(), all.raw());
    }

    #[test]
    fn gaps_overlaps_and_other_renders() {
        let (a, c) = (part(0..2, 9, 1.0), part(5..6, 9, 1.0));
        let ac = a.merge(&c).unwrap();
        assert_eq!(ac.ranges(), &[0..2, 5..6]);
        assert_eq!(ac.missing(), vec![2..5]);
        assert_eq!(ac.spp(), 3);
        let e = ac.merge(&part(1..3, 9, 1.0)).unwrap_err();
        assert_eq!(e.to_string(), "the parts overlap: samples 1 are in both (each sample index may be merged once)");
        let e = ac.merge(&part(4..9, 9, 1.0)).unwrap_err();
        assert!(e.to_string().contains("samples 5 are in both"), "{e}");
        let e = a.merge(&part(2..4, 10, 1.0)).unwrap_err();
        assert!(e.to_string().contains("different renders"), "{e}");
        let wide = PartialFilm::new(&Accumulator::new(3, 1).unwrap(), 4..5, 9, ToneMap::Classic, true).unwrap();
        assert!(a.merge(&wide).unwrap_err().to_string().contains("2×1 and 3×1"));
        assert_eq!(
            PartialFilm::new(&Accumulator::new(1, 1).unwrap(), 3..3, 0, ToneMap::Classic, true),
            Err(PartialError::Empty(3, 3))
        );
    }

    #[test]
    fn bytes_round_trip_and_damage_is_caught() {
        let p = part(0..2, 9, 0.3).merge(&part(4..7, 9, 2.0)).unwrap();
        let bytes = p.to_bytes();
        assert_eq!(bytes.len(), HEADER + 16 + 64 + 8);
        assert_eq!(PartialFilm::from_bytes(&bytes, "p.lpart").unwrap(), p);
        for i in [0, 9, 13, 25, 40, HEADER + 20, bytes.len() - 1] {
            let mut bad = bytes.clone();
            bad[i] ^= 0x10;
            let e = PartialFilm::from_bytes(&bad, "p.lpart").unwrap_err();
            assert!(matches!(e, PartialError::Damaged { .. }), "byte {i}: {e}");
            assert!(e.to_string().starts_with("p.lpart: "), "{e}");
        }
        let e = PartialFilm::from_bytes(&bytes[..bytes.len() - 3], "p.lpart").unwrap_err();
        assert!(e.to_string().contains("checksum"), "{e}");
        let e = PartialFilm::from_bytes(b"LUCENTCK\x01\0\0\0", "x").unwrap_err();
        assert!(e.to_string().contains("too short"), "{e}");
    }

    /// Version 1 files (before AOVs) are still read; parts with AOVs
    /// round-trip and merge only with parts of the same AOVs.
    #[test]
    fn version_1_files_and_aov_sums() {
        let p = part(0..2, 9, 0.3);
        let v2 = p.to_bytes();
        let mut v1 = v2[..36].to_vec();
        v1[8..12].copy_from_slice(&1u32.to_le_bytes());
        v1.extend_from_slice(&v2[40..v2.len() - 8]);
        let checksum = fnv1a(&v1);
        v1.extend_from_slice(&checksum.to_le_bytes());
        assert_eq!(PartialFilm::from_bytes(&v1, "old.lpart").unwrap(), p);

        let aovs = AovSet::of(&[crate::film::Aov::Normal]);
        let with_aovs = |range: Range<u32>, n: f32| {
            let acc = Accumulator::with_aovs(2, 1, aovs).unwrap();
            acc.splat_with_aovs(1, 0, Color::splat(2.0), &[0.0, n, 1.0], 0.5);
            PartialFilm::new(&acc, range, 9, ToneMap::Reinhard, false).unwrap()
        };
        let (a, b) = (with_aovs(0..1, 0.25), with_aovs(1..2, -0.75));
        let ab = a.merge(&b).unwrap();
        assert_eq!(PartialFilm::from_bytes(&ab.to_bytes(), "n.lpart").unwrap(), ab);
        assert_eq!(ab.to_aov_images().layer(crate::film::Aov::Normal).unwrap()[3..], [0.0, -0.25, 1.0]);
        let e = a.merge(&part(1..2, 9, 1.0)).unwrap_err();
        assert!(e.to_string().contains("one holds the auxiliary images normal, the other none"), "{e}");
    }

    #[test]
    fn files_are_written_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.lpart");
        let p = part(3..4, 1, 0.5);
        p.save(&path).unwrap();
        assert_eq!(PartialFilm::load(&path).unwrap(), p);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "no temporary file is left");
        let e = PartialFilm::load(&dir.path().join("missing.lpart")).unwrap_err();
        assert!(e.to_string().contains("missing.lpart: cannot read it"), "{e}");
    }
}
