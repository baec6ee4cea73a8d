//! Accounting of samples delivered and lost by the sampling hardware.
//!
//! # Design
//! The ADC is triggered by a timer at exactly `fs`; DMA hands over whole blocks. When a
//! block is not taken in time (DMA overrun) or the ADC overruns, the firmware restarts the
//! sampling, and the samples triggered in between are gone. A lost sample is lost time, and
//! lost time is a position error, so the count matters: the ledger derives it from a
//! free-running hardware counter (on the board TIM5, 32 bits at the 96 MHz timer clock:
//! `firmware/src/clock.rs`) read at the end of every good block and at the restart. Because
//! the trigger timer and the counter share one clock, the sample period is an exact number
//! of counts, and
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
    /// `block` is zero, or one block lasts half the counter's wrap or more.
    Block {
        /// The rejected block length [sample triples].
        block: u32,
    },
}

impl fmt::Display for LedgerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::SampleRate { fs_hz, cycles_hz } => write!(
                f,
                "fs_hz = {fs_hz}: must divide the {cycles_hz} Hz clock into a whole number of cycles"
            ),
            Self::Block { block } => write!(
                f,
                "block = {block}: must be at least 1 and last under 2^31 counter cycles"
            ),
        }
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
    /// Sampling restarts after an overrun or a stall.
    pub restarts: u32,
    /// Blocks that arrived one block period or more late (the DMA had already overwritten
    /// the older buffer), and unfilled buffers dropped.
    pub late_blocks: u32,
    /// Sample triples lost.
    pub lost: u64,
}

/// What a delivered block means for the integration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Delivery {
    /// The block follows the last one: integrate it.
    OnTime,
    /// This many sample triples (whole blocks) were overwritten before this block was
    /// taken; integrate it after accounting for them.
    Late(u32),
}

/// Sample accounting for one sampling stream.
///
/// The time stamps are in cycles of the counter given to [`SampleLedger::new`]; the stamp of
/// the last good block is the reference for both the late-block and the stall checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleLedger {
    cycles_per_sample: u32,
    block: u32,
    last_good: Option<u32>,
    integrating: bool,
    paused: bool,
    counters: LedgerCounters,
}

impl SampleLedger {
    /// A ledger for blocks of `block` (`>= 1`) samples at `fs_hz`, timed by a counter at
    /// `cycles_hz`.
    ///
    /// # Errors
    /// [`LedgerError::SampleRate`] unless `fs_hz` divides `cycles_hz`;
    /// [`LedgerError::Block`] if `block` is zero or a block lasts `2^31` cycles or more (the
    /// counter's half wrap: gaps are measured modulo `2^32`).
    pub const fn new(cycles_hz: u32, fs_hz: u32, block: u32) -> Result<Self, LedgerError> {
        if fs_hz == 0 || !cycles_hz.is_multiple_of(fs_hz) {
            return Err(LedgerError::SampleRate { fs_hz, cycles_hz });
        }
        let cycles_per_sample = cycles_hz / fs_hz;
        if block == 0 || (cycles_per_sample as u64) * (block as u64) >= 1 << 31 {
            return Err(LedgerError::Block { block });
        }
        Ok(Self {
            cycles_per_sample,
            block,
            last_good: None,
            integrating: false,
            paused: false,
            counters: LedgerCounters {
                blocks: 0,
                samples: 0,
                restarts: 0,
                late_blocks: 0,
                lost: 0,
            },
        })
    }

    /// Cycles between two samples.
    pub const fn cycles_per_sample(&self) -> u32 {
        self.cycles_per_sample
    }

    /// Sampling was (re)started at cycle count `now`: the stall check runs from here, so a
    /// sampling that never delivers a block is caught too.
    pub fn start(&mut self, now: u32) {
        self.last_good = Some(now);
        self.integrating = false;
        self.paused = false;
    }

    /// Sampling for tracking was stopped on purpose (USB suspend; the motion probe's slow
    /// blocks may go on): no stall, nothing lost, no block late, until the next
    /// [`Self::start`]. Blocks and restarts meanwhile are counted and leave it paused.
    pub fn pause(&mut self) {
        self.last_good = None;
        self.integrating = false;
        self.paused = true;
    }

    /// Whether the ledger is running (started and not paused).
    pub const fn running(&self) -> bool {
        self.last_good.is_some()
    }

    /// Whether the ledger is paused ([`Self::pause`] since the last [`Self::start`]).
    pub const fn paused(&self) -> bool {
        self.paused
    }

