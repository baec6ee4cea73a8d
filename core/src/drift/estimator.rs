//! The estimator: when a motion ends.
//!
//! A motion is integrated from its onset (where the start test says its run began, at zero
//! velocity, [`super::rest`]), every sample, exactly. It ends when two things hold on both
//! horizontal axes at a tick's end:
//!
//! - **quiet**: the last 20 ms of raw ticks have a mean within `K_QUIET` sd of the zero, plus
//!   what the measured disturbance can put into a 20 ms mean (`G_quiet A` per tick,
//!   [`super::noise`]). 20 ms is the stop latency this test costs (a stroke's deceleration
//!   tapers to zero at its end); a hand's deceleration is not over while it fails;
//! - **the velocity explained**: the integrated velocity `V` within `K_VELOCITY` of its own
//!   sd, `sd(V)^2 = q n + q n^2 / N_b` (`n` samples since the onset, the zero averaged over
//!   `N_b` samples; REFERENCE (i)), plus the velocity amplitude the disturbance measured now
//!   could give (`A fs / (2 pi f D)` at its frequency; a disturbed motion starts from the
//!   disturbance's own velocity, [`super::rest`], so only its swing since remains).
//!
//! Mid-stroke the acceleration passes through zero while the hand moves fastest: the velocity
//! keeps the motion going. A drag's glide has no acceleration at all, but its velocity is
//! many sd from zero (the accelerometer saw the ramp that made it: `sd(V)` grows as
//! `sqrt(ND^2 t / 2 + sd(b)^2 t^2)`, 5 mm/s 2 s after a ramp): it goes on. A velocity that
//! no acceleration explains and that is within `K_VELOCITY` sd is stopped, however long it
//! has lasted: there is no timeout.
//!
//! Both tests are on the two horizontal axes together: `sum_a (e_a / sd_a)^2 <= K^2`, each
//! `e_a` the axis's offset less its allowance, `K^2` the 99.73 % point of a chi-square with 2
//! degrees of freedom (11.8): a motion along a diagonal is judged as one along an axis.
//!
//! # On a shaking desk
//! A motion that starts while the desk is disturbed (a machine vibrating, starting up faster
//! than the disturbance's estimate follows; a ring) may be the disturbance itself: it is held
//! until its velocity stands out of what the velocity test explains (the disturbance's
//! velocity allowed for), and discarded if it stops first. A hand's stroke outruns a
//! vibration's velocity (2.6 mm/s at 50 mg and 30 Hz) within tens of milliseconds. Its
//! replay counts: a stroke found after it ended (a slow one's two lobes together) is at rest
//! again when it starts, but its velocity stood out at a replayed block's end, so it is a
//! hand's ([`super::rest`]). And a motion found within a tick, before a tick's end could
//! show the desk disturbed, is made unproven at the first tick's end that does, while its
//! hold has delivered nothing of it: the hand-band residual that measures the disturbance
//! is centred 40 ms back, and a machine spinning up starts the fast test first. A machine
//! that starts at once is followed from below by the measured amplitude while the long
//! average catches up (160 ms), so until the desk has been disturbed for that long, a
//! replay is proven a hand's only against the largest amplitude the short average allows
//! ([`super::noise::Disturbance::new_amplitude`]; on a desk shaking for longer that bound
//! is loose, and a stroke found whole after it ended was taken for the shaking): against
//! the measured one, two false starts within 0.2 s of a machine starting at 46.7
//! mg and 35 Hz delivered 7 counts (the lab's vibration-rest, seed 17, trial 13). The same
//! bound for the proof while moving was tried and not kept: over seeds 9-21 it moved
//! knocks both ways (0.35 -> 0.76 mm, 0.10 -> 0.03) and no trial needed it.
//!
//! # A glide that fades
//! A glide's velocity is stopped once its uncertainty has grown past it (a 10 mm/s glide 1.5 s
//! after its ramp), although the hand may glide on: if its ramp down then started a motion
//! from zero velocity, it would run the cursor back at the glide's speed. So a stop after the
//! acceleration has been calm for an eighth of the longest stroke (no deceleration brought the
//! velocity down: a glide faded, it did not end) keeps the velocity as **latent**: the cursor
//! stops, and a motion that starts within `glide_max_s` of it starts from that velocity, its
//! uncertainty counted from the glide's own onset. A ramp down then brings it to zero.
//!
//! Calm is judged on the quiet test's own windows, but at the bound for the whole span:
//! its `m = fade_ticks / quiet_ticks` windows (12.5) each have the one window's tail `p`
//! (0.27 %) of failing on noise alone, so an unbroken run of quiet windows failed by noise
//! in about `m p` of glides (3 %) and a small jolt (a hand's tremor, a desk's tick) broke it
//! every time: the glide's velocity was then dropped at its stop, and its ramp down ran the
//! cursor back (the lab's `drags:13`, seeds 2 and 3: 7.6 mm). A window breaks the calm only
//! past the chi-square whose 2-dof tail is `p / m`, `chi2 + 2 ln m` (16.9): the span as a
//! whole keeps the one window's error rate. A stroke's deceleration is far past either.
//!
//! The calm's bound keeps its error rate over the span, not over a glide of seconds: noise
//! breaks a long glide's calm now and then, and if its velocity is explained just after, it
//! stopped as a motion that decelerated to rest (the lab's drags, seed 11, trial 122: a 12.9
//! mm/s glide's calm broken by a window at 19.2 against 16.9, its velocity explained 32
//! ticks later at 9.2 mm/s, 3.4 sd; its ramp down 1.7 s later started from zero velocity
//! and ran the cursor back 9.2 mm). The velocity itself tells them apart: a hand that
//! decelerated to rest left it near zero, a glide near the velocity it held. So a stop calm
//! for the wait at the longest calm's bound (below) whose velocity is nearer the motion's
//! mean (its velocities at block ends averaged) than zero, the mean out of its own
//! uncertainty, is a glide that faded too: `2 V . M > M . M` is the likelihood ratio's side
//! for the two, equally uncertain. A jolt (a knock's few ticks) has a mean but no calm; a
//! motion within the noise has no mean out of its uncertainty (a slow stroke after a tilt:
//! taken for a glide, seed 11's after-tilt 172 ends 35.5 mm off, allowed 18.4).
//!
//! A glide's velocity may stand out of its uncertainty for tens of seconds, so a motion that
//! starts from a wrong velocity (a stroke found in its second lobe, a ramp down taken for a
//! ramp up) would glide that long. No hand glides longer than `glide_max_s`, and its ramps'
//! calm ends add at most the longest stroke: a motion calm for longer than both stops, its
//! velocity dropped. That bounds such a runaway; it does not mend it. That calm is judged
//! at its own span's bound, `chi2 + 2 ln m` for its `m = calm_max / quiet_ticks` windows
//! (23.2 for 300), as the fade's is: at the fade's bound noise broke a 6 s calm in about
//! one span in ten (300 windows at a 0.02 % tail each), and the runaway glided on for 6 s
//! more (a new user's two strokes after a tilt, still moving 10 s after the hand).
//!
//! A glide's estimated velocity random-walks (`ND sqrt(t / 2)`, plus the zero's error times
//! `t`) while the hand holds it steady: after seconds it may be several sd short of the
//! glide's, and the ramp down, which takes the whole glide, then leaves it pointing back
//! against the travel, unexplained (a 25.1 mm/s glide of the lab's drags, seed 4, trial
//! 110: 13 mm/s left of it after 1.7 s, its ticks 0.26 LSB against the travel, 4 sd of their
//! mean; 12 mm/s backwards after the ramp, 3.4 sd). It glided back until the longest calm.
//! A hand does not glide back without a lobe of its own after the ramp's, so a motion calm
//! for the stop's wait (an eighth of the longest stroke) whose velocity points against its
//! own travel (`V . D < 0`, `D` the sum of its velocities at block ends) ends there as one
//! that decelerated to rest: its velocity is error, and the bridge below moves it forward
//! by what a constant zero error gave it (that drag: 6.1 mm off, allowed 14.5, after 24.4).
//! That bridge never moves the cursor back, so what such a motion runs back during the wait
//! is taken back at its end if the wait completes: nothing is delivered while a motion calm
//! at the last tick has its velocity against its travel ([`super::Detector::pauses`]), and
//! what it integrated meanwhile follows if the wait ends otherwise (the acceleration
//! returns: a hand's lobe, delivered late by at most the wait). That drag ran back 4.3 mm
//! during the wait, and 0.8 mm now (during its ramp down, which is not calm). A hand that
//! reverses into a glide without stopping is cut at the wait: where the sensor cannot tell
//! them apart, the target's "never back" decides.
//!
//! A stroke ends with a deceleration, but near the noise floor its velocity may be explained
//! before the deceleration is over; what is left of it would start a motion backwards. So
//! any stop keeps its velocity for an eighth of the longest stroke (the fade's own quiet
//! time), and a motion whose run began within it and whose acceleration since points against
//! that velocity (`a . V < 0`: the rest of the deceleration) resumes the one that stopped; a
//! click forgets it. Within it, counted to the run's onset, not to the alarm: near the noise
//! floor the rest of a deceleration is found late (a 45.5 mm stroke over 1.68 s at 741
//! ug/sqrt(Hz) stopped mid-way at 26 mm/s, and its deceleration, whose run began at that
//! stop, alarmed 0.26 s later and went back 59 to 83 mm from zero velocity). A motion that
//! accelerates along or across the stopped velocity is a new stroke (a zigzag's next leg,
//! begun as the last ended at rest): resumed, it carried the stopped motion's whole
//! uncertainty, its stop test explained it within tens of milliseconds, and the rest of the
//! leg glided (a new user's five-leg zigzags at 428 ug/sqrt(Hz): 17 of 40 draws outside
//! their target, 6 with the direction test). A faded glide's velocity is resumed by any
//! motion: its ramp down, or the hand speeding up again.
//!
//! Either way the resuming motion's stop judges the resumption. The rest of a deceleration
//! or a ramp down brings the resumed velocity `W_r` to zero; a motion of its own (a stroke
//! begun within the wait whose first lobe happens to point against `W_r`, half of them; a
//! stroke after a knock's tiny motion; a faded glide's velocity taken up by the next stroke
//! seconds later) comes to rest with `W_r` still in its velocity. So a stop whose velocity
//! is nearer `W_r` than zero (the likelihood ratio's side, as for the faded glide above)
//! carried it: its correction takes back what `W_r` moved over the motion's own samples
//! (`Z -= 2 W_r n_own`) and bridges only the rest of the velocity over them. A faded
//! glide's own span is left as its stop left it: it was a hand's glide at its start, its
//! velocity lost within its uncertainty only as it faded (bridged too, the lab's families
//! were the same and a new tester's mixed sessions 84.2 -> 83.9 % within). Bridged as one
//! motion over the whole span, the wait included, a 26.7 mm stroke over 0.3 s at 150
//! ug/sqrt(Hz) that took up a 4.4 mm/s glide 2.3 s old jumped 8.6 mm at its stop (that
//! tester's: 6.9 mm off, 0.1 now); of the lab's knocky strokes on seeds 1-21, 10 more
//! within and 1 less. The judgment needs no memory of its own: the resumed velocity stays
//! in [`Latent`] until the stop.
//!
//! That correction is made whichever way it points, at once. The bridge's premise (below)
//! fails when the hand still moves at the stop, so the bridge does not move the cursor back
//! at the stop; this one's premise is the judgment itself: the motion came to rest, a deceleration's end and not a
//! fade, with `W_r` still in it, so `W_r` was not its hand's. A stroke that takes up a faded
//! glide along its own way (a slow stroke whose deceleration stayed calm past the fade's
//! quiet time, the next stroke 0.26 s later in nearly its direction) carried `W_r` along its
//! travel, and a forward test kept all of it: a new tester's 36.8 mm stroke over 0.4 s at
//! 100 Hz and 150 ug/sqrt(Hz) ended 3.3 mm past its end (0.4 mm now; that tester's 862
//! motions 84.2 -> 87.4 % within, 46 closer by more than 0.3 mm and none further). Its
//! cost: a wobble within a drag's glide that takes the glide up and comes to rest with it
//! is stepped back by `W_r` over the wobble's samples. `W_r` had faded within its
//! uncertainty, so the step is at most that uncertainty over the wobble's length (the lab's
//! drags on seeds 1-21: 5 of 4200 step back, by 0.39 to 1.56 mm; their errors moved by
//! -1.7 to +0.8 mm, each still within its bound).
//!
//! # A long stroke's deceleration
//! A motion started as a long stroke's first lobe left the blocks ([`super::rest`]) begins
//! where its run rose, not where the hand began: its velocity is short of the hand's by what
//! the first lobe gave before, and near the noise floor its deceleration is within the quiet
//! test (a 25 mm stroke over 2 s decelerates at 3.5 mg; a 20 ms mean's sd is 1.5 mg). Its
//! velocity, short, was explained mid-way through the deceleration; the rest of it, found
//! again from rest, ran the cursor back a few millimetres (20 mm over 2 s: 24 of 48 noise
//! draws more than 2 mm). So such a motion does not stop while the tilt tests' long
//! sub-window (400 ms, where that deceleration is several sd) is significant against its
//! travel (its velocity before its first block's end): against the travel, not the
//! velocity, which the deceleration takes through zero before the hand stops (10 of the 48
//! still went back more than 2 mm, each by at most 7.3). Nor while the tick ring's mean
//! acceleration points against its velocity, significant or not: near the floor the
//! deceleration stays under the sub-window's test for most of its length (4 of the 48 go
//! back more than 2 mm with it; the guard's own docs).
//!
//! # What sampling leaves
//! A minimum-jerk stroke's acceleration starts and ends with a jerk step of `32 v / D^2`
//! (`v` its peak velocity, `D` its duration). The samples' sum is the integral plus the
//! spectrum at the multiples of `fs` (Poisson's summation), and a step `J` puts `J / (2 pi
//! f)^2` there: at most `J / (12 fs^2)` in all, so a stroke can end with `16 v / (3 (D
//! fs)^2)` of velocity that no noise explains (a 96 mm stroke over 0.21 s at 100 Hz: 10.7
//! mm/s, 10 sd of the noise's). The velocity test allows for it per axis, at the shortest
//! stroke a hand makes below `knock_hz / 2`, `D = 2 / knock_hz` (0.1 s): 5.3 % of the
//! motion's top speed (at block ends) at 100 Hz, 0.006 % at 3 kHz.
//!
//! # The end's bridge
//! A motion that decelerated to rest ends with a velocity `V` that is error: the noise's
//! random walk and the zero's error, both from zero at the onset. Given that end value, the
//! error's expected path is the straight line from zero to `V` (for the zero's error
//! exactly, for the random walk a Brownian bridge's mean), so the position is expected
//! `V n / 2` off after `n` samples, and the stop moves it back by that (`Z -= W n`,
//! [`Action::Settle`]). Knowing the end removes three quarters of the random walk's
//! position variance (`n^3 / 3` to `n^3 / 12` in units of the per-sample variance): the
//! position's sd halves. There is no constant in it.
//!
//! The premise fails when the stop comes while the hand still moves (a slow deceleration
//! within the velocity's uncertainty: a noisy sensor, a long stroke). The velocity left then
//! points along the motion, and the correction would move the cursor back by the hand's own
//! velocity times half the motion. So a correction that points back against the motion's
//! travel (its velocity summed at each 20 ms block's end) is not made at the stop: there the
//! bridge only moves the cursor on towards where the hand went (a carried velocity's
//! correction, above, is another judgment). A motion that resumes the one that stopped (its
//! hand was still moving) keeps the correction: taking it back would be a step back; its own
//! stop corrects the whole span less what was corrected already, again only forwards. A
//! faded glide (its hand may still move) stops without one, and on a disturbed desk the
//! velocity the disturbance can swing (the velocity test's allowance) is not taken for
//! error.
//!
//! # The late bridge
//! Never pulling back is one-sided: a velocity error along the travel is half of all noise
//! draws, and each left its stroke over by `V n / 2` (of a new tester's strokes at 100 Hz
//! and 150 ug/sqrt(Hz), 8 ended outside their target, 7 of them long; at 300 ug/sqrt(Hz) a
//! 14.3 mm stroke over 0.46 s ended 1.6 mm over, its velocity error 5.2 mm/s along the
//! travel at its stop, the hand at rest). The rest after the stop tells the two apart.
//! A hand still moving at the stop decelerates after it, within the stop's wait (an eighth of
//! the longest stroke, where a stroke's rest of deceleration resumes its velocity): the
//! acceleration over that wait takes the velocity left, `E` (the stop's velocity error, the
//! disturbance's allowance taken off), back to zero. A velocity that was error leaves the
//! acceleration after the stop nil. So a stop whose bridge points back keeps it pending
//! ([`Latent`]'s `pending`, in the latent's padding: no RAM), and once the tick ring holds
//! only the rest since (`REPLAY` ticks: 0.32 s at 200 Hz and above, 0.51 s at 250 Hz, 0.64 s
//! at 100 Hz) `Detector::late_bridge` sums the wait's acceleration, `dW`: nearer `-E`
//! than zero (`2 (-dW) . E > E . E`, the likelihood ratio's side) the hand was moving and
//! nothing is made; else the bridge is made then, in one step back. No constant: the wait is
//! the stop's own. It is judged at the ring's end, not the wait's, because a test on every
//! tick at rest cost the sample path 1.0 instruction a triple at 3 kHz (codegen).
//!
//! Only where a step back is the bridge's: not for a motion that glided (calm for the fade's
//! quiet time while moving, [`Motion`]'s `glided`: a drag's glide, whose velocity error a
//! step back would retreat by, target 2), nor one longer than the longest stroke, nor one
//! that resumed a velocity (its span holds another's correction), nor one that came to rest
//! nearer its mean velocity than zero (a glide's velocity held, or a knock's swing: the
//! lab's knocks, 21 more over 0.3 mm without it). A motion, a click or a lift within the
//! ring's time drops the pending step.
//!
//! # Error rates
//! `K^2 = 11.8` (2 degrees of freedom, 0.27 %): a window at rest passes the quiet test with
//! probability 0.997 (a false "not quiet" only delays a stop by a tick); the end of a stroke
//! at rest is taken for a glide with probability 0.27 %, and that glide then stops as `sd(V)`
//! grows past it.

