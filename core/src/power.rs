//! USB suspend and remote wake-up: when the device stops sampling, when it starts again, and
//! when it wakes a sleeping host.
//!
//! # Design
//! The host suspends the bus (no traffic for 3 ms); a suspended device must draw at most
//! 2.5 mA, so the sampling for tracking stops (only for a device the host configured: a
//! bus that reads suspended before any host configured it is no host at all, and the
//! device keeps sampling and shows "not configured", [`Power::link_seen`]) ([`PowerAction::Suspend`]) and the board keeps
//! only a slow motion probe and the KEY. When the host resumes or resets the bus, sampling
//! starts again ([`PowerAction::Resume`]; the tracker recalibrates, since the rest it knew is
//! stale). If the host enabled remote wake-up (SET_FEATURE DEVICE_REMOTE_WAKEUP, allowed by
//! the configuration descriptor), a KEY press or a motion wakes it ([`PowerAction::Wake`]):
//! not before the bus has been idle [`Power::WAKE_AFTER_MS`] (USB 2.0, 7.1.7.7), and at most
//! once every [`Power::WAKE_RETRY_MS`] while the host stays asleep.
//!
//! Motion is a probe sample that differs from the first probe after the suspend by more than
//! the threshold on any axis: a moved or tilted mouse. The threshold is in ADC codes; the
//! board sets it far above the single-sample noise (about 1 LSB for the ADXL335 here).

use crate::indicator::Link;

/// What the board must do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PowerAction {
    /// Nothing changes.
    None,
    /// The bus was suspended: stop sampling for tracking, start the motion probe, dim.
    Suspend,
    /// The bus is active again: stop the probe, start sampling, recalibrate.
    Resume,
    /// Signal remote wake-up to the host (resume signalling for 1 to 15 ms).
    Wake,
}

/// The suspend state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Power {
    motion_lsb: u16,
    suspended_at: Option<u32>,
    reference: Option<[u16; 3]>,
    moved: bool,
    key_was: bool,
    woke_at: Option<u32>,
    configured: bool,
}

impl Power {
    /// Bus idle time before a remote wake-up may be signalled [ms], counted from the
    /// suspend's detection (which itself follows 3 ms of idle).
    pub const WAKE_AFTER_MS: u32 = 5;
    /// Interval between two wake-up signals while the host does not resume [ms].
    pub const WAKE_RETRY_MS: u32 = 1000;

    /// Awake, with a motion threshold of `motion_lsb` ADC codes on any axis.
    pub const fn new(motion_lsb: u16) -> Self {
        Self {
            motion_lsb,
            suspended_at: None,
            reference: None,
            moved: false,
            key_was: false,
            woke_at: None,
            configured: false,
        }
    }

    /// The motion threshold [ADC codes on any axis].
    pub const fn motion_lsb(&self) -> u16 {
        self.motion_lsb
    }

    /// Whether the device is suspended (sampling for tracking stopped).
    pub const fn suspended(&self) -> bool {
        self.suspended_at.is_some()
    }

    /// The link as the device should show it: a bus that reads suspended before the device
    /// was ever configured (no host, or a charger: a full-speed core with VBUS sensing off
    /// raises suspend with no cable) is shown as not configured, and the device keeps
    /// sampling ([`Self::tick`] does not suspend it).
    pub const fn link_seen(&self, link: Link) -> Link {
        match link {
            Link::Suspended if !self.configured && !self.suspended() => Link::NotConfigured,
            other => other,
        }
    }

    /// One probe sample `[x, y, z]` [ADC codes] while suspended; ignored while awake.
    pub fn probe(&mut self, codes: [u16; 3]) {
        if !self.suspended() {
            return;
        }
        match self.reference {
            None => self.reference = Some(codes),
            Some(r) => {
                let far = r
                    .iter()
                    .zip(codes)
                    .any(|(&r, c)| r.abs_diff(c) > self.motion_lsb);
                self.moved |= far;
            }
        }
    }

