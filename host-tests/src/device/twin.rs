//! `cargo lab twin`: the firmware's application (`imu_app`) and the core, unchanged, run on
//! the host in real time as a USB/IP device ([`crate::device::usbip`]), fed by a scene or a
//! recording instead of the ADC.
//!
//! # Design
//! One loop plays the RTIC tasks in the firmware's order, once a millisecond on a running
//! deadline: the DMA task (one block of `imu_app::device::block_len(fs)` samples through
//! `imu_app::sampling::on_block`), the USB task (`Mouse::service` with the tracker's fresh
//! counts), the housekeeping tick (`Housekeeping::tick` over `rtic_core::Exclusive`
//! resources). Between ticks the USB stack is polled every 250 us, as the OTG interrupt
//! would be. KEY follows the scene's finger, or `press` / `release` lines on standard input.
//! The scene starts when a host has configured the device; after it ends the twin keeps
//! serving until every count is delivered (or the drain time passes), then reports.
//!
//! The configuration interface runs as on the board: requests through
//! `imu_app::control::serve`, the raw stream through `control::push_stream`, the profile in
//! a [`FileFlash`] (two 16 KiB sectors, kept in a file if one is given, so a restarted twin
//! finds what was saved). The twin runs the profile's rate, `block_len(fs)` samples a
//! millisecond, and plays the scene in its own time whatever that rate ([`Playhead`]): each
//! device sample takes the scene's sample at its time (the latest at or before it), so a
//! device sampling faster repeats samples and one sampling slower skips them; a new rate
//! changes the block length from the next millisecond (the board retimes its ADC trigger).
//!
//! The sampling's decisions are the board's (`imu_app::sampler` over a stand-in timer):
//! suspend drops to the probe's block of three scans every 60 ms, resume and stalls as on
//! the board. USB/IP has no suspend: `suspend` / `resume` lines idle and wake the bus (no
//! traffic while suspended), and a remote wake-up the device signals resumes it as a host
//! would; the summary gives each suspend, its cause of wake-up (`key`, or the scene's first
//! sample past the probe's threshold) and the wake-up's time.
//!
//! What the twin cannot show: USB electrical behaviour (suspend current, resume
//! signalling), the ADC, DMA and timers (the board layer), timing under interrupt load.

use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use embedded_hal::digital::{ErrorType, InputPin, OutputPin};
use imu_app::commands::Commands;
use imu_app::control::{self, Resources};
use imu_app::sampler::{Acquisition, DmaEvent, Outcome, Sampling};
use imu_app::store::Store;
use imu_app::stream::Stream;
use imu_app::{device, identity, sampling::on_block, Housekeeping, Mouse, Status};
use imu_core::protocol::Source;
use imu_core::{hid::screen_motion, Link, PowerAction, Tracker};
use rtic_core::Exclusive;
use serde::Serialize;
use usb_device::bus::UsbBusAllocator;

use crate::device::flash::{FileFlash, CAPACITY};
use crate::device::usbip::{Listing, Traffic, UsbIpBus};

/// The sample clock the twin's rates must divide [Hz]: the board's timer clock.
const CLOCK_HZ: u32 = 96_000_000;
/// The suspend probe's rate [Hz] and the stall limit [blocks], as the board's
/// (`firmware/src/board.rs`).
const PROBE_HZ: u32 = 50;
const STALL_BLOCKS: u32 = 5;
/// Scans in a probe block (the board's blocks at the probe rate: 3 triples).
const PROBE_SCANS: usize = 3;

/// [`Operator::bus`]: suspend the bus.
pub const SUSPEND: u8 = 1;
/// [`Operator::bus`]: resume the bus.
pub const RESUME: u8 = 2;

/// What the operator does from standard input: KEY, and the bus's suspend and resume.
#[derive(Clone, Debug, Default)]
pub struct Operator {
    /// KEY held.
    pub key: Arc<AtomicBool>,
    /// A bus request not yet carried out: 0, [`SUSPEND`] or [`RESUME`].
    pub bus: Arc<AtomicU8>,
}

