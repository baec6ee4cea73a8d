//! Hardware-timed sampling: TIM2's update event triggers an ADC1 scan of X, Y, Z; DMA2
//! stream 0 moves each scan into one of two buffers and interrupts when a buffer is full.
//! This file programs the registers; every decision (rates, suspend, stalls, restarts, the
//! order of a retime) is `imu_app::sampler`'s, tested on the host.
//!
//! # Design
//! - No software trigger and no per-sample interrupt: TIM2 (TRGO on update, PSC 0 and the
//!   ARR of `board`) starts each scan; the ADC's continuous bit stays off, or it would
//!   free-run. Suspend lowers TIM2 to the probe rate; in Stop mode ([`Sampler::park`],
//!   `crate::stop`) the transfer is parked and the probe scans are taken by software;
//!   resume rebuilds the transfer and runs TIM2 at the running rate.
//! - Double buffering with a third, spare buffer: on each transfer-complete interrupt the
//!   spare goes to the DMA and the full buffer comes back, so the core reads a buffer the
//!   DMA is not writing. Each buffer given to the DMA is marked unfilled
//!   (`imu_app::sampling`); one that comes back still marked is dropped.
//! - Lost samples are never silent. A block taken one block period or more late (the DMA
//!   overwrote the older buffer) is reported by the ledger as `Delivery::Late`; a DMA
//!   overrun, or blocks that stop arriving (ADC overrun, or a sampling that never started),
//!   restart the sampling: ADC reset through the RCC (which clears OVR), reconfigured, the
//!   DMA stream enabled and only then the ADC, and the samples lost counted from TIM5.
//! - The rate is set at run time ([`Sampler::retime`]): the three buffers are sized for the
//!   longest block (1 ms at 20 kHz) and each [`Block`] gives the DMA only the words of one
//!   block at the running rate; a retime stops TIM2, re-arms the DMA with the new length,
//!   loads the new ARR and starts a fresh ledger.

use embedded_dma::WriteBuffer;
pub use imu_app::sampler::Outcome;
use imu_app::sampler::{Acquisition, DmaEvent, Sampling};
use imu_app::sampling::{filled, mark_unfilled};
use imu_app::uptime::Uptime;
use imu_core::{Delivery, SampleLedger};
use stm32f4xx_hal::{
    adc::{
        config::{AdcConfig, Dma, ExternalTrigger, Scan, Sequence, TriggerMode},
        Adc,
    },
    dma::{config::DmaConfig, DMAError, PeripheralToMemory, Stream0, Transfer},
    gpio::{Analog, PA1, PA2, PA3},
    pac::{self, ADC1, DMA2, TIM2},
    rcc::{Enable, Rcc, Reset},
};

use crate::board::{
    ADC_PRESCALER, ADC_SAMPLE_TIME, ADC_STAB_CYCLES, BUF_MAX, PROBE_ARR, STALL_BLOCKS, TIMER_HZ,
};
use crate::clock::Clock;

/// The storage of one DMA buffer: the longest block's scans of X, Y, Z codes.
pub type Buffer = [u16; BUF_MAX];

/// One DMA buffer at the running rate: the first `len` words of its storage.
pub struct Block {
    words: &'static mut Buffer,
    len: usize,
}

impl Block {
    /// A block over `words`, `len` words long (clamped to the storage).
    pub fn new(words: &'static mut Buffer, len: usize) -> Self {
        Self {
            words,
            len: len.min(BUF_MAX),
        }
    }

    /// The block's words.
    pub fn codes(&self) -> &[u16] {
        &self.words[..self.len]
    }

    fn codes_mut(&mut self) -> &mut [u16] {
        &mut self.words[..self.len]
    }

    fn resize(&mut self, len: usize) {
        self.len = len.min(BUF_MAX);
    }
}

// SAFETY: `words` is an exclusive `'static` borrow, so the memory stays valid and unaliased
// for as long as the DMA owns the `Block`, and `write_buffer` returns the same pointer and
// length until a `&mut self` method runs (only `resize`, called on a released buffer).
// `len <= BUF_MAX` always (`new` and `resize` clamp), so the DMA writes inside `words`.
#[allow(unsafe_code)]
unsafe impl WriteBuffer for Block {
    type Word = u16;
    unsafe fn write_buffer(&mut self) -> (*mut u16, usize) {
        (self.words.as_mut_ptr(), self.len)
    }
}

