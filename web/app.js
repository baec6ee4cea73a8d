// The imu-mouse settings page. Every frame is encoded and decoded by the core's protocol
// compiled to WebAssembly (imu_protocol.wasm, the `wasm` crate); this file only moves the
// frames (WebHID, or the lab's WebSocket bridge) and shows what they say.

/** The protocol module: the core's encoder and decoder and the device's key table. */
class Protocol {
  static async load() {
    const { instance } = await WebAssembly.instantiateStreaming(fetch("imu_protocol.wasm"));
    return new Protocol(instance.exports);
  }

  constructor(x) {
    this.x = x;
    this.codes = this.json(x.constants());
  }

  bytes(ptr, n) {
    return new Uint8Array(this.x.memory.buffer, ptr, n);
  }

  put(bytes) {
    this.bytes(this.x.in_ptr(), bytes.length).set(bytes);
  }

  putF64(values) {
    this.put(new Uint8Array(new Float64Array(values).buffer));
  }

  json(n) {
    if (n === 0) throw new Error("the protocol module gave no answer");
    return JSON.parse(new TextDecoder().decode(this.bytes(this.x.out_ptr(), n)));
  }

  /** Request `code` (a name of `codes`) with `tag`, as its 64-byte frame. */
  encode(code, tag, arg = 0, pairs = []) {
    this.putF64(pairs.flat());
    const n = this.x.encode_request(this.codes[code], tag, arg, pairs.length);
    if (n === 0) throw new Error(`request ${code} could not be encoded`);
    return this.bytes(this.x.out_ptr(), n).slice();
  }

  decode(frame) {
    this.put(frame);
    return this.json(this.x.decode_frame(frame.length));
  }

  /** The key table of the profile whose values (in the table's order) are `values`. */
  keys(values = []) {
    this.putF64(values.map((v) => (v === null ? NaN : v)));
    return this.json(this.x.key_table(values.length));
  }

  /** Starts the device's tracker on the stream with the profile `values`: whether it runs. */
  trackStart(values) {
    this.putF64(values.map((v) => (v === null ? NaN : v)));
    return this.json(this.x.track_start(values.length)).ok;
  }

  /** Feeds the tracker `codes` ([x, y, z] triples): `{x, y, state, held, samples}`. */
  trackFeed(codes) {
    this.put(new Uint8Array(new Uint16Array(codes.flat()).buffer));
    return this.json(this.x.track_feed(codes.length));
  }

  /** The value `text` gives key `id`: `{value}` or `{error}`. */
  read(id, text) {
    const b = new TextEncoder().encode(text);
    this.put(b);
    return this.json(this.x.read_value(id, b.length));
  }
}

/** The lab's bridge: frames as binary WebSocket messages to `cargo lab ui`. */
class BridgeTransport {
  constructor(url) {
    this.url = url;
    this.onframe = () => {};
    this.onclose = () => {};
  }

  /** Resolves once the lab has opened the device (`link_ready`), rejects with its reason. */
  open() {
    return new Promise((resolve, reject) => {
      const ws = new WebSocket(this.url);
      ws.binaryType = "arraybuffer";
      let ready = false;
      ws.onerror = () => {
        if (!ready) reject(new Error(`no bridge at ${this.url}: is \`cargo lab ui\` running?`));
      };
      ws.onmessage = (m) => {
        if (typeof m.data !== "string") return this.onframe(new Uint8Array(m.data));
        const said = JSON.parse(m.data);
        if (said.link_ready) {
          ready = true;
          resolve();
        } else if (!ready) {
          reject(new Error(said.link_error));
        } else {
          this.onclose(said.link_error);
        }
      };
      ws.onclose = () => {
        if (ready) this.onclose(null);
        else reject(new Error("the lab closed the bridge"));
      };
      this.ws = ws;
    });
  }

  send(frame) {
    this.ws.send(frame);
  }

  close() {
    this.ws.onclose = null;
    this.ws.close();
  }
}

/** WebHID: the device's vendor-defined configuration collection (usage page 0xFF00). */
class HidTransport {
  constructor() {
    this.onframe = () => {};
    this.onclose = () => {};
  }

