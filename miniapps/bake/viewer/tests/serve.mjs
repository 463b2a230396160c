// A minimal localhost static server for the viewer folder (the page needs http:// for
// module workers and fetch). Run directly:
//   node tests/serve.mjs [--port 8080] [--seconds 3600] [--maps DIR (served under /maps/)]
import { createReadStream, statSync } from 'node:fs';
import { createServer } from 'node:http';
import { dirname, extname, join, normalize, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

export const viewerRoot = normalize(join(dirname(fileURLToPath(import.meta.url)), '..'));
const kTypes = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
  '.png': 'image/png',
  '.bs': 'text/plain; charset=utf-8',
  '.bsb': 'application/octet-stream',
};

// Serves files under root (and extra named roots, e.g. {'/maps/': dir}) on 127.0.0.1.
export function startServer({ root = viewerRoot, port = 0, mounts = {} } = {}) {
  const server = createServer((req, res) => {
    const path = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    let base = root;
    let rel = path;
    for (const [prefix, dir] of Object.entries(mounts)) {
      if (path.startsWith(prefix)) {
        base = dir;
        rel = path.slice(prefix.length);
      }
    }
    const file = normalize(join(base, rel.endsWith('/') ? `${rel}index.html` : rel));
    let stat = null;
    try {
      stat = file.startsWith(normalize(base) + sep) || file === normalize(base) ? statSync(file) : null;
    } catch {
      stat = null;
    }
    if (!stat || !stat.isFile()) {
      res.writeHead(404, { 'Content-Type': 'text/plain' });
      res.end(`not found: ${path}\n`);
      return;
    }
    res.writeHead(200, {
      'Content-Type': kTypes[extname(file)] ?? 'application/octet-stream',
      'Content-Length': stat.size,
      'Cache-Control': 'no-store',
    });
    createReadStream(file).pipe(res);
  });
  return new Promise((resolve) => {
    server.listen(port, '127.0.0.1', () => resolve({ server, url: `http://127.0.0.1:${server.address().port}/` }));
  });
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const arg = (name, fallback) => {
    const i = process.argv.indexOf(name);
    return i > 0 ? process.argv[i + 1] : fallback;
  };
  const maps = arg('--maps', null);
  const { server, url } = await startServer({ port: Number(arg('--port', 8080)), mounts: maps ? { '/maps/': maps } : {} });
  const seconds = Number(arg('--seconds', 3600));
  console.log(`viewer at ${url}index.html (stops after ${seconds} s)`);
  setTimeout(() => server.close(() => process.exit(0)), seconds * 1000);
}
