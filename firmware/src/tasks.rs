//! What the RTIC tasks do beyond `imu_app`: the stall check under one lock with the
//! tracker, the board's part of a configuration request (retime, save), and the logs
//! through defmt. Every decision is made by
//! `imu_app` and `imu_core` (tested on the host).

use imu_app::commands::{Commands, Effect};
use imu_app::control::Resources;
use imu_app::sleep::{self, End, Why};
use imu_app::store::{Loaded, StoreError};
use imu_app::{Mouse, Status};
use imu_core::profile::AxisMap;
use imu_core::protocol::Source;
use imu_core::{Counters, Event, LedgerCounters, Tracker};
use rtic::Mutex;
use stm32f4xx_hal::{otg_fs::UsbBusType, watchdog::IndependentWatchdog};

use crate::board;
use crate::sampling::{Outcome, Sampler};
use crate::stop::{self, Stop};
use crate::wakeup::RemoteWakeup;

/// Logs the profile the device starts with and where it came from.
pub fn log_start(loaded: &Loaded) {
    let c = &loaded.profile.config;
    match loaded.source {
        Source::Stored => defmt::info!("profile: stored"),
        Source::Defaults => defmt::info!("profile: defaults (none stored)"),
        Source::Corrupt => defmt::warn!("profile: the store is unreadable; defaults"),
        Source::Invalid => defmt::warn!(
            "profile: the stored {} no longer validates; defaults",
            loaded.invalid.map_or("value", |k| k.name())
        ),
        Source::Changed => {}
    }
    defmt::info!(
        "imu-mouse: fs {} Hz, {} counts/inch, calibrating for {} s: keep still",
        c.fs_hz,
        c.counts_per_inch,
        c.calibration_s
    );
}

/// Logs a save's outcome.
pub fn log_save(result: &Result<(), StoreError>) {
    match result {
        Ok(()) => defmt::info!("profile saved"),
        Err(e) => defmt::error!("profile not saved: {}", e),
    }
}

/// Polls the USB stack and hands the mouse the tracker's fresh counts in screen order, at
/// the time base's milliseconds.
pub fn service_mouse(
    mouse: &mut impl Mutex<T = Mouse<'static, UsbBusType>>,
    tracker: &mut impl Mutex<T = Tracker>,
    route: &mut impl Mutex<T = AxisMap>,
    sampler: &mut impl Mutex<T = Sampler>,
) {
    let map = route.lock(|r| *r);
    let counts = tracker.lock(Tracker::take_counts);
    let now_ms = sampler.lock(Sampler::now_ms);
    mouse.lock(|m| m.service(map.screen(counts), now_ms));
}

/// What only the board does for a request: a new rate retimes the sampling; a save goes to
/// the `save` task (`spawn`, which saves the running profile), or is answered as failed if
/// it cannot be spawned.
pub fn board_effect<'r, M, C, T, S, R, Q>(
    effect: &Effect,
    r: &mut Resources<'r, M, C, T, S, R, Q>,
    sampler: &mut impl Mutex<T = Sampler>,
    spawn: impl FnOnce() -> bool,
) where
    M: Mutex<T = Mouse<'static, UsbBusType>>,
    C: Mutex<T = Commands>,
{
    if effect.retime {
        let fs_hz = r.commands.lock(|c| c.running().config.fs_hz);
        sampler.lock(|s| s.retime(fs_hz));
        defmt::info!("sampling retimed to {} Hz", fs_hz);
    }
    if effect.save && !spawn() {
        imu_app::control::answer_save(false, r.commands, r.mouse);
    }
}

/// Restarts a stalled sampling and tells the tracker, under one lock of both (a block cannot
/// be fed between the restart and its lost samples). Returns whether ADC data arrives.
pub fn check_stall(
    sampler: &mut impl Mutex<T = Sampler>,
    tracker: &mut impl Mutex<T = Tracker>,
) -> bool {
    sampler.lock(|s| {
        if let Outcome::Restarted(lost) = s.check_stalled() {
            tracker.lock(|t| t.restarted(lost));
            defmt::warn!("no ADC data: sampling restarted, {} samples lost", lost);
        }
        s.delivering()
    })
}

/// Logs what a DMA interrupt produced.
pub fn log_outcome(outcome: &Outcome, event: Option<&Event>) {
    if let Outcome::Restarted(lost) = outcome {
        defmt::warn!("DMA overrun: sampling restarted, {} samples lost", lost);
    }
    if let Some(e) = event {
        log_event(e);
    }
}

