//! Lift: the device leaves the desk. Tracking stops, as an optical mouse's does, until it
//! rests again; then the zero is taken anew if it differs (set down on a slope).
//!
//! # Displacement, not acceleration (REFERENCE (j))
//! A lift of `h` rising in `T_r` peaks at only `5.77 h / T_r^2` on Z (3 mm in 0.25 s: 0.28
//! m/s^2, the size of a knock's or a machine's acceleration), but it moves the device by
//! millimetres; a knock flexes the desk by 20-200 um and returns, a machine's 50 mg at 30 Hz
//! moves it by 14 um. So the test is on the vertical displacement over the last `W` ticks
//! from rest, each tick taken at its centre:
//!
//! ```text
//! 2 d = D sum_{j < W} (2 j + 1) (s[t-j] 2^16 - D z)  = D ((2 R1 + R0) 2^16 - D z W^2)
//! R0 = sum_j s[t-j],  R1 = sum_j j s[t-j]   (running: R1 += R0 - W s[t-W], R0 += s[t] - s[t-W])
//! Var(2 d) = 4/3 q (W D)^3 + q (W D)^4 / N_b
//! ```
//!
//! (exact integer sums of raw codes in Q16 LSB samples^2; the zero `z` subtracted when
//! used). A lift is `|2 d_z| > K_LIFT sd(2 d_z) + r (|2 d_x| + |2 d_y|) + allowance`, for
//! `P` ticks in a row:
//!
//! - `W = 0.6 T_r` for the slowest rise `T_r` ([`super::Drift::lift_rise_s`]): the window that
//!   maximises a minimum-jerk rise's displacement over the noise's `W^1.5` (the maximum of
//!   `step(u) / u^1.5` is at `u = 0.605`). ADXL335, 0.5 s: sd 0.21 mm, the threshold 1.1 mm
//!   against 2.0 mm from a 3 mm lift;
//! - `K_LIFT` from the false-start budget: one false lift per [`super::Drift::false_start_hours`],
//!   each window of `W` ticks an independent two-sided chance (5.2 sd for 10^4 h);
//! - `r = sin(mount_tilt_deg)`: the share of a horizontal displacement that a tilted
//!   mounting or cross-axis sensitivity puts on Z;
//! - the allowance: twice what the measured disturbance can move the device over the window
//!   ([`super::noise`]): its velocity amplitude carried over the window (a window that starts
//!   inside a knock's ring does not start at rest) and its displacement amplitude;
//! - `P = 1 / (2 knock_hz)` (25 ms): a knock's flex returns within half a ring's period; a
//!   lift stays up.
//!
//! # Landing
//! Lifted, nothing is integrated. A hand holds a lifted mouse still in the air as well as on
//! the desk, so a landing must follow a fall: the vertical velocity, integrated from the lift
//! window's start, turning against the rise by `K_LIFT` of its sd `sqrt(q n (1 + n / N_b))` (a
//! fall is the rise's mirror image: as fast, as visible), or, for a set-down too gentle to be
//! seen, the longest stroke's time since the lift. A lift seen going down is its own fall: a
//! device goes down only from above the desk, after a rise too slow for the test (5 mm over 1.2
//! s) or a landing taken in the air (a rotation in the hand takes `g (1 - cos theta)` off Z,
//! which the velocity test reads as a fall, and the device held still there rests at a level
//! gravity gives); waiting for the device to rise and fall again, it stayed lifted for the
//! longest stroke's time after the set-down, and a stroke 0.5 s after it was lost (down is -Z:
//! the sensor's Z reads +g at rest, as the gravity test below assumes). Then, once the last
//! eighth of the longest stroke (0.25 s, in blocks, [`super::tilt`]) is steady on every axis
//! (its thirds agree within `K_TILT` sd plus what the disturbance measured now can put into
//! their means, below), the device rests: the zeros become that window's middle third's means
//! if any differs from the old zero by more than its noise allows (set down on a slope), and
//! stay otherwise. The middle third, not the last: while lifted no start test runs, and a
//! stroke begun in the last third's final milliseconds leaves it steady with the others but
//! moves its means (a new user's stroke begun 10 ms before a landing at the timeout: 1.2 LSB on
//! X and Y, a zero from which the stroke never came to rest, delivered 4.1 m off); the thirds
//! agree, so the middle one's level is the last's within their test. The lift test then waits
//! `W` ticks, until its window holds only ticks at the new zero. A new zero is a tilt's in all
//! but name (a level from 83 ms, on a pad that may settle), so a motion within the longest
//! stroke after it is wary as after a tilt's ([`super::tilt`]): held until its acceleration
//! reverses, as a hand's does and a zero's error never does. Without it, the lab's lifts (seed
//! 14, trial 29: set down on a 4.8 degree slope, the zero about 1 LSB off on X) started a
//! motion on that offset 0.3 s later and delivered 12 mm before the hold held it.
//!
//! # A landing in doubt
//! A rotation in the hand moves Z without any motion: `g (1 - cos theta)` off it, and up to
//! `r |delta_h|` either way for the old rest's orientation within `mount_tilt_deg` of Z
//! (the gravity test's relation below, tick by tick). The fall test integrates that as a
//! fall (8 degrees: 0.095 m/s^2, past its bound within 0.3 s). So a fall is *sure* only if the
//! velocity is past its bound by what a rotation can put into it: `|o|^2 / (2 g)` summed over
//! the lift's ticks (`o` a tick's offsets from the zeros), and `r (|v_x| + |v_y|)` for the
//! horizontal velocities `v` since the window's start. The old rest's orientation `u0` is
//! fixed over the lift, so what it puts into Z's velocity is `u0 . v`, at most `r` of the
//! velocity, not of every tick's acceleration summed: a carry's two ends cancel (summed,
//! a 50 mm carry over 0.3 s put 54 mm/s into the bound after it ended, and a re-placement
//! onto a 3 degree slope whose 20 mm fall came then was in doubt). A fall
//! that is not sure still lands the device: a gentle fall onto a slope is seen only through
//! its own tilt (4 mm over 0.52 s peaks at 14.5 mm/s, under the bound's 18), and at rest
//! the sensor cannot tell it from a tilt held still in the air. Such a landing is *in doubt*.
//! If it was in the air (a new user's lifts, tilted 8-10 degrees in the hand, held, and
//! turned back as they were set down: 5 of 24 lost the stroke after them), the set-down
//! turns the device back and goes down, and the lift test reads it either way: as a rise
//! (the window begins mid-descent and sees only its end, the rotation's horizontal share
//! having hidden the rest), or as a descent. So while the motions after a landing in doubt
//! are wary (the longest stroke's time, [`super::tilt`]):
//! - a lift seen going up whose window turned (X or Y past `K_TILT` sd of its sum) is its
//!   own fall; a rise straight up turns nothing and waits for its fall (the lab's lifts,
//!   seed 6, trial 108: a second lift 2 s after a landing in doubt otherwise landed in the
//!   air and sent its set-down's tilt out as 7.4 mm);
//! - the gravity test allows `(|dx| + |dy|) / g` more than `r`, the doubtful zero's own turn
//!   from the one before: its orientation is not the desk's within `r` (a set-down from an
//!   8 degree zero onto a 3.8 degree slope otherwise waited for the longest stroke's time).
//!
//! A landing after a sure fall leaves the next lift to wait for its own: a hand that lifts
//! while carrying sideways also turns the window's X, and pausing in the air it would land
//! there and send the rest of the carry out. The same for a lift after the wary time.
//!
//! The same doubt holds the motions: one that starts while the motions after a landing in
//! doubt are wary may be a carry in the air (a hand that holds the device still and tilted
//! there, then carries it: a new user's hovers tilted 4 degrees or more, 12 of 32 sent their
//! carry out as a stroke, 23-97 mm). It is held until it stops, whatever its acceleration
//! does ([`super::tilt`] releases a wary one when it reverses), and what it moved stays held
//! at rest for the slowest rise plus `P` (`LiftSettings::seen`, 0.53 s by default): a
//! set-down begun as it stopped has been seen by then, if it is to be. A lift seen meanwhile
//! drops it (the set-down, its own fall as above); otherwise it is delivered whole. The
//! cost: a stroke on the desk after a gentle set-down in doubt arrives at its stop plus
//! that time, not as it is made (the lab's after-tilt strokes: about one in ten, 0.6 s later
//! at the median; a tester's after lifts: most were held to their end already). A device set
//! down level after a lift keeps its zero and is not wary; nor is what follows it.
//!
//! # The desk's disturbance
//! The thirds' test and the gravity test below allow for what the disturbance measured as
//! they decide ([`super::noise`]) can put into their means: a machine shaking the desk. Not
//! the one measured at the lift (until the eighteenth stop, lest the fall's own motion count
//! as the desk's): a rise's motion counts there, its residual above `knock_hz` measured as a
//! disturbance. A new user's 14 mm lift rising in 0.16 s read as 17 LSB a sample on Z; its
//! gentle flat set-down's thirds (a 0.49 s descent) then passed as steady 94 ms after it,
//! the descent's tail in them, the Z zero came out 5.7 LSB off, a false lift followed 0.3 s
//! later, and the stroke 1.9 s after the set-down was lost with it. And a machine started
//! while the device was in the air was not allowed for at all: its shaking kept the thirds
//! apart, and the device landed 0.6 to 1.5 s after the set-down instead of 0.26 s. A gentle
//! fall's own motion measured now has not mattered in any scene: of the lab's lifts on seeds
//! 1-21 one trial moved (0.16 mm closer), and a tester's 80 re-placements stayed at 0 mm.
//!
//! # Gravity at rest
//! The thirds' test compares three means; a fall's accelerations can average alike over
//! them while the device still moves (the lab's `lifts:50`, seed 1: Z 8 LSB below its zero
//! in each third, 56 ms before the fall ended; the zero taken there ran the cursor 34 mm).
//! At rest the sensor measures gravity alone, whatever the orientation: from the old rest
//! `g u0` to the new `g u1 = g u0 + delta`, `|u1| = 1` gives `u0 . delta = -|delta|^2 / (2 g)`.
//! With `u0` within `mount_tilt_deg` of the sensor's Z (mounting and slope together, `r` of
//! the lift test; the hand model's pads slope up to 5 degrees), `|delta_z + |delta|^2 / (2 g)| <= r (|delta_x| + |delta_y|)` (the
//! `1 - cos` term, under 0.4 % of `delta_z` within 5 degrees, left out). So a level is a
//! rest only if its Z is within `K_TILT` sd of `-|delta|^2 / (2 g)` (g from the configured
//! scale) past that allowance and the desk's disturbance; a landing at any other level
//! waits. A level gravity cannot give that lasts (a pad steeper than `r` allows, a scale
//! configured far off) is taken once the longest stroke's time has passed since the lift,
//! as a set-down without a fall is: the cursor is dead for at most that long.
//!
//! A hand may move the device before the window is steady (a stroke begun 0.1 to 0.25 s
//! after the set-down would otherwise stay Lifted until it ends, and be lost). So when, the
//! fall seen, the window is not steady, but its first two thirds agree on every axis and its
//! last third agrees with them on Z and not on X or Y (the device rests on the desk, and
//! moves along it), and gravity gives the first two thirds' level, the device landed: the
//! zeros become those thirds' means if they differ from the old ones by more than their noise
//! allows, and a motion starts from zero velocity at the last third
//! ([`super::Action::Land`]), wary as after a tilt's new zero (held until its acceleration
//! reverses: a pad still settling never does, [`super::tilt`]). It needs two thirds of the
//! window at rest, 0.17 s: a stroke begun sooner after the set-down is still lost.

