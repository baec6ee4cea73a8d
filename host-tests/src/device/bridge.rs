//! The settings page's bridge to a device: 64-byte frames between a WebSocket (the page, as
//! binary messages) and the configuration interface ([`Link`]: a board through `hidapi`,
//! the twin over USB/IP), unchanged in both directions. The page encodes and decodes them
//! with the core's protocol compiled to WebAssembly; the bridge reads none of them.
//!
//! # Design
//! One thread a page, alternating between the two sides: a WebSocket read that waits at
//! most [`POLL`], then up to [`BURST`] frames the device has ready (each read waits at most
//! [`POLL`] too). A request therefore waits about two polls, 2 ms, and a frame from the
//! device as long. A stream at 10 kHz (10 triples a millisecond, of the 12 a full-speed
//! stream carries) passes with nothing lost (`web/tests/browser.mjs`; with 5 ms polls too).
//! The device link is opened when the page connects and closed when it goes, so that `cargo
//! lab device` can use the device in between (a device serves one host at a time).

use std::io::ErrorKind;
use std::net::TcpStream;
use std::time::Duration;

use imu_core::protocol::{Frame, FRAME_LEN};
use tungstenite::{Message, WebSocket};

use crate::device::client::{ClientError, Link};

/// How long each side is waited for before the other is looked at.
pub const POLL: Duration = Duration::from_millis(1);
/// The most device frames forwarded before the page is looked at again. A device sends at
/// most one 64-byte report a full-speed frame, 1000 a second whatever the stream's rate, so
/// a turn (at least [`POLL`]) rarely finds more than one or two; the bound only keeps a
/// flood from holding the page's requests up.
pub const BURST: usize = 16;

/// Why a bridge session ended.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// The page's socket.
    #[error("the page's WebSocket: {0}")]
    Socket(#[from] tungstenite::Error),
    /// The device.
    #[error("the device: {0}")]
    Device(#[from] ClientError),
    /// The page sent something that is not one 64-byte frame.
    #[error("the page sent a message of {0} bytes, not a {FRAME_LEN}-byte frame")]
    NotAFrame(usize),
}

fn timed_out(e: &tungstenite::Error) -> bool {
    matches!(e, tungstenite::Error::Io(io)
        if matches!(io.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut))
}

/// Forwards frames between `ws` and `link` until the page closes its socket (`Ok`) or
/// either side fails. Returns the frames forwarded to the device and from it.
///
/// # Errors
/// [`BridgeError`]: the socket or the device failed, or the page sent a message that is
/// not a frame.
pub fn run<L: Link>(
    ws: &mut WebSocket<TcpStream>,
    link: &mut L,
) -> Result<(u64, u64), BridgeError> {
    ws.get_mut()
        .set_read_timeout(Some(POLL))
        .map_err(|e| BridgeError::Socket(e.into()))?;
    let (mut to, mut from) = (0u64, 0u64);
    loop {
        match ws.read() {
            Ok(Message::Binary(b)) => {
                let frame: Frame = b
                    .as_ref()
                    .try_into()
                    .map_err(|_| BridgeError::NotAFrame(b.len()))?;
                link.send(&frame)?;
                to += 1;
            }
            Ok(Message::Close(_)) => return Ok((to, from)),
            Ok(_) => {}
            Err(e) if timed_out(&e) => {}
            Err(tungstenite::Error::ConnectionClosed | tungstenite::Error::AlreadyClosed) => {
                return Ok((to, from))
            }
            Err(e) => return Err(e.into()),
        }
        // At most a burst, so that a running stream cannot keep the page's requests (its
        // stop among them) waiting.
        for _ in 0..BURST {
            let Some(frame) = link.recv(POLL)? else { break };
            ws.send(Message::binary(frame.to_vec()))?;
            from += 1;
        }
    }
}
