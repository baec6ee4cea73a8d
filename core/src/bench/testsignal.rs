//! A deterministic synthetic ADC trace for benchmarks: the same codes on the target (the
//! QEMU speed harness) and on the host, so both compute the same outputs bit for bit.
//!
//! Not used by the device. The codes are 2048 plus a slowly wandering offset and a
//! triangular noise of +-63 codes, from SplitMix64: busy enough that no branch or shift is
//! constant, and always inside a 12-bit range.

/// An endless stream of codes from a 64-bit seed.
#[derive(Clone, Debug)]
pub struct Trace {
    state: u64,
    wander: i32,
}

impl Trace {
    /// A trace from `seed`.
    pub const fn new(seed: u64) -> Self {
        Self {
            state: seed,
            wander: 0,
        }
    }

    /// The next raw 64-bit value of the generator (SplitMix64).
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// The next code, in `1800..=2296`.
    pub fn next_code(&mut self) -> u16 {
        let r = self.next_u64();
        let step = ((r & 3) as i32) - 1; // -1, 0, 1, 2: a slow drift ...
        self.wander = (self.wander + step - i32::from(self.wander > 100)).clamp(-180, 180);
        let a = ((r >> 8) & 63) as i32; // ... plus triangular noise in -63..=63
        let b = ((r >> 16) & 63) as i32;
        (2048 + self.wander + a - b) as u16
    }
}

/// A checksum of a stream of 64-bit values: rotate-and-add, order-sensitive.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Checksum(pub u64);

impl Checksum {
    /// Mixes in `v`.
    #[inline(always)]
    pub fn add(&mut self, v: u64) {
        self.0 = self.0.rotate_left(5).wrapping_add(v) ^ 0x9E37_79B9_7F4A_7C15;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_stay_in_range_and_are_reproducible() {
        let mut a = Trace::new(42);
        let mut b = Trace::new(42);
        for _ in 0..100_000 {
            let c = a.next_code();
            assert!((1800..=2296).contains(&c));
            assert_eq!(c, b.next_code());
        }
    }
}