use super::noise::within;
use super::ticks::offset_q16;
use super::{Action, Detector, DriftSettings, State, RING};

/// Standard gravity [m/s^2]: what a device at rest measures, whatever its orientation.
const G_M_S2: f64 = 9.80665;

/// The lift test's coefficients.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LiftSettings {
    /// Window `W` [ticks].
    pub(crate) window: u32,
    /// Persistence `P` [ticks].
    pub(crate) persist: u32,
    /// `K_LIFT^2` [Q8].
    pub(crate) k2_q8: u64,
    /// Mounting ratio `r` [Q16]: at most `sin 30 deg`, 2^15.
    pub(crate) mount_q16: u32,
    /// The window's samples cubed, `n^3` (`n = W D`) [samples^3]: below `2^38`.
    pub(crate) cube: u64,
    /// `floor(4 n^3 / 3)` [samples^3], the integrated noise's term of the test's variance.
    pub(crate) cube_4_3: u64,
    /// Twice the standard gravity, `2 g` [Q16 LSB]: the rest's gravity test.
    pub(crate) two_g_q16: u64,
    /// The slowest rise plus `P` [ticks], at most 120 (a rise of 0.5 s at 5 ms ticks, and
    /// `P` for `knock_hz` 5): by then a set-down begun as a motion stopped has been seen, if
    /// it is to be (module docs, "A landing in doubt").
    pub(crate) seen: u8,
}

