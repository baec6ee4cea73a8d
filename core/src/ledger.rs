//! Accounting of samples delivered and lost by the sampling hardware.
//!
//! # Design
//! The ADC is triggered by a timer at exactly `fs`; DMA hands over whole blocks. When a
//! block is not taken in time (DMA overrun) or the ADC overruns, the firmware restarts the
//! sampling, and the samples triggered in between are gone. A lost sample is lost time, and
//! lost time is a position error, so the count matters: the ledger derives it from a
//! free-running cycle counter (the Cortex-M DWT `CYCCNT`) read at the end of every good block
//! and at the restart. Because the trigger timer and the CPU share one clock, the sample
//! period is an exact number of cycles, and
//! `lost = round((t_restart - t_last_good_block) / cycles_per_sample)`, to within one sample
//! (interrupt latency), for gaps shorter than the counter's wrap (`2^32` cycles: 44.7 s at
//! 96 MHz; the watchdog resets the device long before).

use core::fmt;

/// Why a ledger cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LedgerError {
    /// `fs_hz` is zero or does not divide `cycles_hz`: the sample period would not be a whole
    /// number of cycles (nor of timer ticks).
    SampleRate {
        /// The rejected sampling rate [Hz].
        fs_hz: u32,
        /// The cycle counter's rate [Hz].
        cycles_hz: u32,
    },
}

impl fmt::Display for LedgerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Self::SampleRate { fs_hz, cycles_hz } = self;
        write!(
            f,
            "fs_hz = {fs_hz}: must divide the {cycles_hz} Hz clock into a whole number of cycles"
        )
    }
}

/// Totals kept by the ledger.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LedgerCounters {
    /// Blocks delivered.
    pub blocks: u32,
    /// Sample triples delivered.
    pub samples: u64,
    /// Sampling restarts after an overrun.
    pub restarts: u32,
    /// Sample triples lost.
    pub lost: u64,
}

/// Sample accounting for one sampling stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleLedger {
    cycles_per_sample: u32,
    last_good: Option<u32>,
    counters: LedgerCounters,
}

impl SampleLedger {
    /// A ledger for samples at `fs_hz` timed by a cycle counter at `cycles_hz`.
    ///
    /// # Errors
    /// [`LedgerError::SampleRate`] unless `fs_hz` divides `cycles_hz`.
    pub const fn new(cycles_hz: u32, fs_hz: u32) -> Result<Self, LedgerError> {
        if fs_hz == 0 || !cycles_hz.is_multiple_of(fs_hz) {
            return Err(LedgerError::SampleRate { fs_hz, cycles_hz });
        }
        Ok(Self {
            cycles_per_sample: cycles_hz / fs_hz,
            last_good: None,
            counters: LedgerCounters {
                blocks: 0,
                samples: 0,
                restarts: 0,
                lost: 0,
            },
        })
    }

    /// Cycles between two samples.
    pub const fn cycles_per_sample(&self) -> u32 {
        self.cycles_per_sample
    }

    /// A good block of `samples` triples was taken at cycle count `now`.
    pub fn block(&mut self, now: u32, samples: u32) {
        self.last_good = Some(now);
        self.counters.blocks = self.counters.blocks.wrapping_add(1);
        self.counters.samples += u64::from(samples);
    }

    /// Sampling was restarted at cycle count `now` after an overrun; returns the sample
    /// triples lost since the last good block (0 if there was none yet: nothing was being
    /// integrated).
    pub fn restart(&mut self, now: u32) -> u32 {
        self.counters.restarts = self.counters.restarts.wrapping_add(1);
        let Some(last) = self.last_good else {
            return 0;
        };
        let elapsed = now.wrapping_sub(last);
        let lost = (elapsed + self.cycles_per_sample / 2) / self.cycles_per_sample;
        self.counters.lost += u64::from(lost);
        // The next good block continues from the restart.
        self.last_good = Some(now);
        lost
    }

    /// Whether no good block has arrived for more than `max_samples` sample periods before
    /// cycle count `now`: the sampling has stopped (ADC or DMA overrun, or a transfer error)
    /// and must be restarted. `false` before the first block.
    pub fn stalled(&self, now: u32, max_samples: u32) -> bool {
        self.last_good
            .is_some_and(|last| now.wrapping_sub(last) / self.cycles_per_sample > max_samples)
    }

    /// Running totals.
    pub const fn counters(&self) -> LedgerCounters {
        self.counters
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_must_divide_the_clock() {
        assert!(SampleLedger::new(96_000_000, 3000).is_ok());
        assert_eq!(
            SampleLedger::new(96_000_000, 7000),
            Err(LedgerError::SampleRate {
                fs_hz: 7000,
                cycles_hz: 96_000_000
            })
        );
        assert!(SampleLedger::new(96_000_000, 0).is_err());
    }

    #[test]
    fn lost_samples_are_the_gap_in_sample_periods_across_a_wrap() {
        let mut l = SampleLedger::new(96_000_000, 3000).expect("divides"); // 32000 cycles
        assert_eq!(l.restart(5), 0); // nothing integrated yet
        l.block(u32::MAX - 10_000, 3);
        // 7.4 periods later, across the counter's wrap.
        let now = (u32::MAX - 10_000).wrapping_add(7 * 32_000 + 13_000);
        assert_eq!(l.restart(now), 7);
        assert_eq!(l.counters().lost, 7);
        assert_eq!(l.counters().restarts, 2);
        assert_eq!(l.counters().samples, 3);
    }

    #[test]
    fn stall_is_more_than_the_allowed_sample_periods_without_a_block() {
        let mut l = SampleLedger::new(96_000_000, 3000).expect("divides");
        assert!(!l.stalled(1 << 31, 15)); // not started yet
        l.block(1000, 3);
        assert!(!l.stalled(1000 + 15 * 32_000, 15));
        assert!(!l.stalled(1000 + 16 * 32_000 - 1, 15));
        assert!(l.stalled(1000 + 16 * 32_000, 15));
    }
}
