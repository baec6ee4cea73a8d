//! Tilt and the zero: a steady one-sided acceleration is gravity through a tilt, not a hand;
//! at rest the zero follows slow drift.
//!
//! # What tells a tilt from a hand (REFERENCE (j))
//! A tilt of `theta` leaks `g sin(theta)` (0.171 m/s^2 per degree) into X or Y: a step that
//! never reverses. A hand's acceleration reverses within its stroke: a stroke of `T` keeps
//! one sign for `T / 2`, so a hand's for at most half its longest stroke
//! ([`super::Drift::stroke_max_s`], `T_max`). A pad tilting slowly and a stroke starting are
//! the same signal until the stroke's acceleration would have reversed: before that no
//! statistic tells them apart, so the damage is bounded, not avoided.
//!
//! # The test, on 20 ms blocks of raw code sums
//! Per horizontal axis and scale, at each block's end, the last `m` blocks (a sub-window of
//! 100 ms or of 400 ms) have an offset `o` from the zero (a sum of `n` samples); it is
//! **significant** when `|o| > K_TILT sd(o) + G A n / D` (`sd^2 = q n (1 + n / N_b)`; `G` the
//! gain of the sub-window's boxcar above `knock_hz`, `A` the measured disturbance,
//! [`super::noise`]). The axis's **run** at a scale is the number of consecutive blocks
//! whose sub-window was significant with one sign. A lobe of one sign lasting `L` blocks can
//! make at most `L + m - 1` sub-windows significant (each must overlap it), so a run `r` says
//! the acceleration kept its sign for at least `r - m + 1` blocks: the tests below use that
//! least length, which no stroke's lobe can make longer than it is. A hand's acceleration
//! passes through zero at the end of each lobe,
//! antisymmetrically about the crossing (as a minimum-jerk stroke's does), so a sub-window
//! centred on that crossing averages to zero and is not significant: the run breaks, at
//! either scale. The short scale sees a large acceleration's sign change within 100 ms; the
//! long one sees a small steady leak (a slight tilt, or what a slow tilt adds after the zero
//! was taken) that a 100 ms window cannot tell from noise.
//!
//! - **Hold**: an axis one-sided for at least `T_max / 8` (0.25 s) at either scale: the motion is still integrated but
//!   not delivered; the cursor stops. This bounds a tilt's runaway: what it integrated
//!   before the hold, `g sin(theta) (t_detect + T_max / 8)^2 / 2` for a sudden tilt. A stroke
//!   longer than `T_max / 4` is held during part of each lobe (its cursor pauses, then
//!   catches up).
//! - **Release**: held, and no axis one-sided for `T_max / 8` at either scale (the
//!   acceleration reversed or went quiet, as a hand's does): what was held is delivered.
//!   Unless the level before the change (the three short sub-windows before the last) was
//!   significant on X or Y: then the change may be a stroke's second lobe (the hold was a
//!   slow stroke's first) or a new motion after a tilt to that level (the hold was a pad
//!   tilting, then the hand moved). No statistic tells them apart as they happen (REFERENCE
//!   (j)); their ends do: at rest the acceleration returns to the old zero after a stroke,
//!   to the tilt's level after a tilt. So the motion stays held, and its **shadow**, the
//!   second hypothesis, is integrated beside it from the last sub-window on, from zero
//!   velocity against that level ([`super::Action::Shadow`]). Whichever stop test passes
//!   first (quiet and velocity explained, each against its own zero) wins: the motion is
//!   delivered as it is, or the shadow replaces it ([`super::Action::Adopt`]: the tilt's
//!   runaway dropped, the level the new zero). A shadow adopted delivers what it
//!   integrated only if its velocity stood out of its uncertainty at some tick's end (it
//!   carried a motion); one that never did integrated the noise about its level, and only
//!   its zeros are taken (seeds 6 and 13 of the lab's pad tilts: a confirmed tilt's shadow,
//!   turned by a 3 sd noise sub-window, delivered 0.13 and 0.41 mm 0.62 and 0.65 s after
//!   the pad rested). The shadow may win only once one axis's
//!   short sub-windows (of its replay or later) have gone both ways against the level, as a
//!   hand's stroke from rest does (two lobes). A release can come at a slow stroke's crest:
//!   one 100 ms sub-window of a lobe peaking at 5.8 sd falls short of `K_TILT` by noise,
//!   the level before it is the crest's, and there the shadow is quiet and its velocity
//!   small while the acceleration rounds the crest; a shadow that could win one-sided won
//!   within 50 ms and took the stroke's first half for a tilt (a 45.5 mm stroke over 1.68 s
//!   at 741 ug/sqrt(Hz): 38 mm short in 2 of 40 noise draws). A pad that goes on settling
//!   after the level was taken only adds to its tilt: its shadow never goes both ways, and
//!   the tilt is confirmed as any (below). If the tilt is confirmed (one-sided for long
//!   enough against the motion's zero) while the shadow has not yet gone both ways, but
//!   went against the tilt by more than `K_TURN` sd on an axis, a hand moved the settled
//!   pad: the tilt is certain, the shadow's level is the pad's (taken before the hand
//!   moved) and the shadow goes on, certain, winning at its end one-sided. Confirmed as any
//!   tilt instead, from the latest steady stretch, that stretch was in the stroke (a slow
//!   lobe's crest is steady over 0.3 s): the rest of the stroke ran against it and was
//!   dropped as a second tilt (a 60.6 mm stroke 0.2 s after a 3.7 degree tilt, its first
//!   lobe against it: 0 mm arrived). `K_TURN = 5` rather than `K_TILT`: a shadow tests up
//!   to 200 sub-windows (X and Y over the longest stroke), and at 3 sd one of them goes
//!   against the tilt by noise in about one pad tilt in a hundred (then the shadow came to
//!   rest and was adopted, and 1-3 mm arrived 0.7-0.9 s after the pad rested); at 5 sd (4.3
//!   sd of the difference, the level's own uncertainty not counted) in fewer than one in
//!   ten thousand. If neither has won within the longest stroke, neither is proven. Still
//!   accelerating against both zeros, the hand is still moving: the shadow ends and the
//!   held motion goes on under the hold's tests (a tilt is still confirmed once one-sided
//!   for long enough, and its held motion dropped). Adopting the shadow there, as when the
//!   acceleration was one-sided at that moment, took a long zigzag's level (a turn's crest,
//!   3 m/s^2) for a tilt and delivered metres at once. Unless, at that timeout, the shadow
//!   is at rest (quiet, its velocity explained) and the held motion is not: no lobe is
//!   still to come, the device rests at the shadow's level, and the held motion glides on a
//!   velocity no acceleration gives it now, against a zero that was off (a tilt's new zero
//!   from a steady stretch that took in a stroke's start, 2 LSB short at 800 ug/sqrt(Hz):
//!   its hold released as the runs at 3.5 sd broke by noise, it glided to the longest calm,
//!   1.2-4.8 m). The level becomes the zero and the held motion is dropped, not adopted: a
//!   shadow that never went both ways carries no hand's stroke from rest (adopted, a new
//!   user's small strokes after a tilt arrived 2-8 times their length), and the held
//!   motion's end velocity mixes the zero's error with the velocity its start missed, which
//!   no end test tells apart (corrected for the zero, 17 of 1500 strokes came out worse,
//!   most that were lost arriving 2-5 times their length). Otherwise, quiet against either
//!   zero, the device is not accelerating on that hypothesis, and the last sub-window's
//!   mean is no hand's: nothing held is delivered, and the zeros become that mean (as at a
//!   change's timeout, below). Left to the hold's tests, the held motion was delivered when
//!   their runs broke by noise, with the velocity its start had missed: a circle held as it
//!   turned slowly (10 mm, 1.5 turns in 4 s at 520 ug/sqrt(Hz)) ended 78 to 359 mm off in 6
//!   of 8 noise draws.
//! - **A release at the zeros**: released, the level before the change not significant:
//!   the acceleration came back to the zeros the motion began on, as a rock's return does
//!   (the device tipped on its base or the pad pressed, and back), or as a slow stroke's
//!   does near its crossing. The velocity the held lobe gave is still in the motion, and only
//!   what comes next tells a stroke (a second lobe takes it back) from a rock (nothing
//!   does). So the hold goes on until the device rests on those zeros (the last three short
//!   sub-windows agree, none significant), and there an undone shadow begins from rest
//!   (below): the held motion is delivered if it comes to rest with its velocity explained,
//!   and dropped past the longest stroke at rest on the zeros; a stroke begun meanwhile is
//!   the shadow's. Released and delivered, a rock whose return was slow glided on its pulse's
//!   velocity (0.1-0.4 m/s) until the longest calm: a 3 degree rock, 0.3 s down and 0.5 s
//!   back, 1.3 m; the lab's rocks, 101 of 4200 over 100 mm, up to 2.0 m. Delivered when
//!   the runs broke before the device rested (a 5 degree rock's, 0.55 s back), one still
//!   glided 1.1 m. The undone shadow begins only at rest: begun at a release mid-stroke (a
//!   stroke begun as a tilt's remainder was held, its reversal the release) it missed the
//!   stroke's first 8 ms, never came to rest, and the stroke was lost (143.8 mm). A motion
//!   younger than four short sub-windows has no level before its change and is delivered:
//!   a rock within about 0.4 s is one lobe as short as a drag's push (never held, or
//!   released that young), and glides as a drag would until the longest calm (the lab's
//!   rocks, 16 of 4200 over 100 mm, up to 556 mm); the sensor cannot tell it from a drag
//!   before the drag's ramp down, which may come 4 s later.
//! - **A change while held**: held, the three short sub-windows before the last steady
//!   and significant (a level), and the last not steady with them. Either the pad settled
//!   and a hand moved it (the stroke would otherwise be dropped with the tilt's runaway
//!   when the tilt is confirmed), or the acceleration of the held stroke itself stood
//!   steady at its crest and now falls. A shadow from that level, replaying the last
//!   sub-window, tells them apart at its end, as at a release, two-sided: a crest's fall
//!   goes one way (a shadow begun at the crest is quiet and its velocity small while the
//!   acceleration rounds the crest, and one-sided it would take the stroke's first half for
//!   a tilt). Where a crest's noise makes both signs the shadow can still win wrongly (seed
//!   2's trial 68 of the 14- and 16-bit sweeps, 73 mm). If the tilt is confirmed before
//!   such a shadow has gone both ways, the change was more of the tilt: the shadow ends and
//!   the confirmation goes on as without it (the latest steady level). If it times out
//!   unconfirmed, its level was not a settled pad's (a slow tilt's ramp reads as steady
//!   over 0.3 s), and the held motion, held since before the change, has not ended either:
//!   neither hypothesis is proven. The shadow is dropped, not adopted (adopted, a stroke
//!   made while the pad still tilted arrived with the rest of the tilt, 2.4 times its
//!   length). If the device is quiet on either zero, nothing held is delivered, as at a
//!   release's timeout: the zeros become the last sub-window's means and the held motion is
//!   dropped. Left to the hold's tests, it was delivered when their runs broke by noise,
//!   with the velocity its start had missed, and glided to the longest calm: a slow circle
//!   held at a turn (36.8 mm, 3.9 turns in 11 s) ended 1.1 to 1.9 m off in 10 of 12 noise
//!   draws, and a new user's two strokes after a tilt more than 1 m off in 3 of 1000. If
//!   the device is still accelerating on both, that mean is a hand's: the held motion goes
//!   on under the hold's tests (a zero from mid-stroke ran a tilt's held zigzag 88 mm off
//!   its legs' 35). A stroke a shadow carries arrives at once when the shadow wins, after
//!   the hand stopped.
//! - **The tilt undone**: while a shadow runs, the last three short sub-windows steady
//!   (as a level's, the disturbance allowed for), significant off the shadow's level on X
//!   or Y but not off the motion's own zeros: the pad was let go, or the hand rocked the
//!   device on its base and back. The held motion carries the rock's runaway and the
//!   velocity its pulse gave, against zeros the device is back at; the shadow, from a
//!   level the device has left, can never come to rest. Either one would wait for the
//!   timeout, and a stroke begun meanwhile was lost (the twentieth tester's rocks: 11 of 16
//!   strokes 1 s after). An **undone shadow** replaces it: from rest, against the motion's
//!   zeros, waiting from the replaced shadow's start. Sharing the held motion's zeros, its
//!   quiet test is the held motion's; their velocities tell them apart. At rest with its
//!   velocity explained, it begins again from rest at each block's end (a zero-velocity
//!   update: begun once, the noise its velocity integrated at rest ran into strokes 1-2 s
//!   later, 6-15 mm). The held motion at rest with its velocity explained was a hand's after
//!   all (a drag whose steady push was held as a tilt, its glide at the zeros, now ended):
//!   it stops and is delivered. The undone shadow at rest, its velocity explained, having
//!   gone both ways since it last began again (a stroke from rest, ended) wins: its motion
//!   is delivered, the rock's dropped. Nothing under way past the longest stroke (the
//!   device resting on the zeros: three short sub-windows agree and none is significant,
//!   whatever the undone shadow's velocity holds, as presses since leave it): the held
//!   motion is dropped, the zeros kept, and a motion soon after is wary as after any tilt
//!   (if the held motion was a drag gliding longer than that, its ramp down is unreversed
//!   and dropped, not run back: the drag is lost, as before, since no statistic tells its
//!   glide from a rock's rest until that ramp down). Still moving then, it waits for that
//!   motion's end for the longest stroke more. The tilt's runs start again with it: one-sided
//!   against the zeros for long enough to confirm a tilt, the device was passing through
//!   them (a pad tilting back past the level it had settled at), and the tilt is confirmed
//!   as any. A stroke in the wait arrives at its end, not as it moves. Where a slow stroke's
//!   crossing lies within the noise of the zeros for 0.3 s (20 mm over 1.56 s at 300
//!   ug/sqrt(Hz)) it reads as undone too; its second lobe, one-sided, leaves the undone
//!   shadow unable to win and the held stroke ends as before, but a knock in it went both
//!   ways and the shadow won mid-stroke (one knocky stroke of 4200, 34 mm off); and at the
//!   wait's end such a crossing reads as rest on the zeros, and the stroke is dropped
//!   mid-way (5 after-tilt strokes of 4200).
//! - **The tilt let go**: held, the device steady at rest on the zeros it had before the
//!   tilts taken since (the last three short sub-windows agree and are not significant off
//!   them) and significantly off the present ones: the pad was let go, or the device rocked
//!   back onto its base, after its tilt was confirmed (a slow tilt is confirmed while the
//!   pad still tilts, and what follows, the rest of the tilt, its return and a stroke after
//!   it, is one motion held against the tilted zeros). What was held is the return's
//!   runaway, dropped, and the zeros before the tilt come back: they were averaged for as
//!   long as the device rested, not a short stretch. Held on instead, the return was
//!   confirmed as a second tilt with the stroke in it, or never ended, and the stroke was
//!   lost (the lab's after-tilt, 27 of 4200 on seeds 1-21). The zeros before are kept as
//!   their offset from the present ones, and as the present ones follow the device at
//!   rest the offset takes the step back: followed with them, they came back up to 0.9 LSB
//!   off (a pad still settling while the tilted zeros were tracked), and a stroke 0.9 s after
//!   the return ended 125 mm off. Off the present zeros too: at rest on both (a small
//!   slow stroke's lobe after the zeros were already back), the held stroke was dropped (15
//!   and 22 mm strokes, 18 and 25 mm off). A lift forgets them (the device is set down
//!   elsewhere).
//! - **Tilt**: an axis one-sided for more than `T_max / 2` at a scale: no lobe of a hand's
//!   stroke is that long. Unless a horizontal axis was significant with both signs within
//!   that time (at either scale): a tilt leaks gravity along one fixed horizontal direction,
//!   so neither axis changes sign, while a hand turning does: a circle's acceleration
//!   rotates, one axis keeps its sign for half a turn (longer than `T_max / 2` for a turn
//!   slower than 2 s) while the other sweeps from one sign to the other (confirmed, a
//!   circle was dropped a third of the way round and its zeros became the hand's level).
//!   Confirmed, the held motion is dropped and the zeros become the level of the latest
//!   steady stretch (three short sub-windows in a row that agree on every axis within
//!   `K_TILT` sd, the disturbance allowed for; on every axis, since Z moves by `g (1 - cos
//!   theta)`): if that stretch is the last, Still; if something changed after it (a hand
//!   moved the tilted device), the change goes on as the shadow, which now wins at its end
//!   whatever the motion does. With no steady stretch (the pad still tilting) the zeros
//!   become the last sub-window's means, Still, and the rest of the tilt is a new motion,
//!   held again.
//!
//! At a start the runs are counted back over the motion's replayed blocks, so that a motion
//! found late (a slow tilt) is judged from its onset.
//!
//! A tilt's new zero comes from at most a few hundred milliseconds of it, and a pad may go on
//! settling: what is left of the tilt starts a motion soon after, too small for the tests to
//! hold quickly. So a motion that starts within the longest stroke after a tilt's new zero
//! is held from its start until its acceleration reverses on an axis (a short sub-window
//! significant with the other sign than the first one seen): a hand's does within its
//! stroke, a tilt's remainder never does (it is then confirmed, as any tilt). The
//! reversal must pass `K_TURN`: over the seconds such a motion may glide, the first sign
//! seen and a 3 sd sub-window against it by noise ended the hold in one draw in four (then
//! what was held arrived at once: 0.8 m of a 143 mm/s glide). Such a motion that ends
//! unreversed after the longest stroke, quiet with its velocity explained or at the longest
//! calm a hand has ([`super::estimator`]), is dropped, not delivered: it glided on the
//! velocity of a start found in a stroke's second lobe, or of a tilt's remainder against a
//! zero a little off, that nothing gave it (delivered, 0.15-0.9 m arrived at once). One that
//! ends sooner is delivered: a slow stroke that the stop tests end at its mid-point is two
//! motions of one lobe each (dropped, small slow strokes after a tilt were lost whole).
//! After a landing in doubt the reversal does not release it: it may be a carry in the air,
//! held until it stops ([`super::lift`], "A landing in doubt").
//!
//! `K_TILT = 3`: a sub-window of a tilt falls short with probability 0.13 % (the hold is
//! then released, and taken again a sub-window later).
//!
//! # The zero at rest
//! At rest, the tick [`super::REPLAY`] ticks old (older than any onset a start could still
//! claim) is averaged into the zero with weight `D / min(N_b, bias_tau_s fs)`: a running
//! mean after a new zero, an exponential with time constant `bias_tau_s` later. The same
//! ticks teach the noise ([`super::noise::Learn`]).