    /// A good block was taken at cycle count `now`. Blocks come one block period apart; a
    /// gap of `k` periods (rounded, so interrupt latency under half a block is tolerated)
    /// means `k - 1` blocks were overwritten by the double-buffered DMA before this one was
    /// taken: they are counted and returned as [`Delivery::Late`]. The first block after a
    /// start has no predecessor and is on time.
    pub fn block(&mut self, now: u32) -> Delivery {
        self.counters.blocks = self.counters.blocks.wrapping_add(1);
        self.counters.samples += u64::from(self.block);
        if self.paused {
            // A probe block: the stall and late checks are for tracking's rate, not the
            // probe's (a probe block at the running rate's limit would restart sampling).
            return Delivery::OnTime;
        }
        let previous = self.last_good.replace(now);
        let was_integrating = core::mem::replace(&mut self.integrating, true);
        let (Some(last), true) = (previous, was_integrating) else {
            return Delivery::OnTime;
        };
        let period = self.cycles_per_sample * self.block;
        let periods = (now.wrapping_sub(last) + period / 2) / period;
        if periods <= 1 {
            return Delivery::OnTime;
        }
        let lost = (periods - 1) * self.block;
        self.counters.late_blocks = self.counters.late_blocks.wrapping_add(periods - 1);
        self.counters.lost += u64::from(lost);
        Delivery::Late(lost)
    }

    /// A buffer came back unfilled (the DMA had not written it: a race of the buffer swap).
    /// It is dropped; its time is accounted for by the next good block.
    pub fn unfilled(&mut self) {
        self.counters.late_blocks = self.counters.late_blocks.wrapping_add(1);
    }

    /// Sampling was restarted at cycle count `now` after an overrun or a stall; returns the
    /// sample triples lost since the last good block (0 if nothing was being integrated yet).
    /// The stall check and the next block count from `now`.
    pub fn restart(&mut self, now: u32) -> u32 {
        self.counters.restarts = self.counters.restarts.wrapping_add(1);
        if self.paused {
            return 0;
        }
        let previous = self.last_good.replace(now);
        let was_integrating = core::mem::replace(&mut self.integrating, false);
        let (Some(last), true) = (previous, was_integrating) else {
            return 0;
        };
        let elapsed = now.wrapping_sub(last);
        let lost = (elapsed + self.cycles_per_sample / 2) / self.cycles_per_sample;
        self.counters.lost += u64::from(lost);
        lost
    }

    /// Whether no good block has arrived for more than `max_samples` sample periods before
    /// cycle count `now` (counting from the last block, or from the start if none came): the
    /// sampling has stopped, or never started, and must be restarted. `false` while paused.
    pub fn stalled(&self, now: u32, max_samples: u32) -> bool {
        self.last_good
            .is_some_and(|last| now.wrapping_sub(last) / self.cycles_per_sample > max_samples)
    }

    /// Whether a block has arrived since the last start or restart.
    pub const fn delivering(&self) -> bool {
        self.integrating
    }

