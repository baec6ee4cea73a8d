//! The configuration interface's requests, decided: what each answers and what the device
//! must do for it, free of the bus and of the flash.
//!
//! # Design
//! [`Commands`] holds the running profile, a staged one while a `config set` spans several
//! frames, and where the running profile came from. [`Commands::handle`] turns one request
//! into a [`Reply`]: the response (or none yet, for a save, which answers when the flash is
//! done: [`Commands::saved`]) and an [`Effect`] that the caller carries out on the tracker,
//! the sampling hardware, the stream and the store. A configuration is applied only when the
//! whole staged profile validates ([`Profile::validate`]) and the device can run its rate;
//! otherwise the error names the key and nothing running changes.

use imu_core::profile::{Key, Profile, ProfileError};
use imu_core::protocol::{
    code, AxisCalibration, Counters, ErrorCode, Info, Request, Response, Source, TrackerState,
    PAIRS_MAX,
};
use imu_core::Calibration;

use crate::device::unsupported;
use crate::identity::FIRMWARE_VERSION;

/// What the caller must do after a request.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Effect {
    /// Run [`Commands::running`]: reconfigure the tracker (which recalibrates) and take the
    /// new axis mapping.
    pub apply: bool,
    /// The sampling rate changed: retime the trigger and the DMA blocks.
    pub retime: bool,
    /// Keep [`Commands::running`] in flash, then answer with [`Commands::saved`].
    pub save: bool,
    /// Calibrate again.
    pub recalibrate: bool,
    /// Start (`Some(true)`) or stop (`Some(false)`) the raw stream.
    pub stream: Option<bool>,
}

/// A request's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct Reply {
    /// The response now, or `None` when it comes after the save ([`Commands::saved`]).
    pub response: Option<Response>,
    /// What the caller must do.
    pub effect: Effect,
}

impl Reply {
    fn now(response: Response) -> Self {
        Self {
            response: Some(response),
            effect: Effect::default(),
        }
    }
    fn error(e: ErrorCode) -> Self {
        Self::now(Response::Error(e))
    }
}

/// What the device knows that the read-only requests report.
#[derive(Clone, Copy, Debug, Default)]
pub struct View {
    /// The tracker's phase is tracking.
    pub tracking: bool,
    /// The tracker's counters.
    pub counters: imu_core::Counters,
    /// The last successful calibration.
    pub calibration: Option<[Calibration; 3]>,
    /// Sampling restarts.
    pub restarts: u32,
    /// Mouse reports sent.
    pub reports: u32,
    /// Whether a raw stream runs, its frames sent and triples lost.
    pub stream: (bool, u32, u32),
    /// The cursor's motion so far [counts] (right, down; [`imu_core::Reporter::added`]).
    pub counts: [i64; 2],
    /// What the tracker is doing.
    pub tracker: TrackerState,
}

/// The configuration interface's state.
#[derive(Clone, Copy, Debug)]
pub struct Commands {
    running: Profile,
    staged: Option<(Profile, u8)>,
    source: Source,
    invalid: Option<Key>,
    saving: Option<(u8, u8)>,
    clock_hz: u32,
}

impl Commands {
    /// Running `profile` (from `source`; `invalid` names the stored key that failed), on a
    /// device whose sample clock is `clock_hz` [Hz] (the rates it can run).
    pub fn new(profile: Profile, source: Source, invalid: Option<Key>, clock_hz: u32) -> Self {
        Self {
            running: profile,
            staged: None,
            source,
            invalid,
            saving: None,
            clock_hz,
        }
    }

    /// The running profile.
    pub fn running(&self) -> &Profile {
        &self.running
    }

    /// Where the running profile came from.
    pub fn source(&self) -> Source {
        self.source
    }

