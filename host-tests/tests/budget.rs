//! The fixed-point stages held to their f64 twins within the bounds the Q formats imply
//! (derivations in `host_tests::commands::budget`).

use host_tests::commands::budget::{self, Row};
use imu_core::Scheme;

/// Sampling slack on an RMS measured over `n` independent uniform errors: the relative
/// standard error of an rms is `0.5 sqrt(0.8 / n)`; allow 3.29 of them (the project's
/// 0.1 % two-sided critical value).
fn rms_slack(n: u64) -> f64 {
    1.0 + 3.29 * 0.5 * (0.8 / n as f64).sqrt()
}

#[track_caller]
fn within(row: &Row) {
    eprintln!(
        "{}: max {:.3e} (bound {:.3e}), rms {:.3e} (expected {:?})",
        row.stage, row.max_err, row.max_bound, row.rms_err, row.rms_bound
    );
    assert!(
        row.max_err <= row.max_bound,
        "{}: max error above bound",
        row.stage
    );
}

#[test]
fn lowpass_output_is_within_half_a_q16_lsb_for_every_ratio() {
    // The ratio range's two ends and the default device's 50 Hz at 3 kHz.
    for ratio in [1e-6, 1e-3, 50.0 / 3000.0, 0.499_999] {
        let row = budget::lowpass(ratio, 1_000_000, 1);
        within(&row);
        let expected = row.rms_bound.expect("random rounding");
        assert!(
            row.rms_err <= expected * rms_slack(row.samples),
            "{}",
            row.stage
        );
        // The rounding is really used, not avoided: the rms is at least half the uniform one.
        assert!(row.rms_err >= 0.5 * expected, "{}", row.stage);
    }
}

#[test]
fn calibration_rounds_the_mean_once() {
    for row in budget::calibration(200, 3000, 2) {
        within(&row);
    }
}

#[test]
fn integrators_are_exact() {
    // Against integer sums in i128 written here from REFERENCE (c)'s recursions in the
    // integrator's units (W = 2 V, Z = 4 S): Euler `W += 2 c, Z += 2 W`; trapezoid
    // `W' = W + c[n-1] + c[n], Z += W + W'` from the second sample. Random 12-bit codes in
    // Q16 around an offset of 1500 LSB, so that Z passes 2^63 (beyond any i64) within
    // 400 000 samples: a wrap, a rounding, a narrower accumulator or another recursion each
    // shows as a difference. (The f64 rows of `cargo lab budget` cannot: f64 is exact on
    // these integers too, and only up to 2^53.)
    use imu_core::IntegratorState;
    use rand::Rng;
    for scheme in [Scheme::Euler, Scheme::Trapezoid] {
        let mut rng = host_tests::world::noise::rng(3);
        let mut state = IntegratorState::default();
        let (mut w, mut z, mut prev) = (0i128, 0i128, None::<i128>);
        for n in 0..400_000u32 {
            let c = (i64::from(rng.random_range(0..4096u16)) - 2048 + 1500) << 16;
            scheme.step(&mut state, c);
            let c = i128::from(c);
            match scheme {
                Scheme::Euler => {
                    w += 2 * c;
                    z += 2 * w;
                }
                Scheme::Trapezoid => {
                    if let Some(p) = prev {
                        let w_next = w + p + c;
                        z += w + w_next;
                        w = w_next;
                    }
                    prev = Some(c);
                }
            }
            if n % 997 == 0 {
                assert_eq!(
                    i128::from(state.velocity()),
                    w,
                    "{scheme:?} W at sample {n}"
                );
                assert_eq!(state.position(), z, "{scheme:?} Z at sample {n}");
            }
        }
        assert!(
            z > i128::from(i64::MAX),
            "{scheme:?}: Z = {z} never left the i64 range"
        );
        assert_eq!(i128::from(state.velocity()), w, "{scheme:?} W");
        assert_eq!(state.position(), z, "{scheme:?} Z");
    }
}

#[test]
fn readout_never_drifts_from_the_position() {
    within(&budget::readout(30_000, 5));
}

#[test]
fn pipeline_position_is_within_its_rounding_budget() {
    for t in [1.0, 60.0] {
        let row = budget::pipeline(t, 8, 6);
        within(&row);
    }
}