/// The twin's sampling hardware for `imu_app::sampler`: a timer counting the twin's
/// milliseconds at the board's clock, and the trigger's period (the running rate's or the
/// probe's) that decides which blocks the scene delivers.
struct TwinBoard {
    now: u32,
    arr: u32,
}

impl Acquisition for TwinBoard {
    fn now(&self) -> u32 {
        self.now
    }
    fn set_period(&mut self, arr: u32) {
        self.arr = arr;
    }
    fn stop(&mut self) {}
    fn run(&mut self) {}
    fn rearm(&mut self, _words: usize) {}
}

/// The device's inputs: ADC codes and the finger on KEY, sample by sample.
#[derive(Clone, Debug)]
pub struct Input {
    /// Sampling rate [Hz] (must be accepted by `imu_app::device::rate_accepted`).
    pub fs_hz: u32,
    /// `[x, y, z]` codes.
    pub codes: Vec<[u16; 3]>,
    /// Whether the finger holds KEY at each sample (empty: never).
    pub held: Vec<bool>,
}

/// Where the scene stands in device samples: device sample `n` since the last change of rate
/// plays the scene's sample `base + n * fs_scene / fs_device` (rounded down), so the scene
/// keeps its own time at any device rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Playhead {
    scene_hz: u64,
    device_hz: u64,
    base: usize,
    n: u64,
}

impl Playhead {
    /// At the scene's start, a scene at `scene_hz` [Hz] on a device at `device_hz` [Hz]
    /// (both > 0).
    pub const fn new(scene_hz: u32, device_hz: u32) -> Self {
        Self {
            scene_hz: scene_hz as u64,
            device_hz: device_hz as u64,
            base: 0,
            n: 0,
        }
    }

    /// The scene sample that the device's `j`-th sample from now plays.
    pub fn index(&self, j: usize) -> usize {
        self.base + ((self.n + j as u64) * self.scene_hz / self.device_hz.max(1)) as usize
    }

    /// The scene samples played so far.
    pub fn played(&self) -> usize {
        self.index(0)
    }

    /// The device samples played since the start or the last [`Self::retime`].
    pub const fn device_samples(&self) -> u64 {
        self.n
    }

    /// `samples` device samples played.
    pub fn advance(&mut self, samples: usize) {
        self.n += samples as u64;
    }

    /// The device samples at `device_hz` [Hz] from now on.
    pub fn retime(&mut self, device_hz: u32) {
        self.base = self.played();
        self.n = 0;
        self.device_hz = u64::from(device_hz);
    }
}

/// How the twin runs.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// The USB/IP address to listen on (the protocol's port is 3240).
    pub addr: SocketAddr,
    /// How long to wait for a host to configure the device [s].
    pub wait_host_s: f64,
    /// How long to keep serving after the scene so that owed counts reach the host [s].
    pub drain_s: f64,
    /// The USB serial number string (a board's is its MCU's unique ID).
    pub serial: &'static str,
    /// Play the input again from its start each time it ends, until the process is stopped
    /// (a session longer than the scene); the summary is then never printed.
    pub repeat: bool,
}

/// Why the twin could not run.
#[derive(Debug, thiserror::Error)]
pub enum TwinError {
    /// The USB/IP port could not be bound.
    #[error("cannot listen on {addr}: {}", listen_words(.source))]
    Listen {
        /// The address.
        addr: SocketAddr,
        /// The socket error.
        source: std::io::Error,
    },
    /// The sampling rate is not one the device accepts.
    #[error("fs {0} Hz: the device accepts 100..=20000 Hz dividing 96 MHz")]
    Rate(u32),
    /// The device could not be built (a configuration error).
    #[error("device: {0}")]
    Device(String),
    /// No host configured the device in time.
    #[error("no USB/IP host configured the device within {0} s")]
    NoHost(f64),
    /// The store's range does not fit the flash (a defect of the twin).
    #[error("store: {0}")]
    Store(String),
}

