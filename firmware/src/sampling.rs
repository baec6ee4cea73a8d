//! Hardware-timed sampling: TIM2's update event triggers an ADC1 scan of X, Y, Z; DMA2
//! stream 0 moves each scan into one of two buffers and interrupts when a buffer is full.
//!
//! # Design
//! - No software trigger and no per-sample interrupt: TIM2 (TRGO on update, PSC 0 and the
//!   ARR of `board`) starts each scan; the ADC's continuous bit stays off, or it would
//!   free-run. Suspend lowers TIM2 to the probe rate; resume restores it.
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
use imu_app::device::block_len;
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
    pac::{ADC1, DMA2, TIM2},
    rcc::{Enable, Rcc, Reset},
};

use crate::board::{ADC_PRESCALER, ADC_SAMPLE_TIME, BUF_MAX, PROBE_ARR, STALL_BLOCKS, TIMER_HZ};
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

/// What an interrupt or a stall check produced.
pub enum Outcome {
    /// A block was handed to the closure.
    Block,
    /// Nothing to do (not a transfer-complete event, or an unfilled buffer dropped).
    Idle,
    /// Sampling was restarted; this many sample triples were lost.
    Restarted(u32),
}

/// The sampling pipeline's hardware and its ledger.
pub struct Sampler {
    trigger: TIM2,
    /// TIM2's auto-reload at the running rate, and the block length [triples].
    arr: u32,
    block: usize,
    transfer: Option<AdcTransfer>,
    spare: Option<Block>,
    pins: Pins,
    rcc: Rcc,
    clock: Clock,
    uptime: Uptime,
    ledger: SampleLedger,
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

/// The ledger of a rate the device accepts (`imu_app::device::rate_accepted`, checked by
/// the caller; every accepted rate builds: `app/tests/device.rs`).
fn ledger(fs_hz: u32) -> SampleLedger {
    let Ok(ledger) = SampleLedger::new(TIMER_HZ, fs_hz, block_len(fs_hz) as u32) else {
        defmt::panic!("ledger at {} Hz (see app/tests/device.rs)", fs_hz)
    };
    ledger
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
        let block = block_len(fs_hz);
        let [a, b, spare] = buffers.map(|w| Block::new(w, 3 * block));
        let transfer = armed(hw.stream, adc, a, b);
        TIM2::enable(&mut rcc);
        TIM2::reset(&mut rcc);
        let tim = hw.tim2;
        let arr = TIMER_HZ / fs_hz - 1;
        tim.psc().write(|w| w.psc().set(0));
        tim.arr().write(|w| w.arr().set(arr));
        tim.cr2().modify(|_, w| w.mms().update());
        tim.egr().write(|w| w.ug().set_bit());
        tim.cr1().modify(|_, w| w.cen().set_bit());
        let mut ledger = ledger(fs_hz);
        ledger.start(clock.now());
        let uptime = Uptime::new(TIMER_HZ / 1000, clock.now(), 0);
        Self {
            trigger: tim,
            arr,
            block,
            transfer: Some(transfer),
            spare: Some(spare),
            pins: hw.pins,
            rcc,
            clock,
            uptime,
            ledger,
        }
    }

    /// Runs the sampling at `fs_hz` (an accepted rate) from now: TIM2 stopped, the DMA
    /// re-armed with blocks of the new length, the new ARR loaded, a fresh ledger, TIM2
    /// started. The samples of the old rate still in flight are dropped (the tracker
    /// recalibrates after a new configuration anyway).
    pub fn retime(&mut self, fs_hz: u32) {
        self.trigger.cr1().modify(|_, w| w.cen().clear_bit());
        self.block = block_len(fs_hz);
        self.arr = TIMER_HZ / fs_hz - 1;
        let len = 3 * self.block;
        if let Some(spare) = self.spare.as_mut() {
            spare.resize(len);
        }
        if let Some(transfer) = self.transfer.take() {
            let (stream, mut adc, mut a, b) = transfer.release();
            <ADC1 as Reset>::reset(&mut self.rcc);
            fresh_adc(&mut adc, &self.pins);
            a.resize(len);
            if let Some(mut b) = b {
                b.resize(len);
                self.transfer = Some(armed(stream, adc, a, b));
            }
        }
        self.ledger = ledger(fs_hz);
        self.ledger.start(self.clock.now());
        self.set_rate(self.arr);
        self.trigger.cr1().modify(|_, w| w.cen().set_bit());
    }