  async open() {
    const [device] = await navigator.hid.requestDevice({
      filters: [{ usagePage: 0xff00, usage: 0x01 }],
    });
    if (!device) throw new Error("no device chosen");
    if (!device.opened) await device.open();
    device.addEventListener("inputreport", (e) => {
      this.onframe(new Uint8Array(e.data.buffer, e.data.byteOffset, e.data.byteLength));
    });
    this.disconnected = (e) => {
      if (e.device === device) this.onclose("the device was unplugged");
    };
    navigator.hid.addEventListener("disconnect", this.disconnected);
    this.device = device;
  }

  send(frame) {
    // No report IDs: report 0.
    this.device.sendReport(0, frame);
  }

  close() {
    navigator.hid.removeEventListener("disconnect", this.disconnected);
    this.device.close();
  }
}

/** Requests and their answers over a transport, matched by tag; stream frames aside. */
class Session {
  constructor(protocol, transport) {
    this.p = protocol;
    this.t = transport;
    this.tag = 0;
    this.pending = new Map();
    this.onstream = () => {};
    transport.onframe = (f) => this.frame(f);
  }

  frame(bytes) {
    const m = this.p.decode(bytes);
    if (m.stream) return this.onstream(m.stream);
    const waiting = this.pending.get(m.tag);
    if (!waiting) return;
    this.pending.delete(m.tag);
    clearTimeout(waiting.timer);
    waiting.resolve(m);
  }

  /** Sends request `code` and resolves with its answer (an `error` answer included). */
  request(code, arg = 0, pairs = []) {
    this.tag = (this.tag % 255) + 1;
    const tag = this.tag;
    const frame = this.p.encode(code, tag, arg, pairs);
    return new Promise((resolve, reject) => {
      const timer = setTimeout(() => {
        this.pending.delete(tag);
        reject(new Error(`the device did not answer ${code} within 3 s`));
      }, 3000);
      this.pending.set(tag, { resolve, timer });
      this.t.send(frame);
    });
  }

  /** Every key's value, in the key table's order. */
  async config() {
    const values = [];
    let total = 1;
    while (values.length < total) {
      const r = await this.request("GET_CONFIG", values.length);
      if (!r.config) throw new Error(`config: ${JSON.stringify(r)}`);
      total = r.config.total;
      for (const [, v] of r.config.pairs) values.push(v);
      if (r.config.pairs.length === 0) break;
    }
    return values;
  }

  /** Stages `pairs` of [id, value] in frames of PAIRS_MAX and commits: every key or none. */
  async set(pairs) {
    const max = this.p.codes.PAIRS_MAX;
    for (let i = 0; i < pairs.length || i === 0; i += max) {
      const chunk = pairs.slice(i, i + max);
      const last = i + max >= pairs.length;
      const r = await this.request("SET_CONFIG", last ? 1 : 0, chunk);
      if (r.error) return r.error;
    }
    return null;
  }
}

// ---- the page --------------------------------------------------------------------------

const $ = (id) => document.getElementById(id);
const state = {
  protocol: null,
  session: null,
  values: [],
  table: [],
  fs: 0,
  live: { codes: [], lost: 0, frames: 0, seq: null },
  tracking: false,
  track: null,
  path: [],
  recording: null,
  // The device's own tracker state and cursor (COUNTERS, polled), and its path since the
  // stream started.
  device: null,
  devicePath: [],
  deviceFrom: null,
  polling: false,
};

function status(text, error = false) {
  $("status").textContent = text;
  $("status").classList.toggle("error", error);
}

function connected(on) {
  for (const id of [
    "refresh",
    "apply",
    "save",
    "defaults",
    "recalibrate",
    "export",
    "import",
    "live-start",
    "live-stop",
    "rec-start",
    "check-start",
    "disconnect",
  ]) {
    $(id).disabled = !on;
  }
  $("rec-stop").disabled = true;
  $("connect-bridge").disabled = on;
  $("connect-hid").disabled = on || !("hid" in navigator);
}