impl LiftSettings {
    /// The coefficients for the slowest rise `rise_s` and a window of `window_s` (that rise
    /// times the tuning's fraction), `knock_hz`, `mount_tilt_deg`, a budget of `hours`
    /// between false lifts, at ticks of `tick_s` seconds and `tick` samples, and a scale of
    /// `m_s2_per_lsb`; `None` if the window would not fit the tick ring.
    pub(crate) fn new(
        (rise_s, window_s): (f64, f64),
        knock_hz: f64,
        mount_tilt_deg: f64,
        hours: f64,
        (tick_s, tick): (f64, u32),
        m_s2_per_lsb: f64,
    ) -> Option<Self> {
        use crate::math::round_to_u64 as round;
        let window = round(window_s / tick_s).max(2) as u32;
        if window as usize >= RING {
            return None;
        }
        let persist = libm::ceil(0.5 / knock_hz / tick_s).max(1.0) as u32;
        let chances = hours * 3600.0 / (f64::from(window) * tick_s);
        let k = super::z_of_tail(0.5 / chances);
        let mount = libm::sin(mount_tilt_deg.clamp(0.0, 30.0).to_radians());
        // n < RING ticks of at most 100 samples (20 kHz): n^3 < 2^38, 4 n^3 < 2^40.
        let n = u64::from(window) * u64::from(tick);
        Some(Self {
            window,
            persist,
            k2_q8: round(k * k * 256.0),
            mount_q16: round(mount * 65_536.0) as u32,
            cube: n * n * n,
            cube_4_3: 4 * n * n * n / 3,
            two_g_q16: round(2.0 * G_M_S2 / m_s2_per_lsb * 65_536.0),
            seen: u8::try_from(round(rise_s / tick_s).saturating_add(u64::from(persist)))
                .unwrap_or(u8::MAX),
        })
    }
}

