//! Milliseconds since boot from a free-running hardware counter, so that time a stalled CPU
//! spends (a flash erase stalls every fetch, and with it every interrupt) is not lost.
//!
//! # Design
//! A counter of interrupts (SysTick) cannot count while the CPU is stalled: an 800 ms erase
//! would come back as one tick, and the debounce, the LED patterns and the suspend timing
//! would run late by it. A hardware timer keeps counting. [`Uptime::update`] takes the
//! counter's reading (32 bits, wrapping) and adds the cycles since the last reading, carried
//! exactly (the remainder below a millisecond is kept), so the milliseconds never drift from
//! the counter. Readings must come less than one wrap apart (`2^32` cycles: 44.7 s at
//! 96 MHz); the 1 ms housekeeping tick and the watchdog (5 s) make sure they do.

/// Milliseconds since boot, extended from a wrapping cycle counter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Uptime {
    cycles_per_ms: u32,
    last: u32,
    rem: u32,
    ms: u32,
}

impl Uptime {
    /// Counting from the counter's reading `now` [cycles] at a rate of `cycles_per_ms`
    /// (`>= 1`; 96 000 for TIM5 at 96 MHz), from `start_ms` [ms].
    pub const fn new(cycles_per_ms: u32, now: u32, start_ms: u32) -> Self {
        Self {
            cycles_per_ms: if cycles_per_ms == 0 { 1 } else { cycles_per_ms },
            last: now,
            rem: 0,
            ms: start_ms,
        }
    }

    /// The milliseconds at the counter's reading `now` [cycles]: the cycles since the last
    /// reading (modulo `2^32`) added, whole milliseconds counted, the rest carried. Wraps
    /// after 49.7 days, as a `u32` of milliseconds does.
    pub fn update(&mut self, now: u32) -> u32 {
        let elapsed = u64::from(now.wrapping_sub(self.last)) + u64::from(self.rem);
        self.last = now;
        let per = u64::from(self.cycles_per_ms);
        // elapsed < 2^33 cycles: at 2 or more cycles a millisecond the whole milliseconds fit
        // a u32 (at 1 they could not, and saturate).
        let whole = u32::try_from(elapsed / per).unwrap_or(u32::MAX);
        self.rem = (elapsed % per) as u32;
        self.ms = self.ms.wrapping_add(whole);
        self.ms
    }

    /// Adds `ms` [ms] the counter did not see (it stops with the clocks in Stop mode,
    /// `crate::sleep`), from the counter's reading `now` [cycles] on: the cycles before `now`
    /// since the last reading are counted first, the remainder carried.
    pub fn credit(&mut self, now: u32, ms: u32) -> u32 {
        self.update(now);
        self.ms = self.ms.wrapping_add(ms);
        self.ms
    }

    /// The milliseconds at the last [`Self::update`].
    pub const fn ms(&self) -> u32 {
        self.ms
    }
}
