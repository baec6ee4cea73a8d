//! The rest statistic: when a motion starts, and where it began.
//!
//! # Two CUSUMs per horizontal axis and sign
//! At rest, per tick, each axis's offset from its zero is standardised by the tick sum's
//! long-run sd `sqrt(q D)` ([`super::noise`]) and fed to one-sided CUSUMs
//! `S = max(0, S + z - kappa)`, alarm at `S > h` (Page's test; REFERENCE (j)):
//!
//! - the **slow** one on the hand-band filter's output ([`super::ticks`]), `kappa = 1/2`:
//!   the quickest test for offsets near one sd, a slow stroke's; the filter removes a knock's
//!   ring and a machine's vibration, so that they do not start it;
//! - the **fast** one on the raw ticks, `kappa = 3/2`: offsets near 3 sd, a brisk stroke's,
//!   without the filter's delay (a brisk stroke's first count is due about 20 ms after it
//!   starts); also checked within a tick, on the samples so far, so that a brisk start does
//!   not wait for the tick's end. Within a tick it is checked once a USB frame (every
//!   `fs / 1000` samples, 1 ms; every sample below 2 kHz): the host polls the mouse once a
//!   frame, so a start found sooner could not reach it sooner, and the checks between cost
//!   about 16 instructions a sample triple at 3 kHz.
//!
//! What the measured disturbance `A` (a sinusoid's tick-sum amplitude, [`super::noise`])
//! can fake is allowed for differently in each. The raw one's `kappa` is widened by `A`: its
//! runs are a few ticks long. The filtered one's runs are long, and a sinusoid's sums are
//! bounded: at `x` cycles a tick, `sum_{m..n} sin(2 pi x k + phi)` is at most `1 / |sin(pi x)|`
//! over any run of ticks. So on noise plus a sinusoid that passes the hand-band filter at
//! `G_band`, the CUSUM exceeds the one on the noise alone by at most `B = G_band A / |sin(pi
//! x)|` (the largest at or above the disturbance's frequency bin, aliases included: 0.32 A
//! at 3 kHz, from a machine near the 200 Hz tick rate, which the ticks alias to near DC):
//! the run is judged net of `B`, with the alarm and the false-start rate of
//! a quiet desk, and no drift lost. A knock's ring decays faster than a run forgets what
//! it added, so `B` is held per axis as the runs forget: `max(B_now, B_before - kappa sd)`,
//! the rate at which a run's height falls on a zero-mean input. (Held at its largest since
//! the run left zero instead, a stroke's own 10 Hz content, which the residual counts as a
//! disturbance for a few ticks, raised the alarm for the rest of its run: an 8 mm stroke
//! over 1 s in noise draw 1003 never moved.) The run's height, its first lobe's and the
//! two-lobe sum are all net of theirs. Widening `kappa` by `G_band A` instead
//! cost a stroke `G_band A` a tick for its whole length: under a machine's 47.6 mg at 30 Hz,
//! slow strokes of 5-20 mm over 1-2 s never started (the lab's vibration-all, seed 3: 89 %
//! of strokes within target).
//!
//! # Two lobes together
//! A slow stroke's lobes may each fall short of the slow alarm: at 1000 ug/sqrt(Hz), or 300
//! on a slow hand, a stroke of a few floors peaks near one tick sd, and each lobe's run
//! rises by about `(mean - kappa)` sd a tick over half the stroke (an 8 mm stroke over 1 s
//! at 1.2 LSB of tick noise, each axis's lobes averaging 0.7 tick sd: runs of 6 to 21 sd
//! in four noise draws, under the alarm, and pairs of 19 to 39). Both
//! lobes together hold twice the evidence, and noise rarely makes it: a run's height has
//! the tail `c e^(-2 kappa x)` (the Brownian excursion's), so two consecutive runs of
//! opposite sides, the first at least `lobe_sd`, sum past `b` with probability at most `(1 +
//! 2 kappa (b - lobe_sd))` times one run's passing `b` (the convolution of the two tails).
//! The two-lobe alarm is the `b` at which that rate is one test's share of the budget
//! (`pair_threshold`: 27.7 sd beside the single 24.5 at 3 kHz). It is checked when the
//! second lobe's run ends, the stroke over: the motion starts from the first lobe's onset
//! with every block since replayed, and arrives whole at once, its latency the stroke's
//! duration. A start replays at most `BLOCKS - 1` blocks (1.26 s), so for a longer stroke
//! the sum is also checked once, as the first lobe's onset is about to leave them, with the
//! second run's highest value so far (as at its end: its value at that tick, falling, lost
//! strokes of 1.2 to 1.3 s whose run ended a few ticks later); a pair
//! whose first lobe has left starts nothing. A replay from the oldest block would start the
//! motion mid-way from zero velocity: a new user's out-and-back strokes, whose middle lobes
//! of one sign make one run, glided 340 to 620 mm that way (the tests with their controls:
//! `core/tests/drift.rs`).
//!
//! # A long stroke's last chance
//! A stroke of 1.3 to 2 s whose lobes each stay under the slow alarm (a few floors: each
//! lobe's mean near `kappa`, so its run hardly rises) has its pair's sum pass the alarm only
//! after the first lobe's onset has left the blocks: it started nothing, and was lost whole
//! (the lab's slow strokes, 1-2 s: 368 of 4200 on seeds 1-21, lengths up to 25 mm). So as
//! the first lobe's onset is about to leave, a second run going on after a first lobe past
//! `lobe_sd` starts the motion from that onset even short of the pair's alarm, **unproven**
//! as on a shaking desk ([`super::estimator`]): nothing of it is delivered until its
//! velocity stands out of what the velocity test explains (at once if it did at a replayed
//! block's end), and it is discarded if it stops first. No new threshold: noise makes no
//! such pair, a run on noise ends within a few ticks (its drift is `-kappa` sd a tick), and
//! this one has lasted since its first lobe began, 1.26 s ago; what does make one (a tilt
//! and its return, a drag's ramps) is judged by the tests of the motion it starts. The
//! motion is marked long: its velocity is short of the hand's by what the first lobe gave
//! before its run rose, and the stop test is held off while its deceleration goes on
//! ([`super::estimator`]).
//!
//! # Thresholds from the false-start budget
//! The eight CUSUMs (slow and fast, X and Y, both signs) and the slow ones' four two-lobe
//! sums (below) share [`super::Drift::false_start_hours`] equally. On unit-variance Gaussian increments a
//! CUSUM's average run length to a false alarm is `(e^(2 kappa b) - 1 - 2 kappa b) / (2
//! kappa^2)` (Siegmund), with `b = h` for the filtered one (a smooth input has no overshoot:
//! Brownian motion's exact result, conservative) and `b = h + 1.166` for the raw one. At
//! 3 kHz (5 ms ticks) and 10^4 hours: `h = 24.5` (slow) and `h = 7.7` (fast). When the
//! sensor's noise is below an LSB the codes' excursions are not Gaussian: the ADC's steps
//! steepen a large one beyond the small fluctuations the noise was learnt from, so the sd
//! both CUSUMs standardise by is the learnt one times the quantizer's bound
//! ([`super::noise::quantizer_bound_q16`]: 1.37 for 0.36 LSB of noise, exactly 1 from 0.82
//! LSB, the ADXL335's 1.1 among them). The rate is measured by the long-rest benchmark
//! (`cargo lab mouse --long-rest`), beside this prediction.
//!
//! # Where the motion began
//! Each CUSUM remembers the tick at which it last left zero: that is where the run that
//! crossed the alarm began. The raw one's onset is the tick itself; the slow one's is moved
//! back by the filter's delay. A stroke's acceleration has two lobes of opposite sign; a slow
//! one's first lobe may fall short of the alarm and its second cross it, and integrating from
//! the second lobe alone would leave the cursor gliding back at the stroke's peak speed. So
//! as a run leaves zero it takes its **first lobe**: its other side's run, still decaying or
//! the last one, if that run ended where this one began (within the lobes' gap and the
//! filter's length) and rose above 5 sd, which noise alone does with probability `e^(-2
//! kappa 5) = 0.7 %` per run ([`super::Tuning::lobe_sd`]); the onset is then that run's. Between the lobes the acceleration stays within `kappa` of zero: a
//! minimum-jerk stroke of `T` crosses zero at `30 d / T^3` and peaks at `A = 5.77 d / T^2`,
//! so for `0.385 T kappa / A`, and the slow CUSUM's runs stop there. For the longest stroke
//! and a peak of `1.5 kappa` (about the weakest whose first lobe's run still rises well
//! past 5 sd) that is a quarter of the stroke: the lobes' gap, 0.5 s by default.
//! With the filter's length alone (85 ms) a slow stroke's first lobe was missed, and its
//! second left the cursor gliding back for tens of seconds (a new user's 15.5 mm stroke
//! over 1.57 s: 3.2 m). The gap only widens the match; noise reaches 5 sd in the same 0.7 % of
//! runs, and a false match moves the onset back by that run only. The blocks since the onset
//! (at most [`super::BLOCKS`] - 1, 1.28 s) are integrated at once, from zero velocity: a slow
//! stroke found half-way loses nothing of its start. A stroke's lobes come on both axes at
//! once, and noise may leave one axis's first lobe under `lobe_sd` while the other's passes it:
//! a start also begins at the first lobe of a slow run going on, on either axis, that has one
//! and has itself risen past `lobe_sd` (a new user's 14.9 mm stroke over 1.61 s alarmed on Y's
//! second lobe alone and glided back 209 mm from zero velocity there; X's second run was going
//! on after a first lobe of 5.2 sd). Noise makes such a pair, both runs past `lobe_sd` within
//! the gap, in well under 0.7 % squared of runs, and a false one only replays more blocks of
//! rest. The fast CUSUM's test within a tick takes the same onset as the tick's end would:
//! a stroke that eases in and stops sharply has its stop alarm within a tick, and from the
//! fast run's onset alone its stop was integrated from zero velocity (a second tester's
//! 8.8 mm over 1.06 s glided 135 mm back; of 96 noise draws of 8.8 mm speeding up over
//! 0.9 s and stopping in 0.3 s, 18 went back by more than 2 mm, up to 153 mm, 11 with it).
//! A start whose alarm was crossed by one tick alone is a step (a jolt), not a hand's
//! ramp: its hold runs from now, not from an onset noise may have placed earlier
//! ([`super::click`]).
//!
//! # A lone lobe: the end of a glide the start tests missed
//! A drag's ramp up and its ramp down are one lobe mirrored, and the glide between shows
//! nothing. Near the noise floor the ramp up may stay under the alarms while the ramp down,
//! the same velocity over a shorter time, crosses them: integrated from zero velocity it
//! then glides backwards at the drag's speed (a new user's drags: 58 of 65 ramp downs found
//! alone went back more than 2 mm, up to 179 mm). The ramp up left a slow run that did not
//! alarm. So per horizontal axis the highest slow run since this rest began is kept, if it
//! had no first lobe and began after the stop's wait (an eighth of the longest stroke:
//! before, it may be the rest of the motion's deceleration, [`super::estimator`]). A run of
//! the other side past `lobe_sd` that begins within the lobes' gap of its end is its pair
//! (a stroke): none is kept. One that begins later, with no first lobe of its own, took
//! back its length of the kept run's (a ramp down missed too: the glide is over), and what
//! it gave beyond is kept as its own. A start on the other side of the kept run, within the
//! longest glide of its end, is its **mate**, held until its acceleration reverses, as
//! after a tilt ([`super::tilt`]). The estimator ends the wait: once the mate's velocity is
//! past what the kept run can have given, reversed, that run was noise or a glide that
//! ended, and the mate is a hand's; calm unreversed within it, it ended the glide, and it
//! is dropped ([`super::estimator`]).
//!
//! The run must rise past `lone_sd = ln(n / P_LONE) / (2 kappa)` (10.6 sd at 3 kHz): on
//! noise a run passes `x` with probability `e^(-2 kappa x)` (the tail above), and at most
//! `n = glide_ticks / 2` runs end within the longest glide (each takes a tick above zero and
//! one at it), so noise makes the mate of at most `P_LONE` = 1 % of starts. What a kept run
//! can have given: its increments `z - kappa` summed to zero or less where it ended, so its
//! ticks' offsets sum to at most `kappa len` sd over its `len` ticks; its tails below
//! `kappa` before and after it add at most `kappa` sd a tick over the hand-band filter's
//! span `L1 + L2` each: `kappa (len + 2 (L1 + L2)) sd` in all, the mate's velocity within
//! `K_TILT` of its own sd of that.

