// Independent check of an MCAP file written by polyloc (tests/tools/write_mcap_fixture.cpp):
// reads it with @mcap/core (indexed reader and stream reader), decodes every message with
// @foxglove/rosmsg2-serialization using the schema text stored in the file, and compares the
// values with the fixture's JSON. Also checks the file's CRCs and that our ros2msg schemas parse
// to the same fields as @foxglove/rosmsg-msgs-common's ROS 2 definitions.
// Usage: node check_mcap.mjs FILE.mcap EXPECTED.json
// Exits 1 with one line per difference (first 30) if anything is off.
import { readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { crc32 } from "@foxglove/crc";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { ros2humble, ros2jazzy } from "@foxglove/rosmsg-msgs-common";
import { decompress as zstdDecompress } from "fzstd";
import lz4 from "lz4js";

const [file, expectedFile] = process.argv.slice(2);
if (!file || !expectedFile) {
  console.error("usage: node check_mcap.mjs FILE.mcap EXPECTED.json");
  process.exit(2);
}
const errors = [];
const fail = (what) => errors.push(`${file}: ${what}`);

const decompressHandlers = {
  zstd: (data, size) => zstdDecompress(data, new Uint8Array(Number(size))),
  lz4: (data, size) => Uint8Array.from(lz4.decompress(data, Number(size))),
};

// ---- value comparison --------------------------------------------------------------------

const specials = { inf: Infinity, "-inf": -Infinity, nan: NaN };
function sameNumber(exp, act) {
  if (typeof exp === "string") exp = specials[exp];
  if (typeof act === "bigint") act = Number(act);
  if (typeof act !== "number") return false;
  if (Number.isNaN(exp)) return Number.isNaN(act);
  if (exp === act) return true;
  return Number.isFinite(exp) && Math.abs(exp - act) <= 1e-6 * Math.max(1, Math.abs(exp));
}
function compare(path, exp, act) {
  if (Array.isArray(exp)) {
    const a = ArrayBuffer.isView(act) ? Array.from(act) : act;
    if (!Array.isArray(a)) return fail(`${path}: expected an array, got ${typeof act}`);
    if (a.length !== exp.length) return fail(`${path}: expected ${exp.length} elements, got ${a.length}`);
    exp.forEach((e, i) => compare(`${path}[${i}]`, e, a[i]));
  } else if (exp !== null && typeof exp === "object") {
    if (act === null || typeof act !== "object") return fail(`${path}: expected a message, got ${act}`);
    const ek = Object.keys(exp).sort().join(","), ak = Object.keys(act).sort().join(",");
    if (ek !== ak) return fail(`${path}: fields differ: expected {${ek}}, decoded {${ak}}`);
    for (const k of Object.keys(exp)) compare(`${path}.${k}`, exp[k], act[k]);
  } else if (typeof exp === "number" || exp in specials) {
    if (!sameNumber(exp, act)) fail(`${path}: expected ${exp}, decoded ${act}`);
  } else if (exp !== act) {
    fail(`${path}: expected ${JSON.stringify(exp)}, decoded ${JSON.stringify(act)}`);
  }
}

// ---- schemas -----------------------------------------------------------------------------

// By schema text: the data section and the summary each carry the schemas, and both are checked.
const readers = new Map(); // name + text -> MessageReader
function readerFor(schema) {
  const text = new TextDecoder().decode(schema.data);
  const key = `${schema.name}\n${text}`;
  if (!readers.has(key)) {
    if (schema.encoding !== "ros2msg") fail(`schema ${schema.name}: encoding ${schema.encoding}, not ros2msg`);
    const defs = parse(text, { ros2: true });
    checkAgainstCommon(schema.name, defs);
    readers.set(key, new MessageReader(defs));
  }
  return readers.get(key);
}

// Every type in our schema text must have exactly the fields of the common ROS 2 definitions.
function checkAgainstCommon(schemaName, defs) {
  const shortName = schemaName.replace("/msg/", "/");
  const fields = (d) => JSON.stringify(d.definitions);
  for (const [i, def] of defs.entries()) {
    const name = i === 0 ? shortName : def.name;
    for (const [distro, common] of [["humble", ros2humble], ["jazzy", ros2jazzy]]) {
      const ref = common[name];
      if (!ref) fail(`schema ${schemaName}: type ${name} is not in rosmsg-msgs-common ${distro}`);
      else if (fields(def) !== fields(ref)) {
        const n = Math.max(def.definitions.length, ref.definitions.length);
        const i = [...Array(n).keys()].find((k) => JSON.stringify(def.definitions[k]) !== JSON.stringify(ref.definitions[k]));
        fail(`schema ${schemaName}: ${name} differs from rosmsg-msgs-common ${distro} at field ${i}:\n` +
          `  ours:   ${JSON.stringify(def.definitions[i])}\n  theirs: ${JSON.stringify(ref.definitions[i])}`);
      }
    }
  }
}

// ---- the checks --------------------------------------------------------------------------

const bytes = new Uint8Array(await readFile(file));
const expected = JSON.parse(await readFile(expectedFile, "utf8"));
const wantCompression = expected.compression;

// lookup(m) gives the {channel, schema} a message was written under.
function decodeAndCompare(label, messages, exp, lookup) {
  if (messages.length !== exp.length) fail(`${label}: ${messages.length} messages, expected ${exp.length}`);
  messages.slice(0, exp.length).forEach((m, i) => {
    const e = exp[i];
    const where = `${label} message ${i} (${e.topic} at ${e.log_time})`;
    const { channel, schema } = lookup(m);
    if (!channel) return fail(`${where}: unknown channel ${m.channelId}`);
    if (channel.topic !== e.topic) return fail(`${where}: on topic ${channel.topic}`);
    if (channel.messageEncoding !== "cdr") fail(`${where}: message encoding ${channel.messageEncoding}`);
    if (m.logTime !== BigInt(e.log_time)) fail(`${where}: log time ${m.logTime}`);
    if (!schema || schema.name !== e.type) return fail(`${where}: schema ${schema?.name}, expected ${e.type}`);
    const reader = readerFor(schema);
    let decoded;
    try {
      decoded = reader.readMessage(m.data);
    } catch (err) {
      return fail(`${where}: rosmsg2-serialization cannot decode it: ${err.message}`);
    }
    if (reader.lastReadHadTrailingBytes()) fail(`${where}: trailing bytes after the message`);
    compare(where, e.message, decoded);
  });
}

// Raw layout: magics and the data section CRC, which @mcap/core reads but does not check.
const magic = [0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a];
if (!magic.every((b, i) => bytes[i] === b && bytes[bytes.length - 8 + i] === b)) fail("magic missing at start or end");

const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
};
let indexed;
try {
  indexed = await McapIndexedReader.Initialize({ readable, decompressHandlers });
} catch (err) {
  fail(`@mcap/core indexed reader: ${err.message}`);
}
if (indexed) {
  if (indexed.header.profile !== "ros2") fail(`profile ${indexed.header.profile}, expected ros2`);
  if (indexed.header.library !== "polyloc") fail(`library ${indexed.header.library}`);
  if (indexed.footer.summaryCrc === 0) fail("summary CRC not set");
  const dataCrc = crc32(bytes.subarray(0, Number(indexed.dataEndOffset)));
  if (indexed.dataSectionCrc !== dataCrc) fail(`data section CRC ${indexed.dataSectionCrc}, computed ${dataCrc}`);
  if (indexed.chunkIndexes.length < 2) fail(`only ${indexed.chunkIndexes.length} chunk(s); the fixture should make several`);
  for (const ci of indexed.chunkIndexes)
    if (ci.compression !== wantCompression) fail(`chunk at ${ci.chunkStartOffset}: compression "${ci.compression}", expected "${wantCompression}"`);
  const stats = indexed.statistics;
  if (!stats) fail("no Statistics record");
  else {
    if (stats.messageCount !== BigInt(expected.messages.length)) fail(`statistics: ${stats.messageCount} messages`);
    if (stats.chunkCount !== indexed.chunkIndexes.length) fail(`statistics: ${stats.chunkCount} chunks`);
    for (const [id, ch] of indexed.channelsById) {
      const want = expected.messages.filter((m) => m.topic === ch.topic).length;
      if (stats.channelMessageCounts.get(id) !== BigInt(want)) fail(`statistics: ${ch.topic} count ${stats.channelMessageCounts.get(id)}, expected ${want}`);
    }
  }
  const messages = [];
  try {
    for await (const m of indexed.readMessages({ validateCrcs: true })) messages.push(m);
  } catch (err) {
    fail(`@mcap/core indexed reader: ${err.message}`);
  }
  // The indexed reader gives log-time order; ties in any order, so sort both the same way.
  const key = (topic, t) => `${String(t).padStart(20, "0")} ${topic}`;
  const byTime = [...expected.messages].sort((a, b) => (key(a.topic, a.log_time) < key(b.topic, b.log_time) ? -1 : 1));
  for (let i = 1; i < messages.length; ++i)
    if (messages[i].logTime < messages[i - 1].logTime) fail(`indexed reader: message ${i} out of log-time order`);
  const topicOf = (m) => indexed.channelsById.get(m.channelId)?.topic ?? "";
  messages.sort((a, b) => (key(topicOf(a), a.logTime) < key(topicOf(b), b.logTime) ? -1 : 1));
  decodeAndCompare("indexed", messages, byTime, (m) => {
    const channel = indexed.channelsById.get(m.channelId);
    return { channel, schema: channel && indexed.schemasById.get(channel.schemaId) };
  });
}

