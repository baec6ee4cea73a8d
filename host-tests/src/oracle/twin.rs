//! f64 twins of the core's stages: the same algorithms in double precision, the yardstick
//! the fixed-point path is held to (`tests/budget.rs`, `cargo lab budget`).
//!
//! Units follow the core: acceleration in ADC LSB, velocity in LSB * samples, position in
//! LSB * samples^2 (multiply by `LSB / fs` and `LSB / fs^2` for SI).

/// The integration rule, REFERENCE (c): (i) rectangle (Euler), (ii) trapezoid. The oracle's
/// own type: it shares nothing with the core it judges, so a caller states which rule it
/// compares with which of the core's schemes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// `v += a; s += v`.
    Euler,
    /// `v += (a[n-1] + a[n]) / 2; s += (v[n-1] + v[n]) / 2`, from the second sample.
    Trapezoid,
}

/// Single-pole low-pass `y += k (x - y)` in f64.
#[derive(Clone, Copy, Debug)]
pub struct Lowpass {
    /// Coefficient `k = 1 - exp(-alpha)`.
    pub k: f64,
    /// Output [LSB].
    pub y: f64,
}

impl Lowpass {
    /// The ideal filter for `fc / fs`, settled at `y0` [LSB].
    pub fn ideal(fc_over_fs: f64, y0: f64) -> Self {
        Self {
            k: -(-2.0 * std::f64::consts::PI * fc_over_fs).exp_m1(),
            y: y0,
        }
    }

    /// The filter with the core's realised Q0.32 coefficient, settled at `y0` [LSB].
    pub fn realised(k_q32: u32, y0: f64) -> Self {
        Self {
            k: f64::from(k_q32) / 4_294_967_296.0,
            y: y0,
        }
    }

    /// Filters one sample [LSB].
    pub fn process(&mut self, x: f64) -> f64 {
        self.y += self.k * (x - self.y);
        self.y
    }
}

/// Mean and unbiased standard deviation of codes [LSB].
pub fn calibrate(codes: &[u16]) -> (f64, f64) {
    let n = codes.len() as f64;
    let mean = codes.iter().map(|&c| f64::from(c)).sum::<f64>() / n;
    let var = codes
        .iter()
        .map(|&c| (f64::from(c) - mean).powi(2))
        .sum::<f64>()
        / (n - 1.0);
    (mean, var.sqrt())
}

/// Double integration in f64, REFERENCE (c)(i) and (ii).
#[derive(Clone, Copy, Debug)]
pub struct Integrator {
    /// Scheme.
    pub scheme: Scheme,
    /// Velocity [LSB * samples].
    pub v: f64,
    /// Position [LSB * samples^2].
    pub s: f64,
    prev: Option<f64>,
}

impl Integrator {
    /// At rest.
    pub fn new(scheme: Scheme) -> Self {
        Self {
            scheme,
            v: 0.0,
            s: 0.0,
            prev: None,
        }
    }

    /// Integrates one sample [LSB].
    pub fn step(&mut self, a: f64) {
        match self.scheme {
            Scheme::Euler => {
                self.v += a;
                self.s += self.v;
            }
            Scheme::Trapezoid => {
                if let Some(p) = self.prev {
                    let v = self.v + (p + a) / 2.0;
                    self.s += (self.v + v) / 2.0;
                    self.v = v;
                }
                self.prev = Some(a);
            }
        }
    }
}

/// One axis in f64: optional low-pass, bias, double integration.
#[derive(Clone, Copy, Debug)]
pub struct Axis {
    /// The filter, if any.
    pub lowpass: Option<Lowpass>,
    /// Bias [LSB].
    pub bias: f64,
    /// The integrator.
    pub integrator: Integrator,
}

impl Axis {
    /// Processes one code.
    pub fn update(&mut self, code: u16) {
        let x = f64::from(code);
        let y = self.lowpass.as_mut().map_or(x, |lp| lp.process(x));
        self.integrator.step(y - self.bias);
    }

    /// Position [LSB * samples^2].
    pub fn position(&self) -> f64 {
        self.integrator.s
    }
}