async function connect(transport, how) {
  status(`Connecting ${how} ...`);
  try {
    await transport.open();
  } catch (e) {
    status(e.message, true);
    return;
  }
  const session = new Session(state.protocol, transport);
  transport.onclose = (why) => {
    if (state.session !== session) return;
    ended();
    status(why ? `Disconnected: ${why}` : "Disconnected.", Boolean(why));
  };
  session.onstream = live;
  state.session = session;
  connected(true);
  try {
    const info = await refresh();
    // A stream an earlier page left running (a reload, a lost connection) is stopped
    // first, so that this page's counts start from its own Start.
    if (info.streaming) {
      await session.request("STREAM_STOP");
      await refresh();
    }
    await loadSettings();
    status(`Connected ${how}.`);
  } catch (e) {
    ended();
    transport.close();
    status(`Could not connect ${how}: ${e.message}`, true);
  }
}

/** What a connection's end ends: a recording (kept for download), a check, the stream. */
function ended() {
  if (state.recording) recordStop(" (ended by the disconnection)");
  if (state.check) {
    state.check.failed("the connection ended");
    state.check = null;
  }
  state.streaming = false;
  state.tracking = false;
  state.session = null;
  connected(false);
}

async function disconnect() {
  const s = state.session;
  if (!s) return;
  // A stream is stopped before the page lets the device go (best effort).
  if (state.streaming) await s.request("STREAM_STOP").catch(() => {});
  ended();
  s.t.close();
  status("Disconnected.");
}

function rows(tbody, list) {
  tbody.replaceChildren(
    ...list.map((cells) => {
      const tr = document.createElement("tr");
      for (const c of cells) {
        const td = document.createElement("td");
        td.textContent = c;
        tr.append(td);
      }
      return tr;
    }),
  );
}

async function refresh() {
  const s = state.session;
  const { info } = await s.request("INFO");
  state.fs = info.fs_hz;
  $("firmware").textContent = info.firmware;
  $("protocol").textContent = info.protocol;
  $("source").textContent =
    info.source === "invalid" ? `invalid (stored key ${info.invalid_key} failed)` : info.source;
  $("fs").textContent = `${info.fs_hz} Hz`;
  $("tracking").textContent =
    (info.tracking ? "tracking" : "calibrating") + (info.streaming ? ", streaming" : "");
  const { counters } = await s.request("COUNTERS");
  rows(
    $("counters").tBodies[0],
    Object.entries(counters).map(([k, v]) => [
      k.replaceAll("_", " "),
      Array.isArray(v) ? v.join(", ") : String(v),
    ]),
  );
  const { calibration } = await s.request("CALIBRATION");
  rows(
    $("calibration").tBodies[0],
    calibration
      ? calibration.map((a, k) => ["XYZ"[k], a.bias_lsb.toFixed(2), a.noise_lsb.toFixed(3)])
      : [["-", "not calibrated yet", ""]],
  );
  return info;
}

async function loadSettings() {
  state.values = await state.session.config();
  state.table = state.protocol.keys(state.values);
  const body = $("settings").tBodies[0];
  body.replaceChildren(
    ...state.table.map((k) => {
      const tr = document.createElement("tr");
      const name = document.createElement("td");
      name.textContent = k.name;
      const cell = document.createElement("td");
      const input = document.createElement("input");
      input.id = `key-${k.name}`;
      input.dataset.key = k.name;
      input.value = k.shown;
      input.setAttribute("aria-label", k.name);
      input.addEventListener("input", () => {
        input.classList.toggle("changed", input.value !== k.shown);
      });
      const error = document.createElement("span");
      error.className = "error";
      error.id = `error-${k.name}`;
      cell.append(input, error);
      const takes = document.createElement("td");
      takes.textContent = k.takes;
      const about = document.createElement("td");
      about.className = "about";
      about.textContent = k.about;
      tr.append(name, cell, takes, about);
      return tr;
    }),
  );
}

function fieldError(name, text) {
  const e = $(`error-${name}`);
  if (e) e.textContent = text;
}

/** The changed fields as [id, value] pairs, or null when one does not read. */
function changes(texts) {
  const pairs = [];
  let ok = true;
  for (const k of state.table) {
    fieldError(k.name, "");
    const text = texts.get(k.name);
    if (text === undefined || text === k.shown) continue;
    const r = state.protocol.read(k.id, text);
    if (r.error) {
      fieldError(k.name, `${k.name} ${r.error}`);
      ok = false;
    } else if (k.kind === "integer" && !Number.isInteger(r.value)) {
      fieldError(k.name, `${k.name} must be a whole number (it takes ${k.takes})`);
      ok = false;
    } else {
      pairs.push([k.id, r.value === null ? NaN : r.value]);
    }
  }
  return ok ? pairs : null;
}

