//! `.spd` files: a spectrum as text, pairs of wavelength (nm) and value
//! separated by white space (or commas), `#` to the end of a line a
//! comment, as pbrt-v4 reads them (`ReadFloatFile`).

use super::kinds::PiecewiseLinear;
use super::{Spectrum, SpectrumError};
use std::path::{Path, PathBuf};

/// The piecewise-linear spectrum of the `.spd` text `text` (see the module
/// documentation). Errors name the line of the offending number.
///
/// ```
/// use lucent::spectrum::parse_spd;
///
/// let s = parse_spd("# wavelength value\n400 0.5\n700 1.5 # red\n")?;
/// assert_eq!(s.evaluate(550.0), 1.0);
/// let e = parse_spd("400 0.5\n700 x\n").unwrap_err();
/// assert_eq!(e.to_string(), "line 2: `x` is not a number");
/// # Ok::<(), lucent::spectrum::SpectrumError>(())
/// ```
pub fn parse_spd(text: &str) -> Result<Spectrum, SpectrumError> {
    parse(text, None)
}

/// The spectrum of the `.spd` file at `path` ([`parse_spd`]); errors name
/// the file.
pub fn read_spd(path: &Path) -> Result<Spectrum, SpectrumError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| SpectrumError::Io { path: path.to_owned(), message: e.to_string() })?;
    parse(&text, Some(path.to_owned()))
}

impl Spectrum {
    /// The spectrum of a pbrt-v4 `spectrum` string value: a named spectrum
    /// ([`Spectrum::named`]) if `name` is one, otherwise the `.spd` file
    /// `name`, relative to `base_dir` (the scene file's directory) unless
    /// absolute. When neither exists the error lists the known names.
    pub fn named_or_file(name: &str, base_dir: &Path) -> Result<Self, SpectrumError> {
        if Spectrum::is_named(name) {
            return Spectrum::named(name);
        }
        let path = base_dir.join(name);
        if !path.exists() {
            return Err(SpectrumError::NoSuchSpectrum { name: name.to_owned(), path });
        }
        read_spd(&path)
    }
}

fn parse(text: &str, path: Option<PathBuf>) -> Result<Spectrum, SpectrumError> {
    let err = |line: usize, message: String| SpectrumError::Spd { path: path.clone(), line, message };
    let mut lambdas: Vec<f64> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    // The line of the last wavelength read, for a missing value.
    let mut pending: Option<(f64, usize)> = None;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let data = line.split('#').next().unwrap_or("");
        for token in data.split(|c: char| c.is_whitespace() || c == ',').filter(|t| !t.is_empty()) {
            let v: f64 = token.parse().map_err(|_| err(n, format!("`{token}` is not a number")))?;
            if !v.is_finite() {
                return Err(err(n, format!("`{token}` is not a finite number")));
            }
            match pending.take() {
                None => {
                    if let Some(&prev) = lambdas.last() {
                        if v <= prev {
                            return Err(err(
                                n,
                                format!("wavelength {v} does not increase (the previous one is {prev})"),
                            ));
                        }
                    }
                    pending = Some((v, n));
                }
                Some((lambda, _)) => {
                    lambdas.push(lambda);
                    values.push(v);
                }
            }
        }
    }
    if let Some((lambda, line)) = pending {
        return Err(err(line, format!("wavelength {lambda} has no value (the file holds an odd count of numbers)")));
    }
    if lambdas.is_empty() {
        return Err(err(text.lines().count().max(1), "no wavelength–value pairs".to_owned()));
    }
    Ok(Spectrum::PiecewiseLinear(PiecewiseLinear::new(lambdas, values)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_comments_and_separators() {
        let s = parse_spd("# a comment\n\n 400\t0.25, 500 0.75 # trailing\n600\n1.0e0\n").unwrap();
        let Spectrum::PiecewiseLinear(p) = &s else { panic!() };
        assert_eq!(p.lambdas(), &[400.0, 500.0, 600.0]);
        assert_eq!(p.values(), &[0.25, 0.75, 1.0]);
        assert_eq!(s.evaluate(450.0), 0.5);
        assert_eq!(s.evaluate(700.0), 0.0);
    }

    #[test]
    fn errors_name_the_line() {
        let msg = |t: &str| parse_spd(t).unwrap_err().to_string();
        assert_eq!(msg("400 1\n500 2\n450 3\n"), "line 3: wavelength 450 does not increase (the previous one is 500)");
        assert_eq!(msg("400 1\n500\n"), "line 2: wavelength 500 has no value (the file holds an odd count of numbers)");
        assert_eq!(msg("400 1\n# x\n500 1..2\n"), "line 3: `1..2` is not a number");
        assert_eq!(msg("400 inf\n"), "line 1: `inf` is not a finite number");
        assert_eq!(msg("# nothing\n\n"), "line 2: no wavelength–value pairs");
        assert_eq!(msg(""), "line 1: no wavelength–value pairs");
    }

    #[test]
    fn files_are_read_and_named_in_errors() {
        let dir = tempfile::tempdir().unwrap();
        let good = dir.path().join("good.spd");
        std::fs::write(&good, "300 1\n800 2\n").unwrap();
        assert_eq!(read_spd(&good).unwrap().evaluate(550.0), 1.5);
        let bad = dir.path().join("bad.spd");
        std::fs::write(&bad, "300 1\n800 two\n").unwrap();
        assert_eq!(
            read_spd(&bad).unwrap_err().to_string(),
            format!("{}: line 2: `two` is not a number", bad.display())
        );
        // Names first, then files relative to the base directory.
        assert_eq!(Spectrum::named_or_file("stdillum-A", dir.path()), Spectrum::named("stdillum-A"));
        assert_eq!(Spectrum::named_or_file("good.spd", dir.path()).unwrap().evaluate(300.0), 1.0);
        let e = Spectrum::named_or_file("nope.spd", dir.path()).unwrap_err().to_string();
        assert!(e.contains("nope.spd") && e.contains("metal-Au-eta"), "{e}");
        let missing = dir.path().join("missing.spd");
        let e = read_spd(&missing).unwrap_err().to_string();
        assert!(e.starts_with(&format!("cannot read spectrum file {}", missing.display())), "{e}");
    }
}
