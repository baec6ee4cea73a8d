//! Who the device says it is on USB: IDs, strings, power, the HID endpoint's interval and the
//! motion that wakes a suspended host. Product identity, not board wiring: the firmware and
//! the twin enumerate identically.

/// USB vendor and product ID: pid.codes' test PID 1209:0001, free to use for testing an
/// open project. A released product should get its own PID from pid.codes.
pub const VID_PID: (u16, u16) = (0x1209, 0x0001);
/// Manufacturer string.
pub const MANUFACTURER: &str = "imu-mouse project";
/// Product string.
pub const PRODUCT: &str = "imu-mouse accelerometer mouse";
/// Serial number string of a device without a unique ID of its own (the app's tests). A
/// board's serial is its MCU's unique device ID ([`serial`]); the twin's is its `--serial`.
pub const SERIAL: &str = "0001";

/// Length of a board's serial number string [characters]: the 96-bit unique device ID as
/// hex digits.
pub const SERIAL_LEN: usize = 24;

/// The serial number string of a board whose MCU has the unique device ID `uid` (the 12
/// bytes from 0x1FFF_7A10 in address order, RM0383 section 24.1: wafer X and Y as
/// little-endian u16, the wafer number, the lot number's 7 ASCII bytes), written into `out`
/// as upper-case hex digits in address order, so that two boards never show one serial and
/// `cargo lab device --serial` can tell them apart.
pub fn serial<'a>(uid: &[u8; 12], out: &'a mut [u8; SERIAL_LEN]) -> &'a str {
    const HEX: &[u8; 16] = b"0123456789ABCDEF";
    for (i, b) in uid.iter().enumerate() {
        out[2 * i] = HEX[usize::from(b >> 4)];
        out[2 * i + 1] = HEX[usize::from(b & 0xF)];
    }
    // Hex digits are ASCII: always UTF-8.
    core::str::from_utf8(out).unwrap_or(SERIAL)
}
/// Device release number, BCD (`bcdDevice`, 0x0100 = 1.00).
pub const RELEASE_BCD: u16 = 0x0100;
/// Most current the device draws from the bus while configured [mA]; the configuration
/// descriptor carries half of it (2 mA units). The F411 at 96 MHz with the ADC running and
/// an ADXL335 stays well under it.
pub const MAX_POWER_MA: usize = 100;
/// HID interrupt IN polling interval requested from the host [ms] (full speed frames).
pub const POLL_MS: u8 = 1;
/// Acceleration change that wakes a suspended host [m/s^2], on any axis (the probe compares
/// single samples with the first after the suspend; ADXL335 noise per sample is about
/// 0.03 m/s^2, a hand moving a mouse exceeds 0.5 m/s^2, and a tilt of 3 degrees gives it).
pub const WAKE_MOTION_M_S2: f64 = 0.5;

/// A version component, at compile time (a non-numeric one fails the build).
const fn digits(s: &str) -> u8 {
    match u8::from_str_radix(s, 10) {
        Ok(v) => v,
        Err(_) => panic!("a version component is a number below 256"),
    }
}

/// Firmware version `[major, minor, patch]`: this crate's version, as the configuration
/// interface's `info` reports it.
pub const FIRMWARE_VERSION: [u8; 3] = [
    digits(env!("CARGO_PKG_VERSION_MAJOR")),
    digits(env!("CARGO_PKG_VERSION_MINOR")),
    digits(env!("CARGO_PKG_VERSION_PATCH")),
];
