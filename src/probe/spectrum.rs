//! The dominant frequency of a sampled signal, from its FFT.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

/// The frequency (Hz) of the largest peak of the spectrum of `values`, sampled every `dt`
/// seconds. The mean is removed, a Hann window applied and the signal zero-padded to eight
/// times its length (a power of two) before the FFT; the peak is then located between bins
/// by a parabola through the logarithms of the three largest magnitudes (exact for the
/// Gaussian-like main lobe of the window to well under a bin). `None` for fewer than 8
/// samples or a constant signal.
pub fn dominant_frequency(values: &[f64], dt: f64) -> Option<f64> {
    let n = values.len();
    if n < 8 || dt.is_nan() || dt <= 0.0 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let size = (8 * n).next_power_of_two();
    let mut buf = vec![Complex::new(0.0, 0.0); size];
    for (k, v) in values.iter().enumerate() {
        let w = 0.5 - 0.5 * (std::f64::consts::TAU * k as f64 / (n - 1) as f64).cos();
        buf[k] = Complex::new((v - mean) * w, 0.0);
    }
    FftPlanner::new().plan_fft_forward(size).process(&mut buf);
    let mag: Vec<f64> = buf[..size / 2].iter().map(|c| c.norm()).collect();
    let (peak, &top) = mag
        .iter()
        .enumerate()
        .skip(1)
        .max_by(|a, b| a.1.total_cmp(b.1))?;
    if top <= 0.0 || peak + 1 >= mag.len() {
        return None;
    }
    let (a, b, c) = (mag[peak - 1].ln(), top.ln(), mag[peak + 1].ln());
    let denom = a - 2.0 * b + c;
    let shift = if denom.abs() > 0.0 {
        0.5 * (a - c) / denom
    } else {
        0.0
    };
    Some((peak as f64 + shift) / (size as f64 * dt))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_decaying_sine_between_bins() {
        // 12.3 periods of 1118 Hz in 2000 samples: the raw resolution is 91 Hz, 11 Hz
        // after padding; the interpolated peak is within 0.1%.
        let f = 1118.0;
        let dt = 5.5e-6;
        let v: Vec<f64> = (0..2000)
            .map(|k| {
                let t = k as f64 * dt;
                (std::f64::consts::TAU * f * t).cos() * (-30.0 * t).exp() + 0.3
            })
            .collect();
        let got = dominant_frequency(&v, dt).unwrap();
        assert!((got / f - 1.0).abs() < 1e-3, "{got}");
    }
}