type AdcTransfer = Transfer<Stream0<DMA2>, 0, Adc<ADC1>, PeripheralToMemory, Block>;

/// The accelerometer's analog inputs.
pub struct Pins {
    /// X, ADC1 IN1.
    pub x: PA1<Analog>,
    /// Y, ADC1 IN2.
    pub y: PA2<Analog>,
    /// Z, ADC1 IN3.
    pub z: PA3<Analog>,
}

/// The peripherals the sampling path owns.
pub struct Hardware {
    /// The ADC trigger timer.
    pub tim2: TIM2,
    /// The ADC.
    pub adc1: ADC1,
    /// DMA2 stream 0 (channel 0 is ADC1).
    pub stream: Stream0<DMA2>,
    /// The accelerometer's inputs.
    pub pins: Pins,
}

/// The DMA stream, the ADC and the two transfer buffers, released from the transfer while
/// the board is in Stop mode (`crate::stop`): the CPU takes the probe's scans.
struct Parked {
    stream: Stream0<DMA2>,
    adc: Adc<ADC1>,
    a: Block,
    b: Block,
}

/// The board's half of the sampling: TIM2, the DMA transfer (or its parts, parked) and its
/// spare buffer, the ADC's pins and reset, and TIM5 ([`Acquisition`] for
/// `imu_app::sampler`).
struct Board {
    trigger: TIM2,
    transfer: Option<AdcTransfer>,
    parked: Option<Parked>,
    spare: Option<Block>,
    pins: Pins,
    rcc: Rcc,
    clock: Clock,
}

/// The sampling pipeline: the board's registers and the app's decisions over them.
pub struct Sampler {
    board: Board,
    logic: Sampling,
    uptime: Uptime,
}

fn adc_config() -> AdcConfig {
    AdcConfig::default()
        .clock(ADC_PRESCALER)
        .scan(Scan::Enabled)
        .dma(Dma::Continuous)
        .external_trigger(TriggerMode::RisingEdge, ExternalTrigger::Tim_2_trgo)
}

fn configure_channels(adc: &mut Adc<ADC1>, pins: &Pins) {
    adc.configure_channel(&pins.x, Sequence::One, ADC_SAMPLE_TIME);
    adc.configure_channel(&pins.y, Sequence::Two, ADC_SAMPLE_TIME);
    adc.configure_channel(&pins.z, Sequence::Three, ADC_SAMPLE_TIME);
}

fn dma_config() -> DmaConfig {
    DmaConfig::default()
        .memory_increment(true)
        .double_buffer(true)
        .transfer_complete_interrupt(true)
}

/// The ADC, disabled, configured for the scan.
fn fresh_adc(adc: &mut Adc<ADC1>, pins: &Pins) {
    adc.disable();
    adc.apply_config(adc_config());
    configure_channels(adc, pins);
}

/// A transfer into `a` and `b` (marked unfilled), the stream enabled before the ADC so that
/// the first trigger finds the DMA ready.
fn armed(stream: Stream0<DMA2>, adc: Adc<ADC1>, mut a: Block, mut b: Block) -> AdcTransfer {
    mark_unfilled(a.codes_mut());
    mark_unfilled(b.codes_mut());
    let mut t = Transfer::init_peripheral_to_memory(stream, adc, a, Some(b), dma_config());
    t.start(|adc| adc.enable());
    t
}

/// The decisions at a rate the device accepts (`imu_app::device::rate_accepted`, checked
/// by the caller; every accepted rate builds: `app/tests/device.rs`).
fn logic(fs_hz: u32) -> Sampling {
    let Ok(logic) = Sampling::new(TIMER_HZ, fs_hz, PROBE_ARR, STALL_BLOCKS) else {
        defmt::panic!("sampling at {} Hz (see app/tests/device.rs)", fs_hz)
    };
    logic
}