use super::noise::within;
use super::ticks::offset_q16;
use super::{Action, Detector, DriftSettings, State, REPLAY};

/// `K_TURN^2` in Q8 [sd^2]: a shadow's sub-window against the tilt by more than `K_TURN = 5`
/// sd is a hand's (see the module docs).
const K2_TURN_Q8: u64 = 25 * 256;

/// The tilt tests' state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tilt {
    /// Per scale and horizontal axis, the sign of the run and its length [blocks].
    run: [[(i8, u32); 2]; 2],
    /// Whether the motion is held.
    held: bool,
    /// While a shadow runs: the tilt's zeros [Q16 counts], the samples the shadow has
    /// integrated, the tick it began, and whether the tilt is certain.
    shadow: Option<([i64; 3], u64, u64, bool)>,
    /// A motion soon after a tilt's new zero: held until it reverses; the first significant
    /// sign seen on each horizontal axis.
    wary: bool,
    first: [i8; 2],
    /// A motion soon after a landing in doubt ([`super::lift`]): it may be a carry in the
    /// air, which a set-down ends; held until it stops, whatever its acceleration does.
    air: bool,
    /// Wary because it may be the end of a glide the start tests missed ([`super::rest`]):
    /// calm and unreversed within the lone lobe's velocity, it is dropped
    /// ([`super::estimator`]).
    lone: bool,
    /// While a shadow runs: the tilt's direction on each horizontal axis (the sign of its
    /// zeros against the motion's).
    shadow_dir: [i8; 2],
    /// While a shadow runs: the signs its short sub-windows took against the level, a bit
    /// per axis and sign (bit `2 a` negative, `2 a + 1` positive); whether it may win only
    /// once one axis has taken both (a shadow begun at a release or at a change while
    /// held); and whether it began at a change while held (its timeout keeps the held
    /// motion). (Two flags rather than the [`Origin`]: stored as an enum, the device path
    /// measured 2.4 instructions a sample triple more.)
    shadow_signs: u8,
    shadow_two_sided: bool,
    shadow_change: bool,
    /// While a shadow runs: whether a short sub-window went against the tilt's direction by
    /// more than `K_TURN` sd (a hand's lobe, not noise).
    shadow_hand: bool,
    /// While a shadow runs: whether its velocity has stood out of its uncertainty at a
    /// tick's end (it carried a motion, not the noise about its level).
    shadow_moved: bool,
    /// Per horizontal axis and sign (negative, positive), the block count (`+ 1`, wrapping;
    /// 0: never) when a sub-window of either scale was last significant with that sign.
    seen: [[u32; 2]; 2],
}

