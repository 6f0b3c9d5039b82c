// Protocol checks of polylocd's live view server (service/live/foxglove_server.cpp) against an
// idle polylocd, with no other viewer connected:
//   HTTP       GET / answers 200 text/html, GET /nope 404;
//   (a) limit  --max-clients N connections are accepted, the next is refused with HTTP 503; once
//              they have closed, a new one is accepted again;
//   (b)        a connection without the foxglove.websocket.v1 subprotocol is refused (400);
//   (c) junk   malformed messages on one connection (not JSON, no op, an unknown op, a binary frame,
//              subscribe with a missing, negative or unknown channel id, a subscription id in use,
//              unsubscribe of an unknown id) are each answered with a status of level 2 and the
//              connection stays usable; the 20th (max_bad_messages) closes it;
//   (d) size   a text message over 64 KiB closes the connection;
//   (e)        afterwards a fresh client still gets serverInfo and advertise, and the health's
//              viewers counters saw it all.
//
//   node check_live_protocol.mjs ws://127.0.0.1:PORT --max-clients N
// Every problem as `FAIL: ...`, exit 1.
import http from "node:http";
import WebSocket from "ws";

const PROTOCOL = "foxglove.websocket.v1";
const MAX_BAD = 20;            // ServerConfig::max_bad_messages
const MAX_MESSAGE = 64 * 1024; // ServerConfig::max_client_message
const STEP_MS = 5000;          // any single answer must come within this

const args = process.argv.slice(2);
let url = null, maxClients = null;
for (let i = 0; i < args.length; i++) {
  if (args[i] === "--max-clients") maxClients = Number(args[++i]);
  else if (!url && !args[i].startsWith("--")) url = args[i];
  else { console.error(`FAIL: unexpected argument ${args[i]}`); process.exit(1); }
}
if (!url || !(Number.isInteger(maxClients) && maxClients >= 1)) {
  console.error("FAIL: usage: node check_live_protocol.mjs ws://HOST:PORT --max-clients N");
  process.exit(1);
}
const httpBase = url.replace(/^ws/, "http").replace(/\/?$/, "/");

class Fail extends Error {}
const fail = (msg) => { throw new Fail(msg); };
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const withTimeout = (p, ms, what) =>
  Promise.race([p, new Promise((_, rej) => setTimeout(() => rej(new Fail(`${what}: nothing within ${ms / 1000} s`)), ms))]);

// A connection that queues what arrives, so each step can wait for "the next text message".
function connect(protocols = [PROTOCOL]) {
  const ws = new WebSocket(url, protocols);
  const c = { ws, texts: [], binaries: 0, waiters: [], closed: null, refused: null, error: null };
  const wake = () => { for (const w of c.waiters.splice(0)) w(); };
  ws.on("message", (data, isBinary) => {
    if (isBinary) c.binaries++;
    else c.texts.push(JSON.parse(data.toString()));
    wake();
  });
  ws.on("unexpected-response", (_req, res) => {
    let body = "";
    res.on("data", (d) => (body += d));
    res.on("end", () => { c.refused = { status: res.statusCode, body: body.trim() }; wake(); });
  });
  ws.on("error", (e) => { c.error = e.message; wake(); });
  ws.on("close", (code, reason) => { c.closed = { code, reason: reason.toString() }; wake(); });
  c.until = (pred, what) => withTimeout(new Promise((resolve) => {
    const check = () => (pred(c) ? resolve() : c.waiters.push(check));
    check();
  }), STEP_MS, what);
  c.nextText = async (what) => {
    await c.until((x) => x.texts.length > 0 || x.closed, what);
    if (!c.texts.length) fail(`${what}: connection closed (${c.closed.code} ${c.closed.reason}) instead`);
    return c.texts.shift();
  };
  return c;
}