use super::click::Click;
use super::noise::within;
use super::ticks::offset;
use super::{Action, Detector, DriftSettings};

/// A motion under way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Motion {
    /// Samples integrated since the onset (of the glide a latent velocity came from).
    pub(crate) samples: u64,
    /// Ticks since the quiet test last failed at the fade's span bound (a deceleration).
    calm_run: u32,
    /// Ticks since it last failed at the longest calm's span bound.
    long_calm: u32,
    /// Started on a disturbed desk and not yet out of the disturbance's velocity.
    pub(crate) unproven: bool,
    /// Started as a long stroke's first lobe left the blocks, its second lobe going on
    /// ([`super::rest`]): it does not stop while that lobe decelerates it (the long stroke's
    /// stop guard).
    pub(crate) long: bool,
    /// The horizontal velocities (`W`) summed at each block's end since the onset, of the
    /// motion this one resumes too: the direction of its travel, for the bridge.
    travel: [i64; 2],
    /// The block ends `travel` summed.
    blocks: u32,
    /// The bridge's corrections made so far to this motion (at the stops of the motions it
    /// resumes) [`Z = 4 S` units].
    corrected: [i128; 2],
    /// What sampling can have left of its velocity: its largest speed at a block's end times
    /// `alias` ([`DriftSettings`]), per horizontal axis [`V`, Q16 counts times samples].
    alias: [u64; 2],
    /// Glided: calm for the fade's quiet time at some tick (a drag's glide; the late bridge
    /// never steps it back).
    pub(crate) glided: bool,
}