use core::cmp::Ordering;

use super::noise::{Disturbance, Noise};
use super::ticks::{offset, TickStream};
use super::{Action, Detector, DriftSettings, State, BLOCKS};

/// The share of starts at most that a lone lobe of noise makes wary (see the module docs):
/// a run past `ln(n / P_LONE) / (2 kappa)` sd among the `n` runs of a glide's span.
pub(crate) const P_LONE: f64 = 0.01;

/// A slow run kept as a lone lobe ([`Rest`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Lone {
    /// The tick it ended (low 32 bits: 248 days of 5 ms ticks).
    end: u32,
    /// Its highest value [sd, Q8]; 0 for none (or paired).
    height: u16,
    /// Its length [ticks], at most 255 (1.3 s: no ramp is that long).
    len: u8,
    /// Its side: 0 positive, 1 negative.
    side: u8,
}

/// The start tests' state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rest {
    /// `[slow, fast][axis X, Y][side +, -]` [Q16 LSB samples].
    cusum: [[[i64; 2]; 2]; 2],
    /// The tick each CUSUM last left zero.
    onset: [[[u64; 2]; 2]; 2],
    /// Each CUSUM's highest value in its current run, the slow one's net of the
    /// disturbance's run allowance [Q16 LSB samples].
    peak: [[[i64; 2]; 2]; 2],
    /// Per horizontal axis, the slow CUSUMs' run allowance: what the measured disturbance can
    /// have added to their runs, forgotten at their drift (see the module docs) [Q16 LSB
    /// samples].
    run_allow: [i64; 2],
    /// Each CUSUM's last finished run: its onset, its highest value, the tick it ended.
    last: [[[(u64, i64, u64); 2]; 2]; 2],
    /// Each slow CUSUM's current run's first lobe, taken as the run left zero: the onset
    /// and highest value of the other side's run before it, if it was one (see the module
    /// docs); a highest value of 0 for none [Q16 LSB samples]. (The fast one's runs are a
    /// few ticks long: its other side's last run is still the one before when it alarms.)
    lobe: [[(u64, i64); 2]; 2],
    /// Per horizontal axis, the highest slow run since this rest began, within the longest
    /// glide, that had no first lobe and no mate since (see the module docs).
    lone: [Lone; 2],
    /// Per horizontal axis and side, how far the current tick's offset so far may go before
    /// the fast CUSUM alarms on it with a whole tick's drift subtracted [Q16 LSB samples]:
    /// `alarm - S + kappa sd + A` ([`Self::within_headroom`]).
    headroom: [[i64; 2]; 2],
}

