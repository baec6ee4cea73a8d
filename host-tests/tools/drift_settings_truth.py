"""Drift control's derived coefficients, computed independently of the core.

A second derivation, written from the module docs of core/src/drift (REFERENCE (i), (j)),
not from its code paths: the CUSUM alarms solved with mpmath's root finder instead of a
bisection, the lift test's sd multiple from mpmath's normal tail, and the disturbance's
gains by a brute-force scan of every frequency from each bin's edge to Nyquist (1/64 of the
narrowest lobe) instead of the core's one tick period of aliased residues. Prints
core/tests/data/drift_settings.csv: `config,name,index,value`, values in natural units
(the real value before the core rounds it to Q8 or Q16). core/tests/drift_settings.rs holds
the core to it; host-tests/tools/check_generated.py checks that the file is this script's
output. Run: python3 host-tests/tools/drift_settings_truth.py > core/tests/data/drift_settings.csv
"""
import math

import mpmath

mpmath.mp.dps = 40

BINS = 6
RING = 64
BLOCKS = 64
BLOCK_S = 0.02

TUNING = dict(k_sd=3.0, chi2=11.83, kappa=(0.5, 1.5), lobe_sd=5.0, sub_s=(0.1, 0.4),
              hold_fraction=0.125, fade_fraction=0.125, confirm_fraction=0.5, quiet_s=0.02,
              disturbance_s=0.16, disturbance_sigmas=3.0, lift_window=0.605,
              q_inflation_sd=2.0)
DEFAULT = dict(false_start_hours=1e4, hold_s=0.016, knock_hz=20.0, stroke_max_s=2.0,
               glide_max_s=4.0, lift_rise_s=0.5, mount_tilt_deg=5.0, bias_tau_s=10.0,
               click_freeze_s=0.15)
# Every limit changed at once, at rates with one sample per tick, a ragged tick and the
# extremes: core/tests/drift_settings.rs builds the same configurations.
VARIANT = dict(false_start_hours=100.0, hold_s=0.01, knock_hz=35.0, stroke_max_s=1.2,
               glide_max_s=2.5, lift_rise_s=0.3, mount_tilt_deg=2.0, bias_tau_s=3.0,
               click_freeze_s=0.1)
CONFIGS = [("default", DEFAULT, fs) for fs in (100, 1001, 3000, 20000)] + [
    ("variant", VARIANT, fs) for fs in (500, 3000)]


def rnd(x):
    """Round half up (the core's round_to_u64)."""
    return math.floor(x + 0.5)


def boxcar(n, x):
    s = math.sin(math.pi * x)
    if abs(s) < 1e-12:
        return 1.0
    return abs(math.sin(math.pi * n * x) / (n * s))


def cusum_b(kappa, arl):
    """b with (e^(2 kappa b) - 1 - 2 kappa b) / (2 kappa^2) = arl (Siegmund)."""
    k = mpmath.mpf(kappa)
    f = lambda b: (mpmath.expm1(2 * k * b) - 2 * k * b) / (2 * k * k) - arl
    guess = mpmath.log(2 * k * k * arl) / (2 * k)
    return float(mpmath.findroot(f, guess))


def pair_b(kappa, lobe, arl):
    """b with Siegmund's run length over (1 + 2 kappa (b - lobe)) = arl: two consecutive
    runs of opposite sides, the first at least lobe, summing past b."""
    k = mpmath.mpf(kappa)
    f = lambda b: (mpmath.expm1(2 * k * b) - 2 * k * b) / (2 * k * k) / (
        1 + 2 * k * (b - lobe)) - arl
    return float(mpmath.findroot(f, cusum_b(kappa, arl) + 3))


def z_upper(p):
    """z with P(Z > z) = p."""
    return float(mpmath.findroot(lambda z: mpmath.erfc(z / mpmath.sqrt(2)) / 2 - p, 5))


