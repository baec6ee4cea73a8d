//! The first reports after the host configures the device: an opening report, then a quiet
//! time, then the motion owed and the held buttons again.
//!
//! # Design
//! Linux's usbhid drops every input report that completes within 50 ms of the moment it
//! opens the device (`usbhid_open`: `HID_RESUME_RUNNING` through `msleep(50)`, or
//! `input_start_time` 50 ms on, in drivers/hid/usbhid/hid-core.c), and it polls the mouse's
//! endpoint only from that moment. A report the device sends at once after a
//! (re)enumeration is therefore lost on a Linux host: the held button re-sent after a bus
//! reset, or the first counts of a stroke (`host-tests/tools/kernel_check.py` saw both with
//! the kernel's own drivers). So after each new configuration the device first sends an
//! opening report (the held buttons, no motion), whose completion tells it that the host
//! polls; it then holds every report for [`QUIET_MS`] after that completion, motion
//! accumulating as owed, and then reports the held buttons again with the motion. A host
//! that does not drop reports sees the held buttons twice (no edge) and the motion 80 ms
//! late, once per enumeration.
//!
//! Not covered: a host that closes and reopens the device without re-enumerating it (an
//! X server restart) starts a new window the device cannot see.

/// Quiet time after the opening report's completion [ms]: usbhid's 50 ms, plus two ticks of
/// the coarsest common kernel clock (HZ = 100; `msleep` and `time_after` each round up a
/// tick), plus 10 ms for the opening process to be scheduled again.
pub const QUIET_MS: u32 = 50 + 2 * 10 + 10;

/// Where the opening stands.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum State {
    /// Reports flow.
    #[default]
    Open,
    /// The opening report is to be sent.
    Opening,
    /// The opening report is in the endpoint, not yet taken.
    Sent,
    /// Taken at this time [ms]; quiet until [`QUIET_MS`] later.
    Quiet(u32),
}

/// What the device may push now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gate {
    /// The opening report: the held buttons, no motion.
    Opening,
    /// Nothing: motion accumulates as owed.
    Hold,
    /// Reports as usual; `resend`: the held buttons are to be reported again first.
    Open {
        /// The quiet time just ended: report the held buttons again.
        resend: bool,
    },
}

/// The opening's state machine.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Opening {
    state: State,
}

impl Opening {
    /// The host configured the device afresh (after an enumeration or a bus reset; not after
    /// a resume, which keeps the host's open device).
    pub fn configured(&mut self) {
        self.state = State::Opening;
    }

    /// The gate at `now_ms` [ms]; `delivered`: the report in flight was taken by the host in
    /// this poll.
    pub fn gate(&mut self, delivered: bool, now_ms: u32) -> Gate {
        if self.state == State::Sent && delivered {
            self.state = State::Quiet(now_ms);
        }
        match self.state {
            State::Open => Gate::Open { resend: false },
            State::Opening => Gate::Opening,
            State::Sent => Gate::Hold,
            State::Quiet(at) if now_ms.wrapping_sub(at) < QUIET_MS => Gate::Hold,
            State::Quiet(_) => {
                self.state = State::Open;
                Gate::Open { resend: true }
            }
        }
    }

    /// The opening report went into the endpoint.
    pub fn sent(&mut self) {
        if self.state == State::Opening {
            self.state = State::Sent;
        }
    }
}
