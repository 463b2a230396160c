// Loads a map off the main thread: streams the bytes (fetch body or File.stream()),
// parses text line by line as it arrives (binary once complete), packs it for the GPU
// and transfers the arrays back. Messages out: progress {loaded, total}, done, error.
import { BakeshopTextParser } from './bakeshop_text.js';
import { isBakeshopBinary, parseBakeshopBinary } from './bakeshop_binary.js';
import { packMap, packedTransferables } from './pack_map.js';

const kProgressIntervalMs = 100;

async function openSource(msg) {
  if (msg.file) return { stream: msg.file.stream(), total: msg.file.size, name: msg.file.name };
  const response = await fetch(msg.url);
  if (!response.ok) throw new Error(`${msg.url}: HTTP ${response.status} ${response.statusText}`);
  const total = Number(response.headers.get('Content-Length')) || 0;
  const name = decodeURIComponent(new URL(msg.url, self.location.href).pathname.split('/').pop());
  return { stream: response.body, total, name };
}

async function load(msg) {
  const t0 = performance.now();
  const { stream, total, name } = await openSource(msg);
  const reader = stream.getReader();
  let loaded = 0;
  let lastReport = 0;
  let mode = null; // 'text' | 'binary', decided by the first bytes
  const decoder = new TextDecoder('utf-8');
  const parser = new BakeshopTextParser(name);
  const chunks = [];
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
      if (mode === null) mode = isBakeshopBinary(value) || name.endsWith('.bsb') ? 'binary' : 'text';
    loaded += value.length;
    if (mode === 'text') parser.push(decoder.decode(value, { stream: true }));
    else chunks.push(value);
    const now = performance.now();
    if (now - lastReport > kProgressIntervalMs) {
      lastReport = now;
      self.postMessage({ type: 'progress', loaded, total });
    }
  }
  self.postMessage({ type: 'progress', loaded, total: total || loaded });
  let map;
  if (mode === 'binary') {
    const bytes = new Uint8Array(loaded);
    let at = 0;
    for (const c of chunks) {
      bytes.set(c, at);
      at += c.length;
    }
    map = parseBakeshopBinary(name, bytes.buffer);
  } else {
    parser.push(decoder.decode());
    map = parser.finish();
  }
  const parseMs = performance.now() - t0;
  const packed = packMap(map);
  packed.name = name;
  packed.format = mode === 'binary' ? 'bsb' : 'bs';
  packed.bytes = loaded;
  packed.parseMs = parseMs;
  self.postMessage({ type: 'done', packed }, packedTransferables(packed));
}

self.onmessage = (event) => {
  load(event.data).catch((err) => self.postMessage({ type: 'error', message: err.message }));
};
