//! `lucent diff`: error figures of an image against a reference image.

use clap::Args;
use lucent::film::{Film, PendingImage, ToneMap};
use lucent::tools::{block_means, compare, read_image, relative_squared_error, CompareError};
use std::path::PathBuf;

/// Compare an image with a reference: MSE, relative MSE (relative to the
/// reference), the largest absolute error and where it is, and the count of
/// non-finite pixels.
///
/// Images are OpenEXR or Radiance .hdr (linear) or PNG/BMP (sRGB, decoded to
/// linear); both must have the same size. Pixels that are NaN or infinite in
/// either image are left out of the figures and counted.
#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The image to assess.
    #[arg(value_name = "A")]
    pub a: PathBuf,
    /// The reference image.
    #[arg(value_name = "REFERENCE")]
    pub b: PathBuf,
    /// Print the figures as one JSON object: mse, rel_mse, max_abs_error,
    /// max_at ([x, y] or null), max_channel, nonfinite (pixels of A),
    /// nonfinite_reference, mean and mean_reference ([r, g, b] over the
    /// pixels compared), width, height; with --block also block and
    /// block_rel_mse.
    #[arg(long)]
    pub json: bool,
    /// Also write a false-colour map of each pixel's relative squared error
    /// (.png or .bmp): black below 1e-4, then blue, cyan, yellow, red, and
    /// white at 1 and above, on a logarithmic scale; magenta where a pixel
    /// is not finite.
    #[arg(long, value_name = "OUT")]
    pub heatmap: Option<PathBuf>,
    /// Also give the relative MSE of the means of N×N blocks of pixels
    /// (`block_rel_mse` in JSON): two noisy renders of the same image agree
    /// there to within their noise divided by N, while a real difference in
    /// brightness stays.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub block: Option<u32>,
    /// Also write the two images side by side, A on the left (.png or
    /// .bmp, tone mapped and sRGB-encoded alike).
    #[arg(long, value_name = "OUT")]
    pub side_by_side: Option<PathBuf>,
}

const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// Run `lucent diff`.
pub fn run(args: &DiffArgs) -> Result<(), String> {
    // Reserve the heat map first, so that a bad output path fails before
    // any work, and an existing file is replaced only by a complete one.
    let heatmap = args.heatmap.as_ref().map(PendingImage::create).transpose().map_err(|e| e.to_string())?;
    let side_by_side = args.side_by_side.as_ref().map(PendingImage::create).transpose().map_err(|e| e.to_string())?;
    let a = read_image(&args.a).map_err(|e| e.to_string())?;
    let b = read_image(&args.b).map_err(|e| e.to_string())?;
    let m = compare(&a, &b).map_err(|e| match e {
        CompareError::SizeMismatch(wa, ha, wb, hb) => format!(
            "cannot compare '{}' ({wa}×{ha}) with '{}' ({wb}×{hb}): the sizes differ",
            args.a.display(),
            args.b.display()
        ),
    })?;
    if let Some(pending) = heatmap {
        pending.write(&heat_map(&a, &b), ToneMap::Clamp, false).map_err(|e| e.to_string())?;
    }
    if let Some(pending) = side_by_side {
        pending.write(&beside(&a, &b)?, ToneMap::default(), true).map_err(|e| e.to_string())?;
    }
    let block_rel_mse = args
        .block
        .map(|n| compare(&block_means(&a, n), &block_means(&b, n)).expect("blocks of images of one size").rel_mse);

    if args.json {
        let mut json = serde_json::json!({
            "mse": m.mse,
            "rel_mse": m.rel_mse,
            "max_abs_error": m.max_abs_error,
            "max_at": m.max_at.map(|(x, y, _)| [x, y]),
            "max_channel": m.max_at.map(|(_, _, c)| CHANNELS[c]),
            "nonfinite": m.nonfinite,
            "nonfinite_reference": m.nonfinite_reference,
            "mean": m.mean,
            "mean_reference": m.mean_reference,
            "width": a.width(),
            "height": a.height(),
        });
        // Only with --block (the JSON without it is what `lucent.diff`
        // returns in Python).
        if let (Some(n), Some(e)) = (args.block, block_rel_mse) {
            json["block"] = n.into();
            json["block_rel_mse"] = e.into();
        }
        say!("{json}")?;
        return Ok(());
    }
    match m.max_at {
        Some((x, y, c)) => say!(
            "MSE {:.4e}  relMSE {:.4e}  max |a−b| {:.4e} at ({x}, {y}) channel {}",
            m.mse,
            m.rel_mse,
            m.max_abs_error,
            CHANNELS[c]
        )?,
        None => say!("no pixel is finite in both images: nothing to compare")?,
    }
    if m.compared > 0 {
        let ratio = |c: usize| if m.mean_reference[c] > 0.0 { m.mean[c] / m.mean_reference[c] } else { f64::NAN };
        say!(
            "mean r g b {:.5} {:.5} {:.5}  reference {:.5} {:.5} {:.5}  ratio {:.4} {:.4} {:.4}",
            m.mean[0],
            m.mean[1],
            m.mean[2],
            m.mean_reference[0],
            m.mean_reference[1],
            m.mean_reference[2],
            ratio(0),
            ratio(1),
            ratio(2)
        )?;
    }
    if let (Some(n), Some(e)) = (args.block, block_rel_mse) {
        say!("relMSE of {n}×{n} block means {e:.4e}")?;
    }
    if m.nonfinite > 0 || m.nonfinite_reference > 0 {
        say!(
            "non-finite pixels (left out): {} in '{}', {} in '{}'",
            m.nonfinite,
            args.a.display(),
            m.nonfinite_reference,
            args.b.display()
        )?;
    }
    Ok(())
}

/// `a` and `b` (of one size) side by side, `a` on the left.
fn beside(a: &Film, b: &Film) -> Result<Film, String> {
    let (w, h) = (a.width(), a.height());
    let mut out = Film::new(2 * w, h).map_err(|e| format!("cannot put the images side by side: {e}"))?;
    for (y, row) in out.pixels_mut().chunks_exact_mut(2 * w as usize).enumerate() {
        let at = y * w as usize..(y + 1) * w as usize;
        row[..w as usize].copy_from_slice(&a.pixels()[at.clone()]);
        row[w as usize..].copy_from_slice(&b.pixels()[at]);
    }
    Ok(out)
}

/// The false-colour image of the per-pixel relative squared error, in
/// display values (to be written without tone mapping or sRGB encoding).
fn heat_map(a: &Film, b: &Film) -> Film {
    let mut out = Film::new(a.width(), a.height()).expect("the size of an image that was read");
    for ((dst, &pa), &pb) in out.pixels_mut().iter_mut().zip(a.pixels()).zip(b.pixels()) {
        *dst = if pa.is_finite() && pb.is_finite() {
            ramp(relative_squared_error(pa, pb))
        } else {
            lucent::color::Color::new(1.0, 0.0, 1.0)
        };
    }
    out
}

/// The colour for a relative squared error `e`: `log10 e` from −4 to 0
/// mapped linearly through black, blue, cyan, yellow, red, white.
fn ramp(e: f64) -> lucent::color::Color {
    const STOPS: [[f32; 3]; 6] =
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]];
    let t = if e > 0.0 { ((e.log10() + 4.0) / 4.0).clamp(0.0, 1.0) as f32 } else { 0.0 };
    let x = t * (STOPS.len() - 1) as f32;
    let i = (x as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let (c0, c1) = (lucent::color::Color::from_array(STOPS[i]), lucent::color::Color::from_array(STOPS[i + 1]));
    c0 + (c1 - c0) * f
}