/// The lift test's state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Lift {
    r0: [u64; 3],
    r1: [u64; 3],
    /// Ticks in a row past the threshold, and the sign of the displacement.
    above: u32,
    sign: i8,
    /// While lifted: the rise's sign, whether the fall has been seen, and the velocity on
    /// each axis since the lift window's start [Q16 LSB samples] (over `(W + age) D`
    /// samples): Z's is the fall test's, X's and Y's what the old rest's orientation can put
    /// into it.
    rise: i8,
    fell: bool,
    v: [i64; 3],
    /// Ticks before the window holds only ticks at the current zeros.
    wait: u32,
    /// While lifted: whether the fall was seen past what a rotation can put into the vertical
    /// velocity, and the curvature's share of it, summed over the lift's ticks [Q16 LSB
    /// samples] (module docs, "A landing in doubt").
    sure: bool,
    curv: u64,
    /// Whether the current zeros are a landing's whose fall was not sure: then, while the
    /// motions after it are wary (`Detector::tilted_until`), a lift seen going up and turning
    /// is its own fall (module docs).
    doubt: bool,
    /// How far that landing turned the zeros, `(|dx| + |dy|) / g` [Q12]: what the gravity
    /// test allows beyond `r` while a lift that began in doubt lands.
    doubt_tilt_q12: u16,
}

impl Lift {
    /// Whether the current zeros are a landing's in doubt (module docs).
    pub(crate) const fn in_doubt(&self) -> bool {
        self.doubt
    }

    /// Takes the tick just closed into the running sums.
    pub(crate) fn update(&mut self, l: &LiftSettings, stream: &super::ticks::TickStream) {
        let w = u64::from(l.window);
        for a in 0..3 {
            let leaving = u64::from(stream.code(w + 1, a));
            let entering = u64::from(stream.code(1, a));
            self.r1[a] = self.r1[a] + self.r0[a] - w * leaving;
            self.r0[a] = self.r0[a] + entering - leaving;
        }
        self.wait = self.wait.saturating_sub(1);
    }

    /// The window's sums from the stream's ring (at the start).
    pub(crate) fn refill(&mut self, l: &LiftSettings, stream: &super::ticks::TickStream) {
        let w = u64::from(l.window);
        self.r0 = [0; 3];
        self.r1 = [0; 3];
        for j in 0..w {
            for a in 0..3 {
                let c = u64::from(stream.code(j + 1, a));
                self.r0[a] += c;
                self.r1[a] += j * c;
            }
        }
        self.above = 0;
    }
}

