// Conformance check: reads a VIGS-written MCAP file with the official TypeScript MCAP readers
// (@mcap/core indexed and stream readers, CRCs validated, zstd via @mcap/support), decodes every
// message with Foxglove's ROS decoders (@foxglove/rosmsg2-serialization for "cdr",
// @foxglove/rosmsg-serialization for "ros1", schemas parsed by @foxglove/rosmsg) and compares
// every message and field with the values the C++ writer recorded in EXPECTED.json.
//   node read_mcap.mjs FILE.mcap EXPECTED.json
// Exit 0 = all equal; 1 = a difference (printed); 2 = usage / read error.
import { readFileSync } from "node:fs";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parse } from "@foxglove/rosmsg";
import { MessageReader as Ros2Reader } from "@foxglove/rosmsg2-serialization";
import { MessageReader as Ros1Reader } from "@foxglove/rosmsg-serialization";

function plain(v) {
  if (typeof v === "bigint") return v.toString();
  if (ArrayBuffer.isView(v)) return Array.from(v, (x) => (typeof x === "bigint" ? x.toString() : x));
  if (Array.isArray(v)) return v.map(plain);
  if (v !== null && typeof v === "object") {
    const o = {};
    for (const k of Object.keys(v)) o[k] = plain(v[k]);
    return o;
  }
  return v;
}

function diff(path, got, want, out) {
  if (out.length > 20) return;
  if (Array.isArray(want)) {
    if (!Array.isArray(got) || got.length !== want.length) {
      out.push(`${path}: length ${got?.length} != ${want.length}`);
      return;
    }
    want.forEach((w, i) => diff(`${path}[${i}]`, got[i], w, out));
  } else if (want !== null && typeof want === "object") {
    if (got === null || typeof got !== "object") {
      out.push(`${path}: ${JSON.stringify(got)} is not an object`);
      return;
    }
    const keys = new Set([...Object.keys(want), ...Object.keys(got)]);
    for (const k of keys) {
      if (!(k in want)) out.push(`${path}.${k}: unexpected field`);
      else if (!(k in got)) out.push(`${path}.${k}: missing field`);
      else diff(`${path}.${k}`, got[k], want[k], out);
    }
  } else if (got !== want) {
    out.push(`${path}: got ${JSON.stringify(got)}, want ${JSON.stringify(want)}`);
  }
}

function decoderFor(schema, encoding) {
  const text = new TextDecoder().decode(schema.data);
  if (encoding === "cdr") {
    if (schema.encoding !== "ros2msg") throw new Error(`cdr channel with ${schema.encoding} schema`);
    return new Ros2Reader(parse(text, { ros2: true }));
  }
  if (encoding === "ros1") {
    if (schema.encoding !== "ros1msg") throw new Error(`ros1 channel with ${schema.encoding} schema`);
    return new Ros1Reader(parse(text));
  }
  throw new Error(`unexpected message encoding ${encoding}`);
}

function decodeAll(messages, channels, schemas) {
  const cache = new Map();
  return messages.map((m) => {
    const channel = channels.get(m.channelId);
    const schema = schemas.get(channel.schemaId);
    if (!cache.has(channel.id)) cache.set(channel.id, decoderFor(schema, channel.messageEncoding));
    return {
      topic: channel.topic,
      log_time: m.logTime.toString(),
      publish_time: m.publishTime.toString(),
      sequence: m.sequence,
      schema: schema.name,
      message: plain(cache.get(channel.id).readMessage(m.data)),
    };
  });
}

async function main() {
  if (process.argv.length !== 4) {
    console.error("usage: node read_mcap.mjs FILE.mcap EXPECTED.json");
    process.exit(2);
  }
  const bytes = new Uint8Array(readFileSync(process.argv[2]));
  const expected = JSON.parse(readFileSync(process.argv[3], "utf8")).messages;
  const decompressHandlers = await loadDecompressHandlers();
  const problems = [];

  // 1. Indexed reader: footer, summary, chunk indexes, message indexes, chunk CRCs.
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
  };
  const indexed = await McapIndexedReader.Initialize({ readable, decompressHandlers });
  const indexedMessages = [];
  for await (const m of indexed.readMessages({ validateCrcs: true })) indexedMessages.push(m);
  const stats = indexed.statistics;
  if (!stats || Number(stats.messageCount) !== expected.length) {
    problems.push(`statistics.messageCount ${stats?.messageCount} != ${expected.length}`);
  }
  if (indexed.chunkIndexes.length < 2) problems.push("expected several chunks");
  diff("indexed", decodeAll(indexedMessages, indexed.channelsById, indexed.schemasById), expected, problems);

  // 2. Stream reader: the whole file front to back, data-section and chunk CRCs validated.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  const channels = new Map();
  const schemas = new Map();
  const streamMessages = [];
  let sawFooter = false;
  for (let r; (r = stream.nextRecord()); ) {
    if (r.type === "Schema") schemas.set(r.id, r);
    else if (r.type === "Channel") channels.set(r.id, r);
    else if (r.type === "Message") streamMessages.push(r);
    else if (r.type === "Footer") sawFooter = true;
  }
  if (!sawFooter || !stream.done()) problems.push("stream reader did not reach the footer");
  diff("stream", decodeAll(streamMessages, channels, schemas), expected, problems);

  if (problems.length > 0) {
    console.error(`${process.argv[2]}: ${problems.length} difference(s):\n  ${problems.join("\n  ")}`);
    process.exit(1);
  }
  console.log(`${process.argv[2]}: ${expected.length} messages equal (indexed and stream readers)`);
}

main().catch((e) => {
  console.error(`${process.argv[2]}: ${e.stack ?? e}`);
  process.exit(2);
});