impl Acquisition for Board {
    fn now(&self) -> u32 {
        self.clock.now()
    }

    fn set_period(&mut self, arr: u32) {
        self.trigger.arr().write(|w| w.arr().set(arr));
        self.trigger.egr().write(|w| w.ug().set_bit());
    }

    fn stop(&mut self) {
        self.trigger.cr1().modify(|_, w| w.cen().clear_bit());
    }

    fn run(&mut self) {
        self.trigger.cr1().modify(|_, w| w.cen().set_bit());
    }

    fn rearm(&mut self, words: usize) {
        if let Some(spare) = self.spare.as_mut() {
            spare.resize(words);
        }
        if let Some(mut p) = self.parts() {
            // A full ADC reset is the one way the HAL offers to clear OVR.
            <ADC1 as Reset>::reset(&mut self.rcc);
            fresh_adc(&mut p.adc, &self.pins);
            p.a.resize(words);
            p.b.resize(words);
            self.transfer = Some(armed(p.stream, p.adc, p.a, p.b));
        }
    }
}

impl Board {
    /// The transfer's parts: released from the running transfer, or the parked ones. A
    /// double-buffered transfer always returns its second buffer; without one the sampling
    /// stays stopped and the stall check keeps reporting no data.
    fn parts(&mut self) -> Option<Parked> {
        match self.transfer.take() {
            Some(transfer) => {
                let (stream, adc, a, b) = transfer.release();
                b.map(|b| Parked { stream, adc, a, b })
            }
            None => self.parked.take(),
        }
    }
}