/// A stopped motion's velocity, waiting for the next motion; once that motion resumes it,
/// kept until its stop judges whether it held it (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Latent {
    /// The velocity (`W = 2 V`) per horizontal axis; zeros for none.
    w: [i64; 2],
    /// The stopped motion's samples since its onset, at its stop.
    samples: u64,
    /// The tick of its stop; once resumed, the samples of the resuming motion's span before
    /// its own replay (the stopped motion's and the wait).
    at: u64,
    /// Ticks it waits.
    life: u32,
    /// A faded glide's, which any motion resumes; else a stopped motion's, which only the
    /// rest of its deceleration resumes.
    glide: bool,
    /// Resumed by the motion under way.
    resumed: bool,
    /// Its stop's bridge points back against a travel that never glided: judged once the
    /// tick ring holds only the rest after it (`Detector::late_bridge`).
    pub(crate) pending: bool,
}

impl Latent {
    /// At the stop of the motion that resumed it, with the velocity `v` (`W`) over a span of
    /// `span` samples: if `v` is nearer its velocity than zero (the likelihood ratio's side,
    /// [`nearer_than_zero`]), that motion was one of its own that carried it: its velocity
    /// and the samples of that motion's own.
    fn carried(&self, v: [i64; 2], span: u64) -> Option<([i64; 2], u64)> {
        (self.resumed && nearer_than_zero(v, self.w))
            .then(|| (self.w, span.saturating_sub(self.at)))
    }
}

