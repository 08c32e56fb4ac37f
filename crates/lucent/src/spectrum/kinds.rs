//! The kinds of [`Spectrum`]: constant, blackbody and piecewise linear
//! (PBRT 4th ed., §4.5.1).

use super::SpectrumError;

/// A spectral distribution: a value at every wavelength λ (nanometres).
///
/// lucent renders in RGB, so spectra live only at load time: they are
/// converted once to linear sRGB (see the [module documentation](super)).
///
/// ```
/// use lucent::spectrum::Spectrum;
///
/// let s = Spectrum::from_interleaved(&[400.0, 0.2, 700.0, 0.8])?;
/// assert!((s.evaluate(550.0) - 0.5).abs() < 1e-6);
/// assert_eq!(s.evaluate(300.0), 0.0); // zero outside the samples
/// # Ok::<(), lucent::spectrum::SpectrumError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f64),
    /// Planck's law at a temperature, normalised to peak 1.
    Blackbody(Blackbody),
    /// Linear interpolation between samples, zero outside them.
    PiecewiseLinear(PiecewiseLinear),
}

impl Spectrum {
    /// The constant spectrum `c`.
    pub fn constant(c: f32) -> Self {
        Spectrum::Constant(c as f64)
    }

    /// The blackbody of `temperature` kelvin, normalised to peak 1
    /// ([`Blackbody::new`]).
    pub fn blackbody(temperature: f32) -> Result<Self, SpectrumError> {
        Ok(Spectrum::Blackbody(Blackbody::new(temperature as f64)?))
    }

    /// The piecewise-linear spectrum of pbrt's inline `spectrum` parameter,
    /// `[λ₀ v₀ λ₁ v₁ …]`: wavelengths strictly increasing, values finite.
    pub fn from_interleaved(pairs: &[f32]) -> Result<Self, SpectrumError> {
        if pairs.is_empty() {
            return Err(SpectrumError::Empty);
        }
        if !pairs.len().is_multiple_of(2) {
            return Err(SpectrumError::OddCount(pairs.len()));
        }
        let lambdas = pairs.iter().step_by(2).map(|&l| l as f64).collect();
        let values = pairs.iter().skip(1).step_by(2).map(|&v| v as f64).collect();
        Ok(Spectrum::PiecewiseLinear(PiecewiseLinear::new(lambdas, values)?))
    }

    /// The value at wavelength `lambda` (nm).
    pub fn evaluate(&self, lambda: f32) -> f32 {
        self.value(lambda as f64) as f32
    }

    /// The value at wavelength `lambda` (nm), in double precision.
    pub fn value(&self, lambda: f64) -> f64 {
        match self {
            Spectrum::Constant(c) => *c,
            Spectrum::Blackbody(b) => b.value(lambda),
            Spectrum::PiecewiseLinear(p) => p.value(lambda),
        }
    }

    /// This spectrum times `s` (a constant, blackbody or table scaled).
    pub fn scaled(self, s: f64) -> Self {
        match self {
            Spectrum::Constant(c) => Spectrum::Constant(c * s),
            Spectrum::Blackbody(b) => Spectrum::Blackbody(Blackbody { scale: b.scale * s, ..b }),
            Spectrum::PiecewiseLinear(p) => {
                let values = p.values.iter().map(|v| v * s).collect();
                Spectrum::PiecewiseLinear(PiecewiseLinear { lambdas: p.lambdas, values })
            }
        }
    }
}

/// Samples `(λᵢ, vᵢ)` with strictly increasing λ, interpolated linearly
/// between them and zero outside `[λ₀, λₙ₋₁]` (pbrt-v4's
/// `PiecewiseLinearSpectrum`).
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear {
    lambdas: Vec<f64>,
    values: Vec<f64>,
}

