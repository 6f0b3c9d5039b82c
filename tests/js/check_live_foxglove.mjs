// End-to-end check of polylocd's live view (service/live/, docs/live.md) with Foxglove's own
// client: @foxglove/ws-protocol's FoxgloveClient over the `ws` package subscribes to every
// advertised channel, decodes each message with the schema the server advertised (ros2msg with
// @foxglove/rosmsg + @foxglove/rosmsg2-serialization, JSON with JSON.parse) and checks what it
// got: the map's triangle count, the rig's static transforms, scan and cloud layouts, /tf against
// /pose, the viewers' counters in the health, and, once `polyloc play --truth` wrote the ground
// truth, the poses it received against that truth and its pose rate against the poses polylocd
// counted.
//
//   node check_live_foxglove.mjs ws://127.0.0.1:PORT --until-file TRUTH.tum [--truth FILE]
//        [--triangles 6760] [--max-particles 500] [--settle 3] [--timeout 120] [--stall-check]
//        [--out SUMMARY.json]
//
// Ends when --until-file exists (polyloc play writes the TUM truth atomically when it ends);
// --truth defaults to that file. Prints one line per channel; every problem as `FAIL: ...`,
// exit 1.
import { existsSync, readFileSync, writeFileSync } from "node:fs";
// The package is CommonJS with getter exports, which Node cannot name-import: take the default.
import wsProtocol from "@foxglove/ws-protocol";
import { parse as parseRosmsg } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol;

// ---- arguments ----------------------------------------------------------------------------

function usage(msg) {
  console.error(`FAIL: ${msg}\nusage: node check_live_foxglove.mjs ws://HOST:PORT --until-file FILE [--truth FILE] ` +
                "[--triangles N] [--max-particles N] [--settle S] [--timeout S] [--stall-check] [--out FILE]");
  process.exit(1);
}

function parseArgs(argv) {
  const o = { url: null, untilFile: null, truth: null, triangles: 6760, maxParticles: 500, settle: 3, timeout: 120,
              stallCheck: false, out: null };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i], val = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
    if (a === "--until-file") o.untilFile = val();
    else if (a === "--truth") o.truth = val();
    else if (a === "--triangles") o.triangles = Number(val());
    else if (a === "--max-particles") o.maxParticles = Number(val());
    else if (a === "--settle") o.settle = Number(val());
    else if (a === "--timeout") o.timeout = Number(val());
    else if (a === "--stall-check") o.stallCheck = true;
    else if (a === "--out") o.out = val();
    else if (a.startsWith("--")) usage(`unknown option ${a}`);
    else if (!o.url) o.url = a;
    else usage(`unexpected argument ${a}`);
  }
  if (!o.url) usage("no url");
  if (!o.untilFile) usage("--until-file is required");
  o.truth ??= o.untilFile;
  if (!(Number.isInteger(o.triangles) && o.triangles > 0)) usage("--triangles must be a positive integer");
  if (!(Number.isInteger(o.maxParticles) && o.maxParticles > 0)) usage("--max-particles must be a positive integer");
  if (!(o.settle >= 0)) usage("--settle must be >= 0");
  if (!(o.timeout > 0)) usage("--timeout must be > 0");
  return o;
}
const opt = parseArgs(process.argv.slice(2));

// ---- failures -----------------------------------------------------------------------------

const failures = [];
const failCounts = new Map();  // per key: how many, so a broken stream prints a few lines, not thousands
function fail(key, msg) {
  const n = (failCounts.get(key) ?? 0) + 1;
  failCounts.set(key, n);
  if (n <= 3) failures.push(msg);
  else if (n === 4) failures.push(`${key}: more failures of this kind follow (counted in the summary)`);
}

// ---- helpers ------------------------------------------------------------------------------

const NS = 1e9;
const stampNs = (t) => BigInt(t.sec) * 1000000000n + BigInt(t.nanosec ?? t.nsec ?? 0);
const finite = (...v) => v.every((x) => typeof x === "number" && Number.isFinite(x));
const yawOf = (q) => Math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
const wrap = (a) => Math.atan2(Math.sin(a), Math.cos(a));
const quantile = (sorted, p) => (sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))] : NaN);
const median = (sorted) => quantile(sorted, 0.5);