/// Where a shadow began (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Origin {
    /// At a release: the held acceleration changed from a significant level and stopped
    /// being one-sided; it may win only two-sided.
    Release,
    /// While held: a steady significant level, then a change; it may win only two-sided.
    Change,
    /// At a tilt's confirmation: something changed after the latest steady level; certain.
    Confirmed,
    /// The tilt undone: the device steady back at the motion's own zeros, off the shadow's
    /// level (see the module docs).
    Undone,
}

impl Tilt {
    /// Whether the motion is held by the tilt tests.
    pub(crate) const fn held(&self) -> bool {
        self.held
    }

    /// Whether the motion began soon after a tilt's new zero and its acceleration has not
    /// reversed since (see the module docs).
    pub(crate) const fn unreversed(&self) -> bool {
        self.wary
    }

    /// Whether the motion began soon after a landing in doubt ([`super::lift`]).
    pub(crate) const fn in_air(&self) -> bool {
        self.air
    }

    /// Whether the motion began as a lone lobe's mate ([`super::rest`]).
    pub(crate) const fn lone(&self) -> bool {
        self.lone
    }

    /// The lone lobe was noise, or a glide that ended: the motion is no longer wary for it
    /// (its hold ends at the next block, [`super::estimator`]).
    pub(crate) fn end_lone(&mut self) {
        self.wary = false;
        self.lone = false;
    }

