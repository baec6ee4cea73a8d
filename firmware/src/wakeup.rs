//! Remote wake-up signalling on the OTG_FS core: DCTL.RWUSIG held for
//! `board::REMOTE_WAKEUP_MS` (USB 2.0 asks for 1 to 15 ms). The decision to wake is
//! `imu_core::Power`'s; synopsys-usb-otg 0.4 has no call for the signal, so it is written
//! here.

use imu_app::Mouse;
use rtic::Mutex;
use stm32f4xx_hal::{otg_fs::UsbBusType, pac::OTG_FS_DEVICE};

use crate::board;

/// An ongoing wake-up signal, if any.
#[derive(Default)]
pub struct RemoteWakeup {
    until_ms: Option<u32>,
}

/// Sets or clears DCTL.RWUSIG. Runs under the mouse's lock, so the USB interrupt (the other
/// writer of DCTL, through the USB stack) cannot interleave with the read-modify-write.
#[allow(unsafe_code)]
fn signal(on: bool, mouse: &mut impl Mutex<T = Mouse<'static, UsbBusType>>) {
    mouse.lock(|_| {
        // SAFETY: the OTG_FS_DEVICE block belongs to the USB bus; this touches one bit of
        // DCTL that the USB stack never writes, under the lock that excludes the stack.
        let dev = unsafe { OTG_FS_DEVICE::steal() };
        dev.dctl().modify(|_, w| w.rwusig().bit(on));
    });
}

impl RemoteWakeup {
    /// Starts the resume signal at `now_ms` [ms].
    pub fn start(&mut self, now_ms: u32, mouse: &mut impl Mutex<T = Mouse<'static, UsbBusType>>) {
        signal(true, mouse);
        self.until_ms = Some(now_ms.wrapping_add(board::REMOTE_WAKEUP_MS));
        defmt::info!("remote wake-up: signalling the host");
    }

    /// Whether the signal is on (the OTG core drives it from its 48 MHz clock: no Stop).
    pub fn active(&self) -> bool {
        self.until_ms.is_some()
    }

    /// Ends the signal once its time is up.
    pub fn tick(&mut self, now_ms: u32, mouse: &mut impl Mutex<T = Mouse<'static, UsbBusType>>) {
        if let Some(until) = self.until_ms {
            if now_ms.wrapping_sub(until) < u32::MAX / 2 {
                signal(false, mouse);
                self.until_ms = None;
            }
        }
    }
}