/// The thirds of the last `m` blocks on one axis: their offsets from `bias` [Q16 LSB
/// samples] and their lengths [samples], oldest first.
fn thirds(d: &Detector, s: &DriftSettings, axis: usize, m: u32, bias: i64) -> [(i64, u64); 3] {
    let cut = [m, m - m / 3, m / 3, 0];
    core::array::from_fn(|j| {
        // Blocks back: from cut[j + 1] + 1 to cut[j] inclusive.
        let (from, to) = (cut[j + 1] + 1, cut[j] + 1);
        let n = u64::from(to - from) * u64::from(s.block) * u64::from(s.tick);
        (offset_q16(d.stream.blocks_sum(axis, from, to), n, bias), n)
    })
}

/// `|delta|^2 / (2 g) n` for the offsets `o` of `n` samples each [Q16 LSB samples]: what a
/// rotation with no motion takes off Z's sum (module docs, "Gravity at rest"). In 64 bits: the
/// means in Q8 (a 16-bit code's below 2^24, their squares' sum below 2^50), 2 g in Q8.
fn curvature(l: &LiftSettings, o: [i64; 3], n: u64) -> u64 {
    let square = |oa: &i64| {
        let q8 = crate::math::div_round(*oa, n as i64).unsigned_abs() >> 8;
        q8.saturating_mul(q8)
    };
    let sum = o.iter().map(square).fold(0u64, u64::saturating_add);
    crate::math::div_u64(sum, (l.two_g_q16 >> 8).max(1))
        .saturating_mul(256)
        .saturating_mul(n)
}

/// What the old rest's orientation within `mount_tilt_deg` of Z can put into Z's velocity,
/// either way, for horizontal velocities `v` [Q16 LSB samples]: `r (|v_x| + |v_y|)` (module
/// docs, "A landing in doubt").
fn leak(l: &LiftSettings, v: [i64; 3]) -> u64 {
    (v[0].unsigned_abs().saturating_add(v[1].unsigned_abs())).saturating_mul(u64::from(l.mount_q16))
        >> 16
}

impl Detector {
    /// `2 d` on `axis` [Q16 LSB samples^2]: below `2^71`.
    fn displacement2(&self, s: &DriftSettings, l: &LiftSettings, axis: usize, z: i64) -> i128 {
        let d = i128::from(s.tick);
        let w = i128::from(l.window);
        let r = 2 * i128::from(self.lift.r1[axis]) + i128::from(self.lift.r0[axis]);
        d * ((r << 16) - d * i128::from(z) * w * w)
    }

    /// Whether the device has left the desk (see the module docs); records the rise's sign.
    pub(crate) fn lifted(&mut self, s: &DriftSettings, bias: [i64; 3]) -> bool {
        let Some(l) = s.lift else {
            return false;
        };
        if self.lift.wait > 0 {
            return false;
        }
        let up = self.vertical_past_bound(s, &l, bias);
        if up {
            self.lift_begins(s, &l, bias);
        }
        up
    }

    /// A lift found: records its sign, whether it is its own fall, and the vertical velocity
    /// and rotation allowance of its window. Out of line: the per-tick path at rest stays as
    /// it was.
    #[cold]
    #[inline(never)]
    fn lift_begins(&mut self, s: &DriftSettings, l: &LiftSettings, bias: [i64; 3]) {
        self.lift.rise = self.lift.sign;
        // Going down, the device was above the desk: this is its fall. Going up and turning
        // soon after a landing whose fall was not sure, it may have landed in the air, and its
        // set-down reads as a rise (module docs).
        let n = u64::from(l.window) * u64::from(s.tick);
        let o: [i64; 3] =
            core::array::from_fn(|a| super::ticks::offset(self.lift.r0[a], n, bias[a]));
        let turning =
            (0..2).any(|a| !within(o[a], self.noise[a].var(n, self.bias_samples), s.k2_q8, 0));
        let down = self.lift.sign < 0;
        let doubt = self.lift.doubt && self.stream.ticks() < self.tilted_until;
        self.lift.fell = down || (turning && doubt);
        self.lift.sure = down;
        self.lift.doubt = false;
        if !doubt {
            self.lift.doubt_tilt_q12 = 0;
        }
        self.lift.v = o;
        self.lift.curv = curvature(l, o, n);
    }

