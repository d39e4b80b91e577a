// Reads a `vigs simulate` recording with the official TypeScript MCAP reader (@mcap/core,
// indexed, CRCs validated; zstd via @mcap/support) and decodes every message with Foxglove's
// ROS 2 decoder. Checks the topic counts for SECONDS of sequence and the fixed fields.
//   node read_sim_mcap.cjs NODE_MODULES FILE.mcap SECONDS
// Exit 0 = as expected, 1 = a difference (printed), 2 = read error.
const [nm, file, secondsArg] = process.argv.slice(2).map((s, i) => (i === 0 ? s + "/" : s));
const { McapIndexedReader } = require(nm + "@mcap/core");
const { loadDecompressHandlers } = require(nm + "@mcap/support");
const { parse } = require(nm + "@foxglove/rosmsg");
const { MessageReader } = require(nm + "@foxglove/rosmsg2-serialization");
const fs = require("fs");

(async () => {
  const buf = fs.readFileSync(file);
  const readable = {
    size: async () => BigInt(buf.length),
    read: async (offset, length) => buf.subarray(Number(offset), Number(offset + length)),
  };
  const reader = await McapIndexedReader.Initialize({
    readable,
    decompressHandlers: await loadDecompressHandlers(),
  });
  const decoders = new Map();
  const counts = {};
  const errors = [];
  let lastStamp = -1n;
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    const ch = reader.channelsById.get(m.channelId);
    if (!decoders.has(ch.id)) {
      const schema = reader.schemasById.get(ch.schemaId);
      decoders.set(
        ch.id,
        new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true })),
      );
    }
    const msg = decoders.get(ch.id).readMessage(m.data);
    counts[ch.topic] = (counts[ch.topic] || 0) + 1;
    const stamp = BigInt(msg.header.stamp.sec) * 1000000000n + BigInt(msg.header.stamp.nanosec);
    if (stamp !== m.logTime) errors.push(`${ch.topic}: header stamp ${stamp} != log time ${m.logTime}`);
    if (m.logTime < lastStamp) errors.push(`${ch.topic}: log time goes backwards at ${m.logTime}`);
    lastStamp = m.logTime;
    if (ch.topic === "/vigs/depth" && (msg.encoding !== "16UC1" || msg.data.length !== 720 * 480 * 2))
      errors.push(`depth: ${msg.encoding} ${msg.data.length} bytes`);
    if (ch.topic === "/vigs/rgb" && (msg.encoding !== "rgb8" || msg.step !== 720 * 3))
      errors.push(`rgb: ${msg.encoding} step ${msg.step}`);
    if (
      ch.topic === "/vigs/ground_truth/dynamic_mask" &&
      (msg.encoding !== "mono8" || msg.step !== 720 || msg.data.length !== 720 * 480)
    )
      errors.push(`dynamic_mask: ${msg.encoding} step ${msg.step} ${msg.data.length} bytes`);
    if (ch.topic === "/vigs/camera_info" && (msg.k[0] !== 415.69219381653056 || msg.k[2] !== 360))
      errors.push(`camera_info: K ${Array.from(msg.k)}`);
  }
  const s = Number(secondsArg);
  const want = {
    "/vigs/rgb": Math.round(s * 20) + 1,
    "/vigs/depth": Math.round(s * 20) + 1,
    "/vigs/camera_info": Math.round(s * 20) + 1,
    "/vigs/imu": Math.round(s * 200) + 1,
    "/vigs/ground_truth/body_pose": Math.round(s * 200) + 1,
    "/vigs/ground_truth/dynamic_mask": Math.round(s * 20) + 1,
  };
  for (const [topic, n] of Object.entries(want)) {
    if (counts[topic] !== n) errors.push(`${topic}: ${counts[topic]} messages, expected ${n}`);
  }
  if (errors.length) {
    console.error(errors.slice(0, 20).join("\n"));
    process.exit(1);
  }
  console.log("read_sim_mcap: ok", JSON.stringify(counts));
})().catch((e) => {
  console.error("read_sim_mcap:", e);
  process.exit(2);
});
