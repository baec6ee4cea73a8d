//! The mouse's configuration interface on a scripted bus: a request waits in the inbox until
//! taken, responses wait in the outbox for a busy endpoint and go before stream frames,
//! nothing streams while the host is not listening, and a bus reset empties both boxes.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex};

use imu_app::Mouse;
use imu_core::protocol::{Request, StreamFrame, FRAME_LEN};
use usb_device::bus::{PollResult, UsbBus, UsbBusAllocator};
use usb_device::endpoint::{EndpointAddress, EndpointType};
use usb_device::{Result as UsbResult, UsbDirection, UsbError};

/// The mouse's endpoints as this bus allocates them (in order, per direction, from 1): the
/// mouse's IN is EP1, the configuration interface's OUT is EP1 and its IN is EP2.
const CONFIG_OUT: u8 = 1;
const CONFIG_IN: u8 = 2;

#[derive(Default)]
struct State {
    next: [u8; 2],
    setup: Option<[u8; 8]>,
    outs: HashMap<u8, VecDeque<Vec<u8>>>,
    /// The packet each IN endpoint holds until the host reads it.
    ins: HashMap<u8, Vec<u8>>,
    delivered: HashMap<u8, Vec<Vec<u8>>>,
    in_complete: u16,
    reset: bool,
}

#[derive(Clone, Default)]
struct Host(Arc<Mutex<State>>);

impl Host {
    fn state(&self) -> std::sync::MutexGuard<'_, State> {
        self.0.lock().expect("not poisoned")
    }
    fn setup(&self, s: [u8; 8]) {
        self.state().setup = Some(s);
    }
    fn send(&self, ep: u8, bytes: &[u8]) {
        self.state()
            .outs
            .entry(ep)
            .or_default()
            .push_back(bytes.to_vec());
    }
    /// The host reads what `ep` holds, if anything.
    fn read(&self, ep: u8) -> Option<Vec<u8>> {
        let mut s = self.state();
        let p = s.ins.remove(&ep)?;
        s.delivered.entry(ep).or_default().push(p.clone());
        s.in_complete |= 1 << ep;
        Some(p)
    }
    fn reset(&self) {
        self.state().reset = true;
    }
}

struct ScriptBus(Host);

impl UsbBus for ScriptBus {
    fn alloc_ep(
        &mut self,
        dir: UsbDirection,
        addr: Option<EndpointAddress>,
        _: EndpointType,
        _: u16,
        _: u8,
    ) -> UsbResult<EndpointAddress> {
        if let Some(a) = addr {
            return Ok(a);
        }
        let mut s = self.0.state();
        let i = usize::from(dir == UsbDirection::In);
        s.next[i] += 1;
        Ok(EndpointAddress::from_parts(usize::from(s.next[i]), dir))
    }
    fn enable(&mut self) {}
    fn reset(&self) {}
    fn set_device_address(&self, _: u8) {}
    fn write(&self, ep: EndpointAddress, buf: &[u8]) -> UsbResult<usize> {
        let mut s = self.0.state();
        let i = ep.index() as u8;
        if i == 0 {
            s.in_complete |= 1;
            return Ok(buf.len());
        }
        if s.ins.contains_key(&i) {
            return Err(UsbError::WouldBlock);
        }
        s.ins.insert(i, buf.to_vec());
        Ok(buf.len())
    }
    fn read(&self, ep: EndpointAddress, buf: &mut [u8]) -> UsbResult<usize> {
        let mut s = self.0.state();
        let i = ep.index() as u8;
        if i == 0 {
            if let Some(setup) = s.setup.take() {
                buf[..8].copy_from_slice(&setup);
                return Ok(8);
            }
        }
        let p = s
            .outs
            .get_mut(&i)
            .and_then(VecDeque::pop_front)
            .ok_or(UsbError::WouldBlock)?;
        buf[..p.len()].copy_from_slice(&p);
        Ok(p.len())
    }
    fn set_stalled(&self, _: EndpointAddress, _: bool) {}
    fn is_stalled(&self, _: EndpointAddress) -> bool {
        false
    }
    fn suspend(&self) {}
    fn resume(&self) {}
    fn poll(&self) -> PollResult {
        let mut s = self.0.state();
        if std::mem::take(&mut s.reset) {
            return PollResult::Reset;
        }
        let ep_setup = u16::from(s.setup.is_some());
        let ep_out = s
            .outs
            .iter()
            .filter(|(_, q)| !q.is_empty())
            .fold(0u16, |m, (i, _)| m | 1 << i);
        let ep_in_complete = std::mem::take(&mut s.in_complete);
        if ep_setup | ep_out | ep_in_complete == 0 {
            PollResult::None
        } else {
            PollResult::Data {
                ep_out,
                ep_in_complete,
                ep_setup,
            }
        }
    }
}

