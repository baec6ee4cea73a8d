// The settings page in a real Chromium against `cargo lab ui --twin` and a running twin.
// `node tests/browser.mjs` from web/ (CI: after `cargo build --release -p host-tests`); the
// lab binary is $LAB or ../target/release/lab, the browser $CHROMIUM or /usr/bin/chromium.
// Screenshots go to ../target/ui/. Every check throws on failure; the exit status says.
import { spawn, execFileSync } from "node:child_process";
import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { createServer } from "node:net";
import { tmpdir } from "node:os";
import { join, resolve } from "node:path";
import { chromium } from "playwright-core";

const root = resolve(import.meta.dirname, "..", "..");
const lab = process.env.LAB ?? join(root, "target", "release", "lab");
const shots = join(root, "target", "ui");
mkdirSync(shots, { recursive: true });

function check(ok, what) {
  if (!ok) throw new Error(`check failed: ${what}`);
  console.log(`ok: ${what}`);
}

function freePort() {
  return new Promise((done) => {
    const s = createServer().listen(0, "127.0.0.1", () => {
      const { port } = s.address();
      s.close(() => done(port));
    });
  });
}

/** Starts `lab args` and resolves once its stderr has said `ready`. */
function start(args, ready) {
  const p = spawn(lab, args, { stdio: ["pipe", "pipe", "pipe"] });
  let err = "";
  p.said = () => err;
  return new Promise((done, fail) => {
    p.stderr.on("data", (d) => {
      err += d;
      if (err.includes(ready)) done(p);
    });
    p.on("exit", (c) => fail(new Error(`lab ${args.join(" ")} exited (${c}): ${err}`)));
  });
}

// A recording whose every sample says where it is: sample i has x = i mod 4096,
// y = 7i mod 4096, z = 2048 + (i/8 mod 64). 3 x 4096 samples at the twin's 3000 Hz, so that
// the twin's --repeat joins the end to the start with the same rule.
const N = 3 * 4096;
const pattern = (i) => [i % 4096, (7 * i) % 4096, 2048 + (Math.floor(i / 8) % 64)];
const file = join(tmpdir(), `imu-ui-pattern-${process.pid}.csv`);
writeFileSync(
  file,
  "fs,3000\nn,x,y,z\n" +
    Array.from({ length: N }, (_, i) => `${i},${pattern(i).join(",")}`).join("\n") +
    "\n",
);

const twinPort = await freePort();
const uiPort = await freePort();
const twinAddr = `127.0.0.1:${twinPort}`;
const twin = await start(
  ["twin", "--replay", file, "--repeat", "--addr", twinAddr],
  "waiting for a host",
);
const ui = await start(["ui", "--twin", twinAddr, "--port", String(uiPort)], "settings page is at");
const url = `http://127.0.0.1:${uiPort}/`;

/** Waits until the bridge has let the twin go `n` times (it serves one host at a time). */
async function released(n) {
  for (let t = 0; t < 100; t++) {
    if (ui.said().split("the page disconnected").length - 1 >= n) return;
    await new Promise((ok) => setTimeout(ok, 50));
  }
  throw new Error(`the bridge did not let the twin go: ${ui.said()}`);
}

function configGet() {
  const out = execFileSync(lab, ["device", "--twin", twinAddr, "--json", "config", "get"]);
  return JSON.parse(out);
}

/**
 * A page connected through its own `cargo lab ui` to its own twin (`lab twin ...twinArgs`),
 * a function that stops both, and the twin's address; page errors are kept under `name`.
 */
async function connectedTo(context, twinArgs, name) {
  const addr = `127.0.0.1:${await freePort()}`;
  const port = await freePort();
  const twin = await start(["twin", ...twinArgs, "--addr", addr], "waiting for a host");
  const server = await start(["ui", "--twin", addr, "--port", String(port)], "settings page is at");
  const p = await context.newPage();
  p.on("pageerror", (e) => problems.push(`page (${name}): ${e.message}`));
  await p.goto(`http://127.0.0.1:${port}/`);
  await p.waitForSelector("body[data-ready=true]");
  await p.click("#connect-bridge");
  await p.waitForFunction(() => /^Connected/.test(document.getElementById("status").textContent));
  return [
    p,
    () => {
      server.kill();
      twin.kill();
    },
    addr,
  ];
}

