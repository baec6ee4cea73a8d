//! Frames to and from the page: a request built from the page's arguments and encoded by
//! [`imu_core::protocol`], and any frame the device sends decoded by it and written as JSON.

use core::fmt::{self, Write};

use imu_core::profile::Key;
use imu_core::protocol::{code, ErrorCode, Request, Response, Source, StreamFrame};

use crate::json::Json;

/// The request with code `c` (a [`code`] request), `arg` its one argument (`GET_CONFIG`'s
/// start, `SET_CONFIG`'s commit flag) and `pairs` `SET_CONFIG`'s `(key id, value)` pairs;
/// `None` for an unknown code, an unknown key id or more pairs than a frame holds.
pub fn request(c: u8, arg: u32, pairs: &[(f64, f64)]) -> Option<Request> {
    Some(match c {
        code::INFO => Request::Info,
        code::COUNTERS => Request::Counters,
        code::CALIBRATION => Request::Calibration,
        code::GET_CONFIG => Request::GetConfig {
            start: u8::try_from(arg).ok()?,
        },
        code::SET_CONFIG => {
            let mut v = heapless::Vec::new();
            for &(id, value) in pairs {
                // An id is a whole number 0..=255 (the cast saturates; the test rejects
                // fractions and anything out of range).
                let key = Key::from_id(id as u8).filter(|_| f64::from(id as u8) == id)?;
                v.push((key, value)).ok()?;
            }
            Request::SetConfig {
                commit: arg != 0,
                pairs: v,
            }
        }
        code::SAVE => Request::Save,
        code::DEFAULTS => Request::Defaults,
        code::RECALIBRATE => Request::Recalibrate,
        code::STREAM_START => Request::StreamStart,
        code::STREAM_STOP => Request::StreamStop,
        _ => return None,
    })
}

const fn source(s: Source) -> &'static str {
    match s {
        Source::Defaults => "defaults",
        Source::Stored => "stored",
        Source::Corrupt => "corrupt",
        Source::Invalid => "invalid",
        Source::Changed => "changed",
    }
}

/// `"code":"...","key":"..."` of a refusal (the key where the code names one).
fn refusal(j: &mut Json<'_>, e: ErrorCode) -> fmt::Result {
    let (what, key, detail) = match e {
        ErrorCode::Version(v) => ("version", None, Some(v)),
        ErrorCode::Command(c) => ("command", None, Some(c)),
        ErrorCode::Length => ("length", None, None),
        ErrorCode::UnknownKey(k) => ("unknown_key", None, Some(k)),
        ErrorCode::Value(k) => ("value", Some(k), None),
        ErrorCode::Invalid(k) => ("invalid", Some(k), None),
        ErrorCode::Unsupported(k) => ("unsupported", Some(k), None),
        ErrorCode::Storage => ("storage", None, None),
        ErrorCode::Busy => ("busy", None, None),
    };
    j.key("code")?;
    j.string(what)?;
    if let Some(k) = key {
        j.raw(",")?;
        j.key("key")?;
        j.string(k.name())?;
    }
    if let Some(d) = detail {
        write!(j, ",\"detail\":{d}")?;
    }
    Ok(())
}

fn response(j: &mut Json<'_>, tag: u8, r: &Response) -> fmt::Result {
    write!(j, "{{\"tag\":{tag},")?;
    match r {
        Response::Info(i) => {
            let [a, b, c] = i.firmware;
            write!(
                j,
                "\"info\":{{\"firmware\":\"{a}.{b}.{c}\",\"protocol\":{},\"source\":\"{}\",\
                 \"invalid_key\":{},\"fs_hz\":{},",
                i.protocol,
                source(i.source),
                i.invalid_key,
                i.fs_hz
            )?;
            j.key("tracking")?;
            j.boolean(i.tracking)?;
            j.raw(",")?;
            j.key("streaming")?;
            j.boolean(i.streaming)?;
            j.raw("}")?;
        }
        Response::Counters(c) => write!(
            j,
            "\"counters\":{{\"samples\":{},\"lost\":{},\"restarts\":{},\"reports\":{},\
             \"rejected_windows\":{},\"stream_frames\":{},\"stream_lost\":{},\
             \"counts\":[{},{}],\"tracker\":\"{}\"}}",
            c.samples,
            c.lost,
            c.restarts,
            c.reports,
            c.rejected_windows,
            c.stream_frames,
            c.stream_lost,
            c.counts[0],
            c.counts[1],
            c.tracker.name()
        )?,
        Response::Calibration(None) => j.raw("\"calibration\":null")?,
        Response::Calibration(Some(axes)) => {
            j.raw("\"calibration\":[")?;
            for (n, a) in axes.iter().enumerate() {
                if n > 0 {
                    j.raw(",")?;
                }
                j.raw("{\"bias_lsb\":")?;
                j.number(a.bias_q16 as f64 / 65_536.0)?;
                j.raw(",\"noise_lsb\":")?;
                j.number(f64::from(a.noise_rms_q16) / 65_536.0)?;
                j.raw("}")?;
            }
            j.raw("]")?;
        }
        Response::Config {
            total,
            start,
            pairs,
        } => {
            write!(
                j,
                "\"config\":{{\"total\":{total},\"start\":{start},\"pairs\":["
            )?;
            for (n, (k, v)) in pairs.iter().enumerate() {
                if n > 0 {
                    j.raw(",")?;
                }
                write!(j, "[{},", *k as u8)?;
                j.number(*v)?;
                j.raw("]")?;
            }
            j.raw("]}")?;
        }
        Response::Staged { count, applied } => {
            write!(j, "\"staged\":{{\"count\":{count},\"applied\":")?;
            j.boolean(*applied)?;
            j.raw("}")?;
        }
        Response::Done(c) => write!(j, "\"done\":{c}")?,
        Response::Stopped { frames, lost } => {
            write!(j, "\"stopped\":{{\"frames\":{frames},\"lost\":{lost}}}")?;
        }
        Response::Error(e) => {
            j.raw("\"error\":{")?;
            refusal(j, *e)?;
            j.raw("}")?;
        }
    }
    j.raw("}")
}

