//! `cargo lab ui`: serves the settings page (`web/`) on 127.0.0.1 and bridges it to a board
//! (through `hidapi`) or to the twin (`--twin ADDR`, over USB/IP) with a WebSocket at
//! `/ws` ([`crate::device::bridge`]); `POST /check` judges the page's guided check by
//! `cargo lab device check`'s rules ([`crate::device::check`]). It opens no browser by
//! itself.
//!
//! The page's files are built into the lab (`include_bytes!`), so it serves what it was
//! built with from any directory. Only the page's own origin may open the bridge: a
//! WebSocket from another site's page (which a browser would let connect to 127.0.0.1) is
//! refused, so no web page but this one can change the mouse's settings.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::time::Duration;

use tungstenite::handshake::server::{ErrorResponse, Request, Response};

use crate::device::bridge;
use crate::device::client::HidLink;
use crate::device::usbip::BUSID;
use crate::device::usbip_host::UsbIpHost;

use super::{positive, Error, Outcome};

/// One example, for `cargo lab` alone.
pub const EXAMPLE: &str =
    "cargo lab ui --twin 127.0.0.1:3240   (then open http://127.0.0.1:8340/ in a browser)";

/// `cargo lab ui`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Bridge to the twin (`cargo lab twin`) at this USB/IP address instead of a board.
    #[arg(long)]
    pub twin: Option<SocketAddr>,
    /// The port on 127.0.0.1 to serve the page on, `1..=65535`.
    #[arg(long, default_value_t = 8340)]
    pub port: u16,
    /// The board with this USB serial number (`cargo lab device list`); without it, the only one.
    #[arg(long)]
    pub serial: Option<String>,
    /// How long the device may take to answer when the page connects [s].
    #[arg(long, allow_negative_numbers = true, default_value_t = 5.0)]
    pub timeout: f64,
}

/// The page's files: path, content type, bytes.
const FILES: [(&str, &str, &[u8]); 5] = [
    (
        "/",
        "text/html; charset=utf-8",
        include_bytes!("../../../web/index.html"),
    ),
    (
        "/index.html",
        "text/html; charset=utf-8",
        include_bytes!("../../../web/index.html"),
    ),
    (
        "/app.js",
        "text/javascript; charset=utf-8",
        include_bytes!("../../../web/app.js"),
    ),
    (
        "/style.css",
        "text/css; charset=utf-8",
        include_bytes!("../../../web/style.css"),
    ),
    (
        "/imu_protocol.wasm",
        "application/wasm",
        include_bytes!("../../../web/imu_protocol.wasm"),
    ),
];