// Rigid transforms as {t: [x, y, z], q: {x, y, z, w}}.
function qmul(a, b) {
  return { w: a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, x: a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
           y: a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, z: a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w };
}
function qrot(q, v) {
  const p = qmul(qmul(q, { w: 0, x: v[0], y: v[1], z: v[2] }), { w: q.w, x: -q.x, y: -q.y, z: -q.z });
  return [p.x, p.y, p.z];
}
function compose(a, b) {
  const r = qrot(a.q, b.t);
  return { t: [a.t[0] + r[0], a.t[1] + r[1], a.t[2] + r[2]], q: qmul(a.q, b.q) };
}
const qangle = (a, b) => 2 * Math.acos(Math.min(1, Math.abs(a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z)));
const qnorm = (q) => Math.hypot(q.w, q.x, q.y, q.z);
const fromTransform = (tr) => ({ t: [tr.translation.x, tr.translation.y, tr.translation.z], q: tr.rotation });
const fromPose = (p) => ({ t: [p.position.x, p.position.y, p.position.z], q: p.orientation });

// ---- per-channel state --------------------------------------------------------------------

const channels = new Map();  // channel id -> state
const bySub = new Map();     // subscription id -> state
const byTopic = new Map();
let serverInfo = null, advertised = false;
const poses = [];            // {stamp (BigInt ns), x, y, z, yaw, q}
const poseByStamp = new Map();
const healths = [];          // {h, posesReceived: poses received before this health arrived}
let tfChecked = 0, tfMaxPosErr = 0, tfMaxAngErr = 0, tfUnmatched = 0;
const statuses = [];

const RAW_STAMP = Symbol("stamp_ns as written");

function decoderFor(ch) {
  if (ch.encoding === "cdr") {
    if (ch.schemaEncoding !== "ros2msg") throw new Error(`cdr channel with schemaEncoding ${ch.schemaEncoding}, not ros2msg`);
    const defs = parseRosmsg(ch.schema, { ros2: true });
    if (!defs.length || !defs[0].definitions.length) throw new Error("ros2msg schema has no fields");
    const reader = new MessageReader(defs);
    return (bytes) => {
      const m = reader.readMessage(bytes);
      if (reader.lastReadHadTrailingBytes()) throw new Error("trailing bytes after the CDR message");
      return m;
    };
  }
  if (ch.encoding === "json") {
    if (ch.schemaEncoding !== "jsonschema") throw new Error(`json channel with schemaEncoding ${ch.schemaEncoding}`);
    const schema = JSON.parse(ch.schema);
    if (schema.title && schema.title !== ch.schemaName) throw new Error(`JSON schema titled ${schema.title}`);
    const td = new TextDecoder("utf-8", { fatal: true });
    return (bytes) => {
      const text = td.decode(bytes);
      const m = JSON.parse(text);
      // stamp_ns (wall or data time in ns, ~1.8e18) is past 2^53: JSON.parse rounds it, so the
      // digits are taken from the text to compare with the frame's exact u64 timestamp.
      const s = /"stamp_ns":(-?\d+)/.exec(text);
      if (m && typeof m === "object") m[RAW_STAMP] = s ? BigInt(s[1]) : null;
      return m;
    };
  }
  throw new Error(`unknown encoding ${ch.encoding}`);
}

// A LaserScan's layout: the ranges' count follows from the angles, and is the same every message.
function checkScan(st, m, frame) {
  const key = `${st.topic} layout`;
  if (m.header.frame_id !== frame) fail(key, `${st.topic}: frame_id '${m.header.frame_id}', expected '${frame}'`);
  if (!finite(m.angle_min, m.angle_max, m.angle_increment) || !(m.angle_increment > 0))
    return fail(key, `${st.topic}: bad angles min ${m.angle_min} max ${m.angle_max} increment ${m.angle_increment}`);
  if (!(m.range_min >= 0 && m.range_max > m.range_min)) fail(key, `${st.topic}: range_min ${m.range_min}, range_max ${m.range_max}`);
  const n = m.ranges.length;
  const expect = Math.round((m.angle_max - m.angle_min) / m.angle_increment) + 1;
  if (n !== expect)
    fail(key, `${st.topic}: ${n} ranges, but angle_min ${m.angle_min.toFixed(5)} .. angle_max ${m.angle_max.toFixed(5)} ` +
              `by ${m.angle_increment.toFixed(6)} gives ${expect}`);
  if (n === 0) fail(key, `${st.topic}: no ranges`);
  st.sizes.add(n);
  if (st.sizes.size > 1) fail(`${st.topic} size`, `${st.topic}: range counts change between messages: ${[...st.sizes].join(", ")}`);
  let good = 0;
  for (const r of m.ranges) if (Number.isFinite(r)) {
    good++;
    // Simulated noise puts some ranges a few cm past range_max (ROS: such ranges are to be
    // discarded by the reader); anything far outside would be a wrong scale or unit.
    if (r < 0 || r > m.range_max + 0.5) { fail(`${st.topic} values`, `${st.topic}: range ${r} outside [0, ${m.range_max} + 0.5]`); break; }
    if (r > m.range_max) st.pastMax++;
  }
  st.finiteRanges += good;
}