/** Applies `texts` (key name to typed text); the device's refusal is shown on its field. */
async function applyTexts(texts) {
  const pairs = changes(texts);
  if (pairs === null) return status("A value does not read; see its field.", true);
  if (pairs.length === 0) return status("Nothing changed.");
  const rate = state.table.find((k) => k.name === "fs_hz");
  if (state.recording && pairs.some(([id]) => id === rate.id)) {
    recordStop(" (ended: the rate changed)");
  }
  const refused = await state.session.set(pairs);
  if (refused) {
    if (refused.key) {
      // What the key takes with this set's other values (a range may follow fs_hz).
      const tried = state.table.map((k) => {
        const p = pairs.find(([id]) => id === k.id);
        return p ? p[1] : k.value;
      });
      const k = state.protocol.keys(tried).find((e) => e.name === refused.key);
      // "unsupported": within the key's range, but not a value this board can run (a rate
      // its timer does not divide exactly).
      const cannot = refused.code === "unsupported" ? "the board cannot run this value; " : "";
      fieldError(
        refused.key,
        `refused by the device: ${cannot}${k.name} takes ${k.takes}: ${k.about}`,
      );
      status(`The device refused ${refused.key}; nothing was changed.`, true);
    } else {
      status(`The device refused the change (${refused.code}); nothing was changed.`, true);
    }
    return;
  }
  await loadSettings();
  await refresh();
  restartTracker();
  status(`Applied ${pairs.length} setting(s); Save keeps them.`);
}

function apply() {
  const texts = new Map();
  for (const input of $("settings").querySelectorAll("input[data-key]")) {
    texts.set(input.dataset.key, input.value);
  }
  return applyTexts(texts);
}

async function simple(code, done) {
  const r = await state.session.request(code);
  if (r.error) return status(`The device refused ${code.toLowerCase()}: ${r.error.code}`, true);
  await loadSettings();
  await refresh();
  status(done);
}

/** The profile as `cargo lab device config get --json` writes it. */
function profileJson() {
  const out = {};
  for (const k of state.table) {
    if (k.kind === "flag") out[k.name] = k.value === 1;
    else if (k.kind === "word") out[k.name] = k.shown;
    else out[k.name] = k.value;
  }
  return out;
}

function download(name, type, text) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  a.click();
}

function exportProfile() {
  download("imu-mouse-profile.json", "application/json", JSON.stringify(profileJson(), null, 2));
  status("Profile exported.");
}

async function importProfile(file) {
  let obj;
  try {
    obj = JSON.parse(await file.text());
  } catch (e) {
    return status(`${file.name} is not JSON: ${e.message}`, true);
  }
  if (obj === null || typeof obj !== "object" || Array.isArray(obj)) {
    return status(`${file.name} is not a profile: an object of KEY: value was expected`, true);
  }
  const names = new Set(state.table.map((k) => k.name));
  const unknown = Object.keys(obj).filter((n) => !names.has(n));
  if (unknown.length) return status(`${file.name}: unknown key(s) ${unknown.join(", ")}`, true);
  const texts = new Map();
  for (const [name, v] of Object.entries(obj)) {
    // As `config set --file` reads them: a number, null (off), true/false, or a word.
    if (v !== null && !["number", "boolean", "string"].includes(typeof v)) {
      return status(`${file.name}: ${name}: ${JSON.stringify(v)} is not a value a key takes`, true);
    }
    texts.set(name, v === null || v === false ? "off" : v === true ? "on" : String(v));
  }
  await applyTexts(texts);
}

// ---- live view and recording -------------------------------------------------------------

function live(frame) {
  const l = state.live;
  if (l.seq !== null && frame.seq !== ((l.seq + 1) & 0xffff)) l.lost += 1;
  l.seq = frame.seq;
  l.frames += 1;
  l.lost += frame.lost;
  l.codes.push(...frame.codes);
  if (state.tracking && frame.codes.length) {
    const t = state.protocol.trackFeed(frame.codes);
    const last = state.path[state.path.length - 1];
    if (t.x !== last[0] || t.y !== last[1]) state.path.push([t.x, t.y]);
    state.track = t;
  }
  const keep = Math.max(2 * state.fs, 1);
  if (l.codes.length > 2 * keep) l.codes = l.codes.slice(-keep);
  if (state.recording) state.recording.push(...frame.codes);
  if (state.check) checkTake(frame.codes);
}