    /// The lift test: whether the vertical displacement has been past its bound for `P`
    /// ticks in a row (its sign in `lift.sign`).
    fn vertical_past_bound(&mut self, s: &DriftSettings, l: &LiftSettings, bias: [i64; 3]) -> bool {
        let [x, y, z] = core::array::from_fn(|a| self.displacement2(s, l, a, bias[a]));
        let n = u128::from(l.window) * u128::from(s.tick);
        // 4/3 q n^3 + q n^4 / N_b, in the squared units of 2 d (the cubes from the settings:
        // no 128-bit division per tick); asked for only past the horizontal and the
        // allowance.
        let var = || {
            let q = u128::from(self.noise[2].q_q32);
            q.saturating_mul(u128::from(l.cube_4_3)).saturating_add(
                q.saturating_mul(u128::from(crate::math::div_u64(
                    l.cube,
                    self.bias_samples.max(1),
                )))
                .saturating_mul(n),
            )
        };
        let horizontal =
            (x.unsigned_abs() + y.unsigned_abs()).saturating_mul(u128::from(l.mount_q16)) >> 16;
        // A disturbance's velocity at the window's start carried over the window (its start is
        // not at rest when it starts inside a ring), plus its displacement: peak to peak.
        let dz = &self.disturbance[2];
        let g = dz.gains(s);
        // Nothing without a disturbance (both terms are multiples of its amplitude).
        let allow = if dz.amp_q16 == 0 {
            0
        } else {
            let v = u128::from(dz.allow(g.velocity_q16, 1));
            u128::from(g.displacement)
                .saturating_mul(u128::from(dz.amp_q16))
                .saturating_add(v.saturating_mul(4 * n))
        };
        // |z| > K sd + horizontal + allow, compared in squares: no square root per tick.
        let past = match z
            .unsigned_abs()
            .checked_sub(horizontal.saturating_add(allow))
        {
            None | Some(0) => false,
            Some(e) => e
                .checked_mul(e)
                .is_none_or(|e2| e2 > var().saturating_mul(u128::from(l.k2_q8)) >> 8),
        };
        let sign = z.signum() as i8;
        if past && (self.lift.above == 0 || sign == self.lift.sign) {
            self.lift.above += 1;
            self.lift.sign = sign;
        } else if past {
            self.lift.above = 1;
            self.lift.sign = sign;
        } else {
            self.lift.above = 0;
        }
        self.lift.above >= l.persist
    }

    /// Lifted, at a tick's end: wait for the fall, then until steady, then rest (at a new
    /// zero if it differs).
    pub(crate) fn lifted_tick(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        if let Some(l) = s.lift {
            let d = u64::from(s.tick);
            let o: [i64; 3] = core::array::from_fn(|a| {
                super::ticks::offset(u64::from(self.stream.code(1, a)), d, bias[a])
            });
            for (v, oa) in self.lift.v.iter_mut().zip(o) {
                *v += oa;
            }
            self.lift.curv = self.lift.curv.saturating_add(curvature(&l, o, d));
            let n = (u64::from(l.window) + self.age()) * d;
            let var = self.noise[2].var(n, self.bias_samples);
            let down = -i64::from(self.lift.rise) * self.lift.v[2];
            if down > 0 && !within(down, var, l.k2_q8, 0) {
                self.lift.fell = true;
                let turn = leak(&l, self.lift.v).saturating_add(self.lift.curv);
                self.lift.sure |= !within(down, var, l.k2_q8, turn);
            }
            if !self.lift.fell && self.age() < u64::from(s.land_timeout) {
                return Action::None;
            }
        }
        let m = s.land_blocks;
        let blocks = u64::from(m) * u64::from(s.block);
        if !self.stream.block_closed() || self.age() < blocks {
            return Action::None;
        }
        let mut level = bias;
        let mut moved = false;
        let mut n_level = 0;
        let mut last = [(0, 0); 3];
        for (a, b) in bias.iter().enumerate() {
            let t = thirds(self, s, a, m, *b);
            let noise = &self.noise[a];
            if !(self.steady(s, a, t, 0, 1) && self.steady(s, a, t, 1, 2)) {
                return if self.lift.fell {
                    self.hand_on_landing(s, bias)
                } else {
                    Action::None
                };
            }
            // The middle third (see the module docs); gravity's test on the last.
            let (o, n) = t[1];
            last[a] = t[2];
            n_level = n;
            moved |= !within(o, noise.var(n, self.bias_samples), s.k2_q8, 0);
            level[a] = *b + crate::math::div_round(o, n as i64);
        }
        if !s.lift.is_none_or(|l| self.rests_on_gravity(s, &l, last)) {
            return Action::None;
        }
        self.enter_still();
        self.landed(s, bias, if moved { level } else { bias });
        if moved {
            self.tilted(s);
            self.bias_samples = n_level;
            Action::Rebias {
                bias: level,
                discard: false,
            }
        } else {
            self.lift_wait(s);
            Action::Stop
        }
    }