impl Motion {
    /// A motion whose onset was `samples` samples ago; one that `resumes` the last keeps its
    /// travel and its corrections.
    pub(crate) fn begin(&mut self, samples: u64, resumes: bool) {
        self.samples = samples;
        self.calm_run = 0;
        self.long_calm = 0;
        self.unproven = false;
        self.long = false;
        if !resumes {
            self.glided = false;
            self.travel = [0; 2];
            self.blocks = 0;
            self.corrected = [0; 2];
            self.alias = [0; 2];
        }
    }

    /// The bridge's correction at this motion's stop with the velocity error `e` (`W`, see
    /// [`velocity_error`]), made ([`Motion::made`]) if it does not move the cursor back
    /// against its travel; else `None`, nothing made (see the module docs).
    fn bridge(&mut self, e: [i64; 2]) -> Option<[i128; 2]> {
        let dz = self.bridged(e);
        forward(dz, self.travel).then(|| self.made(dz))
    }

    /// The bridge's correction for the velocity error `e` (`W`): `-e n` over its `n` samples,
    /// less the corrections already made to it [`Z = 4 S` units].
    fn bridged(&self, e: [i64; 2]) -> [i128; 2] {
        let n = i128::from(self.samples);
        [0, 1].map(|a| {
            (-i128::from(e[a]))
                .saturating_mul(n)
                .saturating_sub(self.corrected[a])
        })
    }

    /// The correction `dz` (`Z = 4 S` units), counted as made.
    fn made(&mut self, dz: [i128; 2]) -> [i128; 2] {
        for (c, dz) in self.corrected.iter_mut().zip(dz) {
            *c = c.saturating_add(dz);
        }
        dz
    }

    /// The correction at the stop of a motion that carried a stopped one's velocity `w`
    /// (`W`) it did not hold ([`Latent::carried`]), its velocity error `e` left beside it:
    /// `w` held over its own `own` samples (`Z += 2 w own`) and the bridge of `e` over them
    /// (`-e own`), made whichever way it points (see the module docs). Counted as made. Out
    /// of line: it runs only at such a stop.
    #[inline(never)]
    fn unwind(&mut self, w: [i64; 2], e: [i64; 2], own: u64) -> [i128; 2] {
        // |w|, |e| < 2^63 and the span held below 2^40 samples (a year at 20 kHz): below
        // 2^105.
        let own = i128::from(own.min(1 << 40));
        let dz = [0, 1].map(|a| -((2 * i128::from(w[a]) + i128::from(e[a])) * own));
        self.made(dz)
    }

    /// A block ended with the velocities `w` (`W`): its share of the travel.
    fn travelled(&mut self, w: [i64; 2], alias_q32: u64) {
        self.blocks = self.blocks.saturating_add(1);
        for ((t, m), w) in self.travel.iter_mut().zip(&mut self.alias).zip(w) {
            *t = t.saturating_add(w);
            // |W| / 2 < 2^63, times a Q32 below 2^32: below 2^127.
            let alias = (u128::from(w.unsigned_abs() / 2) * u128::from(alias_q32)) >> 32;
            *m = (*m).max(alias as u64);
        }
    }

    /// Its mean velocity at block ends (`W`), if a block has ended in it.
    fn mean(&self) -> Option<[i64; 2]> {
        (self.blocks > 0).then(|| self.travel.map(|t| t / i64::from(self.blocks)))
    }

    /// One more sample integrated.
    #[inline(always)]
    pub(crate) fn sample(&mut self, click: &mut Click) {
        self.samples += 1;
        click.motion_sample();
    }
}

/// The velocity error left at the stop of a motion that came to rest with the horizontal
/// velocities `w` (`W = 2 V`, Q16 counts times samples), of which the desk's disturbance may
/// account for `allow` (`V` units): `W` less twice its allowance per axis, toward zero.
pub(crate) fn velocity_error(w: [i64; 2], allow: [u64; 2]) -> [i64; 2] {
    [0, 1].map(|a| {
        let left = w[a]
            .unsigned_abs()
            .saturating_sub(allow[a].saturating_mul(2));
        // At most i64::MAX (a saturated W of i64::MIN leaves 2^63).
        w[a].signum() * left.min(i64::MAX as u64) as i64
    })
}

/// Whether a correction `c` (any scale) does not point back against the travel `d`
/// (`c . d >= 0`); `c` is scaled below 2^63 first, so that the products fit 128 bits.
pub(crate) fn forward(c: [i128; 2], d: [i64; 2]) -> bool {
    let m = c[0].unsigned_abs().max(c[1].unsigned_abs());
    let shift = (128 - m.leading_zeros()).saturating_sub(62);
    let dot: i128 = (0..2).map(|a| (c[a] >> shift) * i128::from(d[a])).sum();
    dot >= 0
}

