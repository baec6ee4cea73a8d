//! The sample ledger's time base: TIM5, 32 bits, free-running at the 96 MHz timer clock.
//!
//! # Design
//! A hardware timer, not the DWT cycle counter: the DWT stops with the core clock in `wfi`
//! unless the debug block keeps it (DBGMCU DBG_SLEEP, a debugger convenience), so a board
//! running from a USB charger would mis-count lost samples. TIM5 shares its clock with TIM2
//! (the ADC trigger), so a sample period is an exact number of its counts. It wraps every
//! 44.7 s; the ledger measures gaps modulo 2^32. In Stop mode (USB suspend) it stops with
//! every clock; `Sampler::slept` credits the time asleep (`imu_app::sleep`).

use stm32f4xx_hal::{
    pac::TIM5,
    rcc::{Enable, Rcc, Reset},
};

/// The running TIM5 counter.
pub struct Clock {
    tim: TIM5,
}

impl Clock {
    /// Starts TIM5 counting up from 0 at the timer clock, wrapping at `u32::MAX`.
    pub fn start(tim: TIM5, rcc: &mut Rcc) -> Self {
        TIM5::enable(rcc);
        TIM5::reset(rcc);
        tim.psc().write(|w| w.psc().set(0));
        tim.arr().write(|w| w.arr().set(u32::MAX));
        tim.egr().write(|w| w.ug().set_bit()); // load PSC
        tim.cr1().modify(|_, w| w.cen().set_bit());
        Self { tim }
    }

    /// The counter now [timer cycles].
    pub fn now(&self) -> u32 {
        self.tim.cnt().read().cnt().bits()
    }
}