/**
 * The device's own tracker, four times a second while connected and no other request
 * waits: its state, its cursor since power-up, and (streaming) its path since the stream
 * started, beside the page's tracker's.
 */
async function pollDevice() {
  const s = state.session;
  if (!s || state.polling || s.pending.size) return;
  state.polling = true;
  try {
    const { counters } = await s.request("COUNTERS");
    if (state.session !== s || !counters) return;
    state.device = counters;
    if (state.streaming) {
      state.deviceFrom ??= counters.counts;
      const [x0, y0] = state.deviceFrom;
      state.devicePath.push([counters.counts[0] - x0, counters.counts[1] - y0]);
    }
  } catch {
    // A lost connection says so itself; the next poll tries again.
  } finally {
    state.polling = false;
  }
}

/** The cursor paths since the stream started, x right and y down, at one scale for all. */
function drawPath() {
  const t = state.track;
  $("drift-state").textContent = t ? t.state + (t.held ? ", holding a motion back" : "") : "-";
  $("cursor").textContent = t ? `${t.x}, ${t.y}` : "-";
  const d = state.session ? state.device : null;
  $("device-state").textContent = d ? d.tracker : "-";
  $("device-cursor").textContent = d ? d.counts.join(", ") : "-";
  const canvas = $("path-plot");
  const g = canvas.getContext("2d");
  const w = canvas.width;
  const h = canvas.height;
  g.clearRect(0, 0, w, h);
  const paths = [
    [state.path ?? [], "#1d3557"],
    [state.devicePath ?? [], "#e76f51"],
  ];
  const all = paths.flatMap(([p]) => p);
  if (all.length < 2) return;
  const span = Math.max(50, ...all.map(([x, y]) => Math.max(Math.abs(x), Math.abs(y))));
  const scale = (0.45 * Math.min(w, h)) / span;
  for (const [p, color] of paths) {
    if (p.length < 2) continue;
    g.strokeStyle = color;
    g.beginPath();
    // At most 2000 points drawn: every k-th, and the last.
    const k = Math.ceil(p.length / 2000);
    p.forEach(([x, y], i) => {
      if (i % k && i !== p.length - 1) return;
      const [u, v] = [w / 2 + x * scale, h / 2 + y * scale];
      if (i === 0) g.moveTo(u, v);
      else g.lineTo(u, v);
    });
    g.stroke();
  }
  g.fillStyle = "#5a6470";
  g.fillText(`+-${span} counts`, 8, 14);
}

function draw() {
  drawPath();
  const canvas = $("live-plot");
  const g = canvas.getContext("2d");
  g.clearRect(0, 0, canvas.width, canvas.height);
  const l = state.live;
  const n = Math.min(l.codes.length, 2 * state.fs);
  $("live-info").textContent = state.streaming
    ? `${l.frames} frames, ${l.lost} lost; ${state.recording ? `recording ${state.recording.length} samples` : "not recording"}`
    : "Not streaming.";
  if (n < 2) return;
  const codes = l.codes.slice(-n);
  const lsb = state.table.find((k) => k.name === "m_s2_per_lsb")?.value ?? 1;
  const colors = ["#d62828", "#2a9d8f", "#1d3557"];
  const w = canvas.width;
  const h = canvas.height;
  // One point a pixel column: the mean of its samples (decimated for the eye), in m/s^2
  // from the axis's mean over the window.
  const per = n / w;
  const lines = [0, 1, 2].map((axis) => {
    const mean = codes.reduce((s, c) => s + c[axis], 0) / n;
    const points = [];
    for (let x = 0; x < w; x++) {
      const a = Math.floor(x * per);
      const b = Math.min(n, Math.max(a + 1, Math.floor((x + 1) * per)));
      let sum = 0;
      for (let i = a; i < b; i++) sum += codes[i][axis];
      points.push((sum / (b - a) - mean) * lsb);
    }
    return points;
  });
  // The scale follows the largest excursion, at least 0.2 m/s^2 (a hand's gentlest stroke).
  const top = Math.max(0.2, ...lines.flat().map(Math.abs));
  const scale = (0.45 * h) / top;
  g.strokeStyle = "#e3e6ea";
  g.beginPath();
  g.moveTo(0, h / 2);
  g.lineTo(w, h / 2);
  g.stroke();
  lines.forEach((points, axis) => {
    g.strokeStyle = colors[axis];
    g.beginPath();
    points.forEach((v, x) =>
      x === 0 ? g.moveTo(x, h / 2 - v * scale) : g.lineTo(x, h / 2 - v * scale),
    );
    g.stroke();
    g.fillStyle = colors[axis];
    g.fillText("XYZ"[axis], 8 + 14 * axis, 14);
  });
  g.fillStyle = "#5a6470";
  g.fillText(`+-${top.toPrecision(2)} m/s^2, 2 s`, 60, 14);
}