    /// Whether the shadow's acceleration has gone against the tilt's direction on X or Y
    /// (a sub-window's sign other than the direction's, either for an axis the tilt left
    /// unmoved): a hand's, see `Detector::shadow_against`.
    fn shadow_turned(&self) -> bool {
        (0..2).any(|a| {
            let seen = (self.shadow_signs >> (2 * a)) & 0b11;
            match self.shadow_dir[a] {
                1 => seen & 0b01 != 0,
                -1 => seen & 0b10 != 0,
                _ => seen != 0,
            }
        })
    }
}

/// `x` [Q16 counts] within `i32` (a zero's offset is far inside it: 2^15 counts of a 16-bit
/// ADC).
fn narrow(x: i64) -> i32 {
    x.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
}

/// The scale at which one-sided runs of `sided` blocks (at the short and the long scale) are
/// long enough to confirm a tilt (the longer first), if any.
fn confirmed(s: &DriftSettings, sided: [u32; 2]) -> Option<usize> {
    (0..2).rev().find(|&scale| sided[scale] > s.tilt_blocks[1])
}

impl Detector {
    /// The sub-window of `scale` ending `back` blocks ago (0: the last complete block) on
    /// `axis`: its sign if it is significantly off `bias` (see the module docs), 0 if not.
    /// `k2_q8`: the threshold's square [sd^2, Q8].
    pub(crate) fn sub_sign(
        &self,
        s: &DriftSettings,
        (scale, axis, back): (usize, usize, u32),
        bias: i64,
        k2_q8: u64,
    ) -> i8 {
        let m = s.sub_blocks[scale];
        let n = u64::from(m) * u64::from(s.block) * u64::from(s.tick);
        let o = offset_q16(
            self.stream.blocks_sum(axis, back + 1, back + m + 1),
            n,
            bias,
        );
        let d = &self.disturbance[axis];
        let allow = d.allow(
            d.gains(s).sub_q16[scale],
            crate::math::div_u64(n, u64::from(s.tick)),
        );
        let var = self.noise[axis].var(n, self.bias_samples);
        if within(o, var, k2_q8, allow) {
            0
        } else {
            o.signum() as i8
        }
    }

    /// The runs at a motion's start: counted back over its replayed blocks (`blocks` whole
    /// blocks since its onset). It is wary soon after a tilt's new zero, or as the mate of a
    /// `lone` lobe ([`super::rest`]).
    pub(crate) fn count_runs(
        &mut self,
        s: &DriftSettings,
        blocks: u64,
        lone: bool,
        bias: [i64; 3],
    ) {
        let soon = self.stream.ticks() < self.tilted_until;
        let wary = lone || soon;
        let air = soon && self.lift.in_doubt();
        self.tilt = Tilt {
            wary,
            held: wary,
            air,
            lone,
            ..Tilt::default()
        };
        for scale in 0..2 {
            let m = u64::from(s.sub_blocks[scale]);
            for (a, &b) in bias.iter().enumerate().take(2) {
                let mut run = (0i8, 0u32);
                let mut back = 0u32;
                while u64::from(back) + m <= blocks
                    && (back as usize) + (m as usize) < super::BLOCKS
                {
                    let sign = self.sub_sign(s, (scale, a, back), b, s.k2_q8);
                    if sign == 0 || (run.1 > 0 && sign != run.0) {
                        break;
                    }
                    run = (sign, run.1 + 1);
                    back += 1;
                }
                self.tilt.run[scale][a] = run;
            }
        }
    }

    /// Per scale, the least time the acceleration has kept its sign on a horizontal axis
    /// [blocks]: `r - m + 1` for a run of `r` sub-windows of `m` blocks.
    fn one_sided_blocks(&self, s: &DriftSettings) -> [u32; 2] {
        core::array::from_fn(|scale| {
            self.tilt.run[scale]
                .iter()
                .map(|&(_, r)| (r + 1).saturating_sub(s.sub_blocks[scale]))
                .max()
                .unwrap_or(0)
        })
    }