impl PiecewiseLinear {
    /// The spectrum of the samples `(lambdas[i], values[i])`: as many of
    /// each, at least one, all finite, wavelengths strictly increasing.
    pub fn new(lambdas: Vec<f64>, values: Vec<f64>) -> Result<Self, SpectrumError> {
        if lambdas.is_empty() {
            return Err(SpectrumError::Empty);
        }
        if lambdas.len() != values.len() {
            return Err(SpectrumError::OddCount(lambdas.len() + values.len()));
        }
        for (i, (&l, &v)) in lambdas.iter().zip(&values).enumerate() {
            if !(l.is_finite() && v.is_finite()) {
                return Err(SpectrumError::NonFinite { index: i, lambda: l, value: v });
            }
            if i > 0 && l <= lambdas[i - 1] {
                return Err(SpectrumError::NotIncreasing { index: i, previous: lambdas[i - 1], lambda: l });
            }
        }
        Ok(Self { lambdas, values })
    }

    /// The sample wavelengths, increasing.
    pub fn lambdas(&self) -> &[f64] {
        &self.lambdas
    }

    /// The sample values.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The value at `lambda`: the linear interpolant of the two samples
    /// around it, the sample itself on a sample, zero outside the range.
    pub fn value(&self, lambda: f64) -> f64 {
        let (first, last) = (self.lambdas[0], self.lambdas[self.lambdas.len() - 1]);
        if !(lambda >= first && lambda <= last) {
            return 0.0;
        }
        // The last sample at or below λ (clamped so that i + 1 exists).
        let i =
            self.lambdas.partition_point(|&l| l <= lambda).saturating_sub(1).min(self.lambdas.len().saturating_sub(2));
        if self.lambdas.len() == 1 {
            return self.values[0];
        }
        let (l0, l1) = (self.lambdas[i], self.lambdas[i + 1]);
        let t = (lambda - l0) / (l1 - l0);
        (1.0 - t) * self.values[i] + t * self.values[i + 1]
    }

    /// The samples of a measured table, extended as pbrt-v4's
    /// `PiecewiseLinearSpectrum::FromInterleaved` does: a sample of the
    /// first value at 359 nm when the table starts above 360 nm, and of the
    /// last value at 831 nm when it ends below 830 nm, so the spectrum is
    /// defined over the whole visible range.
    pub(super) fn from_table(table: &[(f64, f64)]) -> Self {
        let mut lambdas = Vec::with_capacity(table.len() + 2);
        let mut values = Vec::with_capacity(table.len() + 2);
        if table[0].0 > super::LAMBDA_MIN {
            lambdas.push(super::LAMBDA_MIN - 1.0);
            values.push(table[0].1);
        }
        for &(l, v) in table {
            lambdas.push(l);
            values.push(v);
        }
        if table[table.len() - 1].0 < super::LAMBDA_MAX {
            lambdas.push(super::LAMBDA_MAX + 1.0);
            values.push(table[table.len() - 1].1);
        }
        Self { lambdas, values }
    }
}

/// The speed of light (m/s), Planck's constant (J·s) and Boltzmann's
/// constant (J/K), the values pbrt-v4 uses (CODATA 2010).
const C: f64 = 299_792_458.0;
const H: f64 = 6.626_069_57e-34;
const KB: f64 = 1.380_648_8e-23;
/// Wien's displacement constant (m·K): the peak of a blackbody of
/// temperature T is at λ = b/T (CODATA 2018).
const WIEN_B: f64 = 2.897_772_1e-3;

/// The emission of a blackbody, normalised to peak 1 (pbrt-v4's
/// `BlackbodySpectrum`, PBRT 4th ed. §4.4.1 and §4.5.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blackbody {
    temperature: f64,
    /// `1 / B(λ_max, T)`, times any scale applied since.
    scale: f64,
}

impl Blackbody {
    /// The blackbody of `temperature` kelvin (positive and finite).
    pub fn new(temperature: f64) -> Result<Self, SpectrumError> {
        if !(temperature.is_finite() && temperature > 0.0) {
            return Err(SpectrumError::Temperature(temperature));
        }
        let peak = planck(WIEN_B / temperature * 1e9, temperature);
        Ok(Self { temperature, scale: 1.0 / peak })
    }