/** The page's tracker anew, with the running settings, while a stream runs. */
function restartTracker() {
  if (!state.streaming) return;
  state.tracking = state.protocol.trackStart(state.values);
  state.path = [[0, 0]];
  state.track = null;
}

async function stream(on) {
  const r = await state.session.request(on ? "STREAM_START" : "STREAM_STOP");
  if (r.error) return status(`The device refused the stream: ${r.error.code}`, true);
  state.streaming = on;
  if (on) {
    state.live = { codes: [], lost: 0, frames: 0, seq: null };
    state.devicePath = [[0, 0]];
    state.deviceFrom = null;
    // The device's tracker, from this stream's first sample (as `cargo lab replay` of a
    // recording started with it).
    restartTracker();
    // A recording asked for with the stream starts with the tracker: frames that came
    // before the device's answer were recorded but not tracked, and a tracker's decisions
    // depend on where its 5 ms ticks fall.
    if (state.recording) {
      state.recording = [];
      state.recordingLost = 0;
    }
  }
  // The device panel's counters and state as they are now.
  if (!on) await refresh();
  status(on ? "Streaming." : `Stream stopped: ${r.stopped.frames} frames, ${r.stopped.lost} lost.`);
}

function recordStart() {
  state.recording = [];
  state.recordingLost = state.live.lost;
  $("rec-start").disabled = true;
  $("rec-stop").disabled = false;
  if (!state.streaming) stream(true);
}

/** The recording in the lab's format (`formats/recording.rs`): fs, profile, n,x,y,z. */
function recordingCsv(samples) {
  const profile = state.table.map((k) => `${k.name}=${k.shown}`).join(",");
  const lines = [
    "# raw ADC codes, as sampled",
    `fs,${state.fs}`,
    "# the device's settings while it recorded",
    `profile,${profile}`,
    "n,x,y,z",
    ...samples.map(([x, y, z], i) => `${i},${x},${y},${z}`),
  ];
  return lines.join("\n") + "\n";
}

function recordStop(why = "") {
  const samples = state.recording ?? [];
  const lost = state.live.lost - (state.recordingLost ?? 0);
  state.recording = null;
  $("rec-start").disabled = false;
  $("rec-stop").disabled = true;
  const link = $("rec-download");
  link.href = URL.createObjectURL(new Blob([recordingCsv(samples)], { type: "text/csv" }));
  link.download = "imu-mouse-recording.csv";
  link.textContent = `Download the recording (${samples.length} samples, ${lost} frames lost)${why}`;
  link.hidden = false;
}

// ---- the guided check ------------------------------------------------------------------

/** The check's steps, as `cargo lab device check` takes them: [s] still, and each move. */
const CHECK_STEPS = [
  [4, "1/3: keep the mouse still, flat on the desk"],
  [5, "2/3: now slide the mouse straight to the RIGHT, about 10 cm"],
  [5, "3/3: now slide it straight AWAY from you, about 10 cm"],
];

function checkPrompt() {
  const c = state.check;
  const [seconds, say] = CHECK_STEPS[c.step] ?? [0, "judging ..."];
  $("check-step").textContent = seconds ? `${say} (${seconds} s) ...` : say;
}

