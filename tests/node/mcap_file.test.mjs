// The MCAP files of `vlpground replay --mcap`, read by the reference reader (@mcap/core):
// the summary opens the file, every message decodes with its schema, counts match the frames
// replayed; files cut short (truncated, or the writer killed) stream up to their last frame.
// Environment (set by ctest): VLPGROUND_CLI, VLPGROUND_SOURCE_DIR, MCAP_TEST_DIR.
import { test, before } from "node:test";
import assert from "node:assert/strict";
import { spawn } from "node:child_process";
import { mkdirSync, readFileSync, existsSync } from "node:fs";
import path from "node:path";
import { chunkEnds, decoders, openIndexed, ready, runCli, streamRecords } from "./mcap_support.mjs";

const source = process.env.VLPGROUND_SOURCE_DIR;
const outDir = process.env.MCAP_TEST_DIR;
const pcap = path.join(source, "pcaps", "urban_demo.pcap");
const topics = ["/vlpground/points", "/vlpground/ground", "/vlpground/range_image", "/vlpground/status"];
const frameTopics = topics.slice(0, 3);

before(async () => {
  await ready();
  mkdirSync(outDir, { recursive: true });
});

function replay(file, extra = []) {
  const { stdout } = runCli(["replay", pcap, "--mcap", file, "--json", ...extra]);
  return JSON.parse(stdout).frames.delivered;
}

function checkDecoded(topic, msg) {
  if (topic === "/vlpground/points") {
    assert.ok(msg.point_stride > 0);
    assert.ok(msg.data.length > 0 && msg.data.length % msg.point_stride === 0, "whole points");
    const names = msg.fields.map((f) => f.name);
    for (const n of ["x", "y", "z", "intensity", "ring", "label"]) assert.ok(names.includes(n), n);
  } else if (topic === "/vlpground/ground") {
    assert.ok(Array.isArray(msg.entities) && msg.entities.length > 0, "ground entities");
  } else if (topic === "/vlpground/range_image") {
    assert.equal(msg.height, 16);
    assert.ok(msg.width > 0);
    assert.equal(msg.data.length, msg.step * msg.height);
  } else if (topic === "/vlpground/status") {
    assert.equal(typeof msg, "object");
  }
}

test("replay --mcap: the indexed reader opens the file via its summary; every message decodes; counts match the frames", async () => {
  const file = path.join(outDir, "urban_zstd.mcap");
  const frames = replay(file);
  assert.ok(frames > 0);
  const { reader, close } = await openIndexed(file);
  try {
    assert.ok(reader.chunkIndexes.length >= frames, "one chunk per frame at least");
    assert.ok(reader.chunkIndexes.every((c) => c.compression === "zstd"));
    const byTopic = new Map([...reader.channelsById.values()].map((c) => [c.topic, c.id]));
    assert.deepEqual([...byTopic.keys()].sort(), [...topics].sort());
    const decode = decoders(reader.schemasById, reader.channelsById);
    const counts = new Map();
    const last = new Map();
    let lastStatus;
    for await (const m of reader.readMessages()) {
      const topic = reader.channelsById.get(m.channelId).topic;
      const msg = decode.get(m.channelId)(m.data);
      checkDecoded(topic, msg);
      if (topic === "/vlpground/status") lastStatus = msg;
      counts.set(topic, (counts.get(topic) ?? 0) + 1);
      assert.ok(m.logTime >= (last.get(topic) ?? 0n), "log times in order per topic");
      last.set(topic, m.logTime);
    }
    for (const t of frameTopics) assert.equal(counts.get(t), frames, `${t}: one message per frame`);
    assert.ok(counts.get("/vlpground/status") >= 1, "the final status at least");
    assert.equal(lastStatus.frames.delivered, frames, "the last status has the final counters");
    const stats = reader.statistics;
    let total = 0;
    for (const t of topics) {
      const n = counts.get(t) ?? 0;
      assert.equal(stats.channelMessageCounts.get(byTopic.get(t)) ?? 0n, BigInt(n), t);
      total += n;
    }
    assert.equal(stats.messageCount, BigInt(total));
    assert.equal(stats.chunkCount, reader.chunkIndexes.length);
  } finally {
    await close();
  }
});

for (const compression of ["lz4", "none"]) {
  test(`replay --mcap-compression ${compression}: readable and decodable`, async () => {
    const file = path.join(outDir, `urban_${compression}.mcap`);
    const frames = replay(file, ["--mcap-compression", compression]);
    const { reader, close } = await openIndexed(file);
    try {
      const expected = compression === "none" ? "" : compression;
      assert.ok(reader.chunkIndexes.every((c) => c.compression === expected));
      const decode = decoders(reader.schemasById, reader.channelsById);
      let points = 0;
      for await (const m of reader.readMessages()) {
        const topic = reader.channelsById.get(m.channelId).topic;
        checkDecoded(topic, decode.get(m.channelId)(m.data));
        if (topic === "/vlpground/points") ++points;
      }
      assert.equal(points, frames);
    } finally {
      await close();
    }
  });
}

