//! Milliseconds from a wrapping hardware counter: exact over long runs and wraps, and a
//! stall of the CPU counted in full.

use imu_app::uptime::Uptime;

const PER_MS: u32 = 96_000;

#[test]
fn readings_every_millisecond_count_every_millisecond_across_wraps() {
    // Start just before a wrap; read every 96 000 cycles for 100 s (two wraps of 44.7 s).
    let start = u32::MAX - 1_000;
    let mut u = Uptime::new(PER_MS, start, 7);
    let mut now = start;
    for k in 1..=100_000u32 {
        now = now.wrapping_add(PER_MS);
        assert_eq!(u.update(now), 7 + k);
    }
}

#[test]
fn uneven_readings_carry_the_fraction_and_never_drift() {
    // Readings 0.37 ms, 1.9 ms, 3 cycles apart...: the milliseconds are always the whole
    // number of milliseconds in the cycles elapsed since the start.
    let mut u = Uptime::new(PER_MS, 123, 0);
    let (mut now, mut total) = (123u32, 0u64);
    for k in 0..20_000u64 {
        let step = [35_520u32, 182_400, 3, 95_999, 1][(k % 5) as usize];
        now = now.wrapping_add(step);
        total += u64::from(step);
        assert_eq!(
            u64::from(u.update(now)),
            total / u64::from(PER_MS),
            "reading {k}"
        );
    }
    assert_eq!(u64::from(u.ms()), total / u64::from(PER_MS));
}

#[test]
fn a_stalled_cpu_loses_no_time() {
    // An 800 ms erase between two readings: 800 ms later, not 1 ms.
    let mut u = Uptime::new(PER_MS, 0, 1000);
    assert_eq!(u.update(PER_MS), 1001);
    assert_eq!(u.update(PER_MS * 801), 1801);
}

#[test]
fn a_rate_of_zero_is_taken_as_one_cycle_a_millisecond() {
    // No division by zero on a misconfigured rate: one cycle a millisecond.
    let mut u = Uptime::new(0, 10, 0);
    assert_eq!(u.update(15), 5);
}

#[test]
fn time_in_stop_mode_is_credited_on_top_of_the_counted_cycles() {
    // The counter stops with the clocks in Stop mode: 1.5 ms counted, then 40 ms slept
    // (two probe periods), then 0.7 ms counted: 42 ms, the fraction carried on.
    let mut u = Uptime::new(PER_MS, 0, 100);
    assert_eq!(u.credit(PER_MS * 3 / 2, 40), 141);
    assert_eq!(u.update(PER_MS * 3 / 2 + PER_MS * 7 / 10), 142);
    assert_eq!(u.ms(), 142);
}
