//! The sampling's decisions, apart from its registers: the running and the probe rate, when
//! sampling is restarted and what was lost, and the order of a change of rate.
//!
//! # Design
//! The board (`firmware/src/sampling.rs`) owns TIM2, ADC1 and the DMA and implements
//! [`Acquisition`]: read the free-running counter, load the trigger's period, stop and run
//! it, reset the ADC and re-arm the DMA. Every decision is here, over that trait, so it is
//! tested on the host:
//!
//! - **Suspend**: the ledger pauses (no stall, nothing lost, nothing late) and the trigger
//!   drops to the probe rate; the probe's slow blocks keep the ledger paused
//!   ([`imu_core::SampleLedger::pause`]). **Resume**: the acquisition rebuilt in a retime's
//!   order (the board may have parked it in Stop mode, `crate::sleep`), the ledger counting
//!   from now.
//! - **Stall**: no block for `stall_blocks` block periods at the running rate (or none since
//!   the start or the last restart): the ADC is reset and the DMA re-armed, and the samples
//!   since the last good block are counted lost. Never while suspended.
//! - **DMA events**: a full block is timed by the ledger (late blocks counted); an unfilled
//!   buffer (the swap raced the DMA) is dropped and counted; a busy stream is nothing; an
//!   overrun restarts sampling.
//! - **Retime**: the trigger stopped first (so no scan lands in a buffer of the old length),
//!   the DMA re-armed for blocks of the new length, a fresh ledger started, the new period
//!   loaded, the trigger run last.

use imu_core::{Delivery, LedgerError, SampleLedger};

use crate::device::block_len;

/// The sampling hardware as the decisions use it.
pub trait Acquisition {
    /// The free-running counter now [timer cycles, wrapping].
    fn now(&self) -> u32;
    /// Loads the trigger timer's auto-reload `arr` (a scan every `arr + 1` timer cycles) and
    /// restarts its count.
    fn set_period(&mut self, arr: u32);
    /// Stops the trigger timer.
    fn stop(&mut self);
    /// Runs the trigger timer.
    fn run(&mut self);
    /// Resets the ADC (clearing an overrun) and re-arms the DMA for blocks of `words` codes
    /// (three a scan). Sampling stays stopped if the transfer cannot be rebuilt; the stall
    /// check then keeps reporting it.
    fn rearm(&mut self, words: usize);
}

/// A DMA interrupt, as the board saw it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DmaEvent {
    /// A buffer came back filled.
    Full,
    /// A buffer came back still marked unfilled (`crate::sampling::filled` says no).
    Unfilled,
    /// Not a transfer-complete event (the stream was busy).
    NotReady,
    /// The DMA overran (or the buffer was too small).
    Overrun,
}

/// What a DMA event or a stall check decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Outcome {
    /// A full block, with the ledger's verdict: hand it to the tracker.
    Block(Delivery),
    /// Nothing to do.
    Idle,
    /// Sampling was restarted; this many sample triples were lost.
    Restarted(u32),
}

/// The sampling's state: the running rate's period and block, the probe's period, the stall
/// limit and the ledger.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampling {
    timer_hz: u32,
    arr: u32,
    block: usize,
    probe_arr: u32,
    stall_blocks: u32,
    ledger: SampleLedger,
}

impl Sampling {
    /// Sampling at `fs_hz` [Hz] from a trigger timer at `timer_hz` [Hz] (an accepted rate:
    /// `fs_hz` divides `timer_hz`), probing at a period of `probe_arr + 1` timer cycles while
    /// suspended, restarting after `stall_blocks` block periods without a block. Not yet
    /// started ([`Self::start`]).
    ///
    /// # Errors
    /// The ledger's [`LedgerError`] for a rate that does not divide the timer's clock.
    pub fn new(
        timer_hz: u32,
        fs_hz: u32,
        probe_arr: u32,
        stall_blocks: u32,
    ) -> Result<Self, LedgerError> {
        let block = block_len(fs_hz);
        // The ledger refuses a rate of 0 or one that does not divide the clock, so the
        // period below is a whole number of cycles, at least one.
        let ledger = SampleLedger::new(timer_hz, fs_hz, block as u32)?;
        Ok(Self {
            timer_hz,
            arr: timer_hz / fs_hz - 1,
            block,
            probe_arr,
            stall_blocks,
            ledger,
        })
    }

    /// Sample triples per block at the running rate.
    pub const fn block(&self) -> usize {
        self.block
    }

    /// The trigger's auto-reload at the running rate.
    pub const fn arr(&self) -> u32 {
        self.arr
    }

    /// The ledger's totals and state.
    pub const fn ledger(&self) -> &SampleLedger {
        &self.ledger
    }

    /// The hardware is armed (DMA, ADC) for blocks of [`Self::block`]: load the running
    /// period, start the ledger, run the trigger.
    pub fn start(&mut self, hw: &mut impl Acquisition) {
        hw.set_period(self.arr);
        self.ledger.start(hw.now());
        hw.run();
    }

    /// Runs the sampling at `fs_hz` [Hz] from now, in the order of the module docs; the
    /// samples of the old rate still in flight are dropped.
    ///
    /// # Errors
    /// The ledger's [`LedgerError`] for a rate that does not divide the timer's clock;
    /// nothing is changed then.
    pub fn retime(&mut self, hw: &mut impl Acquisition, fs_hz: u32) -> Result<(), LedgerError> {
        let next = Self::new(self.timer_hz, fs_hz, self.probe_arr, self.stall_blocks)?;
        hw.stop();
        *self = next;
        hw.rearm(3 * self.block);
        self.start(hw);
        Ok(())
    }

    /// A DMA interrupt: see the module docs.
    pub fn on_dma(&mut self, hw: &mut impl Acquisition, event: DmaEvent) -> Outcome {
        match event {
            DmaEvent::Full => Outcome::Block(self.ledger.block(hw.now())),
            DmaEvent::Unfilled => {
                self.ledger.unfilled();
                Outcome::Idle
            }
            DmaEvent::NotReady => Outcome::Idle,
            DmaEvent::Overrun => self.restart(hw),
        }
    }

    /// Restarts the sampling if no block has come for the stall limit at the running rate.
    pub fn check_stalled(&mut self, hw: &mut impl Acquisition) -> Outcome {
        let limit = self.stall_blocks.saturating_mul(self.block as u32);
        if self.ledger.stalled(hw.now(), limit) {
            self.restart(hw)
        } else {
            Outcome::Idle
        }
    }

    /// Whether blocks arrive (a block since the last start or restart), or the sampling is
    /// paused on purpose.
    pub const fn delivering(&self) -> bool {
        self.ledger.delivering() || !self.ledger.running()
    }

    /// USB suspend: the ledger paused, the trigger at the probe rate.
    pub fn suspend(&mut self, hw: &mut impl Acquisition) {
        self.ledger.pause();
        hw.set_period(self.probe_arr);
    }

    /// USB resume: the acquisition rebuilt as after a retime (trigger stopped, DMA re-armed
    /// for the running block, the running period, a fresh ledger, trigger run). Rebuilt, not
    /// only retimed: in Stop mode the board parks the DMA and takes its probe scans by
    /// software with the ADC switched off between them (`crate::sleep`).
    pub fn resume(&mut self, hw: &mut impl Acquisition) {
        hw.stop();
        hw.rearm(3 * self.block);
        self.start(hw);
    }

    fn restart(&mut self, hw: &mut impl Acquisition) -> Outcome {
        let now = hw.now();
        hw.rearm(3 * self.block);
        Outcome::Restarted(self.ledger.restart(now))
    }
}