function checkCloud(st, m, names, frame) {
  const key = `${st.topic} layout`;
  if (m.header.frame_id !== frame) fail(key, `${st.topic}: frame_id '${m.header.frame_id}', expected '${frame}'`);
  const got = m.fields.map((f) => `${f.name}@${f.offset}:${f.datatype}x${f.count}`).join(" ");
  const want = names.map((n, i) => `${n}@${4 * i}:7x1`).join(" ");  // 7: FLOAT32
  if (got !== want) return fail(key, `${st.topic}: fields ${got}, expected ${want}`);
  const step = 4 * names.length;
  if (m.point_step !== step || m.height !== 1 || m.row_step !== step * m.width || m.data.length !== m.row_step || m.is_bigendian)
    return fail(key, `${st.topic}: point_step ${m.point_step} height ${m.height} width ${m.width} row_step ${m.row_step} ` +
                     `data ${m.data.length} bytes bigendian ${m.is_bigendian}`);
  const v = new DataView(m.data.buffer, m.data.byteOffset, m.data.byteLength);
  const pts = [];
  for (let i = 0; i < m.width; i++) {
    const p = names.map((_, k) => v.getFloat32(i * step + 4 * k, true));
    if (!p.every(Number.isFinite)) { fail(`${st.topic} values`, `${st.topic}: point ${i} is not finite: ${p}`); break; }
    pts.push(p);
  }
  st.maxPoints = Math.max(st.maxPoints, m.width);
  st.minPoints = Math.min(st.minPoints, m.width);
  return pts;
}

// Data-time rate limit (polylocd.live.rate, 10 Hz): at least 100 ms between two stamps.
function checkRateLimited(st, stamp) {
  if (st.lastStamp !== null && stamp > st.lastStamp && stamp - st.lastStamp < 99_000_000n)
    fail(`${st.topic} rate`, `${st.topic}: two messages ${Number(stamp - st.lastStamp) / 1e6} ms apart (data time), over 10 Hz`);
}