/// What the twin did, for the host-side check.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Sampling rate [Hz].
    pub fs_hz: u32,
    /// Scene length played, in the scene's own time [s].
    pub scene_s: f64,
    /// Counts the tracker produced, `[x, y]` on screen (right, down).
    pub produced: [i64; 2],
    /// Counts in reports the host took (their IN transfers completed).
    pub sent: [i64; 2],
    /// Counts dropped while the host was not listening, or lost in the endpoint at a reset.
    pub discarded: [i64; 2],
    /// Counts still owed at the end.
    pub undelivered: [i64; 2],
    /// Counts in the report the USB stack took that the host had not taken at the end.
    pub in_flight: [i64; 2],
    /// Reports the host took.
    pub reports: u32,
    /// Most reports in any 1 s of the run [1/s].
    pub peak_report_rate_hz: u32,
    /// USB/IP traffic.
    pub imports: u32,
    /// URBs completed.
    pub urbs: u64,
    /// Control requests answered with a stall.
    pub stalls: u32,
    /// Interrupt IN packets delivered.
    pub in_packets: u64,
    /// Housekeeping ticks that started more than 1 ms late (the host's scheduler).
    pub late_ticks: u32,
    /// Whether every produced count is sent, discarded or owed.
    pub accounted: bool,
    /// Where the profile came from at start-up (`Defaults`, `Stored`, `Corrupt`, `Invalid`).
    pub profile_source: String,
    /// The sampling rate at the end (a host may have changed it) [Hz].
    pub final_fs_hz: u32,
    /// Raw stream frames sent.
    pub stream_frames: u32,
    /// When the bus was suspended and resumed, and when the device signalled remote wake-up
    /// [ms of the scene].
    pub suspends_ms: Vec<u32>,
    /// See [`Self::suspends_ms`].
    pub resumes_ms: Vec<u32>,
    /// See [`Self::suspends_ms`].
    pub wakes_ms: Vec<u32>,
    /// What asked for each wake-up while suspended, and when [ms]: `key` (a press) or
    /// `motion` (the first probe block past the wake threshold).
    pub causes: Vec<(u32, &'static str)>,
    /// Sampling restarts (stalls or overruns) while suspended.
    pub restarts_suspended: u32,
    /// Mouse reports counted in `sent` whose delivery USB/IP cannot confirm: the last one
    /// before each disconnect, `[x, y]` (the host may have lost it with the connection).
    pub unconfirmed: Vec<[i64; 2]>,
}

/// KEY of the twin: the scene's finger, or the operator's.
#[derive(Clone)]
struct Key {
    scene: Arc<AtomicBool>,
    operator: Arc<AtomicBool>,
}

impl Key {
    /// Whether the scene's finger or the operator holds KEY.
    fn held(&self) -> bool {
        self.scene.load(Ordering::Relaxed) || self.operator.load(Ordering::Relaxed)
    }
}

impl ErrorType for Key {
    type Error = core::convert::Infallible;
}

impl InputPin for Key {
    fn is_high(&mut self) -> Result<bool, Self::Error> {
        Ok(self.held())
    }
    fn is_low(&mut self) -> Result<bool, Self::Error> {
        self.is_high().map(|h| !h)
    }
}

/// The LED of the twin: its state is kept, nothing shows it.
#[derive(Default)]
struct Led(bool);

impl ErrorType for Led {
    type Error = core::convert::Infallible;
}