test("a file cut at arbitrary offsets streams up to its last complete frame", () => {
  const file = path.join(outDir, "urban_zstd.mcap");
  if (!existsSync(file)) replay(file);
  const bytes = new Uint8Array(readFileSync(file));
  const chunks = chunkEnds(bytes);
  assert.ok(chunks.length > 2);
  const whole = streamRecords(bytes);
  assert.ok(whole.done, "the complete file reads to its closing magic");
  const expectedAt = (cut) => chunks.filter((c) => c.end <= cut).reduce((n, c) => n + c.messages, 0);
  const cuts = new Set([9, 100, bytes.length - 1, bytes.length - 30]);
  for (const c of chunks) for (const d of [-1, 0, 1, 17]) cuts.add(c.end + d);
  let seed = 12345;
  for (let i = 0; i < 60; ++i) {
    seed = (seed * 1103515245 + 12345) % 2147483648;
    cuts.add(9 + (seed % (bytes.length - 9)));
  }
  for (const cut of cuts) {
    const { records, done } = streamRecords(bytes.subarray(0, cut));
    const channels = new Map();
    const schemas = new Map();
    let messages = 0;
    for (const r of records) {
      if (r.type === "Schema") schemas.set(r.id, r);
      if (r.type === "Channel") channels.set(r.id, r);
      if (r.type === "Message") ++messages;
    }
    assert.equal(done, false, `cut at ${cut}: not a complete file`);
    assert.equal(messages, expectedAt(cut), `cut at ${cut} of ${bytes.length}`);
    if (cut > chunks[0].end) assert.equal(channels.size, topics.length, "channels precede the chunks");
    const decode = decoders(schemas, channels);
    for (const r of records) if (r.type === "Message") decode.get(r.channelId)(r.data);
  }
});

// Starts a looping real-time replay recording to `file`; resolves once `frames` whole frames
// are on disk (bounded wait).
async function startRecording(file, frames, extra = []) {
  const child = spawn(process.env.VLPGROUND_CLI, ["replay", pcap, "--loop", "--rate", "1", "--mcap", file, ...extra], {
    stdio: ["ignore", "pipe", "ignore"],
  });
  let stdout = "";
  child.stdout.on("data", (d) => (stdout += d));
  // "close": after the exit and the end of its output
  const exited = new Promise((resolve) => child.on("close", (code, signal) => resolve({ code, signal, stdout })));
  const deadline = Date.now() + 30000;
  let complete = 0;
  while (complete < frames * 3 && Date.now() < deadline) {
    await new Promise((r) => setTimeout(r, 50));
    if (existsSync(file)) complete = chunkEnds(new Uint8Array(readFileSync(file))).reduce((n, c) => n + c.messages, 0);
  }
  if (complete < frames * 3) child.kill("SIGKILL");
  assert.ok(complete >= frames * 3, `${frames} frames recorded before the deadline`);
  return { child, exited, complete };
}

test("Ctrl-C (SIGINT) ends the recording with a complete, indexed file holding every delivered frame", async () => {
  const file = path.join(outDir, "interrupted.mcap");
  const { child, exited } = await startRecording(file, 3, ["--json"]);
  child.kill("SIGINT");
  const { code, stdout } = await exited;
  assert.equal(code, 0);
  const delivered = JSON.parse(stdout).frames.delivered;
  const { reader, close } = await openIndexed(file);
  try {
    const points = [...reader.channelsById.values()].find((c) => c.topic === "/vlpground/points").id;
    assert.equal(reader.statistics.channelMessageCounts.get(points), BigInt(delivered));
  } finally {
    await close();
  }
});

test("the recorder killed with SIGKILL mid-run leaves a file that streams up to its last complete frame", async () => {
  const file = path.join(outDir, "killed.mcap");
  const { child, exited, complete } = await startRecording(file, 3);
  child.kill("SIGKILL");
  assert.equal((await exited).signal, "SIGKILL");

  const bytes = new Uint8Array(readFileSync(file));
  const { records, done } = streamRecords(bytes);
  assert.equal(done, false, "no footer: the writer never finished");
  await assert.rejects(openIndexed(file), "no summary: the indexed reader refuses it");
  const messages = records.filter((r) => r.type === "Message");
  assert.equal(messages.length, chunkEnds(bytes).reduce((n, c) => n + c.messages, 0));
  assert.ok(messages.length >= complete);
  const channels = new Map(records.filter((r) => r.type === "Channel").map((r) => [r.id, r]));
  const schemas = new Map(records.filter((r) => r.type === "Schema").map((r) => [r.id, r]));
  const decode = decoders(schemas, channels);
  const perTopic = new Map();
  for (const m of messages) {
    const topic = channels.get(m.channelId).topic;
    checkDecoded(topic, decode.get(m.channelId)(m.data));
    perTopic.set(topic, (perTopic.get(topic) ?? 0) + 1);
  }
  // Whole frames only: every frame channel has the same number of messages.
  const frameCounts = frameTopics.map((t) => perTopic.get(t) ?? 0);
  assert.ok(frameCounts.every((n) => n === frameCounts[0] && n >= 3), JSON.stringify(frameCounts));
});
