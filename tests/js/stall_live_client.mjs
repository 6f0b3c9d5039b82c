// A viewer that stops reading: connects to polylocd's live view (foxglove.websocket.v1),
// subscribes to every advertised channel, then pauses its socket so that nothing more is read.
// polylocd must drop it (polylocd.live.max_queue and stall_timeout) without the daemon or its
// other viewers noticing. Exits 0 once the server has dropped the connection, printing after how
// long; 1 if it is still connected after --timeout seconds. It pings every 250 ms (the server
// reads those as usual) to notice the drop: a paused socket sees no FIN, only a failed write.
//
//   node stall_live_client.mjs ws://127.0.0.1:PORT [--timeout 60]
import WebSocket from "ws";

const args = process.argv.slice(2);
let url = null, timeout = 60;
for (let i = 0; i < args.length; i++) {
  if (args[i] === "--timeout") timeout = Number(args[++i]);
  else if (!url && !args[i].startsWith("--")) url = args[i];
  else { console.error(`FAIL: unexpected argument ${args[i]}\nusage: node stall_live_client.mjs ws://HOST:PORT [--timeout S]`); process.exit(1); }
}
if (!url || !(timeout > 0)) { console.error("usage: node stall_live_client.mjs ws://HOST:PORT [--timeout S]"); process.exit(1); }

const t0 = Date.now();
const secs = (t = Date.now()) => ((t - t0) / 1000).toFixed(1);
let pausedAt = null, received = 0;

const ws = new WebSocket(url, ["foxglove.websocket.v1"]);
const watchdog = setTimeout(() => {
  console.error(`FAIL: stall_live_client: still connected ${timeout} s after connecting ` +
                `(stopped reading at ${pausedAt === null ? "-" : secs(pausedAt)} s): polylocd did not drop a client that reads nothing`);
  process.exit(1);
}, timeout * 1000);

ws.on("unexpected-response", (_req, res) => {
  console.error(`FAIL: stall_live_client: connection refused: HTTP ${res.statusCode}`);
  process.exit(1);
});
ws.on("error", (e) => {
  // After the pause the server resets the connection: that is the expected end, seen at 'close'.
  if (pausedAt === null) { console.error(`FAIL: stall_live_client: ${e.message}`); process.exit(1); }
});
ws.on("message", (data, isBinary) => {
  received++;
  if (isBinary || pausedAt !== null) return;
  const m = JSON.parse(data.toString());
  if (m.op !== "advertise") return;
  ws.send(JSON.stringify({ op: "subscribe", subscriptions: m.channels.map((c, i) => ({ id: i + 1, channelId: c.id })) }));
  // Stop reading: the socket's data stays in the kernel, the server's send queue for us grows.
  ws._socket.pause();
  pausedAt = Date.now();
  // A paused socket does not see the server's FIN or reset; a write does: once the server has
  // closed the connection, its kernel answers the next ping with a reset, the write after that
  // fails, and ws reports 'close'.
  setInterval(() => { if (ws.readyState === WebSocket.OPEN) ws.ping(); }, 250);
  console.log(`stall_live_client: subscribed to ${m.channels.length} channels, stopped reading at ${secs()} s`);
});
ws.on("close", (code, reason) => {
  clearTimeout(watchdog);
  if (pausedAt === null) {
    console.error(`FAIL: stall_live_client: closed before it subscribed (${code} ${reason})`);
    process.exit(1);
  }
  console.log(`stall_live_client: dropped by the server ${secs()} s after connecting, ` +
              `${((Date.now() - pausedAt) / 1000).toFixed(1)} s after it stopped reading (close code ${code}, ${received} messages read)`);
  process.exit(0);
});