impl OutputPin for Led {
    fn set_low(&mut self) -> Result<(), Self::Error> {
        self.0 = false;
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Self::Error> {
        self.0 = true;
        Ok(())
    }
}

fn listing() -> Listing {
    Listing {
        vid_pid: identity::VID_PID,
        release_bcd: identity::RELEASE_BCD,
        interface: (3, 0, 2),
    }
}

/// Polls the USB stack until `deadline`, every 250 us, at the twin's `ms` [ms], and keeps
/// the raw stream moving.
fn serve_until(mouse: &mut Mouse<'_, UsbIpBus>, deadline: Instant, ms: u32, stream: &mut Stream) {
    loop {
        mouse.service([0; 3], ms);
        control::push_stream(&mut Exclusive(&mut *mouse), &mut Exclusive(&mut *stream));
        let now = Instant::now();
        if now >= deadline {
            return;
        }
        std::thread::sleep((deadline - now).min(Duration::from_micros(250)));
    }
}

/// Runs the twin on `input` with its profile store on `flash`; `operator` is KEY as pressed
/// from standard input.
///
/// # Errors
/// [`TwinError`]: the port, the rate, the device, or no host.
pub fn run(
    input: &Input,
    s: Settings,
    operator: Operator,
    flash: FileFlash,
) -> Result<Summary, TwinError> {
    if !device::rate_accepted(input.fs_hz, CLOCK_HZ) {
        return Err(TwinError::Rate(input.fs_hz));
    }
    let mut store =
        Store::new(flash, 0..CAPACITY as u32).map_err(|e| TwinError::Store(format!("{e:?}")))?;
    let loaded = device::runnable(store.load(), CLOCK_HZ);
    if !matches!(loaded.source, Source::Stored | Source::Defaults) {
        eprintln!(
            "twin: the stored profile was not used ({:?}{}); defaults",
            loaded.source,
            loaded.invalid.map(|k| format!(", {k}")).unwrap_or_default()
        );
    }
    let bus = UsbIpBus::new(s.addr, listing()).map_err(|source| TwinError::Listen {
        addr: s.addr,
        source,
    })?;
    eprintln!(
        "twin: USB/IP device on {} (bus id 1-1); waiting for a host",
        s.addr
    );
    let monitor = bus.monitor();
    let bus = UsbBusAllocator::new(bus);
    let mut mouse = Mouse::new(&bus, s.serial).map_err(|e| TwinError::Device(format!("{e:?}")))?;
    let config = loaded.profile.config;
    let mut tracker = Tracker::new(&config).map_err(|e| TwinError::Device(e.to_string()))?;
    let mut status = Status::new(device::wake_motion_lsb(config.m_s2_per_lsb));
    let mut commands = Commands::new(loaded.profile, loaded.source, loaded.invalid, CLOCK_HZ);
    let (mut stream, mut route) = (Stream::default(), loaded.profile.map);
    let scene_key = Arc::new(AtomicBool::new(false));
    let key = Key {
        scene: scene_key.clone(),
        operator: operator.key.clone(),
    };
    let key_seen = key.clone();
    let mut hk = Housekeeping::new(key, false, Led::default(), false, device::TIMING, 0);

    let waited = Instant::now();
    while mouse.reports().link() != Link::Configured {
        if waited.elapsed().as_secs_f64() > s.wait_host_s {
            return Err(TwinError::NoHost(s.wait_host_s));
        }
        serve_until(
            &mut mouse,
            Instant::now() + Duration::from_millis(1),
            0,
            &mut stream,
        );
    }
    eprintln!("twin: a host configured the device; playing the scene");

    let probe_arr = CLOCK_HZ / PROBE_HZ - 1;
    let new_sampling = |fs_hz| Sampling::new(CLOCK_HZ, fs_hz, probe_arr, STALL_BLOCKS);
    let mut sampling = new_sampling(config.fs_hz).map_err(|e| TwinError::Device(e.to_string()))?;
    let mut board = TwinBoard { now: 0, arr: 0 };
    sampling.start(&mut board);
    let mut power = PowerLog::default();
    let mut block = device::block_len(config.fs_hz);
    let tick = Duration::from_millis(1);
    let (mut produced, mut per_ms) = ([0i64; 2], Vec::new());
    let mut late_ticks = 0u32;
    let mut next = Instant::now();
    let mut drain_left = (s.drain_s * 1000.0) as u32;
    let mut ms = 0u32;
    let mut head = Playhead::new(input.fs_hz, config.fs_hz);
    // The millisecond the trigger timer started at the running rate.
    let mut timed_from = 0u32;
    let mut chunk_buf: Vec<[u16; 3]> = Vec::with_capacity(device::block_len(device::FS_MAX_HZ));
    loop {
        board.now = ms.wrapping_mul(CLOCK_HZ / 1000);
        match operator.bus.swap(0, Ordering::Relaxed) {
            SUSPEND => monitor.request_suspend(true),
            RESUME => monitor.request_suspend(false),
            _ => {}
        }
        if s.repeat && head.index(block - 1) >= input.codes.len() {
            // From the start again, at the running rate, the timer counted afresh from here
            // (less than a block of phase: the scene's samples are not the device's anyway).
            head = Playhead::new(input.fs_hz, commands.running().config.fs_hz);
            timed_from = ms;
        }
        // The blocks the trigger timer has made by the end of this millisecond: one a
        // millisecond at multiples of 1 kHz, one every 10 ms at 100 Hz, 1 or 2 at 1500 Hz.
        let made = (u64::from(ms.saturating_sub(timed_from)) + 1)
            * u64::from(commands.running().config.fs_hz)
            / 1000
            / block as u64;
        let due = made.saturating_sub(head.device_samples() / block as u64);
        if head.index(block - 1) < input.codes.len() {
            for first in (0..due).map(|i| i == 0) {
                if head.index(block - 1) >= input.codes.len() {
                    break;
                }
                // The block's own completion time on the sample clock, as the ledger reads it.
                let k = head.device_samples() / block as u64 + 1;
                let fs = u64::from(commands.running().config.fs_hz).max(1);
                board.now = (u64::from(timed_from) * u64::from(CLOCK_HZ / 1000)
                    + k * block as u64 * u64::from(CLOCK_HZ) / fs)
                    as u32;
                let played = head.played();
                scene_key.store(
                    input.held.get(played).copied().unwrap_or(false),
                    Ordering::Relaxed,
                );
                chunk_buf.clear();
                chunk_buf.extend((0..block).map(|j| input.codes[head.index(j)]));
                // Running: a block a millisecond. Suspended: the probe's block of three scans
                // 20 ms apart, every 60 ms, the last of them now, from the scene as it goes on.
                let probing = board.arr == probe_arr;
                let step = (input.fs_hz / PROBE_HZ) as usize;
                let due = if probing {
                    first && ms.is_multiple_of(PROBE_SCANS as u32 * 1000 / PROBE_HZ)
                } else {
                    true
                };
                let probe: [[u16; 3]; PROBE_SCANS] = core::array::from_fn(|k| {
                    let back = (PROBE_SCANS - 1 - k) * step;
                    input.codes[head.index(block - 1).saturating_sub(back)]
                });
                let chunk: &[[u16; 3]] = if probing { &probe } else { &chunk_buf };
                if due {
                    if let Outcome::Block(delivery) = sampling.on_dma(&mut board, DmaEvent::Full) {
                        power.probed(&status, chunk);
                        on_block(
                            chunk,
                            delivery,
                            ms,
                            route,
                            &mut Exclusive(&mut tracker),
                            &mut Exclusive(&mut status),
                            &mut Exclusive(&mut stream),
                        );
                    }
                }
                // The motion's onset as the scene has it: its first sample, at the full rate,
                // past the wake threshold from the suspend's first probe.
                if power.moved(&status, &chunk_buf) {
                    power.cause(ms, "motion");
                }
                head.advance(block);
            }
            // The rest of the millisecond runs at its end, after every block it made.
            board.now = (ms + 1).wrapping_mul(CLOCK_HZ / 1000);
        } else {
            scene_key.store(false, Ordering::Relaxed);
            let owed = mouse.reports().pending() || monitor.in_flight();
            if drain_left == 0 || (!owed && mouse.reports().link() == Link::Configured) {
                eprintln!(
                    "twin: the scene has played ({:.1} s); the device goes away (for a longer \
                     session: --repeat, or --scene rest --seconds S)",
                    head.played() as f64 / f64::from(input.fs_hz)
                );
                break;
            }
            drain_left -= 1;
        }
        let counts = route.screen(tracker.take_counts());
        let (dx, dy) = screen_motion(counts);
        produced[0] += i64::from(dx);
        produced[1] += i64::from(dy);
        let before = mouse.reports().reporter().reports();
        mouse.service(counts, ms);
        let mut r = Resources {
            mouse: &mut Exclusive(&mut mouse),
            commands: &mut Exclusive(&mut commands),
            tracker: &mut Exclusive(&mut tracker),
            status: &mut Exclusive(&mut status),
            route: &mut Exclusive(&mut route),
            stream: &mut Exclusive(&mut stream),
        };
        let effect = control::serve(&mut r, || 0);
        if effect.retime {
            let fs_hz = commands.running().config.fs_hz;
            block = device::block_len(fs_hz);
            head.retime(fs_hz);
            timed_from = ms + 1;
            sampling = new_sampling(fs_hz).map_err(|e| TwinError::Device(e.to_string()))?;
            sampling.start(&mut board);
        }
        if effect.save {
            let ok = store.save(commands.running()).is_ok();
            control::answer_save(
                ok,
                &mut Exclusive(&mut commands),
                &mut Exclusive(&mut mouse),
            );
        }
        control::push_stream(&mut Exclusive(&mut mouse), &mut Exclusive(&mut stream));
        if let Outcome::Restarted(lost) = sampling.check_stalled(&mut board) {
            tracker.restarted(lost);
            power.restarts += u32::from(status.suspended());
        }
        let pressed_before = key_seen.held();
        let done = hk.tick(
            ms,
            sampling.delivering(),
            &mut Exclusive(&mut tracker),
            &mut Exclusive(&mut status),
            &mut Exclusive(&mut mouse),
        );
        if status.suspended() && pressed_before && !power.key_was {
            power.cause(ms, "key");
        }
        power.key_was = pressed_before;
        match done.power {
            PowerAction::Suspend => {
                sampling.suspend(&mut board);
                power.suspends.push(ms);
            }
            PowerAction::Resume => {
                sampling.resume(&mut board);
                power.resumes.push(ms);
            }
            PowerAction::Wake => {
                // A host resumes the bus on the device's remote wake-up signalling.
                power.wakes.push(ms);
                monitor.request_suspend(false);
            }
            PowerAction::None => {}
        }
        next += tick;
        if Instant::now() > next + tick {
            late_ticks += 1;
        }
        serve_until(&mut mouse, next, ms, &mut stream);
        per_ms.push(mouse.reports().reporter().reports().wrapping_sub(before));
        ms += 1;
    }
    let end = End {
        power,
        played: head.played(),
        source: loaded.source,
        final_fs_hz: commands.running().config.fs_hz,
        stream_frames: stream.totals().0,
        unconfirmed: monitor.unconfirmed(),
    };
    Ok(summary(
        input,
        &mouse,
        monitor.traffic(),
        produced,
        &per_ms,
        late_ticks,
        &end,
    ))
}

/// Suspend, resume and remote wake-up as they happened [ms of the scene].
#[derive(Default)]
struct PowerLog {
    suspends: Vec<u32>,
    resumes: Vec<u32>,
    wakes: Vec<u32>,
    causes: Vec<(u32, &'static str)>,
    restarts: u32,
    key_was: bool,
    reference: Option<[u16; 3]>,
}

impl PowerLog {
    /// A wake-up's cause `kind` at `ms`: the first of a suspend not yet woken.
    fn cause(&mut self, ms: u32, kind: &'static str) {
        let waiting = self.wakes.len() < self.suspends.len();
        if waiting && self.causes.len() == self.wakes.len() {
            self.causes.push((ms, kind));
        }
    }

