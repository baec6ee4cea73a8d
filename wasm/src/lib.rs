//! The configuration protocol and the key table for the settings page, as WebAssembly.
//!
//! # Design
//! The page (`web/`) loads `web/imu_protocol.wasm`, built from this crate, and never encodes
//! or decodes a frame itself: [`imu_core::protocol`] does, as in the firmware and in `cargo
//! lab device`. The interface is a few C functions over two static buffers, so the module
//! needs no allocator and no glue code: the page writes arguments into [`in_ptr`]'s buffer
//! and reads answers from [`out_ptr`]'s, frames as their 64 bytes and everything else as
//! JSON text. Every function returns the answer's length in bytes, 0 when there is none (an
//! unknown request, a key id this firmware does not know, an answer too long).
//!
//! Build (the page's copy is committed, so that no user needs the target):
//! `bash web/build-wasm.sh`; CI rebuilds it and compares.
#![cfg_attr(target_arch = "wasm32", no_std)]
// The page calls these functions by their names and shares the two buffers through raw
// pointers: a C interface to JavaScript cannot be written without `no_mangle` and `unsafe`.
#![allow(unsafe_code)]

pub mod frames;
pub mod json;
pub mod keys;
pub mod track;

use imu_core::profile::Key;
use imu_core::protocol::FRAME_LEN;

use json::Json;

/// Bytes the page may write for a call: a frame, a typed value, or a profile of up to 64
/// `f64` values, or 8 `SET_CONFIG` pairs of two `f64`.
pub const IN_LEN: usize = 1024;
/// Bytes an answer may take: the key table of every key is about 7 KiB.
pub const OUT_LEN: usize = 16_384;

struct Buffers {
    input: [u8; IN_LEN],
    output: [u8; OUT_LEN],
    /// The tracker on the page's stream, once started.
    track: Option<track::Track>,
}

static mut BUFFERS: Buffers = Buffers {
    input: [0; IN_LEN],
    output: [0; OUT_LEN],
    track: None,
};

/// The input buffer ([`IN_LEN`] bytes).
#[unsafe(no_mangle)]
pub extern "C" fn in_ptr() -> *mut u8 {
    // SAFETY: a raw pointer, no reference; the page is single-threaded.
    unsafe { core::ptr::addr_of_mut!(BUFFERS.input).cast() }
}

/// The output buffer ([`OUT_LEN`] bytes).
#[unsafe(no_mangle)]
pub extern "C" fn out_ptr() -> *const u8 {
    // SAFETY: as `in_ptr`.
    unsafe { core::ptr::addr_of!(BUFFERS.output).cast() }
}

/// Runs `f` on the first `len` input bytes and the output buffer; returns what `f` wrote.
fn with_buffers(len: u32, f: impl FnOnce(&[u8], &mut [u8]) -> Option<usize>) -> u32 {
    with_track(len, |input, out, _| f(input, out))
}

/// [`with_buffers`] with the stream's tracker.
fn with_track(
    len: u32,
    f: impl FnOnce(&[u8], &mut [u8], &mut Option<track::Track>) -> Option<usize>,
) -> u32 {
    // SAFETY: the module is single-threaded and no call re-enters another, so these are the
    // only references to the buffers while `f` runs.
    let b = unsafe { &mut *core::ptr::addr_of_mut!(BUFFERS) };
    let input = &b.input[..(len as usize).min(IN_LEN)];
    f(input, &mut b.output, &mut b.track).map_or(0, |n| n as u32)
}

fn f64s(bytes: &[u8]) -> impl Iterator<Item = f64> + '_ {
    bytes.chunks_exact(8).map(|c| {
        let mut a = [0u8; 8];
        a.copy_from_slice(c);
        f64::from_le_bytes(a)
    })
}