function onMessage(st, stamp, m) {
  const t = st.topic;
  const headerStamp = (h) => {
    if (stampNs(h.stamp) !== stamp) fail(`${t} stamp`, `${t}: header stamp ${stampNs(h.stamp)} != message timestamp ${stamp}`);
  };
  if (t === "/map") {
    const ents = m.entities ?? [];
    if (ents.length !== 1 || ents[0].id !== "map" || ents[0].frame_id !== "map")
      return fail(t, `/map: expected one entity 'map' in frame map, got ${ents.map((e) => `${e.id}@${e.frame_id}`).join(", ")}`);
    let points = 0;
    for (const tl of ents[0].triangles ?? []) {
      if (!Array.isArray(tl.points) || tl.points.length % 3) fail(t, `/map: a triangle list has ${tl.points?.length} points (not a multiple of 3)`);
      for (const p of tl.points ?? []) if (!finite(p.x, p.y, p.z)) { fail(t, `/map: point ${JSON.stringify(p)}`); break; }
      if (!tl.color || !finite(tl.color.r, tl.color.g, tl.color.b, tl.color.a)) fail(t, `/map: triangle list without a colour`);
      points += tl.points?.length ?? 0;
    }
    st.extra = { lists: ents[0].triangles.length, points, triangles: points / 3 };
    if (points !== 3 * opt.triangles) fail(t, `/map: ${points} points = ${points / 3} triangles, expected ${opt.triangles}`);
  } else if (t === "/polyloc/map_slice") {
    const ok = Array.isArray(m.bounds) && m.bounds.length === 4 && m.bounds[2] > m.bounds[0] && m.bounds[3] > m.bounds[1] &&
      Array.isArray(m.segments) && Array.isArray(m.segment_label) && m.segments.length === 4 * m.segment_label.length &&
      m.segment_label.length > 0 && m.segment_label.every((l) => Number.isInteger(l) && l >= 0 && l < m.labels.length);
    if (!ok || m.frame_id !== "map") fail(t, `${t}: bad slice: bounds ${JSON.stringify(m.bounds)}, ${m.segments?.length} coordinates, ` +
                                             `${m.segment_label?.length} labels of ${JSON.stringify(m.labels)}`);
    st.extra = { segments: m.segment_label?.length, labels: m.labels };
  } else if (t === "/tf_static") {
    const tr = m.transforms;
    const bad = tr.filter((x) => x.header.frame_id !== "base_link" || !x.child_frame_id || Math.abs(qnorm(x.transform.rotation) - 1) > 1e-6);
    if (tr.length !== 7 || bad.length) fail(t, `/tf_static: ${tr.length} transforms (expected 7 from base_link), bad: ${JSON.stringify(bad[0] ?? null)}`);
    if (new Set(tr.map((x) => x.child_frame_id)).size !== tr.length) fail(t, "/tf_static: child frames repeat");
    st.extra = { children: tr.map((x) => x.child_frame_id) };
  } else if (t === "/pose") {
    headerStamp(m.header);
    if (m.header.frame_id !== "map") fail(t, `/pose: frame_id ${m.header.frame_id}`);
    const p = m.pose.pose, q = p.orientation;
    if (!finite(p.position.x, p.position.y, p.position.z, q.x, q.y, q.z, q.w) || Math.abs(qnorm(q) - 1) > 1e-6)
      return fail(t, `/pose: not a pose: ${JSON.stringify(p)}`);
    if (m.pose.covariance.length !== 36 || !Array.from(m.pose.covariance).every(Number.isFinite))
      fail(t, `/pose: covariance of ${m.pose.covariance.length} values, or not finite`);
    if (st.lastStamp !== null && stamp <= st.lastStamp) fail(`${t} order`, `/pose: stamp ${stamp} after ${st.lastStamp} (not increasing)`);
    const rec = { stamp, x: p.position.x, y: p.position.y, z: p.position.z, yaw: yawOf(q), pose: fromPose(p) };
    poses.push(rec);
    poseByStamp.set(stamp, rec);
  } else if (t === "/tf") {
    const tr = m.transforms;
    if (tr.length !== 2 || tr[0].header.frame_id !== "map" || tr[0].child_frame_id !== "odom" ||
        tr[1].header.frame_id !== "odom" || tr[1].child_frame_id !== "base_link")
      return fail(t, `/tf: expected map->odom, odom->base_link; got ${tr.map((x) => `${x.header.frame_id}->${x.child_frame_id}`).join(", ")}`);
    for (const x of tr) headerStamp(x.header);
    const p = poseByStamp.get(stamp);
    if (!p) { tfUnmatched++; return; }
    const prod = compose(fromTransform(tr[0].transform), fromTransform(tr[1].transform));
    const dpos = Math.hypot(prod.t[0] - p.pose.t[0], prod.t[1] - p.pose.t[1], prod.t[2] - p.pose.t[2]);
    const dang = qangle(prod.q, p.pose.q);
    tfChecked++;
    tfMaxPosErr = Math.max(tfMaxPosErr, dpos), tfMaxAngErr = Math.max(tfMaxAngErr, dang);
    if (dpos > 1e-3 || dang > (0.1 * Math.PI) / 180)
      fail(`${t} product`, `/tf at ${stamp}: map->odom * odom->base_link is ${dpos.toFixed(4)} m, ` +
                          `${((dang * 180) / Math.PI).toFixed(3)} deg off /pose`);
  } else if (t === "/particles") {
    headerStamp(m.header);
    checkRateLimited(st, stamp);
    const pts = checkCloud(st, m, ["x", "y", "z", "yaw", "weight"], "map");
    if (!pts) return;
    if (m.width === 0 || m.width > opt.maxParticles) fail(`${t} count`, `/particles: ${m.width} points (expected 1 .. ${opt.maxParticles})`);
    if (pts.some((p) => !(p[4] >= 0 && p[4] <= 1))) fail(`${t} values`, "/particles: a weight outside [0, 1]");
    // The cloud is around the pose of the same stamp (published together).
    const p = poseByStamp.get(stamp);
    if (p && pts.length) {
      const d = pts.map((q) => Math.hypot(q[0] - p.x, q[1] - p.y)).sort((a, b) => a - b);
      st.medianToPose = Math.max(st.medianToPose ?? 0, median(d));
    }
  } else if (t === "/vrs" || t.startsWith("/scan/")) {
    headerStamp(m.header);
    checkScan(st, m, t === "/vrs" ? "base_link" : t.slice("/scan/".length));
    if (st.lastStamp !== null && stamp <= st.lastStamp) fail(`${t} order`, `${t}: stamp ${stamp} after ${st.lastStamp}`);
  } else if (t === "/tracks") {
    headerStamp(m.header);
    if (m.header.frame_id !== "map") fail(t, `/tracks: frame_id ${m.header.frame_id}`);
    for (const k of m.tracks) {
      if (!Number.isInteger(k.id) || k.id < 0) fail(`${t} id`, `/tracks: track id ${k.id} is not an unsigned integer`);
      if (!Number.isInteger(k.status)) fail(`${t} status`, `/tracks: status ${k.status}`);
      if (!finite(k.x, k.y, k.vx, k.vy)) fail(`${t} values`, `/tracks: track ${k.id} not finite: ${k.x} ${k.y} ${k.vx} ${k.vy}`);
      if (k.covariance.length !== 4 || !Array.from(k.covariance).every(Number.isFinite)) fail(`${t} values`, `/tracks: covariance ${k.covariance}`);
      st.ids.add(k.id);
    }
    st.maxTracks = Math.max(st.maxTracks, m.tracks.length);
  } else if (t.startsWith("/depth/")) {
    headerStamp(m.header);
    checkRateLimited(st, stamp);
    checkCloud(st, m, ["x", "y", "z"], "base_link");
  } else if (t === "/polyloc/health") {
    if (m[RAW_STAMP] !== stamp) fail(`${t} stamp`, `${t}: stamp_ns ${m[RAW_STAMP]} != message timestamp ${stamp}`);
    const v = m.viewers;
    const keys = ["clients", "connections", "refused", "messages_sent", "messages_dropped", "disconnected_slow", "bad_messages", "http_requests"];
    if (!v || !keys.every((k) => Number.isInteger(v[k]) && v[k] >= 0)) return fail(t, `${t}: no viewers {${keys.join(", ")}}: ${JSON.stringify(v)}`);
    if (v.clients < 1) fail(t, `${t}: viewers.clients ${v.clients} while this client is connected`);
    if (!Number.isInteger(m.poses) || !Array.isArray(m.inputs)) fail(t, `${t}: no poses counter or inputs`);
    healths.push({ h: m, posesReceived: poses.length });
  } else if (t === "/polyloc/topview") {
    if (m[RAW_STAMP] !== stamp) fail(`${t} stamp`, `${t}: stamp_ns ${m[RAW_STAMP]} != message timestamp ${stamp}`);
    checkRateLimited(st, stamp);
    if (m.frame_id !== "map" || m.particles.length % 3 || m.vrs.length % 2 || !Array.isArray(m.tracks) || typeof m.status !== "string")
      fail(t, `${t}: bad top view: ${JSON.stringify(m).slice(0, 200)}`);
    if (m.pose && !finite(m.pose.x, m.pose.y, m.pose.yaw)) fail(t, `${t}: pose ${JSON.stringify(m.pose)}`);
  }
}