/// The request's head (through the blank line, at most 16 KiB), without consuming it, and
/// its length in bytes (what is to be consumed before the body).
fn peek_head(s: &TcpStream) -> std::io::Result<(String, usize)> {
    let mut buf = vec![0u8; 16 * 1024];
    for _ in 0..200 {
        let n = s.peek(&mut buf)?;
        let end = buf[..n]
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .map(|p| p + 4);
        if let Some(end) = end {
            return Ok((String::from_utf8_lossy(&buf[..end]).into_owned(), end));
        }
        if n == 0 || n == buf.len() {
            return Ok((String::from_utf8_lossy(&buf[..n]).into_owned(), n));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    Ok((String::new(), 0))
}

fn respond(s: &mut TcpStream, status: &str, kind: &str, body: &[u8]) -> std::io::Result<()> {
    s.write_all(answer_head(status, kind, body.len()).as_bytes())?;
    s.write_all(body)
}

/// An answer's head, for a body of `len` bytes of `kind` (a HEAD request gets it alone).
fn answer_head(status: &str, kind: &str, len: usize) -> String {
    format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {len}\r\n\
         Cache-Control: no-store\r\nConnection: close\r\n\r\n"
    )
}

/// Serves one connection: a file, or the bridge.
fn serve(mut s: TcpStream, port: u16, a: &Args) -> std::io::Result<()> {
    s.set_read_timeout(Some(Duration::from_secs(5)))?;
    let (head, head_len) = peek_head(&s)?;
    let mut words = head.split_whitespace();
    let (method, path) = (words.next().unwrap_or(""), words.next().unwrap_or(""));
    let path = path.split('?').next().unwrap_or("");
    if path == "/ws" {
        return bridge_session(s, port, a);
    }
    // Consume the head before answering.
    let mut sink = vec![0u8; head_len];
    s.read_exact(&mut sink)?;
    if path == "/check" && method == "POST" {
        return check_request(&mut s, &head);
    }
    match FILES.iter().find(|(p, _, _)| *p == path) {
        Some((_, kind, body)) if method == "GET" => respond(&mut s, "200 OK", kind, body),
        // HEAD: the headers a GET would get (its length included), no body.
        Some((_, kind, body)) if method == "HEAD" => {
            s.write_all(answer_head("200 OK", kind, body.len()).as_bytes())
        }
        Some(_) => respond(
            &mut s,
            "405 Method Not Allowed",
            "text/plain",
            b"GET only\n",
        ),
        None => respond(
            &mut s,
            "404 Not Found",
            "text/plain",
            b"not part of the page\n",
        ),
    }
}

/// The most a check's recordings may take [bytes]: three steps of up to 60 s at 20 kHz as
/// JSON (about 20 bytes a triple) fit 80 MB.
const CHECK_BODY_MAX: usize = 80 << 20;

/// What the page's guided check sends: the device's rate, scale, resolution and axis
/// mapping, and the three steps' raw codes (at rest, moved right, moved away).
#[derive(serde::Deserialize)]
struct CheckRequest {
    fs: f64,
    m_s2_per_lsb: f64,
    adc_bits: u8,
    /// `(x_axis, x_sign, y_axis, y_sign)` of the running profile.
    current: (usize, f64, usize, f64),
    steps: [Vec<[u16; 3]>; 3],
}

/// `POST /check`: the page's three recordings judged by `cargo lab device check`'s rules
/// ([`crate::device::check`]), answered as its JSON with the chart's SVG.
fn check_request(s: &mut TcpStream, head: &str) -> std::io::Result<()> {
    let len = head
        .lines()
        .find_map(|l| {
            let (k, v) = l.split_once(':')?;
            k.trim()
                .eq_ignore_ascii_case("content-length")
                .then(|| v.trim().parse::<usize>().ok())?
        })
        .unwrap_or(0);
    if len == 0 {
        return respond(
            s,
            "400 Bad Request",
            "text/plain",
            b"a check needs its recordings\n",
        );
    }
    if len > CHECK_BODY_MAX {
        let why = format!("a check's recordings take at most {CHECK_BODY_MAX} bytes\n");
        return respond(s, "413 Payload Too Large", "text/plain", why.as_bytes());
    }
    let mut body = vec![0u8; len];
    s.set_read_timeout(Some(Duration::from_secs(30)))?;
    s.read_exact(&mut body)?;
    let req: CheckRequest = match serde_json::from_slice(&body) {
        Ok(r) => r,
        Err(e) => {
            let why = format!("not a check request: {e}\n");
            return respond(s, "400 Bad Request", "text/plain", why.as_bytes());
        }
    };
    let (x, xs, y, ys) = req.current;
    let top = (1u32 << req.adc_bits.clamp(2, 16)) - 1;
    let valid = req.fs.is_finite()
        && req.fs > 0.0
        && req.m_s2_per_lsb.is_finite()
        && req.m_s2_per_lsb > 0.0
        && (2..=16).contains(&req.adc_bits)
        && x <= 2
        && y <= 2
        && [xs, ys].iter().all(|s| s.abs() == 1.0)
        && req.steps.iter().all(|st| !st.is_empty())
        && req
            .steps
            .iter()
            .flatten()
            .flatten()
            .all(|&c| u32::from(c) <= top);
    if !valid {
        let why = b"a check needs a rate and a scale above 0, 2 to 16 bits, axes 0..=2 with \
            signs +-1, and three recordings of codes the ADC can give\n";
        return respond(s, "400 Bad Request", "text/plain", why);
    }
    use crate::device::check;
    let steps = [&req.steps[0][..], &req.steps[1][..], &req.steps[2][..]];
    let judged = check::judge(steps, req.fs, req.m_s2_per_lsb, req.adc_bits, req.current);
    let colors = [super::COLORS[0], super::COLORS[1], super::COLORS[2]];
    let svg = check::chart(steps, req.fs, req.m_s2_per_lsb, &judged.rest, colors).to_svg();
    let answer = serde_json::json!({ "check": judged, "svg": svg });
    respond(
        s,
        "200 OK",
        "application/json",
        answer.to_string().as_bytes(),
    )
}

/// The origins the page is served from on `port`.
fn own_origin(origin: &str, port: u16) -> bool {
    [
        format!("http://127.0.0.1:{port}"),
        format!("http://localhost:{port}"),
    ]
    .iter()
    .any(|o| o == origin)
}

fn bridge_session(s: TcpStream, port: u16, a: &Args) -> std::io::Result<()> {
    // tungstenite's callback type fixes the error type (an HTTP response).
    #[allow(clippy::result_large_err)]
    let check = |req: &Request, resp: Response| -> Result<Response, ErrorResponse> {
        let origin = req
            .headers()
            .get("origin")
            .and_then(|o| o.to_str().ok())
            .unwrap_or("");
        if own_origin(origin, port) {
            Ok(resp)
        } else {
            let mut refused = ErrorResponse::new(Some(format!(
                "only the page served here may use the bridge, not {origin:?}"
            )));
            *refused.status_mut() = tungstenite::http::StatusCode::FORBIDDEN;
            Err(refused)
        }
    };
    let mut ws = match tungstenite::accept_hdr(s, check) {
        Ok(ws) => ws,
        Err(e) => {
            eprintln!("ui: a WebSocket was refused: {e}");
            return Ok(());
        }
    };
    let timeout = Duration::from_secs_f64(a.timeout);
    // The page waits for this before its first request, and shows a failure's reason.
    let ready = |ws: &mut tungstenite::WebSocket<TcpStream>| {
        ws.send(tungstenite::Message::text("{\"link_ready\":true}"))
            .map_err(|e| e.to_string())
    };
    let ended = match a.twin {
        Some(addr) => match UsbIpHost::connect(addr, BUSID, timeout) {
            Ok(mut host) => ready(&mut ws)
                .and_then(|()| bridge::run(&mut ws, &mut host).map_err(|e| e.to_string())),
            Err(e) => Err(format!(
                "the twin at {addr}: {e} (is `cargo lab twin` running, and no other host \
                 attached to it?)"
            )),
        },
        None => match HidLink::open(a.serial.as_deref()) {
            Ok(mut hid) => ready(&mut ws)
                .and_then(|()| bridge::run(&mut ws, &mut hid).map_err(|e| e.to_string())),
            Err(e) => Err(format!("no board: {e}")),
        },
    };
    match ended {
        Ok((to, from)) => {
            eprintln!("ui: the page disconnected ({to} frames to the device, {from} from it)")
        }
        Err(why) => {
            eprintln!("ui: {why}");
            // The page shows why its connection ended.
            let _ = ws.send(tungstenite::Message::text(format!(
                "{{\"link_error\":{why:?}}}"
            )));
            let _ = ws.close(None);
            let _ = ws.flush();
        }
    }
    Ok(())
}

/// Runs `cargo lab ui` until it is stopped.
///
/// # Errors
/// A bad `--port` or `--timeout`, or the port already in use.
pub fn run(a: &Args) -> Outcome {
    positive("timeout", a.timeout)?;
    if a.timeout > 3600.0 {
        return Err(Error::arg("timeout", a.timeout, "at most 3600 s"));
    }
    if a.port == 0 {
        return Err(Error::arg("port", 0, "1..=65535"));
    }
    let listener = TcpListener::bind(("127.0.0.1", a.port)).map_err(|e| {
        Error::Run(format!(
            "cannot serve on 127.0.0.1:{}: {e} (another `cargo lab ui`? choose --port)",
            a.port
        ))
    })?;
    eprintln!(
        "ui: the settings page is at http://127.0.0.1:{}/ ({}); Ctrl-C stops",
        a.port,
        match a.twin {
            Some(t) => format!("bridged to the twin at {t}"),
            None => "bridged to a board through hidapi, or open it in Chrome for WebHID".into(),
        }
    );
    std::thread::scope(|scope| {
        for s in listener.incoming() {
            match s {
                Ok(s) => {
                    scope.spawn(move || {
                        if let Err(e) = serve(s, a.port, a) {
                            eprintln!("ui: a connection failed: {e}");
                        }
                    });
                }
                Err(e) => eprintln!("ui: accept: {e}"),
            }
        }
    });
    Ok(String::new())
}
