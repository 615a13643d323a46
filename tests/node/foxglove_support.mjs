// Helpers of the live-view node tests: run the CLI with --foxglove on a free port, connect the
// reference client (@foxglove/ws-protocol), decode messages with the advertised schemas,
// wait for conditions with a deadline.
import { spawn } from "node:child_process";
import { once } from "node:events";
import wsProtocol from "@foxglove/ws-protocol";
import WebSocket from "ws";
import protobuf from "protobufjs";
const { FoxgloveClient } = wsProtocol;
import "protobufjs/ext/descriptor.js";

/// Starts `vlpground ARGS --foxglove 127.0.0.1:0`; resolves once the server is listening.
/// Returns { proc, url, port, stderr(), stdout(), exited } (exited: a promise of the exit code).
export async function startCli(args, timeoutMs = 20000) {
  const cli = process.env.VLPGROUND_CLI;
  const proc = spawn(cli, [...args, "--foxglove", "127.0.0.1:0"], { stdio: ["ignore", "pipe", "pipe"] });
  let stderr = "", stdout = "";
  proc.stdout.on("data", (d) => (stdout += d));
  const exited = new Promise((resolve) => proc.on("exit", (code) => resolve(code)));
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no server line within ${timeoutMs} ms:\n${stderr}`)), timeoutMs);
    proc.stderr.on("data", (d) => {
      stderr += d;
      const m = /Foxglove live view on (ws:\/\/[0-9.]+:\d+)/.exec(stderr);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    proc.on("exit", (code) => { clearTimeout(timer); reject(new Error(`exited ${code} before serving:\n${stderr}`)); });
  });
  return { proc, url, port: Number(new URL(url).port), stderr: () => stderr, stdout: () => stdout, exited };
}

/// A connected reference client that collects serverInfo, the advertised channels and
/// decoded messages per topic. `subscribeAll`: subscribe to every channel once advertised.
export function connectClient(url, { subscribeAll = true } = {}) {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const state = { client, ws, serverInfo: null, channels: new Map(), bySub: new Map(), messages: new Map(),
                  statuses: [], closed: false, decoders: new Map() };
  client.on("serverInfo", (info) => (state.serverInfo = info));
  client.on("status", (s) => state.statuses.push(s));
  client.on("close", () => (state.closed = true));
  client.on("advertise", (channels) => {
    for (const ch of channels) {
      state.channels.set(ch.id, ch);
      state.decoders.set(ch.id, decoderOf(ch));
      if (subscribeAll) state.bySub.set(client.subscribe(ch.id), ch);
    }
  });
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    const ch = state.bySub.get(subscriptionId);
    const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
    const list = state.messages.get(ch.topic) ?? [];
    list.push({ timestamp, message: state.decoders.get(ch.id)(bytes) });
    state.messages.set(ch.topic, list);
  });
  return state;
}

function decoderOf(channel) {
  if (channel.encoding === "json") return (bytes) => JSON.parse(new TextDecoder().decode(bytes));
  if (channel.encoding !== "protobuf" || channel.schemaEncoding !== "protobuf") {
    throw new Error(`${channel.topic}: unexpected encoding ${channel.encoding}/${channel.schemaEncoding}`);
  }
  const descriptorSet = Buffer.from(channel.schema, "base64");
  const type = protobuf.Root.fromDescriptor(descriptorSet).lookupType(channel.schemaName);
  return (bytes) => type.toObject(type.decode(bytes), { longs: Number, bytes: Uint8Array, enums: String, defaults: true });
}

/// Resolves when `condition()` holds; rejects after `timeoutMs` with `what`.
export async function waitFor(condition, what, timeoutMs = 20000) {
  const deadline = Date.now() + timeoutMs;
  while (!condition()) {
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 10));
  }
}

/// Ends the CLI (SIGINT, as Ctrl-C) unless it already ended; resolves with its exit code.
export async function stopCli(run) {
  if (run.proc.exitCode === null) run.proc.kill("SIGINT");
  return run.exited;
}

export { once };