impl Rest {
    /// Every CUSUM at zero, their onsets at `tick`.
    pub(crate) fn reset(&mut self, tick: u64) {
        self.cusum = [[[0; 2]; 2]; 2];
        self.onset = [[[tick; 2]; 2]; 2];
        self.peak = [[[0; 2]; 2]; 2];
        self.run_allow = [0; 2];
        self.last = [[[(tick, 0, tick); 2]; 2]; 2];
        self.lobe = [[(tick, 0); 2]; 2];
        self.lone = [Lone::default(); 2];
    }

    /// Whether a run `(onset, peak, end)` of one side of a CUSUM was the first lobe of a run
    /// of the other side beginning at `own`: it ended within `slack` ticks of it and rose
    /// above `lobe_sd` (see the module docs).
    fn is_lobe(s: &DriftSettings, run: (u64, i64, u64), own: u64, sd: i64, slack: u64) -> bool {
        let (_, peak, end) = run;
        end + slack >= own && Self::lobe_high(s, peak, sd)
    }

    /// Whether a run's highest value `peak` [Q16 LSB samples] reached `lobe_sd` for a tick
    /// sum's sd `sd`.
    fn lobe_high(s: &DriftSettings, peak: i64, sd: i64) -> bool {
        i128::from(peak) << 8 >= i128::from(s.lobe_q8) * i128::from(sd)
    }

    /// `kappa sd` of CUSUM `c` (0 slow, 1 fast) for a tick sum's sd `sd` [Q16 LSB samples].
    fn kappa_sd(s: &DriftSettings, c: usize, sd: i64) -> i64 {
        (s.kappa_q8[c] * sd) >> 8
    }

