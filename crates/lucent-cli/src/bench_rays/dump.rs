//! The ray dump of the raybench protocol (SPEC.md section 7): every f32 as
//! its bit pattern in 8 lowercase hex digits, one ray per line, which
//! `gen_rays.py --check` regenerates and compares bit for bit.
//!
//! A dump of whole sets is about 2.5 million lines, so lines are formatted
//! by hand into a byte buffer rather than through `format!`.

use super::rays::{Frame, RayRecord};
use std::io::{self, Write};

/// Appends the 8 lowercase hex digits of `x`'s bit pattern.
fn push_hex(line: &mut Vec<u8>, x: f32) {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    let bits = x.to_bits();
    for shift in (0..8).rev() {
        line.push(DIGITS[((bits >> (shift * 4)) & 0xf) as usize]);
    }
}

/// Appends `n` in decimal.
fn push_decimal(line: &mut Vec<u8>, n: usize) {
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    let mut n = n;
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    line.extend_from_slice(&digits[i..]);
}

/// Appends ` HEX` for each of `values`.
fn push_fields(line: &mut Vec<u8>, values: &[f32]) {
    for &v in values {
        line.push(b' ');
        push_hex(line, v);
    }
}

/// The sets to dump: the first `n` rays of each.
pub struct DumpSets<'a> {
    /// The MESH argument as given.
    pub mesh: &'a str,
    /// Triangle count of the mesh.
    pub triangles: usize,
    /// The frame (for the bbox line).
    pub frame: &'a Frame,
    /// Primary rays.
    pub primary: &'a [RayRecord],
    /// Closest-hit distance of every primary ray (+inf for a miss).
    pub primary_t: &'a [f32],
    /// Shadow rays and the primary ray each starts from.
    pub shadow: &'a [RayRecord],
    /// The primary ray of each shadow ray.
    pub shadow_source: &'a [u32],
    /// Incoherent rays.
    pub incoherent: &'a [RayRecord],
}

/// Writes the dump of the first `n` rays of each set to `out`.
pub fn write_dump(out: &mut impl Write, sets: &DumpSets<'_>, n: usize) -> io::Result<()> {
    let f = sets.frame;
    writeln!(out, "raybench-dump 1")?;
    writeln!(out, "mesh {}", sets.mesh)?;
    writeln!(out, "triangles {}", sets.triangles)?;
    let mut line = Vec::with_capacity(160);
    line.extend_from_slice(b"bbox");
    push_fields(&mut line, &[f.bmin[0], f.bmin[1], f.bmin[2], f.bmax[0], f.bmax[1], f.bmax[2]]);
    out.write_all(&line)?;
    writeln!(
        out,
        "  # {:e} {:e} {:e}  {:e} {:e} {:e}",
        f.bmin[0], f.bmin[1], f.bmin[2], f.bmax[0], f.bmax[1], f.bmax[2]
    )?;

    for (k, ray) in sets.primary.iter().take(n).enumerate() {
        line.clear();
        line.extend_from_slice(b"primary ");
        push_decimal(&mut line, k);
        push_fields(&mut line, &ray.fields());
        line.push(b'\n');
        out.write_all(&line)?;
    }
    for (j, (ray, &k)) in sets.shadow.iter().zip(sets.shadow_source).take(n).enumerate() {
        line.clear();
        line.extend_from_slice(b"shadow ");
        push_decimal(&mut line, j);
        line.push(b' ');
        push_decimal(&mut line, k as usize);
        push_fields(&mut line, &[sets.primary_t[k as usize]]);
        push_fields(&mut line, &ray.fields());
        line.push(b'\n');
        out.write_all(&line)?;
    }
    for (i, ray) in sets.incoherent.iter().take(n).enumerate() {
        line.clear();
        line.extend_from_slice(b"incoherent ");
        push_decimal(&mut line, i);
        push_fields(&mut line, &ray.fields());
        line.push(b'\n');
        out.write_all(&line)?;
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;
    use lucent::geometry::Vec3;

    #[test]
    fn hex_and_decimal_formatting() {
        let mut v = Vec::new();
        push_hex(&mut v, 1.0);
        push_hex(&mut v, f32::INFINITY);
        push_hex(&mut v, -0.0);
        push_hex(&mut v, 0.0);
        assert_eq!(v, b"3f8000007f8000008000000000000000");
        let mut v = Vec::new();
        for n in [0, 7, 10, 1_048_575, usize::MAX] {
            push_decimal(&mut v, n);
            v.push(b',');
        }
        assert_eq!(String::from_utf8(v).unwrap(), format!("0,7,10,1048575,{},", usize::MAX));
    }

    #[test]
    fn dump_lines() {
        let frame = Frame::new(&[Vec3::splat(-1.0), Vec3::splat(1.0)]).unwrap();
        let ray = RayRecord { o: [0.0, 1.0, -2.0], d: [0.5, 0.0, -1.0], tnear: 0.0, tfar: f32::INFINITY };
        let sets = DumpSets {
            mesh: "sphere:2:3",
            triangles: 6,
            frame: &frame,
            primary: &[ray, ray],
            primary_t: &[f32::INFINITY, 2.0],
            shadow: &[ray],
            shadow_source: &[1],
            incoherent: &[ray, ray, ray],
        };
        let mut out = Vec::new();
        write_dump(&mut out, &sets, 2).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let fields = "00000000 3f800000 c0000000 3f000000 00000000 bf800000 00000000 7f800000";
        assert_eq!(lines[0], "raybench-dump 1");
        assert_eq!(lines[1], "mesh sphere:2:3");
        assert_eq!(lines[2], "triangles 6");
        assert!(lines[3].starts_with("bbox bf800000 bf800000 bf800000 3f800000 3f800000 3f800000  # "), "{}", lines[3]);
        assert_eq!(lines[4], format!("primary 0 {fields}"));
        assert_eq!(lines[5], format!("primary 1 {fields}"));
        assert_eq!(lines[6], format!("shadow 0 1 40000000 {fields}"));
        assert_eq!(lines[7], format!("incoherent 0 {fields}"));
        assert_eq!(lines[8], format!("incoherent 1 {fields}"));
        assert_eq!(lines.len(), 9);
    }
}
