//! The device's tracker on the page's raw stream: the core's [`Tracker`] fed the streamed
//! codes as the device feeds its own, so the page shows what drift control decides (its
//! state) and where the cursor goes, from the moment the stream started.
//!
//! The feed is `cargo lab replay`'s (`host-tests/src/device/track.rs`): each triple routed by
//! the profile's axis map, the counts taken every `max(fs / 1000, 1)` samples (a 1 ms poll),
//! given their signs and turned into HID motion (right, down). So the page's cursor total
//! over a recording is `replay`'s on the same recording, count for count. It is not the
//! device's own total, which began at the device's start-up, not the stream's.

use imu_core::hid::screen_motion;
use imu_core::profile::{AxisMap, Profile};
use imu_core::{DriftState, Phase, Tracker};

/// A tracker running on the stream.
pub struct Track {
    tracker: Tracker,
    map: AxisMap,
    per_poll: u64,
    samples: u64,
    /// Counts sent so far, right and down.
    pub sent: (i64, i64),
}

impl Track {
    /// A tracker with profile `p`, or `None` if `p` does not run.
    pub fn new(p: &Profile) -> Option<Self> {
        p.validate().ok()?;
        Some(Self {
            tracker: Tracker::new(&p.config).ok()?,
            map: p.map,
            per_poll: u64::from((p.config.fs_hz / 1000).max(1)),
            samples: 0,
            sent: (0, 0),
        })
    }

    /// Feeds one triple of raw codes in sensor order.
    pub fn feed(&mut self, codes: [u16; 3]) {
        self.samples += 1;
        self.tracker.feed(&[self.map.route(codes)]);
        if self.samples.is_multiple_of(self.per_poll) {
            let (dx, dy) = screen_motion(self.map.screen(self.tracker.take_counts()));
            self.sent.0 += i64::from(dx);
            self.sent.1 += i64::from(dy);
        }
    }

    /// Drift control's state in words: `calibrating`, `off` (no drift control), `still`,
    /// `moving`, `lifted` or `frozen`.
    pub fn state(&self) -> &'static str {
        if self.tracker.phase() == Phase::Calibrating {
            return "calibrating";
        }
        match self.tracker.drift_state() {
            None => "off",
            Some(DriftState::Still) => "still",
            Some(DriftState::Moving) => "moving",
            Some(DriftState::Lifted) => "lifted",
            Some(DriftState::Frozen) => "frozen",
        }
    }

    /// Whether drift control holds a motion back (too young, or held by the tilt tests).
    pub fn held(&self) -> bool {
        self.tracker.is_holding()
    }

    /// Samples fed.
    pub const fn samples(&self) -> u64 {
        self.samples
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_stream_calibrates_and_stays_still() {
        let p = Profile::default();
        let mut t = Track::new(&p).expect("the defaults run");
        assert_eq!(t.state(), "calibrating");
        // 2 s at 3 kHz of codes dithering by one step about mid-scale, 1 g on Z.
        for i in 0..6000u16 {
            let d = i % 2;
            t.feed([2048 + d, 2048 - d, 2048 + 418 + d]);
        }
        assert_eq!(t.state(), "still");
        assert_eq!(t.sent, (0, 0));
        assert_eq!(t.samples(), 6000);
        let mut bad = p;
        bad.config.fs_hz = 0;
        assert!(Track::new(&bad).is_none());
    }
}
