// Mock of polylocd's live view server, for developing service/live/page.html and for a
// self-test of check_live_page.mjs: serves the page on GET / and speaks the subset of
// foxglove.websocket.v1 the page uses, with a synthetic robot driving a circle.
//
//   node mock_live_server.mjs <port>      (0: any free port; prints "listening on <port>")
import { readFileSync } from "node:fs";
import http from "node:http";
import { fileURLToPath } from "node:url";
import { WebSocketServer } from "ws";

const PAGE = fileURLToPath(new URL("../../service/live/page.html", import.meta.url));
const PROTOCOL = "foxglove.websocket.v1";
const port = Number(process.argv[2] ?? 8765);

const CHANNELS = [
  { id: 1, topic: "/polyloc/map_slice", encoding: "json", schemaName: "polyloc.MapSlice" },
  { id: 2, topic: "/polyloc/topview", encoding: "json", schemaName: "polyloc.TopView" },
  { id: 3, topic: "/polyloc/health", encoding: "json", schemaName: "polyloc.Health" },
  // A channel the page must ignore (same topic family, another encoding).
  { id: 4, topic: "/polyloc/pose", encoding: "cdr", schemaName: "geometry_msgs/msg/PoseStamped" },
].map((c) => ({ ...c, schema: c.encoding === "json" ? '{"type":"object"}' : "",
                schemaEncoding: c.encoding === "json" ? "jsonschema" : "ros2msg" }));

// A 10 x 6 m room: walls, a door in the top wall, a glass pane and a danger edge (stairs).
const MAP = {
  frame_id: "map", height: 0.3, bounds: [0, 0, 10, 6],
  labels: ["", "wall", "door", "glass", "danger"],
  segments: [0, 0, 10, 0, 10, 0, 10, 6, 10, 6, 5, 6, 4, 6, 0, 6, 0, 6, 0, 0,
             4, 6, 4.9, 5.6, 10, 2, 10, 4, 0.5, 0.3, 0.5, 1.8],
  segment_label: [1, 1, 1, 1, 1, 2, 3, 4],
};

const R = 2, V = 0.5, CX = 5, CY = 3;  // circle of 2 m at 0.5 m/s around the room centre
const t0 = Date.now();
const gauss = () => Math.sqrt(-2 * Math.log(1 - Math.random())) * Math.cos(2 * Math.PI * Math.random());

function topview() {
  const t = (Date.now() - t0) / 1000, a = (V / R) * t;
  const pose = { x: CX + R * Math.cos(a), y: CY + R * Math.sin(a), yaw: a + Math.PI / 2,
                 cov_xx: 0.09, cov_xy: 0.03, cov_yy: 0.05 };
  const particles = [];
  for (let i = 0; i < 200; i++) particles.push(pose.x + 0.3 * gauss(), pose.y + 0.22 * gauss(), pose.yaw + 0.05 * gauss());
  const vrs = [];
  for (let i = 0; i < 8; i++) vrs.push(8 + 0.05 * i, 1.5 + 0.02 * gauss());  // a table edge
  const px = 5 + 3 * Math.sin(0.3 * t);  // a person pacing along the top wall
  const tracks = [{ id: 3, x: px, y: 5.3, vx: 0.9 * Math.cos(0.3 * t), vy: 0, confirmed: true }];
  return { stamp_ns: Date.now() * 1e6, frame_id: "map", pose, particles, vrs, tracks, status: "tracking" };
}

function messageData(subId, obj) {
  const payload = Buffer.from(JSON.stringify(obj));
  const head = Buffer.alloc(13);
  head.writeUInt8(0x01, 0);
  head.writeUInt32LE(subId, 1);
  head.writeBigUInt64LE(BigInt(Date.now()) * 1000000n, 5);
  return Buffer.concat([head, payload]);
}

const server = http.createServer((req, res) => {
  if (req.method === "GET" && (req.url === "/" || req.url === "/index.html")) {
    res.writeHead(200, { "Content-Type": "text/html; charset=utf-8", "Cache-Control": "no-store" });
    res.end(readFileSync(PAGE));  // read per request: edits show on reload
  } else {
    res.writeHead(404, { "Content-Type": "text/plain" });
    res.end("not found\n");
  }
});

const wss = new WebSocketServer({
  server,
  handleProtocols: (protocols) => (protocols.has(PROTOCOL) ? PROTOCOL : false),
});

wss.on("connection", (ws) => {
  const subs = new Map();  // subscription id -> channel id
  const send = (obj) => ws.send(JSON.stringify(obj));
  send({ op: "serverInfo", name: "polyloc mock", capabilities: [], supportedEncodings: [], metadata: {} });
  send({ op: "advertise", channels: CHANNELS });
  send({ op: "status", level: 1, message: "mock server: synthetic robot" });

  ws.on("message", (data, isBinary) => {
    if (isBinary) return;
    let m;
    try { m = JSON.parse(data.toString()); } catch { return; }
    if (m.op === "subscribe") {
      for (const { id, channelId } of m.subscriptions ?? []) {
        subs.set(id, channelId);
        if (channelId === 1) ws.send(messageData(id, MAP));  // latched
      }
    } else if (m.op === "unsubscribe") {
      for (const id of m.subscriptionIds ?? []) subs.delete(id);
    }
  });

  let tick = 0;
  const timer = setInterval(() => {
    tick++;
    const tv = topview();
    for (const [id, ch] of subs) {
      if (ch === 2) ws.send(messageData(id, tv));
      if (ch === 3 && tick % 10 === 0) ws.send(messageData(id, { viewers: wss.clients.size, dropped: 0 }));
    }
  }, 100);
  ws.on("close", () => clearInterval(timer));
});

server.listen(port, "127.0.0.1", () => console.log(`listening on ${server.address().port}`));
for (const sig of ["SIGINT", "SIGTERM"]) process.on(sig, () => process.exit(0));