fn frame(tag: u8) -> [u8; FRAME_LEN] {
    Request::Info.encode(tag)
}

fn stream_frame() -> StreamFrame {
    StreamFrame {
        seq: 0,
        lost: 0,
        triples: heapless::Vec::from_slice(&[[1, 2, 3]]).expect("one"),
        wide: false,
    }
}

/// A mouse the host has configured.
fn configured(
    host: &Host,
    alloc: &'static UsbBusAllocator<ScriptBus>,
) -> Mouse<'static, ScriptBus> {
    let mut mouse = Mouse::new(alloc, imu_app::identity::SERIAL).expect("identity fits");
    host.setup([0x00, 0x09, 1, 0, 0, 0, 0, 0]); // SET_CONFIGURATION 1
    for _ in 0..3 {
        mouse.service([0; 3], 0);
    }
    assert_eq!(mouse.reports().link(), imu_core::Link::Configured);
    // The opening report (imu_app::opening), taken by the host at 0 ms; the quiet time is
    // over by LATER.
    assert_eq!(host.read(1).as_deref(), Some(&[0u8, 0, 0, 0][..]));
    mouse.service([0; 3], 0);
    mouse
}

/// A time after the opening's quiet time [ms].
const LATER: u32 = 1000;

fn bus() -> (Host, &'static UsbBusAllocator<ScriptBus>) {
    let host = Host::default();
    let alloc = Box::leak(Box::new(UsbBusAllocator::new(ScriptBus(host.clone()))));
    (host, alloc)
}

#[test]
fn a_request_waits_in_the_inbox_and_the_next_stays_on_the_bus_until_then() {
    let (host, alloc) = bus();
    let mut mouse = configured(&host, alloc);
    host.send(CONFIG_OUT, &frame(1));
    host.send(CONFIG_OUT, &frame(2));
    mouse.service([0; 3], LATER);
    mouse.service([0; 3], LATER);
    assert_eq!(
        mouse.take_request().map(|(f, n)| (f[2], n)),
        Some((1, FRAME_LEN))
    );
    assert_eq!(mouse.take_request(), None, "the second is read only after");
    mouse.service([0; 3], LATER);
    assert_eq!(mouse.take_request().map(|(f, _)| f[2]), Some(2));
}

#[test]
fn responses_wait_for_a_busy_endpoint_and_go_before_stream_frames() {
    let (host, alloc) = bus();
    let mut mouse = configured(&host, alloc);
    assert!(mouse.respond(frame(1)), "pushed at once");
    assert!(
        mouse.respond(frame(2)),
        "queued: the host has not read the first"
    );
    assert!(mouse.respond(frame(3)), "queued");
    assert!(!mouse.respond(frame(4)), "the outbox holds two");
    assert!(!mouse.push_stream_frame(&stream_frame()), "responses first");
    for want in [1, 2, 3] {
        assert_eq!(host.read(CONFIG_IN).map(|p| p[2]), Some(want));
        mouse.service([0; 3], LATER);
    }
    assert_eq!(host.read(CONFIG_IN), None, "the fourth was dropped");
    assert!(mouse.push_stream_frame(&stream_frame()));
    assert!(
        !mouse.push_stream_frame(&stream_frame()),
        "the endpoint is busy"
    );
    let p = host.read(CONFIG_IN).expect("a stream frame");
    assert_eq!(StreamFrame::decode(&p), Ok(stream_frame()));
}

