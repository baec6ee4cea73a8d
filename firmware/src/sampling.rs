//! Hardware-timed sampling: TIM2's update event triggers an ADC1 scan of X, Y, Z; DMA2
//! stream 0 moves each scan into one of two buffers and interrupts when a buffer is full.
//!
//! # Design
//! - No software trigger and no per-sample interrupt: TIM2 (TRGO on update, at exactly
//!   `FS_HZ`) starts each scan; the ADC's continuous bit stays off, or it would free-run.
//! - Double buffering with a third, spare buffer: on each transfer-complete interrupt the
//!   spare goes to the DMA and the full buffer comes back, so the core reads a buffer the
//!   DMA is not writing.
//! - Lost samples are never silent. If the interrupt comes too late the DMA reports an
//!   overrun; if the ADC overruns it stops requesting DMA and blocks stop arriving (caught
//!   by [`Sampler::check_stall`]). Either way the ADC is reset through the RCC (which clears
//!   its OVR flag), reconfigured and the transfer restarted, and the samples lost in between
//!   are counted by the [`SampleLedger`] from the cycle counter and handed to the tracker.

use imu_core::SampleLedger;
use stm32f4xx_hal::{
    adc::{
        config::{AdcConfig, Dma, ExternalTrigger, Scan, Sequence, TriggerMode},
        Adc,
    },
    dma::{config::DmaConfig, DMAError, PeripheralToMemory, Stream0, Transfer},
    gpio::{Analog, PA1, PA2, PA3},
    pac::{tim2::cr2::MMS, ADC1, DMA2, TIM2},
    prelude::*,
    rcc::{Rcc, Reset},
    timer::CounterHz,
};

use crate::board::{ADC_SAMPLE_TIME, BLOCK, BUF_LEN};

/// One DMA buffer: [`BLOCK`] scans of X, Y, Z codes.
pub type Buffer = [u16; BUF_LEN];
type AdcTransfer = Transfer<Stream0<DMA2>, 0, Adc<ADC1>, PeripheralToMemory, &'static mut Buffer>;

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
    /// Nothing to do (not a transfer-complete event).
    Idle,
    /// Sampling was restarted; this many sample triples were lost.
    Restarted(u32),
}

/// The sampling pipeline's hardware and its ledger.
pub struct Sampler {
    /// Owned so that nothing else reconfigures it; it runs free at fs once started.
    _trigger: CounterHz<TIM2>,
    transfer: Option<AdcTransfer>,
    spare: Option<&'static mut Buffer>,
    pins: Pins,
    rcc: Rcc,
    ledger: SampleLedger,
}

fn adc_config() -> AdcConfig {
    AdcConfig::default()
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

impl Sampler {
    /// Sets up ADC1 and DMA2 stream 0, starts the transfer, then starts TIM2 at `fs_hz`,
    /// whose every update triggers one scan. `buffers` are the two DMA buffers and the spare.
    ///
    /// # Errors
    /// The timer's error if it cannot run at `fs_hz` (the sampling is then not started).
    pub fn start(
        hw: Hardware,
        buffers: [&'static mut Buffer; 3],
        mut rcc: Rcc,
        ledger: SampleLedger,
        fs_hz: u32,
    ) -> Result<Self, stm32f4xx_hal::timer::Error> {
        let mut adc = Adc::new(hw.adc1, true, adc_config(), &mut rcc);
        configure_channels(&mut adc, &hw.pins);
        let [a, b, spare] = buffers;
        let mut transfer =
            Transfer::init_peripheral_to_memory(hw.stream, adc, a, Some(b), dma_config());
        transfer.start(|_| {});
        let mut trigger = hw.tim2.counter_hz(&mut rcc);
        trigger.set_master_mode(MMS::Update);
        trigger.start(fs_hz.Hz())?;
        Ok(Self {
            _trigger: trigger,
            transfer: Some(transfer),
            spare: Some(spare),
            pins: hw.pins,
            rcc,
            ledger,
        })
    }

    /// Handles the DMA interrupt at cycle count `now`: a full block goes to `take` as
    /// `[x, y, z]` triples; a DMA overrun restarts the sampling.
    pub fn on_dma(&mut self, now: u32, take: impl FnOnce(&[[u16; 3]])) -> Outcome {
        let (Some(transfer), Some(spare)) = (self.transfer.as_mut(), self.spare.take()) else {
            return self.restart(now);
        };
        match transfer.next_transfer(spare) {
            Ok((full, _)) => {
                take(full.as_chunks::<3>().0);
                self.spare = Some(full);
                self.ledger.block(now, BLOCK as u32);
                Outcome::Block
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

    /// Restarts the sampling if no block has arrived for `max_samples` sample periods.
    pub fn check_stall(&mut self, now: u32, max_samples: u32) -> Outcome {
        if self.ledger.stalled(now, max_samples) {
            self.restart(now)
        } else {
            Outcome::Idle
        }
    }

    /// The ledger's totals.
    pub fn ledger(&self) -> &SampleLedger {
        &self.ledger
    }

    fn restart(&mut self, now: u32) -> Outcome {
        if let Some(transfer) = self.transfer.take() {
            let (stream, mut adc, a, b) = transfer.release();
            // A full ADC reset is the one way the HAL offers to clear OVR.
            <ADC1 as Reset>::reset(&mut self.rcc);
            adc.apply_config(adc_config());
            configure_channels(&mut adc, &self.pins);
            adc.enable();
            if let Some(b) = b {
                let mut t =
                    Transfer::init_peripheral_to_memory(stream, adc, a, Some(b), dma_config());
                t.start(|_| {});
                self.transfer = Some(t);
            }
        }
        Outcome::Restarted(self.ledger.restart(now))
    }
}
