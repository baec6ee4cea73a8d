//! `cargo lab hid`: its errors, and that its reports carry the motion exactly.

use host_tests::commands::hid::{wire, HidError};

fn decode(hex: &str) -> (u8, i64, i64) {
    let b: Vec<u8> = (0..4)
        .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).expect("hex"))
        .collect();
    (b[0], i64::from(b[1] as i8), i64::from(b[2] as i8))
}

#[test]
fn reports_sum_to_the_motion_with_buttons_held() {
    for (dx, dy, held) in [
        (300, -100, 1u32),
        (0, 0, 4),
        (-999_999, 1_000_000, 3),
        (1, 1, 0),
    ] {
        let w = wire(dx, dy, held).expect("valid");
        assert_eq!(w.descriptor_hex.len(), 104);
        let (mut sx, mut sy) = (0, 0);
        for r in &w.reports_hex {
            let (b, x, y) = decode(r);
            assert_eq!(u32::from(b), held);
            sx += x;
            sy += y;
        }
        assert_eq!((sx, sy), (dx, dy));
        // The fewest reports possible: ceil(max(|dx|, |dy|) / 127), at least one to show
        // buttons.
        let min = (dx.abs().max(dy.abs()) + 126) / 127;
        assert_eq!(w.reports_hex.len() as i64, min.max(i64::from(held != 0)));
    }
}

#[test]
fn nothing_to_send_sends_nothing() {
    assert!(wire(0, 0, 0).expect("valid").reports_hex.is_empty());
}

#[test]
fn bad_arguments_are_named() {
    assert_eq!(
        wire(2_000_000, 0, 0),
        Err(HidError::Motion {
            axis: "dx",
            value: 2_000_000
        })
    );
    assert_eq!(
        wire(0, -2_000_000, 0),
        Err(HidError::Motion {
            axis: "dy",
            value: -2_000_000
        })
    );
    assert_eq!(wire(0, 0, 8), Err(HidError::Buttons(8)));
    assert_eq!(wire(0, 0, 300), Err(HidError::Buttons(300)));
}