impl Sampler {
    /// Sets up ADC1 and DMA2 stream 0, starts the transfer, then TIM2 at `fs_hz` (an
    /// accepted rate), whose every update triggers one scan; the ledger's stall check runs
    /// from here. `buffers` are the two DMA buffers and the spare.
    pub fn start(
        hw: Hardware,
        buffers: [&'static mut Buffer; 3],
        mut rcc: Rcc,
        clock: Clock,
        fs_hz: u32,
    ) -> Self {
        let mut adc = Adc::new(hw.adc1, true, adc_config(), &mut rcc);
        fresh_adc(&mut adc, &hw.pins);
        let mut logic = logic(fs_hz);
        let [a, b, spare] = buffers.map(|w| Block::new(w, 3 * logic.block()));
        let transfer = armed(hw.stream, adc, a, b);
        TIM2::enable(&mut rcc);
        TIM2::reset(&mut rcc);
        let tim = hw.tim2;
        tim.psc().write(|w| w.psc().set(0));
        tim.cr2().modify(|_, w| w.mms().update());
        let uptime = Uptime::new(TIMER_HZ / 1000, clock.now(), 0);
        let mut board = Board {
            trigger: tim,
            transfer: Some(transfer),
            parked: None,
            spare: Some(spare),
            pins: hw.pins,
            rcc,
            clock,
        };
        logic.start(&mut board);
        Self {
            board,
            logic,
            uptime,
        }
    }

    /// Runs the sampling at `fs_hz` (an accepted rate) from now (`imu_app::sampler`: TIM2
    /// stopped, the DMA re-armed with blocks of the new length, a fresh ledger, the new ARR,
    /// TIM2 run). The samples of the old rate still in flight are dropped (the tracker
    /// recalibrates after a new configuration anyway).
    pub fn retime(&mut self, fs_hz: u32) {
        if self.logic.retime(&mut self.board, fs_hz).is_err() {
            defmt::panic!("sampling at {} Hz (see app/tests/device.rs)", fs_hz);
        }
    }

    /// Handles the DMA interrupt: a full block goes to `take` as `[x, y, z]` triples with
    /// the ledger's verdict; an unfilled buffer is dropped; a DMA overrun restarts sampling.
    pub fn on_dma(&mut self, take: impl FnOnce(&[[u16; 3]], Delivery)) -> Outcome {
        if self.board.parked.is_some() {
            // Parked for Stop mode: a stale event (see `park`); resume rebuilds the transfer.
            return Outcome::Idle;
        }
        let b = &mut self.board;
        let (Some(transfer), Some(mut spare)) = (b.transfer.as_mut(), b.spare.take()) else {
            return self.logic.on_dma(&mut self.board, DmaEvent::Overrun);
        };
        mark_unfilled(spare.codes_mut());
        let (event, back) = match transfer.next_transfer(spare) {
            Ok((full, _)) if filled(full.codes()) => (DmaEvent::Full, full),
            Ok((unfilled, _)) => (DmaEvent::Unfilled, unfilled),
            Err(DMAError::NotReady(spare)) => (DmaEvent::NotReady, spare),
            Err(DMAError::Overrun(spare) | DMAError::SmallBuffer(spare)) => {
                (DmaEvent::Overrun, spare)
            }
        };
        let outcome = self.logic.on_dma(&mut self.board, event);
        if let Outcome::Block(delivery) = outcome {
            take(back.codes().as_chunks::<3>().0, delivery);
        }
        self.board.spare = Some(back);
        outcome
    }

    /// Restarts the sampling if no block has arrived for [`STALL_BLOCKS`] block periods at
    /// the running rate (or none since the start or the last restart); never while
    /// suspended.
    pub fn check_stalled(&mut self) -> Outcome {
        self.logic.check_stalled(&mut self.board)
    }

    /// Whether blocks arrive (a block since the last start or restart), or the sampling is
    /// paused on purpose.
    pub fn delivering(&self) -> bool {
        self.logic.delivering()
    }

    /// USB suspend: TIM2 at the probe rate; the ledger pauses (no stall, nothing lost).
    pub fn suspend(&mut self) {
        self.logic.suspend(&mut self.board);
    }

    /// USB resume: TIM2 back at the running rate; the ledger counts from now.
    pub fn resume(&mut self) {
        self.logic.resume(&mut self.board);
    }

    /// Parks the acquisition for Stop mode: TIM2 stopped, the DMA stream disabled and its
    /// parts kept, the ADC switched off (an enabled ADC draws its analog current in Stop).
    /// Resume rebuilds it (`imu_app::sampler`: a resume re-arms).
    pub fn park(&mut self) {
        self.board.stop();
        if let Some(mut p) = self.board.parts() {
            p.adc.disable();
            self.board.parked = Some(p);
            // Releasing the transfer cleared the stream's flags; a block that completed just
            // before is still latched in the NVIC, and must not reach `on_dma` as an overrun.
            cortex_m::peripheral::NVIC::unpend(pac::Interrupt::DMA2_STREAM0);
        }
    }

    /// One probe scan of X, Y, Z by software on the ADC [`Self::park`] parked (every Stop
    /// parks first: `crate::stop`), on whatever clock runs (the HSI after a Stop), the ADC
    /// powered only for it; `None` if the acquisition is not parked. Each conversion waits
    /// for the ADC's end of conversion; an ADC that never answers is the watchdog's.
    pub fn probe_scan(&mut self) -> Option<[u16; 3]> {
        let p = self.board.parked.as_mut()?;
        let pins = &self.board.pins;
        p.adc.enable();
        cortex_m::asm::delay(ADC_STAB_CYCLES);
        let codes = [
            p.adc.convert(&pins.x, ADC_SAMPLE_TIME),
            p.adc.convert(&pins.y, ADC_SAMPLE_TIME),
            p.adc.convert(&pins.z, ADC_SAMPLE_TIME),
        ];
        p.adc.disable();
        Some(codes)
    }

    /// Adds `ms` [ms] spent in Stop mode, which TIM5 did not count (`imu_app::uptime`).
    pub fn slept(&mut self, ms: u32) {
        self.uptime.credit(self.board.clock.now(), ms);
    }

    /// The ledger's totals.
    pub fn ledger(&self) -> &SampleLedger {
        self.logic.ledger()
    }

    /// Milliseconds since sampling started, from TIM5 (`imu_app::uptime`): the one time
    /// base of the DMA and housekeeping tasks, read at least every millisecond.
    pub fn now_ms(&mut self) -> u32 {
        self.uptime.update(self.board.clock.now())
    }
}