    /// A probe block while suspended: the first of a suspend is the reference the device
    /// compares with (its last scan, as `imu_core::Power::probe` takes it).
    fn probed(&mut self, status: &Status, chunk: &[[u16; 3]]) {
        if !status.suspended() {
            self.reference = None;
        } else if self.reference.is_none() {
            self.reference = chunk.last().copied();
        }
    }

    /// Whether any of `samples` (the scene at the full rate, while suspended) is past the
    /// wake threshold from the reference: the motion a probe can next see.
    fn moved(&self, status: &Status, samples: &[[u16; 3]]) -> bool {
        let threshold = status.wake_motion_lsb();
        match (status.suspended(), self.reference) {
            (true, Some(r)) => samples
                .iter()
                .any(|c| r.iter().zip(c).any(|(a, b)| a.abs_diff(*b) > threshold)),
            _ => false,
        }
    }
}

/// How the run ended, beyond the mouse's accounts.
struct End {
    /// Suspends, resumes and wake-ups.
    power: PowerLog,
    /// Scene samples played.
    played: usize,
    /// Where the profile came from at start-up.
    source: Source,
    /// The sampling rate at the end [Hz].
    final_fs_hz: u32,
    /// Raw stream frames sent.
    stream_frames: u32,
    /// The bus's unconfirmed IN packets (`UsbIpBus`'s monitor).
    unconfirmed: Vec<(u8, Vec<u8>)>,
}

fn summary(
    input: &Input,
    mouse: &Mouse<'_, UsbIpBus>,
    t: Traffic,
    produced: [i64; 2],
    per_ms: &[u32],
    late_ticks: u32,
    end: &End,
) -> Summary {
    let r = mouse.reports().reporter();
    let (sent, discarded, owed) = (r.sent_total(), r.discarded(), r.undelivered());
    let flight = r.in_flight();
    let peak = per_ms
        .windows(1000.min(per_ms.len()).max(1))
        .map(|w| w.iter().sum::<u32>())
        .max()
        .unwrap_or(0);
    Summary {
        fs_hz: input.fs_hz,
        scene_s: end.played as f64 / f64::from(input.fs_hz),
        produced,
        sent: [sent.0, sent.1],
        discarded: [discarded.0, discarded.1],
        undelivered: [owed.0, owed.1],
        in_flight: [flight.0, flight.1],
        reports: mouse.reports().reporter().reports(),
        peak_report_rate_hz: peak,
        imports: t.imports,
        urbs: t.urbs,
        stalls: t.stalls,
        in_packets: t.in_packets,
        late_ticks,
        accounted: sent.0 + discarded.0 + owed.0 + flight.0 == produced[0]
            && sent.1 + discarded.1 + owed.1 + flight.1 == produced[1],
        profile_source: match end.source {
            Source::Defaults => "defaults",
            Source::Stored => "stored",
            Source::Corrupt => "defaults (the store was unreadable)",
            Source::Invalid => "defaults (the stored profile no longer validates)",
            Source::Changed => "changed",
        }
        .into(),
        final_fs_hz: end.final_fs_hz,
        stream_frames: end.stream_frames,
        suspends_ms: end.power.suspends.clone(),
        resumes_ms: end.power.resumes.clone(),
        wakes_ms: end.power.wakes.clone(),
        causes: end.power.causes.clone(),
        restarts_suspended: end.power.restarts,
        unconfirmed: end
            .unconfirmed
            .iter()
            .filter(|(ep, p)| *ep == imu_app::mouse::MOUSE_EP_IN & 0x7F && p.len() >= 3)
            .map(|(_, p)| [i64::from(p[1] as i8), i64::from(p[2] as i8)])
            .collect(),
    }
}

/// Why a port could not be bound, in words a user can act on (the OS's own text otherwise).
fn listen_words(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::AddrInUse => "the port is in use (is a twin running already? stop it, or give \
                         --addr another port)"
            .into(),
        K::AddrNotAvailable => "this computer has no such address (127.0.0.1 serves this \
                                computer, 0.0.0.0 every network)"
            .into(),
        K::PermissionDenied => {
            "permission denied (ports below 1024 need root; 3240 does not)".into()
        }
        _ => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::Playhead;

    #[test]
    fn the_scene_keeps_its_own_time_at_any_device_rate() {
        // Same rate: sample for sample.
        let mut h = Playhead::new(3000, 3000);
        assert_eq!((h.index(0), h.index(2)), (0, 2));
        h.advance(3);
        assert_eq!(h.played(), 3);
        // A device twice as fast repeats each sample; after 1 s of it, 1 s of scene.
        let mut h = Playhead::new(3000, 6000);
        assert_eq!((0..4).map(|j| h.index(j)).collect::<Vec<_>>(), [0, 0, 1, 1]);
        h.advance(6000);
        assert_eq!(h.played(), 3000);
        // Retimed to a slower rate mid-scene: from where it stood, skipping samples.
        h.retime(1000);
        assert_eq!((h.index(0), h.index(1)), (3000, 3003));
        h.advance(1000);
        assert_eq!(h.played(), 6000);
    }
}