    /// At a block's end while a shadow runs: the runs go on counting (the end the shadow
    /// waits for is judged on them), and a run long enough to confirm a tilt makes the shadow
    /// certain, so that at its timeout the tilt's zero wins, not the held motion.
    pub(crate) fn shadow_block(&mut self, s: &DriftSettings, bias: [i64; 3]) {
        self.count_block(s, bias);
        // What a pad does after the level was taken is more of its tilt: against the level
        // its acceleration keeps the tilt's direction. A hand's stroke has lobes of both
        // signs, so one goes against it.
        if let Some((level, ..)) = self.tilt.shadow {
            self.shadow_against(s, level, 0);
        }
        if self.confirmed_scale(s).is_some() {
            if let Some(shadow) = &mut self.tilt.shadow {
                shadow.3 = true;
            }
        }
    }

    /// The scale at which the one-sided run is long enough to confirm a tilt (the longer
    /// first), if any, and no horizontal axis has turned within that time.
    fn confirmed_scale(&self, s: &DriftSettings) -> Option<usize> {
        self.confirmable(s, self.one_sided_blocks(s))
    }

    /// [`Self::confirmed_scale`] for one-sided runs of `sided` blocks already counted.
    fn confirmable(&self, s: &DriftSettings, sided: [u32; 2]) -> Option<usize> {
        confirmed(s, sided).filter(|_| !self.turned(s))
    }

    /// Whether a horizontal axis's sub-windows (of either scale) were significant with both
    /// signs within the time that confirms a tilt: a tilt leaks gravity along one fixed
    /// horizontal direction, so neither axis's acceleration changes sign; a hand's turning
    /// (a circle's, whose acceleration rotates: one axis is one-sided for half a turn while
    /// the other sweeps from one sign to the other) does.
    fn turned(&self, s: &DriftSettings) -> bool {
        let now = self.stream.blocks() as u32;
        let recent = |seen: u32| seen != 0 && now.wrapping_sub(seen - 1) <= s.tilt_blocks[1];
        self.tilt
            .seen
            .iter()
            .any(|&[neg, pos]| recent(neg) && recent(pos))
    }

    /// Records the sign the short sub-window ending `back` blocks ago took on X and Y when
    /// significant off `level`: against the tilt's direction, the shadow is a hand's
    /// ([`Tilt::shadow_turned`]); by more than `K_TURN` sd, a hand's for certain
    /// (`Tilt::shadow_hand`).
    fn shadow_against(&mut self, s: &DriftSettings, level: [i64; 3], back: u32) {
        for (a, &l) in level.iter().enumerate().take(2) {
            let sign = self.sub_sign(s, (0, a, back), l, s.k2_q8);
            if sign != 0 {
                self.tilt.shadow_signs |= 1 << (2 * a + usize::from(sign > 0));
                let against = self.tilt.shadow_dir[a] != sign;
                if against && !self.tilt.shadow_hand {
                    self.tilt.shadow_hand = self.sub_sign(s, (0, a, back), l, K2_TURN_Q8) == sign;
                }
            }
        }
    }

    /// Each scale's run on X and Y, extended or restarted by the block just closed.
    fn count_block(&mut self, s: &DriftSettings, bias: [i64; 3]) {
        for scale in 0..2 {
            for (a, &b) in bias.iter().enumerate().take(2) {
                let sign = self.sub_sign(s, (scale, a, 0), b, s.k2_q8);
                if sign != 0 {
                    // The block count's low 32 bits: 2.7 years of blocks before they wrap.
                    self.tilt.seen[a][usize::from(sign > 0)] =
                        (self.stream.blocks() as u32).wrapping_add(1);
                }
                if scale == 0 && sign != 0 {
                    let first = self.tilt.first[a];
                    if first == 0 {
                        self.tilt.first[a] = sign;
                    } else if sign == -first && self.tilt.wary {
                        // It reversed by more than noise (`K_TURN`): a hand's.
                        self.tilt.wary = self.sub_sign(s, (0, a, 0), b, K2_TURN_Q8) != sign;
                    }
                }
                let run = &mut self.tilt.run[scale][a];
                *run = match sign {
                    0 => (0, 0),
                    _ if sign == run.0 => (sign, run.1 + 1),
                    _ => (sign, 1),
                };
            }
        }
    }

    /// The tilt tests at a block's end while moving (the runs counted already when a shadow
    /// runs: [`Self::shadow_block`]).
    pub(crate) fn tilt_block(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        if self.tilt.shadow.is_none() {
            self.count_block(s, bias);
        }
        if let Some(action) = self.tilt_let_go(s, bias) {
            return action;
        }
        let hold = s.tilt_blocks[0];
        let sided = self.one_sided_blocks(s);
        if let (Some(scale), None) = (self.confirmable(s, sided), self.tilt.shadow) {
            return self.confirm(s, bias, scale);
        }
        let held = self.tilt.wary || self.tilt.air || sided.iter().any(|&b| b >= hold);
        if self.tilt.shadow.is_some() {
            return Action::None; // held until an end decides
        }
        if self.tilt.held && !held {
            match self.level_before_change(s, bias) {
                Some((level, true)) => {
                    return self.begin_shadow(s, level, bias, 1, Origin::Release)
                }
                // Back at the zeros the motion began on: a rock's return or a slow stroke's
                // crossing. Held on until the device rests there, then an undone shadow (see
                // the module docs).
                Some((_, false)) => {
                    if self.at_rest_on(s, bias) {
                        return self.begin_shadow(s, bias, bias, 0, Origin::Undone);
                    }
                    return Action::None;
                }
                None => {}
            }
        }
        // Held, steady at a significant level, and changed in the last sub-window: a hand
        // on a tilted pad, or the crest of the same stroke; a shadow from the level tells
        // them apart at its end (a two-sided one: see the module docs).
        // (The stretch before the last sub-window first: a held stroke's rarely is steady.)
        if self.tilt.held && held {
            if let Some(level) = self.steady_stretch(s, bias, 2) {
                if self.steady_stretch(s, bias, 1).is_none() {
                    return self.begin_shadow(s, level, bias, 1, Origin::Change);
                }
            }
        }
        self.tilt.held = held;
        Action::None
    }

    /// A tilt confirmed at `scale`: the held motion is dropped, the zeros become the level of
    /// the latest steady stretch (a shadow from it if something changed after it), or, still
    /// tilting, the longest one-sided sub-window's means.
    fn confirm(&mut self, s: &DriftSettings, bias: [i64; 3], scale: usize) -> Action {
        let m = s.sub_blocks[0];
        let n = u64::from(m) * u64::from(s.block) * u64::from(s.tick);
        match self.steady_level(s, bias) {
            // Steady at the end: the zeros, and rest.
            Some((1, level)) => {
                self.enter_still();
                self.tilted(s);
                self.untilted_from(bias, level);
                self.bias_samples = 3 * n;
                return Action::Rebias {
                    bias: level,
                    discard: true,
                };
            }
            // Something changed after the steady stretch: it goes on as the shadow.
            Some((j, level)) => return self.begin_shadow(s, level, bias, j - 1, Origin::Confirmed),
            None => {}
        }
        // Still tilting: the zeros become the longest one-sided sub-window's means.
        self.rezero_on_last(s, bias, scale)
    }