    /// A slow run on `axis`, `side` ended at tick `end`: it becomes the axis's lone lobe
    /// if it had no first lobe and rises higher than the one kept (or there is none, or it is
    /// older than the longest glide). Past `lobe_sd` on the other side, it pairs the kept one
    /// if it began within the lobes' gap of its end (a stroke), and later, with no first
    /// lobe, takes back its length of the kept one's (see the module docs).
    fn end_run(&mut self, s: &DriftSettings, axis: usize, side: usize, end: u64, sd: i64) {
        let (onset, peak) = (self.onset[0][axis][side], self.peak[0][axis][side]);
        let height = ((i128::from(peak) << 8) / i128::from(sd.max(1))).clamp(0, 0xFFFF) as u16;
        let first = self.lobe[axis][side].1 != 0;
        let this = Lone {
            end: end as u32,
            height,
            len: end.saturating_sub(onset).min(255) as u8,
            side: side as u8,
        };
        let kept = &mut self.lone[axis];
        let live = i32::from(kept.height) >= s.lobe_q8
            && (end as u32).wrapping_sub(kept.end) <= s.glide_ticks;
        if live && kept.side != this.side {
            if i32::from(height) < s.lobe_q8 {
                return;
            }
            let since = (onset as u32).wrapping_sub(kept.end) as i32;
            if since <= s.lobe_slack as i32 {
                // Its pair: a stroke.
                *kept = Lone::default();
            } else if !first {
                // Later, alone: it took back as much of the velocity the kept run gave (a
                // glide's ramp down, missed too), and what it gave beyond is its own.
                *kept = match kept.len.cmp(&this.len) {
                    Ordering::Greater => Lone {
                        len: kept.len - this.len,
                        ..*kept
                    },
                    Ordering::Equal => Lone::default(),
                    Ordering::Less => Lone {
                        len: this.len - kept.len,
                        ..this
                    },
                };
            }
            return;
        }
        if !first && (!live || height > kept.height) {
            *kept = this;
        }
    }

    /// The lone lobe on `axis`, if it rose past `lone_sd`: its sign, and the most velocity
    /// it can have given (`V`, Q16 LSB samples) for a tick sum's sd `sd`. Its run's
    /// increments `z - kappa` summed to zero or less where the run ended: it gave at most
    /// `kappa len` sd over its `len` ticks (less what later runs of the other side took
    /// back); its tails below `kappa` before and after the run at most `kappa` a tick over
    /// the hand-band filter's span each: `kappa (len + 2 (L1 + L2)) sd` in all.
    pub(crate) fn lone_velocity(
        &self,
        s: &DriftSettings,
        axis: usize,
        sd: i64,
    ) -> Option<(i64, u64)> {
        let l = self.lone[axis];
        if i32::from(l.height) < s.lone_q8 {
            return None;
        }
        let ticks = u64::from(l.len) + 2 * u64::from(s.band[0] + s.band[1]);
        let kappa = Self::kappa_sd(s, 0, sd).unsigned_abs();
        Some((
            if l.side == 0 { 1 } else { -1 },
            kappa.saturating_mul(ticks),
        ))
    }

    /// Whether a start on `axis`, `side` whose run began at `onset` may be the end of a
    /// glide the start tests missed: the axis's lone lobe is of the other side, rose past
    /// `lone_sd`, and ended before `onset` (it is not this start's first lobe) and within
    /// the longest glide of it (see the module docs).
    fn lone_before(&self, s: &DriftSettings, axis: usize, side: usize, onset: u64) -> bool {
        let kept = self.lone[axis];
        let age = (onset as u32).wrapping_sub(kept.end);
        kept.side != side as u8 && i32::from(kept.height) >= s.lone_q8 && age <= s.glide_ticks
    }

    /// As the slow CUSUM on `axis`, `side` leaves zero: its first lobe, the other side's
    /// run before it (still going, a first lobe decaying, or its last) if it was one, within
    /// the lobes' gap and the filter's length, over which it smears a lobe's end.
    fn take_lobe(&mut self, s: &DriftSettings, axis: usize, side: usize, sd: i64) {
        let other = 1 - side;
        let own = self.onset[0][axis][side];
        let run = if self.cusum[0][axis][other] > 0 {
            (self.onset[0][axis][other], self.peak[0][axis][other], own)
        } else {
            self.last[0][axis][other]
        };
        self.lobe[axis][side] = if Self::is_lobe(s, run, own, sd, u64::from(s.lobe_slack)) {
            (run.0.min(own), run.1)
        } else {
            (own, 0)
        };
    }

    /// A start's onset `onset`, moved back to the first lobe's (less the filter's delay) of
    /// a slow run going on that rose past `lobe_sd` after a first lobe, on either horizontal
    /// axis: a stroke's lobes come on both axes at once, and the axis that alarmed may have
    /// seen no first lobe of its own (see the module docs). `sd`: each axis's tick sd [Q16
    /// LSB samples].
    fn first_lobe_across(&self, s: &DriftSettings, onset: u64, sd: [i64; 2]) -> u64 {
        let delay = u64::from(s.band_delay);
        let mut on = onset;
        for (a, &sd) in sd.iter().enumerate() {
            for side in 0..2 {
                let (first, first_peak) = self.lobe[a][side];
                // The current run's highest value is 0 once it has ended.
                if first_peak != 0 && Self::lobe_high(s, self.peak[0][a][side], sd) {
                    on = on.min(first.saturating_sub(delay));
                }
            }
        }
        on
    }