    /// Whether a level `o` (per axis: offset sums from `bias` [Q16 LSB samples] over their
    /// samples) is one gravity can give a device at rest (see the module docs): `o_z` within
    /// `K_TILT` sd of `-|o|^2 / (2 g n)`, allowing `r (|o_x| + |o_y|)` for the old rest's
    /// orientation and the desk's disturbance. After the longest stroke's time since the
    /// lift, any level is.
    fn rests_on_gravity(&self, s: &DriftSettings, l: &LiftSettings, o: [(i64, u64); 3]) -> bool {
        if self.age() >= u64::from(s.land_timeout) {
            return true;
        }
        let n = o[2].1;
        let curvature = i64::try_from(curvature(l, o.map(|(oa, _)| oa), n)).unwrap_or(i64::MAX);
        let r = u64::from(l.mount_q16) + (u64::from(self.lift.doubt_tilt_q12) << 4);
        let turn =
            (o[0].0.unsigned_abs().saturating_add(o[1].0.unsigned_abs())).saturating_mul(r) >> 16;
        let allow = turn.saturating_add(self.desk_allowance(s, 2, n));
        within(
            o[2].0.saturating_add(curvature),
            self.noise[2].var(n, self.bias_samples),
            s.k2_q8,
            allow,
        )
    }

    /// What the desk's disturbance, as measured now, can put into a mean of `n` samples on
    /// `axis` [Q16 LSB samples] (see the module docs).
    fn desk_allowance(&self, s: &DriftSettings, axis: usize, n: u64) -> u64 {
        let d = &self.disturbance[axis];
        d.allow(
            d.gains(s).land_q16,
            crate::math::div_u64(n, u64::from(s.tick)),
        )
    }

    /// Whether thirds `i` and `j` of `t` on `axis` agree (see the module docs).
    fn steady(
        &self,
        s: &DriftSettings,
        axis: usize,
        t: [(i64, u64); 3],
        i: usize,
        j: usize,
    ) -> bool {
        let ((oi, ni), (oj, nj)) = (t[i], t[j]);
        // The difference of two means, compared over the shorter length.
        let n = ni.min(nj);
        let di = crate::math::div_round(oi, ni as i64) * n as i64;
        let dj = crate::math::div_round(oj, nj as i64) * n as i64;
        let allow = self.desk_allowance(s, axis, n);
        within(
            di - dj,
            self.noise[axis].var(2 * n, u64::MAX),
            s.k2_q8,
            2 * allow,
        )
    }

    /// Landed and at once moved (see the module docs): the landing window's first two
    /// thirds agree on every axis, its last third on Z but not on X or Y. The zeros become the
    /// first two thirds' means if those differ from the old ones, and a motion starts at the
    /// last third, wary.
    fn hand_on_landing(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        let m = s.land_blocks;
        let mut early = bias;
        let mut n_early = 0;
        let mut changed = false;
        let mut differs = false;
        let mut level = [(0, 0); 3];
        for (a, b) in bias.iter().enumerate() {
            let t = thirds(self, s, a, m, *b);
            if !self.steady(s, a, t, 0, 1) {
                return Action::None;
            }
            let (o, n) = (t[0].0 + t[1].0, t[0].1 + t[1].1);
            level[a] = (o, n);
            early[a] = *b + crate::math::div_round(o, n as i64);
            n_early = n;
            differs |= !within(o, self.noise[a].var(n, self.bias_samples), s.k2_q8, 0);
            let moved = !self.steady(s, a, t, 1, 2);
            if moved && a == 2 {
                return Action::None;
            }
            changed |= moved;
        }
        let rests = s.lift.is_none_or(|l| self.rests_on_gravity(s, &l, level));
        if !changed || !rests {
            return Action::None;
        }
        self.enter_still();
        self.tilted(s);
        let zero = if differs {
            self.bias_samples = n_early;
            early
        } else {
            bias
        };
        self.landed(s, bias, zero);
        let back = u64::from(m / 3) * u64::from(s.block);
        let onset = self.stream.ticks() - back.min(self.stream.ticks());
        match self.start(s, onset, false, false, false, zero) {
            Action::Start { blocks, .. } => Action::Land { bias: zero, blocks },
            other => other,
        }
    }