def derive(d, fs):
    t = TUNING
    out = []

    def put(name, value, i=0):
        out.append((name, i, value))

    tick = min(max(-(-fs * 5 // 1000), 1), 1 << 14)
    tick_s = tick / fs
    f_t = 1 / tick_s
    l1 = max(rnd(1 / (d["knock_hz"] * tick_s)), 1)
    l2 = max(rnd(2 / (3 * d["knock_hz"] * tick_s)), 1)
    assert l1 + l2 <= RING - 2
    block = max(rnd(BLOCK_S / tick_s), 1)
    block_s = block * tick_s
    sub = [max(rnd(w / block_s), 1) for w in t["sub_s"]]
    hold_blocks = max(rnd(d["stroke_max_s"] * t["hold_fraction"] / block_s), 1)
    confirm = rnd(d["stroke_max_s"] * t["confirm_fraction"] / block_s)
    land = max(hold_blocks, 3)
    quiet = max(rnd(t["quiet_s"] / tick_s), 1)
    put("tick", tick)
    put("early_stride", max(fs // 1000, 1))
    put("block", block)
    put("band", l1, 0)
    put("band", l2, 1)
    put("band_delay", (l1 + l2 - 2) // 2)
    put("sub_blocks", sub[0], 0)
    put("sub_blocks", sub[1], 1)
    put("land_blocks", land)
    put("land_timeout", rnd(d["stroke_max_s"] / tick_s))

    # The disturbance's bins and gains.
    nyq = fs / 2
    hi = max(f_t / 2, d["knock_hz"])
    edge = lambda k: d["knock_hz"] * (hi / d["knock_hz"]) ** (k / BINS)
    for k in range(BINS - 1):
        put("bin_ratio", 4 * math.sin(math.pi * edge(k + 1) / f_t) ** 2, k)
    windows = [quiet, sub[0] * block, sub[1] * block, (land // 3) * block]
    # The hand-band filter summed over any run of ticks: a sinusoid at x cycles a tick sums
    # to at most 1 / |sin(pi x)| of its amplitude.
    tests = [lambda x: boxcar(l1, x) * boxcar(l2, x) / max(abs(math.sin(math.pi * x)), 1e-12)] + [
        (lambda n: lambda x: boxcar(n, x))(n) for n in windows]
    step = f_t / max(windows + [l1]) / 64
    sample_box = lambda f: boxcar(tick, f / fs)
    top = max(min(nyq, 0.8 * f_t), d["knock_hz"])
    for b in range(BINS):
        lo = min(edge(b), nyq)
        # Closed ranges: the grid and both ends.
        grid = lambda a, z: [a + n * step for n in range(int((z - a) / step) + 1)] + [z]
        best = [0.0] * len(tests)
        for f in grid(lo, nyq):
            s = sample_box(f)
            for i, g in enumerate(tests):
                best[i] = max(best[i], s * g(f / f_t))
        vel = disp = 0.0
        for f in grid(edge(b), max(top, edge(b))):
            s = max(sample_box(f), 1e-3)
            w = fs / (2 * math.pi * f)
            vel = max(vel, w / (tick * s))
            disp = max(disp, w * w / (tick * s))
        for name, v in zip(["gain_band_run", "gain_quiet", "gain_sub_short", "gain_sub_long",
                            "gain_land"], best):
            put(name, v, b)
        put("gain_velocity", vel, b)
        put("gain_displacement", 4 * disp, b)

    put("pre_blocks", max(math.ceil(1 / d["knock_hz"] / block_s), 2))
    fade = max(rnd(d["stroke_max_s"] * t["fade_fraction"] / tick_s), 1)
    put("fade_ticks", fade)
    put("glide_ticks", rnd(d["glide_max_s"] / tick_s))
    # A hand's longest calm: the longest glide and its ramps' calm ends (the longest stroke).
    calm = rnd((d["glide_max_s"] + d["stroke_max_s"]) / tick_s)
    put("calm_max", calm)
    shift = min(max(rnd(math.log2(t["disturbance_s"] / tick_s)), 3), 10)
    margin = lambda k: 1 + t["disturbance_sigmas"] * math.sqrt(2 / 2 ** k)
    put("dist_shift", shift)
    put("dist_margin", margin(shift))
    put("dist_margin_short", margin(shift - 2))
    put("burst_k2", t["disturbance_sigmas"] ** 2)
    # Eight one-sided CUSUMs and the slow ones' four two-lobe sums share the false-start
    # budget.
    arl = d["false_start_hours"] * 3600 / tick_s * 12
    put("alarm", cusum_b(t["kappa"][0], arl), 0)
    put("alarm", max(cusum_b(t["kappa"][1], arl) - 1.166, 0.0), 1)
    put("alarm", pair_b(t["kappa"][0], t["lobe_sd"], arl), 2)
    put("kappa", t["kappa"][0], 0)
    put("kappa", t["kappa"][1], 1)
    put("lobe", t["lobe_sd"])
    # A lone lobe: a run noise passes with probability e^(-2 kappa x) (c <= 1), at most one
    # run in two ticks over the longest glide, P_LONE = 1 % of starts.
    runs = max(mpmath.mpf(d["glide_max_s"]) / tick_s / 2, 1)
    put("lone", float(mpmath.log(runs / mpmath.mpf("0.01")) / (2 * t["kappa"][0])))
    put("k2", t["k_sd"] ** 2)
    put("chi2", t["chi2"])
    put("inflation", t["q_inflation_sd"])
    put("hold", rnd(d["hold_s"] * fs))
    put("quiet_ticks", quiet)
    # The gap between a minimum-jerk stroke's lobes where its acceleration is within kappa of
    # zero, 0.385 T kappa / A, for the longest stroke and a peak A of 1.5 kappa, and the
    # hand-band filter's length.
    put("lobe_slack", rnd(0.385 / 1.5 * d["stroke_max_s"] / tick_s) + l1 + l2)
    # The quiet test's bound over the fade's span: the 2-dof tail exp(-c / 2) of one window,
    # shared by its fade / quiet windows.
    put("fade_chi2", t["chi2"] + 2 * math.log(max(fade / quiet, 1)))
    # The same over the longest calm's span.
    put("calm_chi2", t["chi2"] + 2 * math.log(max(calm / quiet, 1)))
    put("tilt_blocks", hold_blocks, 0)
    put("tilt_blocks", confirm, 1)
    # The lift test: a window of 0.605 of the slowest rise, one false lift per budget.
    window = max(rnd(d["lift_rise_s"] * t["lift_window"] / tick_s), 2)
    assert window < RING
    chances = d["false_start_hours"] * 3600 / (window * tick_s)
    k = z_upper(0.5 / chances)
    n = window * tick
    put("lift_window", window)
    persist = max(math.ceil(0.5 / d["knock_hz"] / tick_s), 1)
    put("lift_persist", persist)
    # A set-down begun as a motion stops is seen by the end of the slowest rise, plus P.
    put("lift_seen", rnd(d["lift_rise_s"] / tick_s) + persist)
    put("lift_k2", k * k)
    put("lift_mount", math.sin(math.radians(d["mount_tilt_deg"])))
    put("lift_cube", n ** 3)
    put("lift_cube_4_3", 4 * n ** 3 // 3)
    # Gravity at rest in LSB, twice, for the configuration's scale (10 g over 12 bits).
    put("lift_two_g", 2 * 4096 / 10)
    put("bias_samples_max", max(rnd(d["bias_tau_s"] * fs), 1))
    # The hand's band output is compared with its values over the filter's span: the block
    # ends at least l1 + l2 - 1 ticks back (one more for the block under way), at most the
    # eight kept.
    put("band_lag", min(-(-(l1 + l2 - 1) // block) + 1, 8))
    # What sampling leaves of a minimum-jerk stroke's velocity per unit of its peak: its two
    # jerk steps (32 v / D^2 each) alias by at most a step / (12 fs^2), for the shortest
    # stroke a hand below knock_hz / 2 makes, D = 2 / knock_hz.
    put("alias", 2 * 32 / 12 / (2 / d["knock_hz"] * fs) ** 2)
    put("freeze", rnd(d["click_freeze_s"] * fs))
    put("arl_ticks", rnd(d["false_start_hours"] * 3600 / tick_s))
    return out


def main():
    print("config,name,index,value")
    for name, d, fs in CONFIGS:
        for field, i, v in derive(d, fs):
            print(f"{name}@{fs},{field},{i},{v!r}")


if __name__ == "__main__":
    main()