    /// The onset of the run of CUSUM `c` on `axis`, `side` that alarmed: its first lobe's
    /// if it had one, else its own.
    fn onset_of(&self, s: &DriftSettings, c: usize, axis: usize, side: usize, sd: i64) -> u64 {
        let own = self.onset[c][axis][side];
        if c == 0 {
            return self.lobe[axis][side].0;
        }
        let last = self.last[1][axis][1 - side];
        if Self::is_lobe(s, last, own, sd, 1) {
            last.0.min(own)
        } else {
            own
        }
    }

    /// The slow CUSUM's two-lobe alarm on `axis`, `side` for a run of height `run`: its first
    /// lobe's onset if the two together pass it ([`DriftSettings::alarm_q8`]`[2]`; the test
    /// against the single `alarm` first, which the two-lobe one exceeds, is the cheap one).
    #[inline(always)]
    fn pair(
        &self,
        s: &DriftSettings,
        axis: usize,
        side: usize,
        run: i64,
        sd: i64,
        alarm: i64,
    ) -> Option<u64> {
        let (onset, peak) = self.lobe[axis][side];
        (run + peak > alarm && run + peak > Self::alarm(s.alarm_q8[2], sd)).then_some(onset)
    }

    /// `h sd` for an alarm `h` [sd, Q8] and an `sd` [Q16 LSB samples]: in 64 bits when the
    /// product fits (it does for every sd a 16-bit ADC can show at the default budget), in
    /// 128 otherwise: the same alarm.
    fn alarm(h: u64, sd: i64) -> i64 {
        match i64::try_from(h).ok().and_then(|h| h.checked_mul(sd)) {
            Some(p) => p >> 8,
            None => ((i128::from(h) * i128::from(sd)) >> 8) as i64,
        }
    }

    /// The drift and alarm of CUSUM `c` (0 slow, 1 fast) on an axis of noise `n` and
    /// disturbance `d`, and what the disturbance can add to a run's sum [Q16 LSB samples]:
    /// `(kappa sd, h sd, G_run A)` for the slow one, `(kappa sd + A, h sd, 0)` for the fast
    /// one (see the module docs).
    fn limits(s: &DriftSettings, n: &Noise, d: &Disturbance, c: usize) -> (i64, i64, i64) {
        let sd = n.sd_q16;
        let kappa = Self::kappa_sd(s, c, sd);
        let alarm = Self::alarm(s.alarm_q8[c], sd);
        if c == 0 {
            (kappa, alarm, d.allow(d.gains(s).band_run_q16, 1) as i64)
        } else {
            (kappa + d.amp_q16 as i64, alarm, 0)
        }
    }

    /// Recomputes the headroom after a tick, while Still.
    pub(crate) fn refresh_headroom(
        &mut self,
        s: &DriftSettings,
        noise: &[Noise; 3],
        dist: &[Disturbance; 3],
        state: State,
    ) {
        if state != State::Still {
            return;
        }
        for a in 0..2 {
            let (kappa, alarm, _) = Self::limits(s, &noise[a], &dist[a], 1);
            for side in 0..2 {
                self.headroom[a][side] = alarm - self.cusum[1][a][side] + kappa;
            }
        }
    }

    /// On entering Still, until the next tick's refresh: no early test (the tick's end
    /// makes the exact one).
    pub(crate) fn no_headroom_test(&mut self) {
        self.headroom = [[i64::MAX; 2]; 2];
    }

    /// Whether the current tick so far is within the headroom on both horizontal axes, so
    /// that the fast CUSUM cannot alarm on it: the test made on every sample at rest.
    #[inline(always)]
    pub(crate) fn within_headroom(&self, stream: &TickStream, bias: [i64; 3]) -> bool {
        (0..2).all(|a| {
            let d = stream.partial_offset(a, bias[a]);
            d <= self.headroom[a][0] && -d <= self.headroom[a][1]
        })
    }
}