/// Whether the velocity `w` points back against the travel `d` (`w . d < 0`, exactly: each
/// product of two `i64` is below 2^126, their sum below 2^127).
pub(crate) fn points_back(w: [i64; 2], d: [i64; 2]) -> bool {
    i128::from(w[0]) * i128::from(d[0]) + i128::from(w[1]) * i128::from(d[1]) < 0
}

/// Whether the velocity `w` is nearer `m` than zero (both `W`, per horizontal axis):
/// `|w - m| < |w|`, that is `2 w . m > m . m`. The likelihood ratio's side for a velocity
/// held at `m` against one brought to zero, the two equally uncertain.
pub(crate) fn nearer_than_zero(w: [i64; 2], m: [i64; 2]) -> bool {
    // |w|, |m| < 2^63: each product below 2^126, their sums saturate.
    let dot = |x: [i64; 2]| -> i128 {
        (0..2)
            .map(|a| i128::from(x[a]) * i128::from(m[a]))
            .fold(0, i128::saturating_add)
    };
    dot(w).saturating_mul(2) > dot(m)
}

/// Whether two offsets `d` (Q16 sums) with variances `var` (squared units) and allowances
/// `allow` are explained together: `sum ((|d| - allow)^+ / sd)^2 <= K^2` (2 dof).
fn explained_2d(bound_q8: u128, d: [i64; 2], var: [u128; 2], allow: [u64; 2]) -> bool {
    chi2_2d(bound_q8, d, var, allow) <= bound_q8
}

/// The chi-square `sum ((|d| - allow)^+ / sd)^2` of [`explained_2d`] (Q8), or `cap_q8 + 1`
/// once past `cap_q8`.
fn chi2_2d(cap_q8: u128, d: [i64; 2], var: [u128; 2], allow: [u64; 2]) -> u128 {
    let mut chi2_q8 = 0u128;
    for a in 0..2 {
        let e = u128::from(d[a].unsigned_abs().saturating_sub(allow[a]));
        let e2 = e * e; // < 2^128: e < 2^64
        let v = var[a].max(1);
        // (e^2 / var) in Q8, saturating well above the bound; an offset within its
        // allowance adds nothing (and costs no 128-bit division).
        chi2_q8 += if e2 == 0 {
            0
        } else if e2 >> 119 != 0 {
            cap_q8 + 1
        } else {
            quotient(e2 << 8, v)
        };
        if chi2_q8 > cap_q8 {
            return cap_q8 + 1;
        }
    }
    chi2_q8
}

/// `n / d`, in 64 bits when both fit (the usual case: a Cortex-M4 divides 64 bits several
/// times faster than 128).
fn quotient(n: u128, d: u128) -> u128 {
    match (u64::try_from(n), u64::try_from(d)) {
        (Ok(n), Ok(d)) => u128::from(n / d),
        _ => n / d,
    }
}

impl Detector {
    /// Whether the last 20 ms are quiet on the horizontal axes against the zeros `bias`.
    pub(crate) fn quiet(&self, s: &DriftSettings, bias: [i64; 3]) -> bool {
        self.quiet_chi2(s, bias, s.chi2_q8) <= s.chi2_q8
    }

    /// The quiet test's chi-square (Q8), or `cap_q8 + 1` once past `cap_q8`.
    fn quiet_chi2(&self, s: &DriftSettings, bias: [i64; 3], cap_q8: u128) -> u128 {
        let k = s.quiet_ticks;
        let w = self.stream.window(k);
        let n = u64::from(k) * u64::from(s.tick);
        let allow = |a: usize| {
            let d = &self.disturbance[a];
            d.allow(d.gains(s).quiet_q16, u64::from(k))
        };
        chi2_2d(
            cap_q8,
            [0, 1].map(|a| offset(w[a], n, bias[a])),
            [0, 1].map(|a| self.noise[a].var(n, self.bias_samples)),
            [allow(0), allow(1)],
        )
    }

    /// Whether the velocities `W = 2 V` of a motion of `n` samples, its zero averaged over
    /// `nb` samples, are explained by their uncertainty on the horizontal axes.
    pub(crate) fn velocity_explained(
        &self,
        s: &DriftSettings,
        velocity: [i64; 3],
        n: u64,
        nb: u64,
    ) -> bool {
        self.velocity_explained_with(s, velocity, n, nb, self.velocity_allowance(s))
    }

    /// [`Self::velocity_explained`] with the disturbance's velocity allowance `allow` (`V`
    /// units per horizontal axis).
    pub(crate) fn velocity_explained_with(
        &self,
        s: &DriftSettings,
        velocity: [i64; 3],
        n: u64,
        nb: u64,
        allow: [u64; 2],
    ) -> bool {
        explained_2d(
            s.chi2_q8,
            [velocity[0] / 2, velocity[1] / 2],
            [0, 1].map(|a| self.noise[a].var(n, nb)),
            [0, 1].map(|a| allow[a].saturating_add(self.motion.alias[a])),
        )
    }

    /// Whether the velocities `W` left at a stop are nearer the motion's mean velocity than
    /// zero, the mean itself out of its uncertainty: the velocity held (a glide), no
    /// deceleration brought it down (see the module docs).
    fn held_near_mean(&self, s: &DriftSettings, w: [i64; 3]) -> bool {
        self.motion.mean().is_some_and(|m| {
            nearer_than_zero([w[0], w[1]], m)
                && !self.velocity_explained(
                    s,
                    [m[0], m[1], 0],
                    self.motion.samples,
                    self.bias_samples,
                )
        })
    }

    /// Whether the velocities `W = 2 V` of a lone lobe's mate are what the lone lobe can have
    /// given, reversed, on each axis where it rose past `lone_sd`: against its sign at most
    /// its bound, along it nothing, each within `K_TILT` of its own sd ([`super::rest`]).
    fn lone_explains(&self, s: &DriftSettings, velocity: [i64; 3]) -> bool {
        let (n, nb) = (self.motion.samples, self.bias_samples);
        let mut any = false;
        for (a, &w) in velocity.iter().enumerate().take(2) {
            if let Some((sign, bound)) = self.rest.lone_velocity(s, a, self.noise[a].sd_q16) {
                let v = w / 2;
                let allow = if v.signum() == -sign { bound } else { 0 };
                if !within(v, self.noise[a].var(n, nb), s.k2_q8, allow) {
                    return false;
                }
                any = true;
            }
        }
        any
    }

    /// The velocity amplitude (`V`, Q16 counts times samples) the disturbance measured now
    /// can give each horizontal axis; 0 on a quiet desk.
    fn velocity_allowance(&self, s: &DriftSettings) -> [u64; 2] {
        [0, 1].map(|a| {
            let d = &self.disturbance[a];
            d.allow(d.gains(s).velocity_q16, 1)
        })
    }