/// Logs a calibration outcome in ADC codes (the tracker's axes: cursor X, cursor Y,
/// vertical; `cargo lab device info` shows them in m/s^2).
pub fn log_event(event: &Event) {
    match event {
        Event::Calibrated(axes) => {
            for (name, c) in ["x", "y", "vertical"].iter().zip(axes) {
                defmt::info!(
                    "calibrated {}: bias {} LSB, noise {} LSB rms over {} samples",
                    name,
                    c.bias_q16 as f32 / 65_536.0,
                    c.noise_rms_q16 as f32 / 65_536.0,
                    c.samples
                );
            }
        }
        Event::Rejected { axis, error } => {
            defmt::warn!(
                "calibration rejected on axis {}: {}; keep still",
                axis,
                error
            )
        }
    }
}

/// A snapshot of every counter, taken under short locks and logged outside them.
pub struct Snapshot {
    /// The tracker's totals.
    pub tracker: Counters,
    /// The sampling ledger's totals.
    pub ledger: LedgerCounters,
    /// Reports accepted by the USB stack.
    pub reports: u32,
    /// Reports refused for a reason other than "busy".
    pub drops: u32,
    /// The USB link.
    pub link: imu_core::Link,
}

impl Snapshot {
    /// Takes the counters, one short lock each.
    pub fn take(
        tracker: &mut impl Mutex<T = Tracker>,
        sampler: &mut impl Mutex<T = Sampler>,
        mouse: &mut impl Mutex<T = Mouse<'static, UsbBusType>>,
    ) -> Self {
        let (reports, drops, link) = mouse.lock(|m| {
            let r = m.reports();
            (r.reporter().reports(), r.drops(), r.link())
        });
        Self {
            tracker: tracker.lock(|t| t.counters()),
            ledger: sampler.lock(|s| s.ledger().counters()),
            reports,
            drops,
            link,
        }
    }
}

/// The periodic counter log.
pub fn log_counters(s: &Snapshot) {
    defmt::info!(
        "samples {} lost {} late blocks {} restarts {} rejected windows {} reports {} drops {} usb {}",
        s.tracker.samples,
        s.tracker.lost,
        s.ledger.late_blocks,
        s.ledger.restarts,
        s.tracker.rejected_windows,
        s.reports,
        s.drops,
        s.link
    );
}

/// The idle loop's one pass, interrupts masked throughout (so nothing changes between the
/// decision and the Stop, and no handler runs on the wake clock): a Stop episode if
/// `imu_app::sleep::may_stop` allows one, else `wfi`. An episode's slept time goes to the
/// time base; one that could not restore the clocks resets the MCU.
pub fn rest(
    stop: &mut Stop,
    status: &mut impl Mutex<T = Status>,
    sampler: &mut impl Mutex<T = Sampler>,
    mouse: &mut impl Mutex<T = Mouse<'static, UsbBusType>>,
    wakeup: &mut impl Mutex<T = RemoteWakeup>,
    watchdog: &mut impl Mutex<T = IndependentWatchdog>,
) {
    cortex_m::interrupt::free(|_| {
        let now_ms = sampler.lock(Sampler::now_ms);
        let remote = mouse.lock(|m| m.device().remote_wakeup_enabled());
        let signalling = wakeup.lock(|w| w.active());
        let (key, bus) = (stop::key_down(), stop::bus_suspended());
        if !status.lock(|s| sleep::may_stop(s, now_ms, remote, signalling, key, bus)) {
            cortex_m::asm::wfi();
            return;
        }
        let episode = status.lock(|st| {
            sampler.lock(|sa| {
                watchdog.lock(|wd| {
                    let mut board = stop::Board {
                        stop,
                        sampler: sa,
                        watchdog: wd,
                    };
                    sleep::episode(&mut board, st, now_ms, remote, board::PROBE_MS)
                })
            })
        });
        sampler.lock(|s| s.slept(episode.slept_ms));
        match episode.end {
            End::Awake(Why::Scan) => defmt::warn!("suspend probe: the ADC could not be parked"),
            End::Awake(why) => defmt::debug!("awake ({}), {} probes", why, episode.probes),
            End::Reset(why) => {
                defmt::error!("woken ({}), the clocks did not come back: reset", why);
                cortex_m::peripheral::SCB::sys_reset()
            }
        }
    });
}
