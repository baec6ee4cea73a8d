//! Alternative per-axis pipelines, measured against the default by `cargo lab speed`
//! (speed against error). Not used by the device.
//!
//! - [`F32Pipeline`]: the textbook float version: `y += k (x - y)`, `v += y - b`, `s += v`,
//!   all `f32`. Cheap on a Cortex-M4F, but `s` stops growing once a step is below half its
//!   ulp, and every addition rounds.
//! - [`NarrowPipeline`]: integer like the default but narrower: the bias in Q8 (so up to
//!   `2^-9` LSB of bias is left), velocity in `i32` and position in `i64`, no filter. Fewer
//!   instructions; the coarser bias grows as T^2, and `i32` velocity saturates after
//!   `2^31 / (4095 * 2^8)` = 2048 samples at full scale.

/// The float pipeline's state and coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct F32Pipeline {
    /// Low-pass coefficient `1 - exp(-alpha)`, or `None` for no filter.
    pub k: Option<f32>,
    /// Bias [LSB].
    pub bias: f32,
    /// Filter state [LSB].
    pub y: f32,
    /// Velocity [LSB * samples].
    pub v: f32,
    /// Position [LSB * samples^2].
    pub s: f32,
}

impl F32Pipeline {
    /// At rest, filter settled at the bias.
    pub const fn new(k: Option<f32>, bias: f32) -> Self {
        Self {
            k,
            bias,
            y: bias,
            v: 0.0,
            s: 0.0,
        }
    }

    /// One code.
    #[inline]
    pub fn update(&mut self, code: u16) {
        let x = f32::from(code);
        let y = match self.k {
            Some(k) => {
                self.y += k * (x - self.y);
                self.y
            }
            None => x,
        };
        self.v += y - self.bias;
        self.s += self.v;
    }
}

/// The narrow integer pipeline's state: Q8 bias, `i32` velocity, `i64` position (Euler,
/// no filter).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NarrowPipeline {
    /// Bias in Q8 counts.
    pub bias_q8: i32,
    /// Velocity, Q8 counts * samples.
    pub v: i32,
    /// Position, Q8 counts * samples^2.
    pub s: i64,
}

impl NarrowPipeline {
    /// At rest with bias `bias_q8` (Q8 counts).
    pub const fn new(bias_q8: i32) -> Self {
        Self {
            bias_q8,
            v: 0,
            s: 0,
        }
    }

    /// One code.
    #[inline]
    pub fn update(&mut self, code: u16) {
        let c = (i32::from(code) << 8) - self.bias_q8;
        self.v = self.v.saturating_add(c);
        self.s = self.s.saturating_add(i64::from(self.v));
    }
}