    /// The velocity allowance of the amplitude a new disturbance may already have
    /// ([`super::noise::Disturbance::new_amplitude`]): what proves a motion that started on
    /// a shaking desk a hand's (see the module docs).
    pub(crate) fn new_velocity_allowance(&self, s: &DriftSettings) -> [u64; 2] {
        [0, 1].map(|a| {
            let d = &self.disturbance[a];
            d.with_amplitude(d.new_amplitude(s))
                .allow(d.gains(s).velocity_q16, 1)
        })
    }

    /// The velocity a motion whose run began at tick `onset`, replaying `own` samples,
    /// carries: a faded glide's, or a stopped motion's if this one decelerates it (zeros
    /// `bias`), if the onset is within its wait; and the motion's span, the samples since
    /// that motion's onset (for its uncertainty). Kept, marked resumed, for the stop to
    /// judge ([`Latent::carried`]); else used up. Out of line: it runs once a start.
    #[inline(never)]
    pub(crate) fn take_latent(
        &mut self,
        s: &DriftSettings,
        onset: u64,
        bias: [i64; 3],
        own: u64,
    ) -> Option<([i64; 2], u64)> {
        let l = core::mem::take(&mut self.latent);
        let waited = onset.saturating_sub(l.at);
        if l.resumed || l.w == [0; 2] || waited > u64::from(l.life) {
            return None;
        }
        if !l.glide && !self.decelerates(s, onset, bias, l.w) {
            return None;
        }
        let since = self.stream.ticks() - l.at;
        let span = (l.samples + since * u64::from(s.tick)).max(own);
        self.latent = Latent {
            at: span - own,
            resumed: true,
            pending: false,
            ..l
        };
        Some((l.w, span))
    }

    /// Whether a long stroke's motion ([`Motion`]'s `long`) is still decelerating: on X or Y
    /// the last long sub-window of the tilt tests is significant against its travel, or the
    /// tick ring's mean acceleration (its last 320 ms) points against its velocity,
    /// significant or not. A slow stroke's deceleration is within the quiet test's 20 ms (a
    /// 25 mm stroke over 2 s decelerates at 3.5 mg, a 20 ms mean's sd is 1.5 mg), not within
    /// the long sub-window's. Against the travel, not the velocity: found late in its first
    /// lobe, the motion's velocity is short of the hand's by what that lobe gave before, and
    /// its deceleration takes it through zero before the hand stops. The ring's sign alone:
    /// near the floor the deceleration stays under the sub-window's test for most of its
    /// length, and released at its velocity explained, the motion took the hand's velocity
    /// left for error and its stop's bridge moved it back (20 mm over 2 s at 4.8 LSB of
    /// noise a sample: 10 of 48 draws back by more than 2 mm, 4 with it). Once the hand has
    /// stopped, the ring holds its deceleration for at most its length; on noise the sign is
    /// then a coin's, and a zero's error against the velocity drives that velocity through
    /// zero, where the sign turns: the wait ends.
    /// (Before its first block's end it has no travel yet: its velocity `W` then.)
    /// Out of line: it runs only at a stop, and inlined into the tick's decisions it costs the
    /// sample path 1.6 instructions a triple at 3 kHz (codegen).
    #[inline(never)]
    fn long_decelerating(&self, s: &DriftSettings, bias: [i64; 3], w: [i64; 3]) -> bool {
        if !self.motion.long {
            return false;
        }
        let t = self.motion.travel;
        let d = if t == [0; 2] { [w[0], w[1]] } else { t };
        let ring = self.stream.ticks().saturating_sub(super::RING as u64);
        (0..2).any(|a| {
            let sign = self.sub_sign(s, (1, a, 0), bias[a], s.k2_q8);
            sign != 0 && i64::from(sign) * d[a].signum() < 0
        }) || self.decelerates(s, ring, bias, [w[0], w[1]])
    }

    /// Whether the horizontal acceleration since `onset` (the raw ticks since, at least the
    /// last, at most the tick ring's) points against the velocity `w`: `a . w < 0`.
    fn decelerates(&self, s: &DriftSettings, onset: u64, bias: [i64; 3], w: [i64; 2]) -> bool {
        let k = (self.stream.ticks() - onset).clamp(1, super::RING as u64) as u32;
        let sums = self.stream.window(k);
        let n = u64::from(k) * u64::from(s.tick);
        // |offset| < 2^52 (2^20 samples of 16-bit codes in Q16), |w| < 2^63: each product
        // below 2^115.
        let dot: i128 = (0..2)
            .map(|a| i128::from(offset(sums[a], n, bias[a])) * i128::from(w[a]))
            .sum();
        dot < 0
    }

    /// Whether a motion calm at the fade's bound at the last tick has the horizontal velocity
    /// `w` (`W`) against its travel: in the reversed stop's wait (see the module docs).
    pub(crate) fn backing(&self, w: [i64; 2]) -> bool {
        self.motion.calm_run > 0 && points_back(w, self.motion.travel)
    }

    /// The correction at the stop of a motion of `samples` samples that decelerated to rest
    /// with the velocity `v` (`W`), `resumed` the velocity it resumed if any: a motion that
    /// came to rest nearer that velocity than zero held it, a motion of its own that carried
    /// its error ([`Motion::unwind`]); else the bridge. Out of line: it runs once a motion,
    /// and inlined into the tick's decisions it cost the sample path 1.0 instruction a
    /// triple at 3 kHz (codegen: the scene's motions resume nothing).
    #[inline(never)]
    fn settle(
        &mut self,
        s: &DriftSettings,
        v: [i64; 2],
        samples: u64,
        resumed: Latent,
    ) -> [i128; 2] {
        let allow = self.velocity_allowance(s);
        match resumed.carried(v, samples) {
            Some((w, own)) => {
                let e = [0, 1].map(|a| v[a].saturating_sub(w[a]));
                self.motion.unwind(w, velocity_error(e, allow), own)
            }
            None => {
                let e = velocity_error(v, allow);
                if let Some(dz) = self.motion.bridge(e) {
                    return dz;
                }
                let stroke = u64::from(s.land_timeout) * u64::from(s.tick);
                if !self.motion.glided
                    && !resumed.resumed
                    && self.motion.samples <= stroke
                    && !self.motion.mean().is_some_and(|m| nearer_than_zero(v, m))
                {
                    self.latent.pending = true;
                    self.latent.w = e;
                }
                [0; 2]
            }
        }
    }