fn answer(out: &mut [u8], f: impl FnOnce(&mut Json<'_>) -> core::fmt::Result) -> Option<usize> {
    let mut j = Json::new(out);
    f(&mut j).ok()?;
    Some(j.len())
}

/// Encodes request `code` with `tag` into a 64-byte frame in the output buffer. `arg`:
/// `GET_CONFIG`'s start or `SET_CONFIG`'s commit (0 or 1); `SET_CONFIG`'s pairs are `n` pairs
/// of little-endian `f64` (key id, value) in the input buffer. Returns 64, or 0.
#[unsafe(no_mangle)]
pub extern "C" fn encode_request(code: u32, tag: u32, arg: u32, n: u32) -> u32 {
    with_buffers(n.saturating_mul(16), |input, out| {
        let v: heapless::Vec<f64, 64> = f64s(input).collect();
        let pairs: heapless::Vec<(f64, f64), 32> =
            v.chunks_exact(2).map(|p| (p[0], p[1])).collect();
        let r = frames::request(u8::try_from(code).ok()?, arg, &pairs)?;
        let frame = r.encode(u8::try_from(tag).ok()?);
        out[..FRAME_LEN].copy_from_slice(&frame);
        Some(FRAME_LEN)
    })
}

/// Decodes the frame of `len` bytes in the input buffer as JSON ([`frames::decode`]).
#[unsafe(no_mangle)]
pub extern "C" fn decode_frame(len: u32) -> u32 {
    with_buffers(len, |input, out| answer(out, |j| frames::decode(j, input)))
}

/// The key table ([`keys::table`]) of the profile whose `n` values (little-endian `f64`, in
/// `Key::ALL`'s order; 0 values: the defaults) are in the input buffer.
#[unsafe(no_mangle)]
pub extern "C" fn key_table(n: u32) -> u32 {
    with_buffers(n.saturating_mul(8), |input, out| {
        let v: heapless::Vec<f64, 64> = f64s(input).collect();
        answer(out, |j| keys::table(j, &keys::profile_of(&v)))
    })
}

/// The value the text of `len` bytes in the input buffer gives key `id`, as JSON:
/// `{"value":V}` (`null` for off) or `{"error":"must be ..."}`.
#[unsafe(no_mangle)]
pub extern "C" fn read_value(id: u32, len: u32) -> u32 {
    with_buffers(len, |input, out| {
        let key = Key::from_id(u8::try_from(id).ok()?)?;
        let text = core::str::from_utf8(input).unwrap_or("");
        answer(out, |j| match key.read(text) {
            Some(v) => {
                j.raw("{\"value\":")?;
                j.number(v)?;
                j.raw("}")
            }
            None => {
                j.raw("{\"error\":")?;
                j.string(key.wanted())?;
                j.raw("}")
            }
        })
    })
}

/// Starts the tracker on the stream with the profile whose `n` values (as for [`key_table`])
/// are in the input buffer: `{"ok":true}`, or `{"ok":false}` if the profile does not run.
#[unsafe(no_mangle)]
pub extern "C" fn track_start(n: u32) -> u32 {
    with_track(n.saturating_mul(8), |input, out, t| {
        let v: heapless::Vec<f64, 64> = f64s(input).collect();
        *t = track::Track::new(&keys::profile_of(&v));
        let ok = t.is_some();
        answer(out, |j| {
            j.raw("{\"ok\":")?;
            j.boolean(ok)?;
            j.raw("}")
        })
    })
}

/// Feeds the tracker `n` triples of raw codes (three little-endian `u16` each, sensor order)
/// from the input buffer: `{"x":X,"y":Y,"state":"...","held":B,"samples":N}`, the counts sent
/// since [`track_start`] (right, down); 0 if no tracker runs.
#[unsafe(no_mangle)]
pub extern "C" fn track_feed(n: u32) -> u32 {
    with_track(n.saturating_mul(6), |input, out, t| {
        let t = t.as_mut()?;
        for c in input.chunks_exact(6) {
            let code = |k: usize| u16::from_le_bytes([c[2 * k], c[2 * k + 1]]);
            t.feed([code(0), code(1), code(2)]);
        }
        answer(out, |j| {
            core::fmt::Write::write_fmt(
                j,
                format_args!(
                    "{{\"x\":{},\"y\":{},\"state\":\"{}\",\"held\":{},\"samples\":{}}}",
                    t.sent.0,
                    t.sent.1,
                    t.state(),
                    t.held(),
                    t.samples()
                ),
            )
        })
    })
}

/// The protocol's constants the page needs, as JSON: the request codes by name, the pairs a
/// frame holds, the frame length and the key count.
#[unsafe(no_mangle)]
pub extern "C" fn constants() -> u32 {
    use imu_core::protocol::{code, PAIRS_MAX};
    with_buffers(0, |_, out| {
        answer(out, |j| {
            j.raw("{")?;
            for (name, c) in [
                ("INFO", code::INFO),
                ("COUNTERS", code::COUNTERS),
                ("CALIBRATION", code::CALIBRATION),
                ("GET_CONFIG", code::GET_CONFIG),
                ("SET_CONFIG", code::SET_CONFIG),
                ("SAVE", code::SAVE),
                ("DEFAULTS", code::DEFAULTS),
                ("RECALIBRATE", code::RECALIBRATE),
                ("STREAM_START", code::STREAM_START),
                ("STREAM_STOP", code::STREAM_STOP),
            ] {
                j.key(name)?;
                core::fmt::Write::write_fmt(j, format_args!("{c},"))?;
            }
            core::fmt::Write::write_fmt(
                j,
                format_args!(
                    "\"PAIRS_MAX\":{PAIRS_MAX},\"FRAME_LEN\":{FRAME_LEN},\"KEYS\":{}}}",
                    Key::ALL.len()
                ),
            )
        })
    })
}

#[cfg(target_arch = "wasm32")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    core::arch::wasm32::unreachable()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn out_text(n: u32) -> String {
        // SAFETY: the tests run these calls one at a time (one test).
        let out = unsafe { core::slice::from_raw_parts(out_ptr(), n as usize) };
        String::from_utf8(out.to_vec()).expect("UTF-8")
    }

    fn put(bytes: &[u8]) {
        // SAFETY: as above.
        unsafe { core::ptr::copy_nonoverlapping(bytes.as_ptr(), in_ptr(), bytes.len()) };
    }

    #[test]
    fn the_c_interface_round_trips_through_the_buffers() {
        // counts_per_inch (id 5) = 1600, committed, tag 3.
        let mut pairs = [0u8; 16];
        pairs[..8].copy_from_slice(&5.0f64.to_le_bytes());
        pairs[8..].copy_from_slice(&1600.0f64.to_le_bytes());
        put(&pairs);
        let code = u32::from(imu_core::protocol::code::SET_CONFIG);
        assert_eq!(encode_request(code, 3, 1, 1), 64);
        // SAFETY: as above.
        let frame = unsafe { core::slice::from_raw_parts(out_ptr(), 64) }.to_vec();
        let (tag, r) = imu_core::protocol::Request::decode(&frame).expect("decodes");
        assert_eq!(tag, 3);
        assert_eq!(
            r,
            frames::request(code as u8, 1, &[(5.0, 1600.0)]).expect("ok")
        );
        // The same bytes read back as a frame the device would not send: a refusal-free
        // decode error in JSON, not a crash.
        put(&frame);
        assert!(out_text(decode_frame(64)).starts_with("{\"bad\":"));
        // A typed value and a wrong one.
        put(b"off");
        assert_eq!(out_text(read_value(2, 3)), "{\"value\":null}");
        put(b"maybe");
        assert_eq!(
            out_text(read_value(Key::Drift as u32, 5)),
            "{\"error\":\"must be on or off\"}"
        );
        assert_eq!(read_value(250, 0), 0);
        // The key table of the defaults.
        assert!(out_text(key_table(0)).starts_with("[{\"id\":1,\"name\":\"fs_hz\""));
        // The tracker: started on the defaults, fed a still second, calibrating.
        assert_eq!(out_text(track_start(0)), "{\"ok\":true}");
        let still: Vec<u8> = [2048u16, 2048, 2466]
            .iter()
            .flat_map(|c| c.to_le_bytes())
            .collect::<Vec<u8>>()
            .repeat(100);
        put(&still);
        assert_eq!(
            out_text(track_feed(100)),
            "{\"x\":0,\"y\":0,\"state\":\"calibrating\",\"held\":false,\"samples\":100}"
        );
        let c = out_text(constants());
        assert!(
            c.starts_with("{\"INFO\":1,") && c.contains("\"PAIRS_MAX\":6,"),
            "{c}"
        );
        // A request code that does not exist.
        assert_eq!(encode_request(0x7F, 0, 0, 0), 0);
    }
}