fn stream(j: &mut Json<'_>, s: &StreamFrame) -> fmt::Result {
    write!(
        j,
        "{{\"stream\":{{\"seq\":{},\"lost\":{},\"codes\":[",
        s.seq, s.lost
    )?;
    for (n, [x, y, z]) in s.triples.iter().enumerate() {
        if n > 0 {
            j.raw(",")?;
        }
        write!(j, "[{x},{y},{z}]")?;
    }
    j.raw("]}}")
}

/// Any frame from the device as JSON: `{"stream":{seq, lost, codes}}` for raw codes,
/// `{"tag":T, KIND: ...}` for a response (`info`, `counters`, `calibration`, `config`,
/// `staged`, `done`, `stopped`, `error`), `{"bad":"..."}` for one that does not decode.
pub fn decode(j: &mut Json<'_>, frame: &[u8]) -> fmt::Result {
    let is_stream = matches!(frame.get(1), Some(&(code::STREAM | code::STREAM_WIDE)));
    if is_stream {
        return match StreamFrame::decode(frame) {
            Ok(s) => stream(j, &s),
            Err(e) => write!(j, "{{\"bad\":\"{e:?}\"}}"),
        };
    }
    match Response::decode(frame) {
        Ok((tag, r)) => response(j, tag, &r),
        Err(e) => write!(j, "{{\"bad\":\"{e:?}\"}}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use imu_core::protocol::{Counters, Info};

    fn json_of(frame: &[u8]) -> String {
        let mut b = [0u8; 4096];
        let mut j = Json::new(&mut b);
        decode(&mut j, frame).expect("fits");
        let n = j.len();
        String::from_utf8(b[..n].to_vec()).expect("UTF-8")
    }

    #[test]
    fn requests_are_the_cores_frames() {
        let r = request(code::SET_CONFIG, 1, &[(5.0, 1600.0)]).expect("a request");
        let (tag, back) = Request::decode(&r.encode(9)).expect("decodes");
        assert_eq!(tag, 9);
        assert_eq!(back, r);
        // A fraction, an unknown id, seven pairs, an unknown code: no frame.
        assert_eq!(request(code::SET_CONFIG, 1, &[(7.5, 1.0)]), None);
        assert_eq!(request(code::SET_CONFIG, 1, &[(250.0, 1.0)]), None);
        assert_eq!(request(code::SET_CONFIG, 0, &[(7.0, 1.0); 7]), None);
        assert_eq!(request(0x7F, 0, &[]), None);
    }

    #[test]
    fn responses_and_refusals_read_as_json() {
        let info = Response::Info(Info {
            firmware: [0, 3, 1],
            protocol: 1,
            source: Source::Stored,
            invalid_key: 0,
            fs_hz: 3000,
            tracking: true,
            streaming: false,
        });
        assert_eq!(
            json_of(&info.encode(4)),
            "{\"tag\":4,\"info\":{\"firmware\":\"0.3.1\",\"protocol\":1,\"source\":\"stored\",\
             \"invalid_key\":0,\"fs_hz\":3000,\"tracking\":true,\"streaming\":false}}"
        );
        let refused = Response::Error(ErrorCode::Invalid(Key::CountsPerInch));
        assert_eq!(
            json_of(&refused.encode(5)),
            "{\"tag\":5,\"error\":{\"code\":\"invalid\",\"key\":\"counts_per_inch\"}}"
        );
        let c = Response::Counters(Counters {
            samples: 1 << 40,
            ..Counters::default()
        });
        assert!(json_of(&c.encode(6)).contains("\"samples\":1099511627776"));
        let c = Response::Counters(Counters {
            counts: [-3, i64::MAX],
            tracker: imu_core::protocol::TrackerState::Frozen,
            ..Counters::default()
        });
        assert!(json_of(&c.encode(6))
            .contains("\"counts\":[-3,9223372036854775807],\"tracker\":\"frozen\"}"));
        assert_eq!(json_of(&[1, 2]), "{\"bad\":\"Truncated\"}");
    }

    #[test]
    fn stream_frames_carry_their_codes() {
        let mut triples = heapless::Vec::new();
        triples.push([1, 4095, 2048]).expect("room");
        triples.push([7, 8, 9]).expect("room");
        let f = StreamFrame {
            seq: 3,
            lost: 1,
            triples,
            wide: false,
        };
        assert_eq!(
            json_of(&f.encode()),
            "{\"stream\":{\"seq\":3,\"lost\":1,\"codes\":[[1,4095,2048],[7,8,9]]}}"
        );
    }
}