    /// A stop's bridge that pointed back ([`Latent`]'s `pending`), judged once the tick ring
    /// holds only the rest after that stop (`REPLAY` ticks, the device still since): if the
    /// acceleration over the stop's wait after it (its first `fade_ticks`, where the rest of
    /// a deceleration would be) took the velocity error `E` the stop left nearer back to zero
    /// than not (`2 (-dW) . E > E . E`, the likelihood ratio's side), the hand was still
    /// moving at the stop and decelerated after it: no correction. Else that velocity was
    /// error, and the bridge is made now, late (see the module docs). Called at the first
    /// tick `REPLAY` ticks into a rest, with a step pending. Out of line: it runs once a rest
    /// at most.
    #[cold]
    #[inline(never)]
    pub(crate) fn late_bridge(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Option<Action> {
        self.latent.pending = false;
        // Still since that stop (a lift since is no rest after it).
        if self.latent.at != self.entered {
            return None;
        }
        let age = self.age();
        let wait = u64::from(s.fade_ticks).clamp(1, age);
        let sums = self.stream.ticks_back(age - wait + 1, age);
        let n = wait * u64::from(s.tick);
        // |offset| < 2^58, twice below 2^59.
        let after = [0, 1].map(|a| -2 * offset(sums[a], n, bias[a]));
        let e = self.latent.w;
        if nearer_than_zero(after, e) {
            return None;
        }
        let dz = self.motion.bridged(e);
        Some(Action::Settle {
            dz: self.motion.made(dz),
        })
    }

    /// Decisions while moving at a tick's end: the stop, a tilt's shadow, then the tilt
    /// tests.
    pub(crate) fn moving_tick(
        &mut self,
        s: &DriftSettings,
        bias: [i64; 3],
        velocity: [i64; 3],
        shadow: Option<[i64; 3]>,
    ) -> Action {
        // A motion found within a tick, before its end could show the desk disturbed (a
        // machine starting up: a burst), is the disturbance's as much as one found at a tick's
        // end: unproven while nothing of it has been delivered.
        if self.click.hold_left > 0 && !self.motion.unproven {
            self.motion.unproven = self.shaken_xy();
        }
        let chi2 = self.quiet_chi2(s, bias, s.calm_chi2_q8);
        let quiet = chi2 <= s.chi2_q8;
        self.motion.calm_run = if chi2 > s.fade_chi2_q8 {
            0
        } else {
            self.motion.calm_run + 1
        };
        self.motion.glided |= self.motion.calm_run >= s.fade_ticks;
        self.motion.long_calm = if chi2 > s.calm_chi2_q8 {
            0
        } else {
            self.motion.long_calm + 1
        };
        // Every use of the velocity test below is with the quiet one, but for a motion still
        // unproven: not computed otherwise (two 128-bit variances, most ticks of a stroke).
        let explained = (quiet || self.motion.unproven)
            && self.velocity_explained(s, velocity, self.motion.samples, self.bias_samples);
        // A lone lobe's mate ([`super::rest`]): once its velocity is past what the lone lobe
        // can have given, reversed, the lone lobe was noise and this is a hand's motion: no
        // longer held, nor a shadow its hold began. Calm unreversed within it, it ended a
        // glide the start tests missed: the device rests, and what was held is dropped.
        if self.tilt.lone() && self.tilt.unreversed() {
            if !self.lone_explains(s, velocity) {
                self.tilt.end_lone();
            } else if self.motion.calm_run >= s.fade_ticks {
                self.enter_still();
                return Action::Discard;
            }
        }
        // A tilt's shadow: the end that comes first decides, one the data tell from the other
        // ([`super::tilt`]).
        if let Some(w) = shadow {
            if self.stream.block_closed() {
                self.shadow_block(s, bias);
            }
            if let Some(action) = self.shadow_decision(s, bias, w, quiet, explained) {
                return action;
            }
        }
        if self.motion.unproven && !explained {
            self.motion.unproven = false;
        }
        // No hand glides longer than `glide_max_s`, and its ramps' calm ends (half a lobe each,
        // a lobe at most half the longest stroke) add at most the longest stroke: a motion
        // calm for longer glides on a velocity no hand gave it (a start in a stroke's second
        // lobe, a ramp down taken for a ramp up). It stops, its velocity dropped.
        if quiet && self.motion.long_calm > s.calm_max {
            // What the tilt tests held of it was never delivered: that glide is dropped too.
            let held = self.tilt.held();
            self.still_after_motion(s);
            return if held { Action::Discard } else { Action::Stop };
        }
        // Calm for the stop's wait with its velocity against its own travel: the ramp down
        // took more than the glide's velocity held (see the module docs).
        let reversed = quiet
            && self.motion.calm_run >= s.fade_ticks
            && self.backing([velocity[0], velocity[1]]);
        if quiet && (explained || reversed) && !self.long_decelerating(s, bias, velocity) {
            // A motion that ends younger than its hold was a jolt, not a stroke; one that
            // never stood out of the desk's disturbance was the disturbance; one soon after a
            // tilt that never reversed and outlasted the longest stroke glided on a velocity
            // no hand gave it ([`super::tilt`]). A tilt suspicion that ends in a stop was
            // refuted: deliver.
            let glided = self.tilt.unreversed() && self.age() > u64::from(s.land_timeout);
            let held = self.click.hold_left > 0 || self.motion.unproven || glided;
            let fade = !reversed
                && (self.motion.calm_run >= s.fade_ticks
                    || self.motion.long_calm >= s.fade_ticks && self.held_near_mean(s, velocity));
            let samples = self.motion.samples;
            let v = [velocity[0], velocity[1]];
            let resumed = core::mem::take(&mut self.latent);
            let discarded_only = self.motion.unproven;
            let real_end = self.real_end;
            self.still_after_motion(s);
            if discarded_only {
                self.real_end = real_end;
            }
            if !held {
                self.latent = Latent {
                    w: v,
                    samples,
                    at: self.stream.ticks(),
                    life: if fade { s.glide_ticks } else { s.fade_ticks },
                    glide: fade,
                    resumed: false,
                    pending: false,
                };
            }
            // The velocity left is error if the hand decelerated to rest (not a glide that
            // faded), but for what the desk's disturbance can swing it by (real velocity).
            return match (held, fade) {
                (true, _) => Action::Discard,
                (false, true) => Action::Stop,
                (false, false) => Action::Settle {
                    dz: self.settle(s, v, samples, resumed),
                },
            };
        }
        if self.stream.block_closed() {
            self.motion
                .travelled([velocity[0], velocity[1]], s.alias_q32);
            return self.tilt_block(s, bias);
        }
        Action::None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_two_axes_add_up_in_the_chi_square() {
        // Bound 8 (Q8 2048): each axis 2.5 sd (6.25) passes alone; together 12.5 fail.
        let b = 8 * 256;
        let v = [100u128 * 100; 2];
        assert!(explained_2d(b, [250, 0], v, [0, 0]));
        assert!(explained_2d(b, [0, 250], v, [0, 0]));
        assert!(!explained_2d(b, [250, 250], v, [0, 0]));
        // At the bound exactly: explained; just past it: not.
        assert!(explained_2d(b, [200, 200], v, [0, 0]));
        assert!(!explained_2d(b, [201, 200], v, [0, 0]));
        // The allowance comes off each offset first: 400 - 130 is 2.7 sd (7.3), 400 is 16.
        assert!(explained_2d(b, [400, 0], v, [130, 0]));
        assert!(!explained_2d(b, [400, 0], v, [0, 0]));
        assert!(explained_2d(b, [0, -400], v, [0, 130]));
    }

    #[test]
    fn the_velocity_error_is_what_the_disturbance_cannot_swing() {
        assert_eq!(velocity_error([-10, 4], [0; 2]), [-10, 4]);
        assert_eq!(velocity_error([-10, 4], [2, 5]), [-6, 0]);
        assert_eq!(velocity_error([-10, 4], [u64::MAX, 1]), [0, 2]);
        assert_eq!(
            velocity_error([i64::MIN, i64::MAX], [0; 2]),
            [-i64::MAX, i64::MAX]
        );
    }

    #[test]
    fn a_correction_is_forward_unless_it_points_back_against_the_travel() {
        assert!(forward([3000, -1200], [5000, 1]));
        assert!(!forward([-3000, 0], [5000, 0]));
        assert!(!forward([-300, 300], [1000, -2000]));
        assert!(forward([300, -300], [1000, -2000]));
        // Across the travel, or no travel yet: forward.
        assert!(forward([0, -70], [5000, 0]));
        assert!(forward([-50, -50], [0, 0]));
        // At the extremes the sign is still right (scaled, not overflowed).
        assert!(!forward([i128::MIN, 0], [i64::MAX, i64::MIN]));
        assert!(forward([i128::MAX, i128::MAX], [i64::MAX, i64::MAX]));
        assert!(!forward([-1, 0], [1, 0]));
        assert!(forward([1, i128::MIN >> 70], [i64::MAX, 0]));
    }

    #[test]
    fn a_resumed_motion_is_corrected_for_its_whole_span_less_what_was_corrected() {
        let mut m = Motion::default();
        m.begin(100, false);
        m.travelled([50, 0], 0);
        // -(-10) x 100 = 1000 along +X: forward, made.
        assert_eq!(m.bridge([-10, 0]), Some([1000, 0]));
        // Resumed: 200 samples, -6 left: 1200 in all, 200 more.
        m.begin(200, true);
        assert_eq!(m.bridge([-6, 0]), Some([200, 0]));
        // Resumed again with +2 left: -400 in all, -1600 more would step back: none made.
        m.begin(200, true);
        assert_eq!(m.bridge([2, 0]), None);
        assert_eq!(m.corrected, [1200, 0]);
        // A fresh motion starts from no correction and its own travel.
        m.begin(100, false);
        m.travelled([-50, 0], 0);
        assert_eq!(m.bridge([2, 0]), Some([-200, 0]));
    }

    #[test]
    fn a_velocity_points_back_only_against_its_travel() {
        assert!(points_back([-3, 1], [5, 2]));
        assert!(!points_back([3, -1], [5, 2]));
        // Across the travel (a zero dot) or with no travel yet: not back.
        assert!(!points_back([-2, 5], [5, 2]));
        assert!(!points_back([-100, -100], [0, 0]));
        // Exact at the extremes: the two products nearly cancel, one count decides.
        assert!(points_back([i64::MIN, i64::MAX], [i64::MAX, i64::MAX]));
        assert!(!points_back([i64::MIN + 1, i64::MAX], [i64::MAX, i64::MAX]));
    }

    #[test]
    fn a_velocity_is_nearer_its_mean_than_zero_past_the_midpoint() {
        // Along the mean: past half of it, nearer the mean.
        assert!(nearer_than_zero([60, 0], [100, 0]));
        assert!(!nearer_than_zero([40, 0], [100, 0]));
        // At the midpoint exactly: not nearer (equally near).
        assert!(!nearer_than_zero([50, 0], [100, 0]));
        assert!(nearer_than_zero([51, 0], [100, 0]));
        // Both axes count: (30, 40) against (50, 50): 2 x 3500 > 5000.
        assert!(nearer_than_zero([30, 40], [50, 50]));
        // Across or against the mean: never; no mean: never.
        assert!(!nearer_than_zero([0, 100], [100, 0]));
        assert!(!nearer_than_zero([-100, 0], [100, 0]));
        assert!(!nearer_than_zero([100, 0], [0, 0]));
        // At the extremes the products saturate without changing the side.
        assert!(nearer_than_zero([i64::MAX, i64::MAX], [i64::MAX, i64::MAX]));
        assert!(!nearer_than_zero(
            [i64::MIN, i64::MIN],
            [i64::MAX, i64::MAX]
        ));
    }

    #[test]
    fn a_motions_mean_is_its_travel_over_its_block_ends() {
        let mut m = Motion::default();
        m.begin(100, false);
        assert_eq!(m.mean(), None);
        m.travelled([90, -30], 0);
        m.travelled([30, -10], 0);
        assert_eq!(m.mean(), Some([60, -20]));
        // A resumed motion keeps its travel and its count; a fresh one starts from none.
        m.begin(200, true);
        m.travelled([0, 0], 0);
        assert_eq!(m.mean(), Some([40, -13]));
        m.begin(100, false);
        assert_eq!(m.mean(), None);
    }

    #[test]
    fn what_sampling_leaves_is_the_largest_speed_at_a_block_end_times_alias() {
        // alias 1/4 (Q32): |W| / 2 x 1/4 per axis, the largest block end kept.
        let mut m = Motion::default();
        m.begin(100, false);
        m.travelled([1000, -4000], 1 << 30);
        assert_eq!(m.alias, [125, 500]);
        m.travelled([-3000, 400], 1 << 30);
        assert_eq!(m.alias, [375, 500]);
        // A fresh motion starts from none.
        m.begin(100, false);
        assert_eq!(m.alias, [0, 0]);
    }

    #[test]
    fn the_quotient_is_exact_in_either_width() {
        assert_eq!(quotient(1000, 7), 142);
        let big = (1u128 << 100) + 12_345;
        assert_eq!(quotient(big, 1 << 40), big >> 40);
        assert_eq!(quotient(1 << 70, 3), (1u128 << 70) / 3);
    }
}