// Connected and greeted: serverInfo, then advertise.
async function greeted(c, what) {
  await c.until((x) => x.texts.length >= 2 || x.closed || x.refused || x.error, `${what}: serverInfo + advertise`);
  if (c.refused) fail(`${what}: refused with HTTP ${c.refused.status} (${c.refused.body})`);
  if (c.texts.length < 2) fail(`${what}: no serverInfo + advertise (${c.error ?? JSON.stringify(c.closed)})`);
  const [info, adv] = c.texts.splice(0, 2);
  if (info.op !== "serverInfo" || info.name !== "polylocd") fail(`${what}: first message ${JSON.stringify(info).slice(0, 120)}`);
  if (adv.op !== "advertise" || !Array.isArray(adv.channels) || !adv.channels.length)
    fail(`${what}: second message ${JSON.stringify(adv).slice(0, 120)}`);
  if (c.ws.protocol !== PROTOCOL) fail(`${what}: server selected subprotocol '${c.ws.protocol}'`);
  return adv.channels;
}

async function refusedWith(c, status, what) {
  await c.until((x) => x.refused || x.texts.length || x.closed, what);
  if (!c.refused) fail(`${what}: accepted, expected HTTP ${status}`);
  if (c.refused.status !== status) fail(`${what}: HTTP ${c.refused.status} (${c.refused.body}), expected ${status}`);
  return c.refused;
}

async function closeAll(list) {
  for (const c of list) if (c.ws.readyState === WebSocket.OPEN || c.ws.readyState === WebSocket.CONNECTING) c.ws.close();
  await Promise.all(list.map((c) => c.until((x) => x.closed || x.refused || x.error, "closing")));
}

function httpGet(path) {
  return withTimeout(new Promise((resolve, reject) => {
    // A fresh connection per request: the server closes the connection after answering without
    // saying `Connection: close`, so a kept-alive socket (Node's default agent) would hang up.
    http.get(httpBase + path.replace(/^\//, ""), { agent: false }, (res) => {
      let body = "";
      res.on("data", (d) => (body += d));
      res.on("end", () => resolve({ status: res.statusCode, type: res.headers["content-type"] ?? "", body }));
    }).on("error", reject);
  }), STEP_MS, `GET ${path}`);
}