    /// One housekeeping tick at `now_ms` [ms]: the USB `link`, whether the host enabled
    /// `remote_wakeup`, and whether KEY is `key_pressed` (debounced).
    pub fn tick(
        &mut self,
        now_ms: u32,
        link: Link,
        remote_wakeup: bool,
        key_pressed: bool,
    ) -> PowerAction {
        let press = key_pressed && !self.key_was;
        self.key_was = key_pressed;
        match link {
            Link::Configured => self.configured = true,
            Link::NotConfigured => self.configured = false,
            Link::Suspended => {}
        }
        match (self.suspended_at, link) {
            (None, Link::Suspended) if self.configured => {
                self.suspended_at = Some(now_ms);
                self.reference = None;
                self.moved = false;
                self.woke_at = None;
                PowerAction::Suspend
            }
            (None, _) => PowerAction::None,
            (Some(_), Link::Configured | Link::NotConfigured) => {
                self.suspended_at = None;
                PowerAction::Resume
            }
            (Some(at), Link::Suspended) => {
                let cause = press || self.moved;
                if cause && self.may_signal(at, now_ms, remote_wakeup) {
                    self.woke_at = Some(now_ms);
                    self.moved = false;
                    self.reference = None;
                    PowerAction::Wake
                } else {
                    PowerAction::None
                }
            }
        }
    }
}

impl Power {
    /// Whether a motion probe found motion that the next [`Self::tick`] at `now_ms` [ms]
    /// would signal to a host that enabled `remote_wakeup`: the board keeps its clocks for
    /// it (`imu_app::sleep`). False while awake.
    pub fn motion_pending(&self, now_ms: u32, remote_wakeup: bool) -> bool {
        match self.suspended_at {
            Some(at) => self.moved && self.may_signal(at, now_ms, remote_wakeup),
            None => false,
        }
    }