// ---- the client ---------------------------------------------------------------------------

const t0 = Date.now();
const elapsed = () => ((Date.now() - t0) / 1000).toFixed(1);
let closed = null, done = false;

const client = new FoxgloveClient({ ws: new WebSocket(opt.url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
client.on("error", (e) => fail("ws error", `websocket error: ${e?.message ?? e}`));
client.on("close", (e) => { if (!done) closed = `${e?.code} ${e?.reason ?? ""}`; });
client.on("serverInfo", (info) => {
  serverInfo = info;
  if (info.name !== "polylocd") fail("serverInfo", `serverInfo.name ${info.name}, expected polylocd`);
});
client.on("status", (s) => statuses.push(s));
client.on("advertise", (list) => {
  advertised = true;
  for (const ch of list) {
    if (channels.has(ch.id)) { fail("advertise", `channel id ${ch.id} advertised twice`); continue; }
    const st = { ...ch, count: 0, bytes: 0, lastStamp: null, firstStamp: null, errors: 0, sizes: new Set(), finiteRanges: 0,
                 maxPoints: 0, minPoints: Infinity, pastMax: 0, ids: new Set(), maxTracks: 0, firstArrival: null, lastArrival: null };
    try {
      st.decode = decoderFor(ch);
    } catch (e) {
      fail(`schema ${ch.topic}`, `${ch.topic}: advertised schema ${ch.schemaName} (${ch.schemaEncoding}) does not parse: ${e.message}`);
      continue;
    }
    if (byTopic.has(ch.topic)) fail("advertise", `topic ${ch.topic} advertised twice`);
    channels.set(ch.id, st);
    byTopic.set(ch.topic, st);
    bySub.set(client.subscribe(ch.id), st);
  }
  console.log(`check_live_foxglove: subscribed to ${bySub.size} channels (${elapsed()} s)`);
});
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const st = bySub.get(subscriptionId);
  if (!st) return fail("subscription", `message for unknown subscription ${subscriptionId}`);
  st.count++, st.bytes += data.byteLength;
  const now = Date.now();
  st.firstArrival ??= now, st.lastArrival = now;
  let m;
  try {
    m = st.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
  } catch (e) {
    st.errors++;
    return fail(`${st.topic} decode`, `${st.topic}: message ${st.count} does not decode with its advertised schema: ${e.message}`);
  }
  try {
    onMessage(st, timestamp, m);
  } catch (e) {
    fail(`${st.topic} check`, `${st.topic}: message ${st.count} has an unexpected shape: ${e.message}`);
  }
  st.firstStamp ??= timestamp;
  st.lastStamp = timestamp;
});

// Wait for the until-file (or the timeout, or the server closing on us).
await new Promise((resolve) => {
  const timer = setInterval(() => {
    if (closed !== null) { fail("closed", `the server closed the connection after ${elapsed()} s (${closed})`); }
    else if (existsSync(opt.untilFile)) { /* play is over */ }
    else if ((Date.now() - t0) / 1000 > opt.timeout) { fail("timeout", `${opt.untilFile} did not appear within ${opt.timeout} s`); }
    else return;
    clearInterval(timer);
    resolve();
  }, 100);
});
// Play has ended; what polylocd published before that is on its way: a moment to drain.
if (closed === null) await new Promise((r) => setTimeout(r, 500));
done = true;
client.close();

// ---- after the run ------------------------------------------------------------------------

if (!serverInfo) fail("serverInfo", "no serverInfo received");
if (!advertised) fail("advertise", "no advertise received");
const last = healths.at(-1)?.h;
const stamps = poses.map((p) => p.stamp);

// Every channel must deliver; tracks may be empty but must come; depth only if the camera delivered.
for (const st of channels.values()) {
  if (st.count > 0) continue;
  if (st.topic.startsWith("/depth/")) {
    const cam = st.topic.split("/")[2];
    const input = last?.inputs?.find((i) => i.name === `depth/${cam}` || i.name === cam);
    if (!input || input.taken === 0) { st.quiet = `no frame of ${cam} taken`; continue; }
    // polylocd sends the filtered clouds only while the VRS is on (no /vrs either then).
    if (!byTopic.get("/vrs")?.count) { st.quiet = `VRS off: ${input.taken} frames of ${cam} taken, no /vrs`; continue; }
    fail(`${st.topic} none`, `${st.topic}: no message, although polylocd took ${input.taken} frames of ${cam} and the VRS is on`);
    continue;
  }
  fail(`${st.topic} none`, `${st.topic}: no message received in ${elapsed()} s`);
}
for (const topic of ["/map", "/polyloc/map_slice", "/tf_static"]) {
  const st = byTopic.get(topic);
  if (!st) fail("advertise", `${topic} not advertised`);
  else if (st.count !== 1) fail(`${topic} latched`, `${topic}: latched, expected exactly 1 message per subscription, got ${st.count}`);
}
for (const topic of ["/pose", "/particles", "/tf", "/vrs", "/tracks", "/polyloc/health", "/polyloc/topview"])
  if (!byTopic.has(topic)) fail("advertise", `${topic} not advertised`);
// The static transforms name the rig's sensors, which are the scan and depth topics' frames.
const statics = byTopic.get("/tf_static")?.extra?.children ?? [];
const sensorTopics = [...byTopic.keys()].filter((t) => t.startsWith("/scan/") || t.startsWith("/depth/")).map((t) => t.split("/")[2]);
if (sensorTopics.some((s) => !statics.includes(s)))
  fail("tf_static names", `/tf_static children ${statics.join(",")} do not cover the sensor topics' frames ${sensorTopics.join(",")}`);
const tfSt = byTopic.get("/tf");
if (tfSt && tfSt.count && tfChecked < 0.9 * tfSt.count)
  fail("tf match", `/tf: only ${tfChecked} of ${tfSt.count} messages had a /pose of the same stamp (${tfUnmatched} unmatched)`);
const parts = byTopic.get("/particles");
if (parts && parts.medianToPose > 1.0)
  fail("particles", `/particles: a cloud's median distance to the pose of its stamp is ${parts.medianToPose.toFixed(2)} m`);
const badStatus = statuses.filter((s) => s.level >= 1);
if (badStatus.length) fail("status", `server status messages to a well-behaved client: ${JSON.stringify(badStatus.slice(0, 3))}`);

// The fast client keeps its rate: poses received between its first and last health message vs
// the poses polylocd counted in between (health.poses deltas).
let rate = null;
if (healths.length >= 2) {
  const a = healths[0], b = healths.at(-1);
  const counted = b.h.poses - a.h.poses, received = b.posesReceived - a.posesReceived;
  rate = { counted, received, ratio: counted > 0 ? received / counted : null, healths: healths.length };
  if (counted <= 0) fail("rate", `polylocd counted no poses between the first and last health (${a.h.poses} -> ${b.h.poses})`);
  else if (received < 0.9 * counted)
    fail("rate", `received ${received} poses while polylocd counted ${counted} (${((100 * received) / counted).toFixed(1)} % < 90 %)`);
} else {
  fail("rate", `only ${healths.length} health messages: cannot compare the pose rate`);
}

// Stall check: a stalled client must have been cut off, its messages dropped and counted.
if (opt.stallCheck) {
  const v = last?.viewers;
  if (!v) fail("stall", "--stall-check: no health received");
  else if (!(v.messages_dropped > 0 && v.disconnected_slow >= 1))
    fail("stall", `--stall-check: last health shows messages_dropped ${v.messages_dropped}, disconnected_slow ${v.disconnected_slow} ` +
                  "(expected > 0 and >= 1: the stalled client was not cut off)");
}

// Poses against the truth.
let accuracy = null;
if (existsSync(opt.truth)) {
  const truth = [];
  for (const line of readFileSync(opt.truth, "utf8").split("\n")) {
    const f = line.trim().split(/[\s,]+/);
    if (f.length !== 8 || line.trim().startsWith("#")) continue;
    const [sec, frac = ""] = f[0].split(".");
    const ns = BigInt(sec) * 1000000000n + BigInt((frac + "000000000").slice(0, 9));
    const v = f.slice(1).map(Number);
    truth.push({ stamp: ns, x: v[0], y: v[1], yaw: yawOf({ x: v[3], y: v[4], z: v[5], w: v[6] }) });
  }
  if (truth.length < 2) fail("truth", `${opt.truth}: ${truth.length} poses`);
  else if (!poses.length) fail("truth", "no /pose received to compare with the truth");
  else {
    const settleNs = stamps[0] + BigInt(Math.round(opt.settle * NS));
    const errs = [], yawErrs = [];
    let outside = 0, k = 0;
    for (const p of poses) {
      if (p.stamp < settleNs) continue;
      while (k + 1 < truth.length && truth[k + 1].stamp < p.stamp) k++;
      if (p.stamp < truth[0].stamp || p.stamp > truth.at(-1).stamp || k + 1 >= truth.length) { outside++; continue; }
      const a = truth[k], b = truth[k + 1];
      const u = b.stamp === a.stamp ? 0 : Number(p.stamp - a.stamp) / Number(b.stamp - a.stamp);
      const x = a.x + u * (b.x - a.x), y = a.y + u * (b.y - a.y), yaw = a.yaw + u * wrap(b.yaw - a.yaw);
      errs.push(Math.hypot(p.x - x, p.y - y));
      yawErrs.push(Math.abs(wrap(p.yaw - yaw)));
    }
    errs.sort((a, b) => a - b), yawErrs.sort((a, b) => a - b);
    const within = errs.filter((e) => e <= 0.15).length;
    accuracy = { compared: errs.length, outside_truth: outside, truth_poses: truth.length, within_015: within,
                 fraction_within_015: errs.length ? within / errs.length : 0, median_m: median(errs),
                 p90_m: quantile(errs, 0.9), max_m: errs.at(-1) ?? null, median_yaw_deg: (median(yawErrs) * 180) / Math.PI };
    console.log(`poses vs truth: ${errs.length} compared after ${opt.settle} s (${outside} outside the truth's time span), ` +
                `${(100 * accuracy.fraction_within_015).toFixed(1)} % within 0.15 m, median ${accuracy.median_m?.toFixed(4)} m, ` +
                `p90 ${accuracy.p90_m?.toFixed(4)} m, max ${accuracy.max_m?.toFixed(3)} m, median yaw ${accuracy.median_yaw_deg.toFixed(2)} deg`);
    if (errs.length < 0.9 * (errs.length + outside) || errs.length < 10)
      fail("truth", `only ${errs.length} poses fall inside the truth's time span (${outside} outside): stamps on another clock?`);
    if (accuracy.fraction_within_015 < 0.9) fail("truth", `${(100 * accuracy.fraction_within_015).toFixed(1)} % of poses within 0.15 m of the truth (< 90 %)`);
    if (!(accuracy.median_m <= 0.05)) fail("truth", `median position error ${accuracy.median_m?.toFixed(4)} m (> 0.05 m)`);
  }
} else {
  fail("truth", `no truth file ${opt.truth}`);
}

// ---- report -------------------------------------------------------------------------------

const summary = { url: opt.url, seconds: Number(elapsed()), server: serverInfo?.name, channels: {}, rate, accuracy,
                  tf: { checked: tfChecked, unmatched: tfUnmatched, max_pos_err_m: tfMaxPosErr, max_ang_err_deg: (tfMaxAngErr * 180) / Math.PI },
                  last_health_viewers: last?.viewers ?? null, statuses,
                  poses: poses.map((p) => ({ stamp_ns: String(p.stamp), x: p.x, y: p.y, yaw: p.yaw })),
                  failures: Object.fromEntries(failCounts) };
for (const st of [...channels.values()].sort((a, b) => a.id - b.id)) {
  const span = st.count > 1 ? (st.lastArrival - st.firstArrival) / 1000 : 0;
  const hz = span > 0 ? (st.count - 1) / span : 0;
  const info = [];
  if (st.sizes.size) info.push(`${[...st.sizes].join("/")} ranges${st.pastMax ? ` (${st.pastMax} past range_max)` : ""}`);
  if (st.maxPoints) info.push(`${st.minPoints}..${st.maxPoints} points`);
  if (st.medianToPose !== undefined) info.push(`median distance to the pose at most ${st.medianToPose.toFixed(3)} m`);
  if (st.topic === "/tracks") info.push(`${st.ids.size} track ids, up to ${st.maxTracks} at once`);
  if (st.extra?.triangles) info.push(`${st.extra.triangles} triangles in ${st.extra.lists} lists`);
  if (st.extra?.children) info.push(`${st.extra.children.length} frames`);
  if (st.extra?.segments) info.push(`${st.extra.segments} segments`);
  if (st.quiet) info.push(`quiet: ${st.quiet}`);
  summary.channels[st.topic] = { id: st.id, encoding: st.encoding, schema: st.schemaName, count: st.count, bytes: st.bytes,
                                 hz: Number(hz.toFixed(2)), decode_errors: st.errors, info };
  console.log(`${st.topic.padEnd(26)} ${String(st.count).padStart(5)} msgs ${(st.bytes / 1024).toFixed(0).padStart(6)} KiB ` +
              `${hz.toFixed(1).padStart(5)} Hz  ${st.schemaName}${info.length ? "  " + info.join(", ") : ""}`);
}
if (tfChecked) console.log(`/tf vs /pose: ${tfChecked} compared, max ${(tfMaxPosErr * 1000).toFixed(3)} mm, ${((tfMaxAngErr * 180) / Math.PI).toFixed(4)} deg`);
if (rate) console.log(`pose rate: received ${rate.received} of the ${rate.counted} poses polylocd counted (${(100 * (rate.ratio ?? 0)).toFixed(1)} %)`);
if (last) console.log(`viewers (last health): ${JSON.stringify(last.viewers)}`);
if (opt.out) writeFileSync(opt.out, JSON.stringify(summary, null, 1));
for (const f of failures) console.error(`FAIL: ${f}`);
console.log(failures.length ? `check_live_foxglove: ${failCounts.size} kinds of failure` : "check_live_foxglove: ok");
process.exit(failures.length ? 1 : 0);