    /// The held motion dropped, the zeros the last sub-window's means at `scale`; Still.
    fn rezero_on_last(&mut self, s: &DriftSettings, bias: [i64; 3], scale: usize) -> Action {
        let m = s.sub_blocks[scale];
        let n = u64::from(m) * u64::from(s.block) * u64::from(s.tick);
        let level: [i64; 3] = core::array::from_fn(|a| {
            let o = offset_q16(self.stream.blocks_sum(a, 1, m + 1), n, bias[a]);
            bias[a] + crate::math::div_round(o, n as i64)
        });
        self.enter_still();
        self.tilted(s);
        self.untilted_from(bias, level);
        self.bias_samples = n;
        Action::Rebias {
            bias: level,
            discard: true,
        }
    }

    /// A shadow against the zeros `level` (the motion's: `bias`) from `subs` short
    /// sub-windows back, begun at `origin`.
    fn begin_shadow(
        &mut self,
        s: &DriftSettings,
        level: [i64; 3],
        bias: [i64; 3],
        subs: u32,
        origin: Origin,
    ) -> Action {
        let certain = origin == Origin::Confirmed;
        let m = u64::from(s.sub_blocks[0] * subs);
        let blocks = m.min(self.stream.blocks().saturating_sub(1));
        let samples = blocks * u64::from(s.block) * u64::from(s.tick)
            + u64::from(self.stream.samples_in_block());
        self.tilt.shadow = Some((level, samples, self.stream.ticks(), certain));
        self.tilt.shadow_dir = core::array::from_fn(|a| (level[a] - bias[a]).signum() as i8);
        self.tilt.shadow_signs = 0;
        self.tilt.shadow_hand = false;
        self.tilt.shadow_moved = false;
        self.tilt.shadow_two_sided = origin != Origin::Confirmed;
        self.tilt.shadow_change = origin == Origin::Change;
        // The shadow's replayed stretch is judged as its later blocks will be: its short
        // sub-windows, back to back, against the level.
        let short = u64::from(s.sub_blocks[0]);
        for back in (0..blocks.saturating_sub(short - 1)).step_by(short as usize) {
            self.shadow_against(s, level, back as u32);
        }
        self.tilt.held = true;
        Action::Shadow {
            bias: level,
            blocks: blocks as usize,
        }
    }

    /// The latest steady stretch among the last few short sub-windows: the first `j` (1 =
    /// the last sub-window) whose [`Self::steady_stretch`] is, with its level (Q16 counts).
    fn steady_level(&self, s: &DriftSettings, bias: [i64; 3]) -> Option<(u32, [i64; 3])> {
        let deepest = ((super::BLOCKS as u32 - 1) / s.sub_blocks[0])
            .saturating_sub(2)
            .min(6);
        (1..=deepest).find_map(|j| self.steady_stretch(s, bias, j).map(|level| (j, level)))
    }

    /// The level (Q16 counts) of short sub-windows `j, j + 1, j + 2` back (`j >= 1`, 1 = the
    /// last), if they lie within the motion, agree on every axis and are significant on X or
    /// Y.
    fn steady_stretch(&self, s: &DriftSettings, bias: [i64; 3], j: u32) -> Option<[i64; 3]> {
        self.stretch(s, bias, j)
            .and_then(|(level, significant)| significant.then_some(level))
    }

    /// The level (Q16 counts) of short sub-windows `j, j + 1, j + 2` back (`j >= 1`) and
    /// whether it is significant off `bias` on X or Y, if they lie within the motion and
    /// agree on every axis.
    fn stretch(&self, s: &DriftSettings, bias: [i64; 3], j: u32) -> Option<([i64; 3], bool)> {
        let m = s.sub_blocks[0];
        let n = u64::from(m) * u64::from(s.block) * u64::from(s.tick);
        if self.motion.samples < u64::from(j + 2) * n {
            return None;
        }
        let mut level = bias;
        let mut significant = false;
        for (a, b) in bias.iter().enumerate() {
            let o: [i64; 3] = core::array::from_fn(|i| {
                let back = m * (j - 1 + i as u32);
                offset_q16(self.stream.blocks_sum(a, back + 1, back + m + 1), n, *b)
            });
            let d = &self.disturbance[a];
            let allow = 2 * d.allow(
                d.gains(s).sub_q16[0],
                crate::math::div_u64(n, u64::from(s.tick)),
            );
            let var = self.noise[a].var(2 * n, u64::MAX);
            if !(within(o[0] - o[1], var, s.k2_q8, allow)
                && within(o[1] - o[2], var, s.k2_q8, allow))
            {
                return None;
            }
            let sum: i64 = o.iter().sum();
            if a < 2 {
                let var = self.noise[a].var(3 * n, self.bias_samples);
                significant |= !within(sum, var, s.k2_q8, 3 * allow / 2);
            }
            level[a] = *b + crate::math::div_round(sum, 3 * n as i64);
        }
        Some((level, significant))
    }

    /// The zeros go from `bias` to `level` for a tilt: the zeros from before it are kept
    /// (as their offset from `level`), or, after more of the same tilt, still those from
    /// before the first.
    fn untilted_from(&mut self, bias: [i64; 3], level: [i64; 3]) {
        for (a, u) in self.untilt.iter_mut().enumerate() {
            *u = narrow(i64::from(*u) + bias[a] - level[a]);
        }
    }