    /// The temperature in kelvin.
    pub fn temperature(&self) -> f64 {
        self.temperature
    }

    /// The normalised emission at `lambda` (nm): 1 at Wien's peak.
    pub fn value(&self, lambda: f64) -> f64 {
        planck(lambda, self.temperature) * self.scale
    }
}

/// Planck's law: the spectral radiance of a blackbody of temperature `t`
/// (K) at wavelength `lambda` (nm), `B(λ, T) = 2hc² / (λ⁵ (e^{hc/λk_BT} − 1))`
/// in W·sr⁻¹·m⁻³.
pub fn planck(lambda: f64, t: f64) -> f64 {
    if !(t > 0.0 && lambda > 0.0) {
        return 0.0;
    }
    let l = lambda * 1e-9;
    2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * t)).exp_m1()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_linear_interpolates_and_is_zero_outside() {
        let p = PiecewiseLinear::new(vec![400.0, 500.0, 600.0], vec![1.0, 3.0, 2.0]).unwrap();
        assert_eq!(p.value(400.0), 1.0);
        assert_eq!(p.value(450.0), 2.0);
        assert_eq!(p.value(500.0), 3.0);
        assert_eq!(p.value(575.0), 2.25);
        assert_eq!(p.value(600.0), 2.0);
        assert_eq!(p.value(399.9), 0.0);
        assert_eq!(p.value(600.1), 0.0);
        assert_eq!(p.value(f64::NAN), 0.0);
        let one = PiecewiseLinear::new(vec![550.0], vec![4.0]).unwrap();
        assert_eq!((one.value(550.0), one.value(551.0)), (4.0, 0.0));
    }

    #[test]
    fn invalid_samples_are_rejected() {
        assert_eq!(Spectrum::from_interleaved(&[]), Err(SpectrumError::Empty));
        assert_eq!(Spectrum::from_interleaved(&[400.0, 1.0, 500.0]), Err(SpectrumError::OddCount(3)));
        assert_eq!(
            Spectrum::from_interleaved(&[400.0, 1.0, 400.0, 2.0]),
            Err(SpectrumError::NotIncreasing { index: 1, previous: 400.0, lambda: 400.0 })
        );
        assert!(matches!(
            Spectrum::from_interleaved(&[400.0, f32::NAN]),
            Err(SpectrumError::NonFinite { index: 0, .. })
        ));
        assert_eq!(Spectrum::blackbody(0.0), Err(SpectrumError::Temperature(0.0)));
        assert!(Spectrum::blackbody(f32::NAN).is_err());
    }

    #[test]
    fn blackbody_peaks_at_one_at_wiens_wavelength() {
        for t in [2700.0, 5000.0, 6504.0] {
            let b = Blackbody::new(t).unwrap();
            let peak = WIEN_B / t * 1e9;
            assert!((b.value(peak) - 1.0).abs() < 1e-12);
            assert!(b.value(peak * 0.98) < 1.0 && b.value(peak * 1.02) < 1.0);
        }
        // Planck's law against a hand computation: 5000 K at 500 nm,
        // 2hc² = 1.19104e-16 W·m², so 2hc²/λ⁵ = 3.81134e15, and
        // hc/λk_BT = 5.75511, so B = 3.81134e15 / (e^5.75511 − 1)
        // = 1.21072e13 W·sr⁻¹·m⁻³.
        let b = planck(500.0, 5000.0);
        assert!((b / 1.21072e13 - 1.0).abs() < 1e-5, "{b}");
    }

    #[test]
    fn scaling_scales_every_kind() {
        for s in [
            Spectrum::constant(2.0),
            Spectrum::blackbody(3000.0).unwrap(),
            Spectrum::from_interleaved(&[400.0, 1.0, 700.0, 3.0]).unwrap(),
        ] {
            let v = s.value(555.0);
            assert!((s.scaled(0.5).value(555.0) - 0.5 * v).abs() < 1e-12 * v.abs().max(1.0));
        }
    }
}