    /// Landed at the zeros `to` (from `from`): after a fall that was not sure, the landing is
    /// in doubt (module docs). The tilt's refinements of its zero keep the doubt; the next
    /// landing decides anew.
    fn landed(&mut self, s: &DriftSettings, from: [i64; 3], to: [i64; 3]) {
        self.lift.doubt = !self.lift.sure;
        let Some(l) = s.lift.filter(|_| self.lift.doubt) else {
            return;
        };
        let turned = (to[0] - from[0])
            .unsigned_abs()
            .saturating_add((to[1] - from[1]).unsigned_abs());
        // (|dx| + |dy|) 2^12 / g [Q12], 2 g in Q16 LSB: the product below 2^44 for any zero a
        // 16-bit code gives.
        let q12 = crate::math::div_u64(turned.saturating_mul(1 << 13), l.two_g_q16.max(1));
        self.lift.doubt_tilt_q12 = u16::try_from(q12).unwrap_or(u16::MAX);
    }

    /// A motion ended: Still, and if it began soon after a landing in doubt, what it moved
    /// is held until a set-down begun as it stopped would have been seen (module docs).
    pub(crate) fn still_after_motion(&mut self, s: &DriftSettings) {
        let air = self.tilt.in_air();
        self.enter_still();
        if let Some(l) = s.lift.filter(|_| air) {
            self.air = l.seen;
        }
    }

    /// After a new zero: the lift test waits until its window holds only ticks at it.
    pub(crate) fn lift_wait(&mut self, s: &DriftSettings) {
        if let Some(l) = s.lift {
            self.lift.wait = l.window;
        }
    }
}

impl State {
    /// Whether tracking is suspended (lifted).
    pub const fn is_lifted(self) -> bool {
        matches!(self, State::Lifted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibration::Calibration;

    #[test]
    fn a_landing_in_doubt_keeps_its_zeros_turn_over_g_and_a_sure_one_none() {
        let m_s2_per_lsb = 0.0235;
        let Ok(s) = crate::drift::Drift::default().validate(3000, m_s2_per_lsb) else {
            panic!("the default drift control is valid at 3 kHz");
        };
        let c = Calibration {
            bias_q16: 2048 << 16,
            noise_rms_q16: 1 << 16,
            samples: 3000,
            tick_var_q32: 3 << 32,
            long_run_var_q32: 3 << 32,
            tick_lags_q32: [0; 3],
        };
        let mut d = Detector::new(&s, &[c; 3]);
        // Level, then tilted 8 degrees about an axis at 30 degrees: X and Y gain g sin 8 cos 30
        // and g sin 8 sin 30 (the second negative), Z loses g (1 - cos 8); in Q16 LSB.
        let g = 9.80665 / m_s2_per_lsb;
        let (th, az) = (8f64.to_radians(), 30f64.to_radians());
        let q16 = |lsb: f64| (lsb * 65_536.0).round() as i64;
        let from = [q16(2048.0), q16(2048.0), q16(2048.0 + g)];
        let to = [
            q16(2048.0 + g * th.sin() * az.cos()),
            q16(2048.0 - g * th.sin() * az.sin()),
            q16(2048.0 + g * th.cos()),
        ];
        d.lift.sure = false;
        d.landed(&s, from, to);
        assert!(d.lift.doubt);
        // (|dx| + |dy|) / g = sin 8 (cos 30 + sin 30), in Q12.
        let want = th.sin() * (az.cos() + az.sin()) * 4096.0;
        let got = f64::from(d.lift.doubt_tilt_q12);
        assert!((got - want).abs() <= 1.0, "{got} against {want}");
        // After a sure fall the landing is trusted, and the zeros it took do not matter.
        d.lift.sure = true;
        d.landed(&s, from, to);
        assert!(!d.lift.doubt);
    }
}
