//! The status LED: what the device is doing, as a blink pattern a person can read.
//!
//! | pattern | meaning |
//! |---|---|
//! | blinking 4 Hz | calibrating: keep the device still |
//! | flickering 10 Hz for 1 s | calibration rejected (it moved): still calibrating |
//! | three short flashes every 2 s | the sensor sits on an ADC rail: check the wiring |
//! | on | tracking: it is a mouse |
//! | one short flash a second | USB not configured: no host, or enumeration failed |
//! | on 1 s, off 1 s | no ADC data: sampling never started or stopped (trigger, DMA, ADC) |
//! | off | USB suspended (the suspend current budget) |
//!
//! Precedence: suspended, then no ADC data (a board fault outranks everything the data would
//! tell), then a sensor on a rail, then USB not configured, then the tracker's phase.

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
    /// USB not configured (no host, enumeration failed, or reset).
    NotConfigured,
    /// No ADC data: the sampling stalled or never started.
    NoData,
    /// USB suspended: LED off (within the suspend current budget).
    Suspended,
}

/// The USB link as the device sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Link {
    /// Not configured: unplugged, reset, or enumeration not (yet) done (the state at
    /// power-up).
    #[default]
    NotConfigured,
    /// Configured by the host: reports flow.
    Configured,
    /// Suspended by the host.
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

    /// What to show, in the module's order of precedence: the USB `link`, whether ADC data
    /// `arrives`, whether the tracker is `tracking`, and its `last` calibration outcome.
    pub const fn choose(link: Link, arrives: bool, tracking: bool, last: LastCalibration) -> Self {
        if matches!(link, Link::Suspended) {
            return Self::Suspended;
        }
        if !arrives {
            return Self::NoData;
        }
        if !tracking && matches!(last, LastCalibration::Clipped) {
            return Self::Fault;
        }
        if !matches!(link, Link::Configured) {
            return Self::NotConfigured;
        }
        if tracking {
            return Self::Tracking;
        }
        match last {
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
            Self::NotConfigured => t_ms % 1000 < 100,
            Self::NoData => t_ms % 2000 < 1000,
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
    fn choice_follows_the_documented_precedence() {
        use Indicator as I;
        use LastCalibration::*;
        use Link::*;
        // (link, arrives, tracking, last calibration) -> pattern
        let cases = [
            // Suspended stays dark whatever else holds.
            ((Suspended, false, false, Clipped), I::Suspended),
            // No data outranks the sensor, USB and the phase.
            ((Configured, false, true, Fine), I::NoData),
            ((NotConfigured, false, false, Clipped), I::NoData),
            // A rail outranks USB, but only while calibrating.
            ((NotConfigured, true, false, Clipped), I::Fault),
            ((Configured, true, true, Clipped), I::Tracking),
            ((NotConfigured, true, true, Fine), I::NotConfigured),
            ((NotConfigured, true, false, Fine), I::NotConfigured),
            ((Configured, true, false, Clipped), I::Fault),
            ((Configured, true, false, Moved { ms: 999 }), I::Rejected),
            (
                (Configured, true, false, Moved { ms: 1000 }),
                I::Calibrating,
            ),
            ((Configured, true, false, Fine), I::Calibrating),
        ];
        for ((link, arrives, tracking, last), want) in cases {
            assert_eq!(
                Indicator::choose(link, arrives, tracking, last),
                want,
                "{link:?} arrives {arrives} tracking {tracking} {last:?}"
            );
        }
    }

    #[test]
    fn patterns_switch_at_their_documented_edges() {
        use Indicator::*;
        // Calibrating blinks at 4 Hz (125 ms on, 125 off), Rejected at 10 Hz (50 and 50),
        // Fault flashes three times for 100 ms (at 0, 200 and 400 ms) in every 2 s.
        let cases: [(Indicator, &[u32], &[u32]); 3] = [
            (Calibrating, &[0, 1, 124, 250], &[125, 126, 249, 375]),
            (Rejected, &[0, 1, 49, 100], &[50, 51, 99, 150]),
            (Fault, &[0, 99, 200, 499], &[100, 199, 500, 599, 600, 1999]),
        ];
        for (ind, on, off) in cases {
            for &t in on {
                assert!(ind.lit(t), "{ind:?} lit at {t} ms");
            }
            for &t in off {
                assert!(!ind.lit(t), "{ind:?} dark at {t} ms");
            }
        }
        assert!(Fault.lit(2000));
    }

    #[test]
    fn duty_cycles() {
        assert_eq!(on_ms(Indicator::Calibrating, 1000), 500);
        assert_eq!(on_ms(Indicator::Rejected, 1000), 500);
        assert_eq!(on_ms(Indicator::Fault, 2000), 300); // three 100 ms flashes
        assert_eq!(on_ms(Indicator::Tracking, 1000), 1000);
        assert_eq!(on_ms(Indicator::NotConfigured, 1000), 100);
        assert_eq!(on_ms(Indicator::NoData, 2000), 1000);
        assert_eq!(on_ms(Indicator::Suspended, 1000), 0);
    }

    #[test]
    fn every_pattern_differs_from_every_other_over_two_seconds() {
        use Indicator::*;
        let all = [
            Calibrating,
            Rejected,
            Fault,
            Tracking,
            NotConfigured,
            NoData,
            Suspended,
        ];
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert!(
                    (0..2000).any(|t| a.lit(t) != b.lit(t)),
                    "{a:?} looks like {b:?}"
                );
            }
        }
    }
}
