//! The click hold: a click's jolt does not drag the cursor.
//!
//! A finger pressing the button jolts the device before the button's debounced edge reaches
//! the tracker (the firmware's 5 ms debounce and its housekeeping period: up to 10 ms). So a
//! motion younger than [`super::Drift::hold_s`] (from its onset) is integrated but not
//! delivered, and a button edge inside it discards it. A jolt is a step (one tick crosses
//! the fast alarm alone, [`super::rest`]), so its hold runs from the alarm: an onset that
//! noise placed earlier must not shorten it. A hand's stroke ramps up and is delivered from
//! `hold_s` after its onset, which its detection usually passes already.
//!
//! After an edge nothing is integrated for [`super::Drift::click_freeze_s`] (the jolt of the
//! press or the release, and the hand's recoil); then Still, from zero velocity.

use super::{Action, Detector, DriftSettings, State};

/// The hold and the freeze.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Click {
    /// Samples the new motion is still held for.
    pub(crate) hold_left: u64,
    /// Samples of the click freeze left.
    freeze_left: u32,
}

impl Click {
    /// A motion began `samples` samples ago; a `step` is held from now.
    pub(crate) fn begin_motion(&mut self, s: &DriftSettings, samples: u64, step: bool) {
        self.hold_left = if step {
            s.hold
        } else {
            s.hold.saturating_sub(samples)
        };
    }

    /// One more sample of a motion.
    #[inline(always)]
    pub(crate) fn motion_sample(&mut self) {
        self.hold_left = self.hold_left.saturating_sub(1);
    }

    /// One more frozen sample; `true` when the freeze is over.
    pub(crate) fn frozen_sample(&mut self) -> bool {
        self.freeze_left = self.freeze_left.saturating_sub(1);
        self.freeze_left == 0
    }
}

impl Detector {
    /// A button changed state: the held motion (if any) is discarded, a delivered one
    /// stops, and nothing is integrated for the click freeze.
    pub fn click(&mut self, s: &DriftSettings) -> Action {
        let action = match self.state {
            State::Moving if self.holds() => Action::Discard,
            State::Moving => Action::Stop,
            // Lifted it does not track: a click changes nothing.
            State::Lifted => return Action::None,
            State::Still | State::Frozen => Action::None,
        };
        // A click means the hand is still: a faded glide's velocity is forgotten.
        self.latent = super::estimator::Latent::default();
        if s.freeze > 0 {
            self.enter(State::Frozen);
            self.click.freeze_left = s.freeze;
        } else if self.state == State::Moving {
            self.enter_still();
        }
        action
    }
}