async function run() {
  // ---- HTTP
  const page = await httpGet("/");
  if (page.status !== 200 || !page.type.startsWith("text/html") || !/<html/i.test(page.body))
    fail(`GET /: ${page.status} ${page.type}, ${page.body.length} bytes (expected 200 text/html with a page)`);
  const nope = await httpGet("/nope");
  if (nope.status !== 404) fail(`GET /nope: ${nope.status}, expected 404`);
  console.log(`http: GET / 200 ${page.type} (${page.body.length} bytes), GET /nope ${nope.status}`);

  // ---- (a) max_clients
  const conns = [];
  for (let i = 0; i < maxClients; i++) conns.push(connect());
  let channels = null;
  for (const [i, c] of conns.entries()) channels = await greeted(c, `(a) connection ${i + 1} of ${maxClients}`);
  const extra = connect();
  const r = await refusedWith(extra, 503, `(a) connection ${maxClients + 1} (over max_clients ${maxClients})`);
  for (const [i, c] of conns.entries()) if (c.closed) fail(`(a) connection ${i + 1} closed when the extra one was refused`);
  await closeAll(conns);
  // The server counts a client gone when its close handler ran, a moment after ours.
  let again = null, tries = 0;
  for (; tries < 20; tries++) {
    again = connect();
    await again.until((x) => x.texts.length >= 2 || x.refused || x.closed || x.error, "(a) reconnect");
    if (!again.refused) break;
    await sleep(100);
  }
  await greeted(again, `(a) new connection after the ${maxClients} closed`);
  await closeAll([again]);
  console.log(`(a) ${maxClients} connections accepted, number ${maxClients + 1} refused: HTTP 503 '${r.body}'; after closing, a new one is accepted${tries ? ` (after ${tries} refused tries)` : ""}`);

  // ---- (b) no subprotocol; a wrong one
  const none = connect([]);
  const r400 = await refusedWith(none, 400, "(b) connection without a subprotocol");
  const wrong = connect(["foxglove.websocket.v0"]);
  await refusedWith(wrong, 400, "(b) connection with subprotocol foxglove.websocket.v0 only");
  console.log(`(b) without ${PROTOCOL}: HTTP 400 '${r400.body}'`);

  // ---- (c) malformed messages
  const junk = connect();
  channels = await greeted(junk, "(c) connection");
  const ids = channels.map((ch) => ch.id);
  const unknownChannel = Math.max(...ids) + 100;
  const map = channels.find((ch) => ch.topic === "/map");
  if (!map) fail("(c) /map not advertised");
  const bad = [
    ["not JSON", "this is { not json"],
    ["a JSON array, not an object", "[1, 2, 3]"],
    ["JSON without op", JSON.stringify({ subscriptions: [{ id: 1, channelId: ids[0] }] })],
    ["op not a string", JSON.stringify({ op: 7 })],
    ["unknown op", JSON.stringify({ op: "fly", to: "moon" })],
    ["client publishing (advertise)", JSON.stringify({ op: "advertise", channels: [{ id: 1, topic: "/x", encoding: "json", schemaName: "x" }] })],
    ["binary frame", Buffer.from([0x01, 1, 0, 0, 0, 0x7b, 0x7d])],
    ["subscribe without channelId", JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1 }] })],
    ["subscribe with a negative channelId", JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: -1 }] })],
    ["subscribe to an unknown channel", JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: unknownChannel }] })],
    ["subscribe to channel 0", JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: 0 }] })],
    ["subscriptions not an array", JSON.stringify({ op: "subscribe", subscriptions: { id: 1, channelId: ids[0] } })],
    ["unsubscribe of an unknown subscription", JSON.stringify({ op: "unsubscribe", subscriptionIds: [4242] })],
    ["unsubscribe with a negative id", JSON.stringify({ op: "unsubscribe", subscriptionIds: [-3] })],
  ];
  let sent = 0;
  const sendBad = async ([what, payload]) => {
    junk.ws.send(payload, { binary: Buffer.isBuffer(payload) });
    sent++;
    const st = await junk.nextText(`(c) answer to ${what}`);
    if (st.op !== "status" || st.level !== 2 || typeof st.message !== "string" || !st.message)
      fail(`(c) ${what}: answered ${JSON.stringify(st)}, expected a status of level 2 (error)`);
    return st;
  };
  for (const b of bad) {
    const st = await sendBad(b);
    console.log(`(c) ${b[0].padEnd(40)} -> status 2 '${st.message}'`);
  }
  if (junk.closed) fail(`(c) connection closed after ${sent} malformed messages (${junk.closed.code})`);
  // Still usable: a good subscription delivers the latched map; reusing its id is an error.
  const before = junk.binaries;
  junk.ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 77, channelId: map.id }] }));
  await junk.until((x) => x.binaries > before || x.texts.length || x.closed, "(c) /map after the malformed messages");
  if (junk.binaries === before) fail(`(c) subscribing to /map after ${sent} malformed messages got no map (${JSON.stringify(junk.texts[0] ?? junk.closed)})`);
  const dup = await sendBad(["subscription id in use", JSON.stringify({ op: "subscribe", subscriptions: [{ id: 77, channelId: map.id }] })]);
  console.log(`(c) ${"subscription id in use".padEnd(40)} -> status 2 '${dup.message}'`);
  junk.ws.send(JSON.stringify({ op: "unsubscribe", subscriptionIds: [77] }));  // good: no answer expected
  while (sent < MAX_BAD - 1) await sendBad(["filler", "junk " + sent]);
  await sleep(200);
  if (junk.closed) fail(`(c) connection closed after ${sent} malformed messages (limit ${MAX_BAD})`);
  if (junk.texts.length) fail(`(c) unexpected answer to a good message: ${JSON.stringify(junk.texts[0])}`);
  junk.ws.send("junk, the last straw");
  sent++;
  await junk.until((x) => x.closed, `(c) close after malformed message ${MAX_BAD}`);
  const last = junk.texts.find((t) => t.op === "status");
  if (!last || last.level !== 2) fail(`(c) malformed message ${MAX_BAD} not answered with a status before the close`);
  if (junk.closed.code !== 1008) fail(`(c) closed with code ${junk.closed.code} '${junk.closed.reason}', expected 1008 (policy violation)`);
  console.log(`(c) ${sent} malformed messages: each answered with status level 2; the ${MAX_BAD}th closed it: ` +
              `${junk.closed.code} '${junk.closed.reason}'`);

  // ---- (d) message over 64 KiB
  const big = connect();
  await greeted(big, "(d) connection");
  const tooBig = JSON.stringify({ op: "subscribe", subscriptions: [], pad: "x".repeat(MAX_MESSAGE) });
  big.ws.send(tooBig);
  await big.until((x) => x.closed, "(d) close after a text message over 64 KiB");
  if (big.closed.code !== 1009) fail(`(d) closed with ${big.closed.code} '${big.closed.reason}', expected 1009 (message too big)`);
  // And just under the limit is fine (answered as junk: no such op).
  const fits = connect();
  await greeted(fits, "(d) connection 2");
  const justUnder = JSON.stringify({ op: "nothing", pad: "" });
  fits.ws.send(JSON.stringify({ op: "nothing", pad: "y".repeat(MAX_MESSAGE - justUnder.length - 1) }));
  const st = await fits.nextText("(d) answer to a message of just under 64 KiB");
  if (st.op !== "status" || st.level !== 2) fail(`(d) a message just under 64 KiB: ${JSON.stringify(st).slice(0, 120)}`);
  await closeAll([fits]);
  console.log(`(d) text message of ${tooBig.length} bytes: closed ${big.closed.code} '${big.closed.reason}'; ` +
              `one of ${MAX_MESSAGE - 1} bytes is read (answered: '${st.message.slice(0, 40)}...')`);

  // ---- (e) the daemon lives: a fresh client, and the counters in the health
  const fresh = connect();
  const chs = await greeted(fresh, "(e) fresh connection after all that");
  const health = chs.find((ch) => ch.topic === "/polyloc/health");
  if (!health) fail("(e) /polyloc/health not advertised");
  fresh.ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: health.id }] }));
  // Health comes at 10 Hz, also idle; the connections closed just before may take a frame or
  // two to be counted gone.
  let viewers = null, healths = 0;
  fresh.ws.removeAllListeners("message");
  await withTimeout(new Promise((resolve) => {
    fresh.ws.on("message", (data, isBinary) => {
      if (!isBinary) return;
      viewers = JSON.parse(Buffer.from(data).subarray(13).toString()).viewers;
      if (viewers?.clients === 1 || ++healths >= 10) resolve();
    });
  }), STEP_MS, "(e) health messages (polylocd publishes them at 10 Hz, also idle)");
  const want = { connections: maxClients + 5, refused: 3, bad_messages: MAX_BAD + 1, http_requests: 2 };
  for (const [k, v] of Object.entries(want))
    if (!(viewers?.[k] >= v)) fail(`(e) health viewers.${k} = ${viewers?.[k]}, expected >= ${v} after these checks (${JSON.stringify(viewers)})`);
  if (viewers.clients !== 1) fail(`(e) health viewers.clients = ${viewers.clients} with one client connected`);
  await closeAll([fresh]);
  console.log(`(e) a fresh client gets serverInfo + advertise (${chs.length} channels); viewers ${JSON.stringify(viewers)}`);
}

const watchdog = setTimeout(() => { console.error("FAIL: check_live_protocol took more than 60 s"); process.exit(1); }, 60000);
try {
  await run();
  console.log("check_live_protocol: ok");
  clearTimeout(watchdog);
  process.exit(0);
} catch (e) {
  // Ours, or a socket error (server not there): the message; anything else with its stack.
  console.error(`FAIL: ${e instanceof Fail || e?.code ? e.message : e?.stack ?? e}`);
  process.exit(1);
}