/** Each streamed sample into the step it belongs to; the last step's end ends the check. */
function checkTake(codes) {
  const c = state.check;
  for (const code of codes) {
    if (c.step >= CHECK_STEPS.length) break;
    c.steps[c.step].push(code);
    if (c.steps[c.step].length >= CHECK_STEPS[c.step][0] * state.fs) {
      c.step += 1;
      checkPrompt();
    }
  }
  if (c.step >= CHECK_STEPS.length) c.done();
}

async function runCheck() {
  const value = (name) => state.table.find((k) => k.name === name).value;
  $("check-verdict").textContent = "";
  $("check-findings").replaceChildren();
  $("check-plot").hidden = true;
  $("check-start").disabled = true;
  const lostBefore = state.streaming ? state.live.lost : 0;
  const finished = new Promise((done, failed) => {
    state.check = { step: 0, steps: [[], [], []], done, failed: (why) => failed(new Error(why)) };
  });
  checkPrompt();
  try {
    if (!state.streaming) await stream(true);
    await finished;
  } catch (e) {
    state.check = null;
    $("check-step").textContent = `The check was interrupted: ${e.message}.`;
    $("check-start").disabled = !state.session;
    return;
  }
  const steps = state.check.steps;
  state.check = null;
  await stream(false);
  $("check-start").disabled = false;
  if (state.live.lost > lostBefore) {
    $("check-step").textContent = "Samples were lost during the check: run it again.";
    return;
  }
  await judgeCheck(steps, value);
}

async function judgeCheck(steps, value) {
  const body = JSON.stringify({
    fs: state.fs,
    m_s2_per_lsb: value("m_s2_per_lsb"),
    adc_bits: value("adc_bits"),
    current: [value("x_axis"), value("x_sign"), value("y_axis"), value("y_sign")],
    steps,
  });
  let answer;
  try {
    const r = await fetch("check", { method: "POST", body });
    if (!r.ok) throw new Error(await r.text());
    answer = await r.json();
  } catch (e) {
    $("check-step").textContent = `The lab could not judge the check: ${e.message}`;
    return;
  }
  const { verdict } = answer.check;
  $("check-step").textContent = "Done.";
  $("check-verdict").textContent = verdict.problems.length
    ? `${verdict.problems.length} problem(s) to fix:`
    : "The board looks right.";
  $("check-findings").replaceChildren(
    ...verdict.problems
      .map((p) => `PROBLEM: ${p}`)
      .concat(verdict.notes.map((n) => `ok: ${n}`))
      .map((t) => {
        const li = document.createElement("li");
        li.textContent = t;
        return li;
      }),
  );
  const plot = $("check-plot");
  plot.src = URL.createObjectURL(new Blob([answer.svg], { type: "image/svg+xml" }));
  plot.hidden = false;
}

function guard(f) {
  return async (...a) => {
    try {
      await f(...a);
    } catch (e) {
      status(e.message, true);
    }
  };
}

async function main() {
  state.protocol = await Protocol.load();
  connected(false);
  const ws = `${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`;
  $("connect-bridge").onclick = () => connect(new BridgeTransport(ws), "through the lab");
  $("connect-hid").onclick = () => connect(new HidTransport(), "over WebHID");
  $("disconnect").onclick = disconnect;
  $("refresh").onclick = guard(refresh);
  $("apply").onclick = guard(apply);
  $("save").onclick = guard(() => simple("SAVE", "Saved: the device starts with these settings."));
  $("defaults").onclick = guard(() => simple("DEFAULTS", "The defaults run, and are kept."));
  $("recalibrate").onclick = guard(() =>
    simple("RECALIBRATE", "Calibrating: keep the mouse still."),
  );
  $("export").onclick = exportProfile;
  $("import").onchange = guard(async (e) => {
    if (e.target.files[0]) await importProfile(e.target.files[0]);
    e.target.value = "";
  });
  $("live-start").onclick = guard(() => stream(true));
  $("live-stop").onclick = guard(() => stream(false));
  $("rec-start").onclick = guard(recordStart);
  $("rec-stop").onclick = () => recordStop();
  $("check-start").onclick = guard(runCheck);
  setInterval(draw, 100);
  setInterval(pollDevice, 250);
  document.body.dataset.ready = "true";
}

main().catch((e) => status(`The page could not start: ${e.message}`, true));
