//! Raw recording: the ADC's codes as sampled, queued for the configuration interface and cut
//! into stream frames (`imu_core::protocol::StreamFrame`), with every gap counted.
//!
//! # Design
//! The DMA task pushes each block (sensor order, before the axis mapping) and the samples
//! the hardware lost before it; the USB task takes one frame whenever the IN endpoint is
//! free. A frame never spans a gap: a gap (samples the hardware lost, or the queue could
//! not hold) is recorded at the position of the first sample after it, and the frame that
//! starts there carries the count, so the host sees where samples are missing, not only how
//! many.
//!
//! Bandwidth: a full-speed interrupt endpoint moves one 64-byte packet per 1 ms frame, 12
//! triples with 12-bit packing (9 for wider ADCs): 12 kHz at most, with nothing to spare; the
//! queue absorbs the responses that share the endpoint and a host that polls late.

use heapless::Deque;
use imu_core::protocol::StreamFrame;

/// Sample triples the queue holds: 21 ms at 12 kHz (1.5 KiB).
pub const QUEUE: usize = 256;
/// Gaps the queue can place exactly; more are merged into the newest (the count stays exact).
pub const GAPS: usize = 8;

/// The raw stream's state and queue.
#[derive(Clone, Debug, Default)]
pub struct Stream {
    on: bool,
    wide: bool,
    queue: Deque<[u16; 3], QUEUE>,
    /// Absolute index of the next triple to be queued, and of the queue's front.
    pushed: u64,
    popped: u64,
    /// `(index of the first triple after the gap, triples missing)`.
    gaps: Deque<(u64, u32), GAPS>,
    seq: u16,
    frames: u32,
    lost: u32,
}

impl Stream {
    /// Starts a stream for an ADC of `adc_bits` bits: the queue, the frame numbers and the
    /// counts start afresh.
    pub fn start(&mut self, adc_bits: u8) {
        *self = Self {
            on: true,
            wide: adc_bits > 12,
            ..Self::default()
        };
    }

    /// Stops the stream; returns `(frames sent, triples lost)`.
    pub fn stop(&mut self) -> (u32, u32) {
        self.on = false;
        self.queue.clear();
        self.gaps.clear();
        (self.frames, self.lost)
    }

    /// Whether a stream runs.
    pub fn on(&self) -> bool {
        self.on
    }

    /// Frames sent and triples lost so far.
    pub fn totals(&self) -> (u32, u32) {
        (self.frames, self.lost)
    }

    /// `lost` triples are missing before the next one pushed (a sampling restart, or the
    /// hardware's late block). Nothing happens while the stream is off.
    pub fn lost(&mut self, lost: u32) {
        if !self.on || lost == 0 {
            return;
        }
        self.lost = self.lost.saturating_add(lost);
        let at = self.pushed;
        let full = self.gaps.is_full();
        match self.gaps.back_mut() {
            Some((i, n)) if *i == at || full => *n = n.saturating_add(lost),
            _ => {
                let _ = self.gaps.push_back((at, lost));
            }
        }
    }

    /// A block of `[x, y, z]` codes, after `lost_before` triples the hardware lost. Triples
    /// the queue cannot hold are counted as lost. Nothing happens while the stream is off.
    pub fn push(&mut self, block: &[[u16; 3]], lost_before: u32) {
        if !self.on {
            return;
        }
        self.lost(lost_before);
        for (i, t) in block.iter().enumerate() {
            if self.queue.push_back(*t).is_err() {
                self.lost((block.len() - i) as u32);
                return;
            }
            self.pushed += 1;
        }
    }

    /// The next frame (up to a frame's capacity, never across a gap), if any samples wait.
    /// It stays queued until [`Self::sent`].
    pub fn frame(&self) -> Option<StreamFrame> {
        if !self.on || self.queue.is_empty() {
            return None;
        }
        let (lost, limit) = match (self.gaps.front(), self.gaps.get(1)) {
            (Some(&(at, n)), next) if at == self.popped => (n, next.map(|g| g.0)),
            (Some(&(at, _)), _) => (0, Some(at)),
            (None, _) => (0, None),
        };
        let room = limit.map_or(usize::MAX, |l| (l - self.popped) as usize);
        let n = StreamFrame::capacity(if self.wide { 16 } else { 12 })
            .min(self.queue.len())
            .min(room);
        Some(StreamFrame {
            seq: self.seq,
            lost: u16::try_from(lost).unwrap_or(u16::MAX),
            triples: self.queue.iter().take(n).copied().collect(),
            wide: self.wide,
        })
    }

    /// The frame from [`Self::frame`] was accepted by the USB stack: its samples leave the
    /// queue.
    pub fn sent(&mut self, frame: &StreamFrame) {
        if self.gaps.front().is_some_and(|g| g.0 == self.popped) {
            self.gaps.pop_front();
        }
        for _ in 0..frame.triples.len() {
            self.queue.pop_front();
        }
        self.popped += frame.triples.len() as u64;
        self.seq = self.seq.wrapping_add(1);
        self.frames = self.frames.wrapping_add(1);
    }
}