#[test]
fn nothing_streams_to_a_host_that_is_not_listening_and_a_reset_empties_the_boxes() {
    let (host, alloc) = bus();
    let mut mouse = Mouse::new(alloc, imu_app::identity::SERIAL).expect("identity fits");
    mouse.service([0; 3], LATER);
    assert!(!mouse.push_stream_frame(&stream_frame()), "not configured");
    let mut mouse = {
        host.setup([0x00, 0x09, 1, 0, 0, 0, 0, 0]);
        for _ in 0..3 {
            mouse.service([0; 3], LATER);
        }
        mouse
    };
    host.send(CONFIG_OUT, &frame(1));
    mouse.service([0; 3], LATER);
    mouse.respond(frame(7));
    mouse.respond(frame(8));
    host.reset();
    mouse.service([0; 3], LATER);
    assert_eq!(mouse.take_request(), None, "the host that asked is gone");
    host.read(CONFIG_IN);
    mouse.service([0; 3], LATER);
    assert_eq!(
        host.read(CONFIG_IN),
        None,
        "no stale answer for the next host"
    );
}

#[test]
fn a_request_through_the_real_mouse_is_answered_on_its_in_endpoint() {
    use imu_app::commands::Commands;
    use imu_app::control::{self, Resources};
    use imu_app::stream::Stream;
    use imu_app::Status;
    use imu_core::profile::Profile;
    use imu_core::protocol::{Response, Source};
    use imu_core::Tracker;
    use rtic_core::Exclusive;

    let (host, alloc) = bus();
    let mut mouse = configured(&host, alloc);
    // Two mouse reports, read by the host on EP1.
    for dx in [3, 2] {
        mouse.service([dx, 0, 0], LATER);
        host.read(1).expect("a mouse report");
    }
    let p = Profile::default();
    let mut commands = Commands::new(p, Source::Defaults, None, 96_000_000);
    let mut tracker = Tracker::new(&p.config).expect("valid");
    let (mut status, mut route, mut stream) = (Status::new(20), p.map, Stream::default());
    let mut serve = |mouse: &mut Mouse<'static, ScriptBus>, req: Request, tag: u8| {
        host.send(CONFIG_OUT, &req.encode(tag));
        mouse.service([0; 3], LATER);
        let mut r = Resources {
            mouse: &mut Exclusive(mouse),
            commands: &mut Exclusive(&mut commands),
            tracker: &mut Exclusive(&mut tracker),
            status: &mut Exclusive(&mut status),
            route: &mut Exclusive(&mut route),
            stream: &mut Exclusive(&mut stream),
        };
        control::serve(&mut r, || 0);
        let answer = host.read(CONFIG_IN).expect("answered");
        Response::decode(&answer).expect("decodes")
    };
    let (tag, r) = serve(&mut mouse, Request::Counters, 4);
    let Response::Counters(c) = r else {
        panic!("{r:?}")
    };
    assert_eq!((tag, c.reports), (4, 3), "the opening report and the two");
    assert_eq!(c.counts, [5, 0], "the cursor's counts: 3 and 2 right");
    serve(&mut mouse, Request::StreamStart, 5);
    stream.push(&[[7, 8, 9]], 0);
    control::push_stream(&mut Exclusive(&mut mouse), &mut Exclusive(&mut stream));
    let f = host.read(CONFIG_IN).expect("a stream frame");
    assert_eq!(
        StreamFrame::decode(&f).map(|f| f.triples.to_vec()),
        Ok(vec![[7, 8, 9]])
    );
    assert_eq!(stream.frame(), None, "sent: off the queue");
}