    /// The tilt let go: held, the device steady at the zeros from before the tilts taken
    /// since (the last three short sub-windows agree and are not significant off them) and
    /// significantly off the present ones. The pad it tilted was released, or the device
    /// rocked back onto its base: what was held is the return's runaway, dropped, and those
    /// zeros come back (see the module docs).
    fn tilt_let_go(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Option<Action> {
        if !self.tilt.held || self.untilt == [0; 3] {
            return None;
        }
        let before: [i64; 3] = core::array::from_fn(|a| bias[a] + i64::from(self.untilt[a]));
        if !self.undone(s, before, bias) {
            return None;
        }
        self.tilt.shadow = None;
        self.untilt = [0; 3];
        self.enter_still();
        Some(Action::Rebias {
            bias: before,
            discard: true,
        })
    }

    /// A tilt's new zero was just taken: the lift test waits for its window, and a motion
    /// soon after is wary.
    pub(crate) fn tilted(&mut self, s: &DriftSettings) {
        self.lift_wait(s);
        self.tilted_until = self.stream.ticks() + u64::from(s.land_timeout);
    }

    /// One more sample integrated by the shadow.
    #[inline(always)]
    pub(crate) fn shadow_sample(&mut self) {
        if let Some((_, n, _, _)) = &mut self.tilt.shadow {
            *n += 1;
        }
    }

    /// Whether the device is steady back at the zeros `bias` (the last three short
    /// sub-windows agree, and are significant off `level` on X or Y but not off `bias`): a
    /// tilt from `bias` to `level` was undone (a shadow's, from the motion's zeros to the
    /// shadow's level; or the tilts taken since the zeros before them, [`Self::tilt_let_go`]).
    fn undone(&self, s: &DriftSettings, bias: [i64; 3], level: [i64; 3]) -> bool {
        self.steady_stretch(s, level, 1).is_some() && self.at_rest_on(s, bias)
    }

    /// Whether the last three short sub-windows agree and are not significant off `bias` on
    /// X or Y: the device rests on those zeros.
    fn at_rest_on(&self, s: &DriftSettings, bias: [i64; 3]) -> bool {
        self.stretch(s, bias, 1)
            .is_some_and(|(_, significant)| !significant)
    }

    /// At a release: the level of the three short sub-windows before the last (Q16 counts,
    /// every axis), if it is significant on X or Y.
    fn level_before_change(&self, s: &DriftSettings, bias: [i64; 3]) -> Option<([i64; 3], bool)> {
        let m = s.sub_blocks[0];
        let n = u64::from(m) * u64::from(s.block) * u64::from(s.tick);
        if 4 * m as usize >= super::BLOCKS || self.motion.samples < 4 * n {
            return None;
        }
        let mut level = bias;
        let mut significant = false;
        for (a, b) in bias.iter().enumerate() {
            let sum = offset_q16(self.stream.blocks_sum(a, m + 1, 4 * m + 1), 3 * n, *b);
            if a < 2 {
                let d = &self.disturbance[a];
                let allow = d.allow(
                    d.gains(s).sub_q16[0],
                    crate::math::div_u64(3 * n, u64::from(s.tick)),
                );
                let var = self.noise[a].var(3 * n, self.bias_samples);
                significant |= !within(sum, var, s.k2_q8, allow);
            }
            level[a] = *b + crate::math::div_round(sum, 3 * n as i64);
        }
        Some((level, significant))
    }

    /// While a shadow runs: which end has come (`quiet` and `explained` are the motion's own
    /// stop test's halves, the shadow's are tested here on its zeros and velocities `w`);
    /// `None` to go on (the motion's stop, if it alone passes, is the caller's). While both
    /// quiet tests pass the data cannot tell the hypotheses apart: it waits, but not past the
    /// longest stroke. After the longest stroke: see the module docs.
    pub(crate) fn shadow_decision(
        &mut self,
        s: &DriftSettings,
        bias: [i64; 3],
        w: [i64; 3],
        quiet: bool,
        explained: bool,
    ) -> Option<Action> {
        let (level, n, since, certain) = self.tilt.shadow?;
        // The tilt undone: the pad let go, or the device rocked back onto its base. The
        // shadow it replaces waited from its own start; the undone one waits as long. The
        // runs start again: a tilt from here is a new one.
        if self.stream.block_closed() && self.undone(s, bias, level) {
            let undone = self.begin_shadow(s, bias, bias, 0, Origin::Undone);
            if let Some(sh) = &mut self.tilt.shadow {
                sh.2 = since;
            }
            self.tilt.run = Default::default();
            return Some(undone);
        }
        let nb = 3 * u64::from(s.sub_blocks[0]) * u64::from(s.block) * u64::from(s.tick);
        if !self.tilt.shadow_moved {
            self.tilt.shadow_moved = !self.velocity_explained(s, w, n, nb);
        }
        // An undone shadow's level is the motion's own zeros (any other's is significantly
        // off them).
        if level == bias {
            let age = self.stream.ticks() - since;
            return self.undone_decision(s, (bias, w, n), age, quiet, explained);
        }
        let shadow_quiet = self.quiet(s, level);
        // Within the longest stroke: a hand at rest after either hypothesis is not yet told
        // from the other (each may still have a lobe to come). Waiting on for as long as both
        // stay quiet held a stroke found in its second lobe for 13.8 s while its wrong start
        // glided, then delivered 575 mm at once.
        let timed_out = self.stream.ticks() - since >= u64::from(s.land_timeout);
        if shadow_quiet && quiet && !certain && !timed_out {
            return Some(Action::None);
        }
        let signs = self.tilt.shadow_signs;
        let both = signs & 0b11 == 0b11 || signs & 0b1100 == 0b1100;
        if self.tilt.shadow_two_sided && !both && self.stream.block_closed() {
            if let Some(scale) = self.confirmed_scale(s) {
                // A shadow that went against the tilt is a hand's on the settled pad: the
                // tilt is certain, and so is the shadow's level (taken before the hand
                // moved; the latest steady one may be the hand's crest).
                if !self.tilt.shadow_hand {
                    self.tilt.shadow = None;
                    return Some(self.confirm(s, bias, scale));
                }
                self.tilt.shadow_two_sided = false;
            }
        }
        let may_win = !self.tilt.shadow_two_sided || both;
        // At its timeout, a shadow at rest beside a held motion that is not: the hand has
        // stopped at the shadow's level, and the held motion glides on a zero that was off.
        // Its level, and the held motion dropped; never adopted one-sided (see the module docs).
        let dropped = !may_win && timed_out && !(quiet && explained);
        if (may_win || dropped) && shadow_quiet && self.velocity_explained(s, w, n, nb) {
            let turned = !dropped && self.tilt.shadow_turned() && self.tilt.shadow_moved;
            self.enter_still();
            self.tilted(s);
            self.untilted_from(bias, level);
            self.bias_samples = nb;
            // A shadow that never went against the tilt was the rest of the tilt (the pad
            // settling onto the level), and one whose velocity never stood out carried the
            // noise about its level: its zeros, and nothing delivered.
            return Some(if turned {
                Action::Adopt
            } else {
                Action::Rebias {
                    bias: level,
                    discard: true,
                }
            });
        }
        if quiet && explained && !certain {
            return None;
        }
        if !timed_out {
            return Some(Action::None);
        }
        self.tilt.shadow = None;
        // A shadow that never came to rest beside a held motion that has not ended either:
        // neither hypothesis is proven. A tilt for certain: the pad went on tilting. At rest
        // on either zero (quiet against the held motion's or the shadow's level), the
        // device is not accelerating on one of them, so the last sub-window's mean is no
        // hand's. Either way nothing held is delivered: the zeros become that mean; Still.
        if certain || quiet || shadow_quiet {
            return Some(self.rezero_on_last(s, bias, 0));
        }
        // Still accelerating on both (that mean would be a hand's). A change's shadow: its
        // level was not a settled pad's (a tilt still under way); the held motion goes on
        // as it was.
        if self.tilt.shadow_change {
            return None;
        }
        // A release's shadow: the hand went on moving, and the shadow's level may be a
        // hand's crest; the held motion goes on, and the hold's tests judge it from here (a
        // tilt is still confirmed when one-sided for long enough, and then nothing of it is
        // delivered).
        self.tilt.held = false;
        None
    }

    /// An undone shadow's decision (see the module docs): its zeros `bias` (the motion's),
    /// its velocities `w` over `n` samples, `age` ticks since the shadow it replaced began.
    /// It and the held motion share their zeros, so their quiet tests are one (`quiet`), and
    /// only their velocities tell them apart (the held motion's: `explained`).
    // Kept out of line: inlined into the tick's decisions, the device path measured 450.1
    // instructions a triple against 449.6 (the measured scene never runs it).
    #[inline(never)]
    fn undone_decision(
        &mut self,
        s: &DriftSettings,
        (bias, w, n): ([i64; 3], [i64; 3], u64),
        age: u64,
        quiet: bool,
        explained: bool,
    ) -> Option<Action> {
        let longest = u64::from(s.land_timeout);
        // One-sided against the zeros for longer than a hand's lobe: the device was passing
        // through them, a tilt still under way (a pad tilting back past the level it had
        // settled at). Confirmed as any tilt (waited on, the return of a 4.9 degree tilt
        // over 1.7 s held everything until twice the longest stroke, and a stroke then
        // begun was found again from rest mid-way, 367 mm off).
        if self.stream.block_closed() {
            if let Some(scale) = self.confirmed_scale(s) {
                self.tilt.shadow = None;
                return Some(self.confirm(s, bias, scale));
            }
        }
        // The held motion at rest on its own: it was a hand's after all (a drag's glide,
        // its ramp held, now ended); the caller's stop delivers it.
        if quiet && explained {
            return None;
        }
        let rests = quiet && self.velocity_explained(s, w, n, self.bias_samples);
        let signs = self.tilt.shadow_signs;
        // A stroke from rest (it went both ways since the shadow last began again at rest),
        // ended: the shadow's motion, the tilt's runaway dropped.
        if rests && (signs & 0b11 == 0b11 || signs & 0b1100 == 0b1100) {
            self.enter_still();
            return Some(Action::Adopt);
        }
        // Nothing under way past the longest stroke: the device rests on the zeros (three
        // short sub-windows agree and none is significant), the shadow at rest too or its
        // velocity what presses or rocks since left it, which no acceleration changes now.
        // The held motion is dropped, the zeros kept. A motion soon after is wary, as after
        // any tilt's zero: if the held motion was a drag's glide (its ramp held), the ramp
        // down to come is unreversed and dropped (not wary, it ran the cursor back 9.1 mm).
        // (Waiting on at rest on the zeros, presses 1-2 s before a stroke held it to twice
        // the longest stroke and lost it, 4 of a tester's 24, or ended mid-way and ran the
        // cursor 0.6 m; judged calm on the quiet test's 20 ms windows instead, a slow
        // stroke's lobe of 0.07 m/s^2 passed for rest and was dropped mid-way, 4 of the lab's
        // 4200 after-tilt.)
        let closed = self.stream.block_closed();
        if age >= longest && closed && self.at_rest_on(s, bias) {
            self.enter_still();
            self.tilted(s);
            return Some(Action::Discard);
        }
        // At rest: the shadow begins again from rest at each block's end (a zero-velocity
        // update), so that what the noise gave its velocity at rest does not run on through a
        // stroke to come (begun once, 3 mm/s from its first 0.3 s carried 6-15 mm into
        // strokes 1-2 s later; begun again only until its velocity first stood out, which the
        // noise does within tens of ticks, 5 mm 2 s later).
        if rests && closed {
            let again = self.begin_shadow(s, bias, bias, 0, Origin::Undone);
            if let Some(sh) = &mut self.tilt.shadow {
                sh.2 -= age;
            }
            return Some(again);
        }
        // Moving, or a motion begun within the longest stroke not yet ended: it ends within
        // the longest stroke more (ended at the wait's end, a stroke under way was found again
        // from rest mid-stroke and glided 129-163 mm). Past that, nothing held is delivered,
        // and a hand still moving (no stroke lasts that long) is found again from rest.
        if age >= 2 * longest {
            self.enter_still();
            return Some(Action::Discard);
        }
        Some(Action::None)
    }

    /// At rest: learn the noise and follow the zero from the tick [`REPLAY`] ticks old, once
    /// the device has been still all the time since; at that first tick, a stop's pending
    /// late bridge is judged first ([`super::estimator`], "The late bridge"). Out of line:
    /// with that test in the tick's decisions at rest the sample path measured 450.5
    /// instructions a triple at 3 kHz, out of line 450.0 (codegen).
    #[inline(never)]
    pub(crate) fn track_zero(&mut self, s: &DriftSettings, bias: [i64; 3]) -> Action {
        if self.state != State::Still || self.age() < REPLAY as u64 {
            return Action::None;
        }
        // The zeros are still the stop's: the judgment uses them. A step made skips this
        // tick's learning and tracking (one tick in the zero's average of thousands).
        if self.latent.pending {
            if let Some(settle) = self.late_bridge(s, bias) {
                return settle;
            }
        }
        let old: [u32; 3] = core::array::from_fn(|a| self.stream.code(REPLAY as u64, a));
        // That tick closed REPLAY - 1 ticks before the last.
        let d = &self.disturbance;
        let shaken = [0, 1, 2].map(|a| d[a].shaken >> (REPLAY - 1) & 1 != 0);
        self.learn.push(s, &mut self.noise, old, bias, shaken);
        let Some(max) = s.bias_samples_max else {
            return Action::None;
        };
        self.bias_samples = (self.bias_samples + u64::from(s.tick)).min(max);
        let w = self.bias_samples as i64; // <= 1e6 s * 1e5 Hz < 2^37
        let mut out = bias;
        // The zeros from before a tilt, if kept, stay where they were.
        let untilted = self.untilt != [0; 3];
        for (a, (b, &c)) in out.iter_mut().zip(&old).enumerate() {
            // A tick's offset: below 2^41 in Q16 LSB samples.
            let d = (i64::from(c) << 16) - i64::from(s.tick) * *b;
            let step = crate::math::div_round(d, w);
            *b += step;
            if untilted {
                self.untilt[a] = narrow(i64::from(self.untilt[a]) - step);
            }
        }
        Action::TrackBias(out)
    }
}
