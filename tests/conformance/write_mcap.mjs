// Reverse conformance: re-writes a VIGS MCAP file with the official TypeScript MCAP writer
// (@mcap/core McapWriter, zstd chunks via @foxglove/wasm-zstd), re-encoding every message with
// Foxglove's ROS encoders (@foxglove/rosmsg2-serialization for "cdr",
// @foxglove/rosmsg-serialization for "ros1"). `write_conformance_mcap compare` then checks that
// the VIGS reader and decoders get every message and field of that file back.
//   node write_mcap.mjs SOURCE.mcap OUT.mcap
import { openSync, writeSync, closeSync, readFileSync } from "node:fs";
import { McapIndexedReader, McapWriter } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parse } from "@foxglove/rosmsg";
import {
  MessageReader as Ros2Reader,
  MessageWriter as Ros2Writer,
} from "@foxglove/rosmsg2-serialization";
import {
  MessageReader as Ros1Reader,
  MessageWriter as Ros1Writer,
} from "@foxglove/rosmsg-serialization";
import zstd from "@foxglove/wasm-zstd";

class FileWritable {
  #fd;
  #pos = 0n;
  constructor(path) {
    this.#fd = openSync(path, "w");
  }
  position() {
    return this.#pos;
  }
  async write(buffer) {
    writeSync(this.#fd, buffer);
    this.#pos += BigInt(buffer.byteLength);
  }
  close() {
    closeSync(this.#fd);
  }
}

async function main() {
  const [source, out] = process.argv.slice(2);
  if (!source || !out) {
    console.error("usage: node write_mcap.mjs SOURCE.mcap OUT.mcap");
    process.exit(2);
  }
  await zstd.isLoaded;
  const bytes = new Uint8Array(readFileSync(source));
  const reader = await McapIndexedReader.Initialize({
    readable: {
      size: async () => BigInt(bytes.length),
      read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
    },
    decompressHandlers: await loadDecompressHandlers(),
  });
  const writable = new FileWritable(out);
  const writer = new McapWriter({
    writable,
    chunkSize: 3000,
    compressChunk: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
  });
  await writer.start({ profile: reader.header.profile, library: "@mcap/core conformance" });

  const codecs = new Map();
  const channelIds = new Map();
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    const text = new TextDecoder().decode(schema.data);
    const ros2 = channel.messageEncoding === "cdr";
    const defs = parse(text, { ros2 });
    codecs.set(id, {
      read: ros2 ? new Ros2Reader(defs) : new Ros1Reader(defs),
      write: ros2 ? new Ros2Writer(defs) : new Ros1Writer(defs),
    });
    const schemaId = await writer.registerSchema({
      name: schema.name,
      encoding: schema.encoding,
      data: schema.data,
    });
    channelIds.set(
      id,
      await writer.registerChannel({
        topic: channel.topic,
        schemaId,
        messageEncoding: channel.messageEncoding,
        metadata: channel.metadata,
      }),
    );
  }
  let count = 0;
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    const codec = codecs.get(m.channelId);
    const decoded = codec.read.readMessage(m.data);
    await writer.addMessage({
      channelId: channelIds.get(m.channelId),
      sequence: m.sequence,
      logTime: m.logTime,
      publishTime: m.publishTime,
      data: codec.write.writeMessage(decoded),
    });
    ++count;
  }
  await writer.end();
  writable.close();
  console.log(`${out}: ${count} messages re-written by @mcap/core`);
}

main().catch((e) => {
  console.error(e.stack ?? e);
  process.exit(2);
});
