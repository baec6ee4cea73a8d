//! The status LED: what the device is doing, as a blink pattern a person can read.
//!
//! | pattern | meaning |
//! |---|---|
//! | blinking 4 Hz | calibrating: keep the device still |
//! | flickering 10 Hz for 1 s | calibration rejected (it moved): still calibrating |
//! | three short flashes every 2 s | the sensor sits on an ADC rail: check the wiring |
//! | on | tracking: it is a mouse |
//! | off | USB suspended (or not yet enumerated) |

/// What the LED shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Indicator {
    /// Collecting a calibration window.
    Calibrating,
    /// A calibration window was just rejected for motion.
    Rejected,
    /// A calibration window touched an ADC rail.
    Fault,
    /// Tracking motion.
    Tracking,
    /// USB suspended or not configured: LED off (and within the suspend current budget).
    Suspended,
}

/// The last calibration outcome, as far as the LED cares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LastCalibration {
    /// None yet, or the last one succeeded.
    Fine,
    /// The last window was rejected for motion, `ms` milliseconds ago.
    Moved {
        /// Time since the rejection [ms].
        ms: u32,
    },
    /// The last window touched an ADC rail.
    Clipped,
}

impl Indicator {
    /// How long [`Indicator::Rejected`] is shown before going back to calibrating [ms].
    pub const REJECTED_MS: u32 = 1000;

    /// What to show: USB state first (a suspended device must stay dark), then the tracker's
    /// phase and its last calibration outcome.
    pub const fn choose(usb_configured: bool, tracking: bool, last: LastCalibration) -> Self {
        if !usb_configured {
            return Self::Suspended;
        }
        if tracking {
            return Self::Tracking;
        }
        match last {
            LastCalibration::Clipped => Self::Fault,
            LastCalibration::Moved { ms } if ms < Self::REJECTED_MS => Self::Rejected,
            _ => Self::Calibrating,
        }
    }

    /// Whether the LED is lit at time `t_ms` [ms] (any epoch; patterns repeat).
    pub const fn lit(self, t_ms: u32) -> bool {
        match self {
            Self::Calibrating => (t_ms / 125).is_multiple_of(2),
            Self::Rejected => (t_ms / 50).is_multiple_of(2),
            Self::Fault => {
                let phase = t_ms % 2000;
                phase < 600 && (phase / 100).is_multiple_of(2)
            }
            Self::Tracking => true,
            Self::Suspended => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on_ms(ind: Indicator, period: u32) -> u32 {
        (0..period).filter(|&t| ind.lit(t)).count() as u32
    }

    #[test]
    fn choice_puts_usb_first_then_phase_then_last_outcome() {
        use LastCalibration::*;
        assert_eq!(Indicator::choose(false, true, Fine), Indicator::Suspended);
        assert_eq!(Indicator::choose(true, true, Clipped), Indicator::Tracking);
        assert_eq!(Indicator::choose(true, false, Clipped), Indicator::Fault);
        assert_eq!(
            Indicator::choose(true, false, Moved { ms: 999 }),
            Indicator::Rejected
        );
        assert_eq!(
            Indicator::choose(true, false, Moved { ms: 1000 }),
            Indicator::Calibrating
        );
        assert_eq!(Indicator::choose(true, false, Fine), Indicator::Calibrating);
    }

    #[test]
    fn duty_cycles() {
        assert_eq!(on_ms(Indicator::Calibrating, 1000), 500);
        assert_eq!(on_ms(Indicator::Rejected, 1000), 500);
        assert_eq!(on_ms(Indicator::Fault, 2000), 300); // three 100 ms flashes
        assert_eq!(on_ms(Indicator::Tracking, 1000), 1000);
        assert_eq!(on_ms(Indicator::Suspended, 1000), 0);
    }
}