impl Detector {
    /// Decisions at rest at a tick's end: the start tests, then learning the noise and
    /// following the zero from the tick a start can no longer claim.
    pub(crate) fn still_tick(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        let t = self.stream.ticks();
        let mut alarm: Option<u64> = None;
        let mut step = false;
        let mut lone = false;
        let mut leaving: Option<u64> = None;
        // The filter remembers L1 + L2 - 1 ticks: until it has forgotten the motion before
        // this rest, only the raw test runs.
        let band_ready = self.age() >= u64::from(s.band[0] + s.band[1] - 1);
        let delay = u64::from(s.band_delay);
        // A run begun within a stop's wait may be the rest of its deceleration
        // ([`super::estimator`]): no lone lobe.
        let settled = self.entered + u64::from(s.fade_ticks);
        // A start replays at most BLOCKS - 1 blocks: one less, for the block the onset is in.
        let replay = (BLOCKS as u64 - 2) * u64::from(s.block);
        for (a, &b) in bias.iter().enumerate().take(2) {
            let raw = offset(u64::from(self.stream.code(1, a)), u64::from(s.tick), b);
            let band = self.stream.band_offset(s, a, b);
            let tests = if band_ready { 0..2 } else { 1..2 };
            let sd = self.noise[a].sd_q16;
            // What the disturbance can have added to the slow one's runs, held as a run
            // forgets (see the module docs).
            // (Nothing to do on a quiet desk, the usual case: nothing held, nothing to hold.)
            let held = &mut self.rest.run_allow[a];
            if band_ready && (*held > 0 || self.disturbance[a].amp_q16 > 0) {
                let (kappa, _, allow) = Rest::limits(s, &self.noise[a], &self.disturbance[a], 0);
                *held = (*held - kappa).max(allow);
            }
            let held = *held;
            // (Plain ranges: the arrays' iterators cost about 40 instructions a tick on the
            // Cortex-M4 once this body is too long for them to be unrolled.)
            for c in tests {
                let z = if c == 0 { band } else { raw };
                let (kappa, limit, _) = Rest::limits(s, &self.noise[a], &self.disturbance[a], c);
                let held = if c == 0 { held } else { 0 };
                for side in 0..2 {
                    let z = if side == 0 { z } else { -z };
                    let r = &mut self.rest;
                    let before = r.cusum[c][a][side];
                    let sum = (before + z - kappa).max(0);
                    r.cusum[c][a][side] = sum;
                    let net = sum - held;
                    // The slow one's two lobes together (see the module docs), while the
                    // first one's onset is in the blocks: at the second one's end, or as that
                    // onset is about to leave them.
                    let mut pair = None;
                    if sum == 0 {
                        if before > 0 {
                            if c == 0 {
                                pair = r
                                    .pair(s, a, side, r.peak[0][a][side], sd, limit)
                                    .filter(|&on| t - on.saturating_sub(delay) <= replay);
                                if r.onset[0][a][side] >= settled {
                                    r.end_run(s, a, side, t, sd);
                                }
                            }
                            r.last[c][a][side] = (r.onset[c][a][side], r.peak[c][a][side], t);
                        }
                        r.onset[c][a][side] = t;
                        r.peak[c][a][side] = 0;
                    } else {
                        if c == 0 {
                            if before == 0 {
                                r.take_lobe(s, a, side, sd);
                            }
                            // As the first lobe's onset is about to leave the blocks: the
                            // pair with the run's highest value, as at its end (a stroke's
                            // second lobe may have peaked and be falling by then); short of
                            // its alarm, a long stroke's last chance to start from its onset,
                            // unproven (see the module docs).
                            let (on, first) = r.lobe[a][side];
                            if t - on.saturating_sub(delay) == replay {
                                let high = r.peak[0][a][side].max(net);
                                pair = r.pair(s, a, side, high, sd, limit);
                                if pair.is_none() && first != 0 {
                                    let o = on.saturating_sub(delay);
                                    leaving = Some(leaving.map_or(o, |l: u64| l.min(o)));
                                }
                            }
                        }
                        r.peak[c][a][side] = r.peak[c][a][side].max(net);
                    }
                    if net > limit || pair.is_some() {
                        // The slow one's run began the filter's delay before it shows (and a
                        // disturbance's allowance delays the fast one's: the slow one's run,
                        // if it has begun, is the earlier start); no run began before this
                        // rest.
                        let r = &self.rest;
                        let mut on = pair.unwrap_or_else(|| r.onset_of(s, c, a, side, sd));
                        if c == 0 {
                            on = on.saturating_sub(delay);
                        } else if r.cusum[0][a][side] > 0 {
                            on = on.min(r.onset[0][a][side].saturating_sub(delay));
                        }
                        let on = on.max(self.entered);
                        alarm = Some(alarm.map_or(on, |o: u64| o.min(on)));
                        step |= c == 1 && z - kappa > limit;
                        lone |= self.rest.lone_before(s, a, side, on);
                    }
                }
            }
        }
        if let Some(onset) = alarm {
            let onset = self.onset_across(s, onset);
            return self.start(s, onset, step, lone, false, bias);
        }
        if let Some(onset) = leaving {
            let onset = self.onset_across(s, onset);
            return self.start(s, onset, false, false, true, bias);
        }
        self.track_zero(s, bias)
    }

    /// The fast CUSUM checked within a tick, on the samples of it so far, against the whole
    /// tick's drift (conservative: a partial tick is noisier, and gets no more room); once
    /// in `early_stride` samples (a USB frame, see the module docs).
    #[inline(never)]
    pub(crate) fn early_start(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        let t = self.stream.ticks();
        let mut alarm: Option<u64> = None;
        let mut step = false;
        let mut lone = false;
        for (a, &b) in bias.iter().enumerate().take(2) {
            let d = self.stream.partial_offset(a, b);
            for (side, z) in [d, -d].into_iter().enumerate() {
                if z > self.rest.headroom[a][side] {
                    let sum = self.rest.cusum[1][a][side];
                    let on = if sum == 0 {
                        t
                    } else {
                        self.rest.onset[1][a][side]
                    };
                    alarm = Some(alarm.map_or(on, |o: u64| o.min(on)));
                    // Alone past the alarm (the headroom less what the CUSUM held): a step.
                    step |= z > self.rest.headroom[a][side] + sum;
                    lone |= self.rest.lone_before(s, a, side, on);
                }
            }
        }
        alarm.map_or(Action::None, |onset| {
            // The onset the tick's end would give: a slow run's first lobe, on either axis.
            let onset = self.onset_across(s, onset);
            self.start(s, onset, step, lone, false, bias)
        })
    }

    /// A start's onset `onset` moved back to a slow run's first lobe on either horizontal axis
    /// ([`Rest::first_lobe_across`]), never before this rest: every start test's.
    fn onset_across(&self, s: &DriftSettings, onset: u64) -> u64 {
        let sd = [self.noise[0].sd_q16, self.noise[1].sd_q16];
        self.rest.first_lobe_across(s, onset, sd).max(self.entered)
    }

