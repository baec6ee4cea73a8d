//! Button debouncing and long-press detection, driven by a periodic [`Debouncer::tick`].
//!
//! # Design
//! An integrating debouncer: the reported state changes only after the raw input has
//! disagreed with it for `settle_ticks` consecutive ticks, so a bounce shorter than that is
//! never seen, and a real press is reported `settle_ticks` ticks after it starts. A press held
//! for `long_ticks` ticks reports one [`ButtonEvent::LongPress`] (the device uses it to
//! recalibrate), after the [`ButtonEvent::Pressed`] that started it.

/// What a tick observed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ButtonEvent {
    /// The debounced state became pressed.
    Pressed,
    /// The debounced state became released.
    Released,
    /// The button has been held for the long-press time (once per press).
    LongPress,
}

/// Debounce state of one button.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Debouncer {
    settle_ticks: u16,
    long_ticks: u32,
    disagree: u16,
    pressed: bool,
    held: u32,
}

impl Debouncer {
    /// A released button that needs `settle_ticks` (`>= 1`) agreeing ticks to change state
    /// and reports a long press after `long_ticks` ticks held. With a 1 ms tick, the device
    /// uses 5 and 2000.
    pub const fn new(settle_ticks: u16, long_ticks: u32) -> Self {
        Self {
            settle_ticks: if settle_ticks == 0 { 1 } else { settle_ticks },
            long_ticks,
            disagree: 0,
            pressed: false,
            held: 0,
        }
    }

    /// The debounced state.
    pub const fn is_pressed(&self) -> bool {
        self.pressed
    }

    /// One sample of the raw input (`true` = pressed, after any active-low inversion).
    pub fn tick(&mut self, raw_pressed: bool) -> Option<ButtonEvent> {
        if raw_pressed == self.pressed {
            self.disagree = 0;
        } else {
            self.disagree += 1;
            if self.disagree >= self.settle_ticks {
                self.disagree = 0;
                self.pressed = raw_pressed;
                self.held = 0;
                return Some(if raw_pressed {
                    ButtonEvent::Pressed
                } else {
                    ButtonEvent::Released
                });
            }
        }
        if self.pressed {
            self.held = self.held.saturating_add(1);
            if self.held == self.long_ticks {
                return Some(ButtonEvent::LongPress);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(d: &mut Debouncer, raw: &[bool]) -> [Option<ButtonEvent>; 16] {
        let mut out = [None; 16];
        for (o, &r) in out.iter_mut().zip(raw) {
            *o = d.tick(r);
        }
        out
    }

    #[test]
    fn bounces_shorter_than_settle_are_ignored() {
        let mut d = Debouncer::new(3, 1000);
        let ev = run(&mut d, &[true, false, true, true, false, false, false]);
        assert!(ev.iter().all(Option::is_none));
        assert!(!d.is_pressed());
    }

    #[test]
    fn press_and_release_after_settle() {
        let mut d = Debouncer::new(3, 1000);
        let ev = run(&mut d, &[true, true, true, false, false, false]);
        assert_eq!(ev[2], Some(ButtonEvent::Pressed));
        assert_eq!(ev[5], Some(ButtonEvent::Released));
        let mut d = Debouncer::new(3, 1000);
        run(&mut d, &[true, true, true]);
        assert!(
            d.is_pressed(),
            "the debounced state follows a settled press"
        );
    }

    #[test]
    fn long_press_fires_once() {
        let mut d = Debouncer::new(1, 3);
        let ev = run(&mut d, &[true; 8]);
        assert_eq!(ev[0], Some(ButtonEvent::Pressed));
        assert_eq!(ev[3], Some(ButtonEvent::LongPress));
        assert_eq!(ev.iter().filter(|e| e.is_some()).count(), 2);
    }
}
