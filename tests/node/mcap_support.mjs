// Helpers of the MCAP node tests: decompression handlers for @mcap/core, readers over a file
// or a byte array, message decoding with the channel's schema, and running the CLI.
import { spawnSync } from "node:child_process";
import { open } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { decompress as zstdDecompress } from "fzstd";
import lz4Decompress from "@foxglove/wasm-lz4";
import protobuf from "protobufjs";
import "protobufjs/ext/descriptor.js";

export const decompressHandlers = {
  zstd: (data, size) => zstdDecompress(data, new Uint8Array(Number(size))),
  lz4: (data, size) => lz4Decompress(data, Number(size)),
};

export async function ready() {
  await lz4Decompress.isLoaded;
}

/// The indexed reader (seeks through the summary) over a file on disk.
export async function openIndexed(path) {
  const handle = await open(path, "r");
  const { size } = await handle.stat();
  const readable = {
    size: async () => BigInt(size),
    read: async (offset, length) => {
      const buffer = new Uint8Array(Number(length));
      await handle.read(buffer, 0, buffer.length, Number(offset));
      return buffer;
    },
  };
  try {
    const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
    return { reader, close: () => handle.close() };
  } catch (e) {
    await handle.close();
    throw e;
  }
}

/// Every record the streaming reader yields from `bytes` (a whole or cut-short file), and
/// whether it reached the closing magic.
export function streamRecords(bytes) {
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  reader.append(bytes);
  const records = [];
  for (let r; (r = reader.nextRecord()); ) records.push(r);
  return { records, done: reader.done() };
}

/// channel id -> function(bytes) decoding a message with its channel's schema.
export function decoders(schemasById, channelsById) {
  const byChannel = new Map();
  for (const [id, channel] of channelsById) {
    const schema = schemasById.get(channel.schemaId);
    if (channel.messageEncoding === "protobuf") {
      if (schema?.encoding !== "protobuf") throw new Error(`${channel.topic}: protobuf without a protobuf schema`);
      const type = protobuf.Root.fromDescriptor(schema.data).lookupType(schema.name);
      byChannel.set(id, (data) => type.toObject(type.decode(data), { longs: Number, bytes: Uint8Array }));
    } else if (channel.messageEncoding === "json") {
      byChannel.set(id, (data) => JSON.parse(new TextDecoder().decode(data)));
    } else {
      throw new Error(`${channel.topic}: unexpected message encoding ${channel.messageEncoding}`);
    }
  }
  return byChannel;
}

/// Top-level records of an MCAP file (our own split, independent of @mcap/core): where each
/// Chunk record ends and how many messages its MessageIndex records list.
export function chunkEnds(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const chunks = [];
  let pos = 8;
  while (pos + 9 <= bytes.length) {
    const op = bytes[pos];
    const length = Number(view.getBigUint64(pos + 1, true));
    const end = pos + 9 + length;
    if (end > bytes.length) break;
    if (op === 0x06) chunks.push({ end, messages: 0 });
    if (op === 0x07) chunks.at(-1).messages += view.getUint32(pos + 9 + 2, true) / 16;
    if (op === 0x0f) break;  // DataEnd
    pos = end;
  }
  return chunks;
}

export function runCli(args, timeoutMs = 120000) {
  const cli = process.env.VLPGROUND_CLI;
  const result = spawnSync(cli, args, { encoding: "utf8", timeout: timeoutMs });
  if (result.status !== 0) {
    throw new Error(`${cli} ${args.join(" ")} -> ${result.status}\n${result.stderr}`);
  }
  return result;
}
