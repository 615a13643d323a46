// Bad clients of `vlpground replay --foxglove`: garbage text, binary frames, a frame cut off
// by a disconnect, a client that never reads, 20 clients coming and going. The misbehaving
// ones are dropped with a log line, the stuck one's queue stays bounded, and a well-behaved
// client receives every frame while the pipeline drops none.
// Environment (set by ctest): VLPGROUND_CLI, VLPGROUND_SOURCE_DIR.
import { test } from "node:test";
import assert from "node:assert/strict";
import path from "node:path";
import WebSocket from "ws";
import { connectClient, startCli, waitFor } from "./foxglove_support.mjs";

const source = process.env.VLPGROUND_SOURCE_DIR;
const pcap = path.join(source, "pcaps", "urban_demo.pcap");
const kQueueBytes = 16 * 1024 * 1024;  // ServerConfig::client_queue_bytes default
const protocol = "foxglove.websocket.v1";

// A raw client (ws): resolves once the advertise arrived.
async function rawClient(url) {
  const ws = new WebSocket(url, [protocol]);
  const state = { ws, closed: false, channels: [] };
  ws.on("close", () => (state.closed = true));
  ws.on("error", () => {});
  ws.on("message", (data, binary) => {
    if (binary) return;
    const m = JSON.parse(data.toString());
    if (m.op === "advertise") state.channels = m.channels;
  });
  await waitFor(() => state.channels.length > 0 || state.closed, "advertise");
  return state;
}

test("bad clients are dropped with a log line, a stuck one stays bounded, the good one gets every frame", async () => {
  const run = await startCli(["replay", pcap, "--rate", "5", "--loop", "--frames", "250", "--json"]);
  const good = connectClient(run.url);
  await waitFor(() => good.bySub.size === 4, "the good client's subscriptions");

  // Never reads: subscribes to everything, then stops reading its socket.
  const stuck = await rawClient(run.url);
  stuck.ws.send(JSON.stringify({ op: "subscribe", subscriptions: stuck.channels.map((c) => ({ id: c.id, channelId: c.id })) }));
  await new Promise((r) => setTimeout(r, 50));
  stuck.ws._socket.pause();

  const garbage = await rawClient(run.url);
  garbage.ws.send("garbage, not JSON");
  const binary = await rawClient(run.url);
  binary.ws.send(Buffer.from([1, 0, 0, 0, 0, 42]));
  const cut = await rawClient(run.url);
  // A masked text frame announcing 1000 bytes, then the connection ends after 4 of them.
  cut.ws._socket.write(Buffer.from([0x81, 0x80 | 126, 0x03, 0xe8, 1, 2, 3, 4, 0x7b, 0x22, 0x6f, 0x70]));
  cut.ws._socket.destroy();
  await waitFor(() => garbage.closed && binary.closed, "the server to drop the garbage senders");

  for (let i = 0; i < 20; ++i) {  // coming and going; half close politely, half vanish
    const c = connectClient(run.url);
    await waitFor(() => c.bySub.size === 4, `passing client ${i}`);
    if (i % 2 === 0) c.client.close(); else c.ws.terminate();
    await waitFor(() => c.closed || i % 2 === 1, `passing client ${i} closed`);
  }

  const code = await run.exited;
  assert.equal(code, 0, run.stderr());
  // The server closes the connection after the last message: every message has arrived then.
  await waitFor(() => good.closed, "the good client to see the server close");
  const summary = JSON.parse(run.stdout());
  assert.equal(summary.frames.dropped, 0, "the pipeline dropped no frame");
  const log = run.stderr();
  assert.match(log, /dropped: sent garbage: not JSON/);
  assert.match(log, /dropped: sent a binary message/);
  assert.match(log, /left: disconnected/);

  // The good client (client 1) got every frame from its first on, and lost nothing, by the
  // pipeline's delivery index (`delivered`, which the run's summary counts). Its four
  // subscriptions reach the server one by one: a frame sent meanwhile reaches it on some
  // channels only, so each channel is counted from the first frame all three carry.
  const topics = ["/vlpground/ground", "/vlpground/points", "/vlpground/range_image"];
  const first = topics.map((t) => good.messages.get(t)[0].timestamp).reduce((a, b) => (a > b ? a : b));
  const from = (topic) => good.messages.get(topic).filter(({ timestamp }) => timestamp >= first);
  const frames = from("/vlpground/ground").map(({ message }) =>
    Number(message.entities[0].metadata.find((kv) => kv.key === "delivered").value));
  assert.ok(frames.length >= 100, `frames received: ${frames.length}`);
  for (let i = 1; i < frames.length; ++i) assert.equal(frames[i], frames[i - 1] + 1, "consecutive frames");
  assert.equal(from("/vlpground/points").length, frames.length);
  assert.equal(from("/vlpground/range_image").length, frames.length);
  assert.equal(frames.at(-1), summary.frames.delivered - 1, "up to the last frame");
  const lines = [...log.matchAll(/client (\d+) \(\S+\) (left|dropped): .*?; sent (\d+) messages, dropped (\d+) for being slow, peak queue (\d+) bytes/g)]
    .map((m) => ({ id: Number(m[1]), sent: Number(m[3]), dropped: Number(m[4]), peak: Number(m[5]) }));
  assert.equal(lines.length, 25, "a line for every client");
  for (const l of lines) assert.ok(l.peak <= kQueueBytes, `client ${l.id}: peak queue ${l.peak} bytes`);
  assert.equal(lines.find((l) => l.id === 1).dropped, 0, "the good client lost nothing");
  const stuckLine = lines.find((l) => l.id === 2);
  assert.ok(stuckLine.dropped > 0, "the stuck client lost frames instead of holding up the others");
  assert.ok(stuckLine.peak > kQueueBytes / 2, "its queue filled up to the bound");
});