    /// Running totals.
    pub const fn counters(&self) -> LedgerCounters {
        self.counters
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    const CPS: u32 = 32_000; // 96 MHz / 3 kHz

    fn ledger() -> SampleLedger {
        SampleLedger::new(96_000_000, 3000, 3).expect("divides")
    }

    #[test]
    fn rate_and_block_must_fit_the_clock() {
        assert!(SampleLedger::new(96_000_000, 3000, 3).is_ok());
        assert_eq!(
            SampleLedger::new(96_000_000, 7000, 7),
            Err(LedgerError::SampleRate {
                fs_hz: 7000,
                cycles_hz: 96_000_000
            })
        );
        assert!(SampleLedger::new(96_000_000, 0, 1).is_err());
        assert_eq!(
            SampleLedger::new(96_000_000, 3000, 0),
            Err(LedgerError::Block { block: 0 })
        );
        // 67109 samples of 32000 cycles pass 2^31.
        assert!(SampleLedger::new(96_000_000, 3000, 67_108).is_ok());
        assert!(SampleLedger::new(96_000_000, 3000, 67_109).is_err());
    }

    #[test]
    fn errors_name_the_parameter_and_the_ledger_its_period() {
        let e = LedgerError::SampleRate {
            fs_hz: 7000,
            cycles_hz: 96_000_000,
        };
        assert!(e.to_string().starts_with("fs_hz = 7000: "), "{e}");
        let e = LedgerError::Block { block: 0 };
        assert!(e.to_string().starts_with("block = 0: "), "{e}");
        assert_eq!(ledger().cycles_per_sample(), CPS);
    }

    #[test]
    fn running_from_start_to_pause() {
        let mut l = ledger();
        assert!(!l.running());
        l.start(0);
        assert!(l.running());
        l.pause();
        assert!(!l.running());
    }

    #[test]
    fn gaps_round_to_the_nearest_period() {
        // Blocks of 3 samples, 96 000 cycles apart: a gap of 1.4 periods is interrupt
        // latency (on time), 1.6 periods is one overwritten block (3 samples lost).
        let period = 3 * CPS;
        for (gap, lost) in [(14 * period / 10, 0), (16 * period / 10, 3)] {
            let mut l = ledger();
            l.start(0);
            l.block(period);
            let got = l.block(period + gap);
            let want = if lost == 0 {
                Delivery::OnTime
            } else {
                Delivery::Late(lost)
            };
            assert_eq!(got, want, "gap {gap}");
        }
        // A restart counts the samples since the last good block, to the nearest one.
        for (elapsed, lost) in [(24 * CPS / 10, 2), (26 * CPS / 10, 3)] {
            let mut l = ledger();
            l.start(0);
            l.block(period);
            l.block(2 * period);
            assert_eq!(l.restart(2 * period + elapsed), lost, "elapsed {elapsed}");
        }
    }

    #[test]
    fn lost_samples_are_the_gap_in_sample_periods_across_a_wrap() {
        let mut l = ledger();
        assert_eq!(l.restart(5), 0); // nothing integrated yet
        l.start(u32::MAX - 20_000);
        assert_eq!(l.block(u32::MAX - 10_000), Delivery::OnTime);
        // 7.4 periods later, across the counter's wrap.
        let now = (u32::MAX - 10_000).wrapping_add(7 * CPS + 13_000);
        assert_eq!(l.restart(now), 7);
        assert_eq!(l.counters().lost, 7);
        assert_eq!(l.counters().restarts, 2);
        assert_eq!(l.counters().samples, 3);
        // The restart is the new reference: a block one period later is on time.
        assert_eq!(l.block(now + 3 * CPS), Delivery::OnTime);
    }

    #[test]
    fn a_block_late_by_whole_periods_reports_the_overwritten_ones() {
        let mut l = ledger();
        l.start(0);
        assert_eq!(l.block(3 * CPS + 500), Delivery::OnTime); // the first block: no predecessor
        let mut t = 3 * CPS + 500;
        // Latency jitter under half a block is on time, both ways.
        for jitter in [47_999i64, -47_999, 0] {
            t = (i64::from(t) + 3 * i64::from(CPS) + jitter) as u32;
            assert_eq!(l.block(t), Delivery::OnTime, "jitter {jitter}");
        }
        // Two periods and a bit: one block (3 samples) was overwritten.
        t += 6 * CPS + 1000;
        assert_eq!(l.block(t), Delivery::Late(3));
        t += 12 * CPS;
        assert_eq!(l.block(t), Delivery::Late(9));
        assert_eq!(l.counters().late_blocks, 4);
        assert_eq!(l.counters().lost, 12);
    }

    #[test]
    fn stall_counts_from_the_start_so_a_sampling_that_never_runs_is_caught() {
        let mut l = ledger();
        assert!(!l.stalled(1 << 31, 15)); // never started
        l.start(1000);
        assert!(!l.stalled(1000 + 16 * CPS - 1, 15));
        assert!(l.stalled(1000 + 16 * CPS, 15));
        assert!(!l.delivering());
        l.block(2000);
        assert!(l.delivering());
        assert!(!l.stalled(2000 + 15 * CPS, 15));
        assert!(l.stalled(2000 + 16 * CPS, 15));
        l.pause();
        assert!(!l.running());
        assert!(!l.stalled(2000 + 99 * CPS, 15));
        assert_eq!(l.restart(2000 + 99 * CPS), 0, "a pause loses nothing");
    }

    #[test]
    fn an_unfilled_buffer_is_counted_and_its_time_found_by_the_next_block() {
        let mut l = ledger();
        l.start(0);
        l.block(3 * CPS);
        l.unfilled();
        assert_eq!(l.block(9 * CPS), Delivery::Late(3));
        assert_eq!(l.counters().late_blocks, 2);
    }

    #[test]
    fn probe_blocks_while_paused_neither_run_the_ledger_nor_stall_it() {
        // Suspended at 3 kHz: the probe's blocks come every 60 ms (50 Hz, 3 triples), far
        // past the running rate's 5 ms stall limit. They must not start the ledger (whose
        // stall check would then restart sampling every few ms), nor count as late.
        let mut l = SampleLedger::new(96_000_000, 3000, 3).expect("valid");
        l.start(0);
        l.block(96_000);
        l.pause();
        let limit = 5 * 3000 / 1000;
        for k in 1..=20u32 {
            let now = 96_000 + k * 5_760_000;
            assert_eq!(l.block(now), Delivery::OnTime);
            assert!(!l.running() && l.paused());
            assert!(!l.stalled(now + 600_000, limit), "probe block {k}");
        }
        assert_eq!(
            l.restart(200_000_000),
            0,
            "a restart while paused loses nothing"
        );
        assert!(l.paused() && !l.stalled(300_000_000, limit));
        let c = l.counters();
        assert_eq!((c.blocks, c.late_blocks, c.lost, c.restarts), (21, 0, 0, 1));
        // Resumed: the running rate's checks apply again from the start.
        l.start(400_000_000);
        assert!(l.running() && !l.paused());
        assert!(l.stalled(400_000_000 + 16 * 32_000, limit));
    }
}
