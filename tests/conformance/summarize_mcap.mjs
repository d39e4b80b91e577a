// Opens any MCAP file with the official TypeScript readers (@mcap/core indexed reader with CRC
// validation, then the stream reader front to back), decodes every message with Foxglove's ROS 2
// / ROS 1 decoders, and prints one JSON object: per topic the schema, message count, first and
// last log time, and a few decoded fields of the first message (for the caller to check).
// Used by tests/drivers/test_record_cli (a `vigs record` file).
//   node summarize_mcap.mjs FILE.mcap
// Exit 0 = read and decoded; 1 = the readers disagree or a message does not decode; 2 = usage.
import { readFileSync } from "node:fs";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parse } from "@foxglove/rosmsg";
import { MessageReader as Ros2Reader } from "@foxglove/rosmsg2-serialization";
import { MessageReader as Ros1Reader } from "@foxglove/rosmsg-serialization";

function decoderFor(schema, encoding) {
  const text = new TextDecoder().decode(schema.data);
  if (encoding === "cdr") return new Ros2Reader(parse(text, { ros2: true }));
  if (encoding === "ros1") return new Ros1Reader(parse(text));
  throw new Error(`unexpected message encoding ${encoding}`);
}

function firstFields(schemaName, msg) {
  if (schemaName.endsWith("Image")) {
    return { width: msg.width, height: msg.height, encoding: msg.encoding, bytes: msg.data.length,
             data0: msg.data[0], data1: msg.data[1] };
  }
  if (schemaName.endsWith("Imu")) {
    return { accel_z: msg.linear_acceleration.z, gyro_x: msg.angular_velocity.x };
  }
  if (schemaName.endsWith("SerialChunk")) return { port: msg.port, bytes: msg.data.length };
  if (schemaName.endsWith("CameraInfo")) return { fx: msg.k[0], width: msg.width };
  if (schemaName.endsWith("TimeReference")) return { source: msg.source };
  return {};
}

async function main() {
  if (process.argv.length !== 3) {
    console.error("usage: node summarize_mcap.mjs FILE.mcap");
    process.exit(2);
  }
  const bytes = new Uint8Array(readFileSync(process.argv[2]));
  const decompressHandlers = await loadDecompressHandlers();
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
  };
  const indexed = await McapIndexedReader.Initialize({ readable, decompressHandlers });
  const topics = {};
  const decoders = new Map();
  let total = 0;
  for await (const m of indexed.readMessages({ validateCrcs: true })) {
    const channel = indexed.channelsById.get(m.channelId);
    const schema = indexed.schemasById.get(channel.schemaId);
    if (!decoders.has(channel.id)) decoders.set(channel.id, decoderFor(schema, channel.messageEncoding));
    const msg = decoders.get(channel.id).readMessage(m.data);
    let t = topics[channel.topic];
    if (!t) {
      t = topics[channel.topic] = { schema: schema.name, messages: 0, first_log_time: m.logTime.toString(),
                                    first: firstFields(schema.name, msg) };
    }
    t.messages += 1;
    t.last_log_time = m.logTime.toString();
    total += 1;
  }
  // The stream reader must see the same number of messages (data-section CRC checked).
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  let streamed = 0;
  for (let r; (r = stream.nextRecord()); ) if (r.type === "Message") streamed += 1;
  const problems = [];
  if (streamed !== total) problems.push(`stream reader saw ${streamed} messages, indexed ${total}`);
  if (Number(indexed.statistics?.messageCount ?? -1) !== total) {
    problems.push(`statistics.messageCount ${indexed.statistics?.messageCount} != ${total}`);
  }
  console.log(JSON.stringify({ messages: total, chunks: indexed.chunkIndexes.length, topics, problems }));
  process.exit(problems.length === 0 ? 0 : 1);
}

main().catch((e) => {
  console.error(`summarize_mcap: ${e.message}`);
  process.exit(1);
});