    /// Whether the velocity of a motion replayed from `blocks` complete blocks back, from
    /// the velocity `from` at its onset (`W`, or zero), stood out of what the velocity test
    /// explains at a block's end (the disturbance's velocity allowed for): a stroke found
    /// after it ended, whole in the replay, is then not the disturbance although it is at
    /// rest again.
    fn replay_stood_out(
        &self,
        s: &DriftSettings,
        blocks: u64,
        from: Option<[i64; 3]>,
        bias: [i64; 3],
    ) -> bool {
        let n = u64::from(s.block) * u64::from(s.tick);
        let mut v = from.map_or([0; 2], |w| [w[0] / 2, w[1] / 2]);
        let allow = self.new_velocity_allowance(s);
        for k in (1..=blocks).rev() {
            for (a, v) in v.iter_mut().enumerate() {
                let sum = self.stream.blocks_sum(a, k as u32, k as u32 + 1);
                *v = v.saturating_add(super::ticks::offset_q16(sum, n, bias[a]));
            }
            let m = (blocks - k + 1) * n;
            if !self.velocity_explained_with(
                s,
                [2 * v[0], 2 * v[1], 0],
                m,
                self.bias_samples,
                allow,
            ) {
                return true;
            }
        }
        false
    }

    /// A motion starts: replay the complete blocks since the one `onset` (a tick) lies in (at
    /// most `BLOCKS - 1`) and the current block's samples so far. It is held until `hold_s`
    /// after its onset; after a `step` until `hold_s` after now ([`super::click`]); after a
    /// `lone` lobe until its acceleration reverses ([`super::tilt`]).
    pub(crate) fn start(
        &mut self,
        s: &DriftSettings,
        onset: u64,
        step: bool,
        lone: bool,
        unproven: bool,
        bias: [i64; 3],
    ) -> Action {
        let done = self.stream.blocks();
        let onset_block = onset / u64::from(s.block);
        // Keep one block before the replay: it primes the trapezoid.
        let blocks = (done - onset_block.min(done))
            .min(BLOCKS as u64 - 1)
            .min(done.saturating_sub(1));
        let samples = blocks * u64::from(s.block) * u64::from(s.tick)
            + u64::from(self.stream.samples_in_block());
        let latent = self.take_latent(s, onset, bias, samples);
        // A disturbed device's velocity at the onset is the disturbance's, not zero: the one
        // whose integral over the rest before averages to zero (ticks.rs). Only from rest.
        let disturbed = self.shaken_xy();
        let pre = u64::from(s.pre_blocks) * u64::from(s.block);
        // At rest since before the pre-window: still, or only after motions that were
        // discarded (the disturbance's own).
        let since = self.stream.ticks() - self.real_end;
        let from_rest =
            self.state == State::Still && since >= (blocks + 1) * u64::from(s.block) + pre;
        let shaking = if disturbed && from_rest {
            self.stream.rest_velocity(blocks, s.pre_blocks, bias)
        } else {
            None
        };
        self.enter(State::Moving);
        self.stream.band_span_refresh(s, bias);
        self.motion
            .begin(latent.map_or(samples, |(_, span)| span), latent.is_some());
        self.motion.unproven =
            (disturbed || unproven) && !self.replay_stood_out(s, blocks, shaking, bias);
        self.motion.long = unproven;
        // The hold runs from the onset itself, not from the start of its block.
        let t = self.stream.ticks();
        let age = (t - onset.min(t)) * u64::from(s.tick) + u64::from(self.stream.partial());
        self.click.begin_motion(s, age.min(samples), step);
        self.count_runs(s, blocks, lone, bias);
        Action::Start {
            blocks: blocks as usize,
            carry: latent.map_or(shaking.map_or([0; 2], |w| [w[0], w[1]]), |(w, _)| w),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Drift;

    const SD: i64 = 256;

    fn settings() -> DriftSettings {
        Drift::default()
            .validate(3000, 9.806_65 * 10.0 / 4096.0)
            .expect("the default drift control is valid")
    }

    /// A slow run on X, `side`, from `onset` to `end`, `height` sd high, with a first lobe
    /// or not, ended as the start tests end one.
    fn run(
        r: &mut Rest,
        s: &DriftSettings,
        side: usize,
        (onset, end): (u64, u64),
        height: f64,
        lobe: bool,
    ) {
        r.onset[0][0][side] = onset;
        r.peak[0][0][side] = (height * SD as f64) as i64;
        r.lobe[0][side] = (onset, if lobe { 6 * SD } else { 0 });
        r.end_run(s, 0, side, end, SD);
    }

    #[test]
    fn lone_sd_is_the_height_noise_passes_in_p_lone_of_a_glides_runs() {
        // ln(400 / 0.01) / (2 kappa): 10.6 sd at kappa 1/2, twice that at 1/4.
        let want = |kappa: f64| libm::log(800.0 / 2.0 / P_LONE) / (2.0 * kappa);
        let lone = f64::from(settings().lone_q8) / 256.0;
        assert!((lone - want(0.5)).abs() <= 0.5 / 256.0, "{lone}");
        let quarter = Drift {
            tuning: crate::drift::Tuning {
                kappa: [0.25, 1.5],
                ..crate::drift::Tuning::default()
            },
            ..Drift::default()
        }
        .validate(3000, 9.806_65 * 10.0 / 4096.0)
        .expect("valid");
        let lone = f64::from(quarter.lone_q8) / 256.0;
        assert!((lone - want(0.25)).abs() <= 0.5 / 256.0, "{lone}");
    }

    #[test]
    fn a_lone_lobe_is_a_run_past_lone_sd_of_the_other_side_within_the_longest_glide() {
        let s = settings();
        let lone = f64::from(s.lone_q8) / 256.0;
        assert!((10.0..11.0).contains(&lone), "{lone}");
        let mut r = Rest::default();
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), lone + 0.1, false);
        // A start on the other side of X after it: its mate; on its own side or on Y: not.
        assert!(r.lone_before(&s, 0, 1, 400));
        assert!(!r.lone_before(&s, 0, 0, 400));
        assert!(!r.lone_before(&s, 1, 1, 400));
        // Not one whose run began before it ended (it is that start's first lobe), nor one
        // past the longest glide after it.
        assert!(!r.lone_before(&s, 0, 1, 150));
        assert!(r.lone_before(&s, 0, 1, 160 + u64::from(s.glide_ticks)));
        assert!(!r.lone_before(&s, 0, 1, 161 + u64::from(s.glide_ticks)));
        // Under lone_sd: noise's too often; at it, a lone lobe.
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), lone - 0.1, false);
        assert!(!r.lone_before(&s, 0, 1, 400));
        assert_eq!(r.lone_velocity(&s, 0, SD), None);
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), lone, false);
        assert!(r.lone_velocity(&s, 0, SD).is_some());
    }

    #[test]
    fn a_lobe_of_a_pair_is_no_lone_lobe() {
        let s = settings();
        let slack = u64::from(s.lobe_slack);
        let mut r = Rest::default();
        // A first lobe and its second, past lobe_sd, begun within the lobes' gap: neither.
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), 15.0, false);
        run(&mut r, &s, 1, (160 + slack, 250 + slack), 6.0, true);
        assert!(!r.lone_before(&s, 0, 1, 600));
        assert!(!r.lone_before(&s, 0, 0, 600));
        // A second under lobe_sd, or begun past the gap, leaves the first lone.
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), 15.0, false);
        run(&mut r, &s, 1, (170, 200), 4.0, false);
        assert!(r.lone_before(&s, 0, 1, 600));
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), 15.0, false);
        run(&mut r, &s, 1, (161 + slack, 200 + slack), 6.0, false);
        assert!(r.lone_before(&s, 0, 1, 600));
        // A run with a first lobe is a stroke's second: never kept.
        r.reset(0);
        run(&mut r, &s, 1, (100, 160), 15.0, true);
        assert!(!r.lone_before(&s, 0, 0, 400));
    }

    #[test]
    fn the_highest_run_is_kept_and_a_later_one_of_the_other_side_takes_back_its_length() {
        let s = settings();
        let glide = u64::from(s.glide_ticks);
        let tails = 2 * u64::from(s.band[0] + s.band[1]);
        // The velocity bound of a kept run of `len` ticks (kappa 1/2).
        let bound = |len: u64| (len + tails) * SD as u64 / 2;
        let mut r = Rest::default();
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), 15.0, false);
        // A lower or as high run of its side after it does not replace it; a higher one does.
        run(&mut r, &s, 0, (200, 210), 3.0, false);
        run(&mut r, &s, 0, (220, 230), 15.0, false);
        assert_eq!(r.lone_velocity(&s, 0, SD), Some((1, bound(60))));
        run(&mut r, &s, 0, (240, 270), 15.5, false);
        assert_eq!(r.lone_velocity(&s, 0, SD), Some((1, bound(30))));
        r.reset(0);
        run(&mut r, &s, 0, (100, 160), 15.0, false);
        // One of the other side under lobe_sd is noise's: nothing taken back.
        run(&mut r, &s, 1, (220, 230), 4.9, false);
        assert_eq!(r.lone_velocity(&s, 0, SD), Some((1, bound(60))));
        // Past the lobes' gap, at lobe_sd or past it, it takes back its length.
        let t = 160 + u64::from(s.lobe_slack) + 40;
        run(&mut r, &s, 1, (t, t + 5), 5.0, false);
        assert_eq!(r.lone_velocity(&s, 0, SD), Some((1, bound(55))));
        run(&mut r, &s, 1, (t + 10, t + 15), 16.0, false);
        assert_eq!(r.lone_velocity(&s, 0, SD), Some((1, bound(50))));
        assert!(r.lone_before(&s, 0, 1, t + 100));
        // Longer than what is left: the rest is its own, of its side.
        run(&mut r, &s, 1, (t + 20, t + 90), 16.0, false);
        assert_eq!(r.lone_velocity(&s, 0, SD), Some((-1, bound(20))));
        assert!(r.lone_before(&s, 0, 0, t + 200));
        assert!(!r.lone_before(&s, 0, 1, t + 200));
        // Once older than the longest glide, any run replaces it, a lower one too.
        let late = t + 100 + glide;
        run(&mut r, &s, 0, (late, late + 40), 12.0, false);
        assert_eq!(r.lone_velocity(&s, 0, SD), Some((1, bound(40))));
        assert!(!r.lone_before(&s, 0, 0, late + 100));
        // A rest begins with none.
        run(&mut r, &s, 0, (9000, 9060), 15.0, false);
        r.reset(9100);
        assert!(!r.lone_before(&s, 0, 1, 9200));
    }

    #[test]
    fn a_lone_lobe_gave_at_most_its_drift_over_its_run_and_tails() {
        let s = settings();
        let mut r = Rest::default();
        r.reset(0);
        assert_eq!(r.lone_velocity(&s, 0, SD), None);
        run(&mut r, &s, 1, (100, 160), 15.0, false);
        let (sign, bound) = r.lone_velocity(&s, 0, SD).expect("past lone_sd");
        assert_eq!(sign, -1);
        // 0.5 (60 + 2 (10 + 7)) sd at 3 kHz.
        let want = 0.5 * (60.0 + 2.0 * f64::from(s.band[0] + s.band[1])) * SD as f64;
        assert!((bound as f64 - want).abs() <= 2.0, "{bound} vs {want}");
        assert_eq!(r.lone_velocity(&s, 1, SD), None);
    }
}