    /// The outcome of request `req` with `tag`, given what the device knows (`view`).
    pub fn handle(&mut self, tag: u8, req: Request, view: &View) -> Reply {
        if self.saving.is_some() {
            return Reply::error(ErrorCode::Busy);
        }
        match req {
            Request::Info => Reply::now(Response::Info(Info {
                firmware: FIRMWARE_VERSION,
                protocol: imu_core::protocol::VERSION,
                source: self.source,
                invalid_key: self.invalid.map_or(0, |k| k as u8),
                fs_hz: self.running.config.fs_hz,
                tracking: view.tracking,
                streaming: view.stream.0,
            })),
            Request::Counters => Reply::now(Response::Counters(Counters {
                samples: view.counters.samples,
                lost: view.counters.lost,
                restarts: view.restarts,
                reports: view.reports,
                rejected_windows: view.counters.rejected_windows,
                stream_frames: view.stream.1,
                stream_lost: view.stream.2,
                counts: view.counts,
                tracker: view.tracker,
            })),
            Request::Calibration => Reply::now(Response::Calibration(view.calibration.map(|c| {
                c.map(|a| AxisCalibration {
                    bias_q16: a.bias_q16,
                    noise_rms_q16: u32::try_from(a.noise_rms_q16).unwrap_or(u32::MAX),
                })
            }))),
            Request::GetConfig { start } => {
                let from = usize::from(start).min(Key::ALL.len());
                let pairs = Key::ALL[from..]
                    .iter()
                    .take(PAIRS_MAX)
                    .map(|&k| (k, self.running.get(k)))
                    .collect();
                Reply::now(Response::Config {
                    total: Key::ALL.len() as u8,
                    start,
                    pairs,
                })
            }
            Request::SetConfig { commit, pairs } => self.set(&pairs, commit),
            Request::Save => self.save(tag, code::SAVE, Effect::default()),
            Request::Defaults => {
                let effect = self.apply(Profile::default());
                self.save(tag, code::DEFAULTS, effect)
            }
            Request::Recalibrate => Reply {
                response: Some(Response::Done(code::RECALIBRATE)),
                effect: Effect {
                    recalibrate: true,
                    ..Effect::default()
                },
            },
            Request::StreamStart => Reply {
                response: Some(Response::Done(code::STREAM_START)),
                effect: Effect {
                    stream: Some(true),
                    ..Effect::default()
                },
            },
            Request::StreamStop => Reply {
                response: Some(Response::Stopped {
                    frames: view.stream.1,
                    lost: view.stream.2,
                }),
                effect: Effect {
                    stream: Some(false),
                    ..Effect::default()
                },
            },
        }
    }

    /// Stages `pairs`; with `commit`, validates the staged profile and runs it. Any error
    /// discards everything staged; the running profile never changes on an error.
    fn set(&mut self, pairs: &[(Key, f64)], commit: bool) -> Reply {
        let (mut staged, mut count) = self.staged.take().unwrap_or((self.running, 0));
        for &(key, value) in pairs {
            if let Err(e) = staged.set(key, value) {
                return Reply::error(error(e));
            }
            count = count.saturating_add(1);
        }
        if !commit {
            self.staged = Some((staged, count));
            return Reply::now(Response::Staged {
                count,
                applied: false,
            });
        }
        // What the board cannot run first: a rate or resolution it cannot run also makes
        // other settings fail (a 1 s calibration window at 7 Hz is too short), and the user
        // set the rate, not those.
        if let Some(key) = unsupported(&staged.config, self.clock_hz) {
            return Reply::error(ErrorCode::Unsupported(key));
        }
        if let Err(e) = staged.validate() {
            return Reply::error(blame(error(e), pairs));
        }
        let effect = self.apply(staged);
        Reply {
            response: Some(Response::Staged {
                count,
                applied: true,
            }),
            effect,
        }
    }

    fn apply(&mut self, profile: Profile) -> Effect {
        let retime = profile.config.fs_hz != self.running.config.fs_hz;
        self.running = profile;
        self.source = Source::Changed;
        Effect {
            apply: true,
            retime,
            ..Effect::default()
        }
    }

    fn save(&mut self, tag: u8, code: u8, effect: Effect) -> Reply {
        self.saving = Some((tag, code));
        Reply {
            response: None,
            effect: Effect {
                save: true,
                ..effect
            },
        }
    }

    /// The save asked for by the last reply is done (`ok`) or failed: the response to send,
    /// with the request's tag. `None` if no save was asked for.
    pub fn saved(&mut self, ok: bool) -> Option<(u8, Response)> {
        let (tag, code) = self.saving.take()?;
        if !ok {
            return Some((tag, Response::Error(ErrorCode::Storage)));
        }
        self.source = Source::Stored;
        self.invalid = None;
        Some((tag, Response::Done(code)))
    }
}

/// Two cursor axes on one sensor axis: the key this request set is the one to name (the
/// other kept its value), `y_axis` when it set both or neither.
fn blame(code: ErrorCode, pairs: &[(Key, f64)]) -> ErrorCode {
    let set = |k: Key| pairs.iter().any(|&(p, _)| p == k);
    match code {
        ErrorCode::Invalid(Key::YAxis) if set(Key::XAxis) && !set(Key::YAxis) => {
            ErrorCode::Invalid(Key::XAxis)
        }
        other => other,
    }
}

fn error(e: ProfileError) -> ErrorCode {
    match e {
        ProfileError::Value(k) => ErrorCode::Value(k),
        ProfileError::SameAxis | ProfileError::Invalid(_) => ErrorCode::Invalid(e.key()),
    }
}