    /// A wake-up signal is allowed at `now_ms`: the host enabled it, the bus has idled
    /// [`Self::WAKE_AFTER_MS`] since the suspend seen at `at`, and the last signal is
    /// [`Self::WAKE_RETRY_MS`] old.
    fn may_signal(&self, at: u32, now_ms: u32, remote_wakeup: bool) -> bool {
        let idle = now_ms.wrapping_sub(at) >= Self::WAKE_AFTER_MS;
        let rested = self
            .woke_at
            .is_none_or(|w| now_ms.wrapping_sub(w) >= Self::WAKE_RETRY_MS);
        remote_wakeup && idle && rested
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn suspended(p: &mut Power) {
        assert_eq!(p.tick(0, Link::Configured, true, false), PowerAction::None);
        assert_eq!(
            p.tick(1, Link::Suspended, true, false),
            PowerAction::Suspend
        );
        assert!(p.suspended());
    }

    #[test]
    fn suspend_and_resume_follow_the_link() {
        let mut p = Power::new(12);
        assert_eq!(p.motion_lsb(), 12, "the threshold it was built with");
        suspended(&mut p);
        assert_eq!(p.tick(2, Link::Suspended, true, false), PowerAction::None);
        assert_eq!(
            p.tick(3, Link::Configured, true, false),
            PowerAction::Resume
        );
        assert!(!p.suspended());
        // A bus reset during the suspend resumes too (the host re-enumerates).
        assert_eq!(
            p.tick(4, Link::Suspended, true, false),
            PowerAction::Suspend
        );
        assert_eq!(
            p.tick(5, Link::NotConfigured, true, false),
            PowerAction::Resume
        );
    }

    #[test]
    fn a_key_press_wakes_the_host_only_if_allowed_and_after_the_idle_time() {
        let mut p = Power::new(12);
        suspended(&mut p);
        // Not allowed by the host: never.
        assert_eq!(p.tick(10, Link::Suspended, false, true), PowerAction::None);
        assert_eq!(p.tick(11, Link::Suspended, false, false), PowerAction::None);
        let mut p = Power::new(12);
        suspended(&mut p);
        // Too early (the bus must idle 5 ms after the suspend was seen at 1 ms).
        assert_eq!(p.tick(5, Link::Suspended, true, true), PowerAction::None);
        // Held, not pressed again: no new edge.
        assert_eq!(p.tick(6, Link::Suspended, true, true), PowerAction::None);
        assert_eq!(p.tick(7, Link::Suspended, true, false), PowerAction::None);
        assert_eq!(p.tick(8, Link::Suspended, true, true), PowerAction::Wake);
    }

    #[test]
    fn motion_beyond_the_threshold_wakes_and_the_signal_is_not_repeated_at_once() {
        let mut p = Power::new(12);
        p.probe([2048, 2048, 2900]); // awake: ignored
        suspended(&mut p);
        p.probe([2048, 2048, 2458]);
        p.probe([2060, 2036, 2470]); // 12 codes: noise
        p.probe([2048, 2049, 2458]); // still
        assert_eq!(p.tick(10, Link::Suspended, true, false), PowerAction::None);
        p.probe([2048, 2048, 2471]); // 13 codes on z: moved (or tilted)
        assert_eq!(p.tick(11, Link::Suspended, true, false), PowerAction::Wake);
        // The host did not resume: the next motion wakes it again, a retry interval later.
        p.probe([2048, 2048, 2458]);
        p.probe([2100, 2048, 2458]);
        assert_eq!(p.tick(500, Link::Suspended, true, false), PowerAction::None);
        assert_eq!(
            p.tick(1011, Link::Suspended, true, false),
            PowerAction::Wake
        );
        assert_eq!(
            p.tick(1012, Link::Configured, true, false),
            PowerAction::Resume
        );
    }

    #[test]
    fn motion_is_pending_only_when_the_next_tick_would_signal_it() {
        let mut p = Power::new(12);
        assert!(
            !p.motion_pending(0, true),
            "awake: no probe, nothing pending"
        );
        suspended(&mut p);
        p.probe([2048, 2048, 2458]);
        assert!(!p.motion_pending(10, true), "still: nothing");
        p.probe([2048, 2048, 2471]);
        assert!(
            !p.motion_pending(3, true),
            "the bus has not idled 5 ms since 1 ms"
        );
        assert!(
            !p.motion_pending(10, false),
            "the host did not enable remote wake-up"
        );
        assert!(p.motion_pending(6, true));
        assert_eq!(p.tick(6, Link::Suspended, true, false), PowerAction::Wake);
        assert!(!p.motion_pending(7, true), "signalled: the cause is spent");
        p.probe([2048, 2048, 2458]);
        p.probe([2048, 2048, 2500]);
        assert!(
            !p.motion_pending(1005, true),
            "within the retry interval of the signal"
        );
        assert!(p.motion_pending(1006, true));
        assert_eq!(
            p.tick(1006, Link::Suspended, true, false),
            PowerAction::Wake
        );
    }

    #[test]
    fn a_device_never_configured_is_not_suspended_and_shows_not_configured() {
        // On the bench, powered by the probe with no host: the core reads suspended from the
        // start. Sampling goes on, the LED says "USB not configured".
        let mut p = Power::new(12);
        for t in 0..10 {
            assert_eq!(p.tick(t, Link::Suspended, true, false), PowerAction::None);
            assert!(!p.suspended());
            assert_eq!(p.link_seen(Link::Suspended), Link::NotConfigured);
        }
        // Addressed but not configured, then suspended: still no host that wants a mouse.
        assert_eq!(
            p.tick(10, Link::NotConfigured, true, false),
            PowerAction::None
        );
        assert_eq!(p.tick(11, Link::Suspended, true, false), PowerAction::None);
        // Configured, then suspended: a real suspend, shown as such.
        assert_eq!(p.tick(12, Link::Configured, true, false), PowerAction::None);
        assert_eq!(p.link_seen(Link::Suspended), Link::Suspended);
        assert_eq!(
            p.tick(13, Link::Suspended, true, false),
            PowerAction::Suspend
        );
        assert_eq!(p.link_seen(Link::Suspended), Link::Suspended);
        // A bus reset (re-enumeration) forgets the configuration.
        assert_eq!(
            p.tick(14, Link::NotConfigured, true, false),
            PowerAction::Resume
        );
        assert_eq!(p.tick(15, Link::Suspended, true, false), PowerAction::None);
        assert_eq!(p.link_seen(Link::Suspended), Link::NotConfigured);
        assert_eq!(p.link_seen(Link::Configured), Link::Configured);
    }
}