    /// Handles the DMA interrupt: a full block goes to `take` as `[x, y, z]` triples with
    /// the ledger's verdict; an unfilled buffer is dropped; a DMA overrun restarts sampling.
    pub fn on_dma(&mut self, take: impl FnOnce(&[[u16; 3]], Delivery)) -> Outcome {
        let now = self.clock.now();
        let (Some(transfer), Some(mut spare)) = (self.transfer.as_mut(), self.spare.take()) else {
            return self.restart(now);
        };
        mark_unfilled(spare.codes_mut());
        match transfer.next_transfer(spare) {
            Ok((full, _)) if filled(full.codes()) => {
                let delivery = self.ledger.block(now);
                take(full.codes().as_chunks::<3>().0, delivery);
                self.spare = Some(full);
                Outcome::Block
            }
            Ok((unfilled, _)) => {
                self.ledger.unfilled();
                self.spare = Some(unfilled);
                Outcome::Idle
            }
            Err(DMAError::NotReady(spare)) => {
                self.spare = Some(spare);
                Outcome::Idle
            }
            Err(DMAError::Overrun(spare) | DMAError::SmallBuffer(spare)) => {
                self.spare = Some(spare);
                self.restart(now)
            }
        }
    }

    /// Restarts the sampling if no block has arrived for [`STALL_BLOCKS`] block periods at
    /// the running rate (or none since the start or the last restart).
    pub fn check_stalled(&mut self) -> Outcome {
        let now = self.clock.now();
        if self.ledger.stalled(now, STALL_BLOCKS * self.block as u32) {
            self.restart(now)
        } else {
            Outcome::Idle
        }
    }

    /// Whether blocks arrive (a block since the last start or restart).
    pub fn delivering(&self) -> bool {
        self.ledger.delivering() || !self.ledger.running()
    }

    /// USB suspend: TIM2 at the probe rate; the ledger pauses (no stall, nothing lost).
    pub fn suspend(&mut self) {
        self.ledger.pause();
        self.set_rate(PROBE_ARR);
    }

    /// USB resume: TIM2 back at the running rate; the ledger counts from now.
    pub fn resume(&mut self) {
        self.set_rate(self.arr);
        self.ledger.start(self.clock.now());
    }

    /// Milliseconds since sampling started, from TIM5 (`imu_app::uptime`): the one time
    /// base of the DMA and housekeeping tasks, read at least every millisecond.
    pub fn now_ms(&mut self) -> u32 {
        self.uptime.update(self.clock.now())
    }

    /// The ledger's totals.
    pub fn ledger(&self) -> &SampleLedger {
        &self.ledger
    }

    fn set_rate(&mut self, arr: u32) {
        self.trigger.arr().write(|w| w.arr().set(arr));
        self.trigger.egr().write(|w| w.ug().set_bit());
    }

    fn restart(&mut self, now: u32) -> Outcome {
        if let Some(transfer) = self.transfer.take() {
            let (stream, mut adc, a, b) = transfer.release();
            // A full ADC reset is the one way the HAL offers to clear OVR.
            <ADC1 as Reset>::reset(&mut self.rcc);
            fresh_adc(&mut adc, &self.pins);
            // A double-buffered transfer always returns its second buffer; without one the
            // sampling stays stopped and the stall check keeps reporting no data.
            if let Some(b) = b {
                self.transfer = Some(armed(stream, adc, a, b));
            }
        }
        Outcome::Restarted(self.ledger.restart(now))
    }
}
