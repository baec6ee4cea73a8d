//! The raw stream's queue and frames: samples in order, frames full, every gap counted where
//! it is, nothing while off.

use imu_app::stream::{Stream, GAPS, QUEUE};
use imu_core::protocol::{StreamFrame, STREAM_TRIPLES_PACKED, STREAM_TRIPLES_WIDE};

fn t(i: u16) -> [u16; 3] {
    [i, i + 1000, i + 2000]
}

/// Drains the stream: every frame sent, as `(lost, first triple's index, length)`.
fn drain(s: &mut Stream) -> Vec<(u16, u16, usize)> {
    let mut out = Vec::new();
    while let Some(f) = s.frame() {
        out.push((f.lost, f.triples[0][0], f.triples.len()));
        s.sent(&f);
    }
    out
}

#[test]
fn nothing_is_queued_while_off() {
    let mut s = Stream::default();
    s.push(&[t(0); 5], 3);
    s.lost(4);
    assert!(!s.on());
    assert_eq!(s.frame(), None);
    assert_eq!(s.totals(), (0, 0));
}

#[test]
fn frames_are_full_in_order_and_numbered() {
    let mut s = Stream::default();
    s.start(12);
    let block: Vec<[u16; 3]> = (0..30).map(t).collect();
    s.push(&block, 0);
    let mut seen = Vec::new();
    let mut seqs = Vec::new();
    while let Some(f) = s.frame() {
        assert_eq!(f.lost, 0);
        assert!(!f.wide);
        seqs.push(f.seq);
        seen.extend(f.triples.iter().copied());
        s.sent(&f);
    }
    assert_eq!(seen, block);
    assert_eq!(seqs, [0, 1, 2]);
    assert_eq!(s.totals(), (3, 0));
    // An unsent frame stays queued.
    s.push(&[t(7)], 0);
    let f = s.frame().expect("one");
    assert_eq!(s.frame(), Some(f));
}

#[test]
fn wide_adcs_get_wide_frames() {
    let mut s = Stream::default();
    s.start(16);
    s.push(&[[65_535, 0, 4096]; 20], 0);
    let f = s.frame().expect("frame");
    assert!(f.wide);
    assert_eq!(f.triples.len(), STREAM_TRIPLES_WIDE);
    assert_eq!(StreamFrame::decode(&f.encode()).expect("decodes"), f);
}

#[test]
fn a_gap_starts_a_frame_and_carries_its_count() {
    let mut s = Stream::default();
    s.start(12);
    s.push(&(0..5).map(t).collect::<Vec<_>>(), 0);
    s.push(&(5..8).map(t).collect::<Vec<_>>(), 6);
    s.lost(2);
    s.lost(1);
    s.push(&(8..30).map(t).collect::<Vec<_>>(), 0);
    assert_eq!(
        drain(&mut s),
        [(0, 0, 5), (6, 5, 3), (3, 8, 12), (0, 20, 10)]
    );
    assert_eq!(s.totals(), (4, 9));
    assert_eq!(s.stop(), (4, 9));
    assert!(!s.on());
}

#[test]
fn a_full_queue_counts_what_it_cannot_hold() {
    let mut s = Stream::default();
    s.start(12);
    let block: Vec<[u16; 3]> = (0..(QUEUE as u16 + 10)).map(t).collect();
    s.push(&block, 0);
    // Full: this one is lost too.
    s.push(&[t(8000)], 0);
    // One frame out makes room.
    let first = s.frame().expect("frame");
    s.sent(&first);
    s.push(&[t(9000)], 0);
    let mut frames = vec![(first.lost, first.triples[0][0], first.triples.len())];
    frames.extend(drain(&mut s));
    let carried: usize = frames.iter().map(|f| f.2).sum();
    assert_eq!(carried, QUEUE + 1);
    // The gap sits before the one triple pushed after the overflow.
    assert_eq!(*frames.last().expect("frames"), (11, 9000, 1));
    assert_eq!(s.totals().1, 11);
    assert!(frames[..frames.len() - 1]
        .iter()
        .all(|f| f.0 == 0 && f.2 <= STREAM_TRIPLES_PACKED));
}

#[test]
fn more_gaps_than_it_can_place_are_merged_and_the_count_stays_exact() {
    let mut s = Stream::default();
    s.start(12);
    for i in 0..(GAPS as u16 + 4) {
        s.push(&[t(i)], 1);
    }
    let frames = drain(&mut s);
    let lost: u32 = frames.iter().map(|f| u32::from(f.0)).sum();
    assert_eq!(lost, GAPS as u32 + 4);
    assert_eq!(s.totals().1, GAPS as u32 + 4);
    assert_eq!(frames.iter().map(|f| f.2).sum::<usize>(), GAPS + 4);
}

#[test]
fn a_gap_beyond_sixteen_bits_saturates_in_the_frame_not_in_the_total() {
    let mut s = Stream::default();
    s.start(12);
    s.push(&[t(1)], 100_000);
    assert_eq!(s.frame().expect("frame").lost, u16::MAX);
    assert_eq!(s.totals().1, 100_000);
}

#[test]
fn a_restart_of_the_stream_starts_afresh() {
    let mut s = Stream::default();
    s.start(12);
    s.push(&[t(1); 40], 5);
    s.start(12);
    assert_eq!(s.frame(), None);
    assert_eq!(s.totals(), (0, 0));
}
