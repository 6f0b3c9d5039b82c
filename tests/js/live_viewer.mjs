// A viewer for benchmarks (bench/live_viewers.sh): connects to polylocd's live view, subscribes
// to every channel and reads everything, as Foxglove with all panels open would; decodes nothing.
// On SIGINT/SIGTERM, or when the server closes, prints {messages, bytes, per_topic} as one JSON line and exits.
//   node live_viewer.mjs ws://127.0.0.1:8765
import WebSocket from "ws";

const url = process.argv[2];
if (!url) {
  console.error("usage: node live_viewer.mjs ws://HOST:PORT");
  process.exit(2);
}
const topics = new Map();  // subscription id -> topic
const count = { messages: 0, bytes: 0, per_topic: {} };
const ws = new WebSocket(url, ["foxglove.websocket.v1"]);
ws.binaryType = "nodebuffer";
ws.on("message", (data, isBinary) => {
  if (!isBinary) {
    const m = JSON.parse(data.toString());
    if (m.op === "advertise") {
      const base = topics.size;
      const subs = m.channels.map((c, i) => ({ id: base + i, channelId: c.id }));
      m.channels.forEach((c, i) => topics.set(base + i, c.topic));
      ws.send(JSON.stringify({ op: "subscribe", subscriptions: subs }));
    }
    return;
  }
  if (data[0] !== 1) return;
  const topic = topics.get(data.readUInt32LE(1)) ?? "?";
  count.messages += 1;
  count.bytes += data.length;
  count.per_topic[topic] = (count.per_topic[topic] ?? 0) + 1;
});
ws.on("error", (e) => {
  console.error(`live_viewer: ${e.message}`);
  process.exit(1);
});
let printed = false;
const done = () => {
  if (!printed) console.log(JSON.stringify(count));
  printed = true;
  process.exit(0);
};
ws.on("close", done);  // the server stopped: the count so far
process.on("SIGINT", done);
process.on("SIGTERM", done);