// Stream reader: every record in file order; messages come in the order they were written.
{
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  const channels = new Map(), schemas = new Map(), messages = [], ops = [];
  try {
    stream.append(bytes);
    for (let r; (r = stream.nextRecord()); ) {
      ops.push(r.type);
      if (r.type === "Schema") schemas.set(r.id, r);
      else if (r.type === "Channel") {
        if (!schemas.has(r.schemaId)) fail(`stream: channel ${r.topic} before its schema`);
        channels.set(r.id, r);
      } else if (r.type === "Message") {
        if (!channels.has(r.channelId)) fail(`stream: message before its channel ${r.channelId}`);
        // The summary repeats Schema and Channel records: keep the ones in force for this message.
        const channel = channels.get(r.channelId);
        messages.push({ ...r, channel, schema: channel && schemas.get(channel.schemaId) });
      }
    }
    if (!stream.done()) fail("stream reader: file did not end with a valid footer");
  } catch (err) {
    fail(`@mcap/core stream reader: ${err.message}`);
  }
  if (ops[0] !== "Header") fail(`stream: first record ${ops[0]}, expected Header`);
  if (ops.at(-1) !== "Footer") fail(`stream: last record ${ops.at(-1)}, expected Footer`);
  for (const op of ["DataEnd", "Statistics", "ChunkIndex", "SummaryOffset", "MessageIndex"])
    if (!ops.includes(op)) fail(`stream: no ${op} record`);
  decodeAndCompare("stream", messages, expected.messages, (m) => m);
}

if (errors.length > 0) {
  console.error(errors.slice(0, 30).join("\n"));
  if (errors.length > 30) console.error(`... and ${errors.length - 30} more`);
  console.error(`FAIL: ${errors.length} difference(s)`);
  process.exit(1);
}
console.log(`OK ${file}: ${expected.messages.length} messages, ${new Set([...readers.keys()].map((k) => k.split("\n")[0])).size} schemas match (compression "${wantCompression}")`);
