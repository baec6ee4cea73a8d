//! The sample path's glue between the sampling hardware and the core: what a delivered DMA
//! block means, and how an unfilled buffer is recognised.
//!
//! # Design
//! The board hands over whole blocks with the ledger's verdict ([`Delivery`]). A late block
//! (one or more blocks overwritten by the double-buffered DMA) is preceded by the lost
//! samples, held by the tracker so that its clock stays the hardware's; a restart (the
//! sampling died) is not held (`Tracker::restarted`). While USB is suspended blocks are
//! motion probes for remote wake-up, not tracking data.
//!
//! A buffer handed to the DMA has its last word set to [`UNFILLED`], a value a 12-bit
//! right-aligned conversion never produces; the DMA fills buffers in order, so a buffer that
//! comes back with it is one the DMA never wrote (a race of the buffer swap) and is dropped.

use imu_core::profile::AxisMap;
use imu_core::{Delivery, Event, Tracker};
use rtic_core::Mutex;

use crate::device::{block_len, FS_MAX_HZ};
use crate::status::Status;
use crate::stream::Stream;

/// The longest block the device produces [triples]: 1 ms at [`FS_MAX_HZ`].
pub const BLOCK_MAX: usize = block_len(FS_MAX_HZ);

/// The marker in the last word of a buffer the DMA has not filled yet (no 12-bit code).
pub const UNFILLED: u16 = u16::MAX;

/// Marks `buffer` as not yet filled, before it goes to the DMA.
pub fn mark_unfilled(buffer: &mut [u16]) {
    if let Some(last) = buffer.last_mut() {
        *last = UNFILLED;
    }
}

/// Whether the DMA has written `buffer` to its end (see [`mark_unfilled`]).
pub fn filled(buffer: &[u16]) -> bool {
    buffer.last().is_some_and(|&c| c != UNFILLED)
}

/// A block of `[x, y, z]` codes arrived with the ledger's `delivery` at `now_ms` [ms]: a
/// probe while suspended, else lost samples (if late) and the block go to the stream (as
/// sampled) and to the tracker (routed by `map`). Returns the calibration outcome if a
/// calibration window ended.
pub fn on_block(
    block: &[[u16; 3]],
    delivery: Delivery,
    now_ms: u32,
    map: AxisMap,
    tracker: &mut impl Mutex<T = Tracker>,
    status: &mut impl Mutex<T = Status>,
    stream: &mut impl Mutex<T = Stream>,
) -> Option<Event> {
    if status.lock(|s| {
        if let (true, Some(&last)) = (s.suspended(), block.last()) {
            s.probe(last);
        }
        s.suspended()
    }) {
        return None;
    }
    let lost = match delivery {
        Delivery::Late(lost) => Some(lost),
        Delivery::OnTime => None,
    };
    stream.lock(|s| s.push(block, lost.unwrap_or(0)));
    let event = tracker.lock(|t| {
        if let Some(lost) = lost {
            t.lost(lost);
        }
        let mut event = None;
        let mut routed = [[0u16; 3]; BLOCK_MAX];
        for piece in block.chunks(BLOCK_MAX) {
            for (r, c) in routed.iter_mut().zip(piece) {
                *r = map.route(*c);
            }
            event = t.feed(&routed[..piece.len()]).or(event);
        }
        event
    });
    if let Some(e) = event {
        status.lock(|s| s.record(e, now_ms));
    }
    event
}