/** `cargo lab device --twin addr --json info`, once the twin is free (a page let it go). */
async function infoOf(addr) {
  for (let t = 0; ; t++) {
    try {
      return JSON.parse(execFileSync(lab, ["device", "--twin", addr, "--json", "info"]));
    } catch (e) {
      if (t >= 50) throw e;
      await new Promise((ok) => setTimeout(ok, 100));
    }
  }
}

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"],
});
const problems = [];
try {
  const context = await browser.newContext({
    acceptDownloads: true,
    viewport: { width: 1400, height: 1600 },
  });
  const page = await context.newPage();
  page.on("console", (m) => m.type() === "error" && problems.push(`console: ${m.text()}`));
  page.on("pageerror", (e) => problems.push(`page: ${e.message}`));
  await page.goto(url);
  await page.waitForSelector("body[data-ready=true]");
  const status = () => page.textContent("#status");
  const waitStatus = (re) =>
    page.waitForFunction(
      (s) => new RegExp(s).test(document.getElementById("status").textContent),
      re.source,
    );

  // Identity and settings appear (the CLI first: the twin serves one host at a time).
  const before = configGet();
  await page.click("#connect-bridge");
  await waitStatus(/^Connected through the lab\.$/);
  check(/^\d+\.\d+\.\d+$/.test(await page.textContent("#firmware")), "the firmware version shows");
  check((await page.textContent("#fs")) === "3000 Hz", "the sampling rate shows");
  const keys = await page.$$eval("#settings tbody tr", (r) => r.length);
  check(keys === Object.keys(before).length, `all ${keys} keys of config get are listed`);
  const takes = await page.$eval("#settings tbody tr td:nth-child(3)", (td) => td.textContent);
  check(/Hz$/.test(takes), `fs_hz says what it takes (${takes})`);

  // A second tab while the first holds the device: told why, and left not connected.
  const second = await context.newPage();
  await second.goto(url);
  await second.waitForSelector("body[data-ready=true]");
  await second.click("#connect-bridge");
  await second.waitForFunction(
    () => /no other host attached/.test(document.getElementById("status").textContent),
    null,
    { timeout: 15000 },
  );
  check(await second.isEnabled("#connect-bridge"), "a second tab is told the device is busy");
  await second.close();

  // A change on the page is read back by the CLI.
  const cpi = before.counts_per_inch === 1200 ? 1000 : 1200;
  await page.fill("#key-counts_per_inch", String(cpi));
  await page.click("#apply");
  await waitStatus(/^Applied 1 setting/);
  await page.screenshot({ path: join(shots, "settings.png"), fullPage: true });
  await page.click("#disconnect");
  await released(1);
  check(configGet().counts_per_inch === cpi, `counts_per_inch=${cpi} set on the page reads back`);

  // A refused value shows the device's refusal on its field, and changes nothing; a value
  // that does not read is caught on the page.
  await page.click("#connect-bridge");
  await waitStatus(/^Connected/);
  await page.fill("#key-counts_per_inch", "0");
  await page.click("#apply");
  await waitStatus(/refused counts_per_inch/);
  const said = await page.textContent("#error-counts_per_inch");
  check(
    said.startsWith("refused by the device: counts_per_inch takes "),
    `the field says: ${said}`,
  );
  await page.fill("#key-counts_per_inch", String(cpi));
  await page.fill("#key-drift", "maybe");
  await page.click("#apply");
  check(
    (await page.textContent("#error-drift")) === "drift must be on or off",
    "a word key reads words",
  );
  await page.screenshot({ path: join(shots, "refused.png"), fullPage: true });
  await page.click("#disconnect");
  await released(2);
  check(configGet().counts_per_inch === cpi, "the refused value changed nothing");

  // A profile exported from the page is what `config get --json` prints; one imported from a
  // file is applied whole and read back by the CLI.
  await page.click("#connect-bridge");
  await waitStatus(/^Connected/);
  const [exported] = await Promise.all([page.waitForEvent("download"), page.click("#export")]);
  const profile = JSON.parse(readFileSync(await exported.path(), "utf8"));
  const changed = join(tmpdir(), `imu-ui-profile-${process.pid}.json`);
  writeFileSync(changed, JSON.stringify({ ...profile, counts_per_inch: 900, drift: false }));
  await page.setInputFiles("#import", changed);
  await waitStatus(/^Applied 2 setting/);
  const notProfile = join(tmpdir(), `imu-ui-array-${process.pid}.json`);
  writeFileSync(notProfile, "[1, 2]");
  await page.setInputFiles("#import", notProfile);
  await waitStatus(/is not a profile: an object of KEY: value was expected$/);
  await page.click("#disconnect");
  await released(3);
  const imported = configGet();
  const expected = { ...imported, counts_per_inch: cpi, drift: true };
  const keysOf = (o) => Object.keys(o).sort().join(",");
  check(
    keysOf(profile) === keysOf(expected) &&
      Object.keys(expected).every((k) => profile[k] === expected[k]),
    "the exported profile is config get's, key for key",
  );
  check(
    imported.counts_per_inch === 900 && imported.drift === false,
    "an imported profile applies",
  );
  execFileSync(lab, [
    "device",
    "--twin",
    twinAddr,
    "config",
    "set",
    `counts_per_inch=${cpi}`,
    "drift=on",
  ]);

  // Live view and recording: the downloaded CSV is the twin's samples, in order, none lost.
  await page.click("#connect-bridge");
  await waitStatus(/^Connected/);
  await page.click("#rec-start");
  await page.waitForTimeout(1500);
  await page.click("#rec-stop");
  await page.click("#live-stop");
  await waitStatus(/^Stream stopped: \d+ frames, 0 lost\.$/);
  await page.screenshot({ path: join(shots, "live.png"), fullPage: true });
  const [download] = await Promise.all([
    page.waitForEvent("download"),
    page.click("#rec-download"),
  ]);
  const csv = readFileSync(await download.path(), "utf8")
    .trim()
    .split("\n");
  check(
    csv[1] === "fs,3000" && csv[3].startsWith("profile,fs_hz=3000,"),
    "the CSV carries fs and the profile",
  );
  const rows = csv.slice(csv.indexOf("n,x,y,z") + 1).map((l) => l.split(",").map(Number));
  check(rows.length > 3000, `${rows.length} samples in 1.5 s at 3000 Hz`);
  let broken = 0;
  rows.forEach(([n, x, y, z], k) => {
    const [px, py, pz] = pattern(x);
    const next = k === 0 || x === (rows[k - 1][1] + 1) % 4096;
    if (n !== k || x !== px || y !== py || z !== pz || !next) broken += 1;
  });
  check(broken === 0, "every recorded sample is the twin's next one");
  writeFileSync(join(shots, "recording.csv"), csv.join("\n") + "\n");
  // The lab reads it with the page's profile line (the pattern is no rest, so `allan`, which
  // needs none, rather than `replay`, whose calibration would refuse it).
  const allan = JSON.parse(execFileSync(lab, ["allan", join(shots, "recording.csv"), "--json"]));
  check(allan.axes.x.adev_m_s2.length > 0, "cargo lab allan reads the page's recording");
  await page.click("#disconnect");
  await released(4);

  // The stream at 10 kHz (10 triples a millisecond, of the 12 a full-speed frame carries):
  // the bridge keeps up, nothing is lost.
  await page.click("#connect-bridge");
  await waitStatus(/^Connected/);
  await page.fill("#key-fs_hz", "10000");
  await page.click("#apply");
  await waitStatus(/^Applied 1 setting/);
  check((await page.textContent("#fs")) === "10000 Hz", "fs_hz=10000 runs");
  await page.click("#rec-start");
  await page.waitForTimeout(1500);
  await page.click("#rec-stop");
  await page.click("#live-stop");
  await waitStatus(/^Stream stopped: \d+ frames, 0 lost\.$/);
  const fast = await page.textContent("#rec-download");
  const m = /^Download the recording \((\d+) samples, 0 frames lost\)$/.exec(fast);
  check(m && Number(m[1]) > 10000, `at 10 kHz: ${fast}`);
  await page.fill("#key-fs_hz", "3000");
  await page.click("#apply");
  await waitStatus(/^Applied 1 setting/);
  await page.click("#disconnect");
  await released(5);

  // A disconnection mid-recording ends the recording and keeps it; the stream is stopped, so
  // the next page finds none running.
  await page.click("#connect-bridge");
  await waitStatus(/^Connected/);
  await page.click("#rec-start");
  await page.waitForTimeout(500);
  await page.click("#disconnect");
  await released(6);
  const kept = await page.textContent("#rec-download");
  check(/samples, 0 frames lost\) \(ended by the disconnection\)$/.test(kept), `kept: ${kept}`);
  const info = JSON.parse(execFileSync(lab, ["device", "--twin", twinAddr, "--json", "info"]));
  check(info.streaming === false, "the stream was stopped");

  // WebHID through a stand-in navigator.hid that forwards reports to the bridge.
  const hid = await context.newPage();
  hid.on("console", (m) => m.type() === "error" && problems.push(`console (hid): ${m.text()}`));
  hid.on("pageerror", (e) => problems.push(`page (hid): ${e.message}`));
  await hid.addInitScript(() => {
    class StandIn extends EventTarget {
      async open() {
        this.ws = new WebSocket(`ws://${location.host}/ws`);
        this.ws.binaryType = "arraybuffer";
        // The device is open once the bridge says so; its text messages are the bridge's,
        // not reports.
        await new Promise((ok, fail) => {
          this.ws.onmessage = (m) => {
            if (typeof m.data === "string") {
              const said = JSON.parse(m.data);
              return said.link_ready ? ok() : fail(new Error(said.link_error));
            }
            const e = new Event("inputreport");
            e.data = new DataView(m.data);
            e.reportId = 0;
            this.dispatchEvent(e);
          };
        });
        this.opened = true;
      }
      async sendReport(id, data) {
        if (id !== 0) throw new Error("the device has no report IDs");
        this.ws.send(data);
      }
      async close() {
        this.ws.close();
      }
    }
    const hid = new EventTarget();
    hid.requestDevice = async ({ filters }) =>
      filters[0].usagePage === 0xff00 ? [new StandIn()] : [];
    Object.defineProperty(navigator, "hid", { value: hid });
  });
  await hid.goto(url);
  await hid.waitForSelector("body[data-ready=true]");
  await hid.click("#connect-hid");
  await hid.waitForFunction(
    () => document.getElementById("status").textContent === "Connected over WebHID.",
  );
  check(
    /^\d+\.\d+\.\d+$/.test(await hid.textContent("#firmware")),
    "WebHID (stand-in): identity shows",
  );
  check(
    (await hid.inputValue("#key-counts_per_inch")) === String(cpi),
    "WebHID (stand-in): the settings show",
  );
  await hid.click("#disconnect");
  await released(7);
  // The tracker on the stream: a second twin playing the desk scene. The page's cursor
  // total over a recording started with the stream equals `cargo lab replay`'s of it (the
  // same core on the same samples), and drift control's states show as they change.
  const [d, stopDesk] = await connectedTo(context, ["--repeat"], "desk");
  try {
    await d.click("#rec-start");
    const seen = new Set();
    for (let i = 0; i < 80; i++) {
      seen.add((await d.textContent("#drift-state")).split(",")[0]);
      await d.waitForTimeout(100);
    }
    // The stream first, then the recording: every frame the page's tracker took is in the
    // recording (stopped the other way round, the tracker goes on with frames it has not).
    await d.click("#live-stop");
    await d.waitForFunction(() =>
      /^Stream stopped: \d+ frames, 0 lost\.$/.test(document.getElementById("status").textContent),
    );
    await d.click("#rec-stop");
    const cursor = (await d.textContent("#cursor")).split(", ").map(Number);
    await d.screenshot({ path: join(shots, "desk.png"), fullPage: true });
    const [dl] = await Promise.all([d.waitForEvent("download"), d.click("#rec-download")]);
    const deskCsv = join(shots, "desk.csv");
    writeFileSync(deskCsv, readFileSync(await dl.path()));
    const replayed = JSON.parse(execFileSync(lab, ["replay", deskCsv, "--json"]));
    check(
      replayed.counts[0] === cursor[0] && replayed.counts[1] === cursor[1],
      `the page's cursor ${cursor} is cargo lab replay's ${replayed.counts} on the same recording`,
    );
    check(
      seen.has("calibrating") && seen.has("still") && seen.has("moving"),
      `drift control's states show (${[...seen].join(", ")})`,
    );
    check(Math.abs(cursor[0]) + Math.abs(cursor[1]) > 100, "the desk's strokes move the cursor");
    await d.click("#disconnect");
  } finally {
    stopDesk();
  }

  // The guided check on a twin playing the check scene (still, a stroke right at 6.5 s and
  // one away at 11.5 s, from the first host on): the lab's verdict, on the page.
  const [c, stopCheck, checkAddr] = await connectedTo(
    context,
    ["--scene", "check", "--repeat"],
    "check",
  );
  try {
    await c.click("#check-start");
    check(
      /^1\/3: keep the mouse still/.test(await c.textContent("#check-step")),
      "the check asks for rest first",
    );
    await c.waitForFunction(
      () => document.getElementById("check-step").textContent === "Done.",
      null,
      {
        timeout: 30000,
      },
    );
    const verdict = await c.textContent("#check-verdict");
    const findings = await c.$$eval("#check-findings li", (l) => l.map((e) => e.textContent));
    check(
      verdict === "The board looks right.",
      `the check's verdict: ${verdict} ${findings.join(" | ")}`,
    );
    check(
      findings.includes("ok: the axis mapping matches the strokes") &&
        findings.some((f) => f.startsWith("ok: gravity on +Z")),
      "the check found gravity and the mapping",
    );
    check(await c.isVisible("#check-plot"), "the check's chart shows");
    await c.screenshot({ path: join(shots, "check.png"), fullPage: true });
    // The device's own cursor, as the page shows it from COUNTERS: the scene's two 10 cm
    // strokes (800 counts per inch: 3150 counts each), right and then away (up), once its
    // tracker is still again; and the twin's count total, read by the CLI once the page has
    // let it go, is the same (the scene rests from 12 s to 21.5 s of its 15 s loop).
    await c.waitForFunction(
      () => document.getElementById("device-state").textContent === "still",
      null,
      { timeout: 10000 },
    );
    await c.waitForTimeout(600);
    const shown = (await c.textContent("#device-cursor")).split(", ").map(Number);
    await c.click("#disconnect");
    const info = await infoOf(checkAddr);
    check(
      info.counts[0] === shown[0] && info.counts[1] === shown[1],
      `the page's device cursor ${shown} is the twin's count total ${info.counts} (cargo lab device info)`,
    );
    check(
      shown[0] > 2800 && shown[0] < 3500 && shown[1] < -2800 && shown[1] > -3500,
      `the device's cursor went 10 cm right and 10 cm up (${shown} counts)`,
    );
    check(info.tracker === "still", `the device says it is still (${info.tracker})`);
  } finally {
    stopCheck();
  }

  check(problems.length === 0, `no console error (${problems.join("; ")})`);
  console.log(`status at the end: ${await status()}`);
} finally {
  if (problems.length) console.log(`problems seen: ${problems.join("; ")}`);
  await browser.close();
  ui.kill();
  twin.kill();
}
